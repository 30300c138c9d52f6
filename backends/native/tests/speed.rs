//! Compile speed on a large generated module (the size of a 58,000-line program with
//! about 1000 functions). `cargo test --release -p plcc-native --test speed -- --nocapture`
//! prints the numbers; the assertion is loose so that debug builds pass.

mod common;

use common::{field, Prog};
use plcc_ir::machine::Machine;
use plcc_ir::{BinaryOp, ConvOp, FuncId, FuncKind, Function, IntCC, Module, Type, UnaryOp};
use plcc_native::Jit;
use std::time::Instant;

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

const NFIELDS: u32 = 48;

fn field_type(i: u32) -> Type {
    match i % 4 {
        0 => Type::I16,
        1 => Type::I32,
        2 => Type::F32,
        _ => Type::I1,
    }
}

/// About `stmts` source-statement-sized chunks of IR per function.
pub fn generate(nfuncs: usize, stmts: usize) -> (Module, usize) {
    let fields = (0..NFIELDS)
        .map(|i| field(&format!("v{i}"), field_type(i)))
        .collect();
    let mut p = Prog::new(fields);
    let agg = p.agg;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut funcs: Vec<FuncId> = Vec::new();
    for k in 0..nfuncs {
        let mut f = Function::new(format!("fb{k}"), FuncKind::FbBody, vec![Type::Ptr], None);
        {
            let mut b = plcc_ir::FuncBuilder::new(&mut f);
            let inst = b.params()[0];
            let pick = |rng: &mut Rng, m: u32| rng.below((NFIELDS / 4) as u64) as u32 * 4 + m;
            for _ in 0..stmts {
                match rng.below(10) {
                    0..=3 => {
                        // vI := vJ + vK * c (integers)
                        let m = rng.below(2) as u32;
                        let ty = field_type(m);
                        let (i, j, kk) = (pick(&mut rng, m), pick(&mut rng, m), pick(&mut rng, m));
                        let aj = b.field_addr(inst, agg, j);
                        let x = b.load(ty, aj);
                        let ak = b.field_addr(inst, agg, kk);
                        let y = b.load(ty, ak);
                        let c = b.iconst(ty, rng.below(100) as i64);
                        let y = b.binary(BinaryOp::Imul, y, c);
                        let r = b.binary(BinaryOp::Iadd, x, y);
                        let ai = b.field_addr(inst, agg, i);
                        b.store(r, ai);
                    }
                    4..=5 => {
                        // IF vJ > vK THEN vI := vI / vJ ELSE vI := vK END_IF
                        let m = rng.below(2) as u32;
                        let ty = field_type(m);
                        let (i, j, kk) = (pick(&mut rng, m), pick(&mut rng, m), pick(&mut rng, m));
                        let aj = b.field_addr(inst, agg, j);
                        let x = b.load(ty, aj);
                        let ak = b.field_addr(inst, agg, kk);
                        let y = b.load(ty, ak);
                        let c = b.icmp(IntCC::Sgt, x, y);
                        let (t, e, done) = (b.create_block(), b.create_block(), b.create_block());
                        b.brif(c, t, vec![], e, vec![]);
                        b.switch_to(t);
                        let ai = b.field_addr(inst, agg, i);
                        let v = b.load(ty, ai);
                        let q = b.binary(BinaryOp::Sdiv, v, x);
                        b.store(q, ai);
                        b.jump(done, vec![]);
                        b.switch_to(e);
                        let ai = b.field_addr(inst, agg, i);
                        b.store(y, ai);
                        b.jump(done, vec![]);
                        b.switch_to(done);
                    }
                    6 => {
                        // r := r * 1.5 + REAL(vJ)
                        let (i, j) = (pick(&mut rng, 2), pick(&mut rng, 1));
                        let ai = b.field_addr(inst, agg, i);
                        let r = b.load(Type::F32, ai);
                        let c = b.f32const(1.5);
                        let r = b.binary(BinaryOp::Fmul, r, c);
                        let aj = b.field_addr(inst, agg, j);
                        let x = b.load(Type::I32, aj);
                        let x = b.convert(ConvOp::SiToF, Type::F32, x);
                        let r = b.binary(BinaryOp::Fadd, r, x);
                        let r = if rng.below(8) == 0 {
                            b.unary(UnaryOp::Sin, r)
                        } else {
                            r
                        };
                        b.store(r, ai);
                    }
                    7 => {
                        // flag := a AND NOT b OR (vJ < 10)
                        let (i, j, kk) = (pick(&mut rng, 3), pick(&mut rng, 3), pick(&mut rng, 3));
                        let aj = b.field_addr(inst, agg, j);
                        let x = b.load(Type::I1, aj);
                        let ak = b.field_addr(inst, agg, kk);
                        let y = b.load(Type::I1, ak);
                        let ny = b.unary(UnaryOp::Bnot, y);
                        let z = b.binary(BinaryOp::Band, x, ny);
                        let an = b.field_addr(inst, agg, pick(&mut rng, 0));
                        let n = b.load(Type::I16, an);
                        let ten = b.iconst(Type::I16, 10);
                        let c = b.icmp(IntCC::Slt, n, ten);
                        let z = b.binary(BinaryOp::Bor, z, c);
                        let ai = b.field_addr(inst, agg, i);
                        b.store(z, ai);
                    }
                    8 => {
                        // FOR n := 0 TO 3 DO vI := vI + n END_FOR
                        let i = pick(&mut rng, 1);
                        let head = b.create_block();
                        let body = b.create_block();
                        let exit = b.create_block();
                        let n = b.block_param(head, Type::I32);
                        let z = b.iconst(Type::I32, 0);
                        b.jump(head, vec![z]);
                        b.switch_to(head);
                        let lim = b.iconst(Type::I32, 3);
                        let c = b.icmp(IntCC::Sle, n, lim);
                        b.brif(c, body, vec![], exit, vec![]);
                        b.switch_to(body);
                        let ai = b.field_addr(inst, agg, i);
                        let v = b.load(Type::I32, ai);
                        let v = b.binary(BinaryOp::Iadd, v, n);
                        b.store(v, ai);
                        let one = b.iconst(Type::I32, 1);
                        let n1 = b.binary(BinaryOp::Iadd, n, one);
                        b.jump(head, vec![n1]);
                        b.switch_to(exit);
                    }
                    _ => {
                        // call an earlier FB on the same instance
                        if let Some(&callee) =
                            funcs.get(rng.below(funcs.len().max(1) as u64) as usize)
                        {
                            if rng.below(4) == 0 {
                                b.call(callee, None, vec![inst]);
                            }
                        }
                    }
                }
            }
            b.ret(None);
        }
        funcs.push(p.module.add_func(f));
    }
    let insts: usize = p.module.funcs.iter().map(|f| f.live_inst_count()).sum();
    let m = p.finish(|b, inst, _| {
        for &f in &funcs {
            b.call(f, None, vec![inst]);
        }
    });
    (m, insts)
}

