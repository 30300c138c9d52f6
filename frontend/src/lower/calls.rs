//! Calls of user FUNCTIONs and function block instances.

use super::aggregates::copied_whole;
use super::body::{BodyCx, Place};
use super::builtins::Builtin;
use super::consts::ConstVal;
use super::expr::Val;
use super::qualified::Qualifier;
use super::usertypes::TagDefault;
use super::{CallNode, Storage};
use crate::ast::{Arg, ArgKind, Expr, ExprKind, PouKind, VarKind};
use crate::codes;
use crate::types::{PouId, Ty};
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::{FuncId, MemType, SlotId, Type, UnaryOp, Value};

/// What a call expression calls.
enum Callee<'s> {
    /// An FB instance (its place) of the given FB type.
    Instance(Place, PouId),
    /// A user FUNCTION.
    Function(PouId),
    /// A standard function.
    Builtin(Builtin),
    /// An action, on the instance at the place, of the given POU.
    Action(FuncId, Place, PouId),
    /// A METHOD on an instance; bound statically (`SUPER^.M()`) or not.
    Method(super::methods::Expr2<'s>, PouId, bool),
    /// `SUPER^()`: the base's body on this instance.
    SuperBody,
    /// Already reported.
    Error,
}

/// One parameter of a POU as a call sees it.
#[derive(Copy, Clone)]
struct Param {
    /// The POU declaring it: the callee, or a base it inherits the parameter from.
    pou: PouId,
    var: usize,
    section: VarKind,
}

/// The parameters of `p`: those of its bases first (the farthest first), then its own.
fn params_of(cx: &BodyCx<'_, '_>, p: PouId) -> Vec<Param> {
    let mut lineage = cx.l.lineage(p);
    lineage.reverse();
    let mut out = Vec::new();
    for c in lineage {
        out.extend(
            cx.l.pou(c)
                .vars
                .iter()
                .enumerate()
                .filter(|(_, v)| {
                    matches!(v.section, VarKind::Input | VarKind::InOut | VarKind::Output)
                        && !v.constant
                })
                .map(|(i, v)| Param {
                    pou: c,
                    var: i,
                    section: v.section,
                }),
        );
    }
    out
}

