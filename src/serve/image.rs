//! The I/O image: the four Modbus tables as OpenPLC maps them, and the located
//! variables bound to them.
//!
//! OpenPLC's map (`docs/serve.md`): coils are `%QX` (address = byte × 8 + bit),
//! discrete inputs `%IX`, input registers `%IW`, holding registers 0–1023 `%QW`,
//! 1024–2047 `%MW`, 2048–4095 `%MD` (two registers each, high word first), 4096–8191
//! `%ML` (four registers each, high word first). Every address of every table holds a
//! value whether a variable is located there or not, as OpenPLC's unbound addresses
//! do.
//!
//! The scan thread copies the image into the machine at the start of a scan
//! ([`Image::latch`]: every input, and what clients wrote since the last scan) and
//! the outputs back at its end ([`Image::publish`]), each under the image's lock, so
//! a client never sees half a scan.

use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::vars::PathStep;
use plcc_ir::{AggDef, ElemType, Module};

/// Bits of the coil and discrete-input tables (`%QX0.0`–`%QX1023.7`).
pub const BITS: usize = 8192;
/// Input registers (`%IW0`–`%IW1023`).
pub const INPUT_REGS: usize = 1024;
/// Holding registers (`%QW`, `%MW`, `%MD`, `%ML`).
pub const HOLDING_REGS: usize = 8192;
/// First holding register of `%MW0`.
pub const MW_BASE: usize = 1024;
/// First holding register of `%MD0`.
pub const MD_BASE: usize = 2048;
/// First holding register of `%ML0`.
pub const ML_BASE: usize = 4096;

/// Where a located variable lives in the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// A coil (`%QX`), by bit address.
    Coil(usize),
    /// A discrete input (`%IX`), by bit address.
    Discrete(usize),
    /// An input register (`%IW`).
    InputReg(usize),
    /// `words` holding registers from `start`, high word first.
    Holding {
        /// The first register.
        start: usize,
        /// 1, 2 or 4.
        words: usize,
    },
}

impl Slot {
    /// True for the slots the I/O writes and the program reads (`%IX`, `%IW`).
    pub fn is_input(self) -> bool {
        matches!(self, Slot::Discrete(_) | Slot::InputReg(_))
    }
}

/// A located variable bound to the image.
#[derive(Clone, Debug, PartialEq)]
pub struct Binding {
    /// Its path (`main.start`).
    pub path: String,
    /// Its IEC type.
    pub elem: ElemType,
    /// Its address as written (`%IX0.0`).
    pub location: String,
    /// Where it lives in the image.
    pub slot: Slot,
}

/// The slot of an address (`%QX0.1`, `%mw3`), or why it has none: a malformed
/// address, or one outside OpenPLC's Modbus map (such as `%IB0` or `%QX1024.0`), which
/// stays an ordinary variable.
pub fn slot_of(location: &str) -> Result<Slot, String> {
    let not = |why: &str| Err(format!("`{location}` {why}"));
    let Some(rest) = location.trim().strip_prefix('%') else {
        return not("is not a direct address");
    };
    let up = rest.to_ascii_uppercase();
    let mut chars = up.chars();
    let (Some(dir), Some(size)) = (chars.next(), chars.next()) else {
        return not("is not a direct address");
    };
    let nums: Vec<Option<usize>> = chars.as_str().split('.').map(|p| p.parse().ok()).collect();
    let (a, b) = match nums.as_slice() {
        [Some(a)] => (*a, None),
        [Some(a), Some(b)] => (*a, Some(*b)),
        _ => return not("has no address Modbus reaches (one or two numbers)"),
    };
    let bit = |a: usize, b: Option<usize>| match b {
        Some(b) if b < 8 && a < BITS / 8 => Ok(a * 8 + b),
        _ => Err(format!(
            "`{location}` is outside the bit tables (%X0.0 to %X1023.7)"
        )),
    };
    let word = |a: usize, b: Option<usize>, n: usize, base: usize, words: usize| {
        if b.is_some() || a >= n {
            Err(format!("`{location}` is outside OpenPLC's Modbus map"))
        } else {
            Ok(Slot::Holding {
                start: base + a * words,
                words,
            })
        }
    };
    match (dir, size) {
        ('Q', 'X') => bit(a, b).map(Slot::Coil),
        ('I', 'X') => bit(a, b).map(Slot::Discrete),
        ('I', 'W') if b.is_none() && a < INPUT_REGS => Ok(Slot::InputReg(a)),
        ('Q', 'W') => word(a, b, 1024, 0, 1),
        ('M', 'W') => word(a, b, 1024, MW_BASE, 1),
        ('M', 'D') => word(a, b, 1024, MD_BASE, 2),
        ('M', 'L') => word(a, b, 1024, ML_BASE, 4),
        _ => not("is outside OpenPLC's Modbus map"),
    }
}

