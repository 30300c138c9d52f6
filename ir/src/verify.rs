//! The IR verifier, and the dominator tree it (and other passes) use.
//!
//! [`verify_module`] checks everything `docs/ir.md` promises about a module: block
//! structure, operand and result types, ids in range, SSA dominance, unique names,
//! program and `init_globals` signatures, function tables whose entries have their
//! signature, aggregates that do not contain themselves and an acyclic call graph (a
//! `call_table` calls every entry of its table). It never panics, whatever the module holds, and runs in
//! time linear in the size of the module (plus the dominator computation, which is
//! near-linear on the CFGs front ends produce).

use crate::analysis::inst_callees;
use crate::entities::{AggId, Block, FuncId, Inst, TableId, Value};
use crate::function::{FuncKind, Function, ValueDef};
use crate::inst::{BinaryOp, BlockCall, ConvOp, InstData, Intrinsic, UnaryOp};
use crate::module::{AggDef, DataKind, Module};
use crate::text::{print_inst, write_name};
use crate::types::{ElemType, MemType, Type};
use std::collections::HashMap;
use std::fmt;

const NONE: u32 = u32::MAX;

/// One problem the verifier found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VerifyError {
    /// The function it is in, if any.
    pub func: Option<String>,
    /// The instruction it is about, if any.
    pub inst: Option<Inst>,
    /// The printed instruction (`v5 = iadd v3, v4`), when `inst` is given.
    pub inst_text: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for VerifyError {
    /// `in @f, inst12 (v5 = iadd v3, v4): operand types differ: i32 vs i16`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(func) = &self.func {
            let mut name = String::new();
            write_name(&mut name, '@', func);
            write!(f, "in {name}")?;
            if let Some(i) = self.inst {
                write!(f, ", {i}")?;
                if let Some(t) = &self.inst_text {
                    write!(f, " ({t})")?;
                }
            }
            f.write_str(": ")?;
        } else if let Some(i) = self.inst {
            write!(f, "{i}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for VerifyError {}

/// Verifies a whole module: every function, and the module-level rules.
pub fn verify_module(m: &Module) -> Result<(), Vec<VerifyError>> {
    let mut errs = Vec::new();
    check_module(m, &mut errs);
    // Each function on its own, on several threads for a large module.
    let each = crate::parallel::map(&m.funcs, |f| {
        let mut errs = Vec::new();
        check_function(m, f, &mut errs);
        errs
    });
    errs.extend(each.into_iter().flatten());
    check_recursion(m, &mut errs);
    if errs.is_empty() {
        Ok(())
    } else {
        Err(errs)
    }
}

/// Verifies one function against the module it belongs to (or is being built for):
/// the module resolves callees, aggregates and data objects.
pub fn verify_function(m: &Module, f: &Function) -> Result<(), Vec<VerifyError>> {
    let mut errs = Vec::new();
    check_function(m, f, &mut errs);
    if errs.is_empty() {
        Ok(())
    } else {
        Err(errs)
    }
}

// ---------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------
// Functions

/// The expected result of an instruction, from its operation and operands.
enum Expect {
    /// No result.
    Nothing,
    /// A result of this type.
    Ty(Type),
    /// Unknown (the operands are already reported as broken).
    Unknown,
}

fn arith_int(t: Type) -> bool {
    matches!(t, Type::I8 | Type::I16 | Type::I32 | Type::I64)
}

struct FnCheck<'a> {
    m: &'a Module,
    f: &'a Function,
    errs: &'a mut Vec<VerifyError>,
    in_layout: Vec<bool>,
    inst_block: Vec<u32>,
    inst_pos: Vec<u32>,
}

fn check_function(m: &Module, f: &Function, errs: &mut Vec<VerifyError>) {
    let mut c = FnCheck {
        m,
        f,
        errs,
        in_layout: vec![false; f.blocks.len()],
        inst_block: vec![NONE; f.insts.len()],
        inst_pos: vec![NONE; f.insts.len()],
    };
    c.run();
}

impl FnCheck<'_> {
    fn err(&mut self, inst: Option<Inst>, message: String) {
        self.errs.push(VerifyError {
            func: Some(self.f.name.clone()),
            inst,
            inst_text: inst.map(|i| print_inst(self.m, self.f, i)),
            message,
        });
    }

    fn ty(&self, v: Value) -> Option<Type> {
        self.f.values.get(v.index()).map(|d| d.ty)
    }

    fn run(&mut self) {
        let f = self.f;
        let (nb, ni) = (f.blocks.len(), f.insts.len());
        if f.results.len() != ni || f.spans.len() != ni {
            self.err(
                None,
                format!(
                    "the function has {} instructions but {} results and {} locations",
                    ni,
                    f.results.len(),
                    f.spans.len()
                ),
            );
        }
        if f.layout.is_empty() {
            self.err(None, "the function has no blocks".into());
            return;
        }

        // Blocks of the layout and their instructions.
        let mut blocks: Vec<Block> = Vec::with_capacity(f.layout.len());
        for &b in &f.layout {
            if b.index() >= nb {
                self.err(None, format!("the layout names {b}, which does not exist"));
                continue;
            }
            if std::mem::replace(&mut self.in_layout[b.index()], true) {
                self.err(None, format!("{b} appears more than once in the layout"));
                continue;
            }
            blocks.push(b);
        }
        for &b in &blocks {
            let data = &f.blocks[b.index()];
            if data.insts.is_empty() {
                self.err(
                    None,
                    format!("{b} is empty (every block ends with a terminator)"),
                );
            }
            let n = data.insts.len();
            for (k, &i) in data.insts.iter().enumerate() {
                let Some(idata) = f.insts.get(i.index()) else {
                    self.err(None, format!("{b} lists {i}, which does not exist"));
                    continue;
                };
                if self.inst_block[i.index()] != NONE {
                    let other = Block(self.inst_block[i.index()]);
                    self.err(
                        Some(i),
                        format!("the instruction is placed twice (in {other} and {b})"),
                    );
                    continue;
                }
                self.inst_block[i.index()] = b.0;
                self.inst_pos[i.index()] = k as u32;
                let last = k + 1 == n;
                if idata.is_terminator() && !last {
                    self.err(Some(i), format!("a terminator in the middle of {b}"));
                }
                if last && !idata.is_terminator() {
                    self.err(Some(i), format!("{b} does not end with a terminator"));
                }
            }
            for (k, &v) in data.params.iter().enumerate() {
                match f.values.get(v.index()) {
                    None => self.err(
                        None,
                        format!("parameter {k} of {b} is {v}, which does not exist"),
                    ),
                    Some(d) if d.def != ValueDef::Param(b, k as u32) => self.err(
                        None,
                        format!(
                            "{v} is parameter {k} of {b} but its definition says {:?}",
                            d.def
                        ),
                    ),
                    _ => {}
                }
            }
        }

        // The entry block's parameters are the function's.
        let entry = f.layout[0];
        if entry.index() < nb {
            let params = &f.blocks[entry.index()].params;
            if params.len() != f.params.len() {
                self.err(
                    None,
                    format!(
                        "the entry block {entry} has {} parameters but the function has {}",
                        params.len(),
                        f.params.len()
                    ),
                );
            } else {
                for (k, (&v, &t)) in params.iter().zip(&f.params).enumerate() {
                    if let Some(vt) = self.ty(v) {
                        if vt != t {
                            self.err(
                                None,
                                format!("parameter {k} of the entry block ({v}) is {vt} but the function's is {t}"),
                            );
                        }
                    }
                }
            }
        }

        // Instructions: ids, operand types, results.
        for &b in &blocks {
            for &i in &f.blocks[b.index()].insts {
                if self.placed_here(i, b) {
                    self.check_inst(i);
                }
            }
        }

        // SSA dominance.
        let dom = crate::dominators::DomTree::compute(f);
        let mut operands: Vec<Value> = Vec::new();
        for &b in &blocks {
            let reachable = dom.is_reachable(b);
            for (k, &i) in f.blocks[b.index()].insts.iter().enumerate() {
                if !self.placed_here(i, b) {
                    continue;
                }
                operands.clear();
                f.insts[i.index()].for_each_arg(|v| operands.push(v));
                operands.sort_unstable();
                operands.dedup();
                for &v in &operands {
                    let Some(vd) = f.values.get(v.index()) else {
                        continue; // reported by check_inst
                    };
                    let Some((db, dpos)) = self.def_site(v, vd.def) else {
                        self.err(
                            Some(i),
                            format!("{v} is not defined in any block of the layout"),
                        );
                        continue;
                    };
                    if !reachable {
                        continue;
                    }
                    let upos = k as u32 + 1;
                    if db == b {
                        if dpos >= upos {
                            self.err(Some(i), format!("{v} is used before its definition"));
                        }
                    } else if !dom.dominates(db, b) {
                        self.err(
                            Some(i),
                            format!(
                                "{v} is defined in {db}, which does not dominate this use in {b}"
                            ),
                        );
                    }
                }
            }
        }
    }

    /// True if `i` is a valid instruction whose (first) placement is in `b`.
    fn placed_here(&self, i: Inst, b: Block) -> bool {
        self.inst_block.get(i.index()) == Some(&b.0)
    }

    /// Where a value is defined: its block and position (0 for block parameters, `k +
    /// 1` for the `k`th instruction), if the definition is in the layout and consistent.
    fn def_site(&self, v: Value, def: ValueDef) -> Option<(Block, u32)> {
        let f = self.f;
        match def {
            ValueDef::Param(b, k) => {
                let ok = self.in_layout.get(b.index()) == Some(&true)
                    && f.blocks[b.index()].params.get(k as usize) == Some(&v);
                ok.then_some((b, 0))
            }
            ValueDef::Result(i) => {
                let b = *self.inst_block.get(i.index())?;
                let ok = b != NONE && f.results.get(i.index()) == Some(&Some(v));
                ok.then(|| (Block(b), self.inst_pos[i.index()] + 1))
            }
        }
    }

    fn need_ptr(&mut self, i: Inst, v: Value, what: &str) {
        if let Some(t) = self.ty(v) {
            if t != Type::Ptr {
                self.err(Some(i), format!("{what} {v} is {t}, expected ptr"));
            }
        }
    }

    fn check_block_call(&mut self, i: Inst, bc: &BlockCall) {
        let f = self.f;
        let Some(dest) = f.blocks.get(bc.block.index()) else {
            self.err(
                Some(i),
                format!("branch to {}, which does not exist", bc.block),
            );
            return;
        };
        if !self.in_layout[bc.block.index()] {
            self.err(
                Some(i),
                format!("branch to {}, which is not in the layout", bc.block),
            );
        }
        if dest.params.len() != bc.args.len() {
            self.err(
                Some(i),
                format!(
                    "{} takes {} arguments, found {}",
                    bc.block,
                    dest.params.len(),
                    bc.args.len()
                ),
            );
            return;
        }
        for (k, (&a, &p)) in bc.args.iter().zip(&dest.params).enumerate() {
            if let (Some(at), Some(pt)) = (self.ty(a), self.ty(p)) {
                if at != pt {
                    self.err(
                        Some(i),
                        format!(
                            "argument {k} to {} is {at}, but the parameter {p} is {pt}",
                            bc.block
                        ),
                    );
                }
            }
        }
    }

    fn check_inst(&mut self, i: Inst) {
        let (m, f) = (self.m, self.f);
        let data = &f.insts[i.index()];
        let mut missing = false;
        data.for_each_arg(|v| missing |= v.index() >= f.values.len());
        if missing {
            let mut bad = Vec::new();
            data.for_each_arg(|v| {
                if v.index() >= f.values.len() && !bad.contains(&v) {
                    bad.push(v);
                }
            });
            for v in bad {
                self.err(Some(i), format!("{v} does not exist"));
            }
        }
        let t = |v: Value| f.values.get(v.index()).map(|d| d.ty);
        let expect = match data {
            InstData::Iconst { ty: Type::Ptr, imm } => {
                if *imm != 0 {
                    self.err(Some(i), "the only pointer constant is 0 (null)".to_string());
                }
                Expect::Ty(Type::Ptr)
            }
            InstData::Iconst { ty, imm } => {
                if !ty.is_int() {
                    self.err(Some(i), format!("iconst needs an integer type, not {ty}"));
                } else if ty.canon_int(*imm) != *imm {
                    self.err(
                        Some(i),
                        format!(
                            "the constant {imm} is not in canonical form for {ty} (expected {})",
                            ty.canon_int(*imm)
                        ),
                    );
                }
                Expect::Ty(*ty)
            }
            InstData::SizeOf { ty, of } => {
                if !ty.is_int() || *ty == Type::I1 {
                    self.err(Some(i), format!("sizeof needs an integer type, not {ty}"));
                }
                if let MemType::Agg(a) = of {
                    if a.index() >= m.aggs.len() {
                        self.err(Some(i), format!("{a} does not exist"));
                    }
                }
                Expect::Ty(*ty)
            }
            InstData::Fconst { ty, bits } => {
                if !ty.is_float() {
                    self.err(Some(i), format!("fconst needs a float type, not {ty}"));
                } else if *ty == Type::F32 && *bits > u32::MAX as u64 {
                    self.err(
                        Some(i),
                        format!("the f32 constant {bits:#x} has bits above bit 31"),
                    );
                }
                Expect::Ty(*ty)
            }
            InstData::Unary { op, arg } => match t(*arg) {
                Some(at) => {
                    let (ok, need) = match op {
                        UnaryOp::Bnot => (at.is_int(), "an integer or i1"),
                        _ if op.is_int_op() => (arith_int(at), "an integer (i8..i64)"),
                        _ => (at.is_float(), "a float (f32 or f64)"),
                    };
                    if !ok {
                        self.err(
                            Some(i),
                            format!("{} needs {need} operand, found {at}", op.name()),
                        );
                    }
                    Expect::Ty(at)
                }
                None => Expect::Unknown,
            },
            InstData::Binary { op, args } => match (t(args[0]), t(args[1])) {
                (Some(a), Some(b)) => {
                    if a != b {
                        self.err(Some(i), format!("operand types differ: {a} vs {b}"));
                    }
                    let (ok, need) = match op {
                        BinaryOp::Band | BinaryOp::Bor | BinaryOp::Bxor => {
                            (a.is_int(), "integer or i1")
                        }
                        _ if op.is_int_op() => (arith_int(a), "integer (i8..i64)"),
                        _ => (a.is_float(), "float (f32 or f64)"),
                    };
                    if !ok {
                        self.err(
                            Some(i),
                            format!("{} needs {need} operands, found {a}", op.name()),
                        );
                    }
                    Expect::Ty(a)
                }
                _ => Expect::Unknown,
            },
            InstData::Icmp { args, .. } => {
                if let (Some(a), Some(b)) = (t(args[0]), t(args[1])) {
                    if a != b {
                        self.err(Some(i), format!("operand types differ: {a} vs {b}"));
                    } else if !(a.is_int() || a == Type::Ptr) {
                        self.err(
                            Some(i),
                            format!("icmp needs integer or ptr operands, found {a}"),
                        );
                    }
                }
                Expect::Ty(Type::I1)
            }
            InstData::Fcmp { args, .. } => {
                if let (Some(a), Some(b)) = (t(args[0]), t(args[1])) {
                    if a != b {
                        self.err(Some(i), format!("operand types differ: {a} vs {b}"));
                    } else if !a.is_float() {
                        self.err(Some(i), format!("fcmp needs float operands, found {a}"));
                    }
                }
                Expect::Ty(Type::I1)
            }
            InstData::Convert { op, ty, arg } => {
                if let Some(from) = t(*arg) {
                    let to = *ty;
                    let (ok, rule) = match op {
                        ConvOp::Sext => (
                            arith_int(from) && arith_int(to) && to.bits() > from.bits(),
                            "sext goes from i8..i64 to a strictly wider integer",
                        ),
                        ConvOp::Uext => (
                            from.is_int() && arith_int(to) && to.bits() > from.bits(),
                            "uext goes from i1..i64 to a strictly wider integer",
                        ),
                        ConvOp::Itrunc => (
                            arith_int(from) && to.is_int() && to.bits() < from.bits(),
                            "itrunc goes from i8..i64 to a strictly narrower integer",
                        ),
                        ConvOp::Fpromote => (
                            from == Type::F32 && to == Type::F64,
                            "fpromote goes from f32 to f64",
                        ),
                        ConvOp::Fdemote => (
                            from == Type::F64 && to == Type::F32,
                            "fdemote goes from f64 to f32",
                        ),
                        ConvOp::SiToF | ConvOp::UiToF => (
                            arith_int(from) && to.is_float(),
                            "it goes from an integer (i8..i64) to a float",
                        ),
                        ConvOp::FToSi | ConvOp::FToUi => (
                            from.is_float() && arith_int(to),
                            "it goes from a float to an integer (i8..i64)",
                        ),
                        ConvOp::Bitcast => (
                            ((from.is_int() && to.is_float()) || (from.is_float() && to.is_int()))
                                && from.bits() == to.bits(),
                            "bitcast goes between an integer and a float of the same width",
                        ),
                        ConvOp::PtrToInt => (
                            from == Type::Ptr && arith_int(to),
                            "ptrtoint goes from ptr to an integer (i8..i64)",
                        ),
                        ConvOp::IntToPtr => (
                            arith_int(from) && to == Type::Ptr,
                            "inttoptr goes from an integer (i8..i64) to ptr",
                        ),
                    };
                    if !ok {
                        self.err(
                            Some(i),
                            format!("cannot {} {from} to {to}: {rule}", op.name()),
                        );
                    }
                }
                Expect::Ty(*ty)
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                if let Some(c) = t(*cond) {
                    if c != Type::I1 {
                        self.err(
                            Some(i),
                            format!("the select condition {cond} is {c}, expected i1"),
                        );
                    }
                }
                match (t(*if_true), t(*if_false)) {
                    (Some(a), Some(b)) => {
                        if a != b {
                            self.err(Some(i), format!("select arms differ: {a} vs {b}"));
                        }
                        Expect::Ty(a)
                    }
                    _ => Expect::Unknown,
                }
            }
            InstData::GlobalAddr { data } => {
                if data.index() >= m.data.len() {
                    self.err(Some(i), format!("{data} does not exist"));
                }
                Expect::Ty(Type::Ptr)
            }
            InstData::SlotAddr { slot } => {
                if slot.index() >= f.slots.len() {
                    self.err(Some(i), format!("{slot} does not exist"));
                }
                Expect::Ty(Type::Ptr)
            }
            InstData::FieldAddr { base, agg, field } => {
                self.need_ptr(i, *base, "the address");
                match m.aggs.get(agg.index()) {
                    None => self.err(Some(i), format!("{agg} does not exist")),
                    Some(AggDef::Array(a)) => self.err(
                        Some(i),
                        format!("field_addr needs a struct, but %{} is an array", a.name),
                    ),
                    Some(AggDef::Struct(s)) => {
                        if *field as usize >= s.fields.len() {
                            self.err(
                                Some(i),
                                format!(
                                    "struct %{} has {} fields; field {field} does not exist",
                                    s.name,
                                    s.fields.len()
                                ),
                            );
                        }
                    }
                }
                Expect::Ty(Type::Ptr)
            }
            InstData::ElemAddr { base, agg, index } => {
                self.need_ptr(i, *base, "the address");
                match m.aggs.get(agg.index()) {
                    None => self.err(Some(i), format!("{agg} does not exist")),
                    Some(AggDef::Struct(s)) => self.err(
                        Some(i),
                        format!("elem_addr needs an array, but %{} is a struct", s.name),
                    ),
                    Some(AggDef::Array(_)) => {}
                }
                if let Some(it) = t(*index) {
                    if !arith_int(it) {
                        self.err(
                            Some(i),
                            format!("the index {index} is {it}, expected an integer (i8..i64)"),
                        );
                    }
                }
                Expect::Ty(Type::Ptr)
            }
            InstData::Load { ty, addr } => {
                self.need_ptr(i, *addr, "the address");
                Expect::Ty(*ty)
            }
            InstData::Store { addr, .. } => {
                self.need_ptr(i, *addr, "the address");
                Expect::Nothing
            }
            InstData::Call { func, args } => match m.funcs.get(func.index()) {
                None => {
                    self.err(Some(i), format!("{func} does not exist"));
                    Expect::Unknown
                }
                Some(callee) => {
                    let mut name = String::new();
                    write_name(&mut name, '@', &callee.name);
                    if callee.params.len() != args.len() {
                        self.err(
                            Some(i),
                            format!(
                                "{name} takes {} arguments, found {}",
                                callee.params.len(),
                                args.len()
                            ),
                        );
                    } else {
                        for (k, (&a, &p)) in args.iter().zip(&callee.params).enumerate() {
                            if let Some(at) = t(a) {
                                if at != p {
                                    self.err(
                                        Some(i),
                                        format!("argument {k} of {name} is {at}, expected {p}"),
                                    );
                                }
                            }
                        }
                    }
                    match callee.ret {
                        Some(r) => Expect::Ty(r),
                        None => Expect::Nothing,
                    }
                }
            },
            InstData::InlineC { agg, data, .. } => {
                if !matches!(m.aggs.get(agg.index()), Some(AggDef::Struct(_))) {
                    self.err(Some(i), format!("inline_c: {agg} is not a struct"));
                }
                if t(*data).is_some_and(|ty| ty != Type::Ptr) {
                    self.err(Some(i), format!("inline_c: {data} is not a ptr"));
                }
                Expect::Nothing
            }
            InstData::CallTable { table, index, args } => match m.tables.get(table.index()) {
                None => {
                    self.err(Some(i), format!("{table} does not exist"));
                    Expect::Unknown
                }
                Some(tab) => {
                    if let Some(it) = t(*index) {
                        if !arith_int(it) {
                            self.err(
                                Some(i),
                                format!("the index {index} is {it}, expected an integer (i8..i64)"),
                            );
                        }
                    }
                    if tab.params.len() != args.len() {
                        self.err(
                            Some(i),
                            format!(
                                "{table} takes {} arguments, found {}",
                                tab.params.len(),
                                args.len()
                            ),
                        );
                    } else {
                        for (k, (&a, &p)) in args.iter().zip(&tab.params).enumerate() {
                            if let Some(at) = t(a) {
                                if at != p {
                                    self.err(
                                        Some(i),
                                        format!("argument {k} of {table} is {at}, expected {p}"),
                                    );
                                }
                            }
                        }
                    }
                    match tab.result {
                        Some(r) => Expect::Ty(r),
                        None => Expect::Nothing,
                    }
                }
            },
            InstData::Intrinsic { op, args } => {
                if args.len() != op.operands() {
                    self.err(
                        Some(i),
                        format!(
                            "{} takes {} operands, found {}",
                            op.name(),
                            op.operands(),
                            args.len()
                        ),
                    );
                } else if *op == Intrinsic::Fill {
                    let ts: Vec<Option<Type>> = args.iter().map(|&a| t(a)).collect();
                    if ts[0].is_some_and(|p| p != Type::Ptr) {
                        self.err(Some(i), "fill's first operand must be a ptr".to_string());
                    }
                    if ts[2].is_some_and(|n| n != Type::I64) {
                        self.err(Some(i), "fill's count must be an i64".to_string());
                    }
                }
                match op.result() {
                    Some(r) => Expect::Ty(r),
                    None => Expect::Nothing,
                }
            }
            InstData::Jump { dest } => {
                self.check_block_call(i, dest);
                Expect::Nothing
            }
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                if let Some(c) = t(*cond) {
                    if c != Type::I1 {
                        self.err(
                            Some(i),
                            format!("the branch condition {cond} is {c}, expected i1"),
                        );
                    }
                }
                self.check_block_call(i, then_dest);
                self.check_block_call(i, else_dest);
                Expect::Nothing
            }
            InstData::BrTable {
                arg,
                default,
                table,
            } => {
                if let Some(at) = t(*arg) {
                    if !arith_int(at) {
                        self.err(
                            Some(i),
                            format!(
                                "the br_table index {arg} is {at}, expected an integer (i8..i64)"
                            ),
                        );
                    }
                }
                self.check_block_call(i, default);
                for d in table {
                    self.check_block_call(i, d);
                }
                Expect::Nothing
            }
            InstData::Return { value } => {
                match (value, f.ret) {
                    (Some(v), None) => self.err(
                        Some(i),
                        format!("the function returns nothing, but return has {v}"),
                    ),
                    (None, Some(r)) => self.err(
                        Some(i),
                        format!("return without a value in a function returning {r}"),
                    ),
                    (Some(v), Some(r)) => {
                        if let Some(vt) = t(*v) {
                            if vt != r {
                                self.err(
                                    Some(i),
                                    format!(
                                        "the returned {v} is {vt}, but the function returns {r}"
                                    ),
                                );
                            }
                        }
                    }
                    (None, None) => {}
                }
                Expect::Nothing
            }
        };

        // The result.
        let result = f.results.get(i.index()).copied().flatten();
        if let Some(r) = result {
            match f.values.get(r.index()) {
                None => {
                    self.err(Some(i), format!("the result {r} does not exist"));
                    return;
                }
                Some(d) if d.def != ValueDef::Result(i) => {
                    self.err(
                        Some(i),
                        format!("the result {r} is defined elsewhere ({:?})", d.def),
                    );
                }
                _ => {}
            }
        }
        match (expect, result) {
            (Expect::Nothing, Some(r)) => self.err(
                Some(i),
                format!("the instruction has no result, but {r} is defined"),
            ),
            (Expect::Ty(ty), None) => self.err(
                Some(i),
                format!("the result is missing (the instruction gives {ty})"),
            ),
            (Expect::Ty(ty), Some(r)) => {
                if let Some(rt) = self.ty(r) {
                    if rt != ty {
                        self.err(
                            Some(i),
                            format!("the result {r} is {rt}, but the instruction gives {ty}"),
                        );
                    }
                }
            }
            _ => {}
        }
    }
}

