//! The catalogue of front-end diagnostic codes.
//!
//! Every diagnostic the front ends emit uses a constant from here, so codes stay stable
//! and `plcc explain CODE` can describe each one. Ranges:
//! `E00xx` lexical, `E01xx` syntax, `E02xx` names and declarations, `E03xx` types,
//! `E04xx` calls, `E05xx` rules about writing and recursion, `E06xx` constructs not
//! supported yet, `E070x`–`E071x` Instruction List, `E072x`–`E073x` PLC-UD STL,
//! `E074x`–`E075x` ladder diagrams (PLCopen XML), `E076x` sequential function charts
//! (PLCopen XML), `E078x` textual sequential function charts, `E080x` object
//! orientation, `W0xxx` warnings.

use plcc_ir::diag::CodeInfo;

macro_rules! codes {
    ($( $name:ident = $code:literal, $title:literal, $expl:literal; )*) => {
        $(
            #[doc = $title]
            pub const $name: &str = $code;
        )*
        /// Every front-end code with its title and explanation.
        pub const ALL: &[CodeInfo] = &[
            $( CodeInfo { code: $code, title: $title, explanation: $expl }, )*
        ];
    };
}

codes! {
    // ---- lexical and syntax (E00xx, E01xx) ----
    UNEXPECTED_CHAR = "E0001", "unexpected character",
        "The character cannot start any token of Structured Text (outside comments and \
         strings, ST uses ASCII letters, digits and the operators `:= + - * / ( ) [ ] ...`).\n\
         \n    x := a ? b;      (* error: `?` is not an operator *)\n\
         \n    x := SEL(c, b, a); (* fix: use a function or an IF *)";
    UNTERMINATED_COMMENT = "E0002", "unterminated comment or pragma",
        "A comment `(* ... *)` or `/* ... */`, or a pragma `{ ... }` or `{{ ... }}`, runs to \
         the end of the file. `(* *)` comments nest, so every `(*` inside one needs its own \
         `*)`; a pragma `{{` ends at the first `}}` and `{` at the first `}`.\n\
         \n    (* outer (* inner *)   x := 1;   (* error: the outer comment is never closed *)\n\
         \n    (* outer (* inner *) *) x := 1;  (* fix *)";
    UNTERMINATED_STRING = "E0003", "unterminated string literal",
        "A string literal is not closed on its line. A line break inside a string is \
         written `$N` (or `$L`), and a quote of the same kind is written `$'` (or `$\"`).\n\
         \n    msg := 'it's done';   (* error: the string ends after `it` *)\n\
         \n    msg := 'it$'s done';  (* fix *)";
    INVALID_ESCAPE = "E0004", "invalid escape sequence in a string literal",
        "After `$` a string literal allows `$$ $' $\" $L $N $P $R $T`, or exactly two hex \
         digits in a STRING (`$0A`) and four in a WSTRING (`$000A`).\n\
         \n    s := 'cost: 5$';    (* error: a lone `$` *)\n\
         \n    s := 'cost: 5$$';   (* fix: `$$` is a dollar sign *)";
    MALFORMED_NUMBER = "E0005", "malformed number",
        "A number literal has a digit that is not valid in its base, a base other than 2, 8 \
         or 16, no digits, or letters glued to it.\n\
         \n    m := 16#FG;   x := 3#12;   y := 12abc;   (* errors *)\n\
         \n    m := 16#FF;   x := 2#101;  y := 12;      (* fixes *)";
    INT_LITERAL_TOO_LARGE = "E0006", "integer literal too large",
        "The integer literal does not fit in 128 bits, so no type could hold it.\n\
         \n    x := 999999999999999999999999999999999999999999;  (* error *)\n\
         \n    x := 9223372036854775807;  (* fix: the largest LINT *)";
    MALFORMED_DURATION = "E0007", "malformed duration literal",
        "A duration is `T#` (or `TIME#`, `LT#`, `LTIME#`), an optional `-`, then numbers \
         with units d, h, m, s, ms, us, ns from the largest to the smallest, each at most \
         once; any number may have a decimal fraction, `_` may separate the parts.\n\
         \n    t := T#5x;   u := T#3s1h;   (* errors: unknown unit, units out of order *)\n\
         \n    t := T#5s;   u := T#1h3s;   (* fixes *)";
    MALFORMED_DATE_TIME = "E0008", "malformed date or time literal",
        "Dates are `D#YYYY-MM-DD` (or `DATE#`, `LD#`, `LDATE#`), times of day \
         `TOD#HH:MM:SS[.frac]` (or `TIME_OF_DAY#`, `LTOD#`), dates and times \
         `DT#YYYY-MM-DD-HH:MM:SS[.frac]` (or `DATE_AND_TIME#`, `LDT#`). Every field must be \
         in range (month 1-12, a day that exists in that month, hour 0-23, ...).\n\
         \n    d := D#2023-02-29;   t := TOD#24:00:00;   (* errors *)\n\
         \n    d := D#2023-02-28;   t := TOD#23:59:59;   (* fixes *)";
    MALFORMED_TYPED_LITERAL = "E0009", "malformed typed literal",
        "A typed literal is an elementary type name, `#`, then a value: a number with an \
         optional sign (`INT#-5`, `DINT#16#FF`, `REAL#1.5`), TRUE/FALSE or 0/1 for BOOL, or \
         a string for STRING and WSTRING.\n\
         \n    x := INT#five;   b := BOOL#2;   (* errors *)\n\
         \n    x := INT#5;      b := BOOL#1;   (* fixes *)";
    MALFORMED_ADDRESS = "E0010", "malformed direct address",
        "A direct address is `%`, a location I (input), Q (output) or M (memory), an \
         optional size X (bit), B, W, D or L, then numbers separated by dots, or `*` when \
         the address is assigned in a VAR_CONFIG. After a `.`, `%X3`, `%B1`, `%W0`, `%D0` and \
         `%L0` select a bit or a part of a variable.\n\
         \n    lamp AT %QY0.1 : BOOL;   (* error: Y is not a size *)\n\
         \n    lamp AT %QX0.1 : BOOL;   (* fix *)";
    UNEXPECTED_TOKEN = "E0101", "unexpected token",
        "The parser found something other than what the grammar allows at this point; the \
         message says what it expected.\n\
         \n    IF a > 1 x := 0; END_IF;        (* error: expected `THEN`, found `x` *)\n\
         \n    IF a > 1 THEN x := 0; END_IF;   (* fix *)";
    MISSING_SEMICOLON = "E0102", "missing `;`",
        "Every statement and every declaration ends with `;`, including the last one before \
         END_IF, ELSE, END_VAR and the like, and the END_IF/END_FOR/... of a compound \
         statement.\n\
         \n    IF a THEN x := 1 END_IF;    (* error: expected `;`, found `END_IF` *)\n\
         \n    IF a THEN x := 1; END_IF;   (* fix *)";
    UNMATCHED_END = "E0103", "closing keyword without an opening one",
        "An END_IF, END_FOR, ELSE, ELSIF, UNTIL (or similar) appears where no matching IF, \
         FOR, CASE or REPEAT is open.\n\
         \n    x := 1;\n    END_IF;          (* error: no IF is open *)\n\
         \n    IF c THEN x := 1; END_IF;   (* fix: open the IF, or delete the END_IF *)";
    UNCLOSED_BLOCK = "E0104", "block not closed",
        "A block (IF, CASE, FOR, WHILE, REPEAT, a POU, VAR, TYPE, STRUCT, ...) is not \
         closed by its END_ keyword before something that cannot be inside it.\n\
         \n    FUNCTION f : INT\n        IF a THEN f := 1;\n    END_FUNCTION   (* error: expected `END_IF` *)\n\
         \n    FUNCTION f : INT\n        IF a THEN f := 1; END_IF;\n    END_FUNCTION   (* fix *)";
    NESTING_TOO_DEEP = "E0105", "nesting too deep",
        "Parentheses, statements, types or initialisers are nested deeper than the compiler \
         allows (about 200 levels), or one expression is extremely long. Split the code: \
         put parts of the expression in temporary variables, or move nested statements into \
         a function.\n\
         \n    x := ((((((...))))));   (* error when nested hundreds of levels deep *)\n\
         \n    t := (...); x := (t);   (* fix: name an intermediate result *)";
    UNNAMED_LOCATED_VAR = "E0106", "located variable without a name",
        "Inside a PROGRAM, FUNCTION or FUNCTION_BLOCK a located variable needs a name so \
         that the code can use it; only global and configuration blocks may declare \
         anonymous locations.\n\
         \n    VAR AT %QX0.1 : BOOL; END_VAR        (* error *)\n\
         \n    VAR lamp AT %QX0.1 : BOOL; END_VAR   (* fix *)";
    SYNTAX_NOT_SUPPORTED = "E0107", "syntax not supported",
        "The construct is valid in some IEC 61131-3 dialect (an INTERFACE or CLASS \
         declared inside a POU, a METHOD inside a METHOD, VAR_ACCESS paths) but plcc does not support it. The parser skips it and goes on.\n\
         \n    FUNCTION_BLOCK Line\n      INTERFACE I_Motor ... END_INTERFACE   (* error: not supported here *)\n    END_FUNCTION_BLOCK\n\
         \n    (* fix: declare INTERFACEs and CLASSes at the top level of a file *)";
    NOT_A_STATEMENT = "E0108", "expression is not a statement",
        "A statement must be an assignment `target := value;`, a call `f(...);` or a \
         keyword statement (IF, CASE, FOR, ...). An expression on its own does nothing; \
         `=` compares, it does not assign.\n\
         \n    x = 5;    (* error: expected `:=` *)\n\
         \n    x := 5;   (* fix *)";

    NOTHING_TO_COMPILE = "E0109", "nothing to compile in a file",
        "A file given to plcc declares no PROGRAM, FUNCTION, FUNCTION_BLOCK, TYPE, \
         CONFIGURATION or VAR_GLOBAL, so nothing would be compiled from it: an empty file, \
         one of comments only, or a PLCopen XML file whose POUs are kept where plcc does \
         not read them (TwinCAT's exports keep them inside `<addData>`).\n\
         \n    (* only a comment *)          (* error: nothing to compile *)\n\
         \n    PROGRAM main ... END_PROGRAM   (* fix: declare something, or leave the file out *)";

    // ---- names and declarations (E02xx) ----
    E_UNDECLARED = "E0201", "name not declared",
        "A name is used that is not a variable of the POU, its FUNCTION result, or a FUNCTION.\n\n    x := y + 1;   (* y was never declared *)\n\nDeclare it (`VAR y : INT; END_VAR`) or fix the spelling. A FUNCTION nothing declares is reported once, at its first use, however often it is called; the note counts the calls and the first few are shown. If it is a vendor's block (implemented by an editor's runtime, such as OpenPLC's or Beremiz's), declare it, e.g. as stubs in a file given with `--lib FILE`.";
    E_DUPLICATE = "E0202", "declared twice",
        "Two POUs, or two variables of one POU, have the same name (names ignore case).\n\n    VAR a : INT; A : BOOL; END_VAR\n\nRename one of them.";
    E_UNKNOWN_TYPE = "E0203", "unknown type",
        "A declaration names a type that is neither elementary, nor declared by TYPE, nor a FUNCTION_BLOCK.\n\n    VAR t : TIMER; END_VAR   (* the standard on-delay timer is TON *)\n\nEach unknown name is reported once, at its first use, however many variables have the type; the note counts the uses and the first few are shown. Projects made for an editor's runtime use blocks that runtime implements in C (OpenPLC's Arduino, P1AM, MQTT blocks; Beremiz's `python_eval`, `csv_read_by_int`, SVGHMI blocks), which no IEC library declares: declare them, e.g. as stubs in a file given with `--lib FILE` (`plcc run main.st --lib stubs.st`).";
    E_NOT_A_TYPE = "E0204", "not a type",
        "A PROGRAM or FUNCTION name is used where a type is expected; only FUNCTION_BLOCKs can be instantiated.\n\n    VAR x : MyFunction; END_VAR";
    E_BAD_DECLARATION = "E0205", "invalid declaration",
        "A declaration breaks a rule of IEC 61131-3: array bounds reversed, an initial value where none is allowed, a CONSTANT section other than VAR, an array too large, R_EDGE or F_EDGE on anything but a BOOL VAR_INPUT of a FUNCTION_BLOCK or PROGRAM.\n\n    VAR a : ARRAY[10..1] OF INT; END_VAR";
    E_NOT_CONSTANT = "E0206", "not a constant expression",
        "Array bounds, CASE labels, repetition counts, initial values and CONSTANT values must be computable at compile time from literals and constants.\n\n    VAR CONSTANT n : INT := x; END_VAR   (* x is a variable *)";
    E_NO_MEMBER = "E0207", "no such member or parameter",
        "A member access or named argument names something the function block, STRUCT or function does not have, an internal variable that is not visible from outside, or a value its enumeration does not have (`Color#Purple`).\n\n    t(IN := x, TIME := T#1s);   (* TON's preset is PT *)";
    E_CONTAINS_ITSELF = "E0209", "function block or type contains itself",
        "A FUNCTION_BLOCK has an instance of itself among its variables, or a STRUCT a field of its own type, directly or through other function blocks, STRUCTs and arrays; a value of it would be infinitely large. The message shows the chain.\n\n    FUNCTION_BLOCK A VAR b : B; END_VAR END_FUNCTION_BLOCK\n    FUNCTION_BLOCK B VAR a : A; END_VAR END_FUNCTION_BLOCK";
    E_AMBIGUOUS = "E0210", "ambiguous enumeration value",
        "Several enumeration types have a value of this name, and the context does not say which one is meant (a variable or parameter of one of the types, the other operand of `=`, a CASE selector). Qualify the value with its type.\n\n    TYPE Color : (Red, Green); Light : (Red, Yellow); END_TYPE\n    ok := x = Red;         (* error if x is not of either type *)\n    c := Color#Red;        (* fine *)";
    E_PROGRAM_INSTANCE = "E0211", "a PROGRAM's variable without one instance",
        "In the CODESYS dialect a PROGRAM's variables are read from other POUs as `Prog.x` (CODESYS has one instance of each PROGRAM). plcc's PROGRAMs may have several instances, one per configured `PROGRAM inst WITH task : Prog`, or none when the build does not run the PROGRAM (a library's PROGRAM, one left out by `--program`, or one no configuration instantiates). `Prog.x` needs exactly one running instance: with several it does not say whose `x`, with none there is no `x`. Keep one instance of the PROGRAM, pass the value through a global variable, or run the PROGRAM.\n\n    PROGRAM fast WITH t1 : Counter;\n    PROGRAM slow WITH t2 : Counter;\n    ...\n    n := Counter.count;   (* error: fast's or slow's? *)";
    E_NO_PROGRAM = "E0208", "no such PROGRAM",
        "The PROGRAM asked for on the command line or in a scenario (`program = NAME`) is not declared in the given files.\n\n    plcc run --program mian prog.st   (* error: the PROGRAM is `main` *)\n    plcc run --program main prog.st   (* fix *)";

    // ---- types (E03xx) ----
    E_TYPE_MISMATCH = "E0301", "type mismatch",
        "A value of one type is used where another is needed and IEC 61131-3 does not convert it implicitly (only widening conversions are implicit: INT to DINT, REAL to LREAL, ...). Of the integer literals only 0 and 1 are BOOLs (IEC's boolean literals), where a BOOL is expected or beside a BOOL operand.\n\n    VAR i : INT; d : DINT; b : BOOL; END_VAR\n    i := d;              (* error: narrowing *)\n    i := DINT_TO_INT(d); (* explicit conversion: fine *)\n    b := 2;              (* error: 2 is not a BOOL; b := 1 and b AND 0 are fine *)";
    E_LITERAL_RANGE = "E0302", "literal out of range",
        "A literal or constant does not fit the type it is given: an elementary type, a subrange (`INT (0..100)`) or the base type of an enumeration.\n\n    VAR s : SINT; p : INT (0..100); END_VAR\n    s := 200;   (* SINT holds -128..127 *)\n    p := 150;   (* the subrange holds 0..100 *)";
    E_BAD_INDEX = "E0303", "invalid index or bit access",
        "An array is indexed with the wrong number of indexes or a non-integer, something that is not an array is indexed, or a bit number is out of the word.\n\n    VAR a : ARRAY[1..3] OF INT; w : WORD; END_VAR\n    a[1, 2] := 0;   (* one dimension *)\n    w.16 := TRUE;   (* bits 0..15 *)";
    E_BAD_CASE_LABEL = "E0304", "invalid CASE label",
        "CASE labels must be integer constants in the selector's range, and ranges must not be empty.\n\n    CASE x OF 5..1: a := 1; END_CASE   (* write 1..5 *)";
    E_BAD_FOR = "E0305", "invalid FOR loop",
        "A FOR loop whose step is the constant 0 never ends.\n\n    FOR i := 1 TO 10 BY 0 DO ... END_FOR";

    // ---- calls (E04xx) ----
    E_NOT_CALLABLE = "E0401", "cannot be called",
        "Only FUNCTIONs, standard functions and function block instances can be called; a FUNCTION_BLOCK type or a PROGRAM cannot. IL's CAL calls function block instances only: a FUNCTION is called with its name as the operator.\n\n    TON(IN := x, PT := T#1s);   (* call an instance: t(IN := x, PT := T#1s) *)\n    CAL ABS                     (* IL: LD x, then ABS *)";
    E_ARG_COUNT = "E0402", "wrong arguments",
        "A call has too many or too few arguments, gives one parameter twice, or mixes positional and named arguments where that is not allowed.\n\n    y := LIMIT(0, x);   (* LIMIT(MN, IN, MX) takes three *)";
    E_ARG_DIRECTION = "E0403", "argument in the wrong direction",
        "Inputs are passed with `:=` and outputs read with `=>`.\n\n    t(IN := x, Q := done);   (* Q is an output: Q => done *)";
    E_MISSING_ARG = "E0404", "missing VAR_IN_OUT argument",
        "A VAR_IN_OUT parameter refers to the caller's variable, so every call must give one.\n\n    FUNCTION inc : INT VAR_IN_OUT x : INT; END_VAR ...\n    inc();   (* inc(x := counter) *)";
    E_NO_RESULT = "E0405", "function without result used as a value",
        "A FUNCTION declared without a result type can only be called as a statement.\n\n    FUNCTION log_it VAR_INPUT v : INT; END_VAR ... END_FUNCTION\n    x := log_it(v := 3);   (* error: `log_it` gives no value *)\n    log_it(v := 3);        (* fix: call it as a statement *)";
    E_FB_CALL_IN_EXPR = "E0406", "function block call used as a value",
        "Calling a function block instance is a statement; its outputs are read afterwards.\n\n    x := t(IN := go);           (* error *)\n    t(IN := go); x := t.Q;      (* fine *)";

    // ---- writing, recursion (E05xx) ----
    E_WRITE_CONSTANT = "E0501", "assignment to a constant",
        "A VAR CONSTANT cannot be assigned or used as a FOR variable or VAR_IN_OUT argument.\n\n    VAR CONSTANT limit : INT := 10; END_VAR\n    limit := 20;          (* error *)\n    FOR limit := 1 TO 5 DO  (* error *)";
    E_WRITE_OUTPUT = "E0503", "assignment to an output of an instance",
        "The outputs of a function block instance are written by the instance itself; outside code can only read them. An output that is itself an instance (`CU_T : R_TRIG` in a VAR_OUTPUT) can be read (`ud.CU_T.Q`), but not called or written from outside.\n\n    t.Q := TRUE;          (* error *)\n    ud.CU_T(CLK := x);    (* error: CU_T is an output of ud *)";
    E_NOT_A_PLACE = "E0504", "not a variable",
        "Something that is not a variable is assigned, or passed to a VAR_IN_OUT (which needs a variable of exactly the parameter's type).\n\n    sw(io := a + 1);               (* error: the VAR_IN_OUT `io` needs a variable *)\n    tmp := a + 1; sw(io := tmp);   (* fix *)";
    E_RECURSION = "E0505", "recursion",
        "IEC 61131-3 forbids recursive calls, so that every frame can be allocated statically. The message shows the cycle of calls, through FUNCTIONs, function blocks and ACTIONs.\n\n    FUNCTION fact : DINT VAR_INPUT n : DINT; END_VAR\n        IF n > 1 THEN fact := n * fact(n - 1); ELSE fact := 1; END_IF;   (* error *)\n\n    f := 1; FOR i := 2 TO n DO f := f * i; END_FOR;   (* fix: a loop *)";
    E_OUTSIDE_LOOP = "E0506", "EXIT or CONTINUE outside a loop",
        "EXIT and CONTINUE can only appear inside FOR, WHILE or REPEAT.\n\n    IF done THEN EXIT; END_IF;   (* error: not in a loop *)\n    IF done THEN RETURN; END_IF; (* fix: leave the POU's body *)";
    E_WRITE_INTERNAL = "E0507", "assignment to an internal variable of another instance",
        "In the CODESYS dialect, code outside an instance (of a function block or a PROGRAM) may read its internal variables (VAR), as CODESYS allows, but not write them: an assignment, a `=>` target, a VAR_IN_OUT argument or a FOR variable. This holds for what an internal variable holds too (an element, a field, an input of an internal instance). Calling an internal instance or one of its ACTIONs is allowed, as CODESYS allows it. Under IEC 61131-3 (the default dialect) the internal variables are not visible from outside at all (E0207).\n\n    FUNCTION_BLOCK Acc VAR total : INT; END_VAR ...\n    v := a.total;      (* fine in --dialect codesys *)\n    a.total := 0;      (* error: give Acc an input or an ACTION that resets it *)";
    E_DUPLICATE_LABEL = "E0508", "label defined twice",
        "Two labels of one body (Instruction List, ladder) have the same name, so a jump to it would be ambiguous.\n\n    start: LD a\n    start: ST b   (* rename one *)";
    E_UNKNOWN_LABEL = "E0509", "jump to an unknown label",
        "A jump (JMP, JMPC, JMPCN) names a label that does not exist in the same body: the jump would go nowhere.\n\n    JMPC fnish   (* the label is `finish:` *)";

    // ---- not supported yet (E06xx) ----
    E_OO_DECLARATION = "E0800", "invalid object-oriented declaration",
        "A METHOD, PROPERTY, EXTENDS, IMPLEMENTS or INTERFACE breaks a rule of IEC 61131-3 (6.6.5-6.6.8): a FUNCTION with methods, a PROGRAM with methods outside the CODESYS dialect, EXTENDS of something that is not a FUNCTION_BLOCK (or a STRUCT of a STRUCT), inheritance in a circle, IMPLEMENTS of something that is not an INTERFACE, a method that overrides one with another signature, two members of one name.\n\n    FUNCTION_BLOCK A EXTENDS B ... FUNCTION_BLOCK B EXTENDS A   (* error: a circle *)";
    E_ABSTRACT = "E0801", "abstract function block or method",
        "An ABSTRACT FUNCTION_BLOCK cannot be instantiated, only extended; an ABSTRACT METHOD has no body and must be implemented by every concrete FUNCTION_BLOCK derived from its own; a concrete FUNCTION_BLOCK must implement every method of the interfaces it implements.\n\n    FUNCTION_BLOCK ABSTRACT Shape METHOD ABSTRACT Area : REAL END_METHOD END_FUNCTION_BLOCK\n    VAR s : Shape; END_VAR        (* error: Shape is abstract *)";
    E_FINAL = "E0802", "FINAL function block or method",
        "A FINAL FUNCTION_BLOCK cannot be extended and a FINAL METHOD cannot be overridden.\n\n    FUNCTION_BLOCK FINAL A ... FUNCTION_BLOCK B EXTENDS A   (* error *)";
    E_ACCESS = "E0803", "member not accessible",
        "A PRIVATE method or property is used only inside the FUNCTION_BLOCK that declares it; a PROTECTED one inside that FUNCTION_BLOCK and those derived from it. PUBLIC (the default) and INTERNAL members can be used anywhere in the project.\n\n    METHOD PRIVATE helper ... END_METHOD\n    inst.helper();                 (* error, outside the FUNCTION_BLOCK *)";
    E_UNSUPPORTED = "E0601", "not supported yet",
        "The construct is valid IEC 61131-3 (or a common dialect) but plcc does not compile it yet. The message names the construct.\n\n    r := BCD_TO_REAL(w);   (* error: not supported yet (BCD conversions give integers) *)";
    E_LANGUAGE_UNSUPPORTED = "E0602", "language not supported yet",
        "A body of a PLCopen XML file is written in a language plcc has no front end for \
         there: a sequential function chart (`<SFC>`) as the body of an action or a \
         transition (a chart is the body of a PROGRAM or FUNCTION_BLOCK only), or an \
         unknown language element. plcc compiles `<LD>`, `<FBD>`, `<ST>` and `<IL>` bodies, \
         and `<SFC>` bodies of POUs.\n\
         \n    <action name=\"A\"><body><SFC> ... </SFC></body></action>   <!-- error -->\n\
         \n    <action name=\"A\"><body><ST> ... </ST></body></action>     <!-- fine -->";

    // ---- textual sequential function charts (E078x, W078x) ----
    SFC_TEXT_NO_INITIAL_STEP = "E0780", "chart without an initial step",
        "A sequential function chart needs an INITIAL_STEP: the step that is active when \
         the POU starts. Without one no step would ever be active.\n\
         \n    STEP Idle: END_STEP            (* error: no initial step *)\n\
         \n    INITIAL_STEP Idle: END_STEP    (* fix *)";
    SFC_TEXT_UNKNOWN_STEP = "E0781", "transition to or from an unknown step",
        "A TRANSITION names, after FROM or TO, a step the chart does not declare (a jump \
         to a missing step).\n\
         \n    TRANSITION FROM Fill TO Drian := full; END_TRANSITION   (* the step is `Drain` *)";
    SFC_TEXT_QUALIFIER = "E0782", "bad action qualifier",
        "An action association has a qualifier that is not one of N, R, S, L, D, P, P1, P0, \
         SD, DS and SL, a timed qualifier (L, D, SD, DS, SL) without its duration, or a \
         duration on a qualifier that takes none.\n\
         \n    Pump(L);          (* error: L needs a duration *)\n\
         \n    Pump(L, T#5s);    (* fix *)";
    SFC_TEXT_ACTION = "E0783", "association of something that is no action",
        "An action association in a step names something that is neither an ACTION of the \
         POU nor a BOOL variable (which the chart then sets while the action is active).\n\
         \n    VAR count : INT; END_VAR\n    STEP Run: count(N); END_STEP      (* error: count is an INT *)\n\
         \n    STEP Run: Counting(N); END_STEP   (* fix: ACTION Counting: count := count + 1; END_ACTION *)";
    SFC_TEXT_UNSAFE = "E0784", "unsafe chart",
        "A transition can activate a step that is already active: two tokens would meet on \
         one step. It comes from a simultaneous divergence whose branches are closed by a \
         selective convergence (or a loop that laps a branch). IEC 61131-3 rejects such \
         charts; under `--sfc matiec` it is warning W0782, as matiec runs it (the step \
         stays active).\n\
         \n    TRANSITION FROM S0 TO (A, B) := go; END_TRANSITION\n    TRANSITION FROM A TO C := x; END_TRANSITION\n    TRANSITION FROM B TO C := y; END_TRANSITION   (* error: A and B both reach C *)\n\
         \n    TRANSITION FROM (A, B) TO C := x AND y; END_TRANSITION   (* fix *)";
    W_SFC_SHARED = "W0784", "action driven by several charts",
        "An ACTION is associated with steps of two charts of one POU (the body's and an \
         action's written as a chart, or two such actions). Each chart has a control of \
         its own for it, and the action runs for each, as CODESYS runs it (twice in a \
         scan when both are active); its flags (`A.Q`, `A.A`) are those of the first \
         chart. CODESYS rejects it when the charts are nested in one another.\n\
         \n    ACTION Sub:\n      INITIAL_STEP S1: Pump(N); END_STEP ...\n    END_ACTION\n    \
         INITIAL_STEP Main: Sub(N); Pump(N); END_STEP   (* warning: Pump in both charts *)";
    W_SFC_STEP_RENAMED = "W0785", "step named like a step of another chart",
        "A chart of an ACTION has a step of the name of a step of another chart of the \
         POU (its body's, or another action's). CODESYS scopes step names by chart, so \
         plcc keeps them apart: the later step is a variable of its own, and `S.X` in \
         that chart's conditions and durations reads it; elsewhere (the POU's code, \
         other charts, scenarios) `S.X` is the first chart's step. Rename one of them \
         to read both from everywhere.\n\
         \n    ACTION Up:\n      INITIAL_STEP Stop: END_STEP ...\n    END_ACTION\n    \
         ACTION Down:\n      INITIAL_STEP Stop: END_STEP ...   (* warning: Stop again *)\n    END_ACTION";
    SFC_TEXT_RECURSIVE = "E0785", "charts that drive each other",
        "An ACTION written as a chart drives itself, directly or through other actions \
         written as charts: running it would run it again, without end.\n\
         \n    ACTION Sub:\n      INITIAL_STEP S1: Sub(N); END_STEP   (* error *)\n    END_ACTION";
    W_SFC_UNREACHABLE = "W0780", "step never active",
        "No chain of transitions leads to the step from an initial step, so it is never \
         active and its actions never run. matiec and the editors drop such steps \
         silently.\n\
         \n    INITIAL_STEP A: END_STEP\n    STEP B: END_STEP   (* no TRANSITION ... TO B *)";
    W_SFC_DEAD_END = "W0781", "step with no way out",
        "No transition leaves the step: once active, it stays active for good. That may be \
         meant (a final state); usually a transition is missing.\n\
         \n    TRANSITION FROM Run TO Stop := halt; END_TRANSITION\n    (* and none FROM Stop *)";
    W_SFC_UNSAFE = "W0782", "unsafe chart, run as matiec runs it",
        "Under `--sfc matiec`, an unsafe chart (E0784: a transition can activate a step \
         that is already active) is compiled, as matiec compiles it: the step stays \
         active and the second token is lost.\n\
         \n    TRANSITION FROM S0 TO (A, B) := go; END_TRANSITION\n    TRANSITION FROM A TO C := x; END_TRANSITION\n    TRANSITION FROM B TO C := y; END_TRANSITION";
    W_SFC_DEAD_TRANSITION = "W0783", "transition that never fires",
        "The steps before the transition are never active together, whatever the \
         conditions: it waits for steps of branches that exclude each other (a selective \
         divergence closed by a simultaneous convergence).\n\
         \n    TRANSITION FROM S0 TO A := x; END_TRANSITION\n    TRANSITION FROM S0 TO B := y; END_TRANSITION\n    TRANSITION FROM (A, B) TO C := TRUE; END_TRANSITION   (* warning *)";

    // ---- ladder diagrams in PLCopen XML (E074x, E075x) ----
    LD_MALFORMED_XML = "E0740", "malformed XML",
        "The file is not well-formed XML (a tag not closed, an attribute without quotes, a \
         stray `&` or `<`), so it cannot be read as a PLCopen project. The message gives \
         the XML parser's reason.\n\
         \n    <contact localId=7 negated=\"false\">     <!-- error: attribute values need quotes -->\n\
         \n    <contact localId=\"7\" negated=\"false\">  <!-- fix -->";
    LD_BAD_PROJECT = "E0741", "not a valid PLCopen project",
        "The XML is well formed but is not a PLCopen TC6 project as plcc reads it: the root \
         is not a `<project>` in the namespace `http://www.plcopen.org/xml/tc6_0201` (or \
         `tc6.xsd`, `tc6_0200`), or an element lacks what it needs (a POU without `name` or \
         `pouType`, a variable without `<type>`, an unknown type or value element).\n\
         \n    <pou name=\"main\">                      <!-- error: no pouType -->\n\
         \n    <pou name=\"main\" pouType=\"program\">   <!-- fix -->";
    LD_BAD_ELEMENT = "E0742", "invalid ladder element",
        "An element of a ladder body is malformed or cannot be there: no `localId` (or one \
         that is not a number, or that another element of the body has too), a contact or \
         coil without `<variable>`, a block without `typeName`, an element that belongs to \
         another language (an SFC step), or a rising or falling contact in a FUNCTION (edge \
         detection needs memory from one call to the next, which a FUNCTION has not).\n\
         \n    <contact localId=\"3\"> ... </contact>   <!-- error: no <variable> -->\n\
         \n    <contact localId=\"3\"> ... <variable>start</variable></contact>   <!-- fix -->";
    LD_DANGLING = "E0743", "dangling connection",
        "A connection refers to an element that does not exist (`refLocalId` names no \
         `localId` of the body), to an output a block does not have (`formalParameter`), or \
         to an element with no output (a coil's connection point in is not an output; a \
         jump, a label, an output variable and the right rail have no output).\n\
         \n    <connection refLocalId=\"42\"/>               <!-- error if no element has localId 42 -->\n\
         \n    <connection refLocalId=\"5\" formalParameter=\"Q\"/>   <!-- fix: an existing block and output -->";
    LD_OPEN_CIRCUIT = "E0744", "open circuit",
        "Power cannot flow through part of a rung: nothing is connected to the left of a \
         contact, coil, jump or return (it hangs in the air), or the power through a \
         contact goes nowhere (its right side is not connected to a coil, a block or \
         another contact).\n\
         \n    |--[start]--      --(motor)--|     error: the two halves do not touch\n\
         \n    |--[start]--------(motor)--|       fix";
    LD_SHORT_CIRCUIT = "E0745", "short circuit",
        "A parallel branch is bypassed by a bare wire: the wire joins the same two points \
         as a branch with contacts, so those contacts can never change anything.\n\
         \n    |--+--[a]--+--(x)--|     error: the lower branch is a bare wire, x is\n\
         \n    |  +-------+             always powered\n\
         \n    |--[a]--(x)--|           fix: remove the wire (or put a contact on it)";
    LD_UPPER_PARALLEL = "E0746", "upper parallel branch",
        "A parallel branch is drawn above the line it joins or leaves. A rung is read top \
         to bottom, its main line first: parallel branches go below it.\n\
         \n    |--[b]--+                  error: the branch b is above the line a-x\n\
         \n    |--[a]--+--(x)--|\n\
         \n    |--[a]--+--(x)--|          fix\n\
         \n    |--[b]--+";
    LD_BRIDGE = "E0747", "bridge",
        "A vertical connection joins two parallel branches in their middle, so the rung is \
         not made of series and parallel connections. In ladder, power flows left to right \
         only; a bridge would be read differently by every tool. Split the rung, or repeat \
         the contacts on each path.\n\
         \n    |--[a]--+--[c]--+--(x)--|     error: the wire from a's output to d's input\n\
         \n    |--[b]------[d]-+             crosses from one branch into the other\n\
         \n    |--[a]--[c]--+--(x)--|        fix: each path written out\n\
         \n    |--[a]--[d]--+\n\
         \n    |--[b]--[d]--+";
    LD_COIL_ON_RAIL = "E0748", "coil on the left rail",
        "A coil is connected straight to the left power rail, with no contact in front of \
         it. Such a rung writes TRUE on every scan; the reference's checker rejects it as a \
         drawing mistake. Put the contact that should control it in front, or, to write a \
         constant, a contact on a variable that holds it.\n\
         \n    |--(lamp)--|             error\n\
         \n    |--[power_on]--(lamp)--|  fix";
    LD_BLOCK_INPUT = "E0749", "block input not connected",
        "A block lacks an input it needs: a function block its power input (EN if it has \
         one, else its first input: a timer's IN, a counter's CU), or a function any of its \
         inputs (a function has no state to take a missing value from).\n\
         \n    |            [TON T1 PT:=T#5s]--(lamp)--|    error: nothing drives IN\n\
         \n    |--[start]---[TON T1 PT:=T#5s]--(lamp)--|    fix";
    LD_LOOP = "E0750", "feedback loop",
        "The connections of a rung form a loop: an element's output comes back to its own \
         input. Power flows from left to right only, so a loop has no order to evaluate it \
         in. To use a value in the next scan, write it with a coil and read it with a \
         contact.\n\
         \n    <contact localId=\"2\"> ... <connection refLocalId=\"3\"/> ...\n\
         \n    <contact localId=\"3\"> ... <connection refLocalId=\"2\"/> ...   <!-- error -->";
    LD_OUTPUT_TYPE = "E0751", "type of a block output unknown",
        "The result of a function block (ADD, SEL, ...) is needed after the block, so plcc \
         keeps it in a temporary variable, whose type it must know. It takes it from the \
         function's declaration, from a variable wired to the block's output, or from a \
         variable (or typed literal) wired to its inputs; here there is none.\n\
         \n    [ADD IN1:=5 IN2:=3]--+--> (two other blocks)     error: 5 and 3 have no type\n\
         \n    [ADD IN1:=INT#5 IN2:=3]--+--> ...                  fix";
    W_PLCOPEN_IGNORED = "W0740", "ignored under the chosen PLCopen profile",
        "Under the editors' profiles (`--plcopen-order xml2st`, `openplc3`, `beremiz`), plcc \
         gives a diagram the meaning the editor's translator (PLCGenerator) gives it, and \
         that translator writes nothing for jumps, labels and returns in LD and FBD \
         bodies: they do nothing. The standard profile (`iec`, the default) runs them.\n\
         \n    plcc run --plcopen-order openplc3 prog.xml   (* warning: the jump is ignored *)\n\
         \n    plcc run prog.xml                           (* the jump is taken when powered *)";
    W_PLCOPEN_SKIPPED = "W0741", "element of a PLCopen file skipped",
        "An element is where PLCopen TC6 has no such element, and the editors drop it when \
         they load the file, so plcc skips it too. Today: `<varList>` in a POU's interface \
         (the schema's name of the type of variable sections, which some tools write as \
         an element, often holding copies of the variables with empty types). Declare \
         variables in `<inputVars>`, `<outputVars>`, `<inOutVars>`, `<localVars>`, \
         `<tempVars>`, `<externalVars>` or `<globalVars>`.\n\
         \n    <interface><varList><variable name=\"x\">...</variable></varList></interface>      <!-- warning -->\n\
         \n    <interface><localVars><variable name=\"x\">...</variable></localVars></interface>  <!-- fine -->";

    // ---- sequential function charts in PLCopen XML (E076x, W076x) ----
    SFC_BAD_ELEMENT = "E0760", "invalid SFC element",
        "An element of a sequential function chart is malformed or wired where the chart \
         cannot use it: a step without `name`, two steps with one name, a `priority` that \
         is not a number, a step, jump or action block connected to an element that is \
         not of the kind it needs (a step follows a transition; an action block hangs on a \
         step), or an inline action in another language than ST.\n\
         \n    <step localId=\"3\" name=\"S1\"/> ... <step localId=\"7\" name=\"S1\"/>   <!-- error: two steps S1 -->\n\
         \n    <step localId=\"3\" name=\"S1\"/> ... <step localId=\"7\" name=\"S2\"/>   <!-- fix -->";
    SFC_NO_INITIAL_STEP = "E0761", "SFC without an initial step",
        "A sequential function chart has no step with `initialStep=\"true\"`. The chart \
         is written out from its initial steps (the editors' translator does the same), so \
         without one nothing of it would run; the editors' translator stops with \"No body \
         defined\".\n\
         \n    <step localId=\"1\" name=\"Init\"/>                      <!-- error -->\n\
         \n    <step localId=\"1\" name=\"Init\" initialStep=\"true\"/>  <!-- fix -->";
    SFC_JUMP_TARGET = "E0762", "jump to a missing step",
        "A `<jumpStep>` names a step (`targetName`) that the chart does not have.\n\
         \n    <jumpStep localId=\"9\" targetName=\"Strat\"/>   <!-- error: the step is `Start` -->\n\
         \n    <jumpStep localId=\"9\" targetName=\"Start\"/>   <!-- fix -->";
    SFC_TRANSITION_UNCONNECTED = "E0763", "transition without a step before or after it",
        "A transition of the chart leads from no step or to no step: its \
         `connectionPointIn` is not connected to a step (or to a divergence or convergence \
         of steps), or nothing after it (a step, a jump, a convergence or divergence \
         leading to one) is connected to it. Textual SFC needs both `FROM` and `TO`.\n\
         \n    TRANSITION FROM S1 TO ???   (* error: nothing follows the transition *)\n\
         \n    TRANSITION FROM S1 TO S2    (* fix: connect a step or a jump after it *)";
    SFC_NO_DURATION = "E0764", "timed qualifier without a duration",
        "An action of an action block has a timed qualifier (L, D, SD, DS or SL) but no \
         `duration`. The qualifier needs the time, and IEC compilers reject the \
         association without it.\n\
         \n    <action qualifier=\"L\"><reference name=\"Fill\"/></action>                  <!-- error -->\n\
         \n    <action qualifier=\"L\" duration=\"T#2s\"><reference name=\"Fill\"/></action>  <!-- fix -->";
    SFC_QUALIFIER = "E0765", "action qualifier not accepted",
        "An action's qualifier is not one of N, R, S, P, P0, P1, L, D, SD, DS and SL. The \
         PLCopen schema also allows DL (delayed and time limited), which textual SFC \
         (and so every compiler of the editors' translations) does not have.\n\
         \n    <action qualifier=\"DL\" duration=\"T#1s\"> ...   <!-- error -->\n\
         \n    <action qualifier=\"D\" duration=\"T#1s\"> ...    <!-- e.g. a delay: D, or split the step -->";
    SFC_NO_CONDITION = "E0766", "transition without a usable condition",
        "A transition of the chart has no condition, or one plcc cannot use: an inline \
         condition in another language than ST, a `<reference name=\"T\">` to a \
         transition the POU does not define in `<transitions>`, or a graphical condition \
         whose `connectionPointIn` is connected to nothing.\n\
         \n    <condition><reference name=\"T9\"/></condition>    <!-- error if the POU has no transition T9 -->\n\
         \n    <condition><inline name=\"\"><ST><xhtml:p>start</xhtml:p></ST></inline></condition>   <!-- e.g. an ST expression -->";
    SFC_TRANSITION_BODY = "E0767", "transition body without its result",
        "A transition of the POU (`<transitions><transition name=\"T\">`) written in LD or \
         FBD must compute its value in a coil named `T` or an output variable whose \
         expression is `T`; this one has neither.\n\
         \n    |--[a]--[b]--(done)--|     error in transition `T`: no coil T\n\
         \n    |--[a]--[b]--(T)--|        fix";
    W_SFC_DROPPED = "W0760", "SFC element not reachable, dropped",
        "A step, transition or action of a sequential function chart cannot be reached \
         from an initial step (or an action of the POU is used by no step), so it is left \
         out, as the editors' translator leaves it out: it never runs.\n\
         \n    INITIAL_STEP S0 -> S1 -> S0;  S9 -> S10 -> S9   (* warning: the island S9/S10 is dropped *)";
    W_SFC_MACRO_STEP = "W0761", "macro step ignored",
        "A `<macroStep>` is ignored, as the editors' translator ignores it: the chart is \
         written out without it, and what hangs on it only is not reached. Draw the \
         macro step's body in the chart itself.\n\
         \n    <macroStep localId=\"5\" name=\"M\"> ... </macroStep>   <!-- warning -->";

    // ---- PLC-UD STL (E072x) ----
    STL_UNEXPECTED_CHAR = "E0720", "unexpected character in STL",
        "The character cannot start any token of the PLC-UD STL. Outside comments, STL \
         uses ASCII letters, digits, `_` and the operators `:= + - * / % = <> < > <= >= ( ) \
         , ; : .`; it has no strings, arrays or `&`.\n\
         \n    x := a & b;     (* error: `&` is not an operator *)\n\
         \n    x := a and b;   (* fix *)";
    STL_UNTERMINATED_COMMENT = "E0721", "unterminated comment in STL",
        "A comment `(* ... *)` runs to the end of the file. Comments nest, so every `(*` \
         inside one needs its own `*)`.\n\
         \n    (* outer (* inner *)   x := 1;   (* error: the outer comment is never closed *)\n\
         \n    (* outer (* inner *) *) x := 1;  (* fix *)";
    STL_MALFORMED_NUMBER = "E0722", "malformed number in STL",
        "A number is decimal (`42`), based (`2#1010`, `8#17`, `16#FF`: base 2, 8 or 16) or \
         written with the PLC-UD constant marker (`#30`); it must fit in 128 bits and have \
         no letters glued to it.\n\
         \n    x := 16#FG;   y := 12abc;   (* errors *)\n\
         \n    x := 16#FF;   y := 12;      (* fixes *)";
    STL_UNEXPECTED_TOKEN = "E0723", "unexpected token in STL",
        "The parser found something the STL grammar does not allow here (a malformed \
         statement, a missing `then`/`do`/`)`, a keyword used as a name, an `else` \
         without its `if`, ...); the message says what it expected.\n\
         \n    if a > 1 x := 0;        (* error: expected `then`, found `x` *)\n\
         \n    if a > 1 then x := 0;   (* fix *)";
    STL_MISSING_SEMICOLON = "E0724", "missing `;` in STL",
        "Every simple statement (assignment, procedure call, `repeat ... until c`), every \
         declaration, `end_var`, `uses` and the `program NAME` header end with `;`. Only a \
         `begin ... end` block needs none, and the `;` before `else` may be left out.\n\
         \n    x := 1\n    y := 2;    (* error: expected `;` after `x := 1` *)\n\
         \n    x := 1;\n    y := 2;    (* fix *)";
    STL_ASSIGN_WITHOUT_COLON = "E0725", "assignment written without `:=`",
        "STL assigns with `:=`; `=` compares two values (its result is BOOL), so \
         `x = 5;` is a comparison used as a statement. `: =` with a space is not `:=` \
         either.\n\
         \n    x = 5;    (* error: use `:=` to assign *)\n\
         \n    x := 5;   (* fix *)";
    STL_DECLARATION_ORDER = "E0726", "declarations out of order",
        "An STL program is, in this order: `pragma` lines and `uses`, `program NAME;`, the \
         global `var ... end_var;` blocks, the global `constant`s, the functions and \
         procedures, then the main body `begin ... end.`. Inside the main body and inside \
         a subprogram, the local `var` blocks come first, then the local `constant`s, \
         then the statements.\n\
         \n    program p;\n    constant k : INT := 5;\n    var x : INT; end_var;   (* error: a var block after a constant *)\n\
         \n    program p;\n    var x : INT; end_var;\n    constant k : INT := 5;  (* fix *)";
    STL_MISSING_END_DOT = "E0727", "missing `end.`",
        "The main body of an STL program is `begin ... end.`: it ends with `end` and a \
         dot, and the file must have one.\n\
         \n    begin\n      x := 1;\n    end;     (* error: expected `end.` *)\n\
         \n    begin\n      x := 1;\n    end.     (* fix *)";
    STL_UNCLOSED_BLOCK = "E0728", "block not closed",
        "A `begin` has no `end`, a `repeat` no `until`, or a `var` block no `end_var` before \
         something that cannot be inside it. (The `end.` of the main body closes only the \
         main body.)\n\
         \n    if a then begin x := 1;\n    end.          (* error: the inner `begin` is not closed *)\n\
         \n    if a then begin x := 1; end\n    end.          (* fix *)";
    STL_NESTING_TOO_DEEP = "E0729", "nesting too deep in STL",
        "Parentheses or statements are nested deeper than the compiler allows (about 200 \
         levels), or one expression is extremely long. Split the code: put parts of the \
         expression in variables, or move nested statements into a procedure.\n\
         \n    x := ((((((...))))));   (* error when nested hundreds of levels deep *)\n\
         \n    t := (...); x := (t);   (* fix: name an intermediate result *)";
    STL_CHAINED_COMPARISON = "E0730", "chained comparison",
        "In STL a comparison relates two expressions (`a < b`); comparisons do not chain, \
         so `a < b < c` has no meaning. Combine two comparisons with `and`, or parenthesise \
         a comparison used as a BOOL operand.\n\
         \n    if 0 < x < 10 then ...           (* error *)\n\
         \n    if 0 < x and x < 10 then ...     (* fix *)";
    STL_CONSTANT_WITHOUT_VALUE = "E0731", "constant without a value",
        "An STL constant is `constant NAME : TYPE := value;`: the value is mandatory, and \
         each constant has its own `constant` keyword.\n\
         \n    constant limit : INT;         (* error *)\n\
         \n    constant limit : INT := 100;  (* fix *)";
    STL_RESULT_TYPE = "E0732", "function without a result type, or procedure with one",
        "A `function` returns a value, so its header names the result type; a \
         `procedure` returns nothing and has none.\n\
         \n    function twice(a : INT);          (* error: no result type *)\n\
         \n    function twice(a : INT) INT;      (* fix; or make it a procedure *)";
    STL_TEXT_AFTER_END = "E0733", "text after `end.`",
        "The `end.` of the main body ends the program; nothing but comments may follow. \
         Functions and procedures are declared before the main body.\n\
         \n    begin x := f(1); end.\n    function f(a : INT) INT; begin f := a; end;   (* error *)\n\
         \n    function f(a : INT) INT; begin f := a; end;\n    begin x := f(1); end.   (* fix *)";
    STL_TYPE = "E0734", "not a type of STL",
        "PLC-UD STL has five types: BOOL (1 bit), SINT and USINT (8 bits), INT and UINT \
         (16 bits). Other IEC 61131-3 types (DINT, REAL, TIME, ...) are for Structured \
         Text or Instruction List files, whose FUNCTIONs an STL program can call.\n\
         \n    var total : DINT; end_var;   (* error *)\n\
         \n    var total : INT; end_var;    (* fix; or move the wide arithmetic to a .st file *)";

    // ---- Instruction List (E07xx) ----
    IL_MALFORMED = "E0701", "malformed IL instruction",
        "An Instruction List body holds one instruction per line: an optional label \
         `name:`, an operator (LD, ST, AND, ADD, JMP, CAL, ... or a function name), its \
         modifiers and its operands separated by commas. The line does not start with an \
         operator, or something follows the operands. Structured Text statements cannot \
         be mixed into an IL body (a POU body is either IL or ST).\n\
         \n    LD a + b      (* error: operands are single values *)\n\
         \n    LD a          (* fix *)\n    ADD b";
    IL_MISSING_OPERAND = "E0702", "missing operand",
        "The operator needs an operand on the same line: LD, LDN, ST, STN, S, R, JMP, CAL, \
         the FB input operators (S1, R1, CLK, CU, CD, PV, IN, PT) and the arithmetic, \
         logic and comparison operators (except after `(`, whose operand may follow on \
         the next lines).\n\
         \n    LD            (* error: load what? *)\n\
         \n    LD start      (* fix *)";
    IL_OPERAND_NOT_ALLOWED = "E0703", "operand where none is allowed",
        "NOT, RET, RETC, RETCN and `)` work on the current result alone and take no \
         operand.\n\
         \n    NOT x         (* error *)\n\
         \n    LD x          (* fix: load x, then negate the current result *)\n    NOT";
    IL_BAD_MODIFIER = "E0704", "modifier not allowed with this operator",
        "IL modifiers are `N` (negate the operand: LDN, STN, ANDN, ORN, XORN, &N), `C` and \
         `CN` (only if the current result is TRUE / FALSE: JMPC, JMPCN, CALC, CALCN, RETC, \
         RETCN) and `(` (defer the operator: AND(, ADD(, GT(, ...). Other combinations \
         have no meaning.\n\
         \n    JMPN skip     (* error: jumps take C or CN *)\n    LDN( a        (* error: LD cannot be deferred *)\n\
         \n    JMPCN skip    (* fix *)\n    LDN a";
    IL_UNMATCHED_CLOSE = "E0705", "`)` without `(`",
        "A `)` ends a deferred operation opened by an operator with the `(` modifier; no \
         such operation is open here.\n\
         \n    LD a\n    AND b\n    )             (* error *)\n\
         \n    LD a\n    AND( b\n    OR c\n    )             (* fix: a AND (b OR c) *)";
    IL_UNCLOSED_PAREN = "E0706", "`(` not closed",
        "An operator with the `(` modifier (AND(, ADD(, ...) defers its operation until the \
         matching `)`; the body, or a label, jump, return or CAL, comes before it.\n\
         \n    LD a\n    AND( b\n    OR c\n    ST x          (* error: the AND( is still open *)\n\
         \n    LD a\n    AND( b\n    OR c\n    )\n    ST x          (* fix *)";
    IL_NESTING_TOO_DEEP = "E0707", "IL parentheses nested too deeply",
        "Deferred operations `op(` ... `)` are nested deeper than plcc allows (200 levels). \
         Store intermediate results in variables instead.\n\
         \n    LD a\n    AND( b\n    AND( c        (* ... hundreds of levels *)\n\
         \n    LD b\n    AND c\n    ST t          (* fix: name an intermediate result *)\n    LD a\n    AND t";
    IL_BAD_OPERAND = "E0708", "invalid operand",
        "IL operands are single values: a literal, a variable, a member `a.b`, an array \
         element `a[i]`, a bit `w.3` or a direct address. A jump needs a label name, CAL \
         and the FB input operators a function block instance; a function is called by \
         writing its name as the operator, not inside an operand.\n\
         \n    LD -a         (* error *)\n    LD ABS(x)     (* error *)\n    JMP 10        (* error *)\n\
         \n    LD x\n    ABS           (* fix: ABS of the current result *)";
    IL_NOT_IN_PARENS = "E0709", "instruction not allowed inside `(` ... `)`",
        "Between an operator with the `(` modifier and its `)` only instructions that \
         compute a value are allowed: no label, jump, return or CAL (the deferred \
         operation would be left half done).\n\
         \n    LD a\n    AND( b\n    JMPC out      (* error *)\n    )\n\
         \n    LD b\n    JMPC out\n    LD a\n    AND b         (* fix: jump before or after *)";
    IL_CR_UNDEFINED = "W0701", "the current result is undefined here",
        "An instruction uses the current result (CR) where no value has been loaded: at the \
         start of a body or right after a label (control can reach a label from anywhere, \
         so the CR is undefined there). plcc warns and uses a neutral value of the \
         operand's type (0, FALSE, T#0s): the code is compiled, but its result means \
         nothing, so it is not used as a FUNCTION's result either. Start with LD.\n\
         \n    next:\n    ADD 1         (* warning: add 1 to what? *)\n\
         \n    next:\n    LD count\n    ADD 1         (* fix *)";
    IL_CR_NOT_RESULT = "W0702", "the current result is not used as the FUNCTION result",
        "In a FUNCTION that never stores to its own name, the current result at RET and at \
         the end of the body is the function's result. Here it is a BOOL (a BOOL literal, \
         a comparison, ...) while the function returns another type, so it is taken as \
         left over rather than as the result, and the result keeps its initial value. \
         Store the result explicitly.\n\
         \n    FUNCTION f : INT\n    LD x\n    GT 5          (* warning: a BOOL, not the INT result *)\n\
         \n    FUNCTION f : INT\n    LD x\n    ST f          (* fix *)";
    IL_NOT_WITH_OPERAND = "W0703", "`NOT` with an operand",
        "IEC 61131-3's NOT takes no operand: it negates the current result. Some compilers (matiec) accept `NOT x`; plcc reads it as `LDN x` (load the negation of x) and says so.\n\n    NOT TRUE   (* read as LDN TRUE *)";

    // ---- warnings (W0xxx) ----
    W_C_PRAGMA = "W0010", "C code in a pragma is skipped",
        "matiec, the compiler of Beremiz and OpenPLC, copies the text of a pragma into the C it generates, so their projects inline C in ST and IL bodies: `{{ ... }}` blocks, or single pragmas such as `{__SET_VAR(data__->,Q,,TRUE);}`. plcc's `c` target does the same for a pragma that stands where a statement may stand in a PROGRAM's or FUNCTION_BLOCK's body (docs/c.md). Everywhere else (the other targets, which cannot run C; a pragma inside a statement or among declarations; a FUNCTION's body; STL) the pragma is skipped, with this warning, and the ST around it is compiled; whatever the C did (set variables, call C functions, read the clock) does not happen, so rewrite it in ST if the program needs it. `{{` ends at the first `}}` and `{` at the first `}`. Pragmas of other compilers that change nothing plcc compiles are skipped silently: CODESYS and TwinCAT ones (`{attribute 'x'}`, `{warning 'x'}`, `{IF ...}`, `{region ...}`, `{flag ...}`, ...), Siemens attributes (`{S7_Optimized_Access := 'TRUE'}`) and matiec's `{disable code generation}`, `{enable code generation}` and `{#include \"f\"}`.\n\n    IF trig THEN\n    {{ printf(\"on\\n\"); }}   (* warning: skipped *)\n    END_IF;";
    W_CASE_OVERLAP = "W0304", "overlapping CASE labels",
        "A CASE label covers values an earlier label already covers. The arms are tried in order, so for those values the earlier arm runs and the later label is (partly) dead: usually a mistake.\n\n    CASE x OF 1..5: a := 1; 3: a := 2; END_CASE   (* 3 never reaches `a := 2` *)";
    W_CPDEV_INTERNAL = "W0208", "an FB instance's internal variable used from outside (CPDev dialect)",
        "In a `.cst` file (Structured Text as the CPDev compiler reads it), a program may use an internal VAR of a function block instance from outside, as CPDev allows; IEC 61131-3 allows only inputs and outputs (error E0207 in `.st` files). It compiles, but the program now depends on the block's insides.\n\n    ship(rudder := r);\n    heading := ship.psi_internal;   (* W0208 in a .cst file, E0207 in a .st file *)";
    W_PROTOTYPES = "W0209", "prototypes are checked, not compiled",
        "FUNCTIONs declared under matiec's `{disable code generation}` pragma are prototypes: matiec's standard library declares every standard function that way so that its compiler knows their types. plcc has the standard functions built in, so it checks the prototypes' types and compiles nothing; calls keep going to its own functions. One warning per file.\n\n    {disable code generation}\n    FUNCTION BYTE_TO_REAL : REAL VAR_INPUT IN : BYTE; END_VAR RETURN; END_FUNCTION";
    W_STD_FB_REDECLARED = "W0210", "a standard function block is redeclared",
        "The project declares a FUNCTION_BLOCK with the name of a standard one (TON, CTU, R_TRIG, ...). Its declaration replaces the standard block for the whole project, as libraries such as Beremiz's `Standard_Function_Blocks` intend; plcc's own standard blocks keep using the standard ones. Check that the replacement does what the standard block does: Beremiz's timers, for instance, read the clock in C pragmas (W0010), which plcc skips, so their times never advance. Rename the block if it is not meant as a replacement.\n\n    FUNCTION_BLOCK TON   (* warning: replaces the standard TON *)\n    VAR_INPUT IN : BOOL; PT : TIME; END_VAR\n    VAR_OUTPUT Q : BOOL; ET : TIME; END_VAR\n    ...";
    W_WRITE_INPUT = "W0502", "assignment to an input of an instance",
        "A FUNCTION_BLOCK or PROGRAM assigns its own VAR_INPUT. It compiles, but the input belongs to the caller: the value it set is lost until its next call, which is usually a mistake. Copy the input into a VAR instead. (A FUNCTION's inputs are its own copies and may be assigned freely.)\n\n    FUNCTION_BLOCK F VAR_INPUT x : INT; END_VAR VAR y : INT; END_VAR\n    x := x + 1;   (* warning: write y := x + 1 *)";
}

/// The description of a code, if it is a front-end code.
pub fn lookup(code: &str) -> Option<&'static CodeInfo> {
    ALL.iter().find(|c| c.code.eq_ignore_ascii_case(code))
}
