//! The syntax tree shared by the textual front ends.
//!
//! Structured Text parses straight into it; IL and STL (and ladder, through IL) are
//! turned into it too, so that one semantic analysis and one lowering serve every
//! language. The tree is purely syntactic: names are unresolved, literals untyped.
//! Every node carries the span it came from so later stages can point at it.

use crate::intern::Symbol;
use plcc_ir::diag::{FileId, Span};

/// A name as written, interned case-insensitively (IEC names ignore case).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ident {
    /// The upper-cased, interned name; compare these, not source text.
    pub sym: Symbol,
    /// Where the name is written (the original spelling is the source text here).
    pub span: Span,
}

/// Everything parsed from one source file.
#[derive(Clone, Debug, Default)]
pub struct SourceUnit {
    /// The file the items came from.
    pub file: FileId,
    /// Top-level declarations in source order.
    pub items: Vec<Item>,
}

/// A top-level declaration.
#[derive(Clone, Debug)]
pub enum Item {
    /// PROGRAM, FUNCTION or FUNCTION_BLOCK.
    Pou(Pou),
    /// `TYPE ... END_TYPE` (one item per declared type).
    Type(TypeDecl),
    /// A `VAR_GLOBAL` block outside any configuration.
    Globals(VarBlock),
    /// `CONFIGURATION ... END_CONFIGURATION`.
    Configuration(Configuration),
    /// `ACTION name: ... END_ACTION` written outside its POU (CODESYS export style),
    /// or inside a FUNCTION_BLOCK/PROGRAM after its body.
    Action(Action),
    /// `INTERFACE name [EXTENDS a, b] ... END_INTERFACE`.
    Interface(Interface),
}

/// An access specifier of a METHOD, PROPERTY or FUNCTION_BLOCK.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum AccessSpec {
    /// `PUBLIC` (the default).
    Public,
    /// `PRIVATE`: only the declaring FUNCTION_BLOCK.
    Private,
    /// `PROTECTED`: the declaring FUNCTION_BLOCK and those derived from it.
    Protected,
    /// `INTERNAL`: the same namespace (one project here).
    Internal,
}

/// The modifiers written before a POU's or member's name.
#[derive(Clone, Debug, Default)]
pub struct Modifiers {
    /// `ABSTRACT`.
    pub abstract_: Option<Span>,
    /// `FINAL`.
    pub final_: Option<Span>,
    /// `OVERRIDE` (accepted, not required).
    pub override_: Option<Span>,
    /// `PUBLIC`, `PRIVATE`, `PROTECTED` or `INTERNAL`.
    pub access: Option<(AccessSpec, Span)>,
}

/// The object-oriented parts of a POU (IEC 61131-3 ed. 3, 6.6.5-6.6.8).
#[derive(Clone, Debug, Default)]
pub struct OoParts {
    /// Modifiers of the POU itself (`FUNCTION_BLOCK ABSTRACT fb`).
    pub modifiers: Modifiers,
    /// `IMPLEMENTS i1, i2`.
    pub implements: Vec<Ident>,
    /// `METHOD ... END_METHOD`, in order.
    pub methods: Vec<Method>,
    /// `PROPERTY ... END_PROPERTY`, in order.
    pub properties: Vec<Property>,
    /// Access specifiers of VAR blocks (`VAR PROTECTED`): block index, specifier.
    pub var_access: Vec<(u32, AccessSpec, Span)>,
    /// `CLASS name ... END_CLASS` (IEC 61131-3 ed. 3, 6.6.5), held as a
    /// FUNCTION_BLOCK: the span of its `CLASS` keyword. A class has no body and no
    /// inputs, outputs or in-outs, and its instances are not called (only their
    /// METHODs).
    pub class: Option<Span>,
}

