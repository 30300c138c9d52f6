//! The verifier: every check has a bad function that trips it; valid modules pass.

mod common;

use common::*;
use plcc_ir::dominators::DomTree;
use plcc_ir::function::ValueDef;
use plcc_ir::text::{parse_module, print_module, PrintOptions};
use plcc_ir::verify::{verify_function, verify_module, VerifyError};
use plcc_ir::*;

/// A module with a struct `%S { a: i32, b: %A }`, an array `%A = [4 x i16]`, a data
/// object `@d: %S`, and `@callee(i32, f64) -> i16`.
fn base() -> Module {
    let mut m = Module::new();
    let s = m.add_agg(AggDef::Struct(StructDef {
        name: "S".into(),
        kind: StructKind::Struct,
        fields: vec![
            field("a", FieldRole::Var, scalar(Type::I32), Some(ElemType::DInt)),
            field("b", FieldRole::Var, MemType::Agg(AggId(1)), None),
        ],
    }));
    m.add_agg(AggDef::Array(ArrayDef {
        name: "A".into(),
        elem: scalar(Type::I16),
        elem_type: Some(ElemType::Int),
        len: 4,
        lower: 0,
    }));
    m.add_data(DataDef {
        name: "d".into(),
        ty: MemType::Agg(s),
        elem: None,
        kind: DataKind::Global,
        location: None,
    });
    let mut c = Function::new(
        "callee",
        FuncKind::Function,
        vec![Type::I32, Type::F64],
        Some(Type::I16),
    );
    {
        let mut b = FuncBuilder::new(&mut c);
        let x = b.iconst(Type::I16, 0);
        b.ret(Some(x));
    }
    m.add_func(c);
    m
}

const S: AggId = AggId(0);
const A: AggId = AggId(1);
const CALLEE: FuncId = FuncId(0);

/// Builds `@f(i32, i64, f32, f64, ptr, i1) -> i32` in the base module with `body`,
/// which gets the parameters; then verifies the whole module.
fn check(body: impl FnOnce(&mut FuncBuilder, &[Value])) -> Vec<VerifyError> {
    check_sig(
        vec![
            Type::I32,
            Type::I64,
            Type::F32,
            Type::F64,
            Type::Ptr,
            Type::I1,
        ],
        Some(Type::I32),
        body,
    )
}

fn check_sig(
    params: Vec<Type>,
    ret: Option<Type>,
    body: impl FnOnce(&mut FuncBuilder, &[Value]),
) -> Vec<VerifyError> {
    let mut m = base();
    let mut f = Function::new("f", FuncKind::Function, params, ret);
    {
        let mut b = FuncBuilder::new(&mut f);
        let p = b.params();
        body(&mut b, &p);
    }
    m.add_func(f);
    match verify_module(&m) {
        Ok(()) => Vec::new(),
        Err(e) => e,
    }
}

fn check_func(f: Function) -> Vec<VerifyError> {
    let mut m = base();
    m.add_func(f);
    verify_module(&m).err().unwrap_or_default()
}

#[track_caller]
fn expect(errs: &[VerifyError], msg: &str) {
    assert!(
        errs.iter().any(|e| e.message.contains(msg)),
        "expected an error containing `{msg}`, got {:#?}",
        errs.iter().map(|e| e.to_string()).collect::<Vec<_>>()
    );
}

#[track_caller]
fn expect_only(errs: &[VerifyError], msg: &str) {
    expect(errs, msg);
    assert_eq!(
        errs.len(),
        1,
        "{:#?}",
        errs.iter().map(|e| e.to_string()).collect::<Vec<_>>()
    );
}

#[track_caller]
fn expect_ok(errs: &[VerifyError]) {
    assert!(
        errs.is_empty(),
        "{:#?}",
        errs.iter().map(|e| e.to_string()).collect::<Vec<_>>()
    );
}

fn ret0(b: &mut FuncBuilder, p: &[Value]) {
    b.ret(Some(p[0]));
}

#[test]
fn valid_modules_pass() {
    verify_module(&base()).unwrap();
    verify_module(&kitchen_sink()).unwrap();
    verify_module(&Module::new()).unwrap();
    expect_ok(&check(ret0));
}

