//! The legalized module against the original on the reference interpreter, with edge
//! operands: same results, same fault flag; and probes that check that no guarded
//! operation sees an operand the target leaves undefined.

use super::{run, Defines, Widths};
use crate::entities::{DataId, Value};
use crate::function::Function;
use crate::inst::{BinaryOp, ConvOp, FloatCC, InstData, IntCC};
use crate::interp::Interp;
use crate::machine::Machine;
use crate::module::{DataDef, DataKind, Module};
use crate::text::parse_module;
use crate::types::{ElemType, MemType, Type};
use crate::verify::verify_module;

const INTS: [Type; 4] = [Type::I8, Type::I16, Type::I32, Type::I64];

fn int_edges(ty: Type) -> Vec<u64> {
    let w = ty.bits();
    let min = if w == 64 {
        i64::MIN
    } else {
        -(1i64 << (w - 1))
    };
    let max = if w == 64 {
        i64::MAX
    } else {
        (1i64 << (w - 1)) - 1
    };
    let mut v: Vec<i64> = vec![
        0,
        1,
        -1,
        2,
        -2,
        7,
        -7,
        min,
        max,
        min + 1,
        w as i64 - 1,
        w as i64,
        w as i64 + 1,
        127,
        128,
        255,
        256,
        100_000,
    ];
    v.iter_mut().for_each(|x| *x = ty.canon_int(*x));
    v.sort();
    v.dedup();
    v.into_iter().map(|x| x as u64).collect()
}

fn float_edges(ty: Type) -> Vec<u64> {
    let xs: [f64; 30] = [
        0.0,
        -0.0,
        0.5,
        -0.5,
        -0.999,
        -1.0,
        -1.5,
        1.0,
        127.9,
        128.0,
        -128.5,
        -129.0,
        255.9,
        256.0,
        32767.5,
        -32768.9,
        65535.5,
        65536.0,
        2147483647.0,
        2147483648.0,
        -2147483648.0,
        -2147483649.0,
        4294967295.5,
        9.2e18,
        9.3e18,
        -9.3e18,
        1.9e19,
        1e30,
        f64::INFINITY,
        f64::NAN,
    ];
    let mut out: Vec<u64> = xs
        .iter()
        .map(|&x| {
            if ty == Type::F32 {
                (x as f32).to_bits() as u64
            } else {
                x.to_bits()
            }
        })
        .collect();
    out.push(if ty == Type::F32 {
        f32::NEG_INFINITY.to_bits() as u64
    } else {
        f64::NEG_INFINITY.to_bits()
    });
    out
}

fn parse(text: &str) -> Module {
    let m = parse_module(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    verify_module(&m).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
    m
}

/// Adds `@bad: i32` and, before every operation the target leaves undefined, code
/// that sets `@bad` to 1 when the operation's operands are out of what the target
/// defines. Written independently of the pass.
fn add_probes(m: &mut Module, defines: &Defines) -> DataId {
    let bad = m.add_data(DataDef {
        name: "bad".into(),
        ty: MemType::Scalar(Type::I32),
        elem: Some(ElemType::DInt),
        kind: DataKind::Global,
        location: None,
    });
    for f in &mut m.funcs {
        let blocks = f.layout.clone();
        for b in blocks {
            let insts = f.blocks[b.index()].insts.clone();
            let mut out = Vec::new();
            for i in insts {
                let mut probe = Probe { f, out: &mut out };
                match *probe.f.inst(i) {
                    InstData::Binary { op, args: [x, d] } if op.can_fault() => {
                        let ty = probe.f.value_type(x);
                        let zero = probe.iconst(ty, 0);
                        let mut bad_if = Vec::new();
                        if !defines.div_by_zero {
                            bad_if.push(probe.icmp(IntCC::Eq, d, zero));
                        }
                        let w = ty.bits();
                        if !defines.min_div_neg1.contains(w)
                            && matches!(op, BinaryOp::Sdiv | BinaryOp::Srem)
                        {
                            let min = if w == 64 {
                                i64::MIN
                            } else {
                                -(1i64 << (w - 1))
                            };
                            let minv = probe.iconst(ty, min);
                            let m1 = probe.iconst(ty, -1);
                            let a = probe.icmp(IntCC::Eq, x, minv);
                            let b2 = probe.icmp(IntCC::Eq, d, m1);
                            bad_if.push(probe.bin(BinaryOp::Band, a, b2));
                        }
                        probe.flag(bad_if, bad);
                    }
                    InstData::Binary {
                        op: BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr,
                        args: [x, c],
                    } if !defines.shift_ge_width => {
                        let ty = probe.f.value_type(x);
                        let w = probe.iconst(ty, ty.bits() as i64);
                        let ge = probe.icmp(IntCC::Uge, c, w);
                        probe.flag(vec![ge], bad);
                    }
                    InstData::Convert {
                        op: op @ (ConvOp::FToSi | ConvOp::FToUi),
                        ty,
                        arg,
                    } if !defines.float_to_int_saturates => {
                        // The truncation must fit: trunc(x) in [min, max].
                        let fty = probe.f.value_type(arg);
                        let w = ty.bits() as i32;
                        let (lo, hi) = if op == ConvOp::FToSi {
                            (-(2f64.powi(w - 1)), 2f64.powi(w - 1))
                        } else {
                            (0.0, 2f64.powi(w))
                        };
                        let t = probe.val(
                            InstData::Unary {
                                op: crate::inst::UnaryOp::Ftrunc,
                                arg,
                            },
                            fty,
                        );
                        let lo = probe.fconst(fty, lo);
                        let hi = probe.fconst(fty, hi);
                        let a = probe.fcmp(FloatCC::Ge, t, lo);
                        let b2 = probe.fcmp(FloatCC::Lt, t, hi);
                        let ok = probe.bin(BinaryOp::Band, a, b2);
                        let t1 = probe.iconst(Type::I1, 1);
                        let not_ok = probe.bin(BinaryOp::Bxor, ok, t1);
                        probe.flag(vec![not_ok], bad);
                    }
                    _ => {}
                }
                out.push(i);
            }
            f.blocks[b.index()].insts = out;
        }
    }
    bad
}

struct Probe<'a> {
    f: &'a mut Function,
    out: &'a mut Vec<crate::entities::Inst>,
}