// ---------------------------------------------------------------------------------
// Module

fn mod_err(errs: &mut Vec<VerifyError>, func: Option<&str>, message: String) {
    errs.push(VerifyError {
        func: func.map(str::to_string),
        inst: None,
        inst_text: None,
        message,
    });
}

fn agg_label(m: &Module, id: AggId) -> String {
    let mut s = String::new();
    write_name(&mut s, '%', m.aggs[id.index()].name());
    s
}

fn func_label(m: &Module, id: FuncId) -> String {
    let mut s = String::new();
    write_name(&mut s, '@', &m.funcs[id.index()].name);
    s
}

fn signature(f: &Function) -> String {
    let params: Vec<&str> = f.params.iter().map(|t| t.name()).collect();
    match f.ret {
        Some(r) => format!("({}) -> {r}", params.join(", ")),
        None => format!("({})", params.join(", ")),
    }
}

fn check_module(m: &Module, errs: &mut Vec<VerifyError>) {
    // Unique names.
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, f) in m.funcs.iter().enumerate() {
        if let Some(first) = seen.insert(&f.name, i) {
            mod_err(
                errs,
                None,
                format!(
                    "functions {} and {} are both named {}",
                    FuncId::new(first),
                    FuncId::new(i),
                    func_label(m, FuncId::new(i))
                ),
            );
        }
    }
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, a) in m.aggs.iter().enumerate() {
        if let Some(first) = seen.insert(a.name(), i) {
            mod_err(
                errs,
                None,
                format!(
                    "aggregates {} and {} are both named {}",
                    AggId::new(first),
                    AggId::new(i),
                    agg_label(m, AggId::new(i))
                ),
            );
        }
    }
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, d) in m.data.iter().enumerate() {
        if let Some(first) = seen.insert(d.name.to_ascii_lowercase(), i) {
            let mut a = String::new();
            write_name(&mut a, '@', &m.data[first].name);
            let mut b = String::new();
            write_name(&mut b, '@', &d.name);
            mod_err(
                errs,
                None,
                format!("data objects {a} and {b} have the same name (data names ignore case)"),
            );
        }
    }

    // Aggregates: members exist, field names are unique, IEC types fit.
    let mem_ok = |t: MemType| match t {
        MemType::Agg(a) => a.index() < m.aggs.len(),
        MemType::Scalar(_) => true,
    };
    let elem_fits = |t: MemType, e: Option<ElemType>| match (t, e) {
        (MemType::Scalar(t), Some(e)) => t == Type::Ptr || e.ir_type() == t,
        _ => true,
    };
    for (ai, a) in m.aggs.iter().enumerate() {
        let label = agg_label(m, AggId::new(ai));
        match a {
            AggDef::Struct(s) => {
                let mut names: HashMap<String, usize> = HashMap::with_capacity(s.fields.len());
                for (k, fld) in s.fields.iter().enumerate() {
                    if names.insert(fld.name.to_ascii_lowercase(), k).is_some() {
                        mod_err(
                            errs,
                            None,
                            format!("struct {label} has two fields named `{}` (field names ignore case)", fld.name),
                        );
                    }
                    if !mem_ok(fld.ty) {
                        mod_err(
                            errs,
                            None,
                            format!(
                                "field `{}` of {label} has a type that does not exist",
                                fld.name
                            ),
                        );
                    }
                    if !elem_fits(fld.ty, fld.elem) {
                        mod_err(
                            errs,
                            None,
                            format!(
                                "field `{}` of {label} is {} but its IEC type {} is held in {}",
                                fld.name,
                                mem_name(m, fld.ty),
                                fld.elem.map_or("", |e| e.name()),
                                fld.elem.map_or(Type::I32, |e| e.ir_type())
                            ),
                        );
                    }
                }
            }
            AggDef::Array(arr) => {
                if !mem_ok(arr.elem) {
                    mod_err(
                        errs,
                        None,
                        format!("the element type of {label} does not exist"),
                    );
                }
                if !elem_fits(arr.elem, arr.elem_type) {
                    mod_err(
                        errs,
                        None,
                        format!(
                            "the elements of {label} are {} but their IEC type {} is held in {}",
                            mem_name(m, arr.elem),
                            arr.elem_type.map_or("", |e| e.name()),
                            arr.elem_type.map_or(Type::I32, |e| e.ir_type())
                        ),
                    );
                }
            }
        }
    }
    check_agg_cycles(m, errs);

    // Data objects and slots.
    for d in &m.data {
        let mut label = String::new();
        write_name(&mut label, '@', &d.name);
        if !mem_ok(d.ty) {
            mod_err(
                errs,
                None,
                format!("the type of data {label} does not exist"),
            );
        }
        if !elem_fits(d.ty, d.elem) {
            mod_err(
                errs,
                None,
                format!(
                    "data {label} is {} but its IEC type {} is held in {}",
                    mem_name(m, d.ty),
                    d.elem.map_or("", |e| e.name()),
                    d.elem.map_or(Type::I32, |e| e.ir_type())
                ),
            );
        }
    }
    for f in &m.funcs {
        for (k, s) in f.slots.iter().enumerate() {
            if !mem_ok(s.ty) {
                mod_err(
                    errs,
                    Some(&f.name),
                    format!("the type of ss{k} does not exist"),
                );
            }
        }
    }

    // Programs and init_globals.
    let mut seen: HashMap<String, usize> = HashMap::new();
    for p in &m.programs {
        let mut label = String::from("program ");
        crate::text::write_quoted(&mut label, &p.name);
        if seen.insert(p.name.to_ascii_lowercase(), 0).is_some() {
            mod_err(
                errs,
                None,
                format!("{label} is listed twice (instance names ignore case)"),
            );
        }
        if p.data.index() >= m.data.len() {
            mod_err(
                errs,
                None,
                format!("{label}: its data {} does not exist", p.data),
            );
        }
        for (what, id, kind) in [
            ("body", p.body, FuncKind::ProgramBody),
            ("init", p.init, FuncKind::Init),
        ] {
            let Some(f) = m.funcs.get(id.index()) else {
                mod_err(
                    errs,
                    None,
                    format!("{label}: its {what} {id} does not exist"),
                );
                continue;
            };
            if f.params != [Type::Ptr] || f.ret.is_some() {
                mod_err(
                    errs,
                    None,
                    format!(
                        "{label}: its {what} {} must be (ptr) with no result, but is {}",
                        func_label(m, id),
                        signature(f)
                    ),
                );
            }
            if f.kind != kind {
                mod_err(
                    errs,
                    None,
                    format!(
                        "{label}: its {what} {} must be a `{}` function, but is `{}`",
                        func_label(m, id),
                        kind.name(),
                        f.kind.name()
                    ),
                );
            }
        }
    }
    verify_configuration(m, errs);
    check_tables(m, errs);
    if let Some(id) = m.init_globals {
        match m.funcs.get(id.index()) {
            None => mod_err(errs, None, format!("init_globals {id} does not exist")),
            Some(f) => {
                if !f.params.is_empty() || f.ret.is_some() {
                    mod_err(
                        errs,
                        None,
                        format!(
                            "init_globals {} must be () with no result, but is {}",
                            func_label(m, id),
                            signature(f)
                        ),
                    );
                }
            }
        }
    }
}

