//! Instructions and their operations.
//!
//! The semantics here are the contract every backend and the interpreter implement bit
//! for bit (see `docs/ir.md` for the full table). In short: integer arithmetic wraps;
//! division and remainder by zero give 0 and raise the fault flag; shifts by at least
//! the width give 0; rotates take the count modulo the width; float-to-integer
//! conversions truncate toward zero, saturate, and give 0 for NaN.

use crate::entities::{AggId, Block, DataId, FuncId, SlotId, TableId, Value};
use crate::types::{MemType, Type};

/// Unary operations. The result has the operand's type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// Two's complement negation (wraps: `-MIN = MIN`).
    Ineg,
    /// Bitwise complement; on `i1` it is logical NOT.
    Bnot,
    /// Absolute value of a signed integer (wraps: `abs(MIN) = MIN`).
    Iabs,
    /// Float negation.
    Fneg,
    /// Float absolute value.
    Fabs,
    /// Square root (NaN for negative operands).
    Fsqrt,
    /// Round to the nearest integral value, ties to even.
    Fnearest,
    /// Round toward zero to an integral value.
    Ftrunc,
    /// Round toward negative infinity.
    Ffloor,
    /// Round toward positive infinity.
    Fceil,
    /// Sine (radians).
    Sin,
    /// Cosine.
    Cos,
    /// Tangent.
    Tan,
    /// Arc sine.
    Asin,
    /// Arc cosine.
    Acos,
    /// Arc tangent.
    Atan,
    /// Natural logarithm.
    Ln,
    /// Base-10 logarithm.
    Log10,
    /// e to the power.
    Exp,
}

impl UnaryOp {
    /// Every unary operation.
    pub const ALL: [UnaryOp; 19] = [
        UnaryOp::Ineg,
        UnaryOp::Bnot,
        UnaryOp::Iabs,
        UnaryOp::Fneg,
        UnaryOp::Fabs,
        UnaryOp::Fsqrt,
        UnaryOp::Fnearest,
        UnaryOp::Ftrunc,
        UnaryOp::Ffloor,
        UnaryOp::Fceil,
        UnaryOp::Sin,
        UnaryOp::Cos,
        UnaryOp::Tan,
        UnaryOp::Asin,
        UnaryOp::Acos,
        UnaryOp::Atan,
        UnaryOp::Ln,
        UnaryOp::Log10,
        UnaryOp::Exp,
    ];

    /// The mnemonic of the text form.
    pub fn name(self) -> &'static str {
        match self {
            UnaryOp::Ineg => "ineg",
            UnaryOp::Bnot => "bnot",
            UnaryOp::Iabs => "iabs",
            UnaryOp::Fneg => "fneg",
            UnaryOp::Fabs => "fabs",
            UnaryOp::Fsqrt => "fsqrt",
            UnaryOp::Fnearest => "fnearest",
            UnaryOp::Ftrunc => "ftrunc",
            UnaryOp::Ffloor => "ffloor",
            UnaryOp::Fceil => "fceil",
            UnaryOp::Sin => "sin",
            UnaryOp::Cos => "cos",
            UnaryOp::Tan => "tan",
            UnaryOp::Asin => "asin",
            UnaryOp::Acos => "acos",
            UnaryOp::Atan => "atan",
            UnaryOp::Ln => "ln",
            UnaryOp::Log10 => "log10",
            UnaryOp::Exp => "exp",
        }
    }

    /// True if the operand must be an integer (else it must be a float).
    pub fn is_int_op(self) -> bool {
        matches!(self, UnaryOp::Ineg | UnaryOp::Bnot | UnaryOp::Iabs)
    }
}

