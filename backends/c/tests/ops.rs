//! Every IR operation on every type, on the C machine (built with the
//! undefined-behaviour sanitizer) against the reference interpreter, with edge
//! operands: one module computes them all from two inputs per type each scan.

use plcc_c::{CMachine, Settings};
use plcc_ir::inst::{BinaryOp, ConvOp, FloatCC, IntCC, UnaryOp};
use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::text::parse_module;
use plcc_ir::value::PlcValue;
use plcc_ir::{ElemType, Module, Type};

const INTS: [(Type, ElemType); 4] = [
    (Type::I8, ElemType::SInt),
    (Type::I16, ElemType::Int),
    (Type::I32, ElemType::DInt),
    (Type::I64, ElemType::LInt),
];
const FLOATS: [(Type, ElemType); 2] = [(Type::F32, ElemType::Real), (Type::F64, ElemType::LReal)];

fn elem(ty: Type) -> ElemType {
    INTS.iter()
        .chain(&FLOATS)
        .find(|(t, _)| *t == ty)
        .map_or(ElemType::Bool, |(_, e)| *e)
}

/// The module: inputs `a_T`, `b_T` per type, one output field per operation.
struct Gen {
    fields: Vec<(String, Type)>,
    body: Vec<String>,
    next: usize,
}

impl Gen {
    fn val(&mut self) -> String {
        self.next += 1;
        format!("v{}", self.next)
    }
    fn load(&mut self, field: &str, ty: Type) -> String {
        let (a, x) = (self.val(), self.val());
        self.body
            .push(format!("{a} = field_addr v0, %main.{field}"));
        self.body.push(format!("{x} = load.{ty} {a}"));
        x
    }
    fn out(&mut self, name: String, ty: Type, inst: String) {
        let (r, a) = (self.val(), self.val());
        self.body.push(format!("{r} = {inst}"));
        self.body.push(format!("{a} = field_addr v0, %main.{name}"));
        self.body.push(format!("store {r}, {a}"));
        self.fields.push((name, ty));
    }
}