#[test]
fn display_format() {
    let errs = check(|b, p| {
        let x = b.iconst(Type::I16, 1);
        let y = b.binary(BinaryOp::Iadd, p[0], x);
        b.ret(Some(y));
    });
    expect_only(&errs, "operand types differ: i32 vs i16");
    assert_eq!(
        errs[0].to_string(),
        "in @f, inst1 (v7 = iadd v0, v6): operand types differ: i32 vs i16"
    );
    assert_eq!(errs[0].inst, Some(Inst(1)));
    assert_eq!(errs[0].func.as_deref(), Some("f"));
    let e = VerifyError {
        func: Some("a b".into()),
        inst: None,
        inst_text: None,
        message: "m".into(),
    };
    assert_eq!(e.to_string(), "in @\"a b\": m");
    let e = VerifyError {
        func: None,
        inst: None,
        inst_text: None,
        message: "m".into(),
    };
    assert_eq!(e.to_string(), "m");
}

// ----- block structure -----------------------------------------------------------

#[test]
fn no_blocks() {
    let f = Function::new("f", FuncKind::Function, vec![], None);
    expect_only(&check_func(f), "the function has no blocks");
}

#[test]
fn empty_block() {
    let errs = check(|b, p| {
        let e = b.create_block();
        b.switch_to(e);
        let _ = p;
    });
    expect(&errs, "block0 is empty");
    let errs = check(|b, p| {
        let e = b.create_block();
        b.ret(Some(p[0]));
        b.switch_to(e);
    });
    expect_only(&errs, "block1 is empty");
}