/// `METHOD [modifiers] name [: type] ... END_METHOD`: its variables, result and body
/// are held as a FUNCTION's (`pou.kind` is `Function`, `pou.name` the method's name).
#[derive(Clone, Debug)]
pub struct Method {
    /// Its modifiers.
    pub modifiers: Modifiers,
    /// Name, result type, variables and body.
    pub pou: Pou,
}

/// `PROPERTY [modifiers] name : type GET ... END_GET SET ... END_SET END_PROPERTY`.
#[derive(Clone, Debug)]
pub struct Property {
    /// Its modifiers.
    pub modifiers: Modifiers,
    /// Its name.
    pub name: Ident,
    /// Its type.
    pub ty: TypeSpec,
    /// The getter: a FUNCTION whose result is the property's value (its name is the
    /// property's).
    pub get: Option<Pou>,
    /// The setter: a FUNCTION body where the property's name is the value written.
    pub set: Option<Pou>,
    /// The whole declaration.
    pub span: Span,
}

/// `INTERFACE name [EXTENDS a, b] METHOD ... PROPERTY ... END_INTERFACE`.
#[derive(Clone, Debug)]
pub struct Interface {
    /// Its name.
    pub name: Ident,
    /// The interfaces it extends.
    pub extends: Vec<Ident>,
    /// Its methods (prototypes: no body).
    pub methods: Vec<Method>,
    /// Its properties (prototypes).
    pub properties: Vec<Property>,
    /// The whole declaration.
    pub span: Span,
}

/// The kind of a program organisation unit.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum PouKind {
    /// `PROGRAM`: one instance per task binding, state kept between scans.
    Program,
    /// `FUNCTION`: no state; locals start from their initial values at every call.
    Function,
    /// `FUNCTION_BLOCK`: instances keep their state between calls.
    FunctionBlock,
}

/// A PROGRAM, FUNCTION or FUNCTION_BLOCK.
#[derive(Clone, Debug)]
pub struct Pou {
    /// Which of the three it is.
    pub kind: PouKind,
    /// Its name.
    pub name: Ident,
    /// A FUNCTION's result type (`FUNCTION f : INT`); `None` for the others and for a
    /// FUNCTION declared without one.
    pub return_type: Option<TypeSpec>,
    /// `EXTENDS base` of a FUNCTION_BLOCK (an object-oriented extension).
    pub extends: Option<Ident>,
    /// Declaration blocks in source order.
    pub var_blocks: Vec<VarBlock>,
    /// The body.
    pub body: Body,
    /// ACTIONs declared inside the POU.
    pub actions: Vec<Action>,
    /// Members kept only so that analysis can report them as not supported (span of
    /// each member header).
    pub unsupported_members: Vec<Span>,
    /// The object-oriented parts: modifiers, IMPLEMENTS, METHODs, PROPERTYs.
    pub oo: Box<OoParts>,
    /// A sequential function chart written as the body (IEC 61131-3, 6.7.2: steps
    /// and transitions instead of statements; the chart's ACTIONs are in
    /// `actions`). The front end turns it into statements before lowering
    /// ([`crate::sfc`]).
    pub sfc: Option<Sfc>,
    /// From the POU keyword to the end of its END_ keyword.
    pub span: Span,
}

/// A textual sequential function chart: its steps and transitions in text order.
#[derive(Clone, Debug, Default)]
pub struct Sfc {
    /// `INITIAL_STEP` and `STEP` in order.
    pub steps: Vec<SfcStep>,
    /// `TRANSITION` in order.
    pub transitions: Vec<SfcTransition>,
    /// From the first element to the end of the last.
    pub span: Span,
}

/// `STEP name: assoc; … END_STEP` (or `INITIAL_STEP`).
#[derive(Clone, Debug)]
pub struct SfcStep {
    /// The step's name (its flags are `name.X` and `name.T`).
    pub name: Ident,
    /// `INITIAL_STEP`.
    pub initial: bool,
    /// Its action associations in order.
    pub assocs: Vec<SfcAssoc>,
    /// The whole step.
    pub span: Span,
}