fn module() -> Module {
    let mut g = Gen {
        fields: Vec::new(),
        body: Vec::new(),
        next: 0,
    };
    for (ty, _) in INTS.iter().chain(&FLOATS) {
        g.fields.push((format!("a_{ty}"), *ty));
        g.fields.push((format!("b_{ty}"), *ty));
    }
    for (ty, _) in INTS.iter().chain(&FLOATS) {
        let ty = *ty;
        let a = g.load(&format!("a_{ty}"), ty);
        let b = g.load(&format!("b_{ty}"), ty);
        for op in BinaryOp::ALL {
            if op.is_int_op() == ty.is_int() {
                g.out(
                    format!("{}_{ty}", op.name()),
                    ty,
                    format!("{} {a}, {b}", op.name()),
                );
            }
        }
        for op in UnaryOp::ALL {
            if op.is_int_op() == ty.is_int() {
                g.out(
                    format!("{}_{ty}", op.name()),
                    ty,
                    format!("{} {a}", op.name()),
                );
            }
        }
        if ty.is_int() {
            for cc in IntCC::ALL {
                g.out(
                    format!("icmp_{}_{ty}", cc.name()),
                    Type::I1,
                    format!("icmp {} {a}, {b}", cc.name()),
                );
            }
            for (to, _) in INTS {
                let (op, n) = if to.bits() > ty.bits() {
                    (ConvOp::Sext, "sext")
                } else if to.bits() < ty.bits() {
                    (ConvOp::Itrunc, "itrunc")
                } else {
                    continue;
                };
                g.out(
                    format!("{n}_{ty}_{to}"),
                    to,
                    format!("{}.{to} {a}", op.name()),
                );
                if op == ConvOp::Sext {
                    g.out(format!("uext_{ty}_{to}"), to, format!("uext.{to} {a}"));
                }
            }
            g.out(format!("itrunc1_{ty}"), Type::I1, format!("itrunc.i1 {a}"));
            for (to, _) in FLOATS {
                g.out(format!("sitof_{ty}_{to}"), to, format!("sitof.{to} {a}"));
                g.out(format!("uitof_{ty}_{to}"), to, format!("uitof.{to} {a}"));
            }
        } else {
            for cc in FloatCC::ALL {
                g.out(
                    format!("fcmp_{}_{ty}", cc.name()),
                    Type::I1,
                    format!("fcmp {} {a}, {b}", cc.name()),
                );
            }
            for (to, _) in INTS {
                g.out(format!("ftosi_{ty}_{to}"), to, format!("ftosi.{to} {a}"));
                g.out(format!("ftoui_{ty}_{to}"), to, format!("ftoui.{to} {a}"));
            }
            let (other, conv) = if ty == Type::F32 {
                (Type::F64, "fpromote")
            } else {
                (Type::F32, "fdemote")
            };
            g.out(format!("{conv}_{ty}"), other, format!("{conv}.{other} {a}"));
            let int = if ty == Type::F32 {
                Type::I32
            } else {
                Type::I64
            };
            g.out(format!("bitcast_{ty}"), int, format!("bitcast.{int} {a}"));
        }
    }
    // The clock and the stop request.
    g.out("clock_ms".into(), Type::I32, "clock_ms".into());
    g.out("clock_ns".into(), Type::I64, "clock_ns".into());
    let fields: String = g
        .fields
        .iter()
        .map(|(n, t)| {
            let e = if *t == Type::I1 {
                ElemType::Bool
            } else {
                elem(*t)
            };
            format!("    var {n}: {t} {}\n", e.name())
        })
        .collect();
    let body: String = g.body.iter().map(|l| format!("    {l}\n")).collect();
    let text = format!(
        "struct %main program {{\n{fields}}}\n\ndata @main: %main program\n\n\
         func @main(ptr) program {{\nblock0(v0: ptr):\n{body}    return\n}}\n\n\
         func @main$init(ptr) init {{\nblock0(v0: ptr):\n    return\n}}\n\n\
         program \"main\" data @main body @main init @main$init\n"
    );
    parse_module(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn int_edges(ty: Type) -> Vec<i64> {
    let w = ty.bits();
    let min = if w == 64 {
        i64::MIN
    } else {
        -(1i64 << (w - 1))
    };
    let mut v = vec![
        0,
        1,
        -1,
        2,
        3,
        -7,
        min,
        !min,
        min + 1,
        w as i64,
        w as i64 - 1,
        200,
        12345,
    ];
    v.iter_mut().for_each(|x| *x = ty.canon_int(*x));
    v
}

fn float_edges() -> Vec<f64> {
    vec![
        0.0,
        -0.0,
        1.5,
        -2.5,
        0.5,
        -0.5,
        2.5,
        1e10,
        -1e10,
        3e9,
        -3e9,
        1e20,
        -1e20,
        255.5,
        65535.9,
        -129.0,
        2147483647.0,
        9.3e18,
        1.9e19,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        1e-310,
        // Ties and near-ties for rounding to nearest even, up to where every float
        // is an integer.
        3.5,
        -3.5,
        8388607.5,
        -8388606.5,
        4503599627370495.5,
        0.49999999999999994,
    ]
}

fn same(a: PlcValue, b: PlcValue) -> bool {
    match a.ty {
        ElemType::Real | ElemType::LReal if a.as_f64().is_nan() => b.as_f64().is_nan(),
        _ => a.ty == b.ty && a.bits == b.bits,
    }
}

#[test]
fn every_operation_agrees_with_the_interpreter() {
    let m = module();
    let settings = Settings {
        sanitize: "undefined".into(),
        ..Settings::default()
    };
    let mut c = CMachine::new(&m, &settings).unwrap_or_else(|d| panic!("{d:?}"));
    let mut i = Interp::new(&m).unwrap();
    c.cold_start().unwrap();
    i.cold_start().unwrap();
    let fields: Vec<(String, ElemType)> = match m.agg(plcc_ir::AggId::new(0)) {
        plcc_ir::AggDef::Struct(s) => s
            .fields
            .iter()
            .map(|f| (format!("main.{}", f.name), f.elem.unwrap()))
            .collect(),
        _ => unreachable!(),
    };
    let ints: Vec<Vec<i64>> = INTS.iter().map(|(t, _)| int_edges(*t)).collect();
    let floats = float_edges();
    let clocks = [
        0i64,
        1,
        999,
        1000,
        1500,
        -1,
        -1500,
        2_147_483_647_000,
        5_000_000_000_000,
        -9_000_000_000_000,
    ];
    let mut scans = 0;
    for ka in 0..floats.len().max(13) {
        for kb in 0..floats.len().max(13) {
            for (ty, e) in INTS.iter().chain(&FLOATS) {
                let pick = |k: usize| -> u64 {
                    if ty.is_int() {
                        let v = &ints[INTS.iter().position(|x| x.0 == *ty).unwrap()];
                        v[k % v.len()] as u64
                    } else if *ty == Type::F32 {
                        (floats[k % floats.len()] as f32).to_bits() as u64
                    } else {
                        floats[k % floats.len()].to_bits()
                    }
                };
                for (name, k) in [("a", ka), ("b", kb)] {
                    let v = PlcValue::from_bits(*e, pick(k));
                    let path = format!("main.{name}_{ty}");
                    c.write(&path, v).unwrap();
                    i.write(&path, v).unwrap();
                }
            }
            let t = clocks[(ka * 7 + kb) % clocks.len()];
            c.set_clock_us(t);
            i.set_clock_us(t);
            c.clear_fault();
            i.clear_fault();
            c.scan().unwrap();
            i.scan().unwrap();
            scans += 1;
            for (p, _) in &fields {
                let (x, y) = (c.read(p).unwrap(), i.read(p).unwrap());
                assert!(same(x, y), "scan {scans}: {p}: c {x}, interp {y}");
            }
            assert_eq!(c.fault(), i.fault(), "scan {scans}: fault flag");
        }
    }
    assert!(scans > 500);
}

/// Two machines of one module keep their memory apart (each loads its own copy of
/// the library).
#[test]
fn two_machines_of_one_module_are_apart() {
    let m = module();
    let s = Settings::default();
    let mut a = CMachine::new(&m, &s).unwrap();
    let mut b = CMachine::new(&m, &s).unwrap();
    a.cold_start().unwrap();
    b.cold_start().unwrap();
    a.write("main.a_i32", PlcValue::from_bits(ElemType::DInt, 5))
        .unwrap();
    b.write("main.a_i32", PlcValue::from_bits(ElemType::DInt, 7))
        .unwrap();
    assert_eq!(a.read("main.a_i32").unwrap().bits, 5);
    assert_eq!(b.read("main.a_i32").unwrap().bits, 7);
}
