//! The JIT as a machine: cold start, state across scans, the clock, variable paths,
//! memory (slots, nested aggregates), control flow and calls; compared with the
//! interpreter throughout.

mod common;

use common::{agg_field, field, ld, st, val, Pair, Prog};
use plcc_ir::machine::Machine;
use plcc_ir::{
    AggDef, ArrayDef, BinaryOp, ConvOp, DataDef, DataKind, ElemType, FieldRole, FuncKind, Function,
    IntCC, Intrinsic, MemType, PlcValue, StructDef, StructKind, Type,
};
use plcc_native::Jit;

#[test]
fn counter_keeps_its_state_across_scans_and_cold_start_resets_it() {
    let p = Prog::new(vec![field("count", Type::I16)]);
    let fc = p.f("count");
    let m = p.finish(|b, inst, agg| {
        let c = ld(b, inst, agg, fc, Type::I16);
        let one = b.iconst(Type::I16, 1);
        let n = b.binary(BinaryOp::Iadd, c, one);
        st(b, n, inst, agg, fc);
    });
    let mut p = Pair::new(m);
    assert_eq!(p.read("main.count").as_i64(), 0);
    for i in 1..=5 {
        p.scan();
        assert_eq!(p.read("MAIN.Count").as_i64(), i);
    }
    p.write("main.count", PlcValue::from_i64(ElemType::Int, 32767));
    p.scan();
    assert_eq!(p.read("main.count").as_i64(), -32768);
    p.cold_start();
    assert_eq!(p.read("main.count").as_i64(), 0);
}

#[test]
fn clock_is_sampled_in_ms_and_ns() {
    let p = Prog::new(vec![field("ms", Type::I32), field("ns", Type::I64)]);
    let (fm, fnn) = (p.f("ms"), p.f("ns"));
    let m = p.finish(|b, inst, agg| {
        let ms = b.intrinsic(Intrinsic::ClockMs, vec![]).unwrap();
        st(b, ms, inst, agg, fm);
        let ns = b.intrinsic(Intrinsic::ClockNs, vec![]).unwrap();
        st(b, ns, inst, agg, fnn);
    });
    let mut p = Pair::new(m);
    for us in [
        0i64,
        999,
        1000,
        1_500_000,
        -1,
        -1500,
        3_000_000_000_000,
        i64::MAX / 1000,
    ] {
        p.set_clock_us(us);
        p.scan();
        assert_eq!(
            p.read("main.ms").as_i64(),
            us.div_euclid(1000) as i32 as i64
        );
        assert_eq!(p.read("main.ns").as_i64(), us.wrapping_mul(1000));
    }
    p.cold_start();
    p.scan();
    assert_eq!(p.read("main.ms").as_i64(), 0);
}

#[test]
fn raise_fault_and_clear() {
    let p = Prog::new(vec![field("x", Type::I1)]);
    let fx = p.f("x");
    let m = p.finish(|b, inst, agg| {
        let x = ld(b, inst, agg, fx, Type::I1);
        let then = b.create_block();
        let done = b.create_block();
        b.brif(x, then, vec![], done, vec![]);
        b.switch_to(then);
        b.intrinsic(Intrinsic::RaiseFault, vec![]);
        b.jump(done, vec![]);
        b.switch_to(done);
    });
    let mut p = Pair::new(m);
    p.scan();
    assert!(!p.fault());
    p.write("main.x", PlcValue::from_bool(true));
    p.scan();
    assert!(p.fault());
    p.clear_fault();
    assert!(!p.fault());
    p.scan();
    assert!(p.fault());
    p.cold_start();
    assert!(!p.fault());
}