/// Every entry of a function table exists and has the table's signature.
fn check_tables(m: &Module, errs: &mut Vec<VerifyError>) {
    for (ti, tab) in m.tables.iter().enumerate() {
        let id = TableId::new(ti);
        let mut label = format!("{id} ");
        crate::text::write_quoted(&mut label, &tab.name);
        let params: Vec<&str> = tab.params.iter().map(|t| t.name()).collect();
        let sig = match tab.result {
            Some(r) => format!("({}) -> {r}", params.join(", ")),
            None => format!("({})", params.join(", ")),
        };
        for (k, e) in tab.entries.iter().enumerate() {
            let Some(fid) = *e else { continue };
            let Some(f) = m.funcs.get(fid.index()) else {
                mod_err(
                    errs,
                    None,
                    format!("table {label}: entry {k}, {fid}, does not exist"),
                );
                continue;
            };
            if f.params != tab.params || f.ret != tab.result {
                mod_err(
                    errs,
                    None,
                    format!(
                        "table {label} is {sig}, but its entry {k} {} is {}",
                        func_label(m, fid),
                        signature(f)
                    ),
                );
            }
        }
    }
}

/// The globals' data object is a global struct; a configuration's resources have
/// distinct names, name program entries (each once) and fields of the globals.
fn verify_configuration(m: &Module, errs: &mut Vec<VerifyError>) {
    let mut global_fields: Option<&[crate::module::Field]> = None;
    if let Some(g) = m.globals {
        match m.data.get(g.index()) {
            None => mod_err(errs, None, format!("globals {g} does not exist")),
            Some(d) => match d.ty {
                MemType::Agg(a) if d.kind == DataKind::Global => match m.aggs.get(a.index()) {
                    Some(AggDef::Struct(s)) => global_fields = Some(&s.fields),
                    _ => mod_err(errs, None, format!("globals {g} must hold a struct")),
                },
                _ => mod_err(
                    errs,
                    None,
                    format!("globals {g} must be a `global` data object holding a struct"),
                ),
            },
        }
    }
    let Some(c) = &m.configuration else {
        return;
    };
    let mut resources: HashMap<String, usize> = HashMap::new();
    let mut programs: HashMap<String, usize> = HashMap::new();
    for r in &c.resources {
        if resources.insert(r.name.to_ascii_lowercase(), 0).is_some() {
            mod_err(
                errs,
                None,
                format!("resource {:?} is listed twice (names ignore case)", r.name),
            );
        }
        for p in &r.programs {
            if m.program(p).is_none() {
                mod_err(
                    errs,
                    None,
                    format!(
                        "resource {:?} names program {p:?}, which is not a program entry",
                        r.name
                    ),
                );
            }
            if programs.insert(p.to_ascii_lowercase(), 0).is_some() {
                mod_err(errs, None, format!("program {p:?} is in two resources"));
            }
        }
        for g in &r.globals {
            let known =
                global_fields.is_some_and(|fs| fs.iter().any(|f| f.name.eq_ignore_ascii_case(g)));
            if !known {
                mod_err(
                    errs,
                    None,
                    format!(
                        "resource {:?} names global {g:?}, which is not a field of the globals",
                        r.name
                    ),
                );
            }
        }
    }
}