#[test]
fn block_twice_in_layout() {
    let mut f = Function::new("f", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    f.layout.push(Block(0));
    expect_only(
        &check_func(f),
        "block0 appears more than once in the layout",
    );
}

#[test]
fn layout_block_out_of_range() {
    let mut f = Function::new("f", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    f.layout.push(Block(7));
    expect_only(
        &check_func(f),
        "the layout names block7, which does not exist",
    );
}

#[test]
fn missing_and_misplaced_terminators() {
    let errs = check(|b, p| {
        b.iconst(Type::I32, 1);
        let _ = p;
    });
    expect_only(&errs, "block0 does not end with a terminator");
    // A return in the middle of a block.
    let mut f = Function::new("f", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    let extra = f.create_inst(InstData::Return { value: None }, None, None);
    f.blocks[0].insts.insert(0, extra);
    expect_only(&check_func(f), "a terminator in the middle of block0");
}

#[test]
fn inst_placed_twice_or_missing() {
    let mut f = Function::new("f", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.intrinsic(Intrinsic::RaiseFault, vec![]);
        b.ret(None);
    }
    f.blocks[0].insts.insert(0, Inst(0));
    expect_only(&check_func(f.clone()), "placed twice");
    f.blocks[0].insts[0] = Inst(40);
    expect_only(&check_func(f), "block0 lists inst40, which does not exist");
}

#[test]
fn entry_params_match_the_signature() {
    let mut f = Function::new("f", FuncKind::Function, vec![Type::I32], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    let mut g = f.clone();
    f.params = vec![Type::I32, Type::I32];
    expect_only(
        &check_func(f),
        "the entry block block0 has 1 parameters but the function has 2",
    );
    g.params = vec![Type::I16];
    expect_only(
        &check_func(g),
        "parameter 0 of the entry block (v0) is i32 but the function's is i16",
    );
}

#[test]
fn block_param_definitions() {
    let mut f = Function::new("f", FuncKind::Function, vec![Type::I32], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    f.values[0].def = ValueDef::Param(Block(0), 3);
    expect(
        &check_func(f.clone()),
        "v0 is parameter 0 of block0 but its definition says",
    );
    f.blocks[0].params[0] = Value(9);
    expect(
        &check_func(f),
        "parameter 0 of block0 is v9, which does not exist",
    );
}

#[test]
fn tables_of_different_lengths() {
    let mut f = Function::new("f", FuncKind::Function, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.ret(None);
    }
    f.spans.clear();
    expect_only(
        &check_func(f),
        "the function has 1 instructions but 1 results and 0 locations",
    );
}

// ----- types ---------------------------------------------------------------------

#[test]
fn constants() {
    expect_ok(&check(|b, p| {
        b.iconst(Type::I1, 1);
        b.iconst(Type::I64, i64::MIN);
        b.fconst(Type::F32, f64::NAN);
        ret0(b, p)
    }));
    let errs = check(|b, p| {
        b.func.create_inst(
            InstData::Iconst {
                ty: Type::I8,
                imm: 255,
            },
            Some(Type::I8),
            None,
        );
        let i = Inst(b.func.insts.len() as u32 - 1);
        b.func.blocks[0].insts.push(i);
        ret0(b, p)
    });
    expect_only(
        &errs,
        "the constant 255 is not in canonical form for i8 (expected -1)",
    );
    let errs = check(|b, p| {
        b.func.create_inst(
            InstData::Iconst {
                ty: Type::Ptr,
                imm: 8,
            },
            Some(Type::Ptr),
            None,
        );
        b.func.blocks[0].insts.push(Inst(0));
        ret0(b, p)
    });
    expect_only(&errs, "the only pointer constant is 0 (null)");
    let errs = check(|b, p| {
        b.func.create_inst(
            InstData::Fconst {
                ty: Type::I32,
                bits: 0,
            },
            Some(Type::I32),
            None,
        );
        b.func.blocks[0].insts.push(Inst(0));
        ret0(b, p)
    });
    expect_only(&errs, "fconst needs a float type, not i32");
    let errs = check(|b, p| {
        b.func.create_inst(
            InstData::Fconst {
                ty: Type::F32,
                bits: 1 << 40,
            },
            Some(Type::F32),
            None,
        );
        b.func.blocks[0].insts.push(Inst(0));
        ret0(b, p)
    });
    expect_only(&errs, "has bits above bit 31");
}

#[test]
fn unary_types() {
    let ok = check(|b, p| {
        b.unary(UnaryOp::Bnot, p[5]);
        b.unary(UnaryOp::Bnot, p[1]);
        b.unary(UnaryOp::Ineg, p[0]);
        b.unary(UnaryOp::Iabs, p[1]);
        b.unary(UnaryOp::Fsqrt, p[2]);
        b.unary(UnaryOp::Exp, p[3]);
        ret0(b, p)
    });
    expect_ok(&ok);
    expect_only(
        &check(|b, p| {
            b.unary(UnaryOp::Ineg, p[5]);
            ret0(b, p)
        }),
        "ineg needs an integer (i8..i64) operand, found i1",
    );
    expect_only(
        &check(|b, p| {
            b.unary(UnaryOp::Iabs, p[2]);
            ret0(b, p)
        }),
        "iabs needs an integer (i8..i64) operand, found f32",
    );
    expect_only(
        &check(|b, p| {
            b.unary(UnaryOp::Bnot, p[4]);
            ret0(b, p)
        }),
        "bnot needs an integer or i1 operand, found ptr",
    );
    expect_only(
        &check(|b, p| {
            b.unary(UnaryOp::Sin, p[0]);
            ret0(b, p)
        }),
        "sin needs a float (f32 or f64) operand, found i32",
    );
}

#[test]
fn binary_types() {
    let ok = check(|b, p| {
        for op in [BinaryOp::Band, BinaryOp::Bor, BinaryOp::Bxor] {
            b.binary(op, p[5], p[5]);
        }
        for op in BinaryOp::ALL {
            if op.is_int_op() {
                b.binary(op, p[1], p[1]);
            } else {
                b.binary(op, p[2], p[2]);
            }
        }
        ret0(b, p)
    });
    expect_ok(&ok);
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Iadd, p[5], p[5]);
            ret0(b, p)
        }),
        "iadd needs integer (i8..i64) operands, found i1",
    );
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Ishl, p[4], p[4]);
            ret0(b, p)
        }),
        "ishl needs integer (i8..i64) operands, found ptr",
    );
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Fadd, p[0], p[0]);
            ret0(b, p)
        }),
        "fadd needs float (f32 or f64) operands, found i32",
    );
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Band, p[2], p[2]);
            ret0(b, p)
        }),
        "band needs integer or i1 operands, found f32",
    );
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Fmul, p[2], p[3]);
            ret0(b, p)
        }),
        "operand types differ: f32 vs f64",
    );
    expect_only(
        &check(|b, p| {
            b.binary(BinaryOp::Ishl, p[0], p[1]);
            ret0(b, p)
        }),
        "operand types differ: i32 vs i64",
    );
}

#[test]
fn compare_types() {
    expect_ok(&check(|b, p| {
        b.icmp(IntCC::Eq, p[4], p[4]);
        b.icmp(IntCC::Ult, p[5], p[5]);
        b.icmp(IntCC::Slt, p[1], p[1]);
        b.fcmp(FloatCC::Ne, p[2], p[2]);
        ret0(b, p)
    }));
    expect_only(
        &check(|b, p| {
            b.icmp(IntCC::Eq, p[2], p[2]);
            ret0(b, p)
        }),
        "icmp needs integer or ptr operands, found f32",
    );
    expect_only(
        &check(|b, p| {
            b.icmp(IntCC::Eq, p[0], p[1]);
            ret0(b, p)
        }),
        "operand types differ: i32 vs i64",
    );
    expect_only(
        &check(|b, p| {
            b.fcmp(FloatCC::Eq, p[0], p[0]);
            ret0(b, p)
        }),
        "fcmp needs float operands, found i32",
    );
    expect_only(
        &check(|b, p| {
            b.fcmp(FloatCC::Eq, p[2], p[3]);
            ret0(b, p)
        }),
        "operand types differ: f32 vs f64",
    );
}