impl Probe<'_> {
    fn val(&mut self, data: InstData, ty: Type) -> Value {
        let i = self.f.create_inst(data, Some(ty), None);
        self.out.push(i);
        self.f.result(i).unwrap()
    }
    fn iconst(&mut self, ty: Type, imm: i64) -> Value {
        self.val(
            InstData::Iconst {
                ty,
                imm: ty.canon_int(imm),
            },
            ty,
        )
    }
    fn fconst(&mut self, ty: Type, x: f64) -> Value {
        let bits = if ty == Type::F32 {
            (x as f32).to_bits() as u64
        } else {
            x.to_bits()
        };
        self.val(InstData::Fconst { ty, bits }, ty)
    }
    fn icmp(&mut self, cond: IntCC, a: Value, b: Value) -> Value {
        self.val(InstData::Icmp { cond, args: [a, b] }, Type::I1)
    }
    fn fcmp(&mut self, cond: FloatCC, a: Value, b: Value) -> Value {
        self.val(InstData::Fcmp { cond, args: [a, b] }, Type::I1)
    }
    fn bin(&mut self, op: BinaryOp, a: Value, b: Value) -> Value {
        let ty = self.f.value_type(a);
        self.val(InstData::Binary { op, args: [a, b] }, ty)
    }
    /// `@bad |= any(conds)`.
    fn flag(&mut self, conds: Vec<Value>, bad: DataId) {
        let Some(mut c) = conds.first().copied() else {
            return;
        };
        for &d in &conds[1..] {
            c = self.bin(BinaryOp::Bor, c, d);
        }
        let addr = self.val(InstData::GlobalAddr { data: bad }, Type::Ptr);
        let old = self.val(
            InstData::Load {
                ty: Type::I32,
                addr,
            },
            Type::I32,
        );
        let x = self.val(
            InstData::Convert {
                op: ConvOp::Uext,
                ty: Type::I32,
                arg: c,
            },
            Type::I32,
        );
        let new = self.bin(BinaryOp::Bor, old, x);
        let st = self
            .f
            .create_inst(InstData::Store { value: new, addr }, None, None);
        self.out.push(st);
    }
}

