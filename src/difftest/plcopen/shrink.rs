//! Shrinking a PLCopen program that shows a finding: the FUNCTION_BLOCK `helper` is
//! dropped, then whole networks, then single elements (with every wire from them),
//! single wires, modifiers and `executionOrderId`s, then the variables nothing uses,
//! for as long as the finding stays. A step that leaves something the front end
//! rejects (a jump without its label, a function whose type cannot be told) is no
//! finding, so it is not taken.

use super::{networks, Edge, Kind, Pou, Storage, VarTy, XmlProg, SUB_FB};

/// Removes the elements `ids` of POU `pou` and every wire from them (a removed
/// connector takes its continuations along).
fn without(p: &XmlProg, pou: usize, ids: &[u64]) -> XmlProg {
    let mut q = p.clone();
    let body = &mut q.pous[pou];
    let mut gone: Vec<u64> = ids.to_vec();
    let names: Vec<String> = body
        .elems
        .iter()
        .filter(|e| gone.contains(&e.id))
        .filter_map(|e| match &e.kind {
            Kind::Connector { name, .. } => Some(name.clone()),
            _ => None,
        })
        .collect();
    for e in &body.elems {
        if let Kind::Continuation { name } = &e.kind {
            if names.contains(name) {
                gone.push(e.id);
            }
        }
    }
    body.elems.retain(|e| !gone.contains(&e.id));
    for e in &mut body.elems {
        for list in e.kind.wire_lists_mut() {
            list.retain(|w| !gone.contains(&w.from));
        }
    }
    q
}

/// The variables of `p` that nothing names.
fn unused_vars(p: &Pou, prog: &XmlProg) -> Vec<String> {
    let mut text = String::new();
    for e in &p.elems {
        match &e.kind {
            Kind::Contact { var, .. } | Kind::Coil { var, .. } => text.push_str(var),
            Kind::InVar { expr, .. } | Kind::OutVar { expr, .. } => text.push_str(expr),
            Kind::Block {
                instance: Some(i), ..
            } => text.push_str(i),
            _ => {}
        }
        text.push(' ');
    }
    let words: Vec<String> = text
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .map(str::to_string)
        .collect();
    let sub_uses = |v: &str| {
        // `helper`'s interface is its pins: keep its inputs and outputs while `main`
        // has an instance of it.
        p.fb && prog
            .main()
            .vars
            .iter()
            .any(|m| m.ty == VarTy::Fb(p.name.clone()))
            && p.vars
                .iter()
                .any(|x| x.name == v && x.class != super::Class::Local)
    };
    p.vars
        .iter()
        .filter(|v| !words.contains(&v.name) && !sub_uses(&v.name))
        .map(|v| v.name.clone())
        .collect()
}

/// The programs one step smaller than `p`, the bigger steps first.
fn steps(p: &XmlProg) -> Vec<XmlProg> {
    let mut out = Vec::new();
    if p.pous.len() > 1 {
        let mut q = p.clone();
        q.pous.remove(0);
        let main = q.pous.last_mut().expect("main");
        main.vars.retain(|v| v.ty != VarTy::Fb(SUB_FB.into()));
        let ids: Vec<u64> = main
            .elems
            .iter()
            .filter(|e| matches!(&e.kind, Kind::Block { ty, .. } if ty == SUB_FB))
            .map(|e| e.id)
            .collect();
        let n = q.pous.len() - 1;
        out.push(without(&q, n, &ids));
    }
    for (k, pou) in p.pous.iter().enumerate() {
        for net in networks(pou) {
            out.push(without(p, k, &net));
        }
    }
    for (k, pou) in p.pous.iter().enumerate() {
        for e in &pou.elems {
            out.push(without(p, k, &[e.id]));
        }
    }
    for (k, pou) in p.pous.iter().enumerate() {
        for (i, e) in pou.elems.iter().enumerate() {
            let lists = {
                let mut k2 = e.kind.clone();
                k2.wire_lists_mut()
                    .iter()
                    .map(|l| l.len())
                    .collect::<Vec<_>>()
            };
            for (l, len) in lists.iter().enumerate() {
                for w in 0..*len {
                    let mut q = p.clone();
                    let mut ls = q.pous[k].elems[i].kind.wire_lists_mut();
                    ls[l].remove(w);
                    out.push(q);
                }
            }
            let mut q = p.clone();
            let el = &mut q.pous[k].elems[i];
            let mut plain = false;
            el.order = None;
            match &mut el.kind {
                Kind::Contact { negated, edge, .. } => {
                    *negated = false;
                    *edge = Edge::None;
                }
                Kind::Coil {
                    negated,
                    storage,
                    edge,
                    ..
                } => {
                    *negated = false;
                    *storage = Storage::None;
                    *edge = Edge::None;
                }
                Kind::Block {
                    inputs, outputs, ..
                } => {
                    for pin in inputs.iter_mut().chain(outputs.iter_mut()) {
                        pin.negated = false;
                        pin.edge = Edge::None;
                    }
                }
                Kind::InVar { negated, .. } | Kind::OutVar { negated, .. } => *negated = false,
                _ => plain = true,
            }
            if !plain && q != *p {
                out.push(q);
            }
        }
    }
    for (k, pou) in p.pous.iter().enumerate() {
        let unused = unused_vars(pou, p);
        if !unused.is_empty() {
            let mut q = p.clone();
            q.pous[k].vars.retain(|v| !unused.contains(&v.name));
            out.push(q);
        }
    }
    out
}

/// Shrinks `p` while `keep` holds, trying at most `budget` candidates.
pub fn shrink(p: &XmlProg, keep: &mut dyn FnMut(&XmlProg) -> bool, budget: usize) -> XmlProg {
    let mut cur = p.clone();
    let mut tries = 0;
    let mut from = 0;
    loop {
        let cands = steps(&cur);
        let mut taken = false;
        for (i, q) in cands.iter().enumerate().skip(from) {
            if tries >= budget {
                return cur;
            }
            tries += 1;
            if keep(q) {
                cur = q.clone();
                from = i;
                taken = true;
                break;
            }
        }
        if !taken {
            if from == 0 {
                return cur;
            }
            // One more round from the start: an earlier step may fit now.
            from = 0;
        }
    }
}
