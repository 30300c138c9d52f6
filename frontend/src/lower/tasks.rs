//! CONFIGURATION, RESOURCE and TASK: which PROGRAM instances run, when and in what
//! order.
//!
//! A configuration's `PROGRAM inst WITH task : Type (args)` makes an instance named
//! `inst`. Each instance becomes a program entry whose body is a wrapper made here:
//! the wrapper reads the clock and calls the PROGRAM's body only when the instance's
//! task is due (a cyclic task every INTERVAL, counted from its first run; a program
//! without a task every scan), storing the connected inputs before and copying the
//! outputs after, as a call of a function block would. Entries are ordered by task
//! priority (0 first), then as declared, so every machine schedules the same way
//! with no support of its own: the runner's scans are the base cycle.

use super::body::{BodyCx, Place};
use super::consts::ConstVal;
use super::Lowerer;
use crate::ast::{self, PouKind};
use crate::codes;
use crate::types::{PouId, Ty};
use plcc_ir::{
    AggDef, BinaryOp, DataDef, DataKind, Field, FieldRole, FuncId, FuncKind, Function, IntCC,
    Intrinsic, MemType, ProgramEntry, StructDef, StructKind, Type,
};

/// A task of the configuration.
struct Task<'s> {
    /// INTERVAL in microseconds.
    interval_us: Option<u64>,
    priority: u32,
    /// `SINGLE := v`: the task runs once at each rising edge of `v`.
    single: Option<&'s ast::Expr>,
}

/// A configured PROGRAM instance.
struct Instance<'s> {
    decl: &'s ast::ProgramConfig,
    pou: PouId,
    task: Option<usize>,
    order: usize,
}

