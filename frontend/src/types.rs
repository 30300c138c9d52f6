//! Source-level types and the IEC 61131-3 rules between them: which conversions are
//! implicit, how two operand types combine.

use plcc_ir::{ElemType, Type};

/// Identifies a POU (an FB type, when used as a type).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PouId(pub u32);

/// Identifies an array type in the [`TypeTable`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct ArrayId(pub u32);

/// Identifies a STRUCT type (named by a TYPE declaration, or written in place).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct StructId(pub u32);

/// Identifies a reference type in the [`TypeTable`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct RefId(pub u32);

/// A reference type: what it points to.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct RefTy {
    /// The referenced type.
    pub target: Ty,
    /// The derived type of the target, whose initial value and range it has.
    pub tag: Option<TagId>,
    /// `POINTER TO` (CODESYS) rather than `REF_TO`.
    pub pointer: bool,
    /// `REFERENCE TO` (CODESYS): used by name, it is the variable it points to.
    pub auto: bool,
    /// A variable of an INTERFACE type: the address of an instance of a class that
    /// implements the interface (index into the lowerer's interfaces); `target` is
    /// `Void` then.
    pub iface: Option<usize>,
}

/// Identifies an enumeration type.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct EnumId(pub u32);

/// Identifies what a derived type adds to the type it is based on: its name, its
/// initial value, a subrange's bounds. Values keep the base type ([`Ty`]), so they mix
/// freely with it; declarations carry the tag, so variables get the derived type's
/// initial value and constants assigned to them are checked against its range.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct TagId(pub u32);

/// The type of an expression or variable.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    /// An elementary type.
    Elem(ElemType),
    /// An instance of a FUNCTION_BLOCK.
    Fb(PouId),
    /// An array.
    Array(ArrayId),
    /// A STRUCT (types are equal by declaration, not by shape).
    Struct(StructId),
    /// An enumeration, held as an integer of the base type (INT unless typed).
    Enum(EnumId, ElemType),
    /// `STRING[n]` or `WSTRING[n]`: a string value is the address of its characters.
    Str(StrTy),
    /// `REF_TO t` or `POINTER TO t`: an address (or NULL).
    Ref(RefId),
    /// `NULL`, before its context gives it a reference type.
    Null,
    /// An integer literal not yet given a type by its context.
    AnyInt,
    /// A real literal not yet given a type by its context.
    AnyReal,
    /// No value (a FUNCTION without a result).
    Void,
    /// The type of something that already had an error: accepted everywhere, so one
    /// mistake gives one diagnostic.
    Error,
}

impl Ty {
    /// BOOL
    pub const BOOL: Ty = Ty::Elem(ElemType::Bool);
    /// DINT
    pub const DINT: Ty = Ty::Elem(ElemType::DInt);
    /// TIME
    pub const TIME: Ty = Ty::Elem(ElemType::Time);

    /// The elementary type, if it is one.
    pub fn elem(self) -> Option<ElemType> {
        match self {
            Ty::Elem(e) => Some(e),
            _ => None,
        }
    }

    /// The IR type of a value of this type (`None` for aggregates and void).
    pub fn ir(self) -> Option<Type> {
        match self {
            Ty::Elem(e) | Ty::Enum(_, e) => Some(e.ir_type()),
            Ty::Ref(_) | Ty::Null => Some(Type::Ptr),
            Ty::AnyInt => Some(Type::I64),
            Ty::AnyReal => Some(Type::F64),
            _ => None,
        }
    }

    /// Integers (signed or unsigned) and integer literals.
    pub fn is_integer(self) -> bool {
        matches!(self, Ty::AnyInt) || self.elem().is_some_and(|e| e.is_integer())
    }

    /// Integers, bit strings (not BOOL) and integer literals: what MOD, shifts and
    /// bitwise operators accept besides BOOL.
    pub fn is_int_like(self) -> bool {
        self.is_integer()
            || self
                .elem()
                .is_some_and(|e| e.is_bit_string() && e != ElemType::Bool)
    }

    /// REAL, LREAL and real literals.
    pub fn is_real(self) -> bool {
        matches!(self, Ty::AnyReal) || self.elem().is_some_and(|e| e.is_real())
    }

