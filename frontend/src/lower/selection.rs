//! The selection functions of IEC 61131-3 (SEL, MUX, MAX, MIN, LIMIT) on STRING and
//! WSTRING inputs.
//!
//! The standard defines SEL and MUX on ANY and MAX, MIN and LIMIT on ANY_ELEMENTARY,
//! strings included. Strings of different declared lengths are one type here
//! (`STRING[3]` and `STRING[2]` are both STRING), as in matiec: the result is a
//! string of the width of the inputs and the largest capacity among them, so it holds
//! whichever input is chosen; assigning it cuts it to the target's capacity, as any
//! string assignment does. A string value is an address (see `strings.rs`), so the
//! chosen input is picked by its address and nothing is copied until the result is
//! assigned. MAX, MIN and LIMIT compare as `<` and `>` do: by character codes, a
//! prefix before the longer string.

use super::body::BodyCx;
use super::builtins::Builtin;
use super::expr::Val;
use crate::ast::{BinaryOp as Op, Expr};
use crate::types::{StrTy, Ty};
use plcc_ir::{ElemType, IntCC, Type, Value};

/// The index of the first data input of a selection function (after `G` or `K`).
fn first_data_input(b: Builtin) -> usize {
    match b {
        Builtin::Sel | Builtin::Mux => 1,
        _ => 0,
    }
}

/// True for the functions this module computes on strings.
pub(super) fn is_selection(b: Builtin) -> bool {
    matches!(
        b,
        Builtin::Sel | Builtin::Mux | Builtin::Max | Builtin::Min | Builtin::Limit
    )
}

/// The result type of a selection function whose inputs have the types `tys`, if one
/// of them is a string (`G` and `K` never are): a string of the width of the first
/// string and the largest capacity among the strings of that width.
pub(super) fn string_selection_type(tys: &[Ty]) -> Option<Ty> {
    let first = tys.iter().find_map(|t| t.string())?;
    let cap = tys
        .iter()
        .filter_map(|t| t.string())
        .filter(|s| s.wide == first.wide)
        .map(|s| s.cap)
        .max()
        .unwrap_or(first.cap);
    Some(Ty::Str(StrTy {
        wide: first.wide,
        cap,
    }))
}

impl<'s> BodyCx<'_, 's> {
    /// True if a data input of the selection function `b` is a string.
    pub(super) fn selects_strings(&mut self, b: Builtin, xs: &[&'s Expr]) -> bool {
        let tys: Vec<Ty> = xs.iter().map(|x| self.infer(x)).collect();
        is_selection(b)
            && string_selection_type(&tys[first_data_input(b).min(tys.len())..]).is_some()
    }

    /// SEL, MUX, MAX, MIN or LIMIT with string inputs (`xs` in positional order):
    /// every data input must be a string of the width of the first one (a string
    /// literal takes that width).
    pub(super) fn string_selection(
        &mut self,
        b: Builtin,
        xs: &[&'s Expr],
        name: &str,
    ) -> Option<Val> {
        let tys: Vec<Ty> = xs.iter().map(|x| self.infer(x)).collect();
        let first = first_data_input(b);
        let ty = string_selection_type(&tys[first..])?;
        let wide = ty.string()?.wide;
        // G or K first, then the inputs, each evaluated once, in order.
        let selector = match b {
            Builtin::Sel => Some(self.emit_as(xs[0], Ty::BOOL)),
            Builtin::Mux => Some(self.mux_selector(xs[0], name)?),
            _ => None,
        };
        let mut vals = Vec::new();
        let mut failed = false;
        for x in &xs[first..] {
            match self.emit_string(x, Some(wide)) {
                Some(v) => vals.push(v),
                None => failed = true,
            }
        }
        if failed {
            return None;
        }
        let v = match b {
            Builtin::Sel => self.b.select(selector?, vals[1].v, vals[0].v),
            Builtin::Mux => {
                let vs: Vec<Value> = vals.iter().map(|v| v.v).collect();
                self.mux_pick(selector?, &vs)
            }
            Builtin::Max | Builtin::Min => {
                let op = if b == Builtin::Max { Op::Gt } else { Op::Lt };
                // The first of equal inputs is kept, as for numbers.
                let mut acc = vals[0];
                for &y in &vals[1..] {
                    let c = self.string_cmp(op, y, acc, wide);
                    acc = Val {
                        v: self.b.select(c, y.v, acc.v),
                        ty,
                    };
                }
                acc.v
            }
            _ => {
                // LIMIT(MN, IN, MX) = MIN(MAX(IN, MN), MX).
                let (mn, x, mx) = (vals[0], vals[1], vals[2]);
                let below = self.string_cmp(Op::Lt, x, mn, wide);
                let lo = Val {
                    v: self.b.select(below, mn.v, x.v),
                    ty,
                };
                let above = self.string_cmp(Op::Gt, lo, mx, wide);
                self.b.select(above, mx.v, lo.v)
            }
        };
        Some(Val { v, ty })
    }

    /// The selector `K` of MUX as a LINT (any integer type; a literal is a DINT).
    pub(super) fn mux_selector(&mut self, k: &'s Expr, name: &str) -> Option<Value> {
        let kv = self.emit(k, Some(Ty::DINT));
        let ke = match kv.ty.elem() {
            Some(e) if kv.ty.is_int_like() => e,
            _ if kv.ty == Ty::Error => return None,
            _ => {
                self.bad_arg(name, "an integer selector", kv.ty, k.span);
                return None;
            }
        };
        Some(self.convert(kv.v, ke, ElemType::LInt))
    }

    /// The input `vals[k]` of MUX, with `k` a LINT; a selector out of range picks
    /// the nearest end (the first or the last input).
    pub(super) fn mux_pick(&mut self, k: Value, vals: &[Value]) -> Value {
        let last = vals.len() - 1;
        let mut acc = vals[last];
        for i in (0..last).rev() {
            let lim = self.b.iconst(Type::I64, i as i64);
            let cc = if i == 0 { IntCC::Sle } else { IntCC::Eq };
            let c = self.b.icmp(cc, k, lim);
            acc = self.b.select(c, vals[i], acc);
        }
        acc
    }
}