/// Binary operations. Both operands and the result have one type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// Wrapping addition.
    Iadd,
    /// Wrapping subtraction.
    Isub,
    /// Wrapping multiplication (low half).
    Imul,
    /// Signed division truncating toward zero; `x/0 = 0` + fault; `MIN/-1 = MIN`.
    Sdiv,
    /// Unsigned division; `x/0 = 0` + fault.
    Udiv,
    /// Signed remainder with the sign of the dividend; `x%0 = 0` + fault; `x%-1 = 0`.
    Srem,
    /// Unsigned remainder; `x%0 = 0` + fault.
    Urem,
    /// Bitwise AND (logical on `i1`).
    Band,
    /// Bitwise OR.
    Bor,
    /// Bitwise XOR.
    Bxor,
    /// Shift left; a count (read unsigned) of at least the width gives 0.
    Ishl,
    /// Logical shift right; a count of at least the width gives 0.
    Ushr,
    /// Arithmetic shift right; a count of at least the width gives the sign fill.
    Sshr,
    /// Rotate left by the count modulo the width.
    Rotl,
    /// Rotate right by the count modulo the width.
    Rotr,
    /// IEEE addition.
    Fadd,
    /// IEEE subtraction.
    Fsub,
    /// IEEE multiplication.
    Fmul,
    /// IEEE division (by zero gives an infinity or NaN; no fault).
    Fdiv,
    /// `pow(a, b)` of the C library.
    Fpow,
    /// Arc tangent of a/b using both signs (`atan2`).
    Fatan2,
}

impl BinaryOp {
    /// Every binary operation.
    pub const ALL: [BinaryOp; 21] = [
        BinaryOp::Iadd,
        BinaryOp::Isub,
        BinaryOp::Imul,
        BinaryOp::Sdiv,
        BinaryOp::Udiv,
        BinaryOp::Srem,
        BinaryOp::Urem,
        BinaryOp::Band,
        BinaryOp::Bor,
        BinaryOp::Bxor,
        BinaryOp::Ishl,
        BinaryOp::Ushr,
        BinaryOp::Sshr,
        BinaryOp::Rotl,
        BinaryOp::Rotr,
        BinaryOp::Fadd,
        BinaryOp::Fsub,
        BinaryOp::Fmul,
        BinaryOp::Fdiv,
        BinaryOp::Fpow,
        BinaryOp::Fatan2,
    ];

    /// The mnemonic of the text form.
    pub fn name(self) -> &'static str {
        match self {
            BinaryOp::Iadd => "iadd",
            BinaryOp::Isub => "isub",
            BinaryOp::Imul => "imul",
            BinaryOp::Sdiv => "sdiv",
            BinaryOp::Udiv => "udiv",
            BinaryOp::Srem => "srem",
            BinaryOp::Urem => "urem",
            BinaryOp::Band => "band",
            BinaryOp::Bor => "bor",
            BinaryOp::Bxor => "bxor",
            BinaryOp::Ishl => "ishl",
            BinaryOp::Ushr => "ushr",
            BinaryOp::Sshr => "sshr",
            BinaryOp::Rotl => "rotl",
            BinaryOp::Rotr => "rotr",
            BinaryOp::Fadd => "fadd",
            BinaryOp::Fsub => "fsub",
            BinaryOp::Fmul => "fmul",
            BinaryOp::Fdiv => "fdiv",
            BinaryOp::Fpow => "fpow",
            BinaryOp::Fatan2 => "fatan2",
        }
    }

    /// True if the operands must be integers (else floats).
    pub fn is_int_op(self) -> bool {
        !matches!(
            self,
            BinaryOp::Fadd
                | BinaryOp::Fsub
                | BinaryOp::Fmul
                | BinaryOp::Fdiv
                | BinaryOp::Fpow
                | BinaryOp::Fatan2
        )
    }

    /// True for the operations that may raise the fault flag (division by zero).
    pub fn can_fault(self) -> bool {
        matches!(
            self,
            BinaryOp::Sdiv | BinaryOp::Udiv | BinaryOp::Srem | BinaryOp::Urem
        )
    }

    /// True if `a op b == b op a`.
    pub fn is_commutative(self) -> bool {
        matches!(
            self,
            BinaryOp::Iadd
                | BinaryOp::Imul
                | BinaryOp::Band
                | BinaryOp::Bor
                | BinaryOp::Bxor
                | BinaryOp::Fadd
                | BinaryOp::Fmul
        )
    }
}

