//! The PLC-UD STL front end produces the same syntax tree as Structured Text, so a
//! program written in both languages must give the same optimised IR, byte for byte.
//! Each case below is one program in ST and in STL; both are built with the same file
//! name (the language is forced), so even the file table of the IR agrees.
//!
//! The last test builds a mixed project (an ST library called from an STL program, and
//! the other way round) and runs it on the IR interpreter.
//!
//! The STL examples themselves (`examples/stl/*.stl` with their scenarios) run on both
//! machines in `tests/e2e.rs`, which covers every example with an `.expect`.

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_frontend::Lang;
use plcc_ir::text::{print_module, PrintOptions};

/// The optimised IR of `text` read as `lang`.
fn optimised_ir(text: &str, lang: Lang) -> String {
    let opts = BuildOptions {
        lang: Some(lang),
        ..BuildOptions::default()
    };
    let build = build_sources(vec![("prog".to_string(), text.as_bytes().to_vec())], &opts)
        .unwrap_or_else(|e| panic!("{}", e.0));
    let Some(module) = build.module else {
        let errors: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
        panic!(
            "the {} program does not compile:\n{}\n{text}",
            lang.name(),
            errors.join("\n")
        );
    };
    print_module(&module, &PrintOptions::default())
}

#[track_caller]
fn same_ir(st: &str, stl: &str) {
    let a = optimised_ir(st, Lang::St);
    let b = optimised_ir(stl, Lang::Stl);
    assert!(a.contains("func"), "no function in the IR:\n{a}");
    assert_eq!(a, b, "the ST and STL versions differ");
}

#[test]
fn function_call() {
    same_ir(
        "
FUNCTION RD3 : INT
VAR_INPUT S1 : INT; S2 : INT; S3 : INT; END_VAR
    RD3 := S1 * S2 / S3;
END_FUNCTION

PROGRAM rule_of_three
VAR a : INT; b : INT := 30; c : INT := 100; d : INT := 40; END_VAR
    a := RD3(c, b, d);
    c := c + 10;
END_PROGRAM
",
        "
program rule_of_three;
FUNCTION RD3(S1 : INT; S2 : INT; S3 : INT); INT
BEGIN
  RD3 := S1 * S2 / S3;
END;
begin
  var a : INT; b : INT := 30; c : INT := 100; d : INT := 40; end_var;
  a := rd3(c, b, d);
  c := c + 10;
end.
",
    );
}

#[test]
fn statements() {
    same_ir(
        "
PROGRAM loops
VAR i : INT; s : INT; n : INT; d : INT; flag : BOOL; END_VAR
VAR CONSTANT top : INT := 10; END_VAR
    s := 0;
    FOR i := 1 TO top DO
        s := s + i;
    END_FOR;
    FOR i := 10 TO 1 BY -1 DO
        n := n + i;
        IF n > 20 THEN
            flag := TRUE;
        ELSIF n > 10 THEN
            d := d + 1;
        ELSE
            d := d - 1;
        END_IF;
    END_FOR;
    WHILE s > 0 DO
        s := s - 7;
    END_WHILE;
    REPEAT
        d := d + 3;
    UNTIL d >= 100
    END_REPEAT;
    IF flag THEN
        n := 0;
    END_IF;
END_PROGRAM
",
        "
program loops;
begin
  var i : INT; s : INT; n : INT; d : INT; flag : BOOL; end_var;
  constant top : INT := 10;
  s := 0;
  for i := 1 to top do
    s := s + i;
  for i := 10 downto 1 do
  begin
    n := n + i;
    if n > 20 then flag := true
    else if n > 10 then d := d + 1
    else d := d - 1;
  end
  while s > 0 do s := s - 7;
  repeat
    d := d + 3;
  until d >= 100;
  if flag then begin n := 0; end
end.
",
    );
}

