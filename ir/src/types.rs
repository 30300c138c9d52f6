//! Types of SSA values and of memory.
//!
//! SSA values have one of a few machine-level types with explicit widths; signedness is
//! in the operation (`sdiv`/`udiv`), never in the type. Memory holds scalars of those
//! types and aggregates (structs and arrays) described symbolically: byte offsets are
//! a backend's choice (see [`crate::layout`]), because targets lay memory out
//! differently (the PIC16 packs BOOLs into bits).

use crate::entities::AggId;
use std::fmt;

/// The type of an SSA value.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Type {
    /// A truth value (BOOL).
    I1,
    /// 8-bit integer.
    I8,
    /// 16-bit integer.
    I16,
    /// 32-bit integer.
    I32,
    /// 64-bit integer.
    I64,
    /// IEEE 754 binary32.
    F32,
    /// IEEE 754 binary64.
    F64,
    /// An address in data memory; its width is the target's.
    Ptr,
}

impl Type {
    /// Width in bits (`Ptr` reports 64; ask the target for its real width).
    pub fn bits(self) -> u32 {
        match self {
            Type::I1 => 1,
            Type::I8 => 8,
            Type::I16 => 16,
            Type::I32 | Type::F32 => 32,
            Type::I64 | Type::F64 | Type::Ptr => 64,
        }
    }

    /// Integer types, `I1` included.
    pub fn is_int(self) -> bool {
        matches!(
            self,
            Type::I1 | Type::I8 | Type::I16 | Type::I32 | Type::I64
        )
    }

    /// Floating-point types.
    pub fn is_float(self) -> bool {
        matches!(self, Type::F32 | Type::F64)
    }

    /// The integer type of the given width, if there is one.
    pub fn int_of_bits(bits: u32) -> Option<Type> {
        Some(match bits {
            1 => Type::I1,
            8 => Type::I8,
            16 => Type::I16,
            32 => Type::I32,
            64 => Type::I64,
            _ => return None,
        })
    }

    /// The name used in the text form (`i32`, `f64`, `ptr`).
    pub fn name(self) -> &'static str {
        match self {
            Type::I1 => "i1",
            Type::I8 => "i8",
            Type::I16 => "i16",
            Type::I32 => "i32",
            Type::I64 => "i64",
            Type::F32 => "f32",
            Type::F64 => "f64",
            Type::Ptr => "ptr",
        }
    }

    /// Parses a name of the text form.
    pub fn from_name(s: &str) -> Option<Type> {
        Some(match s {
            "i1" => Type::I1,
            "i8" => Type::I8,
            "i16" => Type::I16,
            "i32" => Type::I32,
            "i64" => Type::I64,
            "f32" => Type::F32,
            "f64" => Type::F64,
            "ptr" => Type::Ptr,
            _ => return None,
        })
    }

    /// Truncates `bits` to this integer type's width and sign-extends it back to 64
    /// bits: the canonical form of integer constants (`I1` is 0 or 1, not sign-extended).
    pub fn canon_int(self, bits: i64) -> i64 {
        match self {
            Type::I1 => bits & 1,
            Type::I8 => bits as i8 as i64,
            Type::I16 => bits as i16 as i64,
            Type::I32 => bits as i32 as i64,
            _ => bits,
        }
    }

    /// The value masked to this type's width, zero-extended (the unsigned reading).
    pub fn zext_bits(self, bits: i64) -> u64 {
        match self {
            Type::I1 => bits as u64 & 1,
            Type::I8 => bits as u8 as u64,
            Type::I16 => bits as u16 as u64,
            Type::I32 | Type::F32 => bits as u32 as u64,
            _ => bits as u64,
        }
    }
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The type of a memory location: a scalar or an aggregate of the module.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum MemType {
    /// One value of an SSA type.
    Scalar(Type),
    /// A struct or array declared in the module.
    Agg(AggId),
}

/// The source-level (IEC 61131-3) type of a scalar in memory.
///
/// The IR computes with [`Type`]s; this is kept beside every scalar field so that the
/// runner can show and parse values as the user wrote them (`T#5s`, `16#FF`, `TRUE`)
/// and so that backends can name types in diagnostics.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ElemType {
    /// BOOL
    Bool,
    /// SINT
    SInt,
    /// INT
    Int,
    /// DINT
    DInt,
    /// LINT
    LInt,
    /// USINT
    USInt,
    /// UINT
    UInt,
    /// UDINT
    UDInt,
    /// ULINT
    ULInt,
    /// BYTE
    Byte,
    /// WORD
    Word,
    /// DWORD
    DWord,
    /// LWORD
    LWord,
    /// REAL
    Real,
    /// LREAL
    LReal,
    /// TIME: signed 32-bit milliseconds.
    Time,
    /// LTIME: signed 64-bit nanoseconds.
    LTime,
    /// DATE: seconds since 1970-01-01, 32-bit.
    Date,
    /// TIME_OF_DAY: milliseconds since midnight, 32-bit.
    Tod,
    /// DATE_AND_TIME: seconds since 1970-01-01T00:00:00, 32-bit.
    Dt,
    /// LDATE: nanoseconds since 1970-01-01 (a whole number of days), 64-bit.
    LDate,
    /// LTIME_OF_DAY: nanoseconds since midnight, 64-bit.
    LTod,
    /// LDATE_AND_TIME: nanoseconds since 1970-01-01T00:00:00, 64-bit.
    LDt,
    /// CHAR: one byte.
    Char,
    /// WCHAR: one UTF-16 unit.
    WChar,
    /// A reference or pointer (shown as an address).
    Ref,
}

