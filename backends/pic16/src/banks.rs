//! Bank selection: RP0/RP1 (and IRP for FSR) are tracked through each unit's control
//! flow, and a `bcf`/`bsf STATUS` is inserted only where an access needs a bank that
//! is not already known to be selected. A skip and the instruction it skips are
//! treated as one group: their bank is selected before the skip, never between.

use crate::asm::{Item, Label, Op, Unit};
use crate::isa::{bank_of, reg, Inst};
use rustc_hash::FxHashMap;

/// What is known about the three bank bits: `None` is unknown.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub struct State {
    rp0: Option<bool>,
    rp1: Option<bool>,
    irp: Option<bool>,
}

impl State {
    /// Nothing known.
    pub const UNKNOWN: State = State {
        rp0: None,
        rp1: None,
        irp: None,
    };

    /// What is known on both paths (`None`: a path that does not reach here).
    pub fn meet(a: Option<State>, b: Option<State>) -> Option<State> {
        let m = |x: Option<bool>, y: Option<bool>| if x == y { x } else { None };
        match (a, b) {
            (None, x) | (x, None) => x,
            (Some(a), Some(b)) => Some(State {
                rp0: m(a.rp0, b.rp0),
                rp1: m(a.rp1, b.rp1),
                irp: m(a.irp, b.irp),
            }),
        }
    }
}

/// What a group of instructions needs.
#[derive(Copy, Clone, Debug, Default)]
struct Need {
    bank: Option<u8>,
    irp: Option<bool>,
}

fn need_of(op: &Op) -> Need {
    match op {
        Op::I(i) => Need {
            bank: i.file().and_then(bank_of),
            irp: None,
        },
        Op::Irp(b) => Need {
            bank: None,
            irp: Some(*b),
        },
        _ => Need::default(),
    }
}

/// The effect of one instruction on the known state.
fn after(op: &Op, mut s: State, exits: &dyn Fn(Label) -> Option<State>) -> State {
    match op {
        Op::Call(l) => exits(*l).unwrap_or(State::UNKNOWN),
        Op::I(Inst::Clrf(reg::STATUS)) => State {
            rp0: Some(false),
            rp1: Some(false),
            irp: Some(false),
        },
        Op::I(Inst::Bcf(reg::STATUS, b)) | Op::I(Inst::Bsf(reg::STATUS, b)) => {
            let v = matches!(op, Op::I(Inst::Bsf(..)));
            match *b {
                reg::RP0 => s.rp0 = Some(v),
                reg::RP1 => s.rp1 = Some(v),
                reg::IRP => s.irp = Some(v),
                _ => {}
            }
            s
        }
        Op::I(i) => {
            let writes_status = i.file() == Some(reg::STATUS)
                && !matches!(
                    i,
                    Inst::Btfsc(..) | Inst::Btfss(..) | Inst::Movf(_, crate::isa::Dest::W)
                );
            if writes_status {
                State::UNKNOWN
            } else {
                s
            }
        }
        _ => s,
    }
}

fn ends_flow(op: &Op) -> bool {
    matches!(
        op,
        Op::Goto(_) | Op::I(Inst::Return) | Op::I(Inst::Retfie) | Op::I(Inst::Retlw(_))
    )
}

/// The selects that bring `s` to what `n` needs, and the state after them.
fn selects(s: State, n: Need, out: &mut Vec<Op>) -> State {
    let mut s = s;
    if let Some(b) = n.bank {
        let (want0, want1) = (b & 1 != 0, b & 2 != 0);
        if s.rp0 != Some(want0) {
            out.push(Op::I(if want0 {
                Inst::Bsf(reg::STATUS, reg::RP0)
            } else {
                Inst::Bcf(reg::STATUS, reg::RP0)
            }));
            s.rp0 = Some(want0);
        }
        if s.rp1 != Some(want1) {
            out.push(Op::I(if want1 {
                Inst::Bsf(reg::STATUS, reg::RP1)
            } else {
                Inst::Bcf(reg::STATUS, reg::RP1)
            }));
            s.rp1 = Some(want1);
        }
    }
    if let Some(i) = n.irp {
        if s.irp != Some(i) {
            out.push(Op::I(if i {
                Inst::Bsf(reg::STATUS, reg::IRP)
            } else {
                Inst::Bcf(reg::STATUS, reg::IRP)
            }));
            s.irp = Some(i);
        }
    }
    s
}

/// Statistics of one run.
#[derive(Clone, Debug, Default)]
pub struct BankStats {
    /// Select instructions inserted.
    pub selects: u32,
    /// What is known when the unit returns (the meet over its returns), if it does.
    pub exit: Option<State>,
    /// What is known at each call the unit makes.
    pub calls: Vec<(Label, State)>,
}