fn measure(m: &Module, threads: &str, opt: &str, regalloc: &str) -> f64 {
    use plcc_ir::backend::{Backend, Options};
    let opts = Options {
        emit: None,
        settings: vec![
            ("threads".into(), threads.into()),
            ("opt_level".into(), opt.into()),
            ("regalloc".into(), regalloc.into()),
        ],
    };
    // The best of a few runs: the machine may be busy with other work.
    let mut best = f64::MAX;
    for _ in 0..3 {
        let t = Instant::now();
        let mut jit = plcc_native::NativeBackend
            .machine(m, &opts)
            .unwrap()
            .unwrap();
        best = best.min(t.elapsed().as_secs_f64());
        jit.cold_start().unwrap();
        jit.scan().unwrap();
    }
    best
}

#[test]
fn large_module_compiles_fast() {
    if cfg!(debug_assertions) {
        // Debug builds of Cranelift are slow: just check that a big module works.
        let (m, _) = generate(200, 25);
        let mut jit = Jit::new(&m).unwrap();
        jit.cold_start().unwrap();
        jit.scan().unwrap();
        return;
    }
    let (m, insts) = generate(1000, 58);
    let n = m.funcs.len();
    println!(
        "{n} functions, {insts} IR instructions, {} threads available",
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    );
    let _ = Jit::new(&m).unwrap(); // warm up (page faults, lazy statics)
    let mut default = 0.0;
    for (opt, ra) in [
        ("speed", "backtracking"),
        ("speed", "single_pass"),
        ("none", "backtracking"),
        ("none", "single_pass"),
    ] {
        let serial = measure(&m, "1", opt, ra);
        let parallel = measure(&m, "0", opt, ra);
        println!(
            "opt_level={opt} regalloc={ra}: serial {serial:.3} s ({:.0} us/function), \
             parallel {parallel:.3} s ({:.0} us/function)",
            serial * 1e6 / n as f64,
            parallel * 1e6 / n as f64,
        );
        if opt == "speed" && ra == "backtracking" {
            default = parallel;
        }
    }
    let t = Instant::now();
    plcc_ir::verify::verify_module(&m).unwrap();
    println!("IR verifier: {:.3} s", t.elapsed().as_secs_f64());
    let (small, insts) = generate(1000, 25);
    let t = measure(&small, "0", "speed", "backtracking");
    println!(
        "{} functions, {insts} IR instructions: parallel {t:.3} s (default settings)",
        small.funcs.len()
    );
    assert!(default < 3.0, "compile too slow: {default} s");
}