/// Integer comparison conditions.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum IntCC {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// signed `<`
    Slt,
    /// signed `<=`
    Sle,
    /// signed `>`
    Sgt,
    /// signed `>=`
    Sge,
    /// unsigned `<`
    Ult,
    /// unsigned `<=`
    Ule,
    /// unsigned `>`
    Ugt,
    /// unsigned `>=`
    Uge,
}

impl IntCC {
    /// Every condition.
    pub const ALL: [IntCC; 10] = [
        IntCC::Eq,
        IntCC::Ne,
        IntCC::Slt,
        IntCC::Sle,
        IntCC::Sgt,
        IntCC::Sge,
        IntCC::Ult,
        IntCC::Ule,
        IntCC::Ugt,
        IntCC::Uge,
    ];

    /// The name of the text form.
    pub fn name(self) -> &'static str {
        match self {
            IntCC::Eq => "eq",
            IntCC::Ne => "ne",
            IntCC::Slt => "slt",
            IntCC::Sle => "sle",
            IntCC::Sgt => "sgt",
            IntCC::Sge => "sge",
            IntCC::Ult => "ult",
            IntCC::Ule => "ule",
            IntCC::Ugt => "ugt",
            IntCC::Uge => "uge",
        }
    }

    /// The condition with the operands swapped (`a < b` is `b > a`).
    pub fn swapped(self) -> IntCC {
        match self {
            IntCC::Eq => IntCC::Eq,
            IntCC::Ne => IntCC::Ne,
            IntCC::Slt => IntCC::Sgt,
            IntCC::Sle => IntCC::Sge,
            IntCC::Sgt => IntCC::Slt,
            IntCC::Sge => IntCC::Sle,
            IntCC::Ult => IntCC::Ugt,
            IntCC::Ule => IntCC::Uge,
            IntCC::Ugt => IntCC::Ult,
            IntCC::Uge => IntCC::Ule,
        }
    }

    /// The negated condition (`!(a < b)` is `a >= b`).
    pub fn inverted(self) -> IntCC {
        match self {
            IntCC::Eq => IntCC::Ne,
            IntCC::Ne => IntCC::Eq,
            IntCC::Slt => IntCC::Sge,
            IntCC::Sle => IntCC::Sgt,
            IntCC::Sgt => IntCC::Sle,
            IntCC::Sge => IntCC::Slt,
            IntCC::Ult => IntCC::Uge,
            IntCC::Ule => IntCC::Ugt,
            IntCC::Ugt => IntCC::Ule,
            IntCC::Uge => IntCC::Ult,
        }
    }
}

/// Float comparison conditions. All are false when an operand is NaN, except `Ne`,
/// which is true (IEEE "unordered or not equal", as `<>` in IEC 61131-3).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum FloatCC {
    /// ordered `==`
    Eq,
    /// unordered or `!=`
    Ne,
    /// ordered `<`
    Lt,
    /// ordered `<=`
    Le,
    /// ordered `>`
    Gt,
    /// ordered `>=`
    Ge,
}

impl FloatCC {
    /// Every condition.
    pub const ALL: [FloatCC; 6] = [
        FloatCC::Eq,
        FloatCC::Ne,
        FloatCC::Lt,
        FloatCC::Le,
        FloatCC::Gt,
        FloatCC::Ge,
    ];

    /// The name of the text form.
    pub fn name(self) -> &'static str {
        match self {
            FloatCC::Eq => "eq",
            FloatCC::Ne => "ne",
            FloatCC::Lt => "lt",
            FloatCC::Le => "le",
            FloatCC::Gt => "gt",
            FloatCC::Ge => "ge",
        }
    }
}

