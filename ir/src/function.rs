//! Functions: blocks in layout order, instructions, SSA values and stack slots.

use crate::diag::Span;
use crate::entities::{Block, Inst, SlotId, Value};
use crate::inst::InstData;
use crate::module::Module;
use crate::types::{MemType, Type};

/// What a function is for. Informational: every kind is called the same way, but
/// backends and the runner use it (an FB body's first parameter is its instance).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum FuncKind {
    /// An IEC FUNCTION.
    Function,
    /// The body of a FUNCTION_BLOCK: `(instance: ptr)`.
    FbBody,
    /// The body of a PROGRAM: `(instance: ptr)`.
    ProgramBody,
    /// Cold-start initialisation of an instance or of the globals.
    Init,
    /// A helper the front end generated (integer power, …).
    Helper,
}

impl FuncKind {
    /// The keyword of the text form.
    pub fn name(self) -> &'static str {
        match self {
            FuncKind::Function => "function",
            FuncKind::FbBody => "fb",
            FuncKind::ProgramBody => "program",
            FuncKind::Init => "init",
            FuncKind::Helper => "helper",
        }
    }

    /// Parses a keyword of the text form.
    pub fn from_name(s: &str) -> Option<FuncKind> {
        Some(match s {
            "function" => FuncKind::Function,
            "fb" => FuncKind::FbBody,
            "program" => FuncKind::ProgramBody,
            "init" => FuncKind::Init,
            "helper" => FuncKind::Helper,
            _ => return None,
        })
    }
}

/// Where an SSA value comes from.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ValueDef {
    /// The `index`th parameter of a block.
    Param(Block, u32),
    /// The result of an instruction.
    Result(Inst),
}

/// An SSA value's type and definition.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct ValueData {
    /// Its type.
    pub ty: Type,
    /// Where it is defined.
    pub def: ValueDef,
}

/// A basic block: parameters and instructions, the last of which is a terminator.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BlockData {
    /// The block's parameters (the SSA form of phi nodes).
    pub params: Vec<Value>,
    /// Its instructions in order.
    pub insts: Vec<Inst>,
}

/// Memory local to one call of a function (FUNCTION locals whose address is taken,
/// VAR_OUTPUT/VAR_IN_OUT buffers, local arrays).
#[derive(Clone, Debug, PartialEq)]
pub struct Slot {
    /// A name for listings (the source variable, if any).
    pub name: String,
    /// What it holds.
    pub ty: MemType,
}

/// A function of the IR.
///
/// Entities are stored in vectors indexed by their ids. `layout` gives the order of the
/// blocks; its first block is the entry, whose parameters are the function's
/// parameters. A block removed from `layout` is dead and ignored by everyone.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Unique name within the module.
    pub name: String,
    /// What the function is for.
    pub kind: FuncKind,
    /// Parameter types.
    pub params: Vec<Type>,
    /// Result type, if it returns a value.
    pub ret: Option<Type>,
    /// The declaration it was lowered from (for diagnostics).
    pub span: Option<Span>,
    /// Stack slots.
    pub slots: Vec<Slot>,
    /// All instructions ever created (only those in a block of `layout` are live).
    pub insts: Vec<InstData>,
    /// The result of each instruction.
    pub results: Vec<Option<Value>>,
    /// The source location of each instruction.
    pub spans: Vec<Option<Span>>,
    /// All values ever created.
    pub values: Vec<ValueData>,
    /// All blocks ever created.
    pub blocks: Vec<BlockData>,
    /// Blocks in layout order; the first is the entry.
    pub layout: Vec<Block>,
}

impl Function {
    /// An empty function (no blocks yet).
    pub fn new(
        name: impl Into<String>,
        kind: FuncKind,
        params: Vec<Type>,
        ret: Option<Type>,
    ) -> Function {
        Function {
            name: name.into(),
            kind,
            params,
            ret,
            span: None,
            slots: Vec::new(),
            insts: Vec::new(),
            results: Vec::new(),
            spans: Vec::new(),
            values: Vec::new(),
            blocks: Vec::new(),
            layout: Vec::new(),
        }
    }