#[test]
fn nested_aggregates_arrays_and_paths() {
    let mut p = Prog::new(vec![]);
    // struct %pt { x: i16 INT, y: f64 LREAL, ok: i1 BOOL }
    let pt = p.module.add_agg(AggDef::Struct(StructDef {
        name: "pt".into(),
        kind: StructKind::Struct,
        fields: vec![
            field("x", Type::I16),
            field("y", Type::F64),
            field("ok", Type::I1),
        ],
    }));
    // array %row = [3 x %pt] lower 1 ; array %grid = [4 x %row] lower -2
    let row = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "row".into(),
        elem: MemType::Agg(pt),
        elem_type: None,
        len: 3,
        lower: 1,
    }));
    let grid = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "grid".into(),
        elem: MemType::Agg(row),
        elem_type: None,
        len: 4,
        lower: -2,
    }));
    let bytes = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "bytes".into(),
        elem: MemType::Scalar(Type::I8),
        elem_type: Some(ElemType::Byte),
        len: 5,
        lower: 0,
    }));
    if let AggDef::Struct(s) = &mut p.module.aggs[p.agg.index()] {
        s.fields = vec![
            field("i", Type::I32),
            field("j", Type::I8),
            agg_field("g", grid),
            agg_field("b", bytes),
            field("sum", Type::F64),
        ];
    }
    let (fi, fj, fg, fb, fs) = (p.f("i"), p.f("j"), p.f("g"), p.f("b"), p.f("sum"));
    let agg = p.agg;
    let init_fill = move |b: &mut plcc_ir::FuncBuilder, inst, agg| {
        // Every element of g and b zeroed by loops written out (small sizes).
        let g = b.field_addr(inst, agg, fg);
        for r in 0..4 {
            let ri = b.iconst(Type::I64, r);
            let rowp = b.elem_addr(g, grid, ri);
            for c in 0..3 {
                let ci = b.iconst(Type::I16, c);
                let e = b.elem_addr(rowp, row, ci);
                let z16 = b.iconst(Type::I16, 0);
                let a = b.field_addr(e, pt, 0);
                b.store(z16, a);
                let zf = b.f64const(0.0);
                let a = b.field_addr(e, pt, 1);
                b.store(zf, a);
                let zb = b.iconst(Type::I1, 0);
                let a = b.field_addr(e, pt, 2);
                b.store(zb, a);
            }
        }
        let bp = b.field_addr(inst, agg, fb);
        for k in 0..5 {
            let ki = b.iconst(Type::I8, k);
            let e = b.elem_addr(bp, bytes, ki);
            let z = b.iconst(Type::I8, 0);
            b.store(z, e);
        }
    };
    let _ = agg;
    let m = p.finish_with(
        move |b, inst, agg| {
            // g[i][j].x += 1; g[i][j].y += 0.5; g[i][j].ok := NOT ok; b[j] := i;
            // sum := g[i][j].y
            let i = ld(b, inst, agg, fi, Type::I32);
            let j = ld(b, inst, agg, fj, Type::I8);
            let g = b.field_addr(inst, agg, fg);
            let rp = b.elem_addr(g, grid, i);
            let e = b.elem_addr(rp, row, j);
            let xa = b.field_addr(e, pt, 0);
            let x = b.load(Type::I16, xa);
            let one = b.iconst(Type::I16, 1);
            let x1 = b.binary(BinaryOp::Iadd, x, one);
            b.store(x1, xa);
            let ya = b.field_addr(e, pt, 1);
            let y = b.load(Type::F64, ya);
            let h = b.f64const(0.5);
            let y1 = b.binary(BinaryOp::Fadd, y, h);
            b.store(y1, ya);
            let oka = b.field_addr(e, pt, 2);
            let ok = b.load(Type::I1, oka);
            let nok = b.unary(plcc_ir::UnaryOp::Bnot, ok);
            b.store(nok, oka);
            let bp = b.field_addr(inst, agg, fb);
            let be = b.elem_addr(bp, bytes, j);
            let i8v = b.convert(ConvOp::Itrunc, Type::I8, i);
            b.store(i8v, be);
            st(b, y1, inst, agg, fs);
        },
        init_fill,
    );
    let mut p = Pair::new(m);
    p.write("main.i", PlcValue::from_i64(ElemType::DInt, 2));
    p.write("main.j", PlcValue::from_i64(ElemType::SInt, 1));
    p.scan();
    p.scan();
    p.write("main.i", PlcValue::from_i64(ElemType::DInt, 3));
    p.write("main.j", PlcValue::from_i64(ElemType::SInt, 2));
    p.scan();
    p.compare_all();
    // Source indexes: grid lower -2, row lower 1.
    assert_eq!(p.read("main.g[0][2].x").as_i64(), 2);
    assert_eq!(p.read("main.g[0,2].y").as_f64(), 1.0);
    assert!(!p.read("main.g[0][2].ok").as_bool());
    assert!(p.read("main.g[1][3].ok").as_bool());
    assert_eq!(p.read("main.b[2]").bits, 3);
    assert_eq!(p.read("main.b[1]").bits, 2);
    assert_eq!(p.read("main.sum").as_f64(), 0.5);
    // Writes reach the code.
    p.write("main.g[1][3].y", PlcValue::from_f64(10.0));
    p.scan();
    assert_eq!(p.read("main.sum").as_f64(), 10.5);
    // Errors.
    assert!(p.jit.read("main.g[2][1].x").is_err());
    assert!(p.jit.read("main.nope").is_err());
    assert!(p
        .jit
        .write("main.i", PlcValue::from_i64(ElemType::Int, 1))
        .is_err());
    assert!(p.jit.write("main.sum", PlcValue::from_f32(1.0)).is_err());
}