/// Every located elementary variable of the module's programs and globals, with its
/// slot; the addresses outside the map are returned apart, with the reason.
pub fn bindings(module: &Module) -> (Vec<Binding>, Vec<String>) {
    let mut out = Vec::new();
    let mut outside = Vec::new();
    for v in crate::scenario::all_variables(module) {
        let location = match v.steps.last() {
            Some(PathStep::Field(agg, i)) => match module.agg(*agg) {
                AggDef::Struct(s) => s.fields[*i as usize].location.clone(),
                AggDef::Array(_) => None,
            },
            Some(PathStep::Elem(..)) => None,
            None => module.data[v.root.index()].location.clone(),
        };
        let Some(location) = location else { continue };
        match slot_of(&location) {
            Ok(slot) => out.push(Binding {
                path: v.path,
                elem: v.elem,
                location,
                slot,
            }),
            Err(why) => outside.push(format!("{}: {why}", v.path)),
        }
    }
    (out, outside)
}

/// The four tables and what clients wrote since the last scan.
#[derive(Clone, Debug)]
pub struct Image {
    /// Coils (`%QX`).
    pub coils: Vec<bool>,
    /// Discrete inputs (`%IX`).
    pub discrete: Vec<bool>,
    /// Input registers (`%IW`).
    pub input_regs: Vec<u16>,
    /// Holding registers (`%QW`, `%MW`, `%MD`, `%ML`).
    pub holding: Vec<u16>,
    /// Coils written by a client since the last scan start.
    dirty_coils: Vec<bool>,
    /// Holding registers written by a client since the last scan start.
    dirty_holding: Vec<bool>,
}

impl Default for Image {
    fn default() -> Self {
        Image {
            coils: vec![false; BITS],
            discrete: vec![false; BITS],
            input_regs: vec![0; INPUT_REGS],
            holding: vec![0; HOLDING_REGS],
            dirty_coils: vec![false; BITS],
            dirty_holding: vec![false; HOLDING_REGS],
        }
    }
}

impl Image {
    /// A client writes coils from `start` (the caller has checked the range).
    pub fn write_coils(&mut self, start: usize, values: &[bool]) {
        for (i, &v) in values.iter().enumerate() {
            self.coils[start + i] = v;
            self.dirty_coils[start + i] = true;
        }
    }

    /// A client writes holding registers from `start` (the caller has checked the
    /// range).
    pub fn write_holding(&mut self, start: usize, values: &[u16]) {
        for (i, &v) in values.iter().enumerate() {
            self.holding[start + i] = v;
            self.dirty_holding[start + i] = true;
        }
    }

    /// The value of a binding's slot as the variable's type.
    pub fn value(&self, b: &Binding) -> PlcValue {
        let bits = match b.slot {
            Slot::Coil(i) => self.coils[i] as u64,
            Slot::Discrete(i) => self.discrete[i] as u64,
            Slot::InputReg(i) => self.input_regs[i] as u64,
            Slot::Holding { start, words } => self.holding[start..start + words]
                .iter()
                .fold(0u64, |acc, &w| (acc << 16) | w as u64),
        };
        PlcValue::from_bits(b.elem, bits)
    }