/// `action(qualifier, duration, indicator);` in a step.
#[derive(Clone, Debug)]
pub struct SfcAssoc {
    /// The ACTION, or a BOOL variable used as an action.
    pub action: Ident,
    /// For `inst.A(ACTIVE);` (a CODESYS step action running an action of an FB
    /// instance): the whole dotted name; `action` is its first part.
    pub qualified: Option<Span>,
    /// N, R, S, L, D, P, P0, P1, SD, DS, SL; `None` when left out (`A();`).
    pub qualifier: Option<Ident>,
    /// The duration of a timed qualifier: a TIME expression (its span, to copy).
    pub duration: Option<Span>,
    /// Indicator variables (kept, not used: IEC gives them no effect on the chart).
    pub indicators: Vec<Ident>,
    /// The whole association.
    pub span: Span,
}

/// `TRANSITION [name] [(PRIORITY := p)] FROM … TO … := cond; END_TRANSITION`.
#[derive(Clone, Debug)]
pub struct SfcTransition {
    /// Its name, if it has one.
    pub name: Option<Ident>,
    /// `PRIORITY := p` and where it is written.
    pub priority: Option<(u32, Span)>,
    /// The steps before it.
    pub from: Vec<Ident>,
    /// The steps after it.
    pub to: Vec<Ident>,
    /// The condition: a BOOL expression (its span, to copy); `None` if missing.
    pub condition: Option<Span>,
    /// The condition is an IL list (`TRANSITION FROM a TO b : LD x END_TRANSITION`)
    /// whose result is the condition, not an expression.
    pub il: bool,
    /// The keyword `TRANSITION` and the name, for messages.
    pub head: Span,
    /// The whole transition.
    pub span: Span,
}

/// The statements of a POU or action.
#[derive(Clone, Debug, Default)]
pub struct Body {
    /// Statements in order.
    pub stmts: Vec<Stmt>,
    /// The span of the whole body (empty at the end of the declarations if no code).
    pub span: Span,
}

/// `ACTION name: body END_ACTION`.
#[derive(Clone, Debug)]
pub struct Action {
    /// For an action declared outside its POU, the POU it belongs to (`ACTION P.A:` or
    /// the CODESYS export form); `None` inside a POU.
    pub pou: Option<Ident>,
    /// The action's name.
    pub name: Ident,
    /// Its body (empty when it is a chart).
    pub body: Body,
    /// The chart, when the action is written in SFC; `crate::sfc` writes it as ST
    /// into `body`.
    pub sfc: Option<Sfc>,
    /// Whole declaration.
    pub span: Span,
}

/// The section keyword of a declaration block.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum VarKind {
    /// `VAR`
    Var,
    /// `VAR_INPUT`
    Input,
    /// `VAR_OUTPUT`
    Output,
    /// `VAR_IN_OUT`
    InOut,
    /// `VAR_TEMP`
    Temp,
    /// `VAR_GLOBAL`
    Global,
    /// `VAR_EXTERNAL`
    External,
    /// `VAR_ACCESS`
    Access,
    /// `VAR_CONFIG`
    Config,
    /// `VAR_STAT` (CODESYS)
    Stat,
    /// `VAR_INST` (CODESYS): variables of a METHOD kept in its instance from one
    /// call to the next.
    Inst,
}

impl VarKind {
    /// The keyword that opens the block (`VAR_INPUT`).
    pub fn keyword(self) -> &'static str {
        match self {
            VarKind::Var => "VAR",
            VarKind::Input => "VAR_INPUT",
            VarKind::Output => "VAR_OUTPUT",
            VarKind::InOut => "VAR_IN_OUT",
            VarKind::Temp => "VAR_TEMP",
            VarKind::Global => "VAR_GLOBAL",
            VarKind::External => "VAR_EXTERNAL",
            VarKind::Access => "VAR_ACCESS",
            VarKind::Config => "VAR_CONFIG",
            VarKind::Stat => "VAR_STAT",
            VarKind::Inst => "VAR_INST",
        }
    }
}

