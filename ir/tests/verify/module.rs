//! The module-level rules: names, aggregates, programs, globals' init, recursion.

use super::*;

fn simple(name: &str, kind: FuncKind, params: Vec<Type>) -> Function {
    let mut f = Function::new(name, kind, params, None);
    FuncBuilder::new(&mut f).ret(None);
    f
}

#[test]
fn duplicate_names() {
    let mut m = base();
    m.add_func(simple("callee", FuncKind::Helper, vec![]));
    expect_only(
        &verify_module(&m).unwrap_err(),
        "functions func0 and func1 are both named @callee",
    );
    let mut m = base();
    let a = m.aggs[1].clone();
    m.add_agg(a);
    expect_only(
        &verify_module(&m).unwrap_err(),
        "aggregates agg1 and agg2 are both named %A",
    );
    let mut m = base();
    let mut d = m.data[0].clone();
    d.name = "D".into();
    m.add_data(d);
    expect_only(
        &verify_module(&m).unwrap_err(),
        "data objects @d and @D have the same name",
    );
    let mut m = base();
    if let AggDef::Struct(s) = &mut m.aggs[0] {
        s.fields
            .push(field("A", FieldRole::Var, scalar(Type::I8), None));
    }
    expect_only(
        &verify_module(&m).unwrap_err(),
        "struct %S has two fields named `A` (field names ignore case)",
    );
}

#[test]
fn aggregate_members() {
    let mut m = base();
    if let AggDef::Struct(s) = &mut m.aggs[0] {
        s.fields
            .push(field("z", FieldRole::Var, MemType::Agg(AggId(40)), None));
        s.fields.push(field(
            "w",
            FieldRole::Var,
            scalar(Type::I16),
            Some(ElemType::Bool),
        ));
    }
    if let AggDef::Array(a) = &mut m.aggs[1] {
        a.elem_type = Some(ElemType::Real);
    }
    m.data[0].ty = MemType::Agg(AggId(41));
    let errs = verify_module(&m).unwrap_err();
    expect(&errs, "field `z` of %S has a type that does not exist");
    expect(
        &errs,
        "field `w` of %S is i16 but its IEC type BOOL is held in i1",
    );
    expect(
        &errs,
        "the elements of %A are i16 but their IEC type REAL is held in f32",
    );
    expect(&errs, "the type of data @d does not exist");
    assert_eq!(errs.len(), 4);
}

#[test]
fn aggregate_cycles() {
    let mut m = base();
    // %A's elements are %S, which contains %A.
    if let AggDef::Array(a) = &mut m.aggs[1] {
        a.elem = MemType::Agg(S);
        a.elem_type = None;
    }
    expect_only(
        &verify_module(&m).unwrap_err(),
        "aggregate %S contains itself: %S -> %A -> %S",
    );
    let mut m = base();
    if let AggDef::Struct(s) = &mut m.aggs[0] {
        s.fields[0].ty = MemType::Agg(S);
        s.fields[0].elem = None;
    }
    expect_only(
        &verify_module(&m).unwrap_err(),
        "aggregate %S contains itself: %S -> %S",
    );
}

fn with_program(body: Function, init: Function) -> Module {
    let mut m = base();
    let b = m.add_func(body);
    let i = m.add_func(init);
    m.programs.push(ProgramEntry {
        name: "p".into(),
        data: DataId(0),
        body: b,
        init: i,
        interval_us: None,
        priority: None,
    });
    m
}

#[test]
fn programs() {
    let good_body = || simple("b", FuncKind::ProgramBody, vec![Type::Ptr]);
    let good_init = || simple("i", FuncKind::Init, vec![Type::Ptr]);
    verify_module(&with_program(good_body(), good_init())).unwrap();
    let errs = verify_module(&with_program(
        simple("b", FuncKind::ProgramBody, vec![Type::I32]),
        good_init(),
    ))
    .unwrap_err();
    expect_only(
        &errs,
        "program \"p\": its body @b must be (ptr) with no result, but is (i32)",
    );
    let errs = verify_module(&with_program(
        good_body(),
        simple("i", FuncKind::Helper, vec![Type::Ptr]),
    ))
    .unwrap_err();
    expect_only(
        &errs,
        "program \"p\": its init @i must be a `init` function, but is `helper`",
    );
    let errs = verify_module(&with_program(
        simple("b", FuncKind::FbBody, vec![Type::Ptr]),
        good_init(),
    ))
    .unwrap_err();
    expect_only(
        &errs,
        "its body @b must be a `program` function, but is `fb`",
    );
    let mut m = with_program(good_body(), good_init());
    m.programs[0].data = DataId(8);
    m.programs[0].init = FuncId(9);
    let errs = verify_module(&m).unwrap_err();
    expect(&errs, "program \"p\": its data data8 does not exist");
    expect(&errs, "program \"p\": its init func9 does not exist");
    let mut m = with_program(good_body(), good_init());
    let again = m.programs[0].clone();
    m.programs.push(ProgramEntry {
        name: "P".into(),
        ..again
    });
    expect_only(
        &verify_module(&m).unwrap_err(),
        "program \"P\" is listed twice",
    );
}