impl<'s> BodyCx<'_, 's> {
    /// A call used as a statement.
    pub(super) fn call_stmt(&mut self, e: &'s Expr) {
        // IL's CAL calls function block instances only.
        let (e, cal) = match &e.kind {
            ExprKind::UsedBy { instr, value } => (&**value, Some(&**instr)),
            _ => (e, None),
        };
        let ExprKind::Call { callee, args } = &e.kind else {
            self.l.error(
                codes::NOT_A_STATEMENT,
                "this expression does nothing: only calls can be statements",
                e.span,
            );
            return;
        };
        let callee_kind = self.classify(callee, args);
        if let Some(instr) = cal {
            let what = match &callee_kind {
                Callee::Function(p) => Some(format!("FUNCTION `{}`", self.l.pou(*p).display)),
                Callee::Builtin(_) => Some(format!(
                    "the standard function `{}`",
                    self.l.text(callee.span)
                )),
                Callee::Instance(..)
                | Callee::Action(..)
                | Callee::Method(..)
                | Callee::SuperBody
                | Callee::Error => None,
            };
            if let Some(what) = what {
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::error(
                        codes::E_NOT_CALLABLE,
                        format!("`{instr}` calls a function block instance; {what} is not one"),
                        callee.span,
                    )
                    .with_label(format!("not a function block instance: `{instr}` cannot call it"))
                    .with_note(
                        "call a FUNCTION with its name as the operator: `LD x` then `NAME arg, ...`",
                    ),
                );
                return;
            }
        }
        if let Callee::Instance(place, _) = &callee_kind {
            // Calling an output of another instance would change it from outside.
            if place.access == super::body::Access::OtherOutput {
                if let Some(d) = self.output_write_error(callee, "call") {
                    self.l.diags.push(d);
                    return;
                }
            }
        }
        let span = e.span;
        // A call whose EN is FALSE leaves the FB's ENO FALSE (the call sets it TRUE
        // when it runs).
        if let (Callee::Instance(place, fb), (Some(_), _)) = (&callee_kind, self.en_eno(args)) {
            if let Some(addr) = self.eno_addr(place.addr, *fb) {
                let f = self.b.iconst(Type::I1, 0);
                self.b.store(f, addr);
            }
        }
        self.with_en_eno(args, |cx| {
            match callee_kind {
                Callee::Instance(place, fb) => cx.fb_call(place, fb, args, span),
                Callee::Function(p) => {
                    cx.func_call(p, args, span);
                }
                Callee::Builtin(b) => {
                    cx.builtin_call(b, args, None, span);
                }
                Callee::Action(f, inst, p) => cx.action_call(f, inst, p, args, span),
                Callee::Method(on, m, st) => {
                    cx.method_call(on, m, st, args, span);
                }
                Callee::SuperBody => {
                    if !args.is_empty() {
                        cx.l.error(
                            codes::E_ARG_COUNT,
                            "`SUPER^()` takes no arguments: it runs the base's body on this instance",
                            span,
                        );
                    }
                    cx.super_body_call(span);
                }
                Callee::Error => {}
            }
            None
        });
    }

    /// The FUNCTION `e` calls if it is a call of a FUNCTION without a result type.
    pub(super) fn void_call(&self, e: &Expr) -> Option<PouId> {
        let ExprKind::Call { callee, .. } = &e.kind else {
            return None;
        };
        let ExprKind::Name(id) = &callee.kind else {
            return None;
        };
        if self.l.pou(self.pou).var(id.sym).is_some() {
            return None;
        }
        let &p = self.l.pou_by_name.get(&id.sym)?;
        let pou = self.l.pou(p);
        (pou.kind == PouKind::Function && pou.ret == Ty::Void).then_some(p)
    }

    /// A call used as a value.
    pub(super) fn call_expr(
        &mut self,
        callee: &'s Expr,
        args: &'s [Arg],
        want: Option<Ty>,
        span: Span,
    ) -> Option<Val> {
        match self.classify(callee, args) {
            Callee::Instance(_, fb) => {
                let n = self.l.pou(fb).display.clone();
                self.l.error(
                    codes::E_FB_CALL_IN_EXPR,
                    format!("a call of a `{n}` instance is a statement, not a value; call it, then read its outputs (`inst.Q`)"),
                    span,
                );
                None
            }
            Callee::Function(p) => {
                let v = self.with_en_eno(args, |cx| cx.func_call(p, args, span));
                if v.is_none() {
                    let n = self.l.pou(p).display.clone();
                    self.l.error(
                        codes::E_NO_RESULT,
                        format!("FUNCTION `{n}` has no result type, so it gives no value"),
                        span,
                    );
                }
                v
            }
            Callee::Builtin(b) => self.with_en_eno(args, |cx| cx.builtin_call(b, args, want, span)),
            Callee::Action(..) => {
                self.l.error(
                    codes::E_NO_RESULT,
                    "an ACTION gives no value: call it as a statement",
                    span,
                );
                None
            }
            Callee::SuperBody => {
                self.l.error(
                    codes::E_NO_RESULT,
                    "`SUPER^()` runs the base's body and gives no value: call it as a statement",
                    span,
                );
                None
            }
            Callee::Method(on, m, st) => {
                let v = self.with_en_eno(args, |cx| cx.method_call(on, m, st, args, span));
                if v.is_none() && self.l.pou(m).ret == Ty::Void {
                    let n = self.l.pou(m).display.clone();
                    self.l.error(
                        codes::E_NO_RESULT,
                        format!("METHOD `{n}` has no result type, so it gives no value"),
                        span,
                    );
                }
                v
            }
            Callee::Error => {
                for a in args {
                    if let ArgKind::Positional(x) | ArgKind::Input { value: x, .. } = &a.kind {
                        let _ = self.emit(x, None);
                    }
                }
                None
            }
        }
    }

    /// The POU a name calls from here: the standard library calls only its own
    /// FUNCTIONs and the standard functions, whatever the user declares.
    fn visible_pou(&self, sym: crate::intern::Symbol) -> Option<PouId> {
        let in_std = self.l.pou(self.pou).std;
        self.l
            .pou_by_name
            .get(&sym)
            .copied()
            .filter(|&p| !in_std || self.l.pou(p).std)
    }

    /// The result type of a call, without emitting anything.
    pub(super) fn infer_call(&mut self, callee: &Expr, args: &[Arg]) -> Ty {
        if let Some((_, m, _)) = self.method_callee(callee) {
            return match self.l.pou(m).ret {
                Ty::Void => Ty::Error,
                t => t,
            };
        }
        let ExprKind::Name(id) = &callee.kind else {
            return Ty::Error;
        };
        if self.l.pou(self.pou).var(id.sym).is_some() {
            return Ty::Error;
        }
        if let Some(p) = self.visible_pou(id.sym) {
            if self.l.pou(p).kind == PouKind::Function {
                // A FUNCTION without a result is reported (E0405) where it is
                // emitted; as an operand it must not cause a second error.
                return match self.l.pou(p).ret {
                    Ty::Void => Ty::Error,
                    t => t,
                };
            }
            return Ty::Error;
        }
        match self.l.builtin(id.sym) {
            Some(b) => self.builtin_infer(b, args),
            None => Ty::Error,
        }
    }

    fn classify(&mut self, callee: &'s Expr, args: &'s [Arg]) -> Callee<'s> {
        if let Some(super::methods::SelfRef::Super(_)) = self.self_ref(callee) {
            return Callee::SuperBody;
        }
        if let Some((on, m, statically)) = self.method_callee(callee) {
            return Callee::Method(on, m, statically);
        }
        match &callee.kind {
            // An ACTION a chart drives: its name is its control's (`A.Q`), the call
            // runs the action (`crate::sfc`).
            ExprKind::Name(id)
                if self.l.chart_action(self.pou, id.sym).is_some() && self.self_ptr.is_some() =>
            {
                let f = self.l.chart_action(self.pou, id.sym).expect("checked");
                let me = self.self_ptr.expect("checked");
                Callee::Action(f, Place::new(me, Ty::Fb(self.pou)), self.pou)
            }
            ExprKind::Member(base, name) if matches!(self.infer(base), Ty::Fb(p) if self.l.chart_action(p, name.sym).is_some()) =>
            {
                let Ty::Fb(p) = self.infer(base) else {
                    return Callee::Error;
                };
                let f = self.l.chart_action(p, name.sym).expect("checked");
                match self.place(base) {
                    Some(bp) => Callee::Action(f, bp, p),
                    None => Callee::Error,
                }
            }
            ExprKind::Name(id) => {
                let is_global = !self.l.pou(self.pou).std
                    && self
                        .l
                        .globals_pou
                        .is_some_and(|g| self.l.pou(g).var(id.sym).is_some());
                if self.l.pou(self.pou).var(id.sym).is_some()
                    || is_global
                    || self.class_name_type(id.sym).is_some()
                {
                    let Some(place) = self.place(callee) else {
                        return Callee::Error;
                    };
                    return match place.ty {
                        Ty::Fb(fb) => Callee::Instance(place, fb),
                        Ty::Error => Callee::Error,
                        t => {
                            let n = self.l.text(id.span).to_string();
                            let tn = self.l.ty_name(t);
                            self.l.error(
                                codes::E_NOT_CALLABLE,
                                format!("`{n}` is a variable of type {tn}; it cannot be called"),
                                id.span,
                            );
                            Callee::Error
                        }
                    };
                }
                if let (Some(f), Some(me)) = (self.l.action(self.pou, id.sym), self.self_ptr) {
                    return Callee::Action(f, Place::new(me, Ty::Fb(self.pou)), self.pou);
                }
                let in_std = self.l.pou(self.pou).std;
                if let Some(p) = self.visible_pou(id.sym) {
                    let n = self.l.text(id.span).to_string();
                    return match self.l.pou(p).kind {
                        PouKind::Function if self.l.used[p.0 as usize] && !self.l.pou(p).std => {
                            Callee::Function(p)
                        }
                        PouKind::Function if self.l.pou(p).std && !self.l.pou(self.pou).std => {
                            // The standard library's FUNCTIONs are plcc's own helpers.
                            self.l.error(
                                codes::E_UNDECLARED,
                                format!("no FUNCTION or function block instance named `{n}`"),
                                id.span,
                            );
                            Callee::Error
                        }
                        PouKind::Function if in_std && !self.l.used[p.0 as usize] => {
                            self.l.use_std_function(p);
                            Callee::Function(p)
                        }
                        PouKind::Function if self.l.used[p.0 as usize] => Callee::Function(p),
                        PouKind::Function => Callee::Error,
                        PouKind::FunctionBlock => {
                            self.l.error(
                                codes::E_NOT_CALLABLE,
                                format!("`{n}` is a FUNCTION_BLOCK type: declare an instance (`x : {n};`) and call the instance"),
                                id.span,
                            );
                            Callee::Error
                        }
                        PouKind::Program => {
                            self.l.error(
                                codes::E_NOT_CALLABLE,
                                format!("PROGRAM `{n}` cannot be called"),
                                id.span,
                            );
                            Callee::Error
                        }
                    };
                }
                if let Some(b) = self.l.builtin(id.sym) {
                    return Callee::Builtin(b);
                }
                let name = self.l.sym_name(id.sym).to_string();
                if let Some(what) = Builtin::unsupported(&name) {
                    // An argument of a type already reported (a STRING variable) makes
                    // this a consequence: say nothing more.
                    if !self.any_arg_failed(args) {
                        self.l.error(
                            codes::E_UNSUPPORTED,
                            format!("not supported yet: {what}"),
                            id.span,
                        );
                    }
                    return Callee::Error;
                }
                if self.l.is_unsupported_name(id.sym) {
                    return Callee::Error;
                }
                let n = self.l.text(id.span).to_string();
                let d = Diagnostic::error(
                    codes::E_UNDECLARED,
                    format!("no FUNCTION or function block instance named `{n}`"),
                    id.span,
                );
                self.l.unknown_block(*id, d);
                Callee::Error
            }
            // CODESYS: `Prog.A()`, an ACTION of the PROGRAM's running instance.
            ExprKind::Member(base, name)
                if matches!(self.qualifier(base), Some(Qualifier::Program(p))
                    if self.l.chart_action(p, name.sym).or(self.l.action(p, name.sym)).is_some()) =>
            {
                let Some(Qualifier::Program(p)) = self.qualifier(base) else {
                    return Callee::Error;
                };
                let f = self
                    .l
                    .chart_action(p, name.sym)
                    .or(self.l.action(p, name.sym));
                let inst = if p == self.pou {
                    self.self_ptr.map(|me| Place::new(me, Ty::Fb(p)))
                } else {
                    let what = self.l.text(callee.span).to_string();
                    self.program_place(p, base, &what)
                };
                match (f, inst) {
                    (Some(f), Some(inst)) => Callee::Action(f, inst, p),
                    _ => Callee::Error,
                }
            }
            ExprKind::Member(base, name) if matches!(self.infer(base), Ty::Fb(p) if self.l.action(p, name.sym).is_some()) =>
            {
                let Ty::Fb(p) = self.infer(base) else {
                    return Callee::Error;
                };
                let f = self.l.action(p, name.sym).expect("checked");
                match self.place(base) {
                    Some(bp) => Callee::Action(f, bp, p),
                    None => Callee::Error,
                }
            }
            ExprKind::Member(..)
            | ExprKind::Index(..)
            | ExprKind::Paren(_)
            | ExprKind::Deref(_) => {
                let Some(place) = self.place(callee) else {
                    return Callee::Error;
                };
                match place.ty {
                    Ty::Fb(fb) => Callee::Instance(place, fb),
                    Ty::Error => Callee::Error,
                    t => {
                        let tn = self.l.ty_name(t);
                        self.l.error(
                            codes::E_NOT_CALLABLE,
                            format!("a value of type {tn} cannot be called"),
                            callee.span,
                        );
                        Callee::Error
                    }
                }
            }
            _ => {
                self.l
                    .error(codes::E_NOT_CALLABLE, "this cannot be called", callee.span);
                Callee::Error
            }
        }
    }

    /// True if some argument names a variable whose type was already rejected.
    fn any_arg_failed(&mut self, args: &'s [Arg]) -> bool {
        args.iter().any(|a| match &a.kind {
            ArgKind::Positional(e) | ArgKind::Input { value: e, .. } => {
                matches!(&e.kind, ExprKind::Name(id)
                    if self.l.pou(self.pou).var(id.sym).is_some() && self.infer(e) == Ty::Error)
            }
            _ => false,
        })
    }

    /// Matches call arguments to parameters: positional ones in declaration order
    /// (inputs and in-outs), named ones by name. Reports unknown, duplicate and
    /// misdirected arguments.
    fn bind_args(
        &mut self,
        callee: PouId,
        params: &[Param],
        args: &'s [Arg],
    ) -> Vec<Option<&'s Arg>> {
        let mut bound: Vec<Option<&'s Arg>> = vec![None; params.len()];
        // Positional arguments fill the inputs and in-outs in declaration order; any
        // beyond those receive the outputs, in order (matiec's non-formal calls list
        // the outputs too).
        let order: Vec<usize> = (0..params.len())
            .filter(|&i| params[i].section != VarKind::Output)
            .chain((0..params.len()).filter(|&i| params[i].section == VarKind::Output))
            .collect();
        let mut next_pos = 0usize;
        let callee_name = self.l.pou(callee).display.clone();
        for a in args {
            let slot = match &a.kind {
                ArgKind::Positional(_) => {
                    let Some(&slot) = order.get(next_pos) else {
                        self.l.error(
                            codes::E_ARG_COUNT,
                            format!("too many arguments for `{callee_name}`"),
                            a.span,
                        );
                        continue;
                    };
                    next_pos += 1;
                    slot
                }
                ArgKind::Input { name, .. } | ArgKind::Output { name, .. } => {
                    let upper = self.l.sym_name(name.sym).to_string();
                    if super::en_eno::is_en_eno(&upper) {
                        // Handled around the call (`with_en_eno`).
                        continue;
                    }
                    let found = params
                        .iter()
                        .position(|p| self.l.pou(p.pou).vars[p.var].name.sym == name.sym);
                    let n = self.l.text(name.span).to_string();
                    let Some(i) = found else {
                        self.l.error(
                            codes::E_NO_MEMBER,
                            format!("`{callee_name}` has no parameter named `{n}`"),
                            name.span,
                        );
                        continue;
                    };
                    let is_out = matches!(a.kind, ArgKind::Output { .. });
                    if is_out != (params[i].section == VarKind::Output) {
                        let msg = if is_out {
                            format!(
                                "`{n}` is an input of `{callee_name}`: pass it with `{n} := value`"
                            )
                        } else {
                            format!("`{n}` is an output of `{callee_name}`: read it with `{n} => variable`")
                        };
                        self.l.error(codes::E_ARG_DIRECTION, msg, a.span);
                        continue;
                    }
                    i
                }
            };
            if bound[slot].is_some() {
                self.l
                    .error(codes::E_ARG_COUNT, "this parameter is given twice", a.span);
                continue;
            }
            bound[slot] = Some(a);
        }
        // IEC 61131-3 (6.6.1.4.2): a non-formal call of a FUNCTION gives every input
        // and in-out, in order; a missing one is a mistake, not a default.
        let wanted = order.len()
            - params
                .iter()
                .filter(|p| p.section == VarKind::Output)
                .count();
        let non_formal = args
            .iter()
            .all(|a| matches!(a.kind, ArgKind::Positional(_)));
        if self.l.pou(callee).kind == PouKind::Function
            && non_formal
            && next_pos > 0
            && next_pos < wanted
        {
            let span = args[args.len() - 1].span;
            let pm = params[order[next_pos]];
            let missing = &self.l.pou(pm.pou).vars[pm.var].name;
            let missing = self.l.text(missing.span).to_string();
            self.l.diags.push(
                plcc_ir::diag::Diagnostic::error(
                    codes::E_ARG_COUNT,
                    format!("`{callee_name}` takes {wanted} argument(s), {next_pos} given"),
                    span,
                )
                .with_label(format!("`{missing}` is missing after this")),
            );
        }
        bound
    }

    /// The value expression of an input argument.
    fn arg_value(a: &'s Arg) -> Option<&'s Expr> {
        match &a.kind {
            ArgKind::Positional(e) | ArgKind::Input { value: e, .. } => Some(e),
            ArgKind::Output { .. } => None,
        }
    }

    /// The place of an in-out argument: a writable variable of exactly the parameter's
    /// type.
    fn inout_arg(&mut self, e: &'s Expr, ty: Ty) -> Option<Value> {
        let p = self.place(e)?;
        if p.bit.is_some() {
            self.l.error(
                codes::E_NOT_A_PLACE,
                "a single bit cannot be passed to a VAR_IN_OUT",
                e.span,
            );
            return None;
        }
        // A longer string may stand for a shorter one: the callee writes at most its
        // declared capacity.
        let fits_string =
            matches!((p.ty, ty), (Ty::Str(a), Ty::Str(d)) if a.wide == d.wide && a.cap >= d.cap);
        if let (Ty::Str(a), Ty::Str(d)) = (p.ty, ty) {
            if a.wide == d.wide && !fits_string {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!(
                        "a VAR_IN_OUT {} needs a string of at least {} characters (the callee may write that many), not {}",
                        d.name(),
                        d.cap,
                        a.name()
                    ),
                    e.span,
                );
                return None;
            }
        }
        // A derived instance is a base instance (its struct begins with the base's).
        let derived = matches!((p.ty, ty), (Ty::Fb(d), Ty::Fb(b)) if self.l.derives_from(d, b));
        if p.ty != ty && p.ty != Ty::Error && !fits_string && !derived {
            let (a, b) = (self.l.ty_name(ty), self.l.ty_name(p.ty));
            self.l.error(
                codes::E_TYPE_MISMATCH,
                format!("a VAR_IN_OUT of type {a} needs a variable of exactly that type, not {b}"),
                e.span,
            );
            return None;
        }
        if !self.check_writable(&p, e.span) {
            return None;
        }
        let Some(guard) = p.guard else {
            return Some(p.addr);
        };
        // An array element whose index was out of bounds: the callee gets a scratch
        // variable holding the type's zero instead of the stand-in element, so it
        // reads 0 and its writes are dropped, as for any other access.
        let (mt, _) = self.l.mem_type(p.ty)?;
        let scratch = self.b.slot("out_of_bounds", mt);
        let scratch_addr = self.b.slot_addr(scratch);
        self.init_var(scratch_addr, p.ty, p.tag, None);
        self.guarded(Some(guard), |_| {});
        Some(self.b.select(guard, p.addr, scratch_addr))
    }

    /// Calls a user FUNCTION; its result, if it has one.
    fn func_call(&mut self, p: PouId, args: &'s [Arg], span: Span) -> Option<Val> {
        self.func_call_with(p, args, span, None)
    }

    /// Calls a user FUNCTION, or a METHOD (`this`: the instance's address and the
    /// function to call, the method's own or a dispatcher).
    pub(super) fn func_call_with(
        &mut self,
        p: PouId,
        args: &'s [Arg],
        span: Span,
        this: Option<(Value, FuncId)>,
    ) -> Option<Val> {
        if self.l.pou(p).owner.is_some() || this.is_none() {
            self.l.calls.push((self.caller, CallNode::Pou(p), span));
        }
        let params = params_of(self, p);
        let bound = self.bind_args(p, &params, args);
        let mut ir_args = Vec::with_capacity(params.len() + 1);
        if let Some((addr, _)) = this {
            ir_args.push(addr);
        }
        let mut outs: Vec<(SlotId, Ty, &'s Arg)> = Vec::new();
        let mut eno_slot: Option<SlotId> = None;
        let callee_name = self.l.pou(p).display.clone();
        for (i, prm) in params.iter().enumerate() {
            let v = self.l.pou(p).vars[prm.var].clone();
            match prm.section {
                VarKind::Input if v.ty.is_aggregate() => {
                    // By address: the callee copies it on entry.
                    let given = bound[i].and_then(Self::arg_value);
                    let addr = match given {
                        Some(e) => self.agg_source(e, v.ty),
                        None => None,
                    };
                    let addr = match addr {
                        Some(a) => a,
                        None => {
                            let s = self.scratch_slot(v.ty, "default");
                            if given.is_none() {
                                self.default_agg_input(p, prm.var, s);
                            }
                            s
                        }
                    };
                    ir_args.push(addr);
                }
                VarKind::Input => {
                    let val = match bound[i].and_then(Self::arg_value) {
                        Some(e) => {
                            self.check_range(v.tag, e);
                            self.emit_as(e, v.ty)
                        }
                        None => self.default_input(p, prm.var, span),
                    };
                    ir_args.push(val);
                }
                VarKind::InOut => {
                    let addr = match bound[i].and_then(Self::arg_value) {
                        Some(e) => self.inout_arg(e, v.ty),
                        None => {
                            self.l.error(
                                codes::E_MISSING_ARG,
                                format!(
                                    "the VAR_IN_OUT `{}` of `{callee_name}` must be given",
                                    v.display
                                ),
                                span,
                            );
                            None
                        }
                    };
                    let addr = match addr {
                        Some(a) => a,
                        None => {
                            // Keep the IR valid: point at a scratch slot.
                            let mt = self
                                .l
                                .mem_type(v.ty)
                                .map(|m| m.0)
                                .unwrap_or(MemType::Scalar(Type::I64));
                            let s = self.b.slot("scratch", mt);
                            self.b.slot_addr(s)
                        }
                    };
                    ir_args.push(addr);
                }
                _ => {
                    let mt = match v.ty {
                        t if t.is_aggregate() => self.l.mem_type(t).map(|m| m.0),
                        t => Some(MemType::Scalar(t.ir().unwrap_or(Type::I32))),
                    }
                    .unwrap_or(MemType::Scalar(Type::I32));
                    let s = self.b.slot(format!("{callee_name}.{}", v.display), mt);
                    let addr = self.b.slot_addr(s);
                    ir_args.push(addr);
                    if v.ty == Ty::BOOL && v.display.eq_ignore_ascii_case("ENO") {
                        eno_slot = Some(s);
                    }
                    if let Some(a) = bound[i] {
                        outs.push((s, v.ty, a));
                    }
                }
            }
        }
        let f = match this {
            Some((_, f)) => f,
            None => self.l.ir[p.0 as usize].body?,
        };
        let ret = self.l.pou(p).ret;
        // A STRUCT or array result goes to a temporary of the caller's, which the
        // assignment then copies (the callee may read the assignment's target).
        let result = ret
            .is_aggregate()
            .then(|| self.scratch_slot(ret, &format!("{callee_name}.result")));
        if let Some(r) = result {
            ir_args.push(r);
        }
        let r = self.b.call(f, ret.ir(), ir_args);
        // The FUNCTION's own ENO (`crate::eno`), as the body left it, is the call's.
        if let Some(slot) = eno_slot {
            let addr = self.b.slot_addr(slot);
            let ok = self.b.load(Type::I1, addr);
            let bad = self.b.unary(plcc_ir::inst::UnaryOp::Bnot, ok);
            self.set_eno_error(bad);
        }
        for (slot, ty, a) in outs {
            let addr = self.b.slot_addr(slot);
            if ty.is_aggregate() {
                self.output_agg(addr, ty, a);
                continue;
            }
            let v = self.b.load(ty.ir().unwrap_or(Type::I32), addr);
            self.assign_output(Val { v, ty }, a);
        }
        match result {
            Some(addr) => Some(Val { v: addr, ty: ret }),
            None => r.map(|v| Val { v, ty: ret }),
        }
    }

    /// The address of a new stack slot that holds a value of type `ty`.
    fn scratch_slot(&mut self, ty: Ty, name: &str) -> Value {
        let mt = self
            .l
            .mem_type(ty)
            .map(|m| m.0)
            .unwrap_or(MemType::Scalar(Type::I64));
        let s = self.b.slot(name.to_string(), mt);
        self.b.slot_addr(s)
    }

    /// A STRUCT or array input that a call does not give: its initial value as the
    /// callee declares it, in a temporary at `addr`. The initialiser is the callee's,
    /// so its names are looked up there.
    fn default_agg_input(&mut self, p: PouId, vi: usize, addr: Value) {
        let v = self.l.pou(p).vars[vi].clone();
        let ast = self.l.pou_ast(p);
        let init = ast.var_blocks[v.decl.0 as usize].decls[v.decl.1 as usize]
            .init
            .as_ref();
        for ci in 0..self.l.pou(p).vars.len() {
            if self.l.pou(p).vars[ci].constant && self.l.ir[p.0 as usize].storage[ci].is_none() {
                self.l.fold_constant(p, ci);
            }
        }
        let saved = self.pou;
        self.pou = p;
        self.init_var(addr, v.ty, v.tag, init);
        self.pou = saved;
    }

    /// `name => target` (or a positional argument in an output's place) of a whole
    /// STRUCT or array output at `src`.
    fn output_agg(&mut self, src: Value, ty: Ty, a: &'s Arg) {
        let (negated, target) = match &a.kind {
            ArgKind::Output {
                negated, target, ..
            } => (*negated, target.as_ref()),
            ArgKind::Positional(e) => (false, Some(e)),
            ArgKind::Input { .. } => return,
        };
        if let Some(t) = target {
            self.assign_output_agg(src, ty, negated, t, a.span);
        }
    }

    /// `name => target` after a call: stores an output into its target.
    fn assign_output(&mut self, out: Val, a: &'s Arg) {
        let (negated, target) = match &a.kind {
            ArgKind::Output {
                negated, target, ..
            } => (*negated, target.as_ref()),
            // A positional argument in an output's place receives the output.
            ArgKind::Positional(e) => (false, Some(e)),
            ArgKind::Input { .. } => return,
        };
        let Some(target) = target else { return };
        let mut out = out;
        if negated {
            if out.ty != Ty::BOOL {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    "only a BOOL output can be negated",
                    a.span,
                );
                return;
            }
            out.v = self.b.unary(UnaryOp::Bnot, out.v);
        }
        let Some(place) = self.place(target) else {
            return;
        };
        if !self.check_writable(&place, target.span) {
            return;
        }
        let v = self.coerce(out, place.ty, target.span);
        self.store_place(&place, v);
    }

    /// The value an input gets when a call does not give it: its declared initial
    /// value (which must be constant), else the type's zero.
    fn default_input(&mut self, p: PouId, vi: usize, span: Span) -> Value {
        let v = self.l.pou(p).vars[vi].clone();
        let ast = self.l.pou_ast(p);
        let init = ast.var_blocks[v.decl.0 as usize].decls[v.decl.1 as usize]
            .init
            .as_ref();
        if let Ty::Enum(en, _) = v.ty {
            if let Some(crate::ast::Init::Expr(e)) = init {
                if let Some(x) = self.l.enum_const(e, en) {
                    return self.constant(ConstVal::Int(x), v.ty, None, span).v;
                }
            }
            return self.default_value(v.ty, v.tag);
        }
        let init = init.or(
            match v.tag.map(|t| self.l.user.tags[t.0 as usize].default) {
                Some(TagDefault::Init(i)) => Some(i),
                _ => None,
            },
        );
        if let Some(crate::ast::Init::Expr(e)) = init {
            if let Some((c, _)) = self.l.const_eval(e, p) {
                return self.constant(c, v.ty, None, span).v;
            }
        }
        self.default_value(v.ty, v.tag)
    }

    /// Calls an FB instance: stores the inputs, runs the body, reads the outputs. A
    /// call on an array element whose index was out of bounds is skipped.
    /// The address of the ENO output of the instance at `inst` of `fb`, if the FB
    /// has one (declared by the user or by `crate::eno`).
    fn eno_addr(&mut self, inst: Value, fb: PouId) -> Option<Value> {
        let sym = self.l.interner.lookup("ENO")?;
        let vi = self.l.pou(fb).var(sym)? as usize;
        let v = &self.l.pou(fb).vars[vi];
        if v.ty != Ty::BOOL || v.section != VarKind::Output {
            return None;
        }
        let Some(Storage::Field(fi)) = self.l.ir[fb.0 as usize].storage[vi] else {
            return None;
        };
        let agg = self.l.ir[fb.0 as usize].agg?;
        Some(self.b.field_addr(inst, agg, fi))
    }

    pub(super) fn fb_call(&mut self, inst: Place, fb: PouId, args: &'s [Arg], span: Span) {
        if let Some(kw) = self.l.pou_ast(fb).oo.class {
            let n = self.l.pou(fb).display.clone();
            let d = Diagnostic::error(
                codes::E_OO_DECLARATION,
                format!("an instance of the CLASS `{n}` is not called: call one of its METHODs"),
                span,
            )
            .with_secondary(kw, "declared a CLASS here");
            self.l.diags.push(d);
            return;
        }
        self.instance_call(inst, fb, None, args, span);
    }

    /// Calls the body of the instance `inst` of `fb`, or its ACTION `action` (CODESYS
    /// passes an action's arguments as its POU's call does): stores the inputs, runs
    /// the code, reads the outputs. An action's call may leave out the VAR_IN_OUTs:
    /// they keep what the last call bound.
    pub(super) fn instance_call(
        &mut self,
        inst: Place,
        fb: PouId,
        action: Option<FuncId>,
        args: &'s [Arg],
        span: Span,
    ) {
        let node = action.map_or(CallNode::Pou(fb), CallNode::Action);
        self.l.calls.push((self.caller, node, span));
        let params = params_of(self, fb);
        let bound = self.bind_args(fb, &params, args);
        // A call on an element whose index was out of bounds is skipped (and raises
        // the fault flag).
        let skip = inst.guard.map(|g| {
            let call = self.b.create_block();
            let bad = self.b.create_block();
            let join = self.b.create_block();
            self.b.brif(g, call, vec![], bad, vec![]);
            self.b.switch_to(bad);
            self.b.intrinsic(plcc_ir::Intrinsic::RaiseFault, vec![]);
            self.b.jump(join, vec![]);
            self.b.switch_to(call);
            join
        });
        let agg = self.l.ir[fb.0 as usize].agg;
        let fb_name = self.l.pou(fb).display.clone();
        let mut outs: Vec<(PouId, usize, &'s Arg)> = Vec::new();
        for (i, prm) in params.iter().enumerate() {
            let v = self.l.pou(prm.pou).vars[prm.var].clone();
            let Some(Storage::Field(fi)) = self.l.ir[prm.pou.0 as usize].storage[prm.var] else {
                continue;
            };
            let Some(agg) = agg else { continue };
            match prm.section {
                VarKind::Input if copied_whole(v.ty) => {
                    if let Some(e) = bound[i].and_then(Self::arg_value) {
                        if let Some(src) = self.agg_source(e, v.ty) {
                            let addr = self.b.field_addr(inst.addr, agg, fi);
                            self.copy_value(addr, src, v.ty);
                        }
                    }
                }
                VarKind::Input => {
                    if let Some(e) = bound[i].and_then(Self::arg_value) {
                        self.check_range(v.tag, e);
                        let val = self.emit_as(e, v.ty);
                        let addr = self.b.field_addr(inst.addr, agg, fi);
                        self.b.store(val, addr);
                    }
                }
                VarKind::InOut => {
                    match bound[i].and_then(Self::arg_value) {
                        Some(e) => {
                            if let Some(p) = self.inout_arg(e, v.ty) {
                                let addr = self.b.field_addr(inst.addr, agg, fi);
                                self.b.store(p, addr);
                            }
                        }
                        None if action.is_some() => {}
                        None => {
                            self.l.error(
                            codes::E_MISSING_ARG,
                            format!("the VAR_IN_OUT `{}` of `{fb_name}` must be given at every call", v.display),
                            span,
                        );
                        }
                    }
                }
                _ => {
                    if let Some(a) = bound[i] {
                        outs.push((prm.pou, prm.var, a));
                    }
                }
            }
        }
        // The FB's ENO (`crate::eno`): TRUE as the body starts, which may clear it;
        // what it holds after is the call's ENO.
        let eno = self.eno_addr(inst.addr, fb);
        if let Some(addr) = eno {
            let t = self.b.iconst(Type::I1, 1);
            self.b.store(t, addr);
        }
        if let Some(f) = action.or(self.l.ir[fb.0 as usize].body) {
            self.b.call(f, None, vec![inst.addr]);
        }
        if let Some(addr) = eno {
            let ok = self.b.load(Type::I1, addr);
            let bad = self.b.unary(plcc_ir::inst::UnaryOp::Bnot, ok);
            self.set_eno_error(bad);
        }
        for (c, vi, a) in outs {
            let v = self.l.pou(c).vars[vi].clone();
            let (Some(Storage::Field(fi)), Some(agg)) = (self.l.ir[c.0 as usize].storage[vi], agg)
            else {
                continue;
            };
            let addr = self.b.field_addr(inst.addr, agg, fi);
            if copied_whole(v.ty) {
                self.output_agg(addr, v.ty, a);
                continue;
            }
            let val = self.b.load(v.ty.ir().unwrap_or(Type::I32), addr);
            self.assign_output(Val { v: val, ty: v.ty }, a);
        }
        if let Some(join) = skip {
            self.b.jump(join, vec![]);
            self.b.switch_to(join);
        }
    }
}