/// `VAR ... END_VAR` and its kin.
#[derive(Clone, Debug)]
pub struct VarBlock {
    /// The section keyword.
    pub kind: VarKind,
    /// `CONSTANT` qualifier.
    pub constant: bool,
    /// `RETAIN` (or `PERSISTENT`) qualifier.
    pub retain: bool,
    /// The name of a global variable list (CODESYS's GVLs: `VAR_GLOBAL GVL`), by which
    /// its variables may be qualified (`GVL.x`).
    pub list: Option<Ident>,
    /// The declarations.
    pub decls: Vec<VarDecl>,
    /// From the section keyword to END_VAR.
    pub span: Span,
}

/// `a, b AT %IX0.0 : INT := 5;`
#[derive(Clone, Debug)]
pub struct VarDecl {
    /// The declared names (several share one type).
    pub names: Vec<Ident>,
    /// `AT %...` location, as written (`%IX0.0`, `%QW1`, `%I*`).
    pub location: Option<(Box<str>, Span)>,
    /// The declared type.
    pub ty: TypeSpec,
    /// The initial value, if any.
    pub init: Option<Init>,
    /// `R_EDGE` (TRUE) or `F_EDGE` (FALSE) after the type of a BOOL input, with its
    /// span (`crate::edges` gives it its meaning).
    pub edge: Option<(bool, Span)>,
    /// The whole declaration.
    pub span: Span,
}

/// A type as written in a declaration.
#[derive(Clone, Debug)]
pub enum TypeSpec {
    /// An elementary, derived or FB type by name: `INT`, `TON`, `MyStruct`.
    Named(Ident),
    /// `STRING`, `STRING[20]`, `STRING(20)`, `WSTRING[..]`.
    String {
        /// WSTRING
        wide: bool,
        /// Declared maximum length, if given.
        len: Option<Box<Expr>>,
        /// Whole spec.
        span: Span,
    },
    /// `ARRAY[lo..hi, lo..hi] OF elem`; `ARRAY[*]` (variable length) has `None` bounds.
    Array {
        /// One `(lo, hi)` pair per dimension; `None` for `*`.
        dims: Vec<Option<(Expr, Expr)>>,
        /// The element type.
        elem: Box<TypeSpec>,
        /// Whole spec.
        span: Span,
    },
    /// `INT(0..100)`: a subrange of an integer type.
    Subrange {
        /// The base type.
        base: Ident,
        /// Lower bound.
        lo: Box<Expr>,
        /// Upper bound.
        hi: Box<Expr>,
        /// Whole spec.
        span: Span,
    },
    /// `(red, green := 5, blue)` with an optional base type after it: `(a, b) INT`.
    Enum {
        /// Values with optional explicit numbers.
        values: Vec<(Ident, Option<Expr>)>,
        /// `(…) INT`: the typed enumeration's base type.
        base: Option<Ident>,
        /// Whole spec.
        span: Span,
    },
    /// `STRUCT ... END_STRUCT` (only in TYPE declarations).
    Struct {
        /// The fields, declared like variables.
        fields: Vec<VarDecl>,
        /// Whole spec.
        span: Span,
    },
    /// `REF_TO t`.
    Ref {
        /// The referenced type.
        target: Box<TypeSpec>,
        /// Whole spec.
        span: Span,
    },
    /// `REFERENCE TO t` (CODESYS): a reference used as the variable it points to.
    Reference {
        /// The referenced type.
        target: Box<TypeSpec>,
        /// Whole spec.
        span: Span,
    },
    /// `POINTER TO t` (CODESYS).
    Pointer {
        /// The pointed-to type.
        target: Box<TypeSpec>,
        /// Whole spec.
        span: Span,
    },
}

