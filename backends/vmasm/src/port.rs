//! The CPDev VM ports and what each one executes.
//!
//! The public C VM is built for many machines, each with its own `vm_cfg.h`: what one
//! port executes another stops on as an "unknown function"
//! (`reference/cpdev-vm-opcodes.md` §0 and §2). `-s port=NAME` names the port a build
//! is for; [`needs`] says which optional parts of the VM an opcode requires, and the
//! instruction selector reports an opcode the chosen port lacks as error E9105 at the
//! source it came from. The C `int` width decides which forms of 16-bit
//! multiplication and which divisions are free of undefined behaviour (§3).

use crate::isa::{op, Opcode};
use plcc_ir::passes::legalize::{Defines, Widths};

/// A CPDev VM port.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Default)]
pub enum Port {
    /// The most capable builds (Windows, BeagleBone AI, iOS, Arduino Due): everything,
    /// with a 32-bit C `int`.
    #[default]
    Full,
    /// ESP32: REAL, math, DATE/TOD/DT and pointers; no LINT, LWORD, LREAL or STRING;
    /// 32-bit `int`.
    Esp32,
    /// ArduinoAVR: as ESP32, with a 16-bit `int`.
    Avr,
    /// The 6502 (cc65) build: integers only (no REAL, math, DATE/TOD/DT, pointers,
    /// LINT/LWORD, LREAL or STRING), a 16-bit `int`.
    M6502,
    /// The sdcc build: as the 6502's.
    Sdcc,
}

/// An optional part of the VM, compiled in on some ports only.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// REAL arithmetic and conversions (`VM_REAL_SUPPORT`).
    Real,
    /// LREAL (`VM_LREAL_SUPPORT`).
    Lreal,
    /// 64-bit integers: LINT, ULINT, LWORD (`VM_LONG_SUPPORT`).
    Long,
    /// The math group 06: EXPT, ABS, SQRT, the transcendental functions, TRUNC.
    Math,
    /// DATE, TOD and DT instructions.
    DateTime,
    /// Pointers (group 1E: DPSTO, DPRDL, DPWRL, CALBR): VAR_IN_OUT, references and
    /// elements of arrays of FBs or STRUCTs at a computed index.
    Pointers,
    /// STRING instructions (group 18, type F).
    Strings,
}

impl Part {
    /// What the part is, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Part::Real => "REAL arithmetic",
            Part::Lreal => "LREAL arithmetic",
            Part::Long => "64-bit integer operations (LINT, ULINT, LWORD)",
            Part::Math => "the math instructions (EXPT, ABS, SQRT, LN, SIN, TRUNC, ...)",
            Part::DateTime => "DATE/TOD/DT instructions",
            Part::Pointers => {
                "pointers (VAR_IN_OUT, references, elements of arrays of FBs or STRUCTs at a computed index)"
            }
            Part::Strings => "STRING instructions",
        }
    }
}

impl Port {
    /// Every port, for messages and tests.
    pub const ALL: [Port; 5] = [Port::Full, Port::Esp32, Port::Avr, Port::M6502, Port::Sdcc];

    /// The port named `s` on the command line.
    pub fn parse(s: &str) -> Option<Port> {
        Some(match s.to_ascii_lowercase().as_str() {
            "full" | "windows" | "bbai" | "ios" | "due" => Port::Full,
            "esp32" => Port::Esp32,
            "avr" => Port::Avr,
            "6502" => Port::M6502,
            "sdcc" => Port::Sdcc,
            _ => return None,
        })
    }

    /// The port's name.
    pub fn name(self) -> &'static str {
        match self {
            Port::Full => "full",
            Port::Esp32 => "esp32",
            Port::Avr => "avr",
            Port::M6502 => "6502",
            Port::Sdcc => "sdcc",
        }
    }

    /// True when the port's C `int` has 16 bits.
    pub fn int16(self) -> bool {
        matches!(self, Port::Avr | Port::M6502 | Port::Sdcc)
    }

    /// What the code for this port defines as the IR does, for the guards of
    /// `passes::legalize` (which the build runs first): division by zero, shifts by
    /// the width or more and float-to-integer conversions out of range are undefined
    /// in the C VMs; `MIN / -1` is defined where the operands are promoted to a wider
    /// C `int` (SINT, and INT where `int` has 32 bits) and for LINT, which the
    /// instruction selector divides by magnitudes as LWORD (`isel::portable`).
    pub fn defines(self) -> Defines {
        Defines {
            div_by_zero: false,
            min_div_neg1: if self.int16() {
                Widths::of(&[8, 64])
            } else {
                Widths::of(&[8, 16, 64])
            },
            shift_ge_width: false,
            float_to_int_saturates: false,
        }
    }

    /// True when the port's VM has `part` compiled in.
    pub fn has(self, part: Part) -> bool {
        match self {
            Port::Full => true,
            Port::Esp32 | Port::Avr => !matches!(part, Part::Lreal | Part::Long | Part::Strings),
            Port::M6502 | Port::Sdcc => false,
        }
    }

    /// The first part `opcode` needs that this port lacks.
    pub fn lacks(self, opcode: Opcode) -> Option<Part> {
        needs(opcode).into_iter().find(|&p| !self.has(p))
    }
}

