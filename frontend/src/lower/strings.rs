//! STRING and WSTRING: their IR arrays, string values, assignment, comparison and the
//! string functions.
//!
//! A string value is the address of its characters (`cap + 1` of them, the text
//! ended by a 0; see `stdlib/strings.st`). Variables give their own address; a
//! literal is stored into a temporary; a function's result is written into a
//! temporary of the caller's. Operations call the helpers of `stdlib/strings.st`
//! (written in ST, so every target gets them), passing every string as an address
//! and its capacity.

use super::body::{BodyCx, Place};
use super::expr::Val;
use super::Lowerer;
use crate::ast::{BinaryOp as Op, Expr, ExprKind, LiteralKind};
use crate::codes;
use crate::types::{StrTy, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{AggDef, AggId, ArrayDef, BinaryOp, ElemType, IntCC, MemType, Type, Value};

/// Literals up to this many characters are stored character by character where they
/// are assigned; longer ones are stored once into a temporary and copied.
const INLINE_LITERAL_MAX: usize = 64;

/// A string function of IEC 61131-3 (table 43), or a conversion to or from a string.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum StrFn {
    /// `LEN(IN)`
    Len,
    /// `LEFT(IN, L)`
    Left,
    /// `RIGHT(IN, L)`
    Right,
    /// `MID(IN, L, P)`
    Mid,
    /// `CONCAT(IN1, IN2, ...)`
    Concat,
    /// `INSERT(IN1, IN2, P)`
    Insert,
    /// `DELETE(IN, L, P)`
    Delete,
    /// `REPLACE(IN1, IN2, L, P)`
    Replace,
    /// `FIND(IN1, IN2)`
    Find,
    /// `X_TO_STRING`, `TO_STRING`, `X_TO_WSTRING`, `TO_WSTRING` (`from` is `None`
    /// for the generic form).
    ToString { from: Option<ElemType>, wide: bool },
    /// `STRING_TO_X`, `WSTRING_TO_X`.
    FromString { wide: bool, to: ElemType },
    /// `STRING_TO_WSTRING`, `WSTRING_TO_STRING`.
    Widen { to_wide: bool },
}

impl StrFn {
    /// The string function with this (upper-case) name.
    pub(super) fn lookup(name: &str) -> Option<StrFn> {
        use StrFn::*;
        Some(match name {
            "LEN" => Len,
            "LEFT" => Left,
            "RIGHT" => Right,
            "MID" => Mid,
            "CONCAT" => Concat,
            "INSERT" => Insert,
            "DELETE" => Delete,
            "REPLACE" => Replace,
            "FIND" => Find,
            "TO_STRING" => ToString {
                from: None,
                wide: false,
            },
            "TO_WSTRING" => ToString {
                from: None,
                wide: true,
            },
            "STRING_TO_WSTRING" => Widen { to_wide: true },
            "WSTRING_TO_STRING" => Widen { to_wide: false },
            _ => {
                let elem = |s: &str| ElemType::from_name(s).filter(|e| *e != ElemType::Ref);
                if let Some(from) = name.strip_suffix("_TO_STRING") {
                    return Some(ToString {
                        from: Some(elem(from)?),
                        wide: false,
                    });
                }
                if let Some(from) = name.strip_suffix("_TO_WSTRING") {
                    return Some(ToString {
                        from: Some(elem(from)?),
                        wide: true,
                    });
                }
                if let Some(to) = name.strip_prefix("STRING_TO_") {
                    return Some(FromString {
                        wide: false,
                        to: elem(to)?,
                    });
                }
                if let Some(to) = name.strip_prefix("WSTRING_TO_") {
                    return Some(FromString {
                        wide: true,
                        to: elem(to)?,
                    });
                }
                return None;
            }
        })
    }

