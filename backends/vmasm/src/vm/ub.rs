//! What the C VMs would compute with undefined behaviour, or misread.
//!
//! The public CPDev VMs are C: a signed overflow, a division by zero, a shift by the
//! width or a float cast out of range is undefined there, and which operations
//! overflow depends on the port's C `int` (`reference/cpdev-vm-opcodes.md` §3). The
//! byte-access builds (the `full` port) also misread a LINT whose bit 31 is set and
//! whose high half is not all ones (§3.8). plcc's VM computes all of these with
//! defined results; a VM made with [`super::Vm::for_port`] instead stops with an error
//! naming the case, so that running plcc's code on it shows any instruction a real
//! VM would get wrong. Only the two-operand forms of the variadic groups are checked
//! (plcc emits no other).

use super::{Core, Exit, Ins};
use crate::port::Port;

/// The rules of one port.
#[derive(Copy, Clone, Debug)]
pub(super) struct Checks {
    /// C `int` has 16 bits.
    pub int16: bool,
    /// LINT reads go through the byte-access getter that misreads.
    pub lint_read_bug: bool,
    /// The port: an opcode it lacks is "unknown function" there.
    pub port: Port,
}

impl Checks {
    pub(super) fn for_port(port: Port) -> Checks {
        Checks {
            int16: port.int16(),
            lint_read_bug: port == Port::Full,
            port,
        }
    }
}

/// True when `op` is an instruction [`check`] may have something to say about under
/// the rules `k` (false only where [`check`] always answers `None`).
pub(super) fn watched(op: u16, k: &Checks) -> bool {
    let (g, f) = ((op >> 8) as u8, op as u8);
    let t = f & 0xF;
    // ADD/SUB/MUL: only a signed C type can overflow, and LINT can be misread.
    let arith =
        matches!(t, 1..=8) && (signed_range(t, k.int16).is_some() || (k.lint_read_bug && t == 4));
    match g {
        0x01 | 0x03 => f >> 4 == 2 && arith,
        0x02 => arith,
        0x04 | 0x05 | 0x0B => true,
        0x06 => matches!(f, 0x11..=0x14 | 0x34..=0x37),
        0x19 => matches!(f, 0x05 | 0x0A | 0x0F | 0x11),
        0x0C..=0x15 => t == 4 && k.lint_read_bug,
        _ => false,
    }
}

fn int(c: &mut Core, t: u8, a: u32) -> Result<i128, Exit> {
    Ok(match t {
        1 => c.ld::<i8>(a)? as i128,
        2 => c.ld::<i16>(a)? as i128,
        3 => c.ld::<i32>(a)? as i128,
        4 => c.ld::<i64>(a)? as i128,
        5 => c.ld::<u8>(a)? as i128,
        6 => c.ld::<u16>(a)? as i128,
        7 | 0xB => c.ld::<u32>(a)? as i128,
        _ => c.ld::<u64>(a)? as i128,
    })
}

/// The range of the signed C type an operation of type code `t` is computed in, or
/// `None` where it is unsigned (wrapping is defined).
fn signed_range(t: u8, int16: bool) -> Option<(i128, i128)> {
    let r = |bits: u32| Some((-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1));
    match (t, int16) {
        // SINT, and BYTE promoted to int; INT, and WORD where int has 32 bits.
        (1 | 5, true) | (2, true) => r(16),
        (1 | 2 | 5 | 6, false) => r(32),
        (3, _) => r(32),
        (4, _) => r(64),
        _ => None,
    }
}