#[test]
fn field_offsets_fold_into_loads_and_stores() {
    let (m, _) = generate(3, 40);
    let text = plcc_native::clif(&m).unwrap();
    // Field addresses never materialise: every access is `base + offset`.
    assert!(text.contains("load.i16 notrap aligned v0+"), "{text}");
    assert!(!text.contains("iadd_imm"), "{text}");
}

#[test]
#[ignore]
fn scan_speed_by_setting() {
    use plcc_ir::backend::{Backend, Options};
    let (m, _) = generate(1000, 25);
    for (opt, ra) in [
        ("speed", "backtracking"),
        ("speed", "single_pass"),
        ("none", "backtracking"),
        ("none", "single_pass"),
    ] {
        let opts = Options {
            emit: None,
            settings: vec![
                ("opt_level".into(), opt.into()),
                ("regalloc".into(), ra.into()),
            ],
        };
        let mut jit = plcc_native::NativeBackend
            .machine(&m, &opts)
            .unwrap()
            .unwrap();
        jit.cold_start().unwrap();
        let t = Instant::now();
        for _ in 0..2000 {
            jit.scan().unwrap();
        }
        println!(
            "{opt} {ra}: {:.1} us/scan",
            t.elapsed().as_secs_f64() * 1e6 / 2000.0
        );
    }
}

/// Times the JIT on an IR file named by `PLCC_IR_FILE` (for example the optimised IR
/// of a benchmark program, from `plcc FILE --emit ir`).
#[test]
#[ignore]
fn ir_file_compile_time() {
    let Ok(path) = std::env::var("PLCC_IR_FILE") else {
        eprintln!("PLCC_IR_FILE is not set");
        return;
    };
    let text = std::fs::read_to_string(&path).unwrap();
    let m = plcc_ir::text::parse_module(&text).unwrap();
    let insts: usize = m.funcs.iter().map(|f| f.live_inst_count()).sum();
    let blocks: usize = m.funcs.iter().map(|f| f.layout.len()).sum();
    println!(
        "{} functions, {insts} instructions, {blocks} blocks",
        m.funcs.len()
    );
    for _ in 0..3 {
        let (c0, t0) = (cpu_seconds(), Instant::now());
        let j = Jit::new(&m).unwrap();
        let (c1, t1) = (cpu_seconds(), Instant::now());
        drop(j);
        println!(
            "Jit::new: wall {:.3} s, CPU {:.3} s; drop: wall {:.3} s, CPU {:.3} s",
            (t1 - t0).as_secs_f64(),
            c1 - c0,
            t1.elapsed().as_secs_f64(),
            cpu_seconds() - c1
        );
    }
    for threads in ["1", "0"] {
        let _ = cranelift_codegen::timing::take_current();
        let cpu0 = cpu_seconds();
        let t = measure(&m, threads, "speed", "backtracking");
        let cpu = (cpu_seconds() - cpu0) / 3.0;
        println!("threads={threads}: {t:.3} s (CPU {cpu:.3} s per run)");
        if threads == "1" {
            println!("{}", cranelift_codegen::timing::take_current());
        }
    }
}

/// User + system CPU time of this process so far (Linux), 0 elsewhere.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    let after = &stat[stat.rfind(')').map_or(0, |i| i + 2)..];
    let f: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|x| x.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(11) + ticks(12)) / 100.0
}