    /// The entry block.
    pub fn entry(&self) -> Option<Block> {
        self.layout.first().copied()
    }

    /// The type of a value.
    #[inline]
    pub fn value_type(&self, v: Value) -> Type {
        self.values[v.index()].ty
    }

    /// The definition of a value.
    #[inline]
    pub fn value_def(&self, v: Value) -> ValueDef {
        self.values[v.index()].def
    }

    /// An instruction's data.
    #[inline]
    pub fn inst(&self, i: Inst) -> &InstData {
        &self.insts[i.index()]
    }

    /// An instruction's data, for rewriting.
    #[inline]
    pub fn inst_mut(&mut self, i: Inst) -> &mut InstData {
        &mut self.insts[i.index()]
    }

    /// An instruction's result.
    #[inline]
    pub fn result(&self, i: Inst) -> Option<Value> {
        self.results[i.index()]
    }

    /// A block's data.
    #[inline]
    pub fn block(&self, b: Block) -> &BlockData {
        &self.blocks[b.index()]
    }

    /// The last instruction of a block, if it is a terminator.
    pub fn terminator(&self, b: Block) -> Option<Inst> {
        let last = *self.blocks[b.index()].insts.last()?;
        self.insts[last.index()].is_terminator().then_some(last)
    }

    /// Creates a block that is not yet in the layout.
    pub fn create_block(&mut self) -> Block {
        self.blocks.push(BlockData::default());
        Block::new(self.blocks.len() - 1)
    }

    /// Adds a parameter of type `ty` to `block`.
    pub fn append_block_param(&mut self, block: Block, ty: Type) -> Value {
        let index = self.blocks[block.index()].params.len() as u32;
        let v = self.make_value(ty, ValueDef::Param(block, index));
        self.blocks[block.index()].params.push(v);
        v
    }

    /// Creates an instruction (not placed in any block) and its result value, whose
    /// type is `result`.
    pub fn create_inst(
        &mut self,
        data: InstData,
        result: Option<Type>,
        span: Option<Span>,
    ) -> Inst {
        let inst = Inst::new(self.insts.len());
        self.insts.push(data);
        self.spans.push(span);
        let res = result.map(|ty| self.make_value(ty, ValueDef::Result(inst)));
        self.results.push(res);
        inst
    }

    /// Adds a stack slot.
    pub fn create_slot(&mut self, name: impl Into<String>, ty: MemType) -> SlotId {
        self.slots.push(Slot {
            name: name.into(),
            ty,
        });
        SlotId::new(self.slots.len() - 1)
    }

    /// Makes room for `insts` more instructions (and as many values) without the
    /// arenas' doubling: for a pass that adds a known few to a large function.
    pub fn reserve(&mut self, insts: usize) {
        self.insts.reserve_exact(insts);
        self.results.reserve_exact(insts);
        self.spans.reserve_exact(insts);
        self.values.reserve_exact(insts);
    }

