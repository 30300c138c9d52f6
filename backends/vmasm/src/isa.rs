//! The CPDev virtual machine's instruction set: opcodes, operand shapes, type codes,
//! and the byte encoding in each addressing mode.
//!
//! An opcode is written as in the CPDev listings and `vmdef.h`, `0xGGFF`: group byte
//! `GG`, then function byte `FF`, stored in that order (`1C15` is the bytes `1C 15`).
//! Operands follow: data and code addresses (2 bytes, or 4 in the 32-bit modes), then
//! immediates. In the aligned mode the opcode is padded to 4 bytes and the `*4A` forms
//! carry 4-byte counts. Everything is little-endian. See `reference/cpdev-vm.md`.

use std::fmt;

/// An addressing mode of the VM (the CPDev toolchain's `mach16b`, `mach32b`, `mach32bA`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Default)]
pub enum Mode {
    /// 16-bit data and code addresses.
    #[default]
    M16,
    /// 32-bit addresses.
    M32,
    /// 32-bit addresses; opcodes padded to 4 bytes, `*4A` forms with 4-byte counts.
    M32A,
}

impl Mode {
    /// Every mode.
    pub const ALL: [Mode; 3] = [Mode::M16, Mode::M32, Mode::M32A];

    /// Bytes of a data or code address.
    pub fn addr_bytes(self) -> usize {
        match self {
            Mode::M16 => 2,
            Mode::M32 | Mode::M32A => 4,
        }
    }

    /// Bytes an opcode takes (with its padding).
    pub fn opcode_bytes(self) -> usize {
        match self {
            Mode::M16 | Mode::M32 => 2,
            Mode::M32A => 4,
        }
    }

    /// The largest data or code address.
    pub fn max_addr(self) -> u64 {
        match self {
            Mode::M16 => 0xFFFF,
            Mode::M32 | Mode::M32A => 0xFFFF_FFFF,
        }
    }

    /// The MCD form plcc writes in this mode: MCD4A in the aligned mode (every
    /// instruction a multiple of 4 bytes long), else MCD.
    pub fn mcd(self) -> Opcode {
        if self == Mode::M32A {
            op::MCD4A
        } else {
            op::MCD
        }
    }

    /// The name used on the command line (`-s mode=…`) and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Mode::M16 => "16",
            Mode::M32 => "32",
            Mode::M32A => "32a",
        }
    }

    /// Parses a mode name (`16`, `32`, `32a`, or the toolchain's `mach16b`, …).
    pub fn parse(s: &str) -> Option<Mode> {
        match s.to_ascii_lowercase().as_str() {
            "16" | "mach16b" | "16bit" => Some(Mode::M16),
            "32" | "mach32b" | "32bit" => Some(Mode::M32),
            "32a" | "mach32ba" | "32bitalign" => Some(Mode::M32A),
            _ => None,
        }
    }
}

/// The type codes of the typed groups (low nibble of the function byte).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Ty {
    /// BOOL, one byte holding 0 or 1.
    Bool = 0,
    /// SINT.
    Sint = 1,
    /// INT.
    Int = 2,
    /// DINT.
    Dint = 3,
    /// LINT.
    Lint = 4,
    /// BYTE (and USINT).
    Byte = 5,
    /// WORD (and UINT).
    Word = 6,
    /// DWORD (and UDINT).
    Dword = 7,
    /// LWORD (and ULINT).
    Lword = 8,
    /// REAL.
    Real = 9,
    /// LREAL.
    Lreal = 0xA,
    /// TIME (unsigned milliseconds).
    Time = 0xB,
    /// DATE.
    Date = 0xC,
    /// TIME_OF_DAY.
    Tod = 0xD,
    /// DATE_AND_TIME.
    Dt = 0xE,
    /// STRING.
    String = 0xF,
}