/// Why the C VM would get instruction `op` wrong with the operands at `i`, if it would.
pub(super) fn check(c: &mut Core, k: &Checks, op: u16, i: &Ins) -> Result<Option<String>, Exit> {
    let (g, f) = ((op >> 8) as u8, op as u8);
    let t = f & 0xF;
    // LINT operands through the misreading getter.
    if k.lint_read_bug {
        let lint_srcs: &[u32] = match (g, f) {
            (0x01..=0x04 | 0x0E | 0x0F | 0x10..=0x15, _) if t == 4 => &[i.b, i.c],
            (0x05, 0x04) | (0x06, 0x14) | (0x19, 0x0F) => &[i.b],
            (0x0C, 0x04) => &[i.c, i.d],
            _ => &[],
        };
        for &a in lint_srcs {
            let v = c.ld::<i64>(a)?;
            let (hi, lo) = ((v >> 32) as u32, v as u32);
            if lo & 0x8000_0000 != 0 && hi != u32::MAX {
                return Ok(Some(format!(
                    "the LINT {v} is misread by the byte-access getter (bit 31 set, high half not all ones)"
                )));
            }
        }
    }
    let why = |s: &str| Ok(Some(s.to_string()));
    match g {
        0x01..=0x03 if matches!(t, 1..=8) => {
            // Unsigned C arithmetic wraps: only a signed type can overflow (and its
            // operands, at most 64 bits, multiply within an i128).
            let Some((lo, hi)) = signed_range(t, k.int16) else {
                return Ok(None);
            };
            let (x, y) = (int(c, t, i.b)?, int(c, t, i.c)?);
            let r = match g {
                0x01 => x + y,
                0x02 => x - y,
                _ => x * y,
            };
            {
                if r < lo || r > hi {
                    return Ok(Some(format!(
                        "{r} overflows the signed C type it is computed in"
                    )));
                }
            }
        }
        0x04 if matches!(t, 1..=8) => {
            let (x, y) = (int(c, t, i.b)?, int(c, t, i.c)?);
            if y == 0 {
                return why("an integer division by zero (a trap on x86 and Xtensa)");
            }
            if y == -1 && matches!(t, 3 | 4) || (t == 2 && k.int16 && y == -1) {
                let (lo, _) = signed_range(t, k.int16).unwrap_or((0, 0));
                if x == lo {
                    return why("MIN / -1 overflows");
                }
            }
        }
        // NEG and ABS (INT with `abs`, DINT with `labs`, LINT by negation).
        0x05 | 0x06 if matches!((g, f), (0x05, 0x02..=0x04) | (0x06, 0x12..=0x14)) => {
            let x = int(c, t, i.b)?;
            let min = match t {
                2 if k.int16 => -(1i128 << 15),
                3 => -(1i128 << 31),
                4 => -(1i128 << 63),
                _ => return Ok(None),
            };
            if x == min {
                return why("negating the most negative value overflows");
            }
        }
        0x0B if matches!(t, 1..=4) => {
            let w = 8u32 << (t - 1);
            let n = c.ld::<i16>(i.c)? as i64;
            // BYTE and WORD are promoted to int (WORD to unsigned int where int has 16
            // bits); DWORD and LWORD keep their width.
            let (p, signed) = match t {
                1 => (if k.int16 { 16 } else { 32 }, true),
                2 if k.int16 => (16, false),
                2 => (32, true),
                _ => (w, false),
            };
            let v = int(c, t + 4, i.b)?;
            let shifts: Vec<i64> = match f >> 4 {
                0 | 1 => vec![n],
                _ => vec![n, w as i64 - n],
            };
            for s in shifts {
                if s < 0 || s >= p as i64 {
                    return Ok(Some(format!("a shift by {s} of a {p}-bit C value")));
                }
            }
            if signed && matches!(f >> 4, 0 | 2 | 3) {
                let left = if f >> 4 == 3 { w as i64 - n } else { n };
                if (v << left) > (1i128 << (p - 1)) - 1 {
                    return why("a left shift past INT_MAX");
                }
            }
        }
        0x06 | 0x19 => {
            let (x, lo, hi): (f64, f64, f64) = match (g, f) {
                (0x06, 0x34) => (c.ld::<f32>(i.b)? as f64, -2147483648.0, 2147483647.0),
                (0x06, 0x35) => (
                    c.ld::<f64>(i.b)?,
                    -9223372036854775808.0,
                    9223372036854774784.0,
                ),
                (0x06, 0x36) => (c.ld::<f32>(i.b)? as f64, -2147483648.5, 2147483647.5),
                (0x06, 0x37) => (
                    c.ld::<f64>(i.b)?,
                    -9223372036854775808.0,
                    9223372036854774784.0,
                ),
                (0x19, 0x0A) => (c.ld::<f32>(i.b)? as f64, -32768.0, 32767.0),
                (0x19, 0x05 | 0x11) => (c.ld::<f32>(i.b)? as f64, 0.0, 4294967295.0),
                _ => return Ok(None),
            };
            let tr = x.trunc();
            if x.is_nan() || tr < lo || tr > hi {
                return Ok(Some(format!("{x} is out of the range of the C cast")));
            }
        }
        _ => {}
    }
    Ok(None)
}