/// Conversions between types. The result type is given by the instruction.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ConvOp {
    /// Sign-extend an integer to a wider one.
    Sext,
    /// Zero-extend an integer (or `i1`) to a wider one.
    Uext,
    /// Keep the low bits of an integer (narrowing wraps).
    Itrunc,
    /// `f32` to `f64`.
    Fpromote,
    /// `f64` to `f32`, rounding to nearest even.
    Fdemote,
    /// Signed integer to float, rounding to nearest even.
    SiToF,
    /// Unsigned integer to float, rounding to nearest even.
    UiToF,
    /// Float to signed integer: toward zero, saturating at the result type's range,
    /// NaN gives 0.
    FToSi,
    /// Float to unsigned integer: toward zero, saturating, NaN and negatives give 0.
    FToUi,
    /// Reinterpret the bits between an integer and a float of the same width.
    Bitcast,
    /// A pointer as an integer: its address, cut or zero-extended to the integer's
    /// width.
    PtrToInt,
    /// An integer as a pointer: the address it holds (zero-extended or cut to the
    /// target's pointer width). Only CODESYS-style pointer arithmetic makes these;
    /// such a pointer may point anywhere, so a module that has one is unchecked
    /// (see [`crate::Module::unchecked_pointers`]).
    IntToPtr,
}

impl ConvOp {
    /// Every conversion.
    pub const ALL: [ConvOp; 12] = [
        ConvOp::Sext,
        ConvOp::Uext,
        ConvOp::Itrunc,
        ConvOp::Fpromote,
        ConvOp::Fdemote,
        ConvOp::SiToF,
        ConvOp::UiToF,
        ConvOp::FToSi,
        ConvOp::FToUi,
        ConvOp::Bitcast,
        ConvOp::PtrToInt,
        ConvOp::IntToPtr,
    ];

    /// The mnemonic of the text form.
    pub fn name(self) -> &'static str {
        match self {
            ConvOp::Sext => "sext",
            ConvOp::Uext => "uext",
            ConvOp::Itrunc => "itrunc",
            ConvOp::Fpromote => "fpromote",
            ConvOp::Fdemote => "fdemote",
            ConvOp::SiToF => "sitof",
            ConvOp::UiToF => "uitof",
            ConvOp::FToSi => "ftosi",
            ConvOp::FToUi => "ftoui",
            ConvOp::Bitcast => "bitcast",
            ConvOp::PtrToInt => "ptrtoint",
            ConvOp::IntToPtr => "inttoptr",
        }
    }
}

/// Services of the runtime that every target provides.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Intrinsic {
    /// `-> i32`: the PLC clock in milliseconds (TIME), sampled once at the start of the
    /// scan, so it is the same value throughout a scan. Wraps after 2^31 ms.
    ClockMs,
    /// `-> i64`: the PLC clock in nanoseconds (LTIME), sampled with `ClockMs`.
    ClockNs,
    /// Raises the runtime fault flag (array index out of range, …).
    RaiseFault,
    /// `-> i1`: TRUE when the machine running the code wants the current scan to stop
    /// (its watchdog fired: the scan ran too long). Always FALSE on targets without a
    /// watchdog. The `watchdog` pass puts it on loop back edges.
    StopRequested,
    /// `fill ptr, value, n` (`n: i64`): stores `value` (any scalar type `T`) into `n`
    /// consecutive elements of an array of `T` starting at `ptr`, as `n` stores
    /// would; nothing when `n <= 0`. Made by [`crate::passes::fill`] from loops that
    /// do exactly that, for the backends that can do it faster (`memset`).
    Fill,
}

impl Intrinsic {
    /// Every intrinsic.
    pub const ALL: [Intrinsic; 5] = [
        Intrinsic::ClockMs,
        Intrinsic::ClockNs,
        Intrinsic::RaiseFault,
        Intrinsic::StopRequested,
        Intrinsic::Fill,
    ];

