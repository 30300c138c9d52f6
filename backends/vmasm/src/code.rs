//! Code before addresses: instructions with symbolic operands, grouped in units (one
//! per function), assembled to the XCP image and printed as the VMASM listing.
//!
//! The listing has the form of the CPDev compiler's `<MNEMONIC_MAP>`: one line per
//! label and per instruction, `:ADDR| BYTES | MNEMONIC OPERANDS`, data operands named
//! by variable, immediates as `#` and their raw little-endian bytes.

use crate::isa::{self, Inst, Kind, Mode, Opcode, Operand};
use rustc_hash::FxHashMap;
use std::fmt::Write;

/// A code label, an index into [`Program::labels`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct LabelId(pub u32);

/// An operand before addresses are known.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    /// A data address relative to DPTR.
    Rel(u32),
    /// An absolute data address, or a literal address operand (CALB's `#0000`).
    Abs(u32),
    /// A code label.
    Label(LabelId),
    /// A fixed-width immediate (count, fill byte).
    Imm(u32),
    /// MCD's bytes.
    Bytes(Vec<u8>),
}

/// An instruction with symbolic operands.
#[derive(Clone, Debug, PartialEq)]
pub struct VInst {
    /// The opcode.
    pub opcode: Opcode,
    /// Its operands, in encoding order.
    pub args: Vec<Arg>,
}

/// One line of a unit.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// A label here.
    Label(LabelId),
    /// An instruction.
    Inst(VInst),
    /// A source line shown in the listing (`;!!!!` lines of the CPDev listings).
    Source(String),
}

/// The code of one function, or of the task.
#[derive(Clone, Debug, Default)]
pub struct Unit {
    /// Its lines.
    pub items: Vec<Item>,
    /// Names of DPTR-relative addresses in this unit, for the listing.
    pub rel_names: FxHashMap<u32, String>,
    /// Names of absolute addresses used in this unit, for the listing.
    pub abs_names: FxHashMap<u32, String>,
}

/// A whole program before assembly.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Units in code order.
    pub units: Vec<Unit>,
    /// Label names (`?PROG.MAIN?CODE`), indexed by [`LabelId`].
    pub labels: Vec<String>,
}

/// The assembled program.
#[derive(Clone, Debug)]
pub struct Image {
    /// The XCP bytes (loaded at code address 0).
    pub code: Vec<u8>,
    /// The address of every label.
    pub label_addrs: Vec<u32>,
    /// The listing.
    pub listing: String,
}

impl Program {
    /// A new label.
    pub fn label(&mut self, name: impl Into<String>) -> LabelId {
        self.labels.push(name.into());
        LabelId(self.labels.len() as u32 - 1)
    }

    /// Assembles the program. Fails when the code does not fit the mode's addresses.
    pub fn assemble(&self, mode: Mode) -> Result<Image, String> {
        // Operand widths do not depend on values, so one pass finds every address.
        let mut label_addrs = vec![u32::MAX; self.labels.len()];
        let mut at: u64 = 0;
        for u in &self.units {
            for it in &u.items {
                match it {
                    Item::Label(l) => label_addrs[l.0 as usize] = at as u32,
                    Item::Inst(i) => at += to_inst(i, &label_addrs, true).len(mode) as u64,
                    Item::Source(_) => {}
                }
            }
        }
        if at > mode.max_addr() + 1 {
            return Err(format!(
                "the code takes {at} bytes, more than the {} bytes {}-bit code addresses reach",
                mode.max_addr() + 1,
                if mode == Mode::M16 { 16 } else { 32 }
            ));
        }
        let mut code = Vec::with_capacity(at as usize);
        let mut listing = String::new();
        let w = if mode == Mode::M16 { 4 } else { 8 };
        for u in &self.units {
            for it in &u.items {
                match it {
                    Item::Label(l) => {
                        let _ = writeln!(
                            listing,
                            ":{:0w$x}| {:33} | :{}",
                            code.len(),
                            "",
                            self.labels[l.0 as usize]
                        );
                    }
                    Item::Source(s) => {
                        let _ = writeln!(listing, ";!!!!| {:33} | {}", "", s);
                    }
                    Item::Inst(vi) => {
                        let inst = to_inst(vi, &label_addrs, false);
                        let start = code.len();
                        inst.encode(mode, &mut code);
                        let hex = group_bytes(&inst, &code[start..], mode);
                        let text = self.text(u, vi, &inst, mode);
                        let _ = writeln!(listing, ":{start:0w$x}| {hex:33} | {text}");
                    }
                }
            }
        }
        let _ = writeln!(listing, ":{:0w$x}", code.len());
        Ok(Image {
            code,
            label_addrs,
            listing,
        })
    }

