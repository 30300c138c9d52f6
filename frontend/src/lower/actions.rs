//! ACTIONs of PROGRAMs and function blocks: bodies that share their POU's variables,
//! called by name inside the POU (`act();`) or on an instance (`inst.act();`); in the
//! CODESYS dialect with the POU's arguments (`inst.act(IN := x);`).
//!
//! Each action is a function of its own with the POU body's signature (the instance
//! address); it is lowered with the POU's variables in scope, as the body is.

use super::body::{BodyCx, Place};
use super::{CallNode, Lowerer};
use crate::ast::{self, PouKind};
use crate::codes;
use crate::intern::Symbol;
use crate::types::PouId;
use plcc_ir::{FuncId, FuncKind, Function, Type};

impl<'s> Lowerer<'s> {
    /// Creates the functions of the actions of every used PROGRAM and FB: those
    /// declared inside them and those declared after them (`ACTION P.A:`, `ACTIONS P
    /// ... END_ACTIONS`).
    pub(super) fn create_actions(&mut self) {
        let units = self.units;
        let mut found: Vec<(PouId, &'s ast::Action)> = Vec::new();
        for i in 0..self.pous.len() {
            if !self.used[i] || self.pous[i].std {
                continue;
            }
            let id = PouId(i as u32);
            for a in &self.pou_ast(id).actions {
                found.push((id, a));
            }
        }
        for unit in units.iter().skip(1) {
            for item in &unit.items {
                let ast::Item::Action(a) = item else { continue };
                let Some(owner) = a.pou else {
                    self.error(
                        codes::E_BAD_DECLARATION,
                        "an ACTION outside its POU names it: `ACTION Pou.Name:`",
                        a.name.span,
                    );
                    continue;
                };
                match self.pou_by_name.get(&owner.sym) {
                    Some(&p) if self.used[p.0 as usize] => found.push((p, a)),
                    _ => {
                        let n = self.text(owner.span).to_string();
                        self.error(
                            codes::E_UNDECLARED,
                            format!("no PROGRAM or FUNCTION_BLOCK named `{n}` for this ACTION"),
                            owner.span,
                        );
                    }
                }
            }
        }
        for (p, a) in found {
            let kind = match self.pou(p).kind {
                PouKind::Program => FuncKind::ProgramBody,
                PouKind::FunctionBlock => FuncKind::FbBody,
                PouKind::Function => {
                    self.error(
                        codes::E_BAD_DECLARATION,
                        "a FUNCTION has no ACTIONs (it keeps no state between calls)",
                        a.name.span,
                    );
                    continue;
                }
            };
            if self.actions.contains_key(&(p, a.name.sym)) || self.pou(p).var(a.name.sym).is_some()
            {
                let n = self.text(a.name.span).to_string();
                self.error(
                    codes::E_DUPLICATE,
                    format!("`{n}` is declared twice in `{}`", self.pou(p).display),
                    a.name.span,
                );
                continue;
            }
            let name = format!("{}.{}", self.pou(p).display, self.text(a.name.span));
            let mut f = Function::new(name, kind, vec![Type::Ptr], None);
            f.span = Some(a.name.span);
            let fid = self.module.add_func(f);
            self.actions.insert((p, a.name.sym), fid);
            self.action_bodies.push((p, fid, a));
        }
    }

    /// Lowers the body of every action.
    pub(super) fn lower_actions(&mut self) {
        let bodies = std::mem::take(&mut self.action_bodies);
        for &(p, fid, a) in &bodies {
            self.with_function(fid, |l, func| {
                let mut cx = BodyCx::new(l, func, p, false);
                cx.caller = CallNode::Action(fid);
                cx.lower_body(&a.body.stmts);
            });
        }
        self.action_bodies = bodies;
    }

    /// The function of action `name` of POU `p`.
    pub(super) fn action(&self, p: PouId, name: Symbol) -> Option<FuncId> {
        self.actions.get(&(p, name)).copied()
    }

    /// The function of action `name` of POU `p` when a chart drives it: `crate::sfc`
    /// renames it `__SFC_A_<name>` (its name is its control's), and a call by its
    /// name runs it.
    pub(super) fn chart_action(&self, p: PouId, name: Symbol) -> Option<FuncId> {
        let renamed = format!("__SFC_A_{}", self.interner.name(name));
        self.interner
            .lookup(&renamed)
            .and_then(|sym| self.action(p, sym))
    }
}

impl<'s> BodyCx<'_, 's> {
    /// Calls an action on the instance `inst` of `p`. IEC 61131-3's actions take no
    /// arguments; CODESYS passes them as to a call of the POU (`inst.A(IN := x, Q
    /// => y)` stores the inputs, runs the action, reads the outputs).
    pub(super) fn action_call(
        &mut self,
        f: FuncId,
        inst: Place,
        p: PouId,
        args: &'s [ast::Arg],
        span: plcc_ir::diag::Span,
    ) {
        if args.is_empty() {
            self.l.calls.push((self.caller, CallNode::Action(f), span));
            self.b.call(f, None, vec![inst.addr]);
            return;
        }
        if !self.l.codesys {
            self.l.diags.push(
                plcc_ir::diag::Diagnostic::error(
                    codes::E_ARG_COUNT,
                    "an ACTION takes no arguments: it works on its POU's variables",
                    span,
                )
                .with_note(
                    "CODESYS passes an action's arguments as to a call of its POU: \
                     `--dialect codesys` compiles this call",
                ),
            );
            return;
        }
        self.instance_call(inst, p, Some(f), args, span);
    }
}