    /// The mnemonic of the text form.
    pub fn name(self) -> &'static str {
        match self {
            Intrinsic::ClockMs => "clock_ms",
            Intrinsic::ClockNs => "clock_ns",
            Intrinsic::RaiseFault => "raise_fault",
            Intrinsic::StopRequested => "stop_requested",
            Intrinsic::Fill => "fill",
        }
    }

    /// The result type, if it produces one.
    pub fn result(self) -> Option<Type> {
        match self {
            Intrinsic::ClockMs => Some(Type::I32),
            Intrinsic::ClockNs => Some(Type::I64),
            Intrinsic::RaiseFault => None,
            Intrinsic::StopRequested => Some(Type::I1),
            Intrinsic::Fill => None,
        }
    }

    /// How many operands it takes.
    pub fn operands(self) -> usize {
        match self {
            Intrinsic::Fill => 3,
            _ => 0,
        }
    }
}

/// A branch destination with the arguments for the block's parameters.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BlockCall {
    /// The destination.
    pub block: Block,
    /// One value per parameter of the destination.
    pub args: Vec<Value>,
}

impl BlockCall {
    /// A destination with arguments.
    pub fn new(block: Block, args: Vec<Value>) -> BlockCall {
        BlockCall { block, args }
    }
}

/// One instruction: the operation and its operands. At most one result.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum InstData {
    /// An integer constant of type `ty`; `imm` is canonical (see [`Type::canon_int`]).
    Iconst {
        /// The result type (an integer type).
        ty: Type,
        /// The value, sign-extended from the type's width (`i1`: 0 or 1).
        imm: i64,
    },
    /// `sizeof.ty T`: the bytes a value of memory type `of` takes in the running
    /// target's layout (`SIZEOF` of ST), as an integer of type `ty`. Each target
    /// answers it with its own layout: the interpreter and the JIT with
    /// [`LayoutRules::HOST`](crate::layout::LayoutRules::HOST), the CPDev VM with its
    /// mode's rules, the PIC16 with BOOL fields packed eight to a byte, C with the C
    /// compiler's `sizeof`. Passes treat it as an unknown constant.
    SizeOf {
        /// The result type (an integer type).
        ty: Type,
        /// The memory type measured.
        of: MemType,
    },
    /// A float constant: `bits` is the IEEE encoding (binary32 in the low 32 bits).
    Fconst {
        /// `F32` or `F64`.
        ty: Type,
        /// The raw encoding.
        bits: u64,
    },
    /// `op arg`
    Unary {
        /// The operation.
        op: UnaryOp,
        /// The operand.
        arg: Value,
    },
    /// `op a, b`
    Binary {
        /// The operation.
        op: BinaryOp,
        /// The operands.
        args: [Value; 2],
    },
    /// `icmp cond a, b -> i1`
    Icmp {
        /// The condition.
        cond: IntCC,
        /// The operands (same integer or pointer type).
        args: [Value; 2],
    },
    /// `fcmp cond a, b -> i1`
    Fcmp {
        /// The condition.
        cond: FloatCC,
        /// The operands (same float type).
        args: [Value; 2],
    },
    /// `op.ty arg`
    Convert {
        /// The conversion.
        op: ConvOp,
        /// The result type.
        ty: Type,
        /// The operand.
        arg: Value,
    },
    /// `select c, a, b`: `a` if `c` else `b`.
    Select {
        /// The `i1` condition.
        cond: Value,
        /// The value when true.
        if_true: Value,
        /// The value when false.
        if_false: Value,
    },
    /// The address of a data object.
    GlobalAddr {
        /// The object.
        data: DataId,
    },
    /// The address of a stack slot of this function.
    SlotAddr {
        /// The slot.
        slot: SlotId,
    },
    /// The address of field `field` of the struct `agg` at `base`.
    FieldAddr {
        /// Address of the struct.
        base: Value,
        /// The struct type.
        agg: AggId,
        /// Field index.
        field: u32,
    },
    /// The address of element `index` (zero-based) of the array `agg` at `base`.
    /// The index must be in range: front ends check bounds before.
    ElemAddr {
        /// Address of the array.
        base: Value,
        /// The array type.
        agg: AggId,
        /// The index (any integer type, read as signed).
        index: Value,
    },
    /// `load.ty addr`
    Load {
        /// The loaded type.
        ty: Type,
        /// The address.
        addr: Value,
    },
    /// `store value, addr`
    Store {
        /// The stored value.
        value: Value,
        /// The address.
        addr: Value,
    },
    /// `call @f(args)`
    Call {
        /// The callee.
        func: FuncId,
        /// One value per parameter.
        args: Vec<Value>,
    },
    /// `call_table t, index(args)`: a call bound at run time. Calls entry `index` of
    /// the module's function table `table` with `args`; the result is the table's.
    /// The index (any integer type but `i1`) is read unsigned; an index out of range or
    /// an empty entry calls nothing, raises the fault flag and gives a zero result
    /// (0, +0.0 or the null pointer).
    CallTable {
        /// The table.
        table: TableId,
        /// Which entry (read unsigned).
        index: Value,
        /// One value per parameter of the table.
        args: Vec<Value>,
    },
    /// A runtime service.
    Intrinsic {
        /// Which service.
        op: Intrinsic,
        /// Its operands ([`Intrinsic::operands`]).
        args: Vec<Value>,
    },
    /// `inline_c %agg, data, "code"`: C code copied into the `c` target's output where
    /// it stands (a pragma of an ST body, as matiec copies it), with `data__` naming
    /// `data` as a pointer to struct `agg` (the POU's instance), so matiec's access
    /// macros (`__GET_VAR(data__->X,)`, `__SET_VAR(data__->,X,,v)`) reach its
    /// variables. It may read and write any memory, like a call of unknown code; no
    /// other target runs it (their backends refuse it).
    InlineC {
        /// The C text, as the pragma held it (matiec's braces dropped).
        code: Box<str>,
        /// The struct `data` points to.
        agg: AggId,
        /// The instance's address.
        data: Value,
    },
    /// `jump block(args)`
    Jump {
        /// The destination.
        dest: BlockCall,
    },
    /// `brif c, then(args), else(args)`
    Brif {
        /// The `i1` condition.
        cond: Value,
        /// Taken when true (boxed, like `else_dest`, so that an instruction is 40
        /// bytes, not 72: most instructions are not branches).
        then_dest: Box<BlockCall>,
        /// Taken when false.
        else_dest: Box<BlockCall>,
    },
    /// `br_table arg, default(args), [b0(args), b1(args), …]`: a jump through a
    /// table. `arg` (an integer, `i8` to `i64`) is read unsigned: below the table's
    /// length control goes to `table[arg]`, else to `default`. Every destination
    /// carries its block's arguments, as `jump`'s does.
    BrTable {
        /// The index (read unsigned).
        arg: Value,
        /// Taken when `arg` is not below the table's length.
        default: Box<BlockCall>,
        /// The destinations by index.
        table: Vec<BlockCall>,
    },
    /// `return` or `return v`
    Return {
        /// The result, if the function has one.
        value: Option<Value>,
    },
}

