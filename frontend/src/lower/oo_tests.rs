//! Object orientation lowered and run on the IR interpreter.

use crate::source::{SourceFile, SourceMap};
use crate::{compile, Lang, LowerOptions};
use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::Module;

fn build(src: &str, codesys: bool) -> Result<Module, Vec<String>> {
    let mut sources = SourceMap::new();
    let f = sources.add(SourceFile::new("t.st", src));
    let opts = LowerOptions {
        codesys,
        ..Default::default()
    };
    let c = compile(&mut sources, &[(f, Lang::St)], &opts);
    let errors: Vec<String> = c
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| format!("{}: {}", d.code, d.message))
        .collect();
    match c.module {
        Some(m) if errors.is_empty() => Ok(m),
        _ => Err(errors),
    }
}

/// Runs `scans` scans and reads the variables.
fn run(src: &str, scans: usize, vars: &[&str]) -> Vec<i64> {
    let m = build(src, false).unwrap_or_else(|e| panic!("{e:?}"));
    let mut i = Interp::new(&m).expect("interpreter");
    i.cold_start().expect("cold start");
    for _ in 0..scans {
        i.scan().expect("scan");
    }
    vars.iter()
        .map(|v| format!("main.{v}"))
        .map(|v| i.read(&v).unwrap_or_else(|e| panic!("{v}: {e:?}")).as_i64())
        .collect()
}

/// The codes of the errors of a program.
fn codes(src: &str) -> Vec<String> {
    match build(src, false) {
        Ok(_) => Vec::new(),
        Err(e) => e.into_iter().map(|s| s[..5].to_string()).collect(),
    }
}

const SHAPES: &str = "
INTERFACE I_Shape
  METHOD Area : INT END_METHOD
  PROPERTY Name : INT GET END_GET END_PROPERTY
END_INTERFACE
FUNCTION_BLOCK ABSTRACT Shape IMPLEMENTS I_Shape
  VAR_INPUT k : INT := 1; END_VAR
  METHOD ABSTRACT Area : INT END_METHOD
  METHOD Twice : INT Twice := 2 * Area(); END_METHOD
  PROPERTY Name : INT GET Name := 0; END_GET END_PROPERTY
END_FUNCTION_BLOCK
FUNCTION_BLOCK Square EXTENDS Shape
  VAR_INPUT side : INT; END_VAR
  METHOD Area : INT Area := side * side * k; END_METHOD
  PROPERTY Name : INT GET Name := 4; END_GET END_PROPERTY
END_FUNCTION_BLOCK
FUNCTION_BLOCK Rect EXTENDS Square
  VAR_INPUT other : INT; END_VAR
  VAR factor : INT := 1; END_VAR
  METHOD OVERRIDE Area : INT Area := side * other * factor; END_METHOD
  PROPERTY Scale : INT
    GET Scale := factor; END_GET
    SET factor := Scale; END_SET
  END_PROPERTY
END_FUNCTION_BLOCK
PROGRAM main
VAR
  s : Square := (side := 3); r : Rect := (side := 2, other := 5);
  shapes : ARRAY[1..3] OF I_Shape; none : I_Shape;
  total, twice, names, sc, isnull, fault_area : INT;
END_VAR
  shapes[1] := s; shapes[2] := r;
  r.Scale := r.Scale + 1;
  sc := r.Scale;
  total := shapes[1].Area() + shapes[2].Area();
  twice := r.Twice() + s.Twice();
  names := shapes[1].Name * 10 + shapes[2].Name;
  IF none = 0 AND shapes[3] = NULL THEN isnull := 1; END_IF;
END_PROGRAM";

#[test]
fn interfaces_abstract_methods_and_properties_bind_at_run_time() {
    let v = run(SHAPES, 1, &["total", "twice", "names", "sc", "isnull"]);
    // Scale 2 after one scan: Rect.Area = 2 * 5 * 2 = 20; Square 9.
    assert_eq!(v, [29, 58, 44, 2, 1]);
    let v = run(SHAPES, 2, &["total", "sc"]);
    assert_eq!(v, [9 + 30, 3]);
}

#[test]
fn class_ids_and_tables() {
    let m = build(SHAPES, false).expect("builds");
    // The class id leads every class's struct.
    for name in ["Shape", "Square", "Rect"] {
        let agg = m
            .aggs
            .iter()
            .find(|a| a.name() == name)
            .unwrap_or_else(|| panic!("{name}"));
        let plcc_ir::AggDef::Struct(s) = agg else {
            panic!("a struct")
        };
        assert_eq!(s.fields[0].name, "__class");
    }
    // Dispatch through function tables, one per dispatched member.
    let names: Vec<&str> = m.tables.iter().map(|t| t.name.as_str()).collect();
    assert!(names.contains(&"I_Shape.Area$dispatch"), "{names:?}");
    assert!(names.contains(&"Shape.Area$dispatch"), "{names:?}");
    // A method no class overrides is called directly.
    assert!(!names.iter().any(|n| n.contains("Twice")), "{names:?}");
}

