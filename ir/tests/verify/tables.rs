//! Function tables and `call_table`: entries of the table's signature, an existing
//! table, an integer index, arguments of the table's types, the table's result, and
//! no recursion through a table.

use super::*;

/// A table of the callee's signature, `(i32, f64) -> i16`, with `entries`.
fn table(entries: Vec<Option<FuncId>>) -> Table {
    Table {
        name: "I.M".into(),
        params: vec![Type::I32, Type::F64],
        result: Some(Type::I16),
        entries,
    }
}

/// Checks `@f(i32, i64, f32, f64, ptr, i1) -> i32` with a table `t0` of `entries`.
fn check_with_table(
    entries: Vec<Option<FuncId>>,
    body: impl FnOnce(&mut FuncBuilder, &[Value]),
) -> Vec<VerifyError> {
    let mut m = base();
    m.add_table(table(entries));
    let mut f = Function::new(
        "f",
        FuncKind::Function,
        vec![
            Type::I32,
            Type::I64,
            Type::F32,
            Type::F64,
            Type::Ptr,
            Type::I1,
        ],
        Some(Type::I32),
    );
    {
        let mut b = FuncBuilder::new(&mut f);
        let p = b.params();
        body(&mut b, &p);
    }
    m.add_func(f);
    verify_module(&m).err().unwrap_or_default()
}

fn ret0(b: &mut FuncBuilder) {
    let z = b.iconst(Type::I32, 0);
    b.ret(Some(z));
}

#[test]
fn a_call_through_a_table_verifies() {
    let errs = check_with_table(vec![Some(CALLEE), None, Some(CALLEE)], |b, p| {
        // Every integer width may index.
        for idx in [p[0], p[1]] {
            b.call_table(TableId(0), Some(Type::I16), idx, vec![p[0], p[3]]);
        }
        let i8v = b.iconst(Type::I8, 2);
        b.call_table(TableId(0), Some(Type::I16), i8v, vec![p[0], p[3]]);
        ret0(b);
    });
    expect_ok(&errs);
}

#[test]
fn entries_have_the_tables_signature() {
    let mut m = base();
    let mut g = Function::new("g", FuncKind::Function, vec![Type::I32], Some(Type::I16));
    {
        let mut b = FuncBuilder::new(&mut g);
        let x = b.iconst(Type::I16, 0);
        b.ret(Some(x));
    }
    let g = m.add_func(g);
    m.add_table(table(vec![Some(CALLEE), Some(g)]));
    expect_only(
        &verify_module(&m).unwrap_err(),
        "table t0 \"I.M\" is (i32, f64) -> i16, but its entry 1 @g is (i32) -> i16",
    );
    let mut m = base();
    m.add_table(table(vec![None, Some(FuncId(9))]));
    expect_only(
        &verify_module(&m).unwrap_err(),
        "table t0 \"I.M\": entry 1, func9, does not exist",
    );
}

#[test]
fn the_table_exists() {
    let errs = check_with_table(vec![], |b, p| {
        b.call_table(TableId(3), Some(Type::I16), p[0], vec![p[0], p[3]]);
        ret0(b);
    });
    expect_only(&errs, "t3 does not exist");
}

#[test]
fn the_index_is_an_integer() {
    for (k, ty) in [(2, "f32"), (4, "ptr"), (5, "i1")] {
        let errs = check_with_table(vec![Some(CALLEE)], |b, p| {
            b.call_table(TableId(0), Some(Type::I16), p[k], vec![p[0], p[3]]);
            ret0(b);
        });
        expect_only(
            &errs,
            &format!("the index v{k} is {ty}, expected an integer (i8..i64)"),
        );
    }
}

#[test]
fn the_arguments_are_the_tables() {
    let errs = check_with_table(vec![Some(CALLEE)], |b, p| {
        b.call_table(TableId(0), Some(Type::I16), p[0], vec![p[0]]);
        ret0(b);
    });
    expect_only(&errs, "t0 takes 2 arguments, found 1");
    let errs = check_with_table(vec![Some(CALLEE)], |b, p| {
        b.call_table(TableId(0), Some(Type::I16), p[0], vec![p[0], p[2]]);
        ret0(b);
    });
    expect_only(&errs, "argument 1 of t0 is f32, expected f64");
}

#[test]
fn the_result_is_the_tables() {
    let errs = check_with_table(vec![Some(CALLEE)], |b, p| {
        b.call_table(TableId(0), Some(Type::I32), p[0], vec![p[0], p[3]]);
        ret0(b);
    });
    expect_only(&errs, "the result v6 is i32, but the instruction gives i16");
    let errs = check_with_table(vec![Some(CALLEE)], |b, p| {
        b.call_table(TableId(0), None, p[0], vec![p[0], p[3]]);
        ret0(b);
    });
    expect_only(&errs, "the result is missing (the instruction gives i16)");
}

/// `@a` calls through a table whose entry `@b` calls `@a`: recursion, although no
/// direct call closes the cycle.
#[test]
fn recursion_through_a_table() {
    let mut m = base();
    m.add_table(Table {
        name: "I.Step".into(),
        params: vec![],
        result: None,
        entries: vec![None, Some(FuncId(2))],
    });
    let mut a = Function::new("a", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut a);
        let i = b.iconst(Type::I32, 1);
        b.call_table(TableId(0), None, i, vec![]);
        b.ret(None);
    }
    m.add_func(a);
    let mut g = Function::new("b", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut g);
        b.call(FuncId(1), None, vec![]);
        b.ret(None);
    }
    m.add_func(g);
    expect_only(&verify_module(&m).unwrap_err(), "recursion: @a -> @b -> @a");
}