impl Ty {
    /// The type of a code.
    pub fn from_code(c: u8) -> Option<Ty> {
        use Ty::*;
        Some(match c {
            0 => Bool,
            1 => Sint,
            2 => Int,
            3 => Dint,
            4 => Lint,
            5 => Byte,
            6 => Word,
            7 => Dword,
            8 => Lword,
            9 => Real,
            0xA => Lreal,
            0xB => Time,
            0xC => Date,
            0xD => Tod,
            0xE => Dt,
            0xF => String,
            _ => return None,
        })
    }

    /// Size in bytes of a value (STRING: 0, it has no fixed size).
    pub fn size(self) -> usize {
        use Ty::*;
        match self {
            Bool | Sint | Byte => 1,
            Int | Word => 2,
            Dint | Dword | Real | Time | Date | Tod => 4,
            Lint | Lword | Lreal | Dt => 8,
            String => 0,
        }
    }

    /// The IEC name.
    pub fn name(self) -> &'static str {
        use Ty::*;
        match self {
            Bool => "BOOL",
            Sint => "SINT",
            Int => "INT",
            Dint => "DINT",
            Lint => "LINT",
            Byte => "BYTE",
            Word => "WORD",
            Dword => "DWORD",
            Lword => "LWORD",
            Real => "REAL",
            Lreal => "LREAL",
            Time => "TIME",
            Date => "DATE",
            Tod => "TIME_OF_DAY",
            Dt => "DATE_AND_TIME",
            String => "STRING",
        }
    }

    /// The type named by an IEC type name (aliases included: USINT is BYTE, …).
    pub fn from_name(s: &str) -> Option<Ty> {
        use Ty::*;
        Some(match s.to_ascii_uppercase().as_str() {
            "BOOL" => Bool,
            "SINT" => Sint,
            "INT" => Int,
            "DINT" => Dint,
            "LINT" => Lint,
            "BYTE" | "USINT" => Byte,
            "WORD" | "UINT" => Word,
            "DWORD" | "UDINT" => Dword,
            "LWORD" | "ULINT" => Lword,
            "REAL" => Real,
            "LREAL" => Lreal,
            "TIME" => Time,
            "DATE" => Date,
            "TIME_OF_DAY" | "TOD" => Tod,
            "DATE_AND_TIME" | "DT" => Dt,
            "STRING" | "WSTRING" => String,
            _ => return None,
        })
    }

    /// True for the signed integer types.
    pub fn is_signed_int(self) -> bool {
        matches!(self, Ty::Sint | Ty::Int | Ty::Dint | Ty::Lint)
    }

    /// True for REAL and LREAL.
    pub fn is_float(self) -> bool {
        matches!(self, Ty::Real | Ty::Lreal)
    }
}

/// What one operand of an instruction is.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A data address (relative to DPTR unless the instruction says otherwise).
    Data,
    /// A code address.
    Code,
    /// A 1-byte immediate.
    Byte,
    /// A 2-byte immediate.
    Word,
    /// A 4-byte immediate.
    Dword,
    /// MCD's payload: a count byte, then that many bytes.
    Bytes,
    /// MCD4A's payload: a 4-byte count, then the bytes padded to a multiple of 4.
    Bytes4A,
}

/// An operand value.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Operand {
    /// A data address.
    Data(u32),
    /// A code address.
    Code(u32),
    /// An immediate of a fixed width (`Byte`, `Word`, `Dword`), stored little-endian.
    Imm(u32),
    /// The bytes of MCD / MCD4A (without the count and the padding).
    Bytes(Vec<u8>),
}

/// An opcode, written `0xGGFF` as in the listings.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Opcode(pub u16);

impl Opcode {
    /// The group byte.
    pub fn group(self) -> u8 {
        (self.0 >> 8) as u8
    }

    /// The function byte.
    pub fn func(self) -> u8 {
        self.0 as u8
    }

    /// An opcode from its two bytes.
    pub fn new(group: u8, func: u8) -> Opcode {
        Opcode((group as u16) << 8 | func as u16)
    }
}

impl fmt::Display for Opcode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X}", self.0)
    }
}