#[test]
fn conversions() {
    use ConvOp::*;
    // (op, from param, to, valid)
    let (i32v, i64v, f32v, f64v, ptr, i1) = (0, 1, 2, 3, 4, 5);
    let cases: &[(ConvOp, usize, Type, bool)] = &[
        (Sext, i32v, Type::I64, true),
        (Sext, i32v, Type::I32, false),
        (Sext, i64v, Type::I32, false),
        (Sext, i1, Type::I8, false),
        (Sext, f32v, Type::I64, false),
        (Uext, i1, Type::I8, true),
        (Uext, i1, Type::I64, true),
        (Uext, i32v, Type::I64, true),
        (Uext, i32v, Type::I1, false),
        (Uext, i32v, Type::F64, false),
        (Itrunc, i64v, Type::I32, true),
        (Itrunc, i32v, Type::I1, true),
        (Itrunc, i32v, Type::I64, false),
        (Itrunc, i32v, Type::I32, false),
        (Itrunc, i1, Type::I1, false),
        (Fpromote, f32v, Type::F64, true),
        (Fpromote, f64v, Type::F32, false),
        (Fpromote, f64v, Type::F64, false),
        (Fdemote, f64v, Type::F32, true),
        (Fdemote, f32v, Type::F64, false),
        (SiToF, i32v, Type::F64, true),
        (SiToF, i64v, Type::F32, true),
        (SiToF, f32v, Type::F64, false),
        (SiToF, i32v, Type::I64, false),
        (UiToF, i64v, Type::F64, true),
        (UiToF, ptr, Type::F64, false),
        (FToSi, f64v, Type::I16, true),
        (FToSi, f64v, Type::I1, false),
        (FToSi, i32v, Type::I64, false),
        (FToUi, f32v, Type::I64, true),
        (FToUi, f32v, Type::F64, false),
        (Bitcast, i32v, Type::F32, true),
        (Bitcast, f64v, Type::I64, true),
        (Bitcast, i32v, Type::F64, false),
        (Bitcast, f32v, Type::F32, false),
        (Bitcast, i64v, Type::I64, false),
        (Bitcast, ptr, Type::I64, false),
    ];
    for &(op, from, to, valid) in cases {
        let errs = check(|b, p| {
            b.convert(op, to, p[from]);
            ret0(b, p)
        });
        if valid {
            expect_ok(&errs);
        } else {
            expect_only(&errs, &format!("cannot {} ", op.name()));
        }
    }
    let errs = check(|b, p| {
        b.convert(Sext, Type::I16, p[0]);
        ret0(b, p)
    });
    assert_eq!(
        errs[0].message,
        "cannot sext i32 to i16: sext goes from i8..i64 to a strictly wider integer"
    );
}

#[test]
fn select_types() {
    expect_ok(&check(|b, p| {
        b.select(p[5], p[4], p[4]);
        ret0(b, p)
    }));
    expect_only(
        &check(|b, p| {
            b.select(p[0], p[0], p[0]);
            ret0(b, p)
        }),
        "the select condition v0 is i32, expected i1",
    );
    expect_only(
        &check(|b, p| {
            b.select(p[5], p[0], p[1]);
            ret0(b, p)
        }),
        "select arms differ: i32 vs i64",
    );
}

