//! `call_table`, calls bound at run time: the text form, the interpreter (entries of
//! every table, empty entries and indexes out of range raising the fault), and the
//! passes, which keep every entry reachable and memory clobbered across the call.

use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::text::{parse_module, print_module, PrintOptions};
use plcc_ir::verify::verify_module;
use plcc_ir::{ElemType, Module, PlcValue};

const TABLES: &str = include_str!("call_table/tables.ir");

fn module() -> Module {
    let m = parse_module(TABLES).unwrap();
    verify_module(&m).unwrap();
    m
}

#[test]
fn tables_print_and_parse_back() {
    let m = module();
    assert_eq!(m.tables.len(), 4);
    let text = print_module(&m, &PrintOptions::default());
    assert!(
        text.contains("table t0 \"I_Op.Apply\" (i32, i32) -> i32 = [@add, @sub, -, @mul]\n"),
        "{text}"
    );
    assert!(text.contains("table t3 \"I_Log.Note\" (ptr, i32) = [@note_add, @note_set, -]\n"));
    assert!(text.contains("    v6 = call_table t0, v2(v4, v5)\n"));
    assert!(text.contains("    call_table t3, v22(v20, v21)\n"));
    let again = parse_module(&text).unwrap();
    assert_eq!(again, m);
    assert_eq!(print_module(&again, &PrintOptions::default()), text);
}

#[test]
fn table_syntax_errors_point_at_the_mistake() {
    let bad = [
        ("table x0 \"T\" () = []\n", "expected a table such as `t0`"),
        (
            "table t0 \"T\" () = [@nope]\n",
            "unknown function `@nope`",
        ),
        (
            "table t0 \"T\" () = []\ntable t0 \"U\" () = []\n",
            "t0 is declared twice",
        ),
        (
            "func @f() function {\nblock0:\n    call_table t1, v0()\n    return\n}\n",
            "t1 is not declared",
        ),
        (
            "table t0 \"T\" () = []\nfunc @f() function {\nblock0:\n    v1 = iconst.i32 0\n    v2 = call_table t0, v1()\n    return\n}\n",
            "t0 returns no value",
        ),
        ("table t0 \"T\" () = [@f @g]\n", "expected `,` or `]`"),
    ];
    for (text, msg) in bad {
        let e = parse_module(text).unwrap_err();
        assert!(e.message.contains(msg), "{text}: {e}");
    }
    // An empty table and one of empty entries are fine.
    let m = parse_module("table t0 \"T\" (i8) -> i1 = []\ntable t7 \"U\" () = [-, -]\n").unwrap();
    assert_eq!(m.tables[1].entries, vec![None, None]);
    verify_module(&m).unwrap();
}

fn run(m: &Module) -> Vec<(i64, bool)> {
    let mut it = Interp::new(m).unwrap();
    assert_eq!(it.problems(), Vec::<String>::new());
    it.set_step_limit(Some(1_000_000));
    it.cold_start().unwrap();
    let mut seen = Vec::new();
    let mut scan = |it: &mut Interp, sel: i64, x: i64, y: f32| {
        it.write("main.sel", PlcValue::from_i64(ElemType::Int, sel))
            .unwrap();
        it.write("main.x", PlcValue::from_i64(ElemType::DInt, x))
            .unwrap();
        it.write("main.y", PlcValue::from_f32(y)).unwrap();
        it.clear_fault();
        it.scan().unwrap();
        let fault = it.fault();
        seen.push((it.read("main.looped").unwrap().as_i64(), fault));
        fault
    };
    let read = |it: &Interp, p: &str| it.read(p).unwrap();

    // sel = 1: every table has its entry: sub, circle, is_neg (index 0), note_set.
    assert!(!scan(&mut it, 1, 10, 2.0));
    assert_eq!(read(&it, "main.acc").as_i64(), 3);
    assert_eq!(read(&it, "main.area"), PlcValue::from_f32(13.0));
    assert_eq!(read(&it, "main.flags").as_i64(), 0);
    assert_eq!(read(&it, "main.total").as_i64(), 70);
    // The loop calls add, sub and mul: ((1 + 1) - 2) * 3.
    assert_eq!(read(&it, "main.looped").as_i64(), 0);

    // sel = 3: mul; t1 has no entry 3 (fault, 0.0); is_odd; t3 has no entry 3.
    assert!(scan(&mut it, 3, 5, 2.0));
    assert_eq!(read(&it, "main.acc").as_i64(), 35);
    assert_eq!(read(&it, "main.area"), PlcValue::from_f32(0.0));
    assert_eq!(read(&it, "main.flags").as_i64(), 1);
    assert_eq!(read(&it, "main.total").as_i64(), 70);
    assert_eq!(read(&it, "main.looped").as_i64(), -3);

    // sel = 0: add; square; t2's i64 index is -1, read unsigned: out of range;
    // note_add reads the total and writes it back.
    assert!(scan(&mut it, 0, -4, 1.5));
    assert_eq!(read(&it, "main.acc").as_i64(), 3);
    assert_eq!(read(&it, "main.area"), PlcValue::from_f32(2.25));
    assert_eq!(read(&it, "main.flags").as_i64(), 0);
    assert_eq!(read(&it, "main.total").as_i64(), 42);

    // sel = 2: t0's entry 2 is empty: the fault, and 0; is_zero(9).
    assert!(scan(&mut it, 2, 9, 1.0));
    assert_eq!(read(&it, "main.acc").as_i64(), 0);
    assert_eq!(read(&it, "main.flags").as_i64(), 0);
    assert_eq!(read(&it, "main.total").as_i64(), 42);

    // sel = -1: read unsigned, every index is out of range.
    assert!(scan(&mut it, -1, 9, 1.0));
    assert_eq!(read(&it, "main.acc").as_i64(), 0);
    assert_eq!(read(&it, "main.area"), PlcValue::from_f32(0.0));
    seen
}

