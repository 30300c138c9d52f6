//! Hand-built modules shared by the text and verifier tests.

#![allow(dead_code)]

use plcc_ir::diag::{FileId, Span};
use plcc_ir::*;

pub fn field(name: &str, role: FieldRole, ty: MemType, elem: Option<ElemType>) -> Field {
    Field {
        name: name.into(),
        ty,
        elem,
        role,
        location: None,
    }
}

pub fn scalar(t: Type) -> MemType {
    MemType::Scalar(t)
}

/// A module that uses every instruction, operation, condition, conversion, intrinsic,
/// field role, struct kind, data kind and function kind, nested aggregates, arrays of
/// structs, slots of aggregate type, block parameters, special float constants and
/// quoted names. It is valid. Instructions are created in layout order and every
/// value and block is live, so it parses back to an equal module.
pub fn kitchen_sink() -> Module {
    let mut m = Module::new();
    m.files = vec!["examples/a.st".into(), "odd \"name\"\\\n.st".into()];

    let r_trig = m.add_agg(AggDef::Struct(StructDef {
        name: "R_TRIG".into(),
        kind: StructKind::FunctionBlock,
        fields: vec![
            field(
                "CLK",
                FieldRole::Input,
                scalar(Type::I1),
                Some(ElemType::Bool),
            ),
            field(
                "Q",
                FieldRole::Output,
                scalar(Type::I1),
                Some(ElemType::Bool),
            ),
            field("M", FieldRole::Hidden, scalar(Type::I1), None),
        ],
    }));
    // A struct declared before the aggregate it contains (forward reference).
    let ton = m.add_agg(AggDef::Struct(StructDef {
        name: "TON".into(),
        kind: StructKind::FunctionBlock,
        fields: vec![
            field(
                "IN",
                FieldRole::Input,
                scalar(Type::I1),
                Some(ElemType::Bool),
            ),
            field(
                "PT",
                FieldRole::Input,
                scalar(Type::I32),
                Some(ElemType::Time),
            ),
            field(
                "Q",
                FieldRole::Output,
                scalar(Type::I1),
                Some(ElemType::Bool),
            ),
            field(
                "ET",
                FieldRole::Output,
                scalar(Type::I32),
                Some(ElemType::Time),
            ),
            field(
                "start",
                FieldRole::Hidden,
                scalar(Type::I32),
                Some(ElemType::Time),
            ),
            field("inner", FieldRole::Var, MemType::Agg(r_trig), None),
            Field {
                location: Some("%QX0.0".into()),
                ..field(
                    "lamp",
                    FieldRole::Var,
                    scalar(Type::I1),
                    Some(ElemType::Bool),
                )
            },
            field(
                "io",
                FieldRole::InOut,
                scalar(Type::Ptr),
                Some(ElemType::Ref),
            ),
            field(
                "tmp",
                FieldRole::Temp,
                scalar(Type::F64),
                Some(ElemType::LReal),
            ),
            field("ext", FieldRole::External, scalar(Type::Ptr), None),
            field("later", FieldRole::Var, MemType::Agg(AggId(5)), None),
        ],
    }));
    let point = m.add_agg(AggDef::Struct(StructDef {
        name: "Point".into(),
        kind: StructKind::Struct,
        fields: vec![
            field("x", FieldRole::Var, scalar(Type::F32), Some(ElemType::Real)),
            field("y", FieldRole::Var, scalar(Type::F32), Some(ElemType::Real)),
        ],
    }));
    let a0 = m.add_agg(AggDef::Array(ArrayDef {
        name: "a0".into(),
        elem: scalar(Type::I16),
        elem_type: Some(ElemType::Int),
        len: 10,
        lower: 1,
    }));
    let grid = m.add_agg(AggDef::Array(ArrayDef {
        name: "grid".into(),
        elem: MemType::Agg(a0),
        elem_type: None,
        len: 3,
        lower: 0,
    }));
    let pts = m.add_agg(AggDef::Array(ArrayDef {
        name: "pts".into(),
        elem: MemType::Agg(point),
        elem_type: None,
        len: 4,
        lower: -2,
    }));
    assert_eq!(pts, AggId(5));
    let weird = m.add_agg(AggDef::Struct(StructDef {
        name: "weird name!".into(),
        kind: StructKind::Other,
        fields: vec![
            field(
                "field.with.dots",
                FieldRole::Var,
                scalar(Type::I8),
                Some(ElemType::SInt),
            ),
            field("sp ace", FieldRole::Var, MemType::Agg(grid), None),
            field(
                "ünï",
                FieldRole::Var,
                scalar(Type::I64),
                Some(ElemType::LWord),
            ),
            field("", FieldRole::Var, scalar(Type::I16), Some(ElemType::WChar)),
        ],
    }));
    let dotted = m.add_agg(AggDef::Struct(StructDef {
        name: "pkg.Inner.".into(),
        kind: StructKind::Struct,
        fields: vec![
            field("v", FieldRole::Var, scalar(Type::I32), Some(ElemType::DInt)),
            field(
                "w.x",
                FieldRole::Var,
                scalar(Type::I32),
                Some(ElemType::UDInt),
            ),
        ],
    }));
    let main_s = m.add_agg(AggDef::Struct(StructDef {
        name: "main".into(),
        kind: StructKind::Program,
        fields: vec![
            field(
                "count",
                FieldRole::Var,
                scalar(Type::I32),
                Some(ElemType::DInt),
            ),
            field("t", FieldRole::Var, MemType::Agg(ton), None),
            field("pts", FieldRole::Var, MemType::Agg(pts), None),
            field("w", FieldRole::Var, MemType::Agg(weird), None),
            field("d", FieldRole::Var, MemType::Agg(dotted), None),
        ],
    }));

    let main_d = m.add_data(DataDef {
        name: "main".into(),
        ty: MemType::Agg(main_s),
        elem: None,
        kind: DataKind::Program,
        location: None,
    });
    let g = m.add_data(DataDef {
        name: "g".into(),
        ty: scalar(Type::I32),
        elem: Some(ElemType::DInt),
        kind: DataKind::Global,
        location: Some("%MD2".into()),
    });
    let tbl = m.add_data(DataDef {
        name: "tbl".into(),
        ty: MemType::Agg(a0),
        elem: None,
        kind: DataKind::Constant,
        location: None,
    });
    let q = m.add_data(DataDef {
        name: "q x".into(),
        ty: scalar(Type::F64),
        elem: Some(ElemType::LReal),
        kind: DataKind::Global,
        location: None,
    });
    m.globals = Some(m.add_data(DataDef {
        name: "$globals".into(),
        ty: MemType::Agg(point),
        elem: None,
        kind: DataKind::Global,
        location: None,
    }));

    // Functions are added first so that calls can refer to later ones.
    let helper_id = FuncId(1);
    // Function tables: one with an empty entry, one with no entries.
    let helper_table = m.add_table(Table {
        name: "I_Helper.Apply".into(),
        params: vec![Type::I64, Type::F32],
        result: Some(Type::I64),
        entries: vec![None, Some(helper_id)],
    });
    let empty_table = m.add_table(Table {
        name: "odd \"table\"".into(),
        params: vec![],
        result: None,
        entries: vec![],
    });
    let mut kf = Function::new(
        "kitchen",
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
    kf.span = Some(Span::new(FileId(0), 1, 999));
    {
        let mut b = FuncBuilder::new(&mut kf);
        let p = b.params();
        let (x32, x64, f32v, f64v, ptr, flag) = (p[0], p[1], p[2], p[3], p[4], p[5]);
        let ss_pt = b.slot("pt", MemType::Agg(point));
        let ss_tmp = b.slot("tmp \"q\"", scalar(Type::I32));
        let ss_grid = b.slot("", MemType::Agg(grid));
        b.set_span(Some(Span::new(FileId(0), 10, 20)));
        for (ty, v) in [
            (Type::I1, 1),
            (Type::I1, 0),
            (Type::I8, -128),
            (Type::I8, 127),
            (Type::I16, -1),
            (Type::I32, i32::MIN as i64),
            (Type::I64, i64::MIN),
            (Type::I64, i64::MAX),
        ] {
            b.iconst(ty, v);
        }
        b.set_span(Some(Span::new(FileId(1), 0, 0)));
        for x in [
            1.5f32,
            -0.0,
            0.0,
            0.1,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
            f32::MIN_POSITIVE,
            1e-45,
            1e30,
            -3.25e-7,
        ] {
            b.f32const(x);
        }
        for bits in [0x7fc0_0001u32, 0xffc0_0000, 0x7f80_0001, 0xff80_0002] {
            b.func.create_inst(
                InstData::Fconst {
                    ty: Type::F32,
                    bits: bits as u64,
                },
                Some(Type::F32),
                None,
            );
            // place it through the builder's current block
            let i = Inst::new(b.func.insts.len() - 1);
            let cur = b.current_block().unwrap();
            b.func.blocks[cur.index()].insts.push(i);
        }
        b.set_span(None);
        for x in [
            1.5f64,
            -0.0,
            0.1,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            1e300,
            123456789.125,
        ] {
            b.f64const(x);
        }
        b.fconst(Type::F64, f64::from_bits(0x7ff8_0000_0000_0001));
        b.fconst(Type::F64, f64::from_bits(0xfff8_0000_0000_0000));
        for op in UnaryOp::ALL {
            if op.is_int_op() {
                b.unary(op, x32);
            } else {
                b.unary(op, f64v);
                b.unary(op, f32v);
            }
        }
        b.unary(UnaryOp::Bnot, flag);
        for op in BinaryOp::ALL {
            if op.is_int_op() {
                b.binary(op, x32, x32);
                b.binary(op, x64, x64);
            } else {
                b.binary(op, f64v, f64v);
                b.binary(op, f32v, f32v);
            }
        }
        for op in [BinaryOp::Band, BinaryOp::Bor, BinaryOp::Bxor] {
            b.binary(op, flag, flag);
        }
        for cc in IntCC::ALL {
            b.icmp(cc, x32, x32);
        }
        b.icmp(IntCC::Eq, ptr, ptr);
        b.icmp(IntCC::Ne, flag, flag);
        for cc in FloatCC::ALL {
            b.fcmp(cc, f64v, f64v);
            b.fcmp(cc, f32v, f32v);
        }
        let byte = b.convert(ConvOp::Itrunc, Type::I8, x32);
        for op in ConvOp::ALL {
            match op {
                ConvOp::Sext => {
                    b.convert(op, Type::I64, x32);
                }
                ConvOp::Uext => {
                    b.convert(op, Type::I16, byte);
                    b.convert(op, Type::I32, flag);
                }
                ConvOp::Itrunc => {
                    b.convert(op, Type::I16, x64);
                    b.convert(op, Type::I1, x32);
                }
                ConvOp::Fpromote => {
                    b.convert(op, Type::F64, f32v);
                }
                ConvOp::Fdemote => {
                    b.convert(op, Type::F32, f64v);
                }
                ConvOp::SiToF | ConvOp::UiToF => {
                    b.convert(op, Type::F64, x32);
                    b.convert(op, Type::F32, x64);
                }
                ConvOp::FToSi | ConvOp::FToUi => {
                    b.convert(op, Type::I16, f64v);
                    b.convert(op, Type::I64, f32v);
                }
                ConvOp::Bitcast => {
                    b.convert(op, Type::F32, x32);
                    b.convert(op, Type::I64, f64v);
                }
                ConvOp::PtrToInt => {
                    b.convert(op, Type::I32, ptr);
                }
                ConvOp::IntToPtr => {
                    b.convert(op, Type::Ptr, x64);
                }
            }
        }
        let c = b.icmp(IntCC::Slt, x32, x32);
        b.select(c, x32, x32);
        b.select(flag, ptr, ptr);
        let gm = b.global_addr(main_d);
        let gg = b.global_addr(g);
        b.global_addr(tbl);
        let gq = b.global_addr(q);
        let sp = b.slot_addr(ss_pt);
        let st = b.slot_addr(ss_tmp);
        let sg = b.slot_addr(ss_grid);
        let fx = b.field_addr(sp, point, 0);
        let fv = b.load(Type::F32, fx);
        b.store(fv, fx);
        let t = b.field_addr(gm, main_s, 1);
        let lamp = b.field_addr(t, ton, 6);
        let lv = b.load(Type::I1, lamp);
        b.store(lv, lamp);
        let inner = b.field_addr(t, ton, 5);
        b.field_addr(inner, r_trig, 2);
        let w = b.field_addr(gm, main_s, 3);
        b.field_addr(w, weird, 0);
        let sp_ace = b.field_addr(w, weird, 1);
        b.field_addr(w, weird, 2);
        b.field_addr(w, weird, 3);
        let d = b.field_addr(gm, main_s, 4);
        b.field_addr(d, dotted, 0);
        b.field_addr(d, dotted, 1);
        let i1 = b.iconst(Type::I16, 1);
        let row = b.elem_addr(sp_ace, grid, i1);
        let i2 = b.iconst(Type::I64, 2);
        let cell = b.elem_addr(row, a0, i2);
        let cv = b.load(Type::I16, cell);
        b.store(cv, cell);
        let row2 = b.elem_addr(sg, grid, byte);
        b.elem_addr(row2, a0, x32);
        let pa = b.field_addr(gm, main_s, 2);
        let p1 = b.elem_addr(pa, pts, x32);
        b.field_addr(p1, point, 1);
        let gv = b.load(Type::I32, gg);
        b.store(gv, st);
        let qv = b.load(Type::F64, gq);
        b.store(qv, gq);
        b.load(Type::Ptr, ptr);
        let r = b.call(helper_id, Some(Type::I64), vec![x64, f32v]).unwrap();
        b.call_table(helper_table, Some(Type::I64), x32, vec![r, f32v]);
        b.call_table(empty_table, None, x64, vec![]);
        for op in Intrinsic::ALL {
            let args = match op {
                // One element of INT: the one written above.
                Intrinsic::Fill => vec![cell, cv, b.iconst(Type::I64, 1)],
                _ => vec![],
            };
            b.intrinsic(op, args);
        }
        // Control flow: a loop with block parameters, a diamond, returns.
        let head = b.create_block();
        let hp = b.block_param(head, Type::I32);
        let hq = b.block_param(head, Type::I64);
        let body = b.create_block();
        let exit = b.create_block();
        let ep = b.block_param(exit, Type::I32);
        b.jump(head, vec![x32, r]);
        b.switch_to(head);
        let one = b.iconst(Type::I32, 1);
        let n = b.binary(BinaryOp::Iadd, hp, one);
        let done = b.icmp(IntCC::Sge, n, x32);
        b.brif(done, exit, vec![n], body, vec![]);
        b.switch_to(body);
        let q2 = b.binary(BinaryOp::Iadd, hq, hq);
        // A jump table whose entries repeat a destination with other arguments.
        b.br_table(
            n,
            BlockCall::new(head, vec![n, q2]),
            vec![
                BlockCall::new(exit, vec![hp]),
                BlockCall::new(head, vec![n, q2]),
                BlockCall::new(head, vec![hp, hq]),
            ],
        );
        b.switch_to(exit);
        b.ret(Some(ep));
    }
    m.add_func(kf);

    let mut hf = Function::new(
        "helper.$x",
        FuncKind::Helper,
        vec![Type::I64, Type::F32],
        Some(Type::I64),
    );
    {
        let mut b = FuncBuilder::new(&mut hf);
        let p = b.params();
        b.ret(Some(p[0]));
    }
    assert_eq!(m.add_func(hf), helper_id);

    let mut fb = Function::new("TON", FuncKind::FbBody, vec![Type::Ptr], None);
    {
        let mut b = FuncBuilder::new(&mut fb);
        let p = b.params();
        let q = b.field_addr(p[0], ton, 2);
        let t = b.iconst(Type::I1, 1);
        b.store(t, q);
        b.ret(None);
    }
    let ton_body = m.add_func(fb);

    let mut body = Function::new("main", FuncKind::ProgramBody, vec![Type::Ptr], None);
    {
        let mut b = FuncBuilder::new(&mut body);
        let p = b.params();
        let t = b.field_addr(p[0], main_s, 1);
        b.call(ton_body, None, vec![t]);
        b.ret(None);
    }
    let body_id = m.add_func(body);
    let mut init = Function::new("main$init", FuncKind::Init, vec![Type::Ptr], None);
    {
        let mut b = FuncBuilder::new(&mut init);
        let p = b.params();
        let c = b.field_addr(p[0], main_s, 0);
        let z = b.iconst(Type::I32, 0);
        b.store(z, c);
        b.ret(None);
    }
    let init_id = m.add_func(init);
    let mut gi = Function::new("globals init", FuncKind::Init, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut gi);
        let a = b.global_addr(g);
        let z = b.iconst(Type::I32, 7);
        b.store(z, a);
        b.ret(None);
    }
    let gi_id = m.add_func(gi);
    m.programs.push(ProgramEntry {
        name: "main".into(),
        data: main_d,
        body: body_id,
        init: init_id,
        interval_us: None,
        priority: None,
    });
    m.programs.push(ProgramEntry {
        name: "fast \"one\"".into(),
        data: main_d,
        body: body_id,
        init: init_id,
        interval_us: Some(10_000),
        priority: Some(0),
    });
    m.init_globals = Some(gi_id);
    m.configuration = Some(Configuration {
        name: "Config \"0\"".into(),
        resources: vec![
            Resource {
                name: "Res0".into(),
                programs: vec!["main".into()],
                globals: vec!["x".into()],
            },
            Resource {
                name: "fast".into(),
                programs: vec!["fast \"one\"".into()],
                globals: Vec::new(),
            },
            Resource::default(),
        ],
    });
    m
}
