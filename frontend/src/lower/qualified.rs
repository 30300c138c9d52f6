//! Names qualified by something that is not a variable (`Q.x`):
//!
//! - a global variable list's name (CODESYS's GVLs, written `VAR_GLOBAL GVL`): `GVL.x`
//!   is the global `x` of that list, read and written as `x` is;
//! - in the CODESYS dialect, a PROGRAM's name: `Prog.x` is the variable `x` of the
//!   PROGRAM's instance that runs (CODESYS has one instance per PROGRAM). Its inputs
//!   may be written, its outputs and internal variables only read, as an FB
//!   instance's; its ACTIONs may be called (`Prog.A()`). A PROGRAM with several
//!   configured instances, or none that runs in the build, is E0211.
//!
//! - in the CODESYS dialect, an enumeration type's name: `Color.Red` is `Color#Red`
//!   (CODESYS's qualified access to a value, the only one with `{attribute
//!   'qualified_only'}`).
//!
//! A variable of the name in scope wins: `Q` is a qualifier only where it names no
//! variable.

use super::body::{BodyCx, Named, Place};
use super::consts::ConstVal;
use super::Lowerer;
use crate::ast::{self, Expr, ExprKind, PouKind};
use crate::codes;
use crate::intern::Symbol;
use crate::types::{EnumId, PouId, Ty};
use plcc_ir::{DataDef, DataId, DataKind, ElemType, MemType};

/// What the left side of `Q.x` names when it is not a variable.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Qualifier {
    /// A global variable list.
    List(Symbol),
    /// A PROGRAM (CODESYS dialect).
    Program(PouId),
    /// An enumeration type (CODESYS dialect).
    Enum(EnumId, ElemType),
}

impl<'s> Lowerer<'s> {
    /// The global variable list the global `vi` is declared in, if it has a name.
    fn list_of_global(&self, g: PouId, vi: usize) -> Option<Symbol> {
        let block = self.pou(g).vars[vi].decl.0 as usize;
        self.pou_ast(g).var_blocks[block].list.map(|n| n.sym)
    }

    /// True if `sym` names a global variable list.
    pub(super) fn is_global_list(&self, sym: Symbol) -> bool {
        self.globals_pou.is_some_and(|g| {
            self.pou_ast(g)
                .var_blocks
                .iter()
                .any(|b| b.list.is_some_and(|n| n.sym == sym))
        })
    }

    /// The names of the instances of PROGRAM `p` that run in this build: those of
    /// the configuration (as `--program` chooses among them), or, without one, the
    /// PROGRAM itself when it runs (all PROGRAMs but a library's, or those named by
    /// `--program`). The names are those of their data objects.
    pub(super) fn running_instances(&self, p: PouId) -> Vec<String> {
        let programs = &self.run_programs;
        let config = self
            .units
            .iter()
            .skip(1)
            .filter(|u| !self.library.contains(&u.file))
            .flat_map(|u| &u.items)
            .find_map(|it| match it {
                ast::Item::Configuration(c) => Some(c),
                _ => None,
            });
        let display = &self.pou(p).display;
        let Some(c) = config else {
            let file = self.units[self.pou(p).unit as usize].file;
            let runs = if programs.is_empty() {
                !self.library.contains(&file)
            } else {
                programs.iter().any(|n| n.eq_ignore_ascii_case(display))
            };
            return if runs {
                vec![display.clone()]
            } else {
                Vec::new()
            };
        };
        let mut names: Vec<String> = Vec::new();
        for pc in c.resources.iter().flat_map(|r| &r.programs) {
            if self.pou_by_name.get(&pc.pou.sym) != Some(&p) {
                continue;
            }
            let n = self.text(pc.name.span).to_string();
            let chosen = programs.is_empty()
                || programs
                    .iter()
                    .any(|x| x.eq_ignore_ascii_case(&n) || x.eq_ignore_ascii_case(display));
            if chosen && !names.iter().any(|m| m.eq_ignore_ascii_case(&n)) {
                names.push(n);
            }
        }
        names
    }

    /// The data object of the PROGRAM instance `name` of `p`: made by the first use
    /// (a `Prog.x` of another POU, or the instance's program entry) and shared by
    /// the others.
    pub(super) fn program_data(&mut self, name: &str, p: PouId) -> Option<DataId> {
        if let Some(&d) = self.program_data.get(name) {
            return Some(d);
        }
        let agg = self.ir[p.0 as usize].agg?;
        let d = self.module.add_data(DataDef {
            name: name.to_string(),
            ty: MemType::Agg(agg),
            elem: None,
            kind: DataKind::Program,
            location: None,
        });
        self.program_data.insert(name.to_string(), d);
        Some(d)
    }
}