/// Inserts the bank selects a unit needs. `entry` is the state when the unit starts
/// (unknown for functions). Fails if a skip and the instruction it skips need
/// different banks (a bug of instruction selection).
/// `exits` gives the state a called unit returns with, where known.
/// `entry` is what is known when the unit starts.
pub fn insert_selects(
    unit: &mut Unit,
    entry: State,
    exits: &dyn Fn(Label) -> Option<State>,
) -> Result<BankStats, String> {
    // Groups: index ranges [start, end) of ops that must share one bank.
    let ops: Vec<(usize, Op)> = unit
        .items
        .iter()
        .enumerate()
        .filter_map(|(i, it)| match it {
            Item::Op(op) => Some((i, *op)),
            _ => None,
        })
        .collect();
    // For each op index (in `ops`), the group need if it starts a group.
    let mut group_need: Vec<Option<Need>> = vec![None; ops.len()];
    let mut k = 0;
    while k < ops.len() {
        let mut end = k + 1;
        while end - 1 < ops.len() && is_skip(&ops[end - 1].1) && end < ops.len() {
            end += 1;
        }
        let mut need = Need::default();
        for (_, op) in &ops[k..end] {
            let n = need_of(op);
            need.bank = match (need.bank, n.bank) {
                (Some(a), Some(b)) if a != b => {
                    return Err(format!(
                        "{}: a skip and the instruction it skips need banks {a} and {b}",
                        unit.name
                    ))
                }
                (a, b) => a.or(b),
            };
            need.irp = need.irp.or(n.irp);
        }
        group_need[k] = Some(need);
        k = end;
    }
    // Dataflow over labels to a fixed point.
    let mut label_in: FxHashMap<Label, Option<State>> = FxHashMap::default();
    for _round in 0..64 {
        let mut changed = false;
        let mut cur: Option<State> = Some(entry);
        let mut skip_pending: Option<Option<State>> = None;
        let mut opi = 0;
        for it in &unit.items {
            match it {
                Item::Label(l) => {
                    let incoming = label_in.get(l).copied().flatten();
                    cur = State::meet(cur, incoming);
                }
                Item::Op(op) => {
                    if let Some(n) = group_need[opi] {
                        if let Some(s) = cur {
                            let mut scratch = Vec::new();
                            cur = Some(selects(s, n, &mut scratch));
                        }
                    }
                    let before = cur;
                    if let Op::Goto(l) | Op::TableGoto(l) = op {
                        let e = label_in.entry(*l).or_insert(None);
                        let m = State::meet(*e, cur);
                        if m != *e {
                            *e = m;
                            changed = true;
                        }
                    }
                    cur = cur.map(|s| after(op, s, exits));
                    if ends_flow(op) {
                        cur = None;
                    }
                    if let Some(b) = skip_pending.take() {
                        // This op may have been skipped.
                        cur = State::meet(cur, b);
                    }
                    if is_skip(op) {
                        skip_pending = Some(before.map(|s| after(op, s, exits)));
                    }
                    opi += 1;
                }
                Item::Comment(_) => {}
            }
        }
        if !changed {
            break;
        }
    }
    // Emit.
    let mut out = Vec::with_capacity(unit.items.len() + 16);
    let mut stats = BankStats::default();
    let mut cur: Option<State> = Some(entry);
    let mut skip_pending: Option<Option<State>> = None;
    let mut opi = 0;
    for it in std::mem::take(&mut unit.items) {
        match &it {
            Item::Label(l) => {
                cur = State::meet(cur, label_in.get(l).copied().flatten());
                out.push(it);
            }
            Item::Op(op) => {
                let op = *op;
                if let Some(n) = group_need[opi] {
                    let mut sel = Vec::new();
                    let s = cur.unwrap_or(State::UNKNOWN);
                    cur = Some(selects(s, n, &mut sel));
                    stats.selects += sel.iter().filter(|o| !matches!(o, Op::Irp(_))).count() as u32;
                    out.extend(sel.into_iter().map(Item::Op));
                }
                let before = cur;
                if matches!(op, Op::I(Inst::Return) | Op::I(Inst::Retlw(_))) {
                    stats.exit = State::meet(stats.exit, cur);
                }
                if let Op::Call(l) = op {
                    stats.calls.push((l, cur.unwrap_or(State::UNKNOWN)));
                }
                cur = cur.map(|s| after(&op, s, exits));
                if ends_flow(&op) {
                    cur = None;
                }
                if let Some(b) = skip_pending.take() {
                    cur = State::meet(cur, b);
                }
                if is_skip(&op) {
                    skip_pending = Some(before.map(|s| after(&op, s, exits)));
                }
                if !matches!(op, Op::Irp(_)) {
                    out.push(Item::Op(op));
                }
                opi += 1;
            }
            Item::Comment(_) => out.push(it),
        }
    }
    unit.items = out;
    Ok(stats)
}