fn mem_name(m: &Module, t: MemType) -> String {
    match t {
        MemType::Scalar(t) => t.name().to_string(),
        MemType::Agg(a) if a.index() < m.aggs.len() => agg_label(m, a),
        MemType::Agg(a) => a.to_string(),
    }
}

/// Finds the cycles of a graph by iterative depth-first search and reports each back
/// edge's cycle (as the list of nodes from the target of the back edge to its source).
fn find_cycles(n: usize, succs: impl Fn(usize) -> Vec<usize>, mut report: impl FnMut(&[usize])) {
    let mut color = vec![0u8; n]; // 0 white, 1 on the stack, 2 done
    let mut stack_pos = vec![0usize; n];
    let mut path: Vec<usize> = Vec::new();
    let mut stack: Vec<(usize, Vec<usize>, usize)> = Vec::new();
    for root in 0..n {
        if color[root] != 0 {
            continue;
        }
        color[root] = 1;
        stack_pos[root] = path.len();
        path.push(root);
        stack.push((root, succs(root), 0));
        while let Some(top) = stack.last_mut() {
            let (node, k) = (top.0, top.2);
            if k < top.1.len() {
                let s = top.1[k];
                top.2 += 1;
                match color[s] {
                    0 => {
                        color[s] = 1;
                        stack_pos[s] = path.len();
                        path.push(s);
                        let next = succs(s);
                        stack.push((s, next, 0));
                    }
                    1 => report(&path[stack_pos[s]..]),
                    _ => {}
                }
            } else {
                color[node] = 2;
                path.pop();
                stack.pop();
            }
        }
    }
}

