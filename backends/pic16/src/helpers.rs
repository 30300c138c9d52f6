//! Runtime subroutines the generated code calls: multiply and divide for each width
//! the program uses, and the bit mask of a BOOL pointer. Each is emitted once, and
//! only when used.
//!
//! They work on one shared [`Workspace`] in banked RAM (they are leaves, so one is
//! enough) and count loops in common RAM.

use crate::asm::{Item, Label, Op, Unit};
use crate::isa::{reg, Dest, Inst};
use std::collections::BTreeMap;

/// A runtime subroutine.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Helper {
    /// `R := A * B` (low `n` bytes); A and B are destroyed.
    Mul(u16),
    /// Unsigned `A := A / B`, `R := A % B` over `n` bytes (B is never 0 here).
    Div(u16),
    /// `W := 1 << ((W >> 1) & 7)`: the mask of the bit a BOOL pointer points at.
    BitMask,
}

/// Where the helpers' operands live: three blocks of up to 8 bytes and a loop
/// counter, in one bank.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Workspace {
    /// Loop counter.
    pub cnt: u16,
    /// First operand (the quotient after a division).
    pub a: u16,
    /// Second operand.
    pub b: u16,
    /// Result of a multiplication, remainder of a division.
    pub r: u16,
}

/// Bytes the workspace needs for operands of `n` bytes.
pub fn workspace_bytes(n: u16) -> u16 {
    3 * n + 1
}

/// The bit-mask helper's scratch (common RAM, never live across its call).
const H0: u16 = crate::isel::SCRATCH[4];
const H1: u16 = crate::isel::SCRATCH[5];

/// The helpers a program uses and their labels.
#[derive(Clone, Debug, Default)]
pub struct HelperSet {
    /// Widest multiplication (bytes), 0 if none.
    pub mul: u16,
    /// Widest division (bytes), 0 if none.
    pub div: u16,
    labels: BTreeMap<Helper, Label>,
}

impl HelperSet {
    /// The label of a helper, registering it as used.
    pub fn label(&mut self, labels: &mut Vec<String>, h: Helper) -> Label {
        *self.labels.entry(h).or_insert_with(|| {
            labels.push(match h {
                Helper::Mul(n) => format!("plc_mul{}", 8 * n),
                Helper::Div(n) => format!("plc_divu{}", 8 * n),
                Helper::BitMask => "plc_bitmask".to_string(),
            });
            Label(labels.len() as u32 - 1)
        })
    }

    /// The code of every helper used, in a stable order.
    pub fn units(&self, ws: Workspace) -> Vec<Unit> {
        self.labels
            .iter()
            .map(|(&h, &l)| {
                let mut items = vec![Item::Label(l)];
                let mut e = Code(&mut items);
                match h {
                    Helper::Mul(n) => e.mul(ws, n),
                    Helper::Div(n) => e.div(ws, n),
                    Helper::BitMask => e.bitmask(),
                }
                Unit {
                    name: format!("{h:?}"),
                    items,
                    ..Default::default()
                }
            })
            .collect()
    }
}

struct Code<'a>(&'a mut Vec<Item>);