impl TypeSpec {
    /// The source range of the type as written.
    pub fn span(&self) -> Span {
        match self {
            TypeSpec::Named(id) => id.span,
            TypeSpec::String { span, .. }
            | TypeSpec::Array { span, .. }
            | TypeSpec::Subrange { span, .. }
            | TypeSpec::Enum { span, .. }
            | TypeSpec::Struct { span, .. }
            | TypeSpec::Ref { span, .. }
            | TypeSpec::Reference { span, .. }
            | TypeSpec::Pointer { span, .. } => *span,
        }
    }
}

/// An initial value in a declaration.
#[derive(Clone, Debug)]
pub enum Init {
    /// `:= expr`
    Expr(Expr),
    /// `:= [1, 2, 3(0)]` (also written without brackets in some dialects).
    Array {
        /// The elements; each may repeat.
        elems: Vec<ArrayInitElem>,
        /// Whole initialiser.
        span: Span,
    },
    /// `:= (a := 1, b := (c := 2))` for structs and FB instances.
    Struct {
        /// Field initialisers.
        fields: Vec<(Ident, Init)>,
        /// Whole initialiser.
        span: Span,
    },
}

impl Init {
    /// The source range of the initialiser.
    pub fn span(&self) -> Span {
        match self {
            Init::Expr(e) => e.span,
            Init::Array { span, .. } | Init::Struct { span, .. } => *span,
        }
    }
}

/// One element of an array initialiser: `v`, `n(v)` or `n()`.
#[derive(Clone, Debug)]
pub struct ArrayInitElem {
    /// The repetition count `n` of `n(v)`.
    pub repeat: Option<Expr>,
    /// The value; `None` for `n()` (n default values).
    pub value: Option<Init>,
    /// Whole element.
    pub span: Span,
}

/// `TYPE name : spec := init; END_TYPE` (one per declared name).
#[derive(Clone, Debug)]
pub struct TypeDecl {
    /// The new type's name.
    pub name: Ident,
    /// `EXTENDS base` of a STRUCT (CODESYS): the base's fields come first.
    pub extends: Option<Ident>,
    /// Its definition.
    pub spec: TypeSpec,
    /// Default initial value of the type.
    pub init: Option<Init>,
    /// The declaration.
    pub span: Span,
}

/// `CONFIGURATION name ... END_CONFIGURATION`.
#[derive(Clone, Debug)]
pub struct Configuration {
    /// The configuration's name.
    pub name: Ident,
    /// Its `VAR_GLOBAL` blocks (and `VAR_ACCESS`/`VAR_CONFIG`).
    pub var_blocks: Vec<VarBlock>,
    /// Its resources. Tasks and programs declared directly in the configuration (a
    /// common shortcut) are put in one resource named after the configuration.
    pub resources: Vec<Resource>,
    /// Whole declaration.
    pub span: Span,
}

/// `RESOURCE name ON cpu ... END_RESOURCE`.
#[derive(Clone, Debug)]
pub struct Resource {
    /// The resource's name.
    pub name: Ident,
    /// The `ON` processor type, if given.
    pub on: Option<Ident>,
    /// Its `VAR_GLOBAL` blocks.
    pub var_blocks: Vec<VarBlock>,
    /// `TASK name(INTERVAL := T#10ms, PRIORITY := 1);`
    pub tasks: Vec<TaskDecl>,
    /// `PROGRAM inst WITH task : Type (args);`
    pub programs: Vec<ProgramConfig>,
    /// Whole declaration.
    pub span: Span,
}

/// `TASK name(INTERVAL := ..., PRIORITY := ..., SINGLE := ...);`
#[derive(Clone, Debug)]
pub struct TaskDecl {
    /// The task's name.
    pub name: Ident,
    /// Its properties as written.
    pub props: Vec<(Ident, Expr)>,
    /// Whole declaration.
    pub span: Span,
}

