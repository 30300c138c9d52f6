//! A large generated module (about the size of a 58,000-line program with 1000
//! functions) compiles on the worker threads and runs; Cranelift folds field offsets
//! into loads and stores.

mod common;

use common::{field, Prog};
use plcc_ir::machine::Machine;
use plcc_ir::{BinaryOp, ConvOp, FuncId, FuncKind, Function, IntCC, Module, Type, UnaryOp};
use plcc_native::Jit;

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

#[test]
fn large_module_compiles_and_runs() {
    // Compile speed is measured by bench/bench.py, not here: this only checks that a
    // module of many functions builds on the worker threads and runs.
    let (m, _) = generate(200, 25);
    let mut jit = Jit::new(&m).unwrap();
    jit.cold_start().unwrap();
    jit.scan().unwrap();
}

#[test]
fn field_offsets_fold_into_loads_and_stores() {
    let (m, _) = generate(3, 40);
    let text = plcc_native::clif(&m).unwrap();
    // Field addresses never materialise: every access is `base + offset`.
    assert!(text.contains("load.i16 notrap aligned v0+"), "{text}");
    assert!(!text.contains("iadd_imm"), "{text}");
}
