//! One IR function as one C function.
//!
//! Every SSA value that something uses is a C local, declared (and zeroed) at the top
//! of the function, so no `goto` crosses an initialisation (C++ forbids that); every
//! block is a label, reached by `goto`; a block's parameters are locals the branches
//! to it assign (through temporaries when an argument is itself a parameter of the
//! destination: the assignments are parallel). Stack slots are locals of their type.
//!
//! Integers are unsigned locals; a signed operation converts its operands to the
//! signed type of the width (a conversion, never an overflow), and arithmetic is done
//! in a type at least as wide as `unsigned int`, so it wraps by C's rules. The module
//! must have been legalized with nothing defined (`legalize::Defines::NONE`): then no
//! division, shift or float-to-integer conversion sees an operand C leaves undefined.

use crate::codes;
use crate::decls::{mem_type, signature};
use crate::names::{signed_type, value_type, wide_type, FuncForm, Names};
use crate::repr::Repr;
use plcc_ir::diag::Diagnostic;
use plcc_ir::function::ValueDef;
use plcc_ir::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use plcc_ir::module::AggDef;
use plcc_ir::types::MemType;
use plcc_ir::{AggId, FuncId, Function, Inst, Module, Type, Value};
use std::fmt::Write;

/// The C definition of function `f`. Fails if the globals' address is used other
/// than to reach a global (each global is a C variable of its own; calls that pass
/// the address must have been inlined, see [`globals_values`]).
pub fn function(module: &Module, names: &Names, f: FuncId) -> Result<String, Vec<Diagnostic>> {
    let func = module.func(f);
    let split = globals_values(names, func);
    let access: Vec<Option<Place>> = (0..func.insts.len())
        .map(|i| accessor(module, names, func, &split, Inst::new(i)))
        .collect();
    let used = used_values(func, &access, &split);
    if let Some(x) = (0..used.len()).find(|&x| used[x] && split[x]) {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_MALFORMED_IR,
            format!(
                "function `{}` uses the address of the globals (v{x}) other than to reach one of them: in C each global is a variable of its own",
                func.name
            ),
        )]);
    }
    let mut e = Emitter {
        module,
        names,
        func,
        used,
        split,
        access,
        out: String::new(),
    };
    e.emit(f);
    Ok(e.out)
}

/// The values that hold the address of the globals' data object: its `global_addr`,
/// and the block parameters that receive nothing else. They are never C values:
/// the `field_addr`s on them name the globals' variables.
pub fn globals_values(names: &Names, func: &Function) -> Vec<bool> {
    let mut split = vec![false; func.values.len()];
    let Some(g) = names.globals_data else {
        return split;
    };
    let mut incoming: Vec<Vec<(Value, Value)>> = vec![Vec::new(); func.blocks.len()];
    for (_, i) in func.inst_iter() {
        let data = func.inst(i);
        if matches!(*data, InstData::GlobalAddr { data } if data == g) {
            if let Some(r) = func.result(i) {
                split[r.index()] = true;
            }
        }
        let mut edge = |d: &BlockCall| {
            for (p, a) in func.block(d.block).params.iter().zip(&d.args) {
                incoming[d.block.index()].push((*p, *a));
            }
        };
        data.dests().for_each(&mut edge);
    }
    // Optimistic: every parameter with an argument, until one argument is not.
    for b in &incoming {
        for (p, _) in b {
            if func.value_type(*p) == Type::Ptr {
                split[p.index()] = true;
            }
        }
    }
    let mut changed = true;
    while changed {
        changed = false;
        for b in &incoming {
            for (p, a) in b {
                if split[p.index()] && !split[a.index()] {
                    split[p.index()] = false;
                    changed = true;
                }
            }
        }
    }
    split
}

/// A variable reached by a `field_addr` whose field is wrapped or located: a load or
/// store of it goes through the runtime's accessor (`__GET_VAR`, `__SET_LOCATED`...).
#[derive(Copy, Clone, Debug)]
struct Place {
    /// The struct's address (`None`: the globals, each a variable).
    base: Option<Value>,
    agg: AggId,
    field: u32,
    repr: Repr,
}