#[test]
fn addresses() {
    expect_ok(&check(|b, p| {
        let d = b.global_addr(DataId(0));
        let a = b.field_addr(d, S, 0);
        let arr = b.field_addr(d, S, 1);
        let e = b.elem_addr(arr, A, p[0]);
        let v = b.load(Type::I16, e);
        b.store(v, e);
        let x = b.load(Type::I32, a);
        b.ret(Some(x));
    }));
    expect_only(
        &check(|b, p| {
            b.field_addr(p[0], S, 0);
            ret0(b, p)
        }),
        "the address v0 is i32, expected ptr",
    );
    expect_only(
        &check(|b, p| {
            b.field_addr(p[4], A, 0);
            ret0(b, p)
        }),
        "field_addr needs a struct, but %A is an array",
    );
    expect_only(
        &check(|b, p| {
            b.field_addr(p[4], S, 2);
            ret0(b, p)
        }),
        "struct %S has 2 fields; field 2 does not exist",
    );
    expect_only(
        &check(|b, p| {
            b.field_addr(p[4], AggId(9), 0);
            ret0(b, p)
        }),
        "agg9 does not exist",
    );
    expect_only(
        &check(|b, p| {
            b.elem_addr(p[4], S, p[0]);
            ret0(b, p)
        }),
        "elem_addr needs an array, but %S is a struct",
    );
    expect_only(
        &check(|b, p| {
            b.elem_addr(p[4], A, p[5]);
            ret0(b, p)
        }),
        "the index v5 is i1, expected an integer (i8..i64)",
    );
    expect_only(
        &check(|b, p| {
            b.elem_addr(p[4], A, p[3]);
            ret0(b, p)
        }),
        "the index v3 is f64, expected an integer (i8..i64)",
    );
    expect_only(
        &check(|b, p| {
            b.elem_addr(p[1], A, p[1]);
            ret0(b, p)
        }),
        "the address v1 is i64, expected ptr",
    );
    expect_only(
        &check(|b, p| {
            b.load(Type::I32, p[0]);
            ret0(b, p)
        }),
        "the address v0 is i32, expected ptr",
    );
    expect_only(
        &check(|b, p| {
            b.store(p[4], p[1]);
            ret0(b, p)
        }),
        "the address v1 is i64, expected ptr",
    );
    expect_only(
        &check(|b, p| {
            b.global_addr(DataId(3));
            ret0(b, p)
        }),
        "data3 does not exist",
    );
    expect_only(
        &check(|b, p| {
            b.slot_addr(SlotId(0));
            ret0(b, p)
        }),
        "ss0 does not exist",
    );
}

#[test]
fn calls() {
    expect_ok(&check(|b, p| {
        b.call(CALLEE, Some(Type::I16), vec![p[0], p[3]]);
        ret0(b, p)
    }));
    expect_only(
        &check(|b, p| {
            b.call(CALLEE, Some(Type::I16), vec![p[0]]);
            ret0(b, p)
        }),
        "@callee takes 2 arguments, found 1",
    );
    expect_only(
        &check(|b, p| {
            b.call(CALLEE, Some(Type::I16), vec![p[0], p[2]]);
            ret0(b, p)
        }),
        "argument 1 of @callee is f32, expected f64",
    );
    expect_only(
        &check(|b, p| {
            b.call(CALLEE, Some(Type::I32), vec![p[0], p[3]]);
            ret0(b, p)
        }),
        "the result v6 is i32, but the instruction gives i16",
    );
    expect_only(
        &check(|b, p| {
            b.call(CALLEE, None, vec![p[0], p[3]]);
            ret0(b, p)
        }),
        "the result is missing (the instruction gives i16)",
    );
    expect_only(
        &check(|b, p| {
            b.call(FuncId(5), None, vec![]);
            ret0(b, p)
        }),
        "func5 does not exist",
    );
    // A call with a result to a function without one.
    let mut m = base();
    let mut g = Function::new("g", FuncKind::Helper, vec![], None);
    FuncBuilder::new(&mut g).ret(None);
    let gid = m.add_func(g);
    let mut f = Function::new("f", FuncKind::Helper, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.call(gid, Some(Type::I32), vec![]);
        b.ret(None);
    }
    m.add_func(f);
    expect_only(
        &verify_module(&m).unwrap_err(),
        "the instruction has no result, but v0 is defined",
    );
}

#[test]
fn intrinsics() {
    expect_ok(&check(|b, p| {
        for op in Intrinsic::ALL {
            let args = match op {
                Intrinsic::Fill => vec![p[4], p[2], p[1]],
                _ => vec![],
            };
            b.intrinsic(op, args);
        }
        ret0(b, p)
    }));
    expect_only(
        &check(|b, p| {
            b.intrinsic(Intrinsic::RaiseFault, vec![p[0]]);
            ret0(b, p)
        }),
        "raise_fault takes 0 operands, found 1",
    );
    expect_only(
        &check(|b, p| {
            b.intrinsic(Intrinsic::Fill, vec![p[4], p[0]]);
            ret0(b, p)
        }),
        "fill takes 3 operands, found 2",
    );
    expect_only(
        &check(|b, p| {
            b.intrinsic(Intrinsic::Fill, vec![p[1], p[0], p[1]]);
            ret0(b, p)
        }),
        "fill's first operand must be a ptr",
    );
    expect_only(
        &check(|b, p| {
            b.intrinsic(Intrinsic::Fill, vec![p[4], p[5], p[0]]);
            ret0(b, p)
        }),
        "fill's count must be an i64",
    );
    expect_only(
        &check(|b, p| {
            b.func.create_inst(
                InstData::Intrinsic {
                    op: Intrinsic::ClockMs,
                    args: vec![],
                },
                None,
                None,
            );
            b.func.blocks[0].insts.push(Inst(0));
            ret0(b, p)
        }),
        "the result is missing (the instruction gives i32)",
    );
    expect_only(
        &check(|b, p| {
            b.func.create_inst(
                InstData::Intrinsic {
                    op: Intrinsic::ClockNs,
                    args: vec![],
                },
                Some(Type::I32),
                None,
            );
            b.func.blocks[0].insts.push(Inst(0));
            ret0(b, p)
        }),
        "the result v6 is i32, but the instruction gives i64",
    );
}