/// Opcodes by name, and constructors of the typed and variadic ones.
pub mod op {
    use super::{Opcode, Ty};

    /// Group numbers.
    pub mod group {
        /// Variadic addition.
        pub const ADD: u8 = 0x01;
        /// Subtraction.
        pub const SUB: u8 = 0x02;
        /// Variadic multiplication.
        pub const MUL: u8 = 0x03;
        /// Division and remainder.
        pub const DIV: u8 = 0x04;
        /// Negation and NOT.
        pub const NEG: u8 = 0x05;
        /// EXPT, ABS, the math functions, day of week.
        pub const MATH: u8 = 0x06;
        /// Memory move between local and absolute addresses.
        pub const MMV: u8 = 0x07;
        /// Variadic AND.
        pub const AND: u8 = 0x08;
        /// Variadic OR.
        pub const OR: u8 = 0x09;
        /// Variadic XOR.
        pub const XOR: u8 = 0x0A;
        /// Shifts and rotates.
        pub const SHIFT: u8 = 0x0B;
        /// SEL.
        pub const SEL: u8 = 0x0C;
        /// LIMIT.
        pub const LIMIT: u8 = 0x0D;
        /// Variadic MAX.
        pub const MAX: u8 = 0x0E;
        /// Variadic MIN.
        pub const MIN: u8 = 0x0F;
        /// GT.
        pub const GT: u8 = 0x10;
        /// GE.
        pub const GE: u8 = 0x11;
        /// EQ.
        pub const EQ: u8 = 0x12;
        /// LE.
        pub const LE: u8 = 0x13;
        /// LT.
        pub const LT: u8 = 0x14;
        /// NE.
        pub const NE: u8 = 0x15;
        /// Variadic MUX.
        pub const MUX: u8 = 0x16;
        /// Conversions.
        pub const CONV: u8 = 0x19;
        /// Control and system.
        pub const SYS: u8 = 0x1C;
        /// Native blocks of the host.
        pub const CUSTOM: u8 = 0x1D;
        /// Pointers.
        pub const PTR: u8 = 0x1E;
    }