impl<'s> Lowerer<'s> {
    /// The user's configuration, if there is one (a second one is reported). A
    /// library's (`--lib`) configurations are not the build's: they are left out.
    pub(super) fn configuration(
        &mut self,
        library: &[plcc_ir::diag::FileId],
    ) -> Option<&'s ast::Configuration> {
        let units = self.units;
        let mut found: Option<&'s ast::Configuration> = None;
        for unit in units.iter().skip(1).filter(|u| !library.contains(&u.file)) {
            for item in &unit.items {
                if let ast::Item::Configuration(c) = item {
                    if let Some(first) = found {
                        self.diags.push(
                            plcc_ir::diag::Diagnostic::error(
                                codes::E_DUPLICATE,
                                "a build has one CONFIGURATION",
                                c.name.span,
                            )
                            .with_secondary(first.name.span, "the first one"),
                        );
                    } else {
                        found = Some(c);
                    }
                }
            }
        }
        found
    }

    /// Creates the program entries of a configuration: one per configured
    /// instance (only those named in `programs`, when it is not empty).
    pub(super) fn instantiate_configuration(
        &mut self,
        c: &'s ast::Configuration,
        programs: &[String],
    ) {
        let mut tasks: Vec<(ast::Ident, Task<'s>)> = Vec::new();
        let mut instances: Vec<Instance<'s>> = Vec::new();
        for r in &c.resources {
            for t in &r.tasks {
                if tasks.iter().any(|(n, _)| n.sym == t.name.sym) {
                    let n = self.text(t.name.span).to_string();
                    self.error(
                        codes::E_DUPLICATE,
                        format!("task `{n}` is declared twice"),
                        t.name.span,
                    );
                    continue;
                }
                let task = self.task(t);
                tasks.push((t.name, task));
            }
        }
        for r in &c.resources {
            for pc in &r.programs {
                let n = self.text(pc.name.span).to_string();
                if instances.iter().any(|i| i.decl.name.sym == pc.name.sym) {
                    self.error(
                        codes::E_DUPLICATE,
                        format!("program instance `{n}` is declared twice"),
                        pc.name.span,
                    );
                    continue;
                }
                let pou = match self.pou_by_name.get(&pc.pou.sym) {
                    Some(&p) if self.pou(p).kind == PouKind::Program && self.used[p.0 as usize] => {
                        p
                    }
                    _ => {
                        let t = self.text(pc.pou.span).to_string();
                        self.error(
                            codes::E_NO_PROGRAM,
                            format!("there is no PROGRAM named `{t}`"),
                            pc.pou.span,
                        );
                        continue;
                    }
                };
                let task = match pc.task {
                    None => None,
                    Some(t) => match tasks.iter().position(|(n, _)| n.sym == t.sym) {
                        Some(i) => Some(i),
                        None => {
                            let tn = self.text(t.span).to_string();
                            self.error(
                                codes::E_UNDECLARED,
                                format!("no TASK named `{tn}` in the configuration"),
                                t.span,
                            );
                            continue;
                        }
                    },
                };
                // An instance is chosen by its name or by its PROGRAM type's.
                let t = self.pou(pou).display.clone();
                if !programs.is_empty()
                    && !programs
                        .iter()
                        .any(|p| p.eq_ignore_ascii_case(&n) || p.eq_ignore_ascii_case(&t))
                {
                    continue;
                }
                let order = instances.len();
                instances.push(Instance {
                    decl: pc,
                    pou,
                    task,
                    order,
                });
            }
        }
        for name in programs {
            if !instances.iter().any(|i| {
                self.text(i.decl.name.span).eq_ignore_ascii_case(name)
                    || self.pou(i.pou).display.eq_ignore_ascii_case(name)
            }) {
                self.diags.push(plcc_ir::diag::Diagnostic::error_nowhere(
                    codes::E_NO_PROGRAM,
                    format!("the configuration has no program instance named `{name}`"),
                ));
            }
        }
        // Higher priority (a smaller number) first; a program without a task last
        // among equals, as declared.
        instances.sort_by_key(|i| {
            let p = i.task.map_or(u32::MAX, |t| tasks[t].1.priority);
            (p, i.order)
        });
        for inst in instances {
            let task = inst.task.map(|t| &tasks[t].1);
            self.instantiate_configured(inst, task);
        }
        self.name_configuration(c);
    }

    /// Keeps the configuration's and its resources' names in the module, with the
    /// program entries made of each resource and the globals it declares.
    fn name_configuration(&mut self, c: &'s ast::Configuration) {
        let mut resources = Vec::new();
        for r in &c.resources {
            let programs = r
                .programs
                .iter()
                .map(|pc| self.text(pc.name.span).to_string())
                .filter(|n| self.module.program(n).is_some())
                .collect();
            let globals = r
                .var_blocks
                .iter()
                .filter(|b| b.kind == ast::VarKind::Global)
                .flat_map(|b| &b.decls)
                .flat_map(|d| &d.names)
                .map(|n| self.text(n.span).to_string())
                .collect();
            // Tasks and programs written directly in the configuration are a
            // resource the parser names after it: matiec calls it RESOURCE.
            let implicit = r.name.span == c.name.span;
            resources.push(plcc_ir::Resource {
                name: if implicit {
                    "RESOURCE".to_string()
                } else {
                    self.text(r.name.span).to_string()
                },
                programs,
                globals,
            });
        }
        self.module.configuration = Some(plcc_ir::Configuration {
            name: self.text(c.name.span).to_string(),
            resources,
        });
    }

    /// A task's INTERVAL and PRIORITY (constants).
    fn task(&mut self, t: &'s ast::TaskDecl) -> Task<'s> {
        let mut task = Task {
            interval_us: None,
            priority: 0,
            single: None,
        };
        for (name, value) in &t.props {
            let prop = self.sym_name(name.sym).to_ascii_uppercase();
            let c = self.const_eval_in(value, None, None).map(|(c, _)| c);
            match (prop.as_str(), c) {
                ("INTERVAL", Some(ConstVal::Int(n))) => {
                    // A literal keeps its nanoseconds (`T#0.5ms`); other TIME
                    // constants are milliseconds, LTIME ones nanoseconds.
                    let ns = match value.literal_kind() {
                        Some(&ast::LiteralKind::Duration { ns, .. }) => ns,
                        _ if matches!(
                            self.const_eval_in(value, None, None),
                            Some((_, Ty::Elem(plcc_ir::ElemType::LTime)))
                        ) =>
                        {
                            n
                        }
                        _ => n * 1_000_000,
                    };
                    if ns <= 0 || ns % 1000 != 0 || ns / 1_000_000 > i32::MAX as i128 {
                        self.error(
                            codes::E_BAD_DECLARATION,
                            "a task's INTERVAL is a positive TIME in whole microseconds, under 24 days",
                            value.span,
                        );
                    } else {
                        task.interval_us = Some((ns / 1000) as u64);
                    }
                }
                ("PRIORITY", Some(ConstVal::Int(p))) if (0..=u32::MAX as i128).contains(&p) => {
                    task.priority = p as u32;
                }
                ("SINGLE", _) => task.single = Some(value),
                ("INTERVAL" | "PRIORITY", _) => {
                    self.error(
                        codes::E_NOT_CONSTANT,
                        format!("a task's {prop} must be a constant"),
                        value.span,
                    );
                }
                _ => {
                    let n = self.text(name.span).to_string();
                    self.error(
                        codes::E_NO_MEMBER,
                        format!("a TASK has INTERVAL, PRIORITY and SINGLE, not `{n}`"),
                        name.span,
                    );
                }
            }
        }
        task
    }

    /// The data object, wrappers and program entry of one configured instance.
    fn instantiate_configured(&mut self, inst: Instance<'s>, task: Option<&Task<'s>>) {
        let ir = &self.ir[inst.pou.0 as usize];
        let (Some(_), Some(body), Some(init)) = (ir.agg, ir.body, ir.init) else {
            return;
        };
        let name = self.text(inst.decl.name.span).to_string();
        let Some(data) = self.program_data(&name, inst.pou) else {
            return;
        };
        let single = task.and_then(|t| t.single);
        // An event task (SINGLE) runs on its event, whatever its INTERVAL.
        let interval = task
            .and_then(|t| t.interval_us)
            .filter(|_| single.is_none());
        // The task's clock: milliseconds (TIME) for an interval of whole
        // milliseconds, nanoseconds (LTIME) for a finer one.
        let fine = interval.is_some_and(|us| us % 1000 != 0);
        let last_ty = if fine { Type::I64 } else { Type::I32 };
        // The task's state: when the instance last ran, and whether it has (a timed
        // task); the event's value at the last scan (an event task).
        let state = (interval.is_some() || single.is_some()).then(|| {
            let sagg = self.module.add_agg(AggDef::Struct(StructDef {
                name: format!("{name}$state"),
                kind: StructKind::Other,
                fields: vec![
                    Field {
                        name: "last".into(),
                        ty: MemType::Scalar(last_ty),
                        elem: None,
                        role: FieldRole::Hidden,
                        location: None,
                    },
                    Field {
                        name: "started".into(),
                        ty: MemType::Scalar(Type::I1),
                        elem: None,
                        role: FieldRole::Hidden,
                        location: None,
                    },
                ],
            }));
            let d = self.module.add_data(DataDef {
                name: format!("{name}$state"),
                ty: MemType::Agg(sagg),
                elem: None,
                kind: DataKind::Global,
                location: None,
            });
            (sagg, d)
        });
        let timing = state.map(|st| match single {
            Some(e) => Due::Event(e, st),
            None => Due::Every(interval.expect("a timed task"), st),
        });
        let wrapped_body = self.task_body(&name, &inst, body, timing);
        let wrapped_init = match state {
            Some((sagg, d)) => {
                // Not `{name}$init`: that is the init of a PROGRAM of the instance's
                // name (CODESYS names a task's instance after its PROGRAM).
                let mut f = Function::new(
                    format!("{name}$task_init"),
                    FuncKind::Init,
                    vec![Type::Ptr],
                    None,
                );
                {
                    let mut b = plcc_ir::FuncBuilder::new(&mut f);
                    let p = b.params()[0];
                    let s = b.global_addr(d);
                    let started = b.field_addr(s, sagg, 1);
                    let no = b.iconst(Type::I1, 0);
                    b.store(no, started);
                    let last = b.field_addr(s, sagg, 0);
                    let zero = b.iconst(last_ty, 0);
                    b.store(zero, last);
                    b.call(init, None, vec![p]);
                    b.ret(None);
                }
                self.module.add_func(f)
            }
            None => init,
        };
        self.module.programs.push(ProgramEntry {
            name,
            data,
            body: wrapped_body,
            init: wrapped_init,
            interval_us: interval,
            priority: task.map(|t| t.priority),
        });
    }

    /// The body the scan runs for one instance: the PROGRAM's body when its task is
    /// due, with the configuration's connections.
    fn task_body(
        &mut self,
        name: &str,
        inst: &Instance<'s>,
        body: FuncId,
        timing: Option<Due<'s>>,
    ) -> FuncId {
        if timing.is_none() && inst.decl.args.is_empty() {
            return body;
        }
        let mut f = Function::new(
            format!("{name}$scan"),
            FuncKind::ProgramBody,
            vec![Type::Ptr],
            None,
        );
        f.span = Some(inst.decl.span);
        let fid = self.module.add_func(f);
        // The connections name globals: lower them as the globals' own code does.
        let ctx = self.globals_pou.unwrap_or(inst.pou);
        let globals = self.globals_data;
        let decl = inst.decl;
        let pou = inst.pou;
        self.with_function(fid, |l, func| {
            let mut cx = BodyCx::new(l, func, ctx, false);
            cx.set_span(decl.span);
            let p = cx.params[0];
            cx.self_ptr = match globals {
                Some(g) if cx.l.globals_pou.is_some() => Some(cx.b.global_addr(g)),
                _ => Some(p),
            };
            let done = cx.b.create_block();
            match timing {
                Some(Due::Every(interval, (sagg, d))) => cx.due_check(interval, sagg, d, done),
                Some(Due::Event(e, (sagg, d))) => cx.event_check(e, sagg, d, done),
                None => {}
            }
            if decl.args.is_empty() {
                cx.b.call(body, None, vec![p]);
            } else {
                let place = Place::new(p, Ty::Fb(pou));
                cx.fb_call(place, pou, &decl.args, decl.span);
            }
            cx.b.jump(done, vec![]);
            cx.b.switch_to(done);
            cx.b.ret(None);
        });
        fid
    }
}

/// When a configured instance runs: every `interval` µs, or at each rising edge of
/// an event; with the task's state (its aggregate and data object).
enum Due<'s> {
    Every(u64, (plcc_ir::AggId, plcc_ir::DataId)),
    Event(&'s ast::Expr, (plcc_ir::AggId, plcc_ir::DataId)),
}

impl<'s> BodyCx<'_, 's> {
    /// Goes on only at a rising edge of the event `e` (a BOOL, read at every scan):
    /// TRUE now and FALSE at the previous scan, the task's state keeping the previous
    /// value (its `started` field; FALSE at cold start, so an event already TRUE at
    /// the first scan runs the task then, as matiec's R_TRIG on it does). Jumps to
    /// `done` otherwise.
    fn event_check(
        &mut self,
        e: &'s ast::Expr,
        sagg: plcc_ir::AggId,
        d: plcc_ir::DataId,
        done: plcc_ir::Block,
    ) {
        let now = self.emit_as(e, Ty::Elem(plcc_ir::ElemType::Bool));
        let s = self.b.global_addr(d);
        let prev_p = self.b.field_addr(s, sagg, 1);
        let prev = self.b.load(Type::I1, prev_p);
        self.b.store(now, prev_p);
        let one = self.b.iconst(Type::I1, 1);
        let not_prev = self.b.binary(BinaryOp::Bxor, prev, one);
        let due = self.b.binary(BinaryOp::Band, now, not_prev);
        let run = self.b.create_block();
        self.b.brif(due, run, vec![], done, vec![]);
        self.b.switch_to(run);
    }

    /// Goes on only when the task is due: at its first scan, then once at least
    /// `interval` µs have passed since its last due time (missed periods are
    /// skipped, the phase is kept). Jumps to `done` otherwise. The clock is TIME's
    /// milliseconds for an interval of whole milliseconds (every target has it
    /// cheaply), LTIME's nanoseconds otherwise.
    fn due_check(
        &mut self,
        interval: u64,
        sagg: plcc_ir::AggId,
        d: plcc_ir::DataId,
        done: plcc_ir::Block,
    ) {
        let (clock, ty, interval) = if interval.is_multiple_of(1000) {
            (Intrinsic::ClockMs, Type::I32, interval / 1000)
        } else {
            (Intrinsic::ClockNs, Type::I64, interval * 1000)
        };
        let now = self
            .b
            .intrinsic(clock, vec![])
            .expect("the clock has a result");
        let s = self.b.global_addr(d);
        let started_p = self.b.field_addr(s, sagg, 1);
        let last_p = self.b.field_addr(s, sagg, 0);
        let started = self.b.load(Type::I1, started_p);
        let first = self.b.create_block();
        let later = self.b.create_block();
        let run = self.b.create_block();
        self.b.brif(started, later, vec![], first, vec![]);
        self.b.switch_to(first);
        let yes = self.b.iconst(Type::I1, 1);
        self.b.store(yes, started_p);
        self.b.store(now, last_p);
        self.b.jump(run, vec![]);
        self.b.switch_to(later);
        let last = self.b.load(ty, last_p);
        let elapsed = self.b.binary(BinaryOp::Isub, now, last);
        let iv = self.b.iconst(ty, interval as i64);
        let due = self.b.icmp(IntCC::Sge, elapsed, iv);
        let advance = self.b.create_block();
        self.b.brif(due, advance, vec![], done, vec![]);
        self.b.switch_to(advance);
        let late = self.b.binary(BinaryOp::Srem, elapsed, iv);
        let due_at = self.b.binary(BinaryOp::Isub, now, late);
        self.b.store(due_at, last_p);
        self.b.jump(run, vec![]);
        self.b.switch_to(run);
    }
}