/// The parts of a type code in the typed groups (ADD … MUX): 4 LINT, 8 LWORD, 9 REAL,
/// A LREAL, C–E DATE/TOD/DT, F STRING.
fn type_parts(t: u8, out: &mut Vec<Part>) {
    match t {
        4 | 8 => out.push(Part::Long),
        9 => out.push(Part::Real),
        0xA => out.push(Part::Lreal),
        0xC..=0xE => out.push(Part::DateTime),
        0xF => out.push(Part::Strings),
        _ => {}
    }
}

/// The optional parts of the VM `opcode` needs (none for the core instructions).
pub fn needs(opcode: Opcode) -> Vec<Part> {
    use op::group as g;
    let (grp, f) = (opcode.group(), opcode.func());
    let t = f & 0xF;
    let mut out = Vec::new();
    match grp {
        g::ADD
        | g::SUB
        | g::MUL
        | g::DIV
        | g::SEL
        | g::LIMIT
        | g::MAX
        | g::MIN
        | g::GT
        | g::GE
        | g::EQ
        | g::LE
        | g::LT
        | g::NE
        | g::MUX => type_parts(t, &mut out),
        g::NEG => match f {
            0x04 | 0x14 => out.push(Part::Long),
            0x07 => out.push(Part::Real),
            0x09 => out.push(Part::Lreal),
            _ => {}
        },
        g::MATH => {
            out.push(Part::Math);
            match f {
                0x04..=0x07 => out.push(Part::Real),
                0x08 => out.push(Part::Lreal),
                0x10..=0x1F => type_parts(t, &mut out),
                0x35 | 0x37 => out.extend([Part::Lreal, Part::Long]),
                0x20..=0x3F if f & 1 == 1 => out.push(Part::Lreal),
                0x20..=0x3F => out.push(Part::Real),
                0x40 | 0x41 => out.push(Part::DateTime),
                _ => {}
            }
        }
        g::AND | g::OR if t == 4 => out.push(Part::Long),
        g::XOR if t == 5 => out.push(Part::Long),
        g::SHIFT if t == 4 => out.push(Part::Long),
        g::CONV => match f {
            0x00 | 0x01 | 0x04 | 0x05 | 0x0A | 0x10 | 0x11 => out.push(Part::Real),
            0x0D | 0x0E => out.extend([Part::Real, Part::Lreal]),
            0x0F => out.extend([Part::Lreal, Part::Long]),
            _ => {}
        },
        g::SYS => match f {
            0x20 | 0x21 | 0x30 => out.push(Part::DateTime),
            0x22 => out.push(Part::Real),
            _ => {}
        },
        g::PTR => out.push(Part::Pointers),
        0x18 => out.push(Part::Strings),
        _ => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ports_follow_the_reference_table() {
        // reference/cpdev-vm-opcodes.md §0: REAL ✓ on AVR and ESP32, not on 6502/sdcc;
        // LINT/LWORD and LREAL only on the full builds; pointers off on 6502/sdcc.
        let add_real = Opcode(0x0129);
        let add_lword = Opcode(0x0128);
        let expt_lreal = Opcode(0x0608);
        let dprdl = Opcode(0x1E01);
        let mul_int = Opcode(0x0322);
        for p in Port::ALL {
            assert_eq!(p.lacks(mul_int), None, "{p:?}");
        }
        assert_eq!(Port::Full.lacks(expt_lreal), None);
        assert_eq!(Port::Esp32.lacks(add_real), None);
        assert_eq!(Port::Esp32.lacks(add_lword), Some(Part::Long));
        assert_eq!(Port::Avr.lacks(expt_lreal), Some(Part::Lreal));
        assert_eq!(Port::Avr.lacks(dprdl), None);
        assert_eq!(Port::M6502.lacks(dprdl), Some(Part::Pointers));
        assert_eq!(Port::Sdcc.lacks(add_real), Some(Part::Real));
        assert_eq!(Port::Sdcc.lacks(Opcode(0x0611)), Some(Part::Math));
        assert!(Port::Avr.int16() && !Port::Esp32.int16() && !Port::Full.int16());
        assert_eq!(Port::parse("ESP32"), Some(Port::Esp32));
        assert_eq!(Port::parse("z80"), None);
    }
}