/// Runs `@f` of `text` on every combination of `operands` before and after
/// legalizing with `defines`: same result, same fault; the probes never fire.
fn agree(text: &str, defines: Defines, operands: &[Vec<u64>]) -> usize {
    let original = parse(text);
    let mut legal = original.clone();
    run(&mut legal, &defines);
    verify_module(&legal).unwrap_or_else(|e| {
        panic!(
            "legalized module does not verify: {e:?}\n{}",
            crate::text::print_module(&legal, &Default::default())
        )
    });
    let bad = add_probes(&mut legal, &defines);
    verify_module(&legal).expect("probes verify");
    let mut a = Interp::new(&original).unwrap();
    let mut b = Interp::new(&legal).unwrap();
    let f = original.func_by_name("f").unwrap();
    let bad_name = legal.data[bad.index()].name.clone();
    // Every combination of operands.
    let mut idx = vec![0usize; operands.len()];
    let mut count = 0;
    loop {
        let args: Vec<u64> = idx.iter().zip(operands).map(|(&i, o)| o[i]).collect();
        a.clear_fault();
        b.clear_fault();
        b.write(
            &bad_name,
            crate::value::PlcValue::from_bits(ElemType::DInt, 0),
        )
        .unwrap();
        let ra = a.call(f, &args).unwrap();
        let rb = b.call(f, &args).unwrap();
        let same = match (ra, rb) {
            (Some(x), Some(y)) => x == y || (is_nan(text, x) && is_nan(text, y)),
            (x, y) => x == y,
        };
        assert!(
            same,
            "{text}\nargs {args:x?}: original {ra:x?}, legalized {rb:x?}"
        );
        assert_eq!(a.fault(), b.fault(), "{text}\nargs {args:x?}: fault flag");
        assert_eq!(
            b.read(&bad_name).unwrap().bits,
            0,
            "{text}\nargs {args:x?}: a guarded operation saw an undefined operand"
        );
        count += 1;
        // Next combination.
        let mut k = 0;
        loop {
            if k == idx.len() {
                return count;
            }
            idx[k] += 1;
            if idx[k] < operands[k].len() {
                break;
            }
            idx[k] = 0;
            k += 1;
        }
    }
}

fn is_nan(text: &str, bits: u64) -> bool {
    if text.contains("-> f32") {
        f32::from_bits(bits as u32).is_nan()
    } else {
        text.contains("-> f64") && f64::from_bits(bits).is_nan()
    }
}

const SOME: [Defines; 5] = [
    Defines::NONE,
    Defines {
        div_by_zero: true,
        ..Defines::NONE
    },
    Defines {
        min_div_neg1: Widths::ALL,
        ..Defines::NONE
    },
    // As vmasm on a port with a 32-bit `int`: SINT and INT are promoted, LINT
    // divided by magnitudes.
    Defines {
        min_div_neg1: Widths::of(&[8, 16, 64]),
        ..Defines::NONE
    },
    Defines::ALL,
];

#[test]
fn divisions_agree_with_the_interpreter() {
    let mut n = 0;
    for ty in INTS {
        for op in ["sdiv", "srem", "udiv", "urem"] {
            // The division's result used after it in the same block, and a second
            // division in the rest (which the pass visits after splitting).
            let text = format!(
                "func @f({ty}, {ty}) -> {ty} function {{\n\
                 block0(v0: {ty}, v1: {ty}):\n    \
                 v2 = {op} v0, v1\n    \
                 v3 = iadd v2, v0\n    \
                 v4 = {op} v3, v1\n    \
                 v5 = bxor v4, v2\n    \
                 return v5\n}}\n"
            );
            let e = int_edges(ty);
            for d in SOME {
                n += agree(&text, d, &[e.clone(), e.clone()]);
            }
        }
    }
    assert!(n > 10_000);
}

#[test]
fn divisions_by_constants() {
    for ty in INTS {
        for op in ["sdiv", "srem", "udiv", "urem"] {
            for c in [0i64, -1, 1, 3, -7] {
                let text = format!(
                    "func @f({ty}) -> {ty} function {{\n\
                     block0(v0: {ty}):\n    \
                     v1 = iconst.{ty} {c}\n    \
                     v2 = {op} v0, v1\n    \
                     return v2\n}}\n"
                );
                agree(&text, Defines::NONE, &[int_edges(ty)]);
            }
        }
    }
}

#[test]
fn division_in_a_loop_and_in_a_branch() {
    // The block split by the guard has a loop back edge and block arguments.
    let text = "func @f(i32, i32) -> i32 function {\n\
block0(v0: i32, v1: i32):\n    \
v2 = iconst.i32 3\n    \
jump block1(v0, v2)\n\n\
block1(v3: i32, v4: i32):\n    \
v5 = sdiv v3, v1\n    \
v6 = iconst.i32 1\n    \
v7 = isub v4, v6\n    \
v8 = iconst.i32 0\n    \
v9 = icmp sgt v7, v8\n    \
brif v9, block1(v5, v7), block2\n\n\
block2:\n    \
v10 = srem v5, v1\n    \
return v10\n}\n";
    let e = int_edges(Type::I32);
    for d in SOME {
        agree(text, d, &[e.clone(), e.clone()]);
    }
}