fn is_skip(op: &Op) -> bool {
    matches!(op, Op::I(i) if i.is_skip())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::Dest;

    fn unit(items: Vec<Item>) -> Unit {
        Unit {
            name: "t".into(),
            items,
            ..Default::default()
        }
    }

    fn ops(u: &Unit) -> Vec<Op> {
        u.items
            .iter()
            .filter_map(|i| match i {
                Item::Op(o) => Some(*o),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn selects_once_per_bank_change() {
        let mut u = unit(vec![
            Item::Op(Op::I(Inst::Movf(0x20, Dest::W))),
            Item::Op(Op::I(Inst::Movwf(0x21))),
            Item::Op(Op::I(Inst::Movwf(0xA0))),
            Item::Op(Op::I(Inst::Movwf(0x70))),
            Item::Op(Op::I(Inst::Movwf(0xA1))),
        ]);
        let st = insert_selects(&mut u, State::UNKNOWN, &|_| None).unwrap();
        assert_eq!(st.selects, 3); // rp0=0, rp1=0 at entry, then rp0=1
        let o = ops(&u);
        assert_eq!(o[0], Op::I(Inst::Bcf(reg::STATUS, reg::RP0)));
        assert_eq!(o[1], Op::I(Inst::Bcf(reg::STATUS, reg::RP1)));
        assert_eq!(o[4], Op::I(Inst::Bsf(reg::STATUS, reg::RP0)));
        assert_eq!(o.len(), 8);
    }

    #[test]
    fn never_between_a_skip_and_its_target() {
        let mut u = unit(vec![
            Item::Op(Op::I(Inst::Bcf(reg::STATUS, reg::RP0))),
            Item::Op(Op::I(Inst::Bcf(reg::STATUS, reg::RP1))),
            Item::Op(Op::I(Inst::Btfsc(reg::STATUS, reg::C))),
            Item::Op(Op::I(Inst::Incf(0xA0, Dest::F))),
        ]);
        insert_selects(&mut u, State::UNKNOWN, &|_| None).unwrap();
        let o = ops(&u);
        assert_eq!(o[2], Op::I(Inst::Bsf(reg::STATUS, reg::RP0)));
        assert_eq!(o[3], Op::I(Inst::Btfsc(reg::STATUS, reg::C)));
    }

    #[test]
    fn merges_at_labels() {
        let l = Label(0);
        let mut u = unit(vec![
            Item::Op(Op::I(Inst::Movwf(0xA0))),
            Item::Op(Op::I(Inst::Btfsc(reg::STATUS, reg::Z))),
            Item::Op(Op::Goto(l)),
            Item::Op(Op::I(Inst::Movwf(0x20))),
            Item::Label(l),
            Item::Op(Op::I(Inst::Movwf(0x21))),
        ]);
        insert_selects(&mut u, State::UNKNOWN, &|_| None).unwrap();
        let o = ops(&u);
        // After the label RP0 is unknown (1 on the jump, 0 on the fall-through).
        let tail = &o[o.len() - 2..];
        assert_eq!(tail[0], Op::I(Inst::Bcf(reg::STATUS, reg::RP0)));
    }

    /// The entries of a jump table are reached with the bank state of the computed
    /// jump: their targets need no select of their own.
    #[test]
    fn table_entries_carry_the_state_of_the_jump() {
        let (la, lb) = (Label(0), Label(1));
        let mut u = unit(vec![
            Item::Op(Op::I(Inst::Movwf(0xA0))),
            Item::Op(Op::I(Inst::Movwf(reg::PCL))),
            Item::Op(Op::TableGoto(la)),
            Item::Op(Op::TableGoto(lb)),
            Item::Label(la),
            Item::Op(Op::I(Inst::Movwf(0xA1))),
            Item::Op(Op::I(Inst::Return)),
            Item::Label(lb),
            Item::Op(Op::I(Inst::Movwf(0xA2))),
            Item::Op(Op::I(Inst::Return)),
        ]);
        let st = insert_selects(&mut u, State::UNKNOWN, &|_| None).unwrap();
        // RP0 and RP1 before the first access, nothing after.
        assert_eq!(st.selects, 2, "{:?}", ops(&u));
    }

    #[test]
    fn conflicting_skip_group_is_an_error() {
        let mut u = unit(vec![
            Item::Op(Op::I(Inst::Btfsc(0x20, 0))),
            Item::Op(Op::I(Inst::Incf(0xA0, Dest::F))),
        ]);
        assert!(insert_selects(&mut u, State::UNKNOWN, &|_| None).is_err());
    }
}