    /// Drops what the passes left behind: the instructions no block of the layout
    /// holds and the values neither they nor a layout block's parameters define;
    /// blocks out of the layout are emptied. What stays keeps its order (number `k`
    /// becomes the count of those kept before it), so that whatever orders
    /// instructions or values by number orders them as before; the printed names
    /// change. Returns the number of instructions dropped.
    pub fn compact(&mut self) -> usize {
        let mut in_layout = vec![false; self.blocks.len()];
        let mut live_inst = vec![false; self.insts.len()];
        let mut live_value = vec![false; self.values.len()];
        for &b in &self.layout {
            in_layout[b.index()] = true;
            let data = &self.blocks[b.index()];
            for &p in &data.params {
                live_value[p.index()] = true;
            }
            for &i in &data.insts {
                live_inst[i.index()] = true;
                if let Some(r) = self.results[i.index()] {
                    live_value[r.index()] = true;
                }
            }
        }
        let kept = live_inst.iter().filter(|&&l| l).count();
        let dropped = self.insts.len() - kept;
        if dropped == 0 && live_value.iter().all(|&l| l) {
            return 0;
        }
        // The new number of each kept one: those kept before it.
        let renumber = |live: &[bool]| -> Vec<u32> {
            let mut next = 0;
            live.iter()
                .map(|&l| {
                    let k = next;
                    next += u32::from(l);
                    k
                })
                .collect()
        };
        let (inst_to, value_to) = (renumber(&live_inst), renumber(&live_value));
        let value = |v: Value| {
            debug_assert!(live_value[v.index()], "{v} is used but not defined");
            Value::new(value_to[v.index()] as usize)
        };
        let inst = |i: Inst| Inst::new(inst_to[i.index()] as usize);
        let mut insts = Vec::with_capacity(kept);
        let mut results = Vec::with_capacity(kept);
        let mut spans = Vec::with_capacity(kept);
        let old = std::mem::take(&mut self.insts);
        for (k, mut data) in old.into_iter().enumerate() {
            if live_inst[k] {
                data.map_args(value);
                insts.push(data);
                results.push(self.results[k].map(value));
                spans.push(self.spans[k]);
            }
        }
        self.values = self
            .values
            .iter()
            .zip(&live_value)
            .filter(|(_, &l)| l)
            .map(|(d, _)| ValueData {
                ty: d.ty,
                def: match d.def {
                    ValueDef::Result(i) => ValueDef::Result(inst(i)),
                    param => param,
                },
            })
            .collect();
        (self.insts, self.results, self.spans) = (insts, results, spans);
        for (b, data) in self.blocks.iter_mut().enumerate() {
            if in_layout[b] {
                data.params.iter_mut().for_each(|p| *p = value(*p));
                data.insts.iter_mut().for_each(|i| *i = inst(*i));
            } else {
                *data = BlockData::default();
            }
        }
        dropped
    }

    fn make_value(&mut self, ty: Type, def: ValueDef) -> Value {
        self.values.push(ValueData { ty, def });
        Value::new(self.values.len() - 1)
    }