#[test]
fn shifts_agree_with_the_interpreter() {
    for ty in INTS {
        for op in ["ishl", "ushr", "sshr", "rotl", "rotr"] {
            let text = format!(
                "func @f({ty}, {ty}) -> {ty} function {{\n\
                 block0(v0: {ty}, v1: {ty}):\n    \
                 v2 = {op} v0, v1\n    \
                 return v2\n}}\n"
            );
            let e = int_edges(ty);
            agree(&text, Defines::NONE, &[e.clone(), e.clone()]);
            for c in [0, 1, ty.bits() as i64 - 1, ty.bits() as i64, 200, -1] {
                let text = format!(
                    "func @f({ty}) -> {ty} function {{\n\
                     block0(v0: {ty}):\n    \
                     v1 = iconst.{ty} {}\n    \
                     v2 = {op} v0, v1\n    \
                     return v2\n}}\n",
                    ty.canon_int(c)
                );
                agree(&text, Defines::NONE, std::slice::from_ref(&e));
            }
        }
    }
}

#[test]
fn float_to_int_agrees_with_the_interpreter() {
    for fty in [Type::F32, Type::F64] {
        for ty in INTS {
            for op in ["ftosi", "ftoui"] {
                let text = format!(
                    "func @f({fty}) -> {ty} function {{\n\
                     block0(v0: {fty}):\n    \
                     v1 = {op}.{ty} v0\n    \
                     return v1\n}}\n"
                );
                agree(&text, Defines::NONE, &[float_edges(fty)]);
            }
        }
    }
}

#[test]
fn a_target_that_defines_everything_is_left_alone() {
    let text = "func @f(i32, i32) -> i32 function {\n\
block0(v0: i32, v1: i32):\n    \
v2 = sdiv v0, v1\n    \
v3 = ishl v2, v1\n    \
return v3\n}\n";
    let mut m = parse(text);
    assert!(!run(&mut m, &Defines::ALL));
    assert_eq!(m, parse(text));
    assert!(run(&mut m, &Defines::NONE));
}

/// The probes are not vacuous: without the pass they fire on the same operands.
#[test]
fn probes_fire_without_the_pass() {
    let cases = [
        ("sdiv.i32", "v2 = sdiv v0, v1", [5u64, 0]),
        ("sdiv MIN", "v2 = sdiv v0, v1", [i32::MIN as u64, u64::MAX]),
        ("ishl", "v2 = ishl v0, v1", [1, 32]),
    ];
    for (what, inst, args) in cases {
        let text = format!(
            "func @f(i32, i32) -> i32 function {{\nblock0(v0: i32, v1: i32):\n    {inst}\n    return v2\n}}\n"
        );
        let mut m = parse(&text);
        let bad = add_probes(&mut m, &Defines::NONE);
        let mut i = Interp::new(&m).unwrap();
        let name = m.data[bad.index()].name.clone();
        i.write(&name, crate::value::PlcValue::from_bits(ElemType::DInt, 0))
            .unwrap();
        i.call(m.func_by_name("f").unwrap(), &args).unwrap();
        assert_eq!(i.read(&name).unwrap().bits, 1, "{what}");
    }
    let text =
        "func @f(f64) -> i8 function {\nblock0(v0: f64):\n    v1 = ftosi.i8 v0\n    return v1\n}\n";
    let mut m = parse(text);
    let bad = add_probes(&mut m, &Defines::NONE);
    let mut i = Interp::new(&m).unwrap();
    let name = m.data[bad.index()].name.clone();
    i.write(&name, crate::value::PlcValue::from_bits(ElemType::DInt, 0))
        .unwrap();
    i.call(m.func_by_name("f").unwrap(), &[300f64.to_bits()])
        .unwrap();
    assert_eq!(i.read(&name).unwrap().bits, 1, "ftosi");
}

/// What a rewrite leaves unused goes: a constant zero divisor keeps only the fault,
/// not the computation of the dividend nobody reads any more.
#[test]
fn what_the_guards_leave_unused_is_removed() {
    let text = "func @f(i32) -> i32 function {\n\
block0(v0: i32):\n    \
v1 = iconst.i32 3\n    \
v2 = iadd v0, v1\n    \
v3 = iconst.i32 0\n    \
v4 = srem v2, v3\n    \
return v4\n}\n";
    let mut m = parse(text);
    assert!(run(&mut m, &Defines::NONE));
    let f = m.func_by_name("f").unwrap();
    let f = m.func(f);
    let ops: Vec<String> = f
        .inst_iter()
        .map(|(_, i)| format!("{:?}", f.inst(i)))
        .collect();
    assert!(
        ops.iter().any(|o| o.contains("RaiseFault")),
        "the fault stays: {ops:?}"
    );
    assert!(
        !ops.iter().any(|o| o.contains("Iadd") || o.contains("Srem")),
        "the dividend goes: {ops:?}"
    );
    agree(text, Defines::NONE, &[int_edges(Type::I32)]);
}