    /// Stores a value into a binding's slot.
    pub fn store(&mut self, b: &Binding, v: PlcValue) {
        match b.slot {
            Slot::Coil(i) => self.coils[i] = v.bits & 1 != 0,
            Slot::Discrete(i) => self.discrete[i] = v.bits & 1 != 0,
            Slot::InputReg(i) => self.input_regs[i] = v.bits as u16,
            Slot::Holding { start, words } => {
                for k in 0..words {
                    let shift = 16 * (words - 1 - k);
                    self.holding[start + k] = (v.bits >> shift) as u16;
                }
            }
        }
    }

    fn dirty(&self, b: &Binding) -> bool {
        match b.slot {
            Slot::Coil(i) => self.dirty_coils[i],
            Slot::Holding { start, words } => {
                self.dirty_holding[start..start + words].iter().any(|&d| d)
            }
            Slot::Discrete(_) | Slot::InputReg(_) => false,
        }
    }

    /// Scan start: every input, and every output or memory variable a client wrote
    /// since the last scan, into the machine.
    pub fn latch(&mut self, m: &mut dyn Machine, binds: &[Binding]) -> Result<(), String> {
        for b in binds {
            if b.slot.is_input() || self.dirty(b) {
                m.write(&b.path, self.value(b))
                    .map_err(|e| format!("writing {}: {e}", b.path))?;
            }
        }
        self.dirty_coils.iter_mut().for_each(|d| *d = false);
        self.dirty_holding.iter_mut().for_each(|d| *d = false);
        Ok(())
    }

    /// Scan end: every output and memory variable into the image, except those a
    /// client wrote during the scan (the next scan takes those).
    pub fn publish(&mut self, m: &dyn Machine, binds: &[Binding]) -> Result<(), String> {
        for b in binds {
            if b.slot.is_input() || self.dirty(b) {
                continue;
            }
            let v = m
                .read(&b.path)
                .map_err(|e| format!("reading {}: {e}", b.path))?;
            self.store(b, v);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn openplc_addresses() {
        assert_eq!(slot_of("%QX0.0"), Ok(Slot::Coil(0)));
        assert_eq!(slot_of("%qx2.3"), Ok(Slot::Coil(19)));
        assert_eq!(slot_of("%IX1023.7"), Ok(Slot::Discrete(8191)));
        assert_eq!(slot_of("%IW5"), Ok(Slot::InputReg(5)));
        assert_eq!(slot_of("%QW7"), Ok(Slot::Holding { start: 7, words: 1 }));
        assert_eq!(
            slot_of("%MW3"),
            Ok(Slot::Holding {
                start: 1027,
                words: 1
            })
        );
        assert_eq!(
            slot_of("%MD1"),
            Ok(Slot::Holding {
                start: 2050,
                words: 2
            })
        );
        assert_eq!(
            slot_of("%ML2"),
            Ok(Slot::Holding {
                start: 4104,
                words: 4
            })
        );
        for outside in [
            "%QX1024.0",
            "%QX0.8",
            "%IB0",
            "%QD0",
            "%IW1024",
            "%MW1024",
            "%MX0.0",
            "%QX0",
            "QX0.0",
            "%Q*",
            "%IX0.0.1",
        ] {
            assert!(slot_of(outside).is_err(), "{outside}");
        }
    }

    #[test]
    fn words_are_high_first_and_values_take_the_variables_type() {
        let mut img = Image::default();
        let b = Binding {
            path: "x".into(),
            elem: ElemType::DInt,
            location: "%MD0".into(),
            slot: Slot::Holding {
                start: MD_BASE,
                words: 2,
            },
        };
        img.store(&b, PlcValue::from_bits(ElemType::DInt, (-2i64) as u64));
        assert_eq!(&img.holding[MD_BASE..MD_BASE + 2], &[0xFFFF, 0xFFFE]);
        assert_eq!(
            img.value(&b).bits,
            PlcValue::from_bits(ElemType::DInt, (-2i64) as u64).bits
        );
        img.write_holding(MD_BASE, &[0, 7]);
        assert!(img.dirty(&b));
        assert_eq!(img.value(&b).bits, 7);
    }
}
