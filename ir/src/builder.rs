//! A cursor for appending instructions to a function.

use crate::diag::Span;
use crate::entities::{AggId, Block, DataId, FuncId, SlotId, TableId, Value};
use crate::function::Function;
use crate::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, InstData, IntCC, Intrinsic, UnaryOp};
use crate::types::{MemType, Type};

/// Appends instructions at the end of a current block.
///
/// Blocks enter the layout when the builder first switches to them, so the layout
/// follows the order the front end fills blocks in. Appending to a block that already
/// ends in a terminator (code after `RETURN` or `EXIT`) opens a fresh unreachable block
/// rather than corrupting the terminated one; CFG simplification removes it.
pub struct FuncBuilder<'f> {
    /// The function being built.
    pub func: &'f mut Function,
    current: Option<Block>,
    placed: Vec<bool>,
    span: Option<Span>,
}

impl<'f> FuncBuilder<'f> {
    /// A builder for `func`. If the function has no blocks yet, an entry block with one
    /// parameter per function parameter is created and made current.
    pub fn new(func: &'f mut Function) -> FuncBuilder<'f> {
        let mut placed = vec![false; func.blocks.len()];
        for &b in &func.layout {
            placed[b.index()] = true;
        }
        let mut b = FuncBuilder {
            func,
            current: None,
            placed,
            span: None,
        };
        if b.func.layout.is_empty() {
            let entry = b.create_block();
            let params = b.func.params.clone();
            for ty in params {
                b.func.append_block_param(entry, ty);
            }
            b.switch_to(entry);
        }
        b
    }

    /// The source location given to the instructions appended from now on.
    pub fn set_span(&mut self, span: Option<Span>) {
        self.span = span;
    }

    /// The current source location.
    pub fn span(&self) -> Option<Span> {
        self.span
    }

    /// The parameters of the entry block (the function's parameters).
    pub fn params(&self) -> Vec<Value> {
        let entry = self.func.layout[0];
        self.func.block(entry).params.clone()
    }

    /// A new block, not yet in the layout.
    pub fn create_block(&mut self) -> Block {
        let b = self.func.create_block();
        self.placed.push(false);
        b
    }

    /// Adds a parameter to a block.
    pub fn block_param(&mut self, block: Block, ty: Type) -> Value {
        self.func.append_block_param(block, ty)
    }

    /// Makes `block` current, placing it at the end of the layout the first time.
    pub fn switch_to(&mut self, block: Block) {
        if !self.placed[block.index()] {
            self.placed[block.index()] = true;
            self.func.layout.push(block);
        }
        self.current = Some(block);
    }

    /// The block instructions go to.
    pub fn current_block(&self) -> Option<Block> {
        self.current
    }

    /// True if the current block already ends in a terminator.
    pub fn is_terminated(&self) -> bool {
        match self.current {
            Some(b) => self.func.terminator(b).is_some(),
            None => true,
        }
    }

    /// Adds a stack slot.
    pub fn slot(&mut self, name: impl Into<String>, ty: MemType) -> SlotId {
        self.func.create_slot(name, ty)
    }

    fn push(&mut self, data: InstData, result: Option<Type>) -> Option<Value> {
        if self.is_terminated() {
            let fresh = self.create_block();
            self.switch_to(fresh);
        }
        let block = self.current.expect("a current block");
        let inst = self.func.create_inst(data, result, self.span);
        self.func.blocks[block.index()].insts.push(inst);
        self.func.result(inst)
    }

    fn push_value(&mut self, data: InstData, ty: Type) -> Value {
        self.push(data, Some(ty)).expect("instruction has a result")
    }

    /// An integer constant (canonicalised to the type's width).
    pub fn iconst(&mut self, ty: Type, imm: i64) -> Value {
        let imm = ty.canon_int(imm);
        self.push_value(InstData::Iconst { ty, imm }, ty)
    }

    /// `sizeof.ty of`: the size of `of` in the target's layout, as a `ty`.
    pub fn size_of(&mut self, ty: Type, of: MemType) -> Value {
        self.push_value(InstData::SizeOf { ty, of }, ty)
    }

    /// A `f32` constant.
    pub fn f32const(&mut self, v: f32) -> Value {
        self.push_value(
            InstData::Fconst {
                ty: Type::F32,
                bits: v.to_bits() as u64,
            },
            Type::F32,
        )
    }

    /// A `f64` constant.
    pub fn f64const(&mut self, v: f64) -> Value {
        self.push_value(
            InstData::Fconst {
                ty: Type::F64,
                bits: v.to_bits(),
            },
            Type::F64,
        )
    }

    /// A float constant of type `ty` (`F32` rounds `v` to binary32).
    pub fn fconst(&mut self, ty: Type, v: f64) -> Value {
        if ty == Type::F32 {
            self.f32const(v as f32)
        } else {
            self.f64const(v)
        }
    }

    /// `op arg`
    pub fn unary(&mut self, op: UnaryOp, arg: Value) -> Value {
        let ty = self.func.value_type(arg);
        self.push_value(InstData::Unary { op, arg }, ty)
    }

    /// `op a, b`
    pub fn binary(&mut self, op: BinaryOp, a: Value, b: Value) -> Value {
        let ty = self.func.value_type(a);
        self.push_value(InstData::Binary { op, args: [a, b] }, ty)
    }

    /// `icmp cond a, b`
    pub fn icmp(&mut self, cond: IntCC, a: Value, b: Value) -> Value {
        self.push_value(InstData::Icmp { cond, args: [a, b] }, Type::I1)
    }

    /// `fcmp cond a, b`
    pub fn fcmp(&mut self, cond: FloatCC, a: Value, b: Value) -> Value {
        self.push_value(InstData::Fcmp { cond, args: [a, b] }, Type::I1)
    }

    /// `op.ty arg`
    pub fn convert(&mut self, op: ConvOp, ty: Type, arg: Value) -> Value {
        self.push_value(InstData::Convert { op, ty, arg }, ty)
    }

    /// `select cond, a, b`
    pub fn select(&mut self, cond: Value, if_true: Value, if_false: Value) -> Value {
        let ty = self.func.value_type(if_true);
        self.push_value(
            InstData::Select {
                cond,
                if_true,
                if_false,
            },
            ty,
        )
    }

    /// The address of a data object.
    pub fn global_addr(&mut self, data: DataId) -> Value {
        self.push_value(InstData::GlobalAddr { data }, Type::Ptr)
    }

    /// The address of a stack slot.
    pub fn slot_addr(&mut self, slot: SlotId) -> Value {
        self.push_value(InstData::SlotAddr { slot }, Type::Ptr)
    }

    /// The address of a struct field.
    pub fn field_addr(&mut self, base: Value, agg: AggId, field: u32) -> Value {
        self.push_value(InstData::FieldAddr { base, agg, field }, Type::Ptr)
    }

    /// The address of an array element (zero-based index, in range).
    pub fn elem_addr(&mut self, base: Value, agg: AggId, index: Value) -> Value {
        self.push_value(InstData::ElemAddr { base, agg, index }, Type::Ptr)
    }

    /// `load.ty addr`
    pub fn load(&mut self, ty: Type, addr: Value) -> Value {
        self.push_value(InstData::Load { ty, addr }, ty)
    }

    /// `store value, addr`
    pub fn store(&mut self, value: Value, addr: Value) {
        self.push(InstData::Store { value, addr }, None);
    }

    /// `call @func(args)`; `ret` is the callee's result type.
    pub fn call(&mut self, func: FuncId, ret: Option<Type>, args: Vec<Value>) -> Option<Value> {
        self.push(InstData::Call { func, args }, ret)
    }

    /// `call_table table, index(args)`: a call of entry `index` of a function table;
    /// `ret` is the table's result type.
    pub fn call_table(
        &mut self,
        table: TableId,
        ret: Option<Type>,
        index: Value,
        args: Vec<Value>,
    ) -> Option<Value> {
        self.push(InstData::CallTable { table, index, args }, ret)
    }

    /// A runtime service.
    pub fn intrinsic(&mut self, op: Intrinsic, args: Vec<Value>) -> Option<Value> {
        self.push(InstData::Intrinsic { op, args }, op.result())
    }

    /// `inline_c %agg, data, "code"`: C code for the `c` target, `data__` being
    /// `data` (a pointer to struct `agg`).
    pub fn inline_c(&mut self, code: &str, agg: AggId, data: Value) {
        self.push(
            InstData::InlineC {
                code: code.into(),
                agg,
                data,
            },
            None,
        );
    }

    /// `jump dest(args)`
    pub fn jump(&mut self, dest: Block, args: Vec<Value>) {
        self.push(
            InstData::Jump {
                dest: BlockCall::new(dest, args),
            },
            None,
        );
    }

    /// `brif cond, then(then_args), else(else_args)`
    pub fn brif(
        &mut self,
        cond: Value,
        then_block: Block,
        then_args: Vec<Value>,
        else_block: Block,
        else_args: Vec<Value>,
    ) {
        self.push(
            InstData::Brif {
                cond,
                then_dest: Box::new(BlockCall::new(then_block, then_args)),
                else_dest: Box::new(BlockCall::new(else_block, else_args)),
            },
            None,
        );
    }

    /// `br_table arg, default(args), [table…]`: to `table[arg]` (`arg` read unsigned),
    /// or to `default` when `arg` is not below the table's length.
    pub fn br_table(&mut self, arg: Value, default: BlockCall, table: Vec<BlockCall>) {
        self.push(
            InstData::BrTable {
                arg,
                default: Box::new(default),
                table,
            },
            None,
        );
    }

    /// `return` / `return value`
    pub fn ret(&mut self, value: Option<Value>) {
        self.push(InstData::Return { value }, None);
    }
}