    /// Formal parameter names, in positional order.
    pub(super) fn param_name(self, i: usize) -> String {
        use StrFn::*;
        let names: &[&str] = match self {
            Len | ToString { .. } | FromString { .. } | Widen { .. } => &["IN"],
            Left | Right => &["IN", "L"],
            Mid => &["IN", "L", "P"],
            Insert => &["IN1", "IN2", "P"],
            Delete => &["IN", "L", "P"],
            Replace => &["IN1", "IN2", "L", "P"],
            Find => &["IN1", "IN2"],
            Concat => return format!("IN{}", i + 1),
        };
        names.get(i).unwrap_or(&"?").to_string()
    }

    /// (minimum, maximum) number of inputs.
    pub(super) fn arity(self) -> (usize, usize) {
        use StrFn::*;
        match self {
            Len | ToString { .. } | FromString { .. } | Widen { .. } => (1, 1),
            Left | Right | Find => (2, 2),
            Mid | Insert | Delete => (3, 3),
            Replace => (4, 4),
            Concat => (2, usize::MAX),
        }
    }
}

impl Lowerer<'_> {
    /// The IR array of a string type: `cap + 1` characters.
    pub(super) fn string_agg(&mut self, s: StrTy) -> AggId {
        if let Some(&agg) = self.string_aggs.get(&s) {
            return agg;
        }
        let elem = if s.wide { Type::I16 } else { Type::I8 };
        let agg = self.module.add_agg(AggDef::Array(ArrayDef {
            name: format!("{}{}", if s.wide { "wstr" } else { "str" }, s.cap),
            elem: MemType::Scalar(elem),
            // Not listed as variables: the characters past the end hold anything.
            elem_type: None,
            len: s.cap + 1,
            lower: 0,
        }));
        self.string_aggs.insert(s, agg);
        agg
    }
}