#[test]
fn stack_slots_of_scalars_and_aggregates() {
    let mut p = Prog::new(vec![
        field("a", Type::I32),
        field("r", Type::I32),
        field("s", Type::F64),
    ]);
    let arr = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "arr".into(),
        elem: MemType::Scalar(Type::F64),
        elem_type: Some(ElemType::LReal),
        len: 4,
        lower: 0,
    }));
    // swap(p: ptr, q: ptr): exchanges two i32 through pointers.
    let swap = p.func("swap", vec![Type::Ptr, Type::Ptr], None, |b, ps| {
        let x = b.load(Type::I32, ps[0]);
        let y = b.load(Type::I32, ps[1]);
        b.store(y, ps[0]);
        b.store(x, ps[1]);
        b.ret(None);
    });
    let (fa, fr, fs) = (p.f("a"), p.f("r"), p.f("s"));
    let m = p.finish(|b, inst, agg| {
        let s0 = b.slot("t0", MemType::Scalar(Type::I32));
        let s1 = b.slot("t1", MemType::Scalar(Type::I32));
        let s2 = b.slot("v", MemType::Agg(arr));
        let a0 = b.slot_addr(s0);
        let a1 = b.slot_addr(s1);
        let a = ld(b, inst, agg, fa, Type::I32);
        b.store(a, a0);
        let k = b.iconst(Type::I32, 77);
        b.store(k, a1);
        b.call(swap, None, vec![a0, a1]);
        let r = b.load(Type::I32, a0);
        st(b, r, inst, agg, fr);
        // v[i] := i * 1.5, s := sum
        let va = b.slot_addr(s2);
        let mut sum = b.f64const(0.0);
        for i in 0..4 {
            let idx = b.iconst(Type::I16, i);
            let e = b.elem_addr(va, arr, idx);
            let x = b.f64const(i as f64 * 1.5);
            b.store(x, e);
        }
        for i in 0..4 {
            let idx = b.iconst(Type::I64, i);
            let e = b.elem_addr(va, arr, idx);
            let x = b.load(Type::F64, e);
            sum = b.binary(BinaryOp::Fadd, sum, x);
        }
        st(b, sum, inst, agg, fs);
    });
    let mut p = Pair::new(m);
    p.write("main.a", PlcValue::from_i64(ElemType::DInt, -5));
    p.scan();
    assert_eq!(p.read("main.r").as_i64(), 77);
    assert_eq!(p.read("main.s").as_f64(), 9.0);
}

#[test]
fn block_params_with_swapped_arguments() {
    // Fibonacci-like loop passing (b, a+b) and a swap of (x, y) -> (y, x) each round.
    let p = Prog::new(vec![
        field("n", Type::I32),
        field("x", Type::I64),
        field("y", Type::I64),
    ]);
    let (fnn, fx, fy) = (p.f("n"), p.f("x"), p.f("y"));
    let m = p.finish(|b, inst, agg| {
        let n = ld(b, inst, agg, fnn, Type::I32);
        let x0 = b.iconst(Type::I64, 1);
        let y0 = b.iconst(Type::I64, 2);
        let i0 = b.iconst(Type::I32, 0);
        let head = b.create_block();
        let body = b.create_block();
        let exit = b.create_block();
        let hi = b.block_param(head, Type::I32);
        let hx = b.block_param(head, Type::I64);
        let hy = b.block_param(head, Type::I64);
        let ex = b.block_param(exit, Type::I64);
        let ey = b.block_param(exit, Type::I64);
        b.jump(head, vec![i0, x0, y0]);
        b.switch_to(head);
        let c = b.icmp(IntCC::Slt, hi, n);
        b.brif(c, body, vec![], exit, vec![hx, hy]);
        b.switch_to(body);
        let one = b.iconst(Type::I32, 1);
        let i1 = b.binary(BinaryOp::Iadd, hi, one);
        // swap on odd rounds only via select-free control: (y, x)
        b.jump(head, vec![i1, hy, hx]);
        b.switch_to(exit);
        st(b, ex, inst, agg, fx);
        st(b, ey, inst, agg, fy);
    });
    let mut p = Pair::new(m);
    for n in 0..6 {
        p.write("main.n", PlcValue::from_i64(ElemType::DInt, n));
        p.scan();
        let (x, y) = if n % 2 == 0 { (1, 2) } else { (2, 1) };
        assert_eq!(p.read("main.x").as_i64(), x);
        assert_eq!(p.read("main.y").as_i64(), y);
    }
}