impl Code<'_> {
    fn i(&mut self, i: Inst) {
        self.0.push(Item::Op(Op::I(i)));
    }

    fn local(&mut self) -> LocalLabel {
        LocalLabel(self.0.len())
    }

    /// `d += s` over n bytes (registers in one bank).
    fn add(&mut self, d: u16, s: u16, n: u16) {
        self.i(Inst::Movf(s, Dest::W));
        self.i(Inst::Addwf(d, Dest::F));
        for k in 1..n {
            self.i(Inst::Movf(s + k, Dest::W));
            self.i(Inst::Btfsc(reg::STATUS, reg::C));
            self.i(Inst::Incfsz(s + k, Dest::W));
            self.i(Inst::Addwf(d + k, Dest::F));
        }
    }

    /// `d -= s` over n bytes; C = 0 afterwards means a borrow.
    fn sub(&mut self, d: u16, s: u16, n: u16) {
        self.i(Inst::Movf(s, Dest::W));
        self.i(Inst::Subwf(d, Dest::F));
        for k in 1..n {
            self.i(Inst::Movf(s + k, Dest::W));
            self.i(Inst::Btfss(reg::STATUS, reg::C));
            self.i(Inst::Incfsz(s + k, Dest::W));
            self.i(Inst::Subwf(d + k, Dest::F));
        }
    }

    /// R := 0 and the counter := one round per bit; the loop's top.
    fn start_loop(&mut self, ws: Workspace, n: u16) -> LocalLabel {
        for k in 0..n {
            self.i(Inst::Clrf(ws.r + k));
        }
        self.i(Inst::Movlw((8 * n) as u8));
        self.i(Inst::Movwf(ws.cnt));
        self.local()
    }

    fn mul(&mut self, ws: Workspace, n: u16) {
        let (a, b, r) = (ws.a, ws.b, ws.r);
        let top = self.start_loop(ws, n);
        // B >>= 1; C = the bit shifted out.
        self.i(Inst::Bcf(reg::STATUS, reg::C));
        for k in (0..n).rev() {
            self.i(Inst::Rrf(b + k, Dest::F));
        }
        let skip_at = self.0.len();
        self.i(Inst::Btfss(reg::STATUS, reg::C));
        self.0.push(Item::Comment(String::new())); // placeholder for `goto noadd`
        self.add(r, a, n);
        let noadd = self.local();
        self.i(Inst::Bcf(reg::STATUS, reg::C));
        for k in 0..n {
            self.i(Inst::Rlf(a + k, Dest::F));
        }
        self.i(Inst::Decfsz(ws.cnt, Dest::F));
        self.0.push(Item::Comment(String::new())); // placeholder for `goto top`
        let back = self.0.len() - 1;
        self.i(Inst::Return);
        self.patch(skip_at + 1, noadd);
        self.patch(back, top);
    }

    fn div(&mut self, ws: Workspace, n: u16) {
        let (a, b, r) = (ws.a, ws.b, ws.r);
        let top = self.start_loop(ws, n);
        // R:A <<= 1
        self.i(Inst::Bcf(reg::STATUS, reg::C));
        for k in 0..n {
            self.i(Inst::Rlf(a + k, Dest::F));
        }
        for k in 0..n {
            self.i(Inst::Rlf(r + k, Dest::F));
        }
        // A carry out of R means R >= B for sure.
        self.i(Inst::Btfsc(reg::STATUS, reg::C));
        let to_force = self.placeholder();
        self.sub(r, b, n);
        self.i(Inst::Btfsc(reg::STATUS, reg::C));
        let to_keep = self.placeholder();
        self.add(r, b, n);
        let to_next = self.placeholder();
        let force = self.local();
        self.sub(r, b, n);
        let keep = self.local();
        self.i(Inst::Bsf(a, 0));
        let next = self.local();
        self.i(Inst::Decfsz(ws.cnt, Dest::F));
        let back = self.placeholder();
        self.i(Inst::Return);
        self.patch(to_force, force);
        self.patch(to_keep, keep);
        self.patch(to_next, next);
        self.patch(back, top);
    }

    fn bitmask(&mut self) {
        self.i(Inst::Movwf(H0));
        self.i(Inst::Movlw(1));
        self.i(Inst::Btfsc(H0, 1));
        self.i(Inst::Movlw(2));
        self.i(Inst::Movwf(H1));
        self.i(Inst::Bcf(reg::STATUS, reg::C));
        self.i(Inst::Btfsc(H0, 2));
        self.i(Inst::Rlf(H1, Dest::F));
        self.i(Inst::Btfsc(H0, 2));
        self.i(Inst::Rlf(H1, Dest::F));
        self.i(Inst::Btfsc(H0, 3));
        self.i(Inst::Swapf(H1, Dest::F));
        self.i(Inst::Movf(H1, Dest::W));
        self.i(Inst::Return);
    }

    fn placeholder(&mut self) -> usize {
        self.0.push(Item::Comment(String::new()));
        self.0.len() - 1
    }

    /// Turns the placeholder at `at` into a jump to the item index `to`, which gets
    /// a label (labels inside helpers are item positions, resolved by `finish`).
    fn patch(&mut self, at: usize, to: LocalLabel) {
        self.0[at] = Item::Comment(format!("@goto {}", to.0));
    }
}

/// A position in a helper's item list, made a real label by [`resolve_local`].
#[derive(Copy, Clone)]
struct LocalLabel(usize);

/// Replaces `@goto N` placeholders by labels (registered in `labels`).
pub fn resolve_local(unit: &mut Unit, labels: &mut Vec<String>) {
    let mut targets: BTreeMap<usize, Label> = BTreeMap::new();
    for it in &unit.items {
        if let Item::Comment(c) = it {
            if let Some(n) = c.strip_prefix("@goto ") {
                let n: usize = n.parse().expect("placeholder");
                let next = targets.len();
                targets.entry(n).or_insert_with(|| {
                    labels.push(format!("{}_L{next}", unit_prefix(&unit.name)));
                    Label(labels.len() as u32 - 1)
                });
            }
        }
    }
    let old = std::mem::take(&mut unit.items);
    for (i, it) in old.into_iter().enumerate() {
        if let Some(l) = targets.get(&i) {
            unit.items.push(Item::Label(*l));
        }
        match it {
            Item::Comment(c) if c.starts_with("@goto ") => {
                let n: usize = c["@goto ".len()..].parse().expect("placeholder");
                unit.items.push(Item::Op(Op::Goto(targets[&n])));
            }
            Item::Comment(c) if c.is_empty() => {}
            other => unit.items.push(other),
        }
    }
}

fn unit_prefix(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect::<String>()
        .trim_end_matches('_')
        .replace("__", "_")
}
