use plcc_ir::text::*;
use plcc_ir::*;
#[test]
fn perf() {
    let mut m = Module::new();
    let mut f = Function::new("big", FuncKind::Function, vec![Type::I32], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let mut acc = b.params()[0];
        for k in 0..200_000 {
            let c = b.iconst(Type::I32, k);
            acc = b.binary(BinaryOp::Iadd, acc, c);
        }
        b.ret(Some(acc));
    }
    m.add_func(f);
    let s = print_module(&m, &PrintOptions::default());
    for _ in 0..3 {
    let t = std::time::Instant::now();
    let _m2 = parse_module(&s).unwrap();
    println!("parse {:?}", t.elapsed());
    }
}