    /// No operation.
    pub const NOP: Opcode = Opcode(0x0000);
    /// `JMP label`.
    pub const JMP: Opcode = Opcode(0x1C00);
    /// `JNZ cond, label`.
    pub const JNZ: Opcode = Opcode(0x1C01);
    /// `JZ cond, label`.
    pub const JZ: Opcode = Opcode(0x1C02);
    /// `CALF area, label`: call a function with DPTR += area.
    pub const CALF: Opcode = Opcode(0x1C10);
    /// `RETURN`.
    pub const RETURN: Opcode = Opcode(0x1C13);
    /// `MCD dst, #n, #bytes`.
    pub const MCD: Opcode = Opcode(0x1C15);
    /// `CALB inst, label`: call an FB with DPTR += inst.
    pub const CALB: Opcode = Opcode(0x1C16);
    /// `CUR_TIME dst`.
    pub const CUR_TIME: Opcode = Opcode(0x1C17);
    /// `RETFB` (alias of RETURN).
    pub const RETFB: Opcode = Opcode(0x1C18);
    /// `TRML label`: end of the scan; the next one starts at `label`.
    pub const TRML: Opcode = Opcode(0x1C1D);
    /// `MEMCP dst, src, #count`.
    pub const MEMCP: Opcode = Opcode(0x1C1F);
    /// `FPAT dst, #byte, #count`.
    pub const FPAT: Opcode = Opcode(0x1C23);
    /// `AURD dst, base, idx, size`.
    pub const AURD: Opcode = Opcode(0x1C24);
    /// `AUWR src, base, idx, size`.
    pub const AUWR: Opcode = Opcode(0x1C25);
    /// `AORD dst, base, idx` (1-byte elements).
    pub const AORD: Opcode = Opcode(0x1C26);
    /// `AOWR src, base, idx`.
    pub const AOWR: Opcode = Opcode(0x1C27);
    /// `ATRD` (2-byte elements).
    pub const ATRD: Opcode = Opcode(0x1C28);
    /// `ATWR`.
    pub const ATWR: Opcode = Opcode(0x1C29);
    /// `AFRD` (4-byte elements).
    pub const AFRD: Opcode = Opcode(0x1C2A);
    /// `AFWR`.
    pub const AFWR: Opcode = Opcode(0x1C2B);
    /// `AQRD` (8-byte elements).
    pub const AQRD: Opcode = Opcode(0x1C2C);
    /// `AQWR`.
    pub const AQWR: Opcode = Opcode(0x1C2D);
    /// `CEAC idx, low, span`: idx -= low; out of 0..=span sets ARRAYBOUND.
    pub const CEAC: Opcode = Opcode(0x1C2E);
    /// `GET_STATUS_WORD1 dst`.
    pub const GET_STATUS_WORD1: Opcode = Opcode(0x1C2F);
    /// `TASK_CYCLE dst`.
    pub const TASK_CYCLE: Opcode = Opcode(0x1C31);
    /// `GET_VMACH_VERSION dst`.
    pub const GET_VMACH_VERSION: Opcode = Opcode(0x1C32);
    /// `MCD4A dst, #count4, #bytes` (aligned mode).
    pub const MCD4A: Opcode = Opcode(0x1C37);
    /// `FPAT4A dst, #byte2, #count2` (aligned mode).
    pub const FPAT4A: Opcode = Opcode(0x1C38);
    /// `MEMCP4A dst, src, #count4` (aligned mode).
    pub const MEMCP4A: Opcode = Opcode(0x1C39);
    /// `DPSTO dst`: stores DPTR (an absolute address) at `dst`.
    pub const DPSTO: Opcode = Opcode(0x1E00);
    /// `DPRDL dst, ptr, #count`: copies `count` bytes from the absolute address in `ptr`.
    pub const DPRDL: Opcode = Opcode(0x1E01);
    /// `DPWRL src, ptr, #count`: copies `count` bytes to the absolute address in `ptr`.
    pub const DPWRL: Opcode = Opcode(0x1E02);
    /// `CALBR ptr, label`: calls an FB whose instance's absolute address is in `ptr`.
    pub const CALBR: Opcode = Opcode(0x1E03);

    /// `ADD` of `n` operands of type `t`.
    pub fn add(t: Ty, n: u8) -> Opcode {
        Opcode::new(group::ADD, n << 4 | t as u8)
    }
    /// `MUL` of `n` operands.
    pub fn mul(t: Ty, n: u8) -> Opcode {
        Opcode::new(group::MUL, n << 4 | t as u8)
    }
    /// `SUB`.
    pub fn sub(t: Ty) -> Opcode {
        Opcode::new(group::SUB, t as u8)
    }
    /// `DIV`.
    pub fn div(t: Ty) -> Opcode {
        Opcode::new(group::DIV, t as u8)
    }
    /// `MOD`.
    pub fn modulo(t: Ty) -> Opcode {
        Opcode::new(group::DIV, 0x10 | t as u8)
    }
    /// A comparison (`group::GT` … `group::NE`), result BOOL.
    pub fn cmp(group: u8, t: Ty) -> Opcode {
        Opcode::new(group, t as u8)
    }
    /// `SEL dst, g, in0, in1`.
    pub fn sel(t: Ty) -> Opcode {
        Opcode::new(group::SEL, t as u8)
    }
    /// `MMV dst, src` of `n` bytes (< 128); `to_abs`: the destination is absolute and
    /// the source local, else the destination is local and the source absolute.
    pub fn mmv(n: u8, to_abs: bool) -> Opcode {
        Opcode::new(group::MMV, (n & 0x7F) | if to_abs { 0x80 } else { 0 })
    }
}

/// An instruction: an opcode and its operands.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Inst {
    /// The opcode.
    pub opcode: Opcode,
    /// The operands, in encoding order.
    pub operands: Vec<Operand>,
}