impl ElemType {
    /// Every elementary type, in the order of the IEC tables.
    pub const ALL: [ElemType; 26] = [
        ElemType::Bool,
        ElemType::SInt,
        ElemType::Int,
        ElemType::DInt,
        ElemType::LInt,
        ElemType::USInt,
        ElemType::UInt,
        ElemType::UDInt,
        ElemType::ULInt,
        ElemType::Byte,
        ElemType::Word,
        ElemType::DWord,
        ElemType::LWord,
        ElemType::Real,
        ElemType::LReal,
        ElemType::Time,
        ElemType::LTime,
        ElemType::Date,
        ElemType::Tod,
        ElemType::Dt,
        ElemType::LDate,
        ElemType::LTod,
        ElemType::LDt,
        ElemType::Char,
        ElemType::WChar,
        ElemType::Ref,
    ];

    /// The IR type that holds a value of this type.
    pub fn ir_type(self) -> Type {
        use ElemType::*;
        match self {
            Bool => Type::I1,
            SInt | USInt | Byte | Char => Type::I8,
            Int | UInt | Word | WChar => Type::I16,
            DInt | UDInt | DWord | Time | Date | Tod | Dt => Type::I32,
            LInt | ULInt | LWord | LTime | LDate | LTod | LDt => Type::I64,
            Real => Type::F32,
            LReal => Type::F64,
            Ref => Type::Ptr,
        }
    }

    /// The IEC name (`DINT`, `TIME`, `TIME_OF_DAY`).
    pub fn name(self) -> &'static str {
        use ElemType::*;
        match self {
            Bool => "BOOL",
            SInt => "SINT",
            Int => "INT",
            DInt => "DINT",
            LInt => "LINT",
            USInt => "USINT",
            UInt => "UINT",
            UDInt => "UDINT",
            ULInt => "ULINT",
            Byte => "BYTE",
            Word => "WORD",
            DWord => "DWORD",
            LWord => "LWORD",
            Real => "REAL",
            LReal => "LREAL",
            Time => "TIME",
            LTime => "LTIME",
            Date => "DATE",
            Tod => "TIME_OF_DAY",
            Dt => "DATE_AND_TIME",
            LDate => "LDATE",
            LTod => "LTIME_OF_DAY",
            LDt => "LDATE_AND_TIME",
            Char => "CHAR",
            WChar => "WCHAR",
            Ref => "REF",
        }
    }

    /// Looks an elementary type up by its IEC name or short form (case-insensitive).
    pub fn from_name(s: &str) -> Option<ElemType> {
        use ElemType::*;
        let u = s.to_ascii_uppercase();
        Some(match u.as_str() {
            "BOOL" => Bool,
            "SINT" => SInt,
            "INT" => Int,
            "DINT" => DInt,
            "LINT" => LInt,
            "USINT" => USInt,
            "UINT" => UInt,
            "UDINT" => UDInt,
            "ULINT" => ULInt,
            "BYTE" => Byte,
            "WORD" => Word,
            "DWORD" => DWord,
            "LWORD" => LWord,
            "REAL" => Real,
            "LREAL" => LReal,
            "TIME" => Time,
            "LTIME" => LTime,
            "DATE" => Date,
            "TIME_OF_DAY" | "TOD" => Tod,
            "DATE_AND_TIME" | "DT" => Dt,
            "LDATE" => LDate,
            "LTIME_OF_DAY" | "LTOD" => LTod,
            "LDATE_AND_TIME" | "LDT" => LDt,
            "CHAR" => Char,
            "WCHAR" => WChar,
            "REF" => Ref,
            _ => return None,
        })
    }

    /// Signed integer types (and TIME/LTIME, which are signed durations).
    pub fn is_signed(self) -> bool {
        use ElemType::*;
        matches!(self, SInt | Int | DInt | LInt | Time | LTime)
    }

    /// Integer types (signed and unsigned), not bit strings.
    pub fn is_integer(self) -> bool {
        use ElemType::*;
        matches!(
            self,
            SInt | Int | DInt | LInt | USInt | UInt | UDInt | ULInt
        )
    }

    /// Bit strings: BOOL, BYTE, WORD, DWORD, LWORD.
    pub fn is_bit_string(self) -> bool {
        use ElemType::*;
        matches!(self, Bool | Byte | Word | DWord | LWord)
    }

    /// REAL and LREAL.
    pub fn is_real(self) -> bool {
        matches!(self, ElemType::Real | ElemType::LReal)
    }

    /// TIME and LTIME.
    pub fn is_duration(self) -> bool {
        matches!(self, ElemType::Time | ElemType::LTime)
    }
}

impl fmt::Display for ElemType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
