//! The dominator tree against a naive algorithm, and the verifier on big functions.

use super::*;

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
                        then_dest: Box::new(BlockCall::new(blocks[t], vec![])),
                        else_dest: Box::new(BlockCall::new(blocks[e], vec![])),
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