impl<'s> BodyCx<'_, 's> {
    /// Calls the string helper `name` (`LEN`, `COPY`, ...) of the given width with
    /// `args` in its declaration order: its result, if it has one.
    pub(super) fn call_helper(
        &mut self,
        wide: bool,
        name: &str,
        args: Vec<Value>,
    ) -> Option<Value> {
        let full = format!("{}{name}", if wide { "__WSTR_" } else { "__STR_" });
        let sym = self.l.interner.intern(&full);
        let p = *self.l.pou_by_name.get(&sym)?;
        self.l.use_std_function(p);
        let f = self.l.ir[p.0 as usize].body?;
        let ret = self.l.pou(p).ret.ir();
        self.b.call(f, ret, args)
    }

    /// A capacity or count as the helpers take it (INT).
    fn int_arg(&mut self, n: u32) -> Value {
        self.b.iconst(Type::I16, n as i64)
    }

    /// A temporary string of type `s` (its text is undefined until written).
    pub(super) fn string_temp(&mut self, s: StrTy) -> Value {
        let agg = self.l.string_agg(s);
        let slot = self.b.slot("string", MemType::Agg(agg));
        self.b.slot_addr(slot)
    }

    /// Stores the characters `units` (cut to the capacity) and the terminating 0 at
    /// `dst`.
    fn store_units(&mut self, dst: Value, s: StrTy, units: &[u16]) {
        let agg = self.l.string_agg(s);
        let t = if s.wide { Type::I16 } else { Type::I8 };
        let n = units.len().min(s.cap as usize);
        for (i, &u) in units[..n].iter().chain(std::iter::once(&0)).enumerate() {
            let idx = self.b.iconst(Type::I16, i as i64);
            let a = self.b.elem_addr(dst, agg, idx);
            let c = self.b.iconst(t, u as i64);
            self.b.store(c, a);
        }
    }

    /// The type a string literal has: its own length as the capacity.
    pub(super) fn literal_string_ty(wide: bool, units: &[u16]) -> Ty {
        Ty::Str(StrTy {
            wide,
            cap: (units.len() as u32).clamp(1, StrTy::MAX_CAP),
        })
    }

    /// The characters of a string literal (after a `STRING#` prefix, if any).
    fn literal_units(e: &Expr) -> Option<(bool, &[u16])> {
        let mut e = e;
        while let ExprKind::Paren(x) = &e.kind {
            e = x;
        }
        match &e.kind {
            ExprKind::Literal(lit) => match &lit.kind {
                LiteralKind::String { wide, units } => Some((*wide, units.as_slice())),
                _ => None,
            },
            _ => None,
        }
    }

    /// Emits a string literal: a temporary holding its text.
    pub(super) fn string_literal(&mut self, e: &'s Expr, want: Option<Ty>) -> Val {
        let Some((wide, units)) = Self::literal_units(e) else {
            return self.error_val();
        };
        // A literal meant for the other width is converted (its characters fit: a
        // STRING literal's bytes are Latin-1, and a WSTRING literal wanted as a STRING
        // is reported by the caller's type check).
        let wide = match want {
            Some(Ty::Str(w)) if w.wide && !wide => true,
            _ => wide,
        };
        if !wide && units.iter().any(|&u| u > 0xFF) {
            self.l.error(
                codes::E_TYPE_MISMATCH,
                "this character does not fit a STRING (one byte per character): write a WSTRING literal in double quotes",
                e.span,
            );
            return self.error_val();
        }
        if units.len() > StrTy::MAX_CAP as usize {
            self.l.error(
                codes::E_LITERAL_RANGE,
                format!(
                    "a string literal of {} characters is longer than the longest string ({})",
                    units.len(),
                    StrTy::MAX_CAP
                ),
                e.span,
            );
            return self.error_val();
        }
        let ty = Self::literal_string_ty(wide, units);
        let s = ty.string().expect("string type");
        let t = self.string_temp(s);
        self.store_units(t, s, units);
        Val { v: t, ty }
    }

    /// Emits an expression that must be a string of the given width (`None`: either).
    /// Reports anything else.
    pub(super) fn emit_string(&mut self, e: &'s Expr, wide: Option<bool>) -> Option<Val> {
        let want = wide.map(|w| {
            Ty::Str(StrTy {
                wide: w,
                cap: StrTy::DEFAULT_CAP,
            })
        });
        let v = self.emit(e, want);
        match v.ty {
            Ty::Str(s) if wide.is_none_or(|w| w == s.wide) => Some(v),
            Ty::Error => None,
            t => {
                let want = match wide {
                    Some(true) => "a WSTRING",
                    Some(false) => "a STRING",
                    None => "a STRING or WSTRING",
                };
                let literal = self.infer(e).is_literal();
                let found = if literal {
                    match t {
                        Ty::Elem(x) if x.is_real() => "a real literal".to_string(),
                        _ => "an integer literal".to_string(),
                    }
                } else {
                    self.l.ty_name(t)
                };
                let mut d = plcc_ir::diag::Diagnostic::error(
                    codes::E_TYPE_MISMATCH,
                    format!("expected {want}, found {found}"),
                    e.span,
                );
                if let (Some(w), Ty::Str(_)) = (wide, t) {
                    let (from, to) = if w {
                        ("STRING", "WSTRING")
                    } else {
                        ("WSTRING", "STRING")
                    };
                    d = d.with_note(format!("convert explicitly: `{from}_TO_{to}(...)`"));
                } else if literal {
                    let text = self.l.text(e.span).to_string();
                    d = d.with_note(format!("write a string literal in quotes: '{text}'"));
                } else if t.elem().is_some() {
                    d = d.with_note(format!(
                        "convert explicitly, e.g. `{found}_TO_{}(...)`",
                        if wide == Some(true) {
                            "WSTRING"
                        } else {
                            "STRING"
                        }
                    ));
                }
                self.l.diags.push(d);
                None
            }
        }
    }

    /// Copies the string at `src` into `dst`, cut to the capacity of `s` (`dst` may
    /// be `src`).
    pub(super) fn copy_string(&mut self, dst: Value, s: StrTy, src: Value) {
        let cap = self.int_arg(s.cap);
        self.call_helper(s.wide, "COPY", vec![dst, src, cap]);
    }

    /// Sets a string variable to the empty string.
    pub(super) fn clear_string(&mut self, dst: Value, s: StrTy) {
        self.store_units(dst, s, &[]);
    }

    /// `target := value` for a string: the value's text, cut to the target's
    /// capacity. A short literal is stored in place.
    pub(super) fn assign_string(&mut self, place: &Place, value: &'s Expr) {
        let Ty::Str(s) = place.ty else { return };
        if let Some((wide, units)) = Self::literal_units(value) {
            if units.len() <= INLINE_LITERAL_MAX && (wide == s.wide || !wide) {
                let units = units.to_vec();
                let dst = place.addr;
                self.guarded(place.guard, |cx| cx.store_units(dst, s, &units));
                return;
            }
        }
        let Some(v) = self.emit_string(value, Some(s.wide)) else {
            return;
        };
        let dst = place.addr;
        self.guarded(place.guard, |cx| cx.copy_string(dst, s, v.v));
    }

    /// The initial value of a string variable at `addr`: the literal, or empty. A
    /// variable in an instance or a global is cleared whole first, so its unused
    /// characters are the same on every machine.
    pub(super) fn init_string(
        &mut self,
        addr: Value,
        s: StrTy,
        init: Option<&'s crate::ast::Init>,
        whole: bool,
    ) {
        if whole {
            self.fill_zero(addr, s);
        }
        match init {
            None => self.clear_string(addr, s),
            Some(crate::ast::Init::Expr(e)) => {
                let p = Place::new(addr, Ty::Str(s));
                self.assign_string(&p, e);
            }
            Some(other) => {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("a {} is initialised with a single value", s.name()),
                    other.span(),
                );
            }
        }
    }

    /// Stores 0 into every character of the string at `addr`.
    fn fill_zero(&mut self, addr: Value, s: StrTy) {
        let agg = self.l.string_agg(s);
        let t = if s.wide { Type::I16 } else { Type::I8 };
        self.counted_loop(Type::I16, s.cap as i64 + 1, |cx, i| {
            let a = cx.b.elem_addr(addr, agg, i);
            let z = cx.b.iconst(t, 0);
            cx.b.store(z, a);
        });
    }

    /// A comparison of two strings (`=`, `<>`, `<`, ...): by character codes, a
    /// prefix before the longer string.
    pub(super) fn compare_strings(&mut self, op: Op, a: &'s Expr, b: &'s Expr, span: Span) -> Val {
        let (ta, tb) = (self.infer(a), self.infer(b));
        let wide = match (ta, tb) {
            (Ty::Str(x), _) => x.wide,
            (_, Ty::Str(y)) => y.wide,
            _ => false,
        };
        let (Some(x), Some(y)) = (
            self.emit_string(a, Some(wide)),
            self.emit_string(b, Some(wide)),
        ) else {
            let v = self.b.iconst(Type::I1, 0);
            return Val { v, ty: Ty::BOOL };
        };
        let _ = span;
        let v = self.string_cmp(op, x, y, wide);
        Val { v, ty: Ty::BOOL }
    }

    /// `x op y` on two emitted strings of one width: a BOOL.
    pub(super) fn string_cmp(&mut self, op: Op, x: Val, y: Val, wide: bool) -> Value {
        let (xs, ys) = (
            x.ty.string().expect("string"),
            y.ty.string().expect("string"),
        );
        let (xc, yc) = (self.int_arg(xs.cap), self.int_arg(ys.cap));
        let c = self
            .call_helper(wide, "CMP", vec![x.v, y.v, xc, yc])
            .unwrap_or_else(|| self.b.iconst(Type::I16, 0));
        let zero = self.b.iconst(Type::I16, 0);
        let cc = match op {
            Op::Eq => IntCC::Eq,
            Op::Ne => IntCC::Ne,
            Op::Lt => IntCC::Slt,
            Op::Le => IntCC::Sle,
            Op::Gt => IntCC::Sgt,
            _ => IntCC::Sge,
        };
        self.b.icmp(cc, c, zero)
    }

    /// A comparison function (`EQ`, `NE`, `LT`, `LE`, `GT`, `GE`) whose inputs are
    /// strings (IEC 61131-3 defines them on every elementary type, strings included):
    /// `GT(a, b, c)` is `a > b AND b > c`, each input evaluated once; every input is a
    /// string of the width of the first string among them.
    pub(super) fn compare_string_args(&mut self, op: Op, xs: &[&'s Expr]) -> Option<Val> {
        let tys: Vec<Ty> = xs.iter().map(|x| self.infer(x)).collect();
        let wide = tys.iter().find_map(|t| t.string())?.wide;
        let vals: Vec<Option<Val>> = xs.iter().map(|x| self.emit_string(x, Some(wide))).collect();
        let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
        let mut acc: Option<Value> = None;
        for w in vals.windows(2) {
            let c = self.string_cmp(op, w[0], w[1], wide);
            acc = Some(match acc {
                Some(a) => self.b.binary(BinaryOp::Band, a, c),
                None => c,
            });
        }
        Some(Val {
            v: acc?,
            ty: Ty::BOOL,
        })
    }

    /// The result type of a string function, without emitting anything.
    pub(super) fn string_fn_infer(
        &mut self,
        f: StrFn,
        arg_ty: &mut dyn FnMut(&mut Self, usize) -> Ty,
        nargs: usize,
    ) -> Ty {
        use StrFn::*;
        let st = |t: Ty| t.string();
        match f {
            Len | Find => Ty::Elem(ElemType::Int),
            Left | Right | Mid | Delete => arg_ty(self, 0),
            Concat => {
                let mut cap = 0u32;
                let mut wide = false;
                for i in 0..nargs {
                    match st(arg_ty(self, i)) {
                        Some(s) => {
                            cap += s.cap;
                            wide = s.wide;
                        }
                        None => return Ty::Error,
                    }
                }
                Ty::Str(StrTy {
                    wide,
                    cap: cap.min(StrTy::MAX_CAP),
                })
            }
            Insert | Replace => match (st(arg_ty(self, 0)), st(arg_ty(self, 1))) {
                (Some(a), Some(b)) => Ty::Str(StrTy {
                    wide: a.wide,
                    cap: (a.cap + b.cap).min(StrTy::MAX_CAP),
                }),
                _ => Ty::Error,
            },
            ToString { wide, .. } => Ty::Str(StrTy {
                wide,
                cap: StrTy::DEFAULT_CAP,
            }),
            FromString { to, .. } => Ty::Elem(to),
            Widen { to_wide } => match st(arg_ty(self, 0)) {
                Some(s) => Ty::Str(StrTy {
                    wide: to_wide,
                    cap: s.cap,
                }),
                None => Ty::Error,
            },
        }
    }

    /// Emits a call of a string function with its arguments in positional order.
    pub(super) fn string_fn_call(
        &mut self,
        f: StrFn,
        xs: &[&'s Expr],
        name: &str,
        want: Option<Ty>,
    ) -> Option<Val> {
        use StrFn::*;
        let int = Ty::Elem(ElemType::Int);
        match f {
            Len => {
                let s = self.emit_string(xs[0], None)?;
                let st = s.ty.string()?;
                let cap = self.int_arg(st.cap);
                let v = self.call_helper(st.wide, "LEN", vec![s.v, cap])?;
                Some(Val { v, ty: int })
            }
            Find => {
                let a = self.emit_string(xs[0], None)?;
                let sa = a.ty.string()?;
                let b = self.emit_string(xs[1], Some(sa.wide))?;
                let sb = b.ty.string()?;
                let (ac, bc) = (self.int_arg(sa.cap), self.int_arg(sb.cap));
                let v = self.call_helper(sa.wide, "FIND", vec![a.v, b.v, ac, bc])?;
                Some(Val { v, ty: int })
            }
            Left | Right | Mid | Delete => {
                let s = self.emit_string(xs[0], None)?;
                let st = s.ty.string()?;
                let mut nums = Vec::new();
                for x in &xs[1..] {
                    nums.push(self.emit_as(x, int));
                }
                let d = self.string_temp(st);
                let (dc, sc) = (self.int_arg(st.cap), self.int_arg(st.cap));
                let helper = match f {
                    Left => "LEFT",
                    Right => "RIGHT",
                    Mid => "MID",
                    _ => "DELETE",
                };
                let mut args = vec![d, s.v, dc, sc];
                args.extend(nums);
                self.call_helper(st.wide, helper, args);
                Some(Val { v: d, ty: s.ty })
            }
            Insert | Replace => {
                let a = self.emit_string(xs[0], None)?;
                let sa = a.ty.string()?;
                let b = self.emit_string(xs[1], Some(sa.wide))?;
                b.ty.string()?;
                let mut nums = Vec::new();
                for x in &xs[2..] {
                    nums.push(self.emit_as(x, int));
                }
                let helper = if f == Insert { "INSERT" } else { "REPLACE" };
                Some(self.join_strings(helper, a, b, nums))
            }
            Concat => {
                let first = self.emit_string(xs[0], None)?;
                let mut acc = first;
                for x in &xs[1..] {
                    let sa = acc.ty.string()?;
                    let b = self.emit_string(x, Some(sa.wide))?;
                    acc = self.join_strings("CONCAT", acc, b, Vec::new());
                }
                Some(acc)
            }
            Widen { to_wide } => {
                let s = self.emit_string(xs[0], Some(!to_wide))?;
                let st = s.ty.string()?;
                let rs = StrTy {
                    wide: to_wide,
                    cap: st.cap,
                };
                let d = self.string_temp(rs);
                self.convert_width(d, rs, s.v, st);
                Some(Val {
                    v: d,
                    ty: Ty::Str(rs),
                })
            }
            ToString { from, wide } => self.text_of(xs[0], from, wide, name),
            FromString { wide, to } => self.parse_string(xs[0], wide, to, name, want),
        }
    }

    /// Calls a helper that builds a string from two (`CONCAT`, `INSERT`, `REPLACE`)
    /// into a new temporary long enough for both, with `nums` after the capacities.
    fn join_strings(&mut self, helper: &str, a: Val, b: Val, nums: Vec<Value>) -> Val {
        let (Some(sa), Some(sb)) = (a.ty.string(), b.ty.string()) else {
            return a;
        };
        let rs = StrTy {
            wide: sa.wide,
            cap: (sa.cap + sb.cap).min(StrTy::MAX_CAP),
        };
        let d = self.string_temp(rs);
        let (dc, ac, bc) = (
            self.int_arg(rs.cap),
            self.int_arg(sa.cap),
            self.int_arg(sb.cap),
        );
        let mut args = vec![d, a.v, b.v, dc, ac, bc];
        args.extend(nums);
        self.call_helper(sa.wide, helper, args);
        Val {
            v: d,
            ty: Ty::Str(rs),
        }
    }

    /// Copies a string into one of the other width, character by character
    /// (WSTRING to STRING keeps the low byte of each character).
    fn convert_width(&mut self, dst: Value, ds: StrTy, src: Value, ss: StrTy) {
        let (dagg, sagg) = (self.l.string_agg(ds), self.l.string_agg(ss));
        let (dt, st) = (
            if ds.wide { Type::I16 } else { Type::I8 },
            if ss.wide { Type::I16 } else { Type::I8 },
        );
        let header = self.b.create_block();
        let exit = self.b.create_block();
        let i = self.b.block_param(header, Type::I16);
        let zero = self.b.iconst(Type::I16, 0);
        self.b.jump(header, vec![zero]);
        self.b.switch_to(header);
        let sa = self.b.elem_addr(src, sagg, i);
        let c = self.b.load(st, sa);
        let c = match (st, dt) {
            (Type::I8, Type::I16) => self.b.convert(plcc_ir::ConvOp::Uext, Type::I16, c),
            (Type::I16, Type::I8) => self.b.convert(plcc_ir::ConvOp::Itrunc, Type::I8, c),
            _ => c,
        };
        let da = self.b.elem_addr(dst, dagg, i);
        self.b.store(c, da);
        let z = self.b.iconst(dt, 0);
        let more = self.b.icmp(IntCC::Ne, c, z);
        let cap = self.b.iconst(Type::I16, ds.cap.min(ss.cap) as i64);
        let room = self.b.icmp(IntCC::Slt, i, cap);
        let go = self.b.binary(plcc_ir::BinaryOp::Band, more, room);
        let one = self.b.iconst(Type::I16, 1);
        let next = self.b.binary(plcc_ir::BinaryOp::Iadd, i, one);
        self.b.brif(go, header, vec![next], exit, vec![]);
        // The loop stops at the terminator or at the capacity; in the second case
        // the last character stored is replaced by the terminator.
        self.b.switch_to(exit);
        let last = self.b.iconst(Type::I16, ds.cap.min(ss.cap) as i64);
        let la = self.b.elem_addr(dst, dagg, last);
        let z = self.b.iconst(dt, 0);
        self.b.store(z, la);
    }

    /// `X_TO_STRING(v)`: the value as text (integers in decimal, BOOL as TRUE/FALSE,
    /// reals with 7 (REAL) or 15 (LREAL) significant digits).
    fn text_of(
        &mut self,
        x: &'s Expr,
        from: Option<ElemType>,
        wide: bool,
        name: &str,
    ) -> Option<Val> {
        let rs = StrTy {
            wide,
            cap: StrTy::DEFAULT_CAP,
        };
        let want = from.map(Ty::Elem);
        let v = match want {
            Some(t) => {
                let v = self.emit_as(x, t);
                Val { v, ty: t }
            }
            None => self.emit(x, None),
        };
        if let Ty::Str(s) = v.ty {
            // TO_STRING of a string: a copy (or a change of width).
            let d = self.string_temp(rs);
            if s.wide == wide {
                self.copy_string(d, rs, v.v);
            } else {
                self.convert_width(d, rs, v.v, s);
            }
            return Some(Val {
                v: d,
                ty: Ty::Str(rs),
            });
        }
        let e = match v.ty {
            Ty::Elem(e) => e,
            Ty::AnyInt | Ty::AnyReal => {
                let t = super::typing::concretize(v.ty, None);
                return self.format_value(Val { v: v.v, ty: t }, rs, x.span);
            }
            Ty::Error => return None,
            t => {
                let tn = self.l.ty_name(t);
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("`{name}` cannot convert a {tn} to a string"),
                    x.span,
                );
                return None;
            }
        };
        self.format_value(
            Val {
                v: v.v,
                ty: Ty::Elem(e),
            },
            rs,
            x.span,
        )
    }

    /// The text of an elementary value `v` in a new string of type `rs`.
    fn format_value(&mut self, v: Val, rs: StrTy, span: Span) -> Option<Val> {
        let Ty::Elem(e) = v.ty else { return None };
        let d = self.string_temp(rs);
        let dc = self.int_arg(rs.cap);
        use ElemType::*;
        match e {
            Bool => {
                // TRUE or FALSE: both texts, one chosen.
                let t = self.string_temp(StrTy {
                    wide: rs.wide,
                    cap: 5,
                });
                let f = self.string_temp(StrTy {
                    wide: rs.wide,
                    cap: 5,
                });
                self.store_units(
                    t,
                    StrTy {
                        wide: rs.wide,
                        cap: 5,
                    },
                    &[84, 82, 85, 69],
                );
                self.store_units(
                    f,
                    StrTy {
                        wide: rs.wide,
                        cap: 5,
                    },
                    &[70, 65, 76, 83, 69],
                );
                let src = self.b.select(v.v, t, f);
                self.copy_string(d, rs, src);
            }
            Real | LReal => {
                let x = if e == Real {
                    self.b.convert(plcc_ir::ConvOp::Fpromote, Type::F64, v.v)
                } else {
                    v.v
                };
                let prec = self.int_arg(if e == Real { 7 } else { 15 });
                self.call_helper(rs.wide, "FROM_LREAL", vec![d, dc, x, prec]);
            }
            LInt | ULInt | LWord => {
                let u = self.b.iconst(Type::I1, (e != LInt) as i64);
                self.call_helper(rs.wide, "FROM_LINT", vec![d, dc, v.v, u]);
            }
            _ if e.is_integer() || e.is_bit_string() || matches!(e, Char | WChar) => {
                let it = e.ir_type();
                let x = match it {
                    Type::I32 => v.v,
                    _ if e.is_signed() => self.b.convert(plcc_ir::ConvOp::Sext, Type::I32, v.v),
                    _ => self.b.convert(plcc_ir::ConvOp::Uext, Type::I32, v.v),
                };
                let u = self.b.iconst(Type::I1, (!e.is_signed()) as i64);
                self.call_helper(rs.wide, "FROM_DINT", vec![d, dc, x, u]);
            }
            _ if super::timestr::is_time_like(e) => self.format_time(d, rs, v.v, e),
            other => {
                self.l.error(
                    codes::E_UNSUPPORTED,
                    format!(
                        "not supported yet: converting a {} to a string",
                        other.name()
                    ),
                    span,
                );
                return None;
            }
        }
        Some(Val {
            v: d,
            ty: Ty::Str(rs),
        })
    }

    /// `STRING_TO_X(s)`: the number the text starts with, 0 if it does not start
    /// with one; for BOOL, TRUE if the text is `TRUE` or a non-zero number.
    fn parse_string(
        &mut self,
        x: &'s Expr,
        wide: bool,
        to: ElemType,
        name: &str,
        _want: Option<Ty>,
    ) -> Option<Val> {
        let s = self.emit_string(x, Some(wide))?;
        let st = s.ty.string()?;
        let cap = self.int_arg(st.cap);
        let v = if to.is_real() {
            let r = self.call_helper(wide, "TO_LREAL", vec![s.v, cap])?;
            if to == ElemType::Real {
                self.b.convert(plcc_ir::ConvOp::Fdemote, Type::F32, r)
            } else {
                r
            }
        } else if to.is_integer() || (to.is_bit_string() && to != ElemType::Bool) {
            let r = self.call_helper(wide, "TO_LINT", vec![s.v, cap])?;
            match to.ir_type() {
                Type::I64 => r,
                t => self.b.convert(plcc_ir::ConvOp::Itrunc, t, r),
            }
        } else if to == ElemType::Bool {
            let r = self.call_helper(wide, "TO_LINT", vec![s.v, cap])?;
            let z = self.b.iconst(Type::I64, 0);
            let nz = self.b.icmp(IntCC::Ne, r, z);
            let t = self.string_temp(StrTy { wide, cap: 4 });
            self.store_units(t, StrTy { wide, cap: 4 }, &[84, 82, 85, 69]);
            let four = self.int_arg(4);
            let c = self.call_helper(wide, "CMP", vec![s.v, t, cap, four])?;
            let z16 = self.b.iconst(Type::I16, 0);
            let is_true = self.b.icmp(IntCC::Eq, c, z16);
            self.b.binary(plcc_ir::BinaryOp::Bor, nz, is_true)
        } else if super::timestr::is_time_like(to) {
            return self.parse_time(s.v, st, to);
        } else {
            self.l.error(
                codes::E_UNSUPPORTED,
                format!("not supported yet: `{name}`"),
                x.span,
            );
            return None;
        };
        Some(Val {
            v,
            ty: Ty::Elem(to),
        })
    }
}