#[test]
fn results_of_instructions_without_one() {
    expect_only(
        &check(|b, p| {
            b.func.create_inst(
                InstData::Store {
                    value: p[0],
                    addr: p[4],
                },
                Some(Type::I32),
                None,
            );
            b.func.blocks[0].insts.push(Inst(0));
            ret0(b, p)
        }),
        "the instruction has no result, but v6 is defined",
    );
    expect_only(
        &check(|b, p| {
            b.func.create_inst(
                InstData::Unary {
                    op: UnaryOp::Ineg,
                    arg: p[0],
                },
                Some(Type::I64),
                None,
            );
            b.func.blocks[0].insts.push(Inst(0));
            ret0(b, p)
        }),
        "the result v6 is i64, but the instruction gives i32",
    );
    expect_only(
        &check(|b, p| {
            b.func.create_inst(
                InstData::Unary {
                    op: UnaryOp::Ineg,
                    arg: p[0],
                },
                None,
                None,
            );
            b.func.blocks[0].insts.push(Inst(0));
            ret0(b, p)
        }),
        "the result is missing",
    );
    // A result value whose definition points elsewhere.
    let errs = check(|b, p| {
        let x = b.iconst(Type::I32, 1);
        b.func.values[x.index()].def = ValueDef::Result(Inst(7));
        ret0(b, p)
    });
    expect(&errs, "the result v6 is defined elsewhere");
}

#[test]
fn returns() {
    expect_only(
        &check(|b, _| b.ret(None)),
        "return without a value in a function returning i32",
    );
    expect_only(
        &check(|b, p| b.ret(Some(p[1]))),
        "the returned v1 is i64, but the function returns i32",
    );
    expect_only(
        &check_sig(vec![Type::I32], None, |b, p| b.ret(Some(p[0]))),
        "the function returns nothing, but return has v0",
    );
}

#[test]
fn branches() {
    let errs = check(|b, p| {
        let t = b.create_block();
        let tp = b.block_param(t, Type::I32);
        let e = b.create_block();
        b.brif(p[5], t, vec![p[0]], e, vec![]);
        b.switch_to(t);
        b.ret(Some(tp));
        b.switch_to(e);
        b.jump(t, vec![p[0]]);
    });
    expect_ok(&errs);
    expect_only(
        &check(|b, p| {
            let t = b.create_block();
            b.block_param(t, Type::I32);
            b.jump(t, vec![]);
            b.switch_to(t);
            ret0(b, p)
        }),
        "block1 takes 1 arguments, found 0",
    );
    expect_only(
        &check(|b, p| {
            let t = b.create_block();
            b.block_param(t, Type::I32);
            b.jump(t, vec![p[1]]);
            b.switch_to(t);
            ret0(b, p)
        }),
        "argument 0 to block1 is i64, but the parameter v6 is i32",
    );
    expect_only(
        &check(|b, p| {
            let t = b.create_block();
            b.brif(p[0], t, vec![], t, vec![]);
            b.switch_to(t);
            ret0(b, p)
        }),
        "the branch condition v0 is i32, expected i1",
    );
    expect_only(
        &check(|b, p| {
            let t = b.create_block();
            b.jump(t, vec![]);
            let _ = p;
        }),
        "branch to block1, which is not in the layout",
    );
    expect_only(
        &check(|b, _| {
            b.jump(Block(33), vec![]);
        }),
        "branch to block33, which does not exist",
    );
}

#[test]
fn ids_out_of_range() {
    let errs = check(|b, p| {
        b.binary(BinaryOp::Iadd, p[0], Value(99));
        ret0(b, p)
    });
    expect_only(&errs, "v99 does not exist");
    let errs = check(|b, p| {
        b.func.create_inst(
            InstData::Return {
                value: Some(Value(77)),
            },
            None,
            None,
        );
        b.func.blocks[0].insts.push(Inst(0));
        let _ = p;
    });
    expect_only(&errs, "v77 does not exist");
    let mut m = base();
    let mut f = Function::new("f", FuncKind::Helper, vec![], None);
    f.create_slot("x", MemType::Agg(AggId(12)));
    FuncBuilder::new(&mut f).ret(None);
    m.add_func(f);
    expect_only(
        &verify_module(&m).unwrap_err(),
        "the type of ss0 does not exist",
    );
}