impl InstData {
    /// True for instructions that end a block.
    pub fn is_terminator(&self) -> bool {
        matches!(
            self,
            InstData::Jump { .. }
                | InstData::Brif { .. }
                | InstData::BrTable { .. }
                | InstData::Return { .. }
        )
    }

    /// True if the instruction has an effect besides its result (so it may not be
    /// removed even when the result is unused).
    pub fn has_side_effects(&self) -> bool {
        match self {
            InstData::Store { .. }
            | InstData::Call { .. }
            | InstData::CallTable { .. }
            | InstData::Intrinsic { .. }
            | InstData::InlineC { .. }
            | InstData::Jump { .. }
            | InstData::Brif { .. }
            | InstData::BrTable { .. }
            | InstData::Return { .. } => true,
            InstData::Binary { op, .. } => op.can_fault(),
            _ => false,
        }
    }

    /// Calls `f` on every value operand, branch arguments included.
    pub fn for_each_arg(&self, mut f: impl FnMut(Value)) {
        match self {
            InstData::Iconst { .. }
            | InstData::SizeOf { .. }
            | InstData::Fconst { .. }
            | InstData::GlobalAddr { .. }
            | InstData::SlotAddr { .. } => {}
            InstData::Unary { arg, .. } | InstData::Convert { arg, .. } => f(*arg),
            InstData::Binary { args, .. }
            | InstData::Icmp { args, .. }
            | InstData::Fcmp { args, .. } => {
                f(args[0]);
                f(args[1]);
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                f(*cond);
                f(*if_true);
                f(*if_false);
            }
            InstData::FieldAddr { base, .. } => f(*base),
            InstData::ElemAddr { base, index, .. } => {
                f(*base);
                f(*index);
            }
            InstData::Load { addr, .. } | InstData::InlineC { data: addr, .. } => f(*addr),
            InstData::Store { value, addr } => {
                f(*value);
                f(*addr);
            }
            InstData::Call { args, .. } | InstData::Intrinsic { args, .. } => {
                args.iter().copied().for_each(f)
            }
            InstData::CallTable { index, args, .. } => {
                f(*index);
                args.iter().copied().for_each(f)
            }
            InstData::Jump { dest } => dest.args.iter().copied().for_each(f),
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                f(*cond);
                then_dest.args.iter().copied().for_each(&mut f);
                else_dest.args.iter().copied().for_each(f);
            }
            InstData::BrTable {
                arg,
                default,
                table,
            } => {
                f(*arg);
                for d in std::iter::once(&**default).chain(table) {
                    d.args.iter().copied().for_each(&mut f);
                }
            }
            InstData::Return { value } => {
                if let Some(v) = value {
                    f(*v)
                }
            }
        }
    }

    /// Calls `f` on every value operand for rewriting, branch arguments included.
    pub fn map_args(&mut self, mut f: impl FnMut(Value) -> Value) {
        match self {
            InstData::Iconst { .. }
            | InstData::SizeOf { .. }
            | InstData::Fconst { .. }
            | InstData::GlobalAddr { .. }
            | InstData::SlotAddr { .. } => {}
            InstData::Unary { arg, .. } | InstData::Convert { arg, .. } => *arg = f(*arg),
            InstData::Binary { args, .. }
            | InstData::Icmp { args, .. }
            | InstData::Fcmp { args, .. } => {
                args[0] = f(args[0]);
                args[1] = f(args[1]);
            }
            InstData::Select {
                cond,
                if_true,
                if_false,
            } => {
                *cond = f(*cond);
                *if_true = f(*if_true);
                *if_false = f(*if_false);
            }
            InstData::FieldAddr { base, .. } => *base = f(*base),
            InstData::ElemAddr { base, index, .. } => {
                *base = f(*base);
                *index = f(*index);
            }
            InstData::Load { addr, .. } | InstData::InlineC { data: addr, .. } => *addr = f(*addr),
            InstData::Store { value, addr } => {
                *value = f(*value);
                *addr = f(*addr);
            }
            InstData::Call { args, .. } | InstData::Intrinsic { args, .. } => {
                args.iter_mut().for_each(|a| *a = f(*a))
            }
            InstData::CallTable { index, args, .. } => {
                *index = f(*index);
                args.iter_mut().for_each(|a| *a = f(*a))
            }
            InstData::Jump { dest } => dest.args.iter_mut().for_each(|a| *a = f(*a)),
            InstData::Brif {
                cond,
                then_dest,
                else_dest,
            } => {
                *cond = f(*cond);
                then_dest.args.iter_mut().for_each(|a| *a = f(*a));
                else_dest.args.iter_mut().for_each(|a| *a = f(*a));
            }
            InstData::BrTable {
                arg,
                default,
                table,
            } => {
                *arg = f(*arg);
                for d in std::iter::once(&mut **default).chain(table) {
                    d.args.iter_mut().for_each(|a| *a = f(*a));
                }
            }
            InstData::Return { value } => {
                if let Some(v) = value {
                    *v = f(*v)
                }
            }
        }
    }

    /// The number of branch destinations of a terminator: 1 for `jump`, 2 for `brif`,
    /// one more than the table's length for `br_table`, 0 for anything else.
    pub fn dest_count(&self) -> usize {
        match self {
            InstData::Jump { .. } => 1,
            InstData::Brif { .. } => 2,
            InstData::BrTable { table, .. } => 1 + table.len(),
            _ => 0,
        }
    }

    /// Branch destination `k` of a terminator: `jump`'s only one (0); `brif`'s then
    /// (0) and else (1); `br_table`'s default (0), then its table's entries (entry `j`
    /// is `k = j + 1`). `None` past the last one.
    pub fn dest(&self, k: usize) -> Option<&BlockCall> {
        match (self, k) {
            (InstData::Jump { dest }, 0) => Some(dest),
            (InstData::Brif { then_dest, .. }, 0) => Some(then_dest),
            (InstData::Brif { else_dest, .. }, 1) => Some(else_dest),
            (InstData::BrTable { default, .. }, 0) => Some(default),
            (InstData::BrTable { table, .. }, k) => table.get(k - 1),
            _ => None,
        }
    }

    /// Branch destination `k` of a terminator (numbered as by [`InstData::dest`]),
    /// for rewriting.
    pub fn dest_mut(&mut self, k: usize) -> Option<&mut BlockCall> {
        match (self, k) {
            (InstData::Jump { dest }, 0) => Some(dest),
            (InstData::Brif { then_dest, .. }, 0) => Some(then_dest),
            (InstData::Brif { else_dest, .. }, 1) => Some(else_dest),
            (InstData::BrTable { default, .. }, 0) => Some(default),
            (InstData::BrTable { table, .. }, k) => table.get_mut(k - 1),
            _ => None,
        }
    }

    /// The branch destinations of a terminator in the order of [`InstData::dest`]
    /// (none for other instructions), without allocating. A block reached by several
    /// destinations appears once per destination (one per CFG edge).
    pub fn dests(&self) -> impl Iterator<Item = &BlockCall> {
        (0..self.dest_count()).filter_map(move |k| self.dest(k))
    }

    /// The branch destinations of a terminator (empty for other instructions).
    pub fn successors(&self) -> Vec<&BlockCall> {
        self.dests().collect()
    }

    /// The branch destinations of a terminator, for rewriting (in the order of
    /// [`InstData::dest`]).
    pub fn successors_mut(&mut self) -> Vec<&mut BlockCall> {
        match self {
            InstData::Jump { dest } => vec![dest],
            InstData::Brif {
                then_dest,
                else_dest,
                ..
            } => vec![&mut **then_dest, &mut **else_dest],
            InstData::BrTable { default, table, .. } => std::iter::once(&mut **default)
                .chain(table.iter_mut())
                .collect(),
            _ => Vec::new(),
        }
    }
}

/// An instruction's size: a function keeps one per instruction ever created, and the
/// IR of a large program is most of the compiler's memory (BENCHMARKS.md, memory).
/// The branch destinations are boxed to keep it at 40 bytes.
#[cfg(all(test, target_pointer_width = "64"))]
#[test]
fn inst_size() {
    assert_eq!(std::mem::size_of::<InstData>(), 40);
}