#[test]
fn loop_back_to_the_entry_block_and_layout_out_of_dominance_order() {
    let mut p = Prog::new(vec![field("n", Type::I32), field("r", Type::I32)]);
    // sum(n, acc): entry block is a loop header (branch target).
    let mut f = Function::new(
        "sum",
        FuncKind::Function,
        vec![Type::I32, Type::I32],
        Some(Type::I32),
    );
    {
        let mut b = plcc_ir::FuncBuilder::new(&mut f);
        let ps = b.params();
        let done = b.create_block();
        let more = b.create_block();
        // Placed in the layout before `more` defines what it uses? `done` uses only
        // its parameter; `more` is placed last.
        let z = b.iconst(Type::I32, 0);
        let c = b.icmp(IntCC::Sle, ps[0], z);
        b.brif(c, done, vec![ps[1]], more, vec![]);
        let dr = b.block_param(done, Type::I32);
        b.switch_to(done);
        b.ret(Some(dr));
        b.switch_to(more);
        let acc = b.binary(BinaryOp::Iadd, ps[1], ps[0]);
        let one = b.iconst(Type::I32, 1);
        let n1 = b.binary(BinaryOp::Isub, ps[0], one);
        let entry = b.func.layout[0];
        b.jump(entry, vec![n1, acc]);
    }
    // Move `more` before `done` in the layout: still valid, now `done` comes last.
    f.layout.swap(1, 2);
    // An unreachable block using a value defined nowhere reachable.
    let sum = p.module.add_func(f);
    let (fnn, fr) = (p.f("n"), p.f("r"));
    let m = p.finish(|b, inst, agg| {
        let n = ld(b, inst, agg, fnn, Type::I32);
        let z = b.iconst(Type::I32, 0);
        let r = b.call(sum, Some(Type::I32), vec![n, z]).unwrap();
        st(b, r, inst, agg, fr);
    });
    let mut p = Pair::new(m);
    for n in [0, 1, 5, 100] {
        p.write("main.n", PlcValue::from_i64(ElemType::DInt, n));
        p.scan();
        assert_eq!(p.read("main.r").as_i64(), n * (n + 1) / 2);
    }
}