/// Why bytes do not decode.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodeError {
    /// The code address of the instruction.
    pub at: u32,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at code address {:04x}: {}", self.at, self.message)
    }
}

impl std::error::Error for DecodeError {}

const D: Kind = Kind::Data;
const C: Kind = Kind::Code;

/// The mnemonic and operand kinds of an opcode in a mode, or `None` for an opcode this
/// VM does not implement.
pub fn shape(opcode: Opcode, mode: Mode) -> Option<(&'static str, Vec<Kind>)> {
    use op::group as g;
    let (grp, func) = (opcode.group(), opcode.func());
    let n = (func >> 4) as usize;
    let t = func & 0xF;
    let data = |k: usize| vec![D; k];
    let typed =
        |name: &'static str, k: usize, ok: bool| if ok { Some((name, data(k))) } else { None };
    // Every instruction executes in every mode (the C VM never checks the mode of an
    // instruction; `reference/cpdev-vm-opcodes.md` §1). Type codes are those the
    // public C VMs implement (§2): any other is "unknown function" and stops them.
    let _ = mode;
    match grp {
        0x00 if func == 0 => Some(("$VMSYS.NOP", vec![])),
        g::ADD => typed("$DEFAULT.ADD", n + 1, n >= 2 && (1..=0xB).contains(&t)),
        g::MUL => typed("$DEFAULT.MUL", n + 1, n >= 2 && (1..=0xA).contains(&t)),
        g::SUB => typed("$DEFAULT.SUB", 3, (1..=0xB).contains(&t) && func < 0x10),
        g::DIV => match func {
            0x01..=0x0A => Some(("$DEFAULT.DIV", data(3))),
            // MOD: integers only.
            0x11..=0x18 => Some(("$DEFAULT.MOD", data(3))),
            _ => None,
        },
        g::NEG => match func {
            0x01..=0x04 | 0x07 | 0x09 => Some(("$DEFAULT.NEG", data(2))),
            0x10..=0x14 => Some(("$DEFAULT.NOT", data(2))),
            _ => None,
        },
        g::MATH => {
            let name = match func {
                0x01..=0x08 => "$DEFAULT.EXPT",
                0x11..=0x1A => "$DEFAULT.ABS",
                0x20 | 0x21 => "$DEFAULT.SQRT",
                0x22 | 0x23 => "$DEFAULT.LN",
                0x24 | 0x25 => "$DEFAULT.LOG",
                0x26 | 0x27 => "$DEFAULT.EXP",
                0x28 | 0x29 => "$DEFAULT.SIN",
                0x2A | 0x2B => "$DEFAULT.COS",
                0x2C | 0x2D => "$DEFAULT.TAN",
                0x2E | 0x2F => "$DEFAULT.ASIN",
                0x30 | 0x31 => "$DEFAULT.ACOS",
                0x32 | 0x33 => "$DEFAULT.ATAN",
                0x34 | 0x35 => "$DEFAULT.TRUNC",
                0x36 | 0x37 => "$DEFAULT.ROUND",
                _ => return None,
            };
            Some((name, data(if func <= 0x08 { 3 } else { 2 })))
        }
        g::MMV if func & 0x7F != 0 => Some(("$VMSYS.MMV", data(2))),
        g::AND => typed("$DEFAULT.AND", n + 1, n >= 2 && t <= 4),
        g::OR => typed("$DEFAULT.OR", n + 1, n >= 2 && t <= 4),
        g::XOR => typed(
            "$DEFAULT.XOR",
            n + 1,
            n >= 2 && matches!(t, 0 | 1 | 2 | 4 | 5),
        ),
        g::SHIFT => {
            let name = match n {
                0 => "$DEFAULT.SHL",
                1 => "$DEFAULT.SHR",
                2 => "$DEFAULT.ROL",
                3 => "$DEFAULT.ROR",
                _ => return None,
            };
            typed(name, 3, (1..=4).contains(&t))
        }
        g::SEL => typed("$DEFAULT.SEL", 4, func <= 0x0E),
        g::LIMIT => typed("$DEFAULT.LIMIT", 4, (1..=0xE).contains(&func)),
        g::MAX => typed("$DEFAULT.MAX", n + 1, n >= 2 && (1..=0xE).contains(&t)),
        g::MIN => typed("$DEFAULT.MIN", n + 1, n >= 2 && (1..=0xE).contains(&t)),
        g::GT => typed("$DEFAULT.GT", 3, func <= 0x0E),
        g::GE => typed("$DEFAULT.GE", 3, func <= 0x0E),
        g::EQ => typed("$DEFAULT.EQ", 3, func <= 0x0E),
        g::LE => typed("$DEFAULT.LE", 3, func <= 0x0E),
        g::LT => typed("$DEFAULT.LT", 3, func <= 0x0E),
        g::NE => typed("$DEFAULT.NE", 3, func <= 0x0E),
        g::MUX => typed("$DEFAULT.MUX", n + 1, n >= 2 && func & 0xF <= 0xE),
        g::CONV => {
            let name = match func {
                0x00 => "$DEFAULT.INT_TO_REAL",
                0x01 => "$DEFAULT.DINT_TO_REAL",
                0x02 => "$DEFAULT.TIME_TO_DINT",
                0x03 => "$DEFAULT.DINT_TO_TIME",
                0x04 => "$DEFAULT.TIME_TO_REAL",
                0x05 => "$DEFAULT.REAL_TO_TIME",
                0x06 => "$DEFAULT.BYTE_BCD_TO_INT",
                0x07 => "$DEFAULT.WORD_BCD_TO_INT",
                0x08 => "$DEFAULT.INT_TO_BCD_BYTE",
                0x09 => "$DEFAULT.INT_TO_BCD_WORD",
                0x0A => "$DEFAULT.REAL_TO_INT",
                0x0B => "$DEFAULT.INT_TO_BOOL",
                0x0C => "$DEFAULT.INT_TO_DINT",
                0x0D => "$DEFAULT.REAL_TO_LREAL",
                0x0E => "$DEFAULT.LREAL_TO_REAL",
                0x0F => "$DEFAULT.LINT_TO_LREAL",
                0x10 => "$DEFAULT.DWORD_TO_REAL",
                0x11 => "$DEFAULT.REAL_TO_DWORD",
                _ => return None,
            };
            Some((name, data(2)))
        }
        g::SYS => {
            let (name, kinds): (&str, Vec<Kind>) = match func {
                0x00 => ("$VMSYS.JMP", vec![C]),
                0x01 => ("$VMSYS.JNZ", vec![D, C]),
                0x02 => ("$VMSYS.JZ", vec![D, C]),
                0x10 => ("$VMSYS.CALF", vec![D, C]),
                0x13 => ("$VMSYS.RETURN", vec![]),
                0x15 => ("$VMSYS.MCD", vec![D, Kind::Bytes]),
                0x16 => ("$VMSYS.CALB", vec![D, C]),
                0x17 => ("$DEFAULT.CUR_TIME", vec![D]),
                0x18 => ("$VMSYS.RETFB", vec![]),
                0x1D => ("$VMSYS.TRML", vec![C]),
                0x1F => ("$VMSYS.MEMCP", vec![D, D, Kind::Word]),
                0x23 => ("$VMSYS.FPAT", vec![D, Kind::Byte, Kind::Byte]),
                0x24 => ("$VMSYS.AURD", vec![D, D, D, D]),
                0x25 => ("$VMSYS.AUWR", vec![D, D, D, D]),
                0x26 => ("$VMSYS.AORD", vec![D, D, D]),
                0x27 => ("$VMSYS.AOWR", vec![D, D, D]),
                0x28 => ("$VMSYS.ATRD", vec![D, D, D]),
                0x29 => ("$VMSYS.ATWR", vec![D, D, D]),
                0x2A => ("$VMSYS.AFRD", vec![D, D, D]),
                0x2B => ("$VMSYS.AFWR", vec![D, D, D]),
                0x2C => ("$VMSYS.AQRD", vec![D, D, D]),
                0x2D => ("$VMSYS.AQWR", vec![D, D, D]),
                0x2E => ("$VMSYS.CEAC", vec![D, D, D]),
                0x2F => ("$VMSYS.GET_STATUS_WORD1", vec![D]),
                0x31 => ("$VMSYS.TASK_CYCLE", vec![D]),
                0x32 => ("$VMSYS.GET_VMACH_VERSION", vec![D]),
                0x37 => ("$VMSYS.MCD4A", vec![D, Kind::Bytes4A]),
                0x38 => ("$VMSYS.FPAT4A", vec![D, Kind::Word, Kind::Word]),
                0x39 => ("$VMSYS.MEMCP4A", vec![D, D, Kind::Dword]),
                _ => return None,
            };
            Some((name, kinds))
        }
        g::PTR => {
            let (name, kinds): (&str, Vec<Kind>) = match func {
                0x00 => ("$VMSYS.DPSTO", vec![D]),
                0x01 => ("$VMSYS.DPRDL", vec![D, D, Kind::Word]),
                0x02 => ("$VMSYS.DPWRL", vec![D, D, Kind::Word]),
                0x03 => ("$VMSYS.CALBR", vec![D, C]),
                // 1E11/1E12 (DPRDL4A/DPWRL4A) are named in vmdef.h but no VM executes them.
                _ => return None,
            };
            Some((name, kinds))
        }
        _ => None,
    }
}