#[test]
fn globals_procedures_and_standard_operations() {
    same_ir(
        "
VAR_GLOBAL total : INT; flags : USINT; END_VAR
VAR_GLOBAL CONSTANT LIMIT : INT := 10; END_VAR

FUNCTION add_rest
VAR_INPUT n : INT; END_VAR
VAR rest : INT; END_VAR
    rest := n MOD LIMIT;
    total := total + rest;
END_FUNCTION

FUNCTION scale : INT
VAR_INPUT x : INT; k : INT; END_VAR
    scale := x * k;
END_FUNCTION

PROGRAM g
VAR k : USINT := 16#1F; scans : INT; END_VAR
    scans := __STL_INC(scans);
    add_rest(scale(scans, 3));
    k := __STL_SWAP(k);
    flags := __STL_SET(flags, 3);
    flags := __STL_CLR(flags, 0);
    k := SHL(k, 1);
    scans := scans + __STL_DEC(LIMIT);
END_PROGRAM
",
        "
pragma gama cero
uses plcud;
program g;
var total : INT; flags : USINT; end_var;
constant LIMIT : INT := 10;
procedure add_rest(n : INT);
var rest : INT; end_var;
begin
  rest := n % LIMIT;
  total := total + rest;
end;
function scale(x : INT, k : INT) INT;
begin
  scale := x * k;
end;
begin
  var k : USINT := 16#1F; scans : INT; end_var;
  INC(scans);
  add_rest(scale(scans, 3));
  k := SWAP(k);
  SET(flags, 3);
  flags := CLR(flags, 0);
  k := SHL(k);
  scans := scans + DEC(LIMIT);
end.
",
    );
}

#[test]
fn conditions() {
    same_ir(
        "
PROGRAM cond
VAR p : INT; q : INT; a : BOOL; b : BOOL; c : BOOL; x : BOOL; y : BOOL; z : BOOL; m : INT; END_VAR
    x := NOT a AND b OR c XOR a;
    y := p > 1 AND q < 2 OR NOT (p = q);
    z := NOT (p + 1 <= q * 2) AND (a = b);
    m := p MOD q * 2 - -p;
    IF p <> q AND NOT c THEN
        m := m + 1;
    END_IF;
END_PROGRAM
",
        "
program cond;
begin
  var p : INT; q : INT; a : BOOL; b : BOOL; c : BOOL; x : BOOL; y : BOOL; z : BOOL; m : INT; end_var;
  x := not a and b or c xor a;
  y := p > 1 and q < 2 or not p = q;
  z := not p + 1 <= q * 2 and (a = b);
  m := p % q * 2 - -p;
  if p <> q and not c then
    m := m + 1;
end.
",
    );
}

#[test]
fn mixed_st_and_stl_project_runs() {
    let lib = "
FUNCTION twice : INT
VAR_INPUT x : INT; END_VAR
    twice := x * 2;
END_FUNCTION

PROGRAM st_side
VAR r : INT; END_VAR
    r := thrice(7);
END_PROGRAM
";
    let main = "
program stl_side;
function thrice(x : INT) INT;
begin
  thrice := x * 3;
end;
begin
  var a : INT; b : INT; end_var;
  a := twice(a + 1);
  b := thrice(a);
end.
";
    let build = build_sources(
        vec![
            ("lib.st".to_string(), lib.as_bytes().to_vec()),
            ("main.stl".to_string(), main.as_bytes().to_vec()),
        ],
        &BuildOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{}", e.0));
    let errors: Vec<String> = build.diagnostics.iter().map(|d| d.to_string()).collect();
    let module = build
        .module
        .unwrap_or_else(|| panic!("does not compile:\n{}", errors.join("\n")));
    let mut m = targets::machine("interp", &module).unwrap_or_else(|e| panic!("{e:?}"));
    m.cold_start().unwrap();
    // a: 0 -> 2 -> 6 -> 14; b = 3 * a; r = 21.
    for (a, b) in [(2, 6), (6, 18), (14, 42)] {
        m.scan().unwrap();
        assert_eq!(m.read("stl_side.a").unwrap().as_i64(), a);
        assert_eq!(m.read("stl_side.b").unwrap().as_i64(), b);
    }
    assert_eq!(m.read("st_side.r").unwrap().as_i64(), 21);
}