#[test]
fn a_call_through_an_unset_interface_is_a_fault() {
    let src = "INTERFACE I METHOD m : INT END_METHOD END_INTERFACE
FUNCTION_BLOCK A IMPLEMENTS I METHOD m : INT m := 7; END_METHOD END_FUNCTION_BLOCK
PROGRAM main VAR a : A; i : I; x : INT := 5; END_VAR x := i.m(); END_PROGRAM";
    let m = build(src, false).expect("builds");
    let mut i = Interp::new(&m).expect("interpreter");
    i.cold_start().expect("cold start");
    i.scan().expect("scan");
    assert!(i.fault());
    assert_eq!(i.read("main.x").expect("x").as_i64(), 0);
}

#[test]
fn super_chains_and_inherited_bodies() {
    let src = "
FUNCTION_BLOCK A VAR_OUTPUT log : INT; END_VAR
  METHOD v : INT v := 1; END_METHOD
  log := log * 10 + 1;
END_FUNCTION_BLOCK
FUNCTION_BLOCK B EXTENDS A
  METHOD v : INT v := SUPER^.v() * 10 + 2; END_METHOD
  SUPER^(); log := log * 10 + 2;
END_FUNCTION_BLOCK
FUNCTION_BLOCK C EXTENDS B
  METHOD v : INT v := SUPER^.v() * 10 + 3; END_METHOD
END_FUNCTION_BLOCK
PROGRAM main VAR c : C; r : INT; END_VAR c(); r := c.v(); END_PROGRAM";
    assert_eq!(run(src, 1, &["c.log", "r"]), [12, 123]);
}

#[test]
fn diagnostics() {
    // Instantiating an abstract FB; a concrete FB missing an interface method.
    let src = "INTERFACE I METHOD m END_METHOD END_INTERFACE
FUNCTION_BLOCK ABSTRACT A END_FUNCTION_BLOCK
FUNCTION_BLOCK B IMPLEMENTS I END_FUNCTION_BLOCK
PROGRAM main VAR a : A; b : B; END_VAR END_PROGRAM";
    assert_eq!(codes(src), ["E0801", "E0801"]);
    // A PRIVATE property written from outside; a property without SET written.
    let src = "FUNCTION_BLOCK F VAR n : INT; END_VAR
PROPERTY PRIVATE P : INT GET P := n; END_GET SET n := P; END_SET END_PROPERTY
PROPERTY Q : INT GET Q := n; END_GET END_PROPERTY
END_FUNCTION_BLOCK
PROGRAM main VAR f : F; END_VAR f.P := 1; f.Q := 2; END_PROGRAM";
    assert_eq!(codes(src), ["E0803", "E0504"]);
    // SUPER^ without a base is not a name; METHODs of a PROGRAM need CODESYS.
    let src = "PROGRAM main METHOD m END_METHOD END_PROGRAM";
    assert_eq!(codes(src), ["E0800"]);
    assert!(build(src, true).is_ok());
}

#[test]
fn var_inst_struct_extends_and_program_methods() {
    let src = "
TYPE P : STRUCT x : INT := 1; END_STRUCT; Q EXTENDS P : STRUCT y : INT := 2; END_STRUCT; END_TYPE
FUNCTION_BLOCK F
  METHOD Count : INT
    VAR_INST n : INT := 10; END_VAR
    VAR t : INT; END_VAR
    n := n + 1; t := t + 1;
    Count := n * 10 + t;
  END_METHOD
END_FUNCTION_BLOCK
PROGRAM Stats VAR sum : INT; END_VAR
  METHOD Add VAR_INPUT v : INT; END_VAR sum := sum + v; END_METHOD
END_PROGRAM
PROGRAM main VAR f : F; c : INT; q : Q; s : INT; END_VAR
  c := f.Count();
  s := q.x + q.y;
  Stats.Add(s);
END_PROGRAM";
    let m = build(src, true).unwrap_or_else(|e| panic!("{e:?}"));
    let mut i = Interp::new(&m).expect("interpreter");
    i.cold_start().expect("cold start");
    i.scan().expect("scan");
    i.scan().expect("scan");
    let read = |p: &str| i.read(p).expect(p).as_i64();
    assert_eq!(read("main.c"), 121);
    assert_eq!(read("main.s"), 3);
    assert_eq!(read("Stats.sum"), 6);
    // VAR_INST outside a method is an error.
    let src = "FUNCTION_BLOCK F VAR_INST n : INT; END_VAR END_FUNCTION_BLOCK";
    assert_eq!(codes(src), ["E0800"]);
}