/// Bytes MCD4A's payload takes for `n` data bytes (padded to a multiple of 4).
pub fn padded4(n: usize) -> usize {
    n.div_ceil(4) * 4
}

/// The byte MCD4A pads its payload with (as the CPDev compiler does).
pub const MCD4A_PAD: u8 = 0xFF;

impl Inst {
    /// An instruction.
    pub fn new(opcode: Opcode, operands: Vec<Operand>) -> Inst {
        Inst { opcode, operands }
    }

    /// Appends the encoding to `out`. Panics if the operands do not fit the opcode's
    /// shape (a bug of the caller: the code generator only builds valid instructions).
    pub fn encode(&self, mode: Mode, out: &mut Vec<u8>) {
        let (name, kinds) = shape(self.opcode, mode).unwrap_or_else(|| {
            panic!("opcode {} has no form in mode {}", self.opcode, mode.name())
        });
        assert_eq!(kinds.len(), self.operands.len(), "{name}: operand count");
        out.push(self.opcode.group());
        out.push(self.opcode.func());
        if mode == Mode::M32A {
            out.extend([0, 0]);
        }
        let a = mode.addr_bytes();
        for (k, o) in kinds.iter().zip(&self.operands) {
            match (k, o) {
                (Kind::Data, Operand::Data(x)) | (Kind::Code, Operand::Code(x)) => {
                    out.extend_from_slice(&x.to_le_bytes()[..a])
                }
                (Kind::Byte, Operand::Imm(x)) => out.push(*x as u8),
                (Kind::Word, Operand::Imm(x)) => out.extend_from_slice(&(*x as u16).to_le_bytes()),
                (Kind::Dword, Operand::Imm(x)) => out.extend_from_slice(&x.to_le_bytes()),
                (Kind::Bytes, Operand::Bytes(b)) => {
                    out.push(b.len() as u8);
                    out.extend_from_slice(b);
                }
                (Kind::Bytes4A, Operand::Bytes(b)) => {
                    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
                    out.extend_from_slice(b);
                    out.extend(std::iter::repeat_n(MCD4A_PAD, padded4(b.len()) - b.len()));
                }
                _ => panic!("{name}: operand {o:?} does not fit {k:?}"),
            }
        }
    }