    fn text(&self, u: &Unit, vi: &VInst, inst: &Inst, mode: Mode) -> String {
        let (name, kinds) = isa::shape(inst.opcode, mode).expect("valid opcode");
        let mut parts = Vec::new();
        for ((a, o), k) in vi.args.iter().zip(&inst.operands).zip(&kinds) {
            parts.push(match (a, o) {
                (Arg::Rel(x), _) => u
                    .rel_names
                    .get(x)
                    .cloned()
                    .unwrap_or_else(|| hex_addr(*x, mode)),
                (Arg::Abs(x), _) => u.abs_names.get(x).cloned().unwrap_or_else(|| {
                    format!("#{}", hex_le(&x.to_le_bytes()[..mode.addr_bytes()]))
                }),
                (Arg::Label(l), _) => format!(":{}", self.labels[l.0 as usize]),
                (_, Operand::Imm(x)) => {
                    let n = match k {
                        Kind::Byte => 1,
                        Kind::Word => 2,
                        _ => 4,
                    };
                    format!("#{}", hex_le(&x.to_le_bytes()[..n]))
                }
                (_, Operand::Bytes(b)) => {
                    let count = if *k == Kind::Bytes4A {
                        hex_le(&(b.len() as u32).to_le_bytes())
                    } else {
                        format!("{:02X}", b.len())
                    };
                    format!("#{count}, #{}", hex_le(b))
                }
                (_, other) => format!("{other:?}"),
            });
        }
        if parts.is_empty() {
            name.to_string()
        } else {
            format!("{name} {}", parts.join(", "))
        }
    }
}

fn hex_addr(x: u32, mode: Mode) -> String {
    format!("#{}", hex_le(&x.to_le_bytes()[..mode.addr_bytes()]))
}

/// Bytes as the listings write them: two hex digits each, in memory order.
pub fn hex_le(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02X}")).collect()
}

/// The bytes of an encoded instruction grouped as the CPDev listings group them: the
/// opcode (with its padding), then each operand.
pub fn group_bytes(inst: &Inst, bytes: &[u8], mode: Mode) -> String {
    let (_, kinds) = isa::shape(inst.opcode, mode).expect("valid opcode");
    let mut groups = vec![hex_le(&bytes[..mode.opcode_bytes()])];
    let mut i = mode.opcode_bytes();
    for (k, o) in kinds.iter().zip(&inst.operands) {
        let mut take = |n: usize| {
            groups.push(hex_le(&bytes[i..i + n]));
            i += n;
        };
        match (k, o) {
            (Kind::Data | Kind::Code, _) => take(mode.addr_bytes()),
            (Kind::Byte, _) => take(1),
            (Kind::Word, _) => take(2),
            (Kind::Dword, _) => take(4),
            (Kind::Bytes, Operand::Bytes(b)) => {
                take(1);
                take(b.len());
            }
            (Kind::Bytes4A, Operand::Bytes(b)) => {
                take(4);
                take(isa::padded4(b.len()));
            }
            _ => {}
        }
    }
    groups.join(" ")
}

/// The instruction with labels resolved (`sizing`: labels may be unknown yet).
fn to_inst(vi: &VInst, labels: &[u32], sizing: bool) -> Inst {
    let operands = vi
        .args
        .iter()
        .map(|a| match a {
            Arg::Rel(x) | Arg::Abs(x) => Operand::Data(*x),
            Arg::Label(l) => {
                let at = labels[l.0 as usize];
                assert!(sizing || at != u32::MAX, "label never placed");
                Operand::Code(if sizing { 0 } else { at })
            }
            Arg::Imm(x) => Operand::Imm(*x),
            Arg::Bytes(b) => Operand::Bytes(b.clone()),
        })
        .collect();
    Inst {
        opcode: vi.opcode,
        operands,
    }
}