/// The field a `field_addr` value reaches, if `addr` is one.
fn place(names: &Names, func: &Function, split: &[bool], addr: Value) -> Option<Place> {
    let ValueDef::Result(i) = func.value_def(addr) else {
        return None;
    };
    let InstData::FieldAddr { base, agg, field } = *func.inst(i) else {
        return None;
    };
    Some(Place {
        base: (!split[base.index()]).then_some(base),
        agg,
        field,
        repr: names.repr.field(agg, field),
    })
}

/// The place a load or store reaches through an accessor: a wrapped or located
/// scalar field of the type accessed.
fn accessor(
    module: &Module,
    names: &Names,
    func: &Function,
    split: &[bool],
    i: Inst,
) -> Option<Place> {
    let (ty, addr) = match *func.inst(i) {
        InstData::Load { ty, addr } => (ty, addr),
        InstData::Store { value, addr } => (func.value_type(value), addr),
        _ => return None,
    };
    let p = place(names, func, split, addr)?;
    let field = match module.agg(p.agg) {
        AggDef::Struct(s) => s.fields.get(p.field as usize)?,
        AggDef::Array(_) => return None,
    };
    match (p.repr, field.ty) {
        (Repr::Var(_) | Repr::Located(_), MemType::Scalar(t)) if t == ty => Some(p),
        _ => None,
    }
}

/// The values the C reads: a value is used when an effect (a store, a call, a
/// branch's condition, a return, a block argument of a used parameter) or a used
/// value's computation reads it. An access through an accessor reads the struct's
/// address, not the field's.
fn used_values(func: &Function, access: &[Option<Place>], split: &[bool]) -> Vec<bool> {
    let mut used = vec![false; func.values.len()];
    let mut work: Vec<Value> = Vec::new();
    let mut edges: Vec<Vec<&BlockCall>> = vec![Vec::new(); func.blocks.len()];
    for (_, i) in func.inst_iter() {
        for d in func.inst(i).dests() {
            edges[d.block.index()].push(d);
        }
    }
    // What computing instruction `i` reads (a branch's block arguments aside).
    let operands = |i: Inst, out: &mut Vec<Value>| match (func.inst(i), access[i.index()]) {
        (InstData::Load { .. }, Some(p)) => out.extend(p.base),
        (InstData::Store { value, .. }, Some(p)) => out.extend(p.base.into_iter().chain([*value])),
        (InstData::FieldAddr { base, .. }, _) if split[base.index()] => {}
        (InstData::Jump { .. }, _) => {}
        (InstData::Brif { cond, .. } | InstData::BrTable { arg: cond, .. }, _) => out.push(*cond),
        (data, _) => data.for_each_arg(|v| out.push(v)),
    };
    let mark = |v: Value, used: &mut Vec<bool>, work: &mut Vec<Value>| {
        if !used[v.index()] {
            used[v.index()] = true;
            work.push(v);
        }
    };
    let mut ops = Vec::new();
    for (_, i) in func.inst_iter() {
        let data = func.inst(i);
        let effect = matches!(
            data,
            InstData::Store { .. }
                | InstData::Call { .. }
                | InstData::InlineC { .. }
                | InstData::CallTable { .. }
                | InstData::Brif { .. }
                | InstData::BrTable { .. }
                | InstData::Return { .. }
                | InstData::Intrinsic {
                    op: Intrinsic::RaiseFault | Intrinsic::Fill,
                    ..
                }
        );
        if effect {
            ops.clear();
            operands(i, &mut ops);
            for &v in &ops {
                mark(v, &mut used, &mut work);
            }
        }
    }
    while let Some(v) = work.pop() {
        match func.value_def(v) {
            ValueDef::Result(i) => {
                ops.clear();
                operands(i, &mut ops);
                for &x in &ops {
                    mark(x, &mut used, &mut work);
                }
            }
            ValueDef::Param(b, k) if !split[v.index()] => {
                for e in &edges[b.index()] {
                    if let Some(&a) = e.args.get(k as usize) {
                        mark(a, &mut used, &mut work);
                    }
                }
            }
            ValueDef::Param(..) => {}
        }
    }
    used
}

struct Emitter<'a> {
    module: &'a Module,
    names: &'a Names,
    func: &'a Function,
    used: Vec<bool>,
    split: Vec<bool>,
    access: Vec<Option<Place>>,
    out: String,
}

fn v(x: Value) -> String {
    format!("v{}", x.index())
}