#[test]
fn calls_extend_narrow_arguments_and_results() {
    let mut p = Prog::new(vec![
        field("a8", Type::I8),
        field("a16", Type::I16),
        field("c", Type::I1),
        field("r", Type::I64),
        field("n8", Type::I8),
        field("nb", Type::I1),
    ]);
    // widen(a: i8, b: i16, c: i1) -> i64 = sext(a) + uext(b) + uext(c)
    let widen = p.func(
        "widen",
        vec![Type::I8, Type::I16, Type::I1],
        Some(Type::I64),
        |b, ps| {
            let a = b.convert(ConvOp::Sext, Type::I64, ps[0]);
            let bb = b.convert(ConvOp::Uext, Type::I64, ps[1]);
            let c = b.convert(ConvOp::Uext, Type::I64, ps[2]);
            let s = b.binary(BinaryOp::Iadd, a, bb);
            let s = b.binary(BinaryOp::Iadd, s, c);
            b.ret(Some(s));
        },
    );
    // neg8(a: i8) -> i8 ; not1(c: i1) -> i1
    let neg8 = p.func("neg8", vec![Type::I8], Some(Type::I8), |b, ps| {
        let r = b.unary(plcc_ir::UnaryOp::Ineg, ps[0]);
        b.ret(Some(r));
    });
    let not1 = p.func("not1", vec![Type::I1], Some(Type::I1), |b, ps| {
        let r = b.unary(plcc_ir::UnaryOp::Bnot, ps[0]);
        b.ret(Some(r));
    });
    let (f8, f16, fc, fr, fn8, fnb) = (
        p.f("a8"),
        p.f("a16"),
        p.f("c"),
        p.f("r"),
        p.f("n8"),
        p.f("nb"),
    );
    let m = p.finish(|b, inst, agg| {
        let a = ld(b, inst, agg, f8, Type::I8);
        let x = ld(b, inst, agg, f16, Type::I16);
        let c = ld(b, inst, agg, fc, Type::I1);
        let r = b.call(widen, Some(Type::I64), vec![a, x, c]).unwrap();
        st(b, r, inst, agg, fr);
        let n = b.call(neg8, Some(Type::I8), vec![a]).unwrap();
        // Use the narrow result in a wide context: sext to i64 and compare.
        let n64 = b.convert(ConvOp::Sext, Type::I64, n);
        let z = b.iconst(Type::I64, 0);
        let _ = b.icmp(IntCC::Slt, n64, z);
        st(b, n, inst, agg, fn8);
        let nb = b.call(not1, Some(Type::I1), vec![c]).unwrap();
        st(b, nb, inst, agg, fnb);
    });
    let mut p = Pair::new(m);
    for (a, x, c) in [
        (-1i64, 65535u64, 1u64),
        (127, 0, 0),
        (-128, 32768, 1),
        (5, 7, 0),
    ] {
        p.write("main.a8", PlcValue::from_i64(ElemType::SInt, a));
        p.write("main.a16", val(Type::I16, x));
        p.write("main.c", PlcValue::from_bool(c != 0));
        p.scan();
        assert_eq!(p.read("main.r").as_i64(), a + x as i64 + c as i64);
        assert_eq!(p.read("main.n8").as_i64(), (a as i8).wrapping_neg() as i64);
        assert_eq!(p.read("main.nb").bits, 1 - c);
    }
}

#[test]
fn globals_init_globals_and_two_programs() {
    // A global counter g shared by two programs; init_globals sets it to 10.
    let mut p = Prog::new(vec![field("seen", Type::I32)]);
    let g = p.module.add_data(DataDef {
        name: "g".into(),
        ty: MemType::Scalar(Type::I32),
        elem: Some(ElemType::DInt),
        kind: DataKind::Global,
        location: Some("%MD4".into()),
    });
    let mut f = Function::new("globals$init", FuncKind::Init, vec![], None);
    {
        let mut b = plcc_ir::FuncBuilder::new(&mut f);
        let a = b.global_addr(g);
        let v = b.iconst(Type::I32, 10);
        b.store(v, a);
        b.ret(None);
    }
    let gi = p.module.add_func(f);
    p.module.init_globals = Some(gi);
    let fs = p.f("seen");
    let mut m = p.finish(|b, inst, agg| {
        let a = b.global_addr(g);
        let v = b.load(Type::I32, a);
        let one = b.iconst(Type::I32, 1);
        let v1 = b.binary(BinaryOp::Iadd, v, one);
        b.store(v1, a);
        st(b, v1, inst, agg, fs);
    });
    // A second instance of the same program type.
    let d2 = m.add_data(DataDef {
        name: "second".into(),
        ty: MemType::Agg(plcc_ir::AggId::new(0)),
        elem: None,
        kind: DataKind::Program,
        location: None,
    });
    let mut e = m.programs[0].clone();
    e.name = "second".into();
    e.data = d2;
    m.programs.push(e);
    let mut p = Pair::new(m);
    assert_eq!(p.read("g").as_i64(), 10);
    p.scan();
    assert_eq!(p.read("main.seen").as_i64(), 11);
    assert_eq!(p.read("second.seen").as_i64(), 12);
    p.write("g", PlcValue::from_i64(ElemType::DInt, -3));
    p.scan();
    assert_eq!(p.read("second.seen").as_i64(), -1);
    p.cold_start();
    assert_eq!(p.read("g").as_i64(), 10);
}