    /// The encoded length in bytes.
    pub fn len(&self, mode: Mode) -> usize {
        let mut v = Vec::new();
        self.encode(mode, &mut v);
        v.len()
    }

    /// Decodes the instruction at `at`; returns it and its length.
    pub fn decode(code: &[u8], at: u32, mode: Mode) -> Result<(Inst, usize), DecodeError> {
        let err = |m: String| DecodeError { at, message: m };
        let start = at as usize;
        let get = |i: usize, n: usize| -> Result<&[u8], DecodeError> {
            code.get(i..i + n)
                .ok_or_else(|| err("the code image ends inside an instruction".into()))
        };
        let b = get(start, 2)?;
        let opcode = Opcode::new(b[0], b[1]);
        let (_, kinds) =
            shape(opcode, mode).ok_or_else(|| err(format!("unknown opcode {opcode}")))?;
        let mut i = start + mode.opcode_bytes();
        get(start, mode.opcode_bytes())?;
        let a = mode.addr_bytes();
        let le = |s: &[u8]| s.iter().rev().fold(0u32, |acc, &x| acc << 8 | x as u32);
        let mut operands = Vec::with_capacity(kinds.len());
        for k in kinds {
            let o = match k {
                Kind::Data => Operand::Data(le(get(i, a)?)),
                Kind::Code => Operand::Code(le(get(i, a)?)),
                Kind::Byte => Operand::Imm(le(get(i, 1)?)),
                Kind::Word => Operand::Imm(le(get(i, 2)?)),
                Kind::Dword => Operand::Imm(le(get(i, 4)?)),
                Kind::Bytes => {
                    let n = get(i, 1)?[0] as usize;
                    i += 1;
                    let v = get(i, n)?.to_vec();
                    i += n;
                    operands.push(Operand::Bytes(v));
                    continue;
                }
                Kind::Bytes4A => {
                    let n = le(get(i, 4)?) as usize;
                    i += 4;
                    let v = get(i, n)?.to_vec();
                    i += padded4(n);
                    get(start, i - start)?;
                    operands.push(Operand::Bytes(v));
                    continue;
                }
            };
            i += match k {
                Kind::Data | Kind::Code => a,
                Kind::Byte => 1,
                Kind::Word => 2,
                _ => 4,
            };
            operands.push(o);
        }
        Ok((Inst { opcode, operands }, i - start))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodes_like_the_listings() {
        let mut v = Vec::new();
        Inst::new(
            op::MCD,
            vec![Operand::Data(0x0C), Operand::Bytes(vec![0xE8, 3, 0, 0])],
        )
        .encode(Mode::M16, &mut v);
        assert_eq!(v, [0x1C, 0x15, 0x0C, 0x00, 0x04, 0xE8, 0x03, 0x00, 0x00]);
        let mut v = Vec::new();
        Inst::new(
            op::add(Ty::Int, 2),
            vec![
                Operand::Data(0x98),
                Operand::Data(0x98),
                Operand::Data(0xC2),
            ],
        )
        .encode(Mode::M16, &mut v);
        assert_eq!(v, [0x01, 0x22, 0x98, 0, 0x98, 0, 0xC2, 0]);
        let mut v = Vec::new();
        Inst::new(
            op::MCD4A,
            vec![Operand::Data(0x50), Operand::Bytes(vec![0, 0])],
        )
        .encode(Mode::M32A, &mut v);
        assert_eq!(
            v,
            [0x1C, 0x37, 0, 0, 0x50, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0xFF, 0xFF]
        );
    }

    #[test]
    fn decodes_what_it_encodes() {
        for mode in Mode::ALL {
            let insts = [
                Inst::new(op::JZ, vec![Operand::Data(0x9A), Operand::Code(0x231)]),
                Inst::new(op::RETURN, vec![]),
                Inst::new(op::mmv(4, true), vec![Operand::Data(1), Operand::Data(2)]),
                Inst::new(op::CALB, vec![Operand::Data(8), Operand::Code(0x3D)]),
            ];
            for i in insts {
                let mut v = Vec::new();
                i.encode(mode, &mut v);
                let (d, n) = Inst::decode(&v, 0, mode).unwrap();
                assert_eq!((d, n), (i, v.len()));
            }
        }
    }
}