    /// Live instructions in layout order, with their blocks.
    pub fn inst_iter(&self) -> impl Iterator<Item = (Block, Inst)> + '_ {
        self.layout
            .iter()
            .flat_map(move |&b| self.blocks[b.index()].insts.iter().map(move |&i| (b, i)))
    }

    /// Makes this function `other`, moving `other`'s tables into its own, whose
    /// capacity stays: a scratch function to build many functions in, one after the
    /// other (see [`Function::take_exact`]).
    pub fn refill_from(&mut self, mut other: Function) {
        fn refill<T>(to: &mut Vec<T>, from: &mut Vec<T>) {
            to.clear();
            to.append(from);
        }
        refill(&mut self.slots, &mut other.slots);
        refill(&mut self.insts, &mut other.insts);
        refill(&mut self.results, &mut other.results);
        refill(&mut self.spans, &mut other.spans);
        refill(&mut self.values, &mut other.values);
        refill(&mut self.blocks, &mut other.blocks);
        refill(&mut self.layout, &mut other.layout);
        self.name = other.name;
        self.kind = other.kind;
        self.params = other.params;
        self.ret = other.ret;
        self.span = other.span;
    }

    /// Moves the function out into one whose tables are exactly as long as they
    /// need to be, leaving this one empty with its capacity kept for the next.
    /// Tables grown by doubling are about a third unused, and a program's IR waits
    /// whole for the optimiser: a front end that builds each function in one
    /// scratch function and keeps this copy holds 11% less memory at its peak
    /// (BENCHMARKS.md, compile scaling). `Vec::shrink_to_fit` would not do: mimalloc
    /// keeps a block in place when it shrinks by less than half.
    pub fn take_exact(&mut self) -> Function {
        fn exact<T>(v: &mut Vec<T>) -> Vec<T> {
            let mut new = Vec::with_capacity(v.len());
            new.append(v);
            new
        }
        Function {
            name: std::mem::take(&mut self.name),
            kind: self.kind,
            params: std::mem::take(&mut self.params),
            ret: self.ret,
            span: self.span,
            slots: exact(&mut self.slots),
            insts: exact(&mut self.insts),
            results: exact(&mut self.results),
            spans: exact(&mut self.spans),
            values: exact(&mut self.values),
            blocks: exact(&mut self.blocks),
            layout: exact(&mut self.layout),
        }
    }

    /// The number of live instructions.
    pub fn live_inst_count(&self) -> usize {
        self.layout
            .iter()
            .map(|b| self.blocks[b.index()].insts.len())
            .sum()
    }

    /// The result type an instruction produces, computed from its operands.
    /// `module` resolves callee signatures. Returns `None` for instructions without a
    /// result.
    pub fn result_type_of(&self, module: &Module, data: &InstData) -> Option<Type> {
        match data {
            InstData::Iconst { ty, .. }
            | InstData::Fconst { ty, .. }
            | InstData::SizeOf { ty, .. } => Some(*ty),
            InstData::Unary { arg, .. } => Some(self.value_type(*arg)),
            InstData::Binary { args, .. } => Some(self.value_type(args[0])),
            InstData::Icmp { .. } | InstData::Fcmp { .. } => Some(Type::I1),
            InstData::Convert { ty, .. } => Some(*ty),
            InstData::Select { if_true, .. } => Some(self.value_type(*if_true)),
            InstData::GlobalAddr { .. }
            | InstData::SlotAddr { .. }
            | InstData::FieldAddr { .. }
            | InstData::ElemAddr { .. } => Some(Type::Ptr),
            InstData::Load { ty, .. } => Some(*ty),
            InstData::Store { .. } => None,
            InstData::Call { func, .. } => module.funcs.get(func.index()).and_then(|f| f.ret),
            InstData::CallTable { table, .. } => {
                module.tables.get(table.index()).and_then(|t| t.result)
            }
            InstData::Intrinsic { op, .. } => op.result(),
            InstData::InlineC { .. } => None,
            InstData::Jump { .. }
            | InstData::Brif { .. }
            | InstData::BrTable { .. }
            | InstData::Return { .. } => None,
        }
    }

    /// Predecessor blocks of every block (indexed by block), from the terminators of
    /// the blocks in the layout. A block appears once per edge.
    pub fn predecessors(&self) -> Vec<Vec<Block>> {
        let mut preds = vec![Vec::new(); self.blocks.len()];
        for &b in &self.layout {
            if let Some(t) = self.terminator(b) {
                for dest in self.insts[t.index()].successors() {
                    preds[dest.block.index()].push(b);
                }
            }
        }
        preds
    }

    /// Successor blocks of a block (one per edge).
    pub fn successors(&self, b: Block) -> Vec<Block> {
        match self.terminator(b) {
            Some(t) => self.insts[t.index()]
                .successors()
                .into_iter()
                .map(|d| d.block)
                .collect(),
            None => Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builder::FuncBuilder;
    use crate::inst::BinaryOp;

    /// A function of `n` additions, built in `f`.
    fn build(f: &mut Function, n: i64) {
        let mut b = FuncBuilder::new(f);
        let mut acc = b.iconst(Type::I32, 0);
        for k in 0..n {
            let c = b.iconst(Type::I32, k);
            acc = b.binary(BinaryOp::Iadd, acc, c);
        }
        b.ret(Some(acc));
    }

    fn new(name: &str) -> Function {
        Function::new(name, FuncKind::Function, Vec::new(), Some(Type::I32))
    }

    #[test]
    fn a_scratch_function_hands_out_exact_copies_and_keeps_its_room() {
        let mut scratch = new("scratch");
        let mut copies = Vec::new();
        for (name, n) in [("big", 100), ("small", 3)] {
            scratch.refill_from(new(name));
            build(&mut scratch, n);
            let copy = scratch.take_exact();
            assert_eq!(copy.insts.capacity(), copy.insts.len());
            assert_eq!(copy.values.capacity(), copy.values.len());
            assert!(scratch.insts.is_empty() && scratch.insts.capacity() >= 201);
            copies.push(copy);
        }
        // The same as building each function on its own.
        for (copy, (name, n)) in copies.iter().zip([("big", 100), ("small", 3)]) {
            let mut alone = new(name);
            build(&mut alone, n);
            assert_eq!(*copy, alone);
        }
    }
}