#[test]
fn init_globals() {
    let mut m = base();
    let g = m.add_func(simple("g", FuncKind::Init, vec![]));
    m.init_globals = Some(g);
    verify_module(&m).unwrap();
    let mut m = base();
    let g = m.add_func(simple("g", FuncKind::Init, vec![Type::Ptr]));
    m.init_globals = Some(g);
    expect_only(
        &verify_module(&m).unwrap_err(),
        "init_globals @g must be () with no result, but is (ptr)",
    );
    let mut m = base();
    m.init_globals = Some(FuncId(3));
    expect_only(
        &verify_module(&m).unwrap_err(),
        "init_globals func3 does not exist",
    );
}

#[test]
fn configuration_and_globals() {
    verify_module(&kitchen_sink()).unwrap();
    let mut m = kitchen_sink();
    m.globals = Some(DataId(1));
    let errs = verify_module(&m).unwrap_err();
    expect(
        &errs,
        "globals data1 must be a `global` data object holding a struct",
    );
    assert_eq!(errs.len(), 2, "and its global `x` is unknown");
    let mut m = kitchen_sink();
    m.globals = Some(DataId(40));
    let errs = verify_module(&m).unwrap_err();
    expect(&errs, "globals data40 does not exist");
    expect(
        &errs,
        "names global \"x\", which is not a field of the globals",
    );
    let mut m = kitchen_sink();
    let c = m.configuration.as_mut().unwrap();
    c.resources[0].programs.push("nobody".into());
    c.resources[1].programs.push("MAIN".into());
    c.resources[1].globals.push("z".into());
    c.resources[2].name = "res0".into();
    let errs = verify_module(&m).unwrap_err();
    expect(
        &errs,
        "resource \"Res0\" names program \"nobody\", which is not a program entry",
    );
    expect(&errs, "program \"MAIN\" is in two resources");
    expect(
        &errs,
        "resource \"fast\" names global \"z\", which is not a field of the globals",
    );
    expect(&errs, "resource \"res0\" is listed twice");
    assert_eq!(errs.len(), 4);
}

#[test]
fn recursion() {
    let caller = |name: &str, callee: FuncId| {
        let mut f = Function::new(name, FuncKind::Helper, vec![], None);
        {
            let mut b = FuncBuilder::new(&mut f);
            b.call(callee, None, vec![]);
            b.ret(None);
        }
        f
    };
    let mut m = base();
    m.add_func(caller("a", FuncId(2)));
    m.add_func(caller("b", FuncId(3)));
    m.add_func(caller("c", FuncId(1)));
    let errs = verify_module(&m).unwrap_err();
    expect_only(&errs, "recursion: @a -> @b -> @c -> @a");
    assert_eq!(
        errs[0].to_string(),
        "in @a: recursion: @a -> @b -> @c -> @a"
    );
    let mut m = base();
    m.add_func(caller("self", FuncId(1)));
    expect_only(
        &verify_module(&m).unwrap_err(),
        "recursion: @self calls itself",
    );
    // A diamond is not a cycle.
    let mut m = base();
    m.add_func(caller("top", FuncId(2)));
    m.add_func(caller("mid", FuncId(3)));
    m.add_func(simple("leaf", FuncKind::Helper, vec![]));
    let mut f = Function::new("top2", FuncKind::Helper, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.call(FuncId(2), None, vec![]);
        b.call(FuncId(3), None, vec![]);
        b.ret(None);
    }
    m.add_func(f);
    verify_module(&m).unwrap();
    // Calls in blocks outside the layout do not count.
    let mut m = base();
    let mut f = caller("dead", FuncId(1));
    f.layout.clear();
    let entry = f.create_block();
    f.layout.push(entry);
    let r = f.create_inst(InstData::Return { value: None }, None, None);
    f.blocks[entry.index()].insts.push(r);
    m.add_func(f);
    verify_module(&m).unwrap();
}

#[test]
fn verify_function_alone() {
    let m = base();
    let mut f = Function::new("new", FuncKind::Helper, vec![Type::I32], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        let p = b.params();
        b.call(CALLEE, Some(Type::I16), vec![p[0]]);
        b.ret(None);
    }
    let errs = verify_function(&m, &f).unwrap_err();
    expect_only(&errs, "@callee takes 2 arguments, found 1");
    assert_eq!(errs[0].func.as_deref(), Some("new"));
    assert_eq!(errs[0].inst_text.as_deref(), Some("v1 = call @callee(v0)"));
}