// ----- SSA dominance -------------------------------------------------------------

#[test]
fn use_before_def_in_a_block() {
    let errs = check(|b, p| {
        let x = b.iconst(Type::I32, 1);
        let y = b.binary(BinaryOp::Iadd, x, x);
        // Swap the two instructions.
        b.func.blocks[0].insts.swap(0, 1);
        let _ = (y, p);
        b.ret(Some(y));
    });
    expect_only(&errs, "v6 is used before its definition");
    // An instruction using its own result.
    let errs = check(|b, p| {
        let x = b.binary(BinaryOp::Iadd, p[0], p[0]);
        if let InstData::Binary { args, .. } = b.func.inst_mut(Inst(0)) {
            args[1] = x;
        }
        b.ret(Some(x));
    });
    expect_only(&errs, "v6 is used before its definition");
}

#[test]
fn use_not_dominated() {
    // if c { x = 1 } ; return x   -- x's block does not dominate the merge.
    let errs = check(|b, p| {
        let t = b.create_block();
        let merge = b.create_block();
        b.brif(p[5], t, vec![], merge, vec![]);
        b.switch_to(t);
        let x = b.iconst(Type::I32, 1);
        b.jump(merge, vec![]);
        b.switch_to(merge);
        b.ret(Some(x));
    });
    expect_only(
        &errs,
        "v6 is defined in block1, which does not dominate this use in block2",
    );
    // A branch argument is used at the end of the branching block: fine even though
    // the destination is not dominated.
    let errs = check(|b, p| {
        let t = b.create_block();
        let merge = b.create_block();
        let mp = b.block_param(merge, Type::I32);
        b.brif(p[5], t, vec![], merge, vec![p[0]]);
        b.switch_to(t);
        let x = b.iconst(Type::I32, 1);
        b.jump(merge, vec![x]);
        b.switch_to(merge);
        b.ret(Some(mp));
    });
    expect_ok(&errs);
    // Block parameters are defined at the start of their block, for a loop too.
    let errs = check(|b, p| {
        let head = b.create_block();
        let hp = b.block_param(head, Type::I32);
        let exit = b.create_block();
        b.jump(head, vec![p[0]]);
        b.switch_to(head);
        let n = b.binary(BinaryOp::Isub, hp, hp);
        let c = b.icmp(IntCC::Eq, n, hp);
        b.brif(c, exit, vec![], head, vec![n]);
        b.switch_to(exit);
        b.ret(Some(n));
    });
    expect_ok(&errs);
}

#[test]
fn def_outside_the_layout() {
    let mut m = base();
    let mut f = Function::new("f", FuncKind::Function, vec![], Some(Type::I32));
    let x;
    {
        let mut b = FuncBuilder::new(&mut f);
        let dead = b.create_block();
        let live = b.create_block();
        b.jump(live, vec![]);
        b.switch_to(dead);
        x = b.iconst(Type::I32, 3);
        b.ret(Some(x));
        b.switch_to(live);
        b.ret(Some(x));
    }
    f.layout.retain(|&b| b != Block(1));
    m.add_func(f.clone());
    expect_only(
        &verify_module(&m).unwrap_err(),
        "v0 is not defined in any block of the layout",
    );
    // A block parameter of a block outside the layout.
    let mut f = Function::new("f", FuncKind::Function, vec![], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let dead = b.create_block();
        let p = b.block_param(dead, Type::I32);
        b.ret(Some(p));
    }
    expect_only(
        &check_func(f),
        "v0 is not defined in any block of the layout",
    );
    // An instruction result whose instruction is in no block.
    let mut f = Function::new("f", FuncKind::Function, vec![], Some(Type::I32));
    let lone = f.create_inst(
        InstData::Iconst {
            ty: Type::I32,
            imm: 1,
        },
        Some(Type::I32),
        None,
    );
    let v = f.result(lone).unwrap();
    FuncBuilder::new(&mut f).ret(Some(v));
    expect_only(
        &check_func(f),
        "v0 is not defined in any block of the layout",
    );
}

#[test]
fn unreachable_blocks_only_need_defs_in_the_layout() {
    // An unreachable block using a value of another unreachable block, not dominated:
    // fine. Using a value of a block outside the layout: not fine.
    let errs = check(|b, p| {
        let u1 = b.create_block();
        let u2 = b.create_block();
        b.ret(Some(p[0]));
        b.switch_to(u2);
        let later = b.create_block();
        let _ = later;
        b.switch_to(u1);
        let x = b.iconst(Type::I32, 1);
        b.ret(Some(x));
        b.switch_to(u2);
        b.ret(Some(x));
    });
    expect_ok(&errs);
}

