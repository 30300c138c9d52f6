//! EN and ENO: `f(EN := cond, x, ENO => ok)` calls `f` only when `cond` is TRUE and
//! sets `ok` to whether it ran (IEC 61131-3, 6.6.1.4: every function and function
//! block call may take them). When EN is FALSE the outputs keep their values and a
//! function's value is its type's default. A standard function that can fail (the BCD
//! conversions) reports the error with [`BodyCx::set_eno_error`]: ENO is then FALSE.

use super::body::BodyCx;
use super::expr::Val;
use crate::ast::{Arg, ArgKind, Expr};
use crate::codes;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{Type, Value};

/// True if `a` is `EN := …` or `ENO => …`, which a call's own parameters skip.
pub(super) fn is_en_eno(cx_name: &str) -> bool {
    cx_name == "EN" || cx_name == "ENO"
}

impl<'s> BodyCx<'_, 's> {
    /// The `EN` value and the `ENO` target of a call's arguments, if any.
    pub(super) fn en_eno(&self, args: &'s [Arg]) -> (Option<&'s Expr>, Option<(&'s Expr, Span)>) {
        let mut en = None;
        let mut eno = None;
        for a in args {
            match &a.kind {
                ArgKind::Input { name, value } if self.l.sym_name(name.sym) == "EN" => {
                    en = Some(value);
                }
                ArgKind::Output {
                    name,
                    target: Some(t),
                    ..
                } if self.l.sym_name(name.sym) == "ENO" => eno = Some((t, a.span)),
                _ => {}
            }
        }
        (en, eno)
    }

    /// Runs `call` (which emits the call itself and gives its value, if any) under
    /// the call's EN, and stores ENO.
    pub(super) fn with_en_eno(
        &mut self,
        args: &'s [Arg],
        call: impl FnOnce(&mut Self) -> Option<Val>,
    ) -> Option<Val> {
        let (en, eno) = self.en_eno(args);
        if en.is_none() && eno.is_none() {
            let v = call(self);
            self.eno_error = None;
            return v;
        }
        let Some(en) = en else {
            // Without EN the call always runs: ENO is TRUE unless it failed.
            let v = call(self);
            let ok = self.eno_ok();
            self.store_eno(eno, ok);
            return v;
        };
        let cond = self.emit_as(en, Ty::BOOL);
        let run = self.b.create_block();
        let skip = self.b.create_block();
        let join = self.b.create_block();
        self.b.brif(cond, run, vec![], skip, vec![]);
        self.b.switch_to(run);
        let v = call(self);
        let ok = self.eno_ok();
        self.store_eno(eno, ok);
        // The value when EN is FALSE: the type's default (an empty string).
        let (param, value_ty) = match v {
            Some(v) if v.ty.ir().is_some() => (
                Some(self.b.block_param(join, v.ty.ir().expect("scalar"))),
                v.ty,
            ),
            Some(v) if matches!(v.ty, Ty::Str(_)) => {
                (Some(self.b.block_param(join, Type::Ptr)), v.ty)
            }
            Some(v) if v.ty != Ty::Error => {
                let t = self.l.ty_name(v.ty);
                self.l.error(
                    codes::E_UNSUPPORTED,
                    format!("not supported yet: EN on a call giving a whole {t}"),
                    en.span,
                );
                (None, Ty::Error)
            }
            _ => (None, Ty::Error),
        };
        self.b.jump(
            join,
            v.filter(|_| param.is_some())
                .map(|v| vec![v.v])
                .unwrap_or_default(),
        );
        self.b.switch_to(skip);
        let not_run = self.b.iconst(Type::I1, 0);
        self.store_eno(eno, not_run);
        let default = match value_ty {
            Ty::Str(s) => {
                let t = self.string_temp(s);
                self.clear_string(t, s);
                Some(t)
            }
            t if param.is_some() => Some(self.zero(t)),
            _ => None,
        };
        self.b
            .jump(join, default.map(|d| vec![d]).unwrap_or_default());
        self.b.switch_to(join);
        param.map(|p| Val { v: p, ty: value_ty })
    }

    /// Records that the standard function being emitted failed when `bad` is TRUE:
    /// the ENO of its call is then FALSE.
    pub(super) fn set_eno_error(&mut self, bad: Value) {
        self.eno_error = Some(bad);
    }

    /// ENO of a call that ran: TRUE, or FALSE where the function reported an error.
    fn eno_ok(&mut self) -> Value {
        match self.eno_error.take() {
            Some(bad) => {
                let f = self.b.iconst(Type::I1, 0);
                let t = self.b.iconst(Type::I1, 1);
                self.b.select(bad, f, t)
            }
            None => self.b.iconst(Type::I1, 1),
        }
    }

    fn store_eno(&mut self, eno: Option<(&'s Expr, Span)>, ok: Value) {
        let Some((target, _)) = eno else { return };
        let Some(place) = self.place(target) else {
            return;
        };
        if !self.check_writable(&place, target.span) {
            return;
        }
        if place.ty != Ty::BOOL && place.ty != Ty::Error {
            let t = self.l.ty_name(place.ty);
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("ENO is a BOOL, and this is a {t}"),
                target.span,
            );
            return;
        }
        self.store_place(&place, ok);
    }
}