    /// Anything arithmetic operators accept: integers, bit strings, reals.
    pub fn is_numeric(self) -> bool {
        self.is_int_like() || self.is_real()
    }

    /// True if arithmetic on it is signed (signed integers, TIME, literals).
    pub fn is_signed(self) -> bool {
        matches!(self, Ty::AnyInt) || self.elem().is_some_and(|e| e.is_signed())
    }

    /// True for literals that have not got their type yet.
    pub fn is_literal(self) -> bool {
        matches!(self, Ty::AnyInt | Ty::AnyReal)
    }

    /// STRUCTs, arrays and strings: values that live in memory and are copied
    /// (passed by address to FUNCTIONs).
    pub fn is_aggregate(self) -> bool {
        matches!(self, Ty::Struct(_) | Ty::Array(_) | Ty::Str(_))
    }

    /// The string type, if it is one.
    pub fn string(self) -> Option<StrTy> {
        match self {
            Ty::Str(s) => Some(s),
            _ => None,
        }
    }
}

/// A string type: `STRING[cap]` (bytes) or `WSTRING[cap]` (16-bit characters). In
/// memory a string is `cap + 1` characters, the text ended by a 0.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct StrTy {
    /// WSTRING
    pub wide: bool,
    /// The most characters it holds.
    pub cap: u32,
}

impl StrTy {
    /// The capacity of a STRING or WSTRING declared without one.
    pub const DEFAULT_CAP: u32 = 80;
    /// The largest capacity plcc accepts (the helpers index with INT).
    pub const MAX_CAP: u32 = 32766;

    /// `STRING[cap]` or `WSTRING[cap]`.
    pub fn name(self) -> String {
        format!(
            "{}[{}]",
            if self.wide { "WSTRING" } else { "STRING" },
            self.cap
        )
    }
}

/// An array type: element type and bounds per dimension.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ArrayTy {
    /// Element type.
    pub elem: Ty,
    /// Inclusive `(lower, upper)` bounds of each dimension.
    pub dims: Vec<(i64, i64)>,
    /// The derived type of the elements (`ARRAY[..] OF Celsius`), whose initial value
    /// they get.
    pub elem_tag: Option<TagId>,
}

impl ArrayTy {
    /// Number of elements of dimension `d` (`u64::MAX` when it does not fit).
    pub fn len(&self, d: usize) -> u64 {
        let (lo, hi) = self.dims[d];
        let n = (i128::from(hi) - i128::from(lo) + 1).max(0);
        u64::try_from(n).unwrap_or(u64::MAX)
    }

    /// Total number of elements, saturating at `u64::MAX`: declared bounds are
    /// arbitrary constants, and an oversized array must reach the size check.
    pub fn total(&self) -> u64 {
        (0..self.dims.len())
            .map(|d| self.len(d))
            .fold(1u64, u64::saturating_mul)
    }
}

/// The array types of a build, deduplicated.
#[derive(Clone, Debug, Default)]
pub struct TypeTable {
    arrays: Vec<ArrayTy>,
    refs: Vec<RefTy>,
}

impl TypeTable {
    /// The id of an array type, adding it if new.
    pub fn array(&mut self, a: ArrayTy) -> ArrayId {
        if let Some(i) = self.arrays.iter().position(|x| *x == a) {
            return ArrayId(i as u32);
        }
        self.arrays.push(a);
        ArrayId(self.arrays.len() as u32 - 1)
    }

    /// How many array and reference types there are.
    pub fn counts(&self) -> (usize, usize) {
        (self.arrays.len(), self.refs.len())
    }

    /// An array type.
    pub fn get(&self, id: ArrayId) -> &ArrayTy {
        &self.arrays[id.0 as usize]
    }

    /// The id of a reference type, adding it if new.
    pub fn reference(&mut self, r: RefTy) -> RefId {
        if let Some(i) = self.refs.iter().position(|x| *x == r) {
            return RefId(i as u32);
        }
        self.refs.push(r);
        RefId(self.refs.len() as u32 - 1)
    }