// ----- module and dominator tree: verify/module.rs, verify/domtree.rs -----------

#[path = "verify/domtree.rs"]
mod domtree;
#[path = "verify/module.rs"]
mod module;
#[path = "verify/tables.rs"]
mod tables;

// ----- robustness ------------------------------------------------------------------

/// Random corruptions of a valid module: the verifier and the printer never panic,
/// and the verifier finds a problem in (almost) every corrupted module.
#[test]
fn corrupted_modules_do_not_panic() {
    let good = kitchen_sink();
    let mut seed: u64 = 77;
    let mut rnd = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n.max(1) as u64) as usize
    };
    for _ in 0..2000 {
        let mut m = good.clone();
        for _ in 0..1 + rnd(3) {
            let fi = rnd(m.funcs.len());
            let f = &mut m.funcs[fi];
            let nv = f.values.len() as u32 + 3;
            let nb = f.blocks.len() as u32 + 2;
            match rnd(12) {
                0 => {
                    let i = rnd(f.insts.len());
                    f.insts[i].map_args(|_| Value(rnd(nv as usize) as u32));
                }
                1 => {
                    let i = rnd(f.insts.len());
                    for d in f.insts[i].successors_mut() {
                        d.block = Block(rnd(nb as usize) as u32);
                    }
                }
                2 => {
                    let b = rnd(f.blocks.len());
                    if !f.blocks[b].insts.is_empty() {
                        let k = rnd(f.blocks[b].insts.len());
                        f.blocks[b].insts.remove(k);
                    }
                }
                3 => {
                    let b = rnd(f.blocks.len());
                    f.blocks[b].insts.push(Inst(rnd(f.insts.len() + 2) as u32));
                }
                4 => {
                    f.layout.push(Block(rnd(nb as usize) as u32));
                }
                5 => {
                    if !f.layout.is_empty() {
                        let k = rnd(f.layout.len());
                        f.layout.remove(k);
                    }
                }
                6 => {
                    let v = rnd(f.values.len());
                    f.values[v].ty = [Type::I1, Type::I8, Type::I32, Type::F32, Type::Ptr][rnd(5)];
                }
                7 => {
                    let v = rnd(f.values.len());
                    f.values[v].def = if rnd(2) == 0 {
                        ValueDef::Param(Block(rnd(nb as usize) as u32), rnd(3) as u32)
                    } else {
                        ValueDef::Result(Inst(rnd(f.insts.len() + 2) as u32))
                    };
                }
                8 => {
                    let i = rnd(f.insts.len());
                    match &mut f.insts[i] {
                        InstData::FieldAddr { agg, field, .. } => {
                            *agg = AggId(rnd(12) as u32);
                            *field = rnd(14) as u32;
                        }
                        InstData::ElemAddr { agg, .. } => *agg = AggId(rnd(12) as u32),
                        InstData::Call { func, .. } => *func = FuncId(rnd(8) as u32),
                        InstData::GlobalAddr { data } => *data = DataId(rnd(6) as u32),
                        InstData::SlotAddr { slot } => *slot = SlotId(rnd(5) as u32),
                        _ => {}
                    }
                }
                9 => {
                    let i = rnd(f.results.len());
                    f.results[i] = if rnd(2) == 0 {
                        None
                    } else {
                        Some(Value(rnd(nv as usize) as u32))
                    };
                }
                10 => {
                    let b = rnd(f.blocks.len());
                    f.blocks[b].params.push(Value(rnd(nv as usize) as u32));
                }
                _ => {
                    let a = rnd(m.aggs.len());
                    match &mut m.aggs[a] {
                        AggDef::Struct(s) if !s.fields.is_empty() => {
                            let k = rnd(s.fields.len());
                            s.fields[k].ty = MemType::Agg(AggId(rnd(12) as u32));
                        }
                        AggDef::Array(arr) => arr.elem = MemType::Agg(AggId(rnd(12) as u32)),
                        _ => {}
                    }
                }
            }
        }
        let res = verify_module(&m);
        let text = print_module(&m, &PrintOptions::LOCATED);
        if let Err(errs) = &res {
            for e in errs {
                let _ = e.to_string();
            }
        }
        // A module that still verifies must still print and parse back.
        if res.is_ok() {
            let m2 = parse_module(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
            assert_eq!(print_module(&m2, &PrintOptions::LOCATED), text);
        }
    }
}
