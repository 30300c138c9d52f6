//! The resolver: the raw form the parser reads, with everything named by its text,
//! turned into a module (names to ids, types inferred, entities checked).

use super::*;

pub(super) struct Resolver<'a> {
    pub(super) text: &'a str,
    /// How many entities numbers may still make the parser allocate (so that `v4000000000`
    /// is an error rather than an allocation of gigabytes).
    pub(super) budget: usize,
}

const NONE: u32 = u32::MAX;

impl<'a> Resolver<'a> {
    pub(super) fn err<T>(&self, pos: Pos, msg: impl Into<String>) -> Result<T, ParseError> {
        Err(error_at(self.text, pos, msg))
    }

    fn spend(&mut self, n: u32, pos: Pos) -> Result<usize, ParseError> {
        let count = n as usize + 1;
        if count > self.budget {
            return self.err(
                pos,
                format!("the number {n} is too large for a text of this size"),
            );
        }
        self.budget -= count;
        Ok(count)
    }

    fn mem(&self, t: &RawMem<'_>, aggs: &HashMap<&str, AggId>) -> Result<MemType, ParseError> {
        match t {
            RawMem::Scalar(t) => Ok(MemType::Scalar(*t)),
            RawMem::Agg(n) => match aggs.get(n.name.as_ref()) {
                Some(&id) => Ok(MemType::Agg(id)),
                None => self.err(n.pos, format!("unknown aggregate `%{}`", n.name)),
            },
        }
    }

    pub(super) fn module(mut self, raw: RawModule<'_>) -> Result<Module, ParseError> {
        let mut m = Module::new();

        // Files.
        if let Some(max) = raw.files.iter().max_by_key(|(v, _)| v.n) {
            let count = self.spend(max.0.n, max.0.pos)?;
            let mut seen = vec![false; count];
            m.files = vec![String::new(); count];
            for (v, name) in &raw.files {
                if std::mem::replace(&mut seen[v.n as usize], true) {
                    return self.err(v.pos, format!("file {} is declared twice", v.n));
                }
                m.files[v.n as usize] = name.to_string();
            }
        }

        // Names of everything, so that anything may refer to anything.
        let mut aggs: HashMap<&str, AggId> = HashMap::new();
        for (i, a) in raw.aggs.iter().enumerate() {
            if aggs.insert(&a.name.name, AggId::new(i)).is_some() {
                return self.err(
                    a.name.pos,
                    format!("aggregate `%{}` is declared twice", a.name.name),
                );
            }
        }
        let mut datas: HashMap<&str, DataId> = HashMap::new();
        for (i, d) in raw.data.iter().enumerate() {
            if datas.insert(&d.name.name, DataId::new(i)).is_some() {
                return self.err(
                    d.name.pos,
                    format!("data `@{}` is declared twice", d.name.name),
                );
            }
        }
        let mut funcs: HashMap<&str, FuncId> = HashMap::new();
        for (i, f) in raw.funcs.iter().enumerate() {
            if funcs.insert(&f.name.name, FuncId::new(i)).is_some() {
                return self.err(
                    f.name.pos,
                    format!("function `@{}` is declared twice", f.name.name),
                );
            }
        }

        // Aggregates and data.
        for a in &raw.aggs {
            let def = match &a.body {
                RawAggBody::Struct { kind, fields } => {
                    let mut fs = Vec::with_capacity(fields.len());
                    for f in fields {
                        fs.push(Field {
                            name: f.name.to_string(),
                            ty: self.mem(&f.ty, &aggs)?,
                            elem: f.elem,
                            role: f.role,
                            location: f.location.as_deref().map(str::to_string),
                        });
                    }
                    AggDef::Struct(StructDef {
                        name: a.name.name.to_string(),
                        kind: *kind,
                        fields: fs,
                    })
                }
                RawAggBody::Array {
                    elem,
                    elem_type,
                    len,
                    lower,
                } => AggDef::Array(ArrayDef {
                    name: a.name.name.to_string(),
                    elem: self.mem(elem, &aggs)?,
                    elem_type: *elem_type,
                    len: *len,
                    lower: *lower,
                }),
            };
            m.aggs.push(def);
        }
        for d in &raw.data {
            let ty = self.mem(&d.ty, &aggs)?;
            m.data.push(DataDef {
                name: d.name.name.to_string(),
                ty,
                elem: d.elem,
                kind: d.kind,
                location: d.location.as_deref().map(str::to_string),
            });
        }

        // Tables, then functions: signatures first (calls need the callee's result
        // type).
        let (tables, table_ids) = self.tables(&raw.tables, &funcs)?;
        m.tables = tables;
        let rets: Vec<Option<Type>> = raw.funcs.iter().map(|f| f.ret).collect();
        let names = Names {
            aggs: &aggs,
            data: &datas,
            funcs: &funcs,
            rets: &rets,
            tables: &table_ids,
        };
        for f in &raw.funcs {
            let func = self.function(f, &m, &names)?;
            m.funcs.push(func);
        }

        let func_ref = |n: &Named| -> Result<FuncId, ParseError> {
            match funcs.get(n.name.as_ref()) {
                Some(&id) => Ok(id),
                None => Err(error_at(
                    self.text,
                    n.pos,
                    format!("unknown function `@{}`", n.name),
                )),
            }
        };
        for p in &raw.programs {
            let Some(&data) = datas.get(p.data.name.as_ref()) else {
                return self.err(p.data.pos, format!("unknown data `@{}`", p.data.name));
            };
            m.programs.push(ProgramEntry {
                name: p.name.to_string(),
                data,
                body: func_ref(&p.body)?,
                init: func_ref(&p.init)?,
                interval_us: p.interval_us,
                priority: p.priority,
            });
        }
        if let Some(g) = &raw.init_globals {
            m.init_globals = Some(func_ref(g)?);
        }
        if let Some(g) = &raw.globals {
            let Some(&data) = datas.get(g.name.as_ref()) else {
                return self.err(g.pos, format!("unknown data `@{}`", g.name));
            };
            m.globals = Some(data);
        }
        m.configuration = raw.configuration.as_ref().map(|c| self.configuration(c));
        m.unchecked_pointers = raw.unchecked_pointers;
        Ok(m)
    }