    /// A reference type.
    pub fn get_ref(&self, id: RefId) -> RefTy {
        self.refs[id.0 as usize]
    }
}

/// Rank of an integer type in its family, used for implicit widening.
fn int_rank(e: ElemType) -> Option<(bool, u32)> {
    use ElemType::*;
    Some(match e {
        SInt => (true, 8),
        Int => (true, 16),
        DInt => (true, 32),
        LInt => (true, 64),
        USInt => (false, 8),
        UInt => (false, 16),
        UDInt => (false, 32),
        ULInt => (false, 64),
        _ => return None,
    })
}

fn bits_rank(e: ElemType) -> Option<u32> {
    use ElemType::*;
    Some(match e {
        Bool => 1,
        Byte => 8,
        Word => 16,
        DWord => 32,
        LWord => 64,
        _ => return None,
    })
}

/// True if a value of `from` converts to `to` without an explicit conversion, as IEC
/// 61131-3 (3rd edition) allows: widening within signed integers, within unsigned
/// integers, unsigned to a wider signed one, within bit strings, integers to a real
/// that holds them exactly, REAL to LREAL, TIME to LTIME, DATE to LDATE, TOD to LTOD,
/// DT to LDT.
pub fn implicit(from: ElemType, to: ElemType) -> bool {
    use ElemType::*;
    if from == to {
        return true;
    }
    if let (Some((sf, bf)), Some((st, bt))) = (int_rank(from), int_rank(to)) {
        return if sf == st {
            bf < bt
        } else {
            !sf && st && bf < bt
        };
    }
    if let (Some(bf), Some(bt)) = (bits_rank(from), bits_rank(to)) {
        return bf < bt && from != Bool;
    }
    match (from, to) {
        (Real, LReal) | (Time, LTime) | (Date, LDate) | (Tod, LTod) | (Dt, LDt) => true,
        (f, Real) => matches!(f, SInt | Int | USInt | UInt),
        (f, LReal) => matches!(f, SInt | Int | DInt | USInt | UInt | UDInt),
        _ => false,
    }
}

/// The range of values of an integer-valued type, for checking literals.
pub fn int_range(e: ElemType) -> Option<(i128, i128)> {
    use ElemType::*;
    Some(match e {
        SInt => (i8::MIN as i128, i8::MAX as i128),
        Int => (i16::MIN as i128, i16::MAX as i128),
        DInt | Time => (i32::MIN as i128, i32::MAX as i128),
        LInt | LTime | LDate | LTod | LDt => (i64::MIN as i128, i64::MAX as i128),
        USInt | Byte | Char => (0, u8::MAX as i128),
        UInt | Word | WChar => (0, u16::MAX as i128),
        UDInt | DWord | Date | Tod | Dt => (0, u32::MAX as i128),
        ULInt | LWord => (0, u64::MAX as i128),
        Bool => (0, 1),
        _ => return None,
    })
}

/// The type an untyped literal gets when nothing else says: DINT if it fits, else LINT
/// (ULINT beyond); LREAL for reals.
pub fn default_literal_type(ty: Ty, value: Option<i128>) -> Ty {
    match ty {
        Ty::AnyInt => match value {
            Some(v) if v < i32::MIN as i128 || v > i32::MAX as i128 => {
                if v > i64::MAX as i128 {
                    Ty::Elem(ElemType::ULInt)
                } else {
                    Ty::Elem(ElemType::LInt)
                }
            }
            _ => Ty::DINT,
        },
        Ty::AnyReal => Ty::Elem(ElemType::LReal),
        t => t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ElemType::*;

    #[test]
    fn widening_rules() {
        assert!(implicit(Int, DInt));
        assert!(implicit(USInt, Int));
        assert!(!implicit(UInt, Int));
        assert!(!implicit(DInt, Int));
        assert!(implicit(Byte, Word));
        assert!(!implicit(Bool, Byte));
        assert!(implicit(Int, Real));
        assert!(!implicit(DInt, Real));
        assert!(implicit(DInt, LReal));
        assert!(implicit(Real, LReal));
        assert!(!implicit(LReal, Real));
        assert!(!implicit(Int, Word));
    }
}