fn check_agg_cycles(m: &Module, errs: &mut Vec<VerifyError>) {
    let n = m.aggs.len();
    let succs = |a: usize| -> Vec<usize> {
        let members: Vec<MemType> = match &m.aggs[a] {
            AggDef::Struct(s) => s.fields.iter().map(|f| f.ty).collect(),
            AggDef::Array(arr) => vec![arr.elem],
        };
        let mut out: Vec<usize> = members
            .into_iter()
            .filter_map(|t| match t {
                MemType::Agg(id) if id.index() < n => Some(id.index()),
                _ => None,
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    };
    find_cycles(n, succs, |cycle| {
        let names: Vec<String> = cycle
            .iter()
            .chain(cycle.first())
            .map(|&a| agg_label(m, AggId::new(a)))
            .collect();
        mod_err(
            errs,
            None,
            format!(
                "aggregate {} contains itself: {}",
                names[0],
                names.join(" -> ")
            ),
        );
    });
}

fn check_recursion(m: &Module, errs: &mut Vec<VerifyError>) {
    let n = m.funcs.len();
    let callees = |fi: usize| -> Vec<usize> {
        let f = &m.funcs[fi];
        let mut out = Vec::new();
        for &b in &f.layout {
            let Some(bd) = f.blocks.get(b.index()) else {
                continue;
            };
            for &i in &bd.insts {
                if let Some(data) = f.insts.get(i.index()) {
                    out.extend(inst_callees(m, data).into_iter().map(FuncId::index));
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    };
    find_cycles(n, callees, |cycle| {
        let names: Vec<String> = cycle
            .iter()
            .chain(cycle.first())
            .map(|&f| func_label(m, FuncId::new(f)))
            .collect();
        let message = if cycle.len() == 1 {
            format!("recursion: {} calls itself", names[0])
        } else {
            format!("recursion: {}", names.join(" -> "))
        };
        mod_err(errs, Some(&m.funcs[cycle[0]].name), message);
    });
}
