//! Copy propagation for SSA with block parameters.
//!
//! A block parameter is a copy when every incoming argument is one value `v` or the
//! parameter itself (a loop that does not change it): every use then becomes `v` and
//! the parameter and its arguments go. Removing one can make others trivial, so sweeps
//! repeat in reverse postorder until nothing changes (forward chains resolve within a
//! sweep; each further sweep only follows loop back edges). A `select` whose two arms
//! are the same value is a copy too.

use crate::dominators::reverse_postorder;
use crate::function::Function;
use crate::inst::InstData;
use crate::passes::util::{dest_ref, remove_block_params, Incoming, ValueMap};

/// Sweeps beyond which the remaining trivial parameters are left to the next run.
const MAX_SWEEPS: usize = 16;

/// Removes trivial block parameters and `select`s with equal arms. Returns true if the
/// function changed.
pub fn run(func: &mut Function) -> bool {
    let Some(entry) = func.entry() else {
        return false;
    };
    let mut vmap = ValueMap::new(func);
    let mut changed = false;
    let order = reverse_postorder(func);
    let incoming = Incoming::compute(func);
    let mut keep: Vec<bool> = Vec::new();
    for _ in 0..MAX_SWEEPS {
        let mut swept_change = false;
        for &b in &order {
            if b == entry || func.blocks[b.index()].params.is_empty() {
                continue;
            }
            let edges = incoming.of(b);
            if edges.is_empty() {
                continue;
            }
            let nparams = func.blocks[b.index()].params.len();
            keep.clear();
            keep.resize(nparams, true);
            let mut any = false;
            for (k, keep_k) in keep.iter_mut().enumerate() {
                let p = func.blocks[b.index()].params[k];
                let mut same = None;
                let mut trivial = true;
                for e in edges {
                    let call = dest_ref(func.inst(e.inst), e.which);
                    let Some(&a) = call.args.get(k) else {
                        trivial = false;
                        break;
                    };
                    let a = vmap.resolve(a);
                    if a == p {
                        continue;
                    }
                    match same {
                        None => same = Some(a),
                        Some(s) if s == a => {}
                        Some(_) => {
                            trivial = false;
                            break;
                        }
                    }
                }
                if let (true, Some(v)) = (trivial, same) {
                    vmap.set(p, v);
                    *keep_k = false;
                    any = true;
                }
            }
            if any {
                remove_block_params(func, b, &keep, edges);
                swept_change = true;
            }
        }
        changed |= swept_change;
        if !swept_change {
            break;
        }
    }

    // Selects with equal arms (after the substitutions above), removed in place.
    let Function {
        layout,
        blocks,
        insts,
        results,
        ..
    } = func;
    for &b in layout.iter() {
        blocks[b.index()].insts.retain(|&i| {
            let InstData::Select {
                if_true, if_false, ..
            } = insts[i.index()]
            else {
                return true;
            };
            let t = vmap.resolve(if_true);
            if t != vmap.resolve(if_false) {
                return true;
            }
            vmap.set(results[i.index()].expect("select has a result"), t);
            changed = true;
            false
        });
    }
    vmap.apply(func);
    changed
}