/// The suffix of the memory helpers for a type.
fn access(ty: Type) -> &'static str {
    match ty {
        Type::I1 | Type::I8 => "u8",
        Type::I16 => "u16",
        Type::I32 => "u32",
        Type::I64 => "u64",
        Type::F32 => "f32",
        Type::F64 => "f64",
        Type::Ptr => "ptr",
    }
}

/// An integer constant of type `ty` as a C expression of that type.
fn int_const(ty: Type, imm: i64) -> String {
    match ty {
        Type::I1 => format!("{}", imm & 1),
        Type::I64 => format!("(uint64_t)0x{:x}ull", imm as u64),
        Type::Ptr => "(unsigned char *)0".to_string(),
        _ => format!("({})0x{:x}u", value_type(ty), ty.zext_bits(imm)),
    }
}

/// The C library's name of a float operation in the precision of `ty`.
fn math(name: &str, ty: Type) -> String {
    if ty == Type::F32 {
        format!("{name}f")
    } else {
        name.to_string()
    }
}

impl Emitter<'_> {
    fn ty(&self, x: Value) -> Type {
        self.func.value_type(x)
    }

    fn emit(&mut self, f: FuncId) {
        let func = self.func;
        let _ = writeln!(
            self.out,
            "/* {} {} */\n{} {{",
            func.kind.name(),
            func.name,
            signature(self.module, self.names, f)
        );
        let Some(entry) = func.entry() else {
            // A function without code: it returns zero.
            let _ = match func.ret {
                Some(t) if t.is_float() => writeln!(self.out, "    return 0;"),
                Some(t) => writeln!(self.out, "    return {};", int_const(t, 0)),
                None => Ok(()),
            };
            self.out.push_str("}\n");
            return;
        };
        // Locals: every used block parameter and instruction result.
        let mut declared = vec![false; func.values.len()];
        for &b in &func.layout {
            let params = func.block(b).params.iter().copied();
            let results = func.block(b).insts.iter().filter_map(|&i| func.result(i));
            for x in params.chain(results) {
                if self.used[x.index()] && !declared[x.index()] {
                    declared[x.index()] = true;
                    let _ = writeln!(self.out, "    {} = 0;", decl(self.ty(x), &v(x)));
                }
            }
        }
        for (k, slot) in func.slots.iter().enumerate() {
            let _ = writeln!(
                self.out,
                "    {}; /* {} */",
                decl_mem(&mem_type(self.names, slot.ty), &format!("ss{k}")),
                slot.name
            );
        }
        for (k, slot) in func.slots.iter().enumerate() {
            let _ = writeln!(self.out, "    memset(&ss{k}, 0, sizeof ss{k});");
            if let MemType::Agg(a) = slot.ty {
                if self.names.repr.binds[a.index()] {
                    let _ = writeln!(
                        self.out,
                        "    __plcc_prep_{}(&ss{k});",
                        self.names.aggs[a.index()]
                    );
                }
            }
        }
        // The parameters are the entry block's.
        let form = self.names.forms[f.index()];
        match form {
            FuncForm::Body(_) | FuncForm::Init(_) => {
                if let FuncForm::Init(_) = form {
                    self.out.push_str("    (void)retain;\n");
                }
                match func.block(entry).params.first() {
                    Some(&p) if self.used[p.index()] => {
                        let _ = writeln!(self.out, "    {} = (unsigned char *)data__;", v(p));
                    }
                    _ => self.out.push_str("    (void)data__;\n"),
                }
            }
            FuncForm::Plain => {
                for (k, &p) in func.block(entry).params.iter().enumerate() {
                    if self.used[p.index()] {
                        let _ = writeln!(self.out, "    {} = p{k};", v(p));
                    } else {
                        let _ = writeln!(self.out, "    (void)p{k};");
                    }
                }
            }
        }
        // Labels only where a branch goes (an unused label is a warning).
        let mut target = vec![false; func.blocks.len()];
        for &b in &func.layout {
            for s in func.successors(b) {
                target[s.index()] = true;
            }
        }
        for &b in &func.layout {
            if target[b.index()] {
                let _ = writeln!(self.out, "b{}:;", b.index());
            }
            for &i in &func.block(b).insts {
                self.inst(i);
            }
        }
        self.out.push_str("}\n");
    }

    /// The prefix and name of a place for the accessors (`((T *)v3)->`, `CNT`).
    fn lvalue(&self, p: Place) -> (String, String) {
        match p.base {
            Some(b) => (
                format!("(({} *){})->", self.names.aggs[p.agg.index()], v(b)),
                self.names.fields[p.agg.index()][p.field as usize].clone(),
            ),
            None => (String::new(), self.names.globals[p.field as usize].clone()),
        }
    }

    /// The read of a place through its accessor, as a value of type `ty`.
    fn get(&self, p: Place, ty: Type) -> String {
        let (prefix, name) = self.lvalue(p);
        let mac = match p.repr {
            Repr::Located(_) => "__GET_LOCATED",
            _ => "__GET_VAR",
        };
        let read = format!("{mac}({prefix}{name}, )");
        if ty == Type::I1 {
            // A BOOL the runtime or a debugger wrote may be any byte.
            format!("(uint8_t)({read} != 0)")
        } else {
            format!("({}){read}", value_type(ty))
        }
    }

    fn line(&mut self, text: &str) {
        let _ = writeln!(self.out, "    {text}");
    }

    fn inst(&mut self, i: plcc_ir::Inst) {
        let func = self.func;
        let data = func.inst(i);
        let result = func.result(i);
        match data {
            InstData::Store { value, .. } if self.access[i.index()].is_some() => {
                let p = self.access[i.index()].expect("an accessor");
                let (prefix, name) = self.lvalue(p);
                let (mac, t) = match p.repr {
                    Repr::Located(k) => ("__SET_LOCATED", self.names.repr.located[k].ty),
                    Repr::Var(t) => ("__SET_VAR", t),
                    _ => unreachable!("an accessor's place is wrapped or located"),
                };
                self.line(&format!(
                    "{{ {mac}({prefix}, {name}, , __plcc_to_{t}({})); }}",
                    v(*value)
                ));
            }
            InstData::Store { value, addr } => {
                let t = self.ty(*value);
                self.line(&format!(
                    "__plcc_st_{}({}, {});",
                    access(t),
                    v(*addr),
                    v(*value)
                ));
            }
            InstData::Intrinsic {
                op: Intrinsic::RaiseFault,
                ..
            } => self.line("__plcc_rt.fault = 1;"),
            InstData::Intrinsic {
                op: Intrinsic::Fill,
                args,
            } => {
                let t = self.ty(args[1]);
                self.line(&format!(
                    "for (int64_t __k = 0; __k < (int64_t){n}; __k++) \
                     __plcc_st_{a}({p} + __k * (ptrdiff_t)sizeof({c}), {x});",
                    n = v(args[2]),
                    a = access(t),
                    p = v(args[0]),
                    c = value_type(t),
                    x = v(args[1]),
                ));
            }
            InstData::Jump { dest } => {
                let text = self.edge(dest);
                self.line(&text);
            }
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                let (t, e) = (self.edge(then_dest), self.edge(else_dest));
                // A branch to a fault path is unlikely: the compiler lays that path
                // out of line and the loop around it tight.
                let c = match (self.raises(then_dest.block), self.raises(else_dest.block)) {
                    (false, true) => format!("__PLCC_LIKELY({})", v(*cond)),
                    (true, false) => format!("__PLCC_UNLIKELY({})", v(*cond)),
                    _ => v(*cond),
                };
                self.line(&format!("if ({c}) {{ {t} }} else {{ {e} }}"));
            }
            InstData::BrTable {
                arg,
                default,
                table,
            } => self.br_table(*arg, default, table),
            InstData::Return { value } => match value {
                Some(x) => self.line(&format!("return {};", v(*x))),
                None => self.line("return;"),
            },
            InstData::InlineC { code, agg, data } => {
                // As matiec copies a pragma: verbatim, with `data__` the instance.
                let ty = &self.names.aggs[agg.index()];
                self.line(&format!(
                    "{{ {ty} *data__ = ({ty} *){}; (void)data__;",
                    v(*data)
                ));
                self.out.push_str("/* C code of a pragma: */\n");
                self.out.push_str(code);
                self.out.push('\n');
                self.line("}");
            }
            InstData::Call { func: callee, args } => {
                let call = self.call(*callee, args);
                match result {
                    Some(r) if self.used[r.index()] => self.line(&format!("{} = {call};", v(r))),
                    Some(_) => self.line(&format!("(void){call};")),
                    None => self.line(&format!("{call};")),
                }
            }
            InstData::CallTable { table, index, args } => {
                self.call_table(*table, *index, args, result)
            }
            _ => {
                // Everything else computes a value with no effect.
                let Some(r) = result else { return };
                if !self.used[r.index()] {
                    return;
                }
                let expr = match self.access[i.index()] {
                    Some(p) => self.get(p, self.ty(r)),
                    None => self.expr(data, self.ty(r)),
                };
                self.line(&format!("{} = {expr};", v(r)));
            }
        }
    }

    /// True if block `b` is a fault path: a small block raising the fault flag (an
    /// index out of range, a division by zero), not the entry.
    fn raises(&self, b: plcc_ir::Block) -> bool {
        let insts = &self.func.block(b).insts;
        self.func.entry() != Some(b)
            && insts.len() <= 4
            && insts.iter().any(|&i| {
                matches!(
                    self.func.inst(i),
                    InstData::Intrinsic {
                        op: Intrinsic::RaiseFault,
                        ..
                    }
                )
            })
    }

    /// The assignments to a destination's parameters and the jump.
    fn edge(&self, dest: &BlockCall) -> String {
        let params = &self.func.block(dest.block).params;
        let moves: Vec<(Value, Value)> = params
            .iter()
            .zip(&dest.args)
            .filter(|(p, a)| self.used[p.index()] && p != a)
            .map(|(p, a)| (*p, *a))
            .collect();
        let goto = format!("goto b{};", dest.block.index());
        if moves.is_empty() {
            return goto;
        }
        // Parallel assignment: through temporaries when an argument is a parameter.
        let overlap = moves.iter().any(|(_, a)| params.contains(a));
        let mut s = String::new();
        if overlap {
            s.push('{');
            for (k, (p, a)) in moves.iter().enumerate() {
                let _ = write!(s, " {} = {};", decl(self.ty(*p), &format!("t{k}")), v(*a));
            }
            for (k, (p, _)) in moves.iter().enumerate() {
                let _ = write!(s, " {} = t{k};", v(*p));
            }
            s.push_str(" }");
        } else {
            for (p, a) in &moves {
                let _ = write!(s, "{} = {}; ", v(*p), v(*a));
            }
        }
        format!("{} {goto}", s.trim_end())
    }

    /// `call_table`: a `switch` on the index (held unsigned, so read unsigned) with a
    /// case per entry the index's type can reach, each a direct call of its own form;
    /// empty entries and the rest raise the fault and give 0.
    fn call_table(
        &mut self,
        table: plcc_ir::TableId,
        index: Value,
        args: &[Value],
        result: Option<Value>,
    ) {
        let tab = &self.module.tables[table.index()];
        let reach: u64 = match self.ty(index).bits() {
            64 => u64::MAX,
            b => (1u64 << b) - 1,
        };
        let dst = result.filter(|r| self.used[r.index()]);
        self.line(&format!("switch ({}) {{", v(index)));
        for (k, e) in tab.entries.iter().enumerate() {
            let Some(callee) = *e else { continue };
            if k as u64 > reach {
                break;
            }
            let call = self.call(callee, args);
            let text = match (dst, result) {
                (Some(r), _) => format!("{} = {call};", v(r)),
                (None, Some(_)) => format!("(void){call};"),
                (None, None) => format!("{call};"),
            };
            self.line(&format!("case {k}u: {text} break;"));
        }
        let zero = match dst {
            Some(r) => format!(" {} = 0;", v(r)),
            None => String::new(),
        };
        self.line(&format!("default: __plcc_rt.fault = 1;{zero} break;"));
        self.line("}");
    }

    /// `br_table` as a `switch` on the index (an unsigned C value): one `case` per
    /// entry (entries with the same destination and arguments share their copies and
    /// `goto`), the default for the rest. Entries past the index type's range are left
    /// out.
    fn br_table(&mut self, arg: Value, default: &BlockCall, table: &[BlockCall]) {
        let reach: u64 = match self.ty(arg).bits() {
            64 => u64::MAX,
            b => (1u64 << b) - 1,
        };
        let reached = table
            .len()
            .min(usize::try_from(reach.saturating_add(1)).unwrap_or(usize::MAX));
        let mut done = vec![false; reached];
        self.line(&format!("switch ({}) {{", v(arg)));
        for k in 0..reached {
            if done[k] || table[k] == *default {
                continue;
            }
            let mut labels = String::new();
            for (j, d) in table[..reached].iter().enumerate().skip(k) {
                if *d == table[k] {
                    done[j] = true;
                    let _ = write!(labels, "case {j}u: ");
                }
            }
            let text = self.edge(&table[k]);
            self.line(&format!("{labels}{{ {text} }}"));
        }
        let text = self.edge(default);
        self.line(&format!("default: {{ {text} }}"));
        self.line("}");
    }

    fn call(&self, callee: FuncId, args: &[Value]) -> String {
        let name = &self.names.funcs[callee.index()];
        match self.names.forms[callee.index()] {
            FuncForm::Body(a) => {
                format!("{name}(({} *){})", self.names.aggs[a.index()], v(args[0]))
            }
            FuncForm::Init(a) => {
                format!(
                    "{name}(({} *){}, 0)",
                    self.names.aggs[a.index()],
                    v(args[0])
                )
            }
            FuncForm::Plain => {
                let a: Vec<String> = args.iter().map(|x| v(*x)).collect();
                format!("{name}({})", a.join(", "))
            }
        }
    }

    /// The C expression of a value-producing instruction without effects.
    fn expr(&self, data: &InstData, rty: Type) -> String {
        match data {
            InstData::Iconst { ty, imm } => int_const(*ty, *imm),
            // The C compiler's layout is the target's.
            InstData::SizeOf { ty, of } => format!(
                "(({})sizeof({}))",
                value_type(*ty),
                crate::decls::mem_type(self.names, *of)
            ),
            InstData::Fconst { ty, bits } => {
                if *ty == Type::F32 {
                    format!("__plcc_f32(0x{:08x}u)", *bits as u32)
                } else {
                    format!("__plcc_f64(0x{bits:016x}ull)")
                }
            }
            InstData::Unary { op, arg } => self.unary(*op, *arg),
            InstData::Binary { op, args } => self.binary(*op, args[0], args[1]),
            InstData::Icmp { cond, args } => self.icmp(*cond, args[0], args[1]),
            InstData::Fcmp { cond, args } => {
                let op = match cond {
                    FloatCC::Eq => "==",
                    FloatCC::Ne => "!=",
                    FloatCC::Lt => "<",
                    FloatCC::Le => "<=",
                    FloatCC::Gt => ">",
                    FloatCC::Ge => ">=",
                };
                format!("(uint8_t)({} {op} {})", v(args[0]), v(args[1]))
            }
            InstData::Convert { op, ty, arg } => self.convert(*op, *ty, *arg),
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => format!("({} ? {} : {})", v(*cond), v(*if_true), v(*if_false)),
            InstData::GlobalAddr { data } => {
                format!("(unsigned char *)&{}", self.names.data[data.index()])
            }
            InstData::SlotAddr { slot } => format!("(unsigned char *)&ss{}", slot.index()),
            InstData::FieldAddr { base, agg, field } => {
                let located = matches!(self.names.repr.field(*agg, *field), Repr::Located(_));
                let p = Place {
                    base: (!self.split[base.index()]).then_some(*base),
                    agg: *agg,
                    field: *field,
                    repr: Repr::Plain,
                };
                if located {
                    // Where the runtime keeps the value.
                    let (prefix, name) = self.lvalue(p);
                    format!("(unsigned char *){prefix}{name}.value")
                } else if p.base.is_none() {
                    format!("(unsigned char *)&{}", self.lvalue(p).1)
                } else {
                    format!(
                        "({} + offsetof({}, {}))",
                        v(*base),
                        self.names.aggs[agg.index()],
                        self.names.fields[agg.index()][*field as usize]
                    )
                }
            }
            InstData::ElemAddr { base, agg, index } => {
                let elem = match self.module.agg(*agg) {
                    AggDef::Array(a) => a.elem,
                    AggDef::Struct(_) => MemType::Scalar(Type::I8),
                };
                let elem = match elem {
                    MemType::Agg(b) => self.names.aggs[b.index()].clone(),
                    MemType::Scalar(t) => value_type(t).to_string(),
                };
                let ity = self.ty(*index);
                let idx = if ity == Type::I1 {
                    v(*index)
                } else {
                    format!("({}){}", signed_type(ity), v(*index))
                };
                format!(
                    "({} + (ptrdiff_t){idx} * (ptrdiff_t)sizeof({elem}))",
                    v(*base)
                )
            }
            InstData::Load { ty, addr } => format!("__plcc_ld_{}({})", access(*ty), v(*addr)),
            InstData::Intrinsic { op, .. } => match op {
                Intrinsic::ClockMs => "(uint32_t)__plcc_rt.clock_ms".into(),
                Intrinsic::ClockNs => "(uint64_t)__plcc_rt.clock_ns".into(),
                Intrinsic::StopRequested => "__plcc_stop_requested()".into(),
                Intrinsic::RaiseFault | Intrinsic::Fill => {
                    unreachable!("an effect, not a value")
                }
            },
            // Effects and terminators are statements (see `inst`).
            InstData::Store { .. }
            | InstData::Call { .. }
            | InstData::InlineC { .. }
            | InstData::CallTable { .. }
            | InstData::Jump { .. }
            | InstData::Brif { .. }
            | InstData::BrTable { .. }
            | InstData::Return { .. } => {
                unreachable!("{data:?} is not an expression of type {rty}")
            }
        }
    }

    fn unary(&self, op: UnaryOp, a: Value) -> String {
        let ty = self.ty(a);
        let (u, s, w) = (value_type(ty), signed_type(ty), wide_type(ty));
        let x = v(a);
        match op {
            UnaryOp::Ineg => format!("({u})(0u - ({w}){x})"),
            UnaryOp::Bnot if ty == Type::I1 => format!("(uint8_t)({x} ^ 1u)"),
            UnaryOp::Bnot => format!("({u})~({w}){x}"),
            UnaryOp::Iabs => format!("(({s}){x} < 0 ? ({u})(0u - ({w}){x}) : {x})"),
            UnaryOp::Fneg => format!("(-{x})"),
            UnaryOp::Fabs => format!("{}({x})", math("fabs", ty)),
            UnaryOp::Fsqrt => format!("{}({x})", math("sqrt", ty)),
            // Round to nearest, ties to even (POUS.h's helper: avr-libc has no
            // nearbyint, and nearbyint follows the current rounding mode).
            UnaryOp::Fnearest => format!("{}({x})", math("__plcc_nearest", ty)),
            UnaryOp::Ftrunc => format!("{}({x})", math("trunc", ty)),
            UnaryOp::Ffloor => format!("{}({x})", math("floor", ty)),
            UnaryOp::Fceil => format!("{}({x})", math("ceil", ty)),
            UnaryOp::Sin => format!("{}({x})", math("sin", ty)),
            UnaryOp::Cos => format!("{}({x})", math("cos", ty)),
            UnaryOp::Tan => format!("{}({x})", math("tan", ty)),
            UnaryOp::Asin => format!("{}({x})", math("asin", ty)),
            UnaryOp::Acos => format!("{}({x})", math("acos", ty)),
            UnaryOp::Atan => format!("{}({x})", math("atan", ty)),
            UnaryOp::Ln => format!("{}({x})", math("log", ty)),
            UnaryOp::Log10 => format!("{}({x})", math("log10", ty)),
            UnaryOp::Exp => format!("{}({x})", math("exp", ty)),
        }
    }

    fn binary(&self, op: BinaryOp, a: Value, b: Value) -> String {
        let ty = self.ty(a);
        let (u, s, w) = (value_type(ty), signed_type(ty), wide_type(ty));
        let bits = ty.bits();
        let (x, y) = (v(a), v(b));
        let arith = |o: &str| format!("({u})(({w}){x} {o} ({w}){y})");
        match op {
            BinaryOp::Iadd => arith("+"),
            BinaryOp::Isub => arith("-"),
            BinaryOp::Imul => arith("*"),
            // Legalized: the divisor is not 0, and not -1 with MIN.
            BinaryOp::Sdiv => format!("({u})(({s}){x} / ({s}){y})"),
            BinaryOp::Srem => format!("({u})(({s}){x} % ({s}){y})"),
            BinaryOp::Udiv => format!("({u})({x} / {y})"),
            BinaryOp::Urem => format!("({u})({x} % {y})"),
            BinaryOp::Band => format!("({u})({x} & {y})"),
            BinaryOp::Bor => format!("({u})({x} | {y})"),
            BinaryOp::Bxor => format!("({u})({x} ^ {y})"),
            // Legalized: the count is below the width.
            BinaryOp::Ishl => format!("({u})(({w}){x} << {y})"),
            BinaryOp::Ushr => format!("({u})({x} >> {y})"),
            BinaryOp::Sshr => format!("({u})(({s}){x} >> {y})"),
            BinaryOp::Rotl | BinaryOp::Rotr => {
                // Both shifts below the width: c and (w - c) taken modulo the width.
                let c = if op == BinaryOp::Rotl {
                    format!("({y} % {bits}u)")
                } else {
                    format!("(({bits}u - {y} % {bits}u) % {bits}u)")
                };
                format!("({u})((({w}){x} << {c}) | (({w}){x} >> (({bits}u - {c}) % {bits}u)))")
            }
            BinaryOp::Fadd => format!("({x} + {y})"),
            BinaryOp::Fsub => format!("({x} - {y})"),
            BinaryOp::Fmul => format!("({x} * {y})"),
            BinaryOp::Fdiv => format!("({x} / {y})"),
            BinaryOp::Fpow => format!("{}({x}, {y})", math("pow", ty)),
            BinaryOp::Fatan2 => format!("{}({x}, {y})", math("atan2", ty)),
        }
    }

    fn icmp(&self, cond: IntCC, a: Value, b: Value) -> String {
        let ty = self.ty(a);
        let (x, y) = if ty == Type::Ptr {
            // Pointers to different objects compare as addresses.
            (
                format!("(uintptr_t){}", v(a)),
                format!("(uintptr_t){}", v(b)),
            )
        } else {
            (v(a), v(b))
        };
        let s = signed_type(ty);
        let (op, signed) = match cond {
            IntCC::Eq => ("==", false),
            IntCC::Ne => ("!=", false),
            IntCC::Slt => ("<", true),
            IntCC::Sle => ("<=", true),
            IntCC::Sgt => (">", true),
            IntCC::Sge => (">=", true),
            IntCC::Ult => ("<", false),
            IntCC::Ule => ("<=", false),
            IntCC::Ugt => (">", false),
            IntCC::Uge => (">=", false),
        };
        if signed {
            format!("(uint8_t)(({s}){x} {op} ({s}){y})")
        } else {
            format!("(uint8_t)({x} {op} {y})")
        }
    }

    fn convert(&self, op: ConvOp, to: Type, a: Value) -> String {
        let from = self.ty(a);
        let x = v(a);
        let u = value_type(to);
        match op {
            ConvOp::Sext => format!("({u})({})({}){x}", signed_type(to), signed_type(from)),
            ConvOp::Uext => format!("({u}){x}"),
            ConvOp::Itrunc if to == Type::I1 => format!("(uint8_t)({x} & 1u)"),
            ConvOp::Itrunc => format!("({u}){x}"),
            ConvOp::Fpromote => format!("(double){x}"),
            ConvOp::Fdemote => format!("(float){x}"),
            ConvOp::SiToF => format!("({u})({}){x}", signed_type(from)),
            ConvOp::UiToF => format!("({u}){x}"),
            // Legalized: the truncated operand fits the result type.
            ConvOp::FToSi => format!("({u})({}){x}", signed_type(to)),
            ConvOp::FToUi => format!("({u}){x}"),
            ConvOp::Bitcast => match to {
                Type::F32 => format!("__plcc_f32({x})"),
                Type::F64 => format!("__plcc_f64({x})"),
                Type::I32 => format!("__plcc_bits_f32({x})"),
                _ => format!("__plcc_bits_f64({x})"),
            },
            ConvOp::PtrToInt => format!("({u})(uintptr_t){x}"),
            ConvOp::IntToPtr => format!("(unsigned char *)(uintptr_t){x}"),
        }
    }
}

/// A declaration of a local of SSA type `ty`.
fn decl(ty: Type, name: &str) -> String {
    decl_mem(value_type(ty), name)
}

fn decl_mem(ty: &str, name: &str) -> String {
    if ty.ends_with('*') {
        format!("{ty}{name}")
    } else {
        format!("{ty} {name}")
    }
}