    fn function(
        &mut self,
        rf: &RawFunc,
        m: &Module,
        names: &Names,
    ) -> Result<Function, ParseError> {
        let mut f = Function::new(rf.name.name.clone(), rf.kind, rf.params.clone(), rf.ret);
        f.span = rf.span;

        // Slots, numbered in declaration order.
        let mut slots: HashMap<u32, SlotId> = HashMap::new();
        for s in &rf.slots {
            let ty = self.mem(&s.ty, names.aggs)?;
            let id = f.create_slot(s.name.clone(), ty);
            if slots.insert(s.num.n, id).is_some() {
                return self.err(s.num.pos, format!("ss{} is declared twice", s.num.n));
            }
        }

        // Blocks and value definitions.
        let max_block = rf.blocks.iter().max_by_key(|b| b.label.n);
        let max_value = rf
            .blocks
            .iter()
            .flat_map(|b| {
                b.params
                    .iter()
                    .map(|p| p.0)
                    .chain(b.insts.iter().filter_map(|i| i.result))
            })
            .max_by_key(|v| v.n);
        let nblocks = match max_block {
            Some(b) => self.spend(b.label.n, b.label.pos)?,
            None => 0,
        };
        let nvalues = match max_value {
            Some(v) => self.spend(v.n, v.pos)?,
            None => 0,
        };
        f.blocks = vec![BlockData::default(); nblocks];
        let mut defined_block = vec![false; nblocks];
        let mut defs: Vec<Option<ValueDef>> = vec![None; nvalues];
        // Types known from the text; `NONE` sources for values whose type is known.
        let mut known: Vec<Option<Type>> = vec![None; nvalues];
        // Instructions are created in text order: the `k`th one is `Inst(k)`.
        let mut next_inst = 0u32;
        for rb in &rf.blocks {
            let b = Block(rb.label.n);
            if std::mem::replace(&mut defined_block[b.index()], true) {
                return self.err(rb.label.pos, format!("{b} is defined twice"));
            }
            f.layout.push(b);
            for (k, (v, t)) in rb.params.iter().enumerate() {
                if defs[v.n as usize].is_some() {
                    return self.err(v.pos, format!("v{} is defined twice", v.n));
                }
                defs[v.n as usize] = Some(ValueDef::Param(b, k as u32));
                known[v.n as usize] = Some(*t);
                f.blocks[b.index()].params.push(Value(v.n));
            }
            for ri in &rb.insts {
                if let Some(r) = ri.result {
                    if defs[r.n as usize].is_some() {
                        return self.err(r.pos, format!("v{} is defined twice", r.n));
                    }
                    defs[r.n as usize] = Some(ValueDef::Result(Inst(next_inst)));
                }
                next_inst += 1;
            }
        }

        // Instructions.
        let mut srcs: Vec<[u32; 2]> = vec![[NONE; 2]; nvalues];
        let val = |v: V| -> Result<Value, ParseError> {
            match defs.get(v.n as usize) {
                Some(Some(_)) => Ok(Value(v.n)),
                _ => Err(error_at(
                    self.text,
                    v.pos,
                    format!("v{} is not defined", v.n),
                )),
            }
        };
        let block_call = |bc: &RawBlockCall| -> Result<BlockCall, ParseError> {
            if !defined_block
                .get(bc.block.n as usize)
                .copied()
                .unwrap_or(false)
            {
                return Err(error_at(
                    self.text,
                    bc.block.pos,
                    format!("block{} is not defined", bc.block.n),
                ));
            }
            let args = bc
                .args
                .iter()
                .map(|&a| val(a))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(BlockCall::new(Block(bc.block.n), args))
        };
        for rb in &rf.blocks {
            let b = Block(rb.label.n);
            for ri in &rb.insts {
                let mut src = [NONE; 2];
                let mut ty: Option<Type> = None;
                let has_result: Option<bool>;
                let data = match &ri.op {
                    RawOp::Iconst(t, imm) => {
                        ty = Some(*t);
                        has_result = Some(true);
                        InstData::Iconst { ty: *t, imm: *imm }
                    }
                    RawOp::SizeOf(t, of) => {
                        ty = Some(*t);
                        has_result = Some(true);
                        InstData::SizeOf {
                            ty: *t,
                            of: self.mem(of, names.aggs)?,
                        }
                    }
                    RawOp::Fconst(t, bits) => {
                        ty = Some(*t);
                        has_result = Some(true);
                        InstData::Fconst {
                            ty: *t,
                            bits: *bits,
                        }
                    }
                    RawOp::Unary(op, a) => {
                        src[0] = a.n;
                        has_result = Some(true);
                        InstData::Unary {
                            op: *op,
                            arg: val(*a)?,
                        }
                    }
                    RawOp::Binary(op, a, c) => {
                        src = [a.n, c.n];
                        has_result = Some(true);
                        InstData::Binary {
                            op: *op,
                            args: [val(*a)?, val(*c)?],
                        }
                    }
                    RawOp::Icmp(cond, a, c) => {
                        ty = Some(Type::I1);
                        has_result = Some(true);
                        InstData::Icmp {
                            cond: *cond,
                            args: [val(*a)?, val(*c)?],
                        }
                    }
                    RawOp::Fcmp(cond, a, c) => {
                        ty = Some(Type::I1);
                        has_result = Some(true);
                        InstData::Fcmp {
                            cond: *cond,
                            args: [val(*a)?, val(*c)?],
                        }
                    }
                    RawOp::Convert(op, t, a) => {
                        ty = Some(*t);
                        has_result = Some(true);
                        InstData::Convert {
                            op: *op,
                            ty: *t,
                            arg: val(*a)?,
                        }
                    }
                    RawOp::Select(c, a, e) => {
                        src = [a.n, e.n];
                        has_result = Some(true);
                        InstData::Select {
                            cond: val(*c)?,
                            if_true: val(*a)?,
                            if_false: val(*e)?,
                        }
                    }
                    RawOp::GlobalAddr(n) => {
                        ty = Some(Type::Ptr);
                        has_result = Some(true);
                        let Some(&data) = names.data.get(n.name.as_ref()) else {
                            return self.err(n.pos, format!("unknown data `@{}`", n.name));
                        };
                        InstData::GlobalAddr { data }
                    }
                    RawOp::SlotAddr(s) => {
                        ty = Some(Type::Ptr);
                        has_result = Some(true);
                        let Some(&slot) = slots.get(&s.n) else {
                            return self.err(s.pos, format!("ss{} is not declared", s.n));
                        };
                        InstData::SlotAddr { slot }
                    }
                    RawOp::FieldAddr(fa) => {
                        let (base, agg, field) = &**fa;
                        ty = Some(Type::Ptr);
                        has_result = Some(true);
                        let Some(&id) = names.aggs.get(agg.name.as_ref()) else {
                            return self.err(agg.pos, format!("unknown aggregate `%{}`", agg.name));
                        };
                        let AggDef::Struct(s) = &m.aggs[id.index()] else {
                            return self.err(agg.pos, format!("`%{}` is not a struct", agg.name));
                        };
                        let idx = s.fields.iter().position(|f| f.name == *field).or_else(|| {
                            s.fields
                                .iter()
                                .position(|f| f.name.eq_ignore_ascii_case(field))
                        });
                        let Some(idx) = idx else {
                            return self.err(
                                agg.pos,
                                format!("struct `%{}` has no field `{field}`", agg.name),
                            );
                        };
                        InstData::FieldAddr {
                            base: val(*base)?,
                            agg: id,
                            field: idx as u32,
                        }
                    }
                    RawOp::InlineC(ic) => {
                        let (agg, data, code) = &**ic;
                        has_result = Some(false);
                        let Some(&id) = names.aggs.get(agg.name.as_ref()) else {
                            return self.err(agg.pos, format!("unknown aggregate `%{}`", agg.name));
                        };
                        InstData::InlineC {
                            code: code.as_ref().into(),
                            agg: id,
                            data: val(*data)?,
                        }
                    }
                    RawOp::ElemAddr(ea) => {
                        let (base, agg, index) = &**ea;
                        ty = Some(Type::Ptr);
                        has_result = Some(true);
                        let Some(&id) = names.aggs.get(agg.name.as_ref()) else {
                            return self.err(agg.pos, format!("unknown aggregate `%{}`", agg.name));
                        };
                        InstData::ElemAddr {
                            base: val(*base)?,
                            agg: id,
                            index: val(*index)?,
                        }
                    }
                    RawOp::Load(t, a) => {
                        ty = Some(*t);
                        has_result = Some(true);
                        InstData::Load {
                            ty: *t,
                            addr: val(*a)?,
                        }
                    }
                    RawOp::Store(v, a) => {
                        has_result = Some(false);
                        InstData::Store {
                            value: val(*v)?,
                            addr: val(*a)?,
                        }
                    }
                    RawOp::Call(c) => {
                        let (n, args) = &**c;
                        let Some(&id) = names.funcs.get(n.name.as_ref()) else {
                            return self.err(n.pos, format!("unknown function `@{}`", n.name));
                        };
                        ty = names.rets[id.index()];
                        if ty.is_none() && ri.result.is_some() {
                            return self.err(ri.pos, format!("`@{}` returns no value", n.name));
                        }
                        has_result = None;
                        InstData::Call {
                            func: id,
                            args: args.iter().map(|&a| val(a)).collect::<Result<_, _>>()?,
                        }
                    }
                    RawOp::CallTable(c) => {
                        let (tn, index, args) = &**c;
                        let Some(&id) = names.tables.get(&tn.n) else {
                            return self.err(tn.pos, format!("t{} is not declared", tn.n));
                        };
                        ty = m.tables[id.index()].result;
                        if ty.is_none() && ri.result.is_some() {
                            return self.err(ri.pos, format!("t{} returns no value", tn.n));
                        }
                        has_result = None;
                        InstData::CallTable {
                            table: id,
                            index: val(*index)?,
                            args: args.iter().map(|&a| val(a)).collect::<Result<_, _>>()?,
                        }
                    }
                    RawOp::Intrinsic(op, args) => {
                        ty = op.result();
                        if ty.is_none() && ri.result.is_some() {
                            return self.err(ri.pos, format!("`{}` produces no value", op.name()));
                        }
                        has_result = None;
                        InstData::Intrinsic {
                            op: *op,
                            args: args.iter().map(|&a| val(a)).collect::<Result<_, _>>()?,
                        }
                    }
                    RawOp::Jump(d) => {
                        has_result = Some(false);
                        InstData::Jump {
                            dest: block_call(d)?,
                        }
                    }
                    RawOp::Brif(br) => {
                        let (c, t, e) = &**br;
                        has_result = Some(false);
                        InstData::Brif {
                            cond: val(*c)?,
                            then_dest: Box::new(block_call(t)?),
                            else_dest: Box::new(block_call(e)?),
                        }
                    }
                    RawOp::BrTable(bt) => {
                        let (index, default, table) = &**bt;
                        has_result = Some(false);
                        InstData::BrTable {
                            arg: val(*index)?,
                            default: Box::new(block_call(default)?),
                            table: table.iter().map(&block_call).collect::<Result<_, _>>()?,
                        }
                    }
                    RawOp::Return(v) => {
                        has_result = Some(false);
                        InstData::Return {
                            value: v.map(val).transpose()?,
                        }
                    }
                };
                match (has_result, ri.result) {
                    (Some(true), None) => {
                        return self.err(
                            ri.pos,
                            format!(
                                "`{}` produces a value: write `vN = {} …`",
                                ri.mnemonic, ri.mnemonic
                            ),
                        )
                    }
                    (Some(false), Some(_)) => {
                        return self.err(ri.pos, format!("`{}` produces no value", ri.mnemonic))
                    }
                    _ => {}
                }
                let inst = Inst::new(f.insts.len());
                f.insts.push(data);
                f.spans.push(ri.span);
                f.results.push(ri.result.map(|r| Value(r.n)));
                f.blocks[b.index()].insts.push(inst);
                if let Some(r) = ri.result {
                    known[r.n as usize] = ty;
                    srcs[r.n as usize] = src;
                }
            }
        }

        // Types of the results that depend on operands, in any order.
        infer_types(&mut known, &srcs);
        if let Some(n) = (0..nvalues).find(|&n| defs[n].is_some() && known[n].is_none()) {
            let pos = rf
                .blocks
                .iter()
                .flat_map(|b| b.insts.iter())
                .find_map(|i| i.result.filter(|r| r.n as usize == n))
                .map_or(rf.name.pos, |r| r.pos);
            return self.err(
                pos,
                format!("cannot infer the type of v{n}: it depends on itself"),
            );
        }

        // Values; numbers no definition uses become parameters of a dead block.
        let mut dead: Option<Block> = None;
        f.values = Vec::with_capacity(nvalues);
        for n in 0..nvalues {
            let vd = match defs[n] {
                Some(def) => ValueData {
                    ty: known[n].unwrap_or(Type::I32),
                    def,
                },
                None => {
                    let d = *dead.get_or_insert_with(|| {
                        f.blocks.push(BlockData::default());
                        Block::new(f.blocks.len() - 1)
                    });
                    let k = f.blocks[d.index()].params.len() as u32;
                    f.blocks[d.index()].params.push(Value::new(n));
                    ValueData {
                        ty: Type::I32,
                        def: ValueDef::Param(d, k),
                    }
                }
            };
            f.values.push(vd);
        }
        Ok(f)
    }
}