/// `PROGRAM inst WITH task : Type (args);`
#[derive(Clone, Debug)]
pub struct ProgramConfig {
    /// The instance name.
    pub name: Ident,
    /// The task it runs in.
    pub task: Option<Ident>,
    /// The PROGRAM type.
    pub pou: Ident,
    /// Connections of its inputs and outputs.
    pub args: Vec<Arg>,
    /// Whole declaration.
    pub span: Span,
}

/// A statement and its span.
#[derive(Clone, Debug)]
pub struct Stmt {
    /// What it does.
    pub kind: StmtKind,
    /// The statement without its terminating `;`.
    pub span: Span,
}

/// The statements of ST (IL and STL are expressed with these too).
#[derive(Clone, Debug)]
pub enum StmtKind {
    /// `target := value`
    Assign {
        /// The assigned variable (a name, member, index or dereference).
        target: Expr,
        /// The value.
        value: Expr,
    },
    /// `target REF= value` (a reference assignment).
    RefAssign {
        /// The reference variable.
        target: Expr,
        /// The referenced variable.
        value: Expr,
    },
    /// A call used as a statement: an FB instance `t(IN := x)`, a function `f(1)`, an
    /// action.
    Call(Expr),
    /// `IF c THEN ... ELSIF c THEN ... ELSE ... END_IF`
    If {
        /// `(condition, statements)` for IF and every ELSIF, in order.
        branches: Vec<(Expr, Vec<Stmt>)>,
        /// The ELSE part.
        else_body: Option<Vec<Stmt>>,
    },
    /// `CASE sel OF labels: ... ELSE ... END_CASE`
    Case {
        /// The selector.
        selector: Expr,
        /// The arms in order.
        arms: Vec<CaseArm>,
        /// The ELSE part.
        else_body: Option<Vec<Stmt>>,
    },
    /// `FOR v := from TO to BY by DO ... END_FOR`
    For {
        /// The control variable.
        var: Ident,
        /// Start value (boxed, as are the end and the step, to keep [`Stmt`] small).
        from: Box<Expr>,
        /// End value (inclusive).
        to: Box<Expr>,
        /// Step (1 if absent).
        by: Option<Box<Expr>>,
        /// The loop body.
        body: Vec<Stmt>,
    },
    /// `WHILE c DO ... END_WHILE`
    While {
        /// The condition tested before each iteration.
        cond: Expr,
        /// The loop body.
        body: Vec<Stmt>,
    },
    /// `REPEAT ... UNTIL c END_REPEAT`
    Repeat {
        /// The loop body.
        body: Vec<Stmt>,
        /// The condition tested after each iteration.
        until: Expr,
    },
    /// `EXIT`
    Exit,
    /// `CONTINUE`
    Continue,
    /// `RETURN`
    Return,
    /// A lone `;`.
    Empty,
    /// A pragma holding C code where a statement stands: the C text matiec would copy
    /// (its braces dropped). The `c` target copies it into its output there; other
    /// targets skip it with warning W0010.
    InlineC(Box<str>),
    /// A jump target (from IL or ladder): `label:`.
    Label(Ident),
    /// An unconditional jump to a label in the same body (from IL or ladder).
    Goto(Ident),
    /// A compiler temporary (from IL's current result): declares `name` with the
    /// type of `value`, assigns it, and makes it readable by name for the rest of the
    /// body. Front ends choose names no user can write (`__cr1`: IEC identifiers
    /// cannot contain two underscores in a row).
    Let {
        /// The temporary's name.
        name: Ident,
        /// Its value.
        value: Expr,
    },
}

/// One arm of a CASE statement.
#[derive(Clone, Debug)]
pub struct CaseArm {
    /// The labels before the `:`.
    pub labels: Vec<CaseLabel>,
    /// The statements of the arm.
    pub body: Vec<Stmt>,
    /// From the first label to the `:`.
    pub span: Span,
}

