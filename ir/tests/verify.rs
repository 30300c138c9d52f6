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
            b.intrinsic(op, vec![]);
        }
        ret0(b, p)
    }));
    expect_only(
        &check(|b, p| {
            b.intrinsic(Intrinsic::RaiseFault, vec![p[0]]);
            ret0(b, p)
        }),
        "raise_fault takes no operands, found 1",
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

// ----- module ----------------------------------------------------------------------

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

// ----- dominator tree -------------------------------------------------------------

/// Dominators by the textbook dataflow over sets, for comparison.
fn naive_dominators(succ: &[Vec<usize>], entry: usize) -> Vec<Option<Vec<bool>>> {
    let n = succ.len();
    let mut reach = vec![false; n];
    let mut stack = vec![entry];
    reach[entry] = true;
    while let Some(b) = stack.pop() {
        for &s in &succ[b] {
            if !reach[s] {
                reach[s] = true;
                stack.push(s);
            }
        }
    }
    let mut preds = vec![Vec::new(); n];
    for (b, ss) in succ.iter().enumerate() {
        for &s in ss {
            if reach[b] {
                preds[s].push(b);
            }
        }
    }
    let mut dom: Vec<Vec<bool>> = (0..n)
        .map(|b| {
            if b == entry {
                (0..n).map(|x| x == entry).collect()
            } else {
                vec![true; n]
            }
        })
        .collect();
    let mut changed = true;
    while changed {
        changed = false;
        for b in 0..n {
            if b == entry || !reach[b] {
                continue;
            }
            let mut new = vec![true; n];
            for &p in &preds[b] {
                for x in 0..n {
                    new[x] &= dom[p][x];
                }
            }
            new[b] = true;
            if new != dom[b] {
                dom[b] = new;
                changed = true;
            }
        }
    }
    (0..n).map(|b| reach[b].then(|| dom[b].clone())).collect()
}

#[test]
fn domtree_matches_the_naive_algorithm_on_random_cfgs() {
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    let mut rnd = |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    for _ in 0..300 {
        let n = 1 + rnd(14);
        let mut f = Function::new("f", FuncKind::Helper, vec![], None);
        let blocks: Vec<Block> = (0..n).map(|_| f.create_block()).collect();
        let c = f.create_inst(
            InstData::Iconst {
                ty: Type::I1,
                imm: 1,
            },
            Some(Type::I1),
            None,
        );
        let cv = f.result(c).unwrap();
        f.blocks[0].insts.push(c);
        let mut succ = vec![Vec::new(); n];
        for (i, &b) in blocks.iter().enumerate() {
            let data = match rnd(3) {
                0 => InstData::Return { value: None },
                1 => {
                    let t = rnd(n);
                    succ[i].push(t);
                    InstData::Jump {
                        dest: BlockCall::new(blocks[t], vec![]),
                    }
                }
                _ => {
                    let (t, e) = (rnd(n), rnd(n));
                    succ[i].push(t);
                    succ[i].push(e);
                    InstData::Brif {
                        cond: cv,
                        then_dest: BlockCall::new(blocks[t], vec![]),
                        else_dest: BlockCall::new(blocks[e], vec![]),
                    }
                }
            };
            let inst = f.create_inst(data, None, None);
            f.blocks[b.index()].insts.push(inst);
        }
        // A random layout order with block 0 first.
        let mut order: Vec<Block> = blocks[1..].to_vec();
        for i in (1..order.len()).rev() {
            order.swap(i, rnd(i + 1));
        }
        f.layout = std::iter::once(blocks[0]).chain(order).collect();
        let dt = DomTree::compute(&f);
        let naive = naive_dominators(&succ, 0);
        for a in 0..n {
            for b in 0..n {
                let want = a == b || naive[b].as_ref().is_some_and(|d| d[a]) && naive[a].is_some();
                assert_eq!(
                    dt.dominates(Block(a as u32), Block(b as u32)),
                    want,
                    "{a} dom {b}\n{succ:?}"
                );
            }
            assert_eq!(dt.is_reachable(Block(a as u32)), naive[a].is_some());
            // The immediate dominator is the strict dominator dominated by all others.
            if let Some(d) = &naive[a] {
                let strict: Vec<usize> = (0..n).filter(|&x| x != a && d[x]).collect();
                let idom = strict
                    .iter()
                    .copied()
                    .find(|&x| strict.iter().all(|&y| naive[x].as_ref().unwrap()[y]));
                assert_eq!(dt.idom(Block(a as u32)), idom.map(|x| Block(x as u32)));
                for &c in dt.children(Block(a as u32)) {
                    assert_eq!(dt.idom(c), Some(Block(a as u32)));
                }
            } else {
                assert_eq!(dt.idom(Block(a as u32)), None);
                assert!(dt.children(Block(a as u32)).is_empty());
            }
        }
        // Reverse postorder: the entry first, every block after its idom.
        let rpo = dt.rpo();
        assert_eq!(rpo.first(), Some(&Block(0)));
        for (i, &b) in rpo.iter().enumerate() {
            assert_eq!(dt.rpo_number(b), Some(i as u32));
            if let Some(d) = dt.idom(b) {
                assert!((dt.rpo_number(d).unwrap() as usize) < i);
            }
        }
        // The verifier agrees the function is valid.
        let m = Module::new();
        verify_function(&m, &f).unwrap();
    }
}

#[test]
fn domtree_of_a_deep_cfg() {
    // A chain of 100k blocks: no recursion anywhere.
    let mut f = Function::new("f", FuncKind::Helper, vec![], None);
    let n = 100_000;
    let blocks: Vec<Block> = (0..n).map(|_| f.create_block()).collect();
    for k in 0..n {
        let data = if k + 1 < n {
            InstData::Jump {
                dest: BlockCall::new(blocks[k + 1], vec![]),
            }
        } else {
            InstData::Return { value: None }
        };
        let i = f.create_inst(data, None, None);
        f.blocks[k].insts.push(i);
    }
    f.layout = blocks.clone();
    let dt = DomTree::compute(&f);
    assert!(dt.dominates(blocks[0], blocks[n - 1]));
    assert!(!dt.dominates(blocks[n - 1], blocks[0]));
    assert_eq!(dt.idom(blocks[n - 1]), Some(blocks[n - 2]));
    verify_function(&Module::new(), &f).unwrap();
}

#[test]
fn verifier_accepts_a_big_function() {
    let mut m = Module::new();
    let mut f = Function::new("big", FuncKind::Function, vec![Type::I32], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let mut acc = b.params()[0];
        let first = acc;
        for k in 0..50_000 {
            let c = b.iconst(Type::I32, k);
            acc = b.binary(BinaryOp::Iadd, acc, c);
            if k % 10 == 0 {
                let t = b.create_block();
                let e = b.create_block();
                let j = b.create_block();
                let jp = b.block_param(j, Type::I32);
                let cond = b.icmp(IntCC::Slt, acc, first);
                b.brif(cond, t, vec![], e, vec![]);
                b.switch_to(t);
                b.jump(j, vec![acc]);
                b.switch_to(e);
                let x = b.binary(BinaryOp::Isub, acc, first);
                b.jump(j, vec![x]);
                b.switch_to(j);
                acc = jp;
            }
        }
        b.ret(Some(acc));
    }
    m.add_func(f);
    // Its speed is measured by bench/bench.py with the rest of the pipeline.
    verify_module(&m).unwrap();
}

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
        let text = print_module(&m, &PrintOptions { locations: true });
        if let Err(errs) = &res {
            for e in errs {
                let _ = e.to_string();
            }
        }
        // A module that still verifies must still print and parse back.
        if res.is_ok() {
            let m2 = parse_module(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
            assert_eq!(print_module(&m2, &PrintOptions { locations: true }), text);
        }
    }
}