/// Name tables of a module being parsed.
struct Names<'n, 'a> {
    aggs: &'n HashMap<&'a str, AggId>,
    data: &'n HashMap<&'a str, DataId>,
    funcs: &'n HashMap<&'a str, FuncId>,
    rets: &'n [Option<Type>],
    /// Table numbers to ids.
    tables: &'n HashMap<u32, TableId>,
}

/// Fills `known` for values whose type is that of an operand: `srcs[v][0]` is the
/// preferred source (the first operand of a binary operation, the `true` arm of a
/// select), `srcs[v][1]` the fallback. Linear for chains of primary sources; the
/// fallback pass only runs on cycles of primary sources (invalid SSA).
fn infer_types(known: &mut [Option<Type>], srcs: &[[u32; 2]]) {
    let n = known.len();
    // 0 = not visited, 1 = on the current path, 2 = finished.
    let mut state = vec![0u8; n];
    let mut path: Vec<usize> = Vec::new();
    for start in 0..n {
        if known[start].is_some() || srcs[start][0] == NONE || state[start] != 0 {
            continue;
        }
        path.clear();
        let mut cur = start;
        let found = loop {
            if let Some(t) = known[cur] {
                break Some(t);
            }
            if state[cur] != 0 {
                break None; // a cycle, or a value that already failed
            }
            state[cur] = 1;
            path.push(cur);
            let next = srcs[cur][0];
            if next == NONE || next as usize >= n {
                break None;
            }
            cur = next as usize;
        };
        for &p in &path {
            state[p] = 2;
            if found.is_some() {
                known[p] = found;
            }
        }
    }
    // Fallback sources, until nothing changes.
    loop {
        let mut progress = false;
        for v in 0..n {
            if known[v].is_some() || srcs[v][0] == NONE {
                continue;
            }
            let t = srcs[v]
                .iter()
                .filter(|&&s| s != NONE)
                .find_map(|&s| known.get(s as usize).copied().flatten());
            if t.is_some() {
                known[v] = t;
                progress = true;
            }
        }
        if !progress {
            break;
        }
    }
}