/// A CASE label: a value or an inclusive range.
#[derive(Clone, Debug)]
pub enum CaseLabel {
    /// `5`, `RED`, `-3`
    Value(Expr),
    /// `1..10`
    Range(Expr, Expr),
}

/// An expression and its span.
#[derive(Clone, Debug)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is written.
    pub span: Span,
}

impl Expr {
    /// The value of a literal written here (not in parentheses), if it is one.
    pub fn literal_kind(&self) -> Option<&LiteralKind> {
        match &self.kind {
            ExprKind::Literal(l) => Some(&l.kind),
            _ => None,
        }
    }
}

/// Expression forms.
#[derive(Clone, Debug)]
pub enum ExprKind {
    /// A literal constant.
    Literal(Box<Literal>),
    /// A plain name: variable, constant, enumeration value, POU.
    Name(Ident),
    /// `base.member`: struct field, FB input/output, qualified enum value.
    Member(Box<Expr>, Ident),
    /// `base.3` or `base.%X3`: one bit of a bit string or integer.
    Bit(Box<Expr>, Box<Expr>),
    /// `base.%B1`, `%W0`, `%D0`: partial access of a larger word (size in bits, index).
    Partial(Box<Expr>, u8, u32),
    /// `base[i, j]`
    Index(Box<Expr>, Box<[Expr]>),
    /// `base^`
    Deref(Box<Expr>),
    /// `Color#Red` (an enumeration value qualified by its type).
    EnumValue {
        /// The enumeration type (boxed: this rare node would make every `Expr`
        /// 8 bytes larger).
        ty: Box<Ident>,
        /// The value.
        value: Ident,
    },
    /// `%IX0.0` used directly in an expression.
    DirectAddress(Box<str>),
    /// A prefix operator.
    Unary(UnaryOp, Box<Expr>),
    /// An infix operator.
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
    /// `callee(args)`: function, FB instance, action or method call.
    Call {
        /// What is called: a `Name` or a `Member`.
        callee: Box<Expr>,
        /// The arguments in order.
        args: Box<[Arg]>,
    },
    /// `(e)`, kept so that diagnostics and printers can see the parentheses.
    Paren(Box<Expr>),
    /// A value as an IL instruction uses it, so that diagnostics name the
    /// instruction, at this node's span: the condition `JMPC`, `CALCN`, `RETC`, `S`
    /// or `R` tests (it must be BOOL), or the call `CAL` makes (of a function block
    /// instance, not a FUNCTION). Anywhere else it reads as `value`.
    UsedBy {
        /// The instruction as messages name it (`JMPC`).
        instr: Box<str>,
        /// The value it uses.
        value: Box<Expr>,
    },
}

/// Prefix operators.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `-x`
    Neg,
    /// `+x`
    Plus,
    /// `NOT x`
    Not,
}

/// Infix operators (precedence is the parser's business).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `OR`
    Or,
    /// `OR_ELSE` (short-circuit)
    OrElse,
    /// `XOR`
    Xor,
    /// `AND` or `&`
    And,
    /// `AND_THEN` (short-circuit)
    AndThen,
    /// `=`
    Eq,
    /// `<>`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `MOD`
    Mod,
    /// `**`
    Pow,
}

impl BinaryOp {
    /// How tightly the operator binds in ST, loosest first: OR and OR_ELSE 1, XOR 2,
    /// AND and AND_THEN 3, `=` `<>` 4, `<` `<=` `>` `>=` 5, `+` `-` 6, `*` `/` MOD 7,
    /// `**` 8. Every one is left-associative. The parser reads and the printer
    /// parenthesises by this table.
    pub fn binding(self) -> u8 {
        use BinaryOp::*;
        match self {
            Or | OrElse => 1,
            Xor => 2,
            And | AndThen => 3,
            Eq | Ne => 4,
            Lt | Le | Gt | Ge => 5,
            Add | Sub => 6,
            Mul | Div | Mod => 7,
            Pow => 8,
        }
    }