#[test]
fn the_interpreter_calls_the_entry_or_raises_the_fault() {
    run(&module());
}

/// The optimiser inlines, forwards and removes around the calls, never through them:
/// the optimised module computes what the original does.
#[test]
fn the_passes_keep_the_entries_and_the_memory_they_write() {
    let m = module();
    let mut o = m.clone();
    plcc_ir::passes::optimize_program(&mut o);
    verify_module(&o).unwrap();
    // Every function an entry names is still there, even those only a table calls.
    for name in [
        "add", "sub", "mul", "square", "circle", "note_add", "note_set",
    ] {
        assert!(o.func_by_name(name).is_some(), "@{name} was removed");
    }
    assert_eq!(o.tables.len(), 4);
    assert_eq!(run(&o), run(&m));
}

/// The call graph counts every entry of a table as a callee.
#[test]
fn the_call_graph_sees_every_entry() {
    let m = module();
    let main = m.func_by_name("main").unwrap();
    let mut names: Vec<&str> = plcc_ir::analysis::callees(&m, main.index())
        .into_iter()
        .map(|f| m.funcs[f].name.as_str())
        .collect();
    names.sort_unstable();
    assert_eq!(
        names,
        [
            "add", "circle", "is_neg", "is_odd", "is_zero", "mul", "note_add", "note_set",
            "square", "sub"
        ]
    );
    assert_eq!(plcc_ir::analysis::call_depths(&m)[main.index()], 1);
}

/// From the roots, callers before callees, and only what the roots reach.
#[test]
fn callers_come_before_their_callees_from_the_roots() {
    let m = module();
    let main = m.func_by_name("main").unwrap();
    let order = plcc_ir::analysis::callers_first_from(&m, &[main]);
    assert_eq!(order[0], main);
    let at = |f: usize| order.iter().position(|g| g.index() == f);
    for (i, f) in order.iter().enumerate() {
        for c in plcc_ir::analysis::callees(&m, f.index()) {
            assert!(
                at(c).is_some_and(|p| p > i),
                "{} comes before its caller {}",
                m.funcs[c].name,
                m.funcs[f.index()].name
            );
        }
    }
    // Exactly the functions reachable from main.
    let mut reach = vec![main.index()];
    let mut k = 0;
    while k < reach.len() {
        for c in plcc_ir::analysis::callees(&m, reach[k]) {
            if !reach.contains(&c) {
                reach.push(c);
            }
        }
        k += 1;
    }
    let mut got: Vec<usize> = order.iter().map(|f| f.index()).collect();
    got.sort_unstable();
    reach.sort_unstable();
    assert_eq!(got, reach);
    assert!(
        reach.len() < m.funcs.len(),
        "the module has functions main does not reach"
    );
}