impl<'s> BodyCx<'_, 's> {
    /// What `base` of `base.x` names when it is a name that names no variable here:
    /// a global variable list, or (CODESYS) a PROGRAM.
    pub(super) fn qualifier(&self, base: &Expr) -> Option<Qualifier> {
        let ExprKind::Name(id) = &base.kind else {
            return None;
        };
        let sym = id.sym;
        let here = self.l.pou(self.pou);
        if here.std
            || self.temps.contains_key(&sym)
            || self.void_temps.contains_key(&sym)
            || here.var(sym).is_some()
        {
            return None;
        }
        let g = self.l.globals_pou;
        if g.is_some_and(|g| self.l.pou(g).var(sym).is_some()) {
            return None;
        }
        if self.l.is_global_list(sym) {
            return Some(Qualifier::List(sym));
        }
        if self.l.codesys {
            if let Some((e, base)) = self.l.enum_type_named(sym) {
                return Some(Qualifier::Enum(e, base));
            }
        }
        let &p = self.l.pou_by_name.get(&sym)?;
        let prog = self.l.pou(p);
        (self.l.codesys
            && prog.kind == PouKind::Program
            && !prog.std
            && Some(p) != g
            && self.l.used[p.0 as usize])
            .then_some(Qualifier::Program(p))
    }

    /// `Q.name` for a qualifier `Q` (`base`): the global of the list, or the
    /// variable of the PROGRAM's running instance.
    pub(super) fn qualified(&mut self, q: Qualifier, base: &Expr, name: ast::Ident) -> Named {
        match q {
            Qualifier::List(list) => {
                let g = self.l.globals_pou.expect("a list is a global block");
                let listed = self
                    .l
                    .pou(g)
                    .var(name.sym)
                    .is_some_and(|vi| self.l.list_of_global(g, vi as usize) == Some(list));
                if !listed {
                    let (l, n) = (self.l.text(base.span), self.l.text(name.span));
                    let msg = format!("the global variable list `{l}` has no variable `{n}`");
                    self.l.error(codes::E_NO_MEMBER, msg, name.span);
                    return Named::Error;
                }
                self.resolve_global(name, true).unwrap_or(Named::Error)
            }
            Qualifier::Enum(e, b) => match self.l.enum_value_of(e, name.sym) {
                Some(v) => Named::Const(ConstVal::Int(v), Ty::Enum(e, b)),
                None => {
                    let en = &self.l.user.enums[e.0 as usize];
                    let names: Vec<&str> = en.values.iter().map(|v| v.display.as_str()).collect();
                    let note = format!("its values are {}", names.join(", "));
                    let msg = format!(
                        "the enumeration {} has no value `{}`",
                        en.display,
                        self.l.text(name.span)
                    );
                    self.l.diags.push(
                        plcc_ir::diag::Diagnostic::error(codes::E_NO_MEMBER, msg, name.span)
                            .with_note(note),
                    );
                    Named::Error
                }
            },
            // Its own PROGRAM's name qualifies the POU's own variable.
            Qualifier::Program(p) if p == self.pou => self.resolve_name(name, true, None),
            Qualifier::Program(p) => {
                if self.in_init {
                    self.l.error(
                        codes::E_NOT_CONSTANT,
                        "an initial value can only use literals and constants",
                        base.span,
                    );
                    return Named::Error;
                }
                let what = format!("{}.{}", self.l.text(base.span), self.l.text(name.span));
                let Some(inst) = self.program_place(p, base, &what) else {
                    return Named::Error;
                };
                match self.member_place(inst.addr, p, name, false) {
                    Some(place) => Named::Place(place),
                    None => Named::Error,
                }
            }
        }
    }

    /// The type of `Q.name`, without emitting anything.
    pub(super) fn qualified_type(&self, q: Qualifier, name: ast::Ident) -> Ty {
        let p = match q {
            Qualifier::List(_) => match self.l.globals_pou {
                Some(g) => g,
                None => return Ty::Error,
            },
            Qualifier::Program(p) => p,
            Qualifier::Enum(e, b) => {
                return match self.l.enum_value_of(e, name.sym) {
                    Some(_) => Ty::Enum(e, b),
                    None => Ty::Error,
                }
            }
        };
        let pou = self.l.pou(p);
        pou.var(name.sym)
            .map_or(Ty::Error, |vi| pou.vars[vi as usize].ty)
    }

    /// The instance of PROGRAM `p` that `base` (its name) stands for in `what` (the
    /// text of `Prog.x`): its one running instance. Several, or none, is E0211 (once
    /// per name and body).
    pub(super) fn program_place(&mut self, p: PouId, base: &Expr, what: &str) -> Option<Place> {
        let names = self.l.running_instances(p);
        if let [name] = names.as_slice() {
            let data = self.l.program_data(name, p)?;
            let addr = self.b.global_addr(data);
            return Some(Place::new(addr, Ty::Fb(p)));
        }
        let ExprKind::Name(id) = &base.kind else {
            return None;
        };
        if let Some(&i) = self.undeclared.get(&id.sym) {
            let d = &mut self.l.diags[i];
            if d.secondary.len() < 3 {
                d.secondary.push((id.span, "also used here".into()));
            }
            return None;
        }
        let prog = self.l.pou(p).display.clone();
        let d = if names.is_empty() {
            plcc_ir::diag::Diagnostic::error(
                codes::E_PROGRAM_INSTANCE,
                format!("PROGRAM `{prog}` does not run in this build, so there is no `{what}`"),
                id.span,
            )
            .with_note("a PROGRAM runs when the configuration has an instance of it; without a configuration, when `--program` names it, or names nothing and it is not a library's")
        } else {
            let list: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
            plcc_ir::diag::Diagnostic::error(
                codes::E_PROGRAM_INSTANCE,
                format!(
                    "PROGRAM `{prog}` has {} instances ({}): `{what}` does not say which one's",
                    names.len(),
                    list.join(", ")
                ),
                id.span,
            )
            .with_note("CODESYS has one instance of each PROGRAM; keep one, or pass the value through a global variable")
        };
        self.undeclared.insert(id.sym, self.l.diags.len());
        self.l.diags.push(d);
        None
    }
}