#[test]
fn cold_start_fills_memory_with_garbage_first() {
    // An init that forgets a field leaves the garbage pattern, on both machines.
    let mut p = Prog::new(vec![field("set", Type::I32)]);
    if let AggDef::Struct(s) = &mut p.module.aggs[0] {
        s.fields.push(plcc_ir::Field {
            name: "forgot".into(),
            ty: MemType::Scalar(Type::I32),
            elem: Some(ElemType::DWord),
            role: FieldRole::Var,
            location: None,
        });
    }
    let m = p.finish(|_, _, _| {});
    // The common init zeroes every scalar field: undo that for `forgot`.
    let mut m = m;
    let init = m.programs[0].init;
    let f = m.func_mut(init);
    let entry = f.layout[0];
    // Keep `set`'s iconst, field_addr and store, then the return.
    let ret = *f.blocks[entry.index()].insts.last().unwrap();
    f.blocks[entry.index()].insts.truncate(3);
    f.blocks[entry.index()].insts.push(ret);
    let mut jit = Jit::new(&m).unwrap();
    jit.cold_start().unwrap();
    assert_eq!(jit.read("main.set").unwrap().bits, 0);
    assert_eq!(jit.read("main.forgot").unwrap().bits, 0xA5A5_A5A5);
    let p = Pair::new(m);
    p.compare_all();
}

#[test]
fn every_variable_is_listed_and_readable() {
    let p = Prog::new(vec![
        field("b", Type::I1),
        field("s", Type::I8),
        field("i", Type::I16),
        field("d", Type::I32),
        field("l", Type::I64),
        field("r", Type::F32),
        field("lr", Type::F64),
    ]);
    let m = p.finish(|_, _, _| {});
    let p = Pair::new(m);
    let vars = plcc_ir::vars::variables(&p.module, plcc_ir::DataId::new(0));
    assert_eq!(vars.len(), 7);
    p.compare_all();
}

#[test]
fn many_machines_in_one_process() {
    // Code memory is freed on drop: compiling many modules must not exhaust anything.
    let p = Prog::new(vec![field("x", Type::I32)]);
    let m = p.finish(|_, _, _| {});
    for _ in 0..300 {
        let mut j = Jit::new(&m).unwrap();
        j.cold_start().unwrap();
        j.scan().unwrap();
    }
}

#[test]
fn malformed_ir_is_a_diagnostic_not_a_panic() {
    let p = Prog::new(vec![field("x", Type::I32)]);
    let mut m = p.finish(|_, _, _| {});
    // Use of a value that is never defined.
    let body = m.programs[0].body;
    let f = m.func_mut(body);
    f.blocks.resize(8, Default::default());
    let ghost = f.append_block_param(plcc_ir::Block::new(7), Type::I32);
    let entry = f.layout[0];
    let inst = f.create_inst(
        plcc_ir::InstData::Unary {
            op: plcc_ir::UnaryOp::Ineg,
            arg: ghost,
        },
        Some(Type::I32),
        None,
    );
    f.blocks[entry.index()].insts.insert(0, inst);
    let err = Jit::new(&m).err().expect("an error");
    assert_eq!(err[0].code, plcc_native::codes::E_MALFORMED_IR);
}

#[test]
fn an_empty_module_runs() {
    let m = plcc_ir::Module::new();
    let mut j = Jit::new(&m).unwrap();
    j.cold_start().unwrap();
    j.set_clock_us(5);
    j.scan().unwrap();
    assert!(!j.fault());
    assert!(j.read("x").is_err());
    assert_eq!(j.target(), "host");
}

#[test]
fn oversized_data_is_refused() {
    // Two 3 GiB arrays in one struct: Layout's 32-bit sizes would wrap.
    let mut p = Prog::new(vec![]);
    let big = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "big".into(),
        elem: MemType::Scalar(Type::I64),
        elem_type: Some(ElemType::LInt),
        len: 400_000_000,
        lower: 0,
    }));
    if let AggDef::Struct(s) = &mut p.module.aggs[0] {
        s.fields = vec![agg_field("a", big), agg_field("b", big)];
    }
    let m = p.finish(|_, _, _| {});
    let e = Jit::new(&m).err().expect("refused");
    assert_eq!(e[0].code, plcc_native::codes::E_DATA_TOO_LARGE);
    // 2 GiB is over the limit too.
    let mut p = Prog::new(vec![]);
    let big = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "big".into(),
        elem: MemType::Scalar(Type::I64),
        elem_type: Some(ElemType::LInt),
        len: 250_000_000,
        lower: 0,
    }));
    if let AggDef::Struct(s) = &mut p.module.aggs[0] {
        s.fields = vec![agg_field("a", big)];
    }
    let m = p.finish(|_, _, _| {});
    let e = Jit::new(&m).err().expect("refused");
    assert_eq!(e[0].code, plcc_native::codes::E_DATA_TOO_LARGE);
}