    /// The operator as written in ST.
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Or => "OR",
            BinaryOp::OrElse => "OR_ELSE",
            BinaryOp::Xor => "XOR",
            BinaryOp::And => "AND",
            BinaryOp::AndThen => "AND_THEN",
            BinaryOp::Eq => "=",
            BinaryOp::Ne => "<>",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Mod => "MOD",
            BinaryOp::Pow => "**",
        }
    }
}

/// One argument of a call.
#[derive(Clone, Debug)]
pub struct Arg {
    /// Positional, `name := value` or `name => target`.
    pub kind: ArgKind,
    /// Whole argument.
    pub span: Span,
}

/// The three forms of argument.
#[derive(Clone, Debug)]
pub enum ArgKind {
    /// `value`
    Positional(Expr),
    /// `name := value` (an input or in-out).
    Input {
        /// The parameter.
        name: Ident,
        /// The value (or the variable, for an in-out).
        value: Expr,
    },
    /// `name => target` or `NOT name => target` (an output).
    Output {
        /// The output parameter.
        name: Ident,
        /// `NOT name => x` stores the negated output.
        negated: bool,
        /// Where the output goes (empty `name =>` has `None`).
        target: Option<Expr>,
    },
}

/// A literal constant as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Literal {
    /// The value.
    pub kind: LiteralKind,
    /// `INT#`, `REAL#`, `DINT#16#…`: the elementary type prefix, if any.
    pub type_prefix: Option<Ident>,
}

/// Literal values.
#[derive(Clone, Debug, PartialEq)]
pub enum LiteralKind {
    /// An integer, decimal or based (`16#FF`); `INT#-5` gives a negative value.
    Int(i128),
    /// A real literal; the text (underscores removed) is kept so that REAL literals
    /// are rounded once, straight to binary32.
    Real(Box<str>),
    /// `TRUE` / `FALSE` (also `BOOL#1`).
    Bool(bool),
    /// `T#…`/`TIME#…` (`long: false`) and `LT#…`/`LTIME#…` (`long: true`), in ns.
    Duration {
        /// Nanoseconds (negative durations allowed).
        ns: i128,
        /// LTIME rather than TIME.
        long: bool,
    },
    /// `D#2024-01-31` / `LDATE#…`: days since 1970-01-01.
    Date {
        /// Days since the epoch.
        days: i64,
        /// LDATE rather than DATE.
        long: bool,
    },
    /// `TOD#12:30:15.5` / `LTOD#…`: nanoseconds since midnight.
    TimeOfDay {
        /// Nanoseconds since midnight.
        ns: i64,
        /// LTOD rather than TOD.
        long: bool,
    },
    /// `DT#2024-01-31-12:30:15` / `LDT#…`: nanoseconds since the epoch.
    DateTime {
        /// Nanoseconds since 1970-01-01T00:00:00.
        ns: i128,
        /// LDT rather than DT.
        long: bool,
    },
    /// `'text'` (bytes, `$` escapes resolved) or `"text"` (UTF-16 code units).
    String {
        /// WSTRING (double quotes).
        wide: bool,
        /// The characters: bytes for STRING, UTF-16 units for WSTRING.
        units: Vec<u16>,
    },
}

/// The sizes of the nodes a body is made of: a file of 250k lines holds millions of
/// them, and the syntax trees live until the IR is made (BENCHMARKS.md, memory).
#[cfg(all(test, target_pointer_width = "64"))]
#[test]
fn node_sizes() {
    let sizes = [
        ("Expr", std::mem::size_of::<Expr>()),
        ("Stmt", std::mem::size_of::<Stmt>()),
        ("Arg", std::mem::size_of::<Arg>()),
    ];
    eprintln!("{sizes:?}");
    assert_eq!(sizes, [("Expr", 48), ("Stmt", 120), ("Arg", 88)]);
}
