//! Coalescing block parameters with their arguments by liveness.

use super::*;
use plcc_ir::analysis::Liveness;

/// Block parameters share a home with the arguments that flow into them when the two
/// are never live at once, so the copies on the edges disappear (SSA's phi copies,
/// coalesced by liveness).
impl Fx<'_, '_> {
    pub(super) fn coalesce_block_params(&mut self) {
        let f = self.f;
        let nv = f.values.len();
        let layout = f.layout.clone();
        let late_use = self.late_use.clone();
        let inst_uses = |i: plcc_ir::entities::Inst| -> Vec<Value> {
            let mut used = Vec::new();
            f.inst(i).for_each_arg(|v| used.push(v));
            used.extend(late_use.get(&i).copied());
            used
        };
        // Where each value is defined: block and position (-1 for parameters).
        let mut def_at: Vec<Option<(usize, i64)>> = vec![None; nv];
        for &b in &layout {
            let bi = b.index();
            for &p in &f.block(b).params {
                def_at[p.index()] = Some((bi, -1));
            }
            for (k, &i) in f.block(b).insts.iter().enumerate() {
                if let Some(r) = f.result(i) {
                    def_at[r.index()] = Some((bi, k as i64));
                }
            }
        }
        let liveness = Liveness::compute(f, |i, push| {
            for v in inst_uses(i) {
                push(v);
            }
        });
        // Is `v` live just after position `k` of block `bi`?
        let live_after = |v: Value, bi: usize, k: i64| -> bool {
            let vi = v.index();
            let defined_before = match def_at[vi] {
                Some((db, dk)) if db == bi => dk <= k,
                _ => liveness.is_live_in(Block::new(bi), v),
            };
            if !defined_before {
                return false;
            }
            if liveness.is_live_out(Block::new(bi), v) {
                return true;
            }
            let insts = &f.block(Block::new(bi)).insts;
            insts
                .iter()
                .skip((k + 1).max(0) as usize)
                .any(|&i| inst_uses(i).contains(&v))
        };
        let operands_of = |v: Value| -> Vec<Value> {
            let mut ops = Vec::new();
            if let ValueDef::Result(i) = f.value_def(v) {
                f.inst(i).for_each_arg(|x| ops.push(x));
            }
            ops
        };
        let atomic = |v: Value| -> bool {
            match f.value_def(v) {
                ValueDef::Result(i) => self.single_vm_inst(f.inst(i)),
                ValueDef::Param(..) => true,
            }
        };
        let interfere = |x: Value, y: Value| -> bool {
            let live_at_def = |a: Value, b: Value| match def_at[b.index()] {
                Some((bi, k)) => live_after(a, bi, k),
                None => true,
            };
            if live_at_def(x, y) || live_at_def(y, x) {
                return true;
            }
            // A definition made of several VM instructions may write its home before
            // it has read all its operands.
            (!atomic(x) && operands_of(x).contains(&y))
                || (!atomic(y) && operands_of(y).contains(&x))
        };
        let is_const = |v: Value| {
            matches!(
                f.value_def(v),
                ValueDef::Result(i) if matches!(f.inst(i), InstData::Iconst { .. } | InstData::Fconst { .. })
            )
        };
        // Classes of values that share a home.
        let mut class_of: FxHashMap<Value, usize> = FxHashMap::default();
        let mut classes: Vec<Vec<Value>> = Vec::new();
        for &b in &layout {
            let Some(term) = f.terminator(b) else {
                continue;
            };
            for bc in f.inst(term).successors() {
                let params = f.block(bc.block).params.clone();
                for (&p, &a) in params.iter().zip(&bc.args) {
                    if p == a
                        || is_const(a)
                        || self.homes[a.index()].is_some()
                        || self.homes[p.index()].is_some()
                        || self.skip[a.index()]
                        || self.size(self.vty(a)) != self.size(self.vty(p))
                    {
                        continue;
                    }
                    let ca = class_of.get(&a).copied();
                    let cp = class_of.get(&p).copied();
                    if ca.is_some() && ca == cp {
                        continue;
                    }
                    let ma = ca.map(|c| classes[c].clone()).unwrap_or_else(|| vec![a]);
                    let mp = cp.map(|c| classes[c].clone()).unwrap_or_else(|| vec![p]);
                    if ma.iter().any(|&x| mp.iter().any(|&y| interfere(x, y))) {
                        continue;
                    }
                    let target = match (ca, cp) {
                        (Some(c), _) | (None, Some(c)) => c,
                        (None, None) => {
                            classes.push(Vec::new());
                            classes.len() - 1
                        }
                    };
                    for v in ma.into_iter().chain(mp) {
                        if let Some(&old) = class_of.get(&v) {
                            if old != target {
                                classes[old].retain(|&x| x != v);
                            }
                        }
                        if !classes[target].contains(&v) {
                            classes[target].push(v);
                        }
                        class_of.insert(v, target);
                    }
                }
            }
        }
        for c in classes {
            if c.len() < 2 {
                continue;
            }
            let size = self.size(self.vty(c[0]));
            let h = self.alloc(size, format!("?V{}", c[0].0));
            for v in c {
                self.homes[v.index()] = Some(h);
            }
        }
    }
}
