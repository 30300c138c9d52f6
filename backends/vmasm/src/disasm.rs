//! Disassembling XCP code images into listings in the form of the CPDev compiler's
//! `<MNEMONIC_MAP>`:
//!
//! ```text
//! :0000|                                   | :?B.T?TSKSTR
//! :0000| 1C16 0000 1000                    | $VMSYS.CALB #0000, :?B.P?INIT
//! ```
//!
//! The address has 4 hex digits in the 16-bit mode, 8 in the 32-bit ones. The hex
//! column groups the opcode (with its padding in the aligned mode), then each operand
//! (MCD: the count, then the bytes); a column wider than 33 characters goes on in
//! continuation lines after a `…`, as the CPDev listings do. The last line is the end
//! address alone.
//!
//! Without names, data operands print as their raw little-endian bytes after `#`
//! (as CALB's `#0000`) and code addresses as `:hhhh`. With a [`Names`] source, label
//! lines come before their instruction, code addresses print as labels, and data
//! addresses as the names the scope of the code sees (scopes change at `?INIT`/`?CODE`
//! and `?TSKSTR`/`?TSKLOOP` labels, see [`crate::asm`]).

use crate::asm::{label_scope, Entry, Scope, Symbols};
use crate::isa::{op, DecodeError, Inst, Kind, Mode, Operand};
use std::fmt::Write;

/// What kind of object a data operand should name, to choose among the names of one
/// address (`TON1` and `TON1.IN` both sit at the instance's address).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Hint {
    /// An instance or call area (CALB's and CALF's first operand).
    Instance,
    /// A variable of this many bytes (MEMCP's, MCD's and FPAT's count).
    Size(u32),
    /// Anything; plain variables are preferred to instances.
    Any,
}

/// A source of names for the disassembler.
pub trait Names {
    /// The labels at a code address (without `:`), in listing order.
    fn labels_at(&self, addr: u32) -> Vec<String>;
    /// The name of a data address in a scope.
    fn data_name(&self, scope: &Scope, addr: u32, hint: Hint) -> Option<String>;
    /// The label printed for a code address operand: the first one there.
    fn label_name(&self, addr: u32) -> Option<String> {
        self.labels_at(addr).into_iter().next()
    }
}

fn pick<'a>(entries: impl Iterator<Item = &'a Entry>, hint: Hint) -> Option<&'a Entry> {
    let mut v: Vec<&Entry> = entries.collect();
    // Stable: DATA_MAP order breaks ties.
    v.sort_by_key(|e| {
        let rank = match hint {
            Hint::Instance => !e.aggregate as u8,
            Hint::Size(n) => match (e.sym.size == n, e.aggregate) {
                (true, false) => 0,
                (true, true) => 1,
                (false, false) => 2,
                (false, true) => 3,
            },
            Hint::Any => e.aggregate as u8,
        };
        (rank, e.depth)
    });
    v.into_iter().next()
}

impl Names for Symbols {
    fn labels_at(&self, addr: u32) -> Vec<String> {
        self.labels
            .iter()
            .filter(|(_, a)| *a == addr)
            .map(|(n, _)| n.clone())
            .collect()
    }

    fn data_name(&self, scope: &Scope, addr: u32, hint: Hint) -> Option<String> {
        let e = match scope {
            // The task calls its programs with a literal `#0000`.
            Scope::Task if hint == Hint::Instance => None,
            Scope::Task => pick(self.task.at(addr), hint),
            Scope::Pou(p) => self
                .pous
                .get(&p.to_ascii_uppercase())
                .and_then(|t| pick(t.at(addr), hint))
                .or_else(|| pick(self.globals.at(addr).filter(|e| e.depth == 0), hint)),
        };
        e.map(|e| e.path.clone())
    }
}

/// One decoded instruction of a listing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Line {
    /// Its code address.
    pub addr: u32,
    /// The labels before it (without `:`).
    pub labels: Vec<String>,
    /// The instruction.
    pub inst: Inst,
    /// Its bytes.
    pub bytes: Vec<u8>,
    /// The hex column (grouped).
    pub hex: String,
    /// The mnemonic text.
    pub text: String,
    /// The scope its names were taken from.
    pub scope: Scope,
}

fn hex(b: &[u8]) -> String {
    b.iter().fold(String::new(), |mut s, x| {
        let _ = write!(s, "{x:02X}");
        s
    })
}

/// The hex column of an encoded instruction, grouped as the CPDev listings group it:
/// the opcode (with its padding), then each operand; MCD's count and bytes apart.
pub fn hex_groups(inst: &Inst, bytes: &[u8], mode: Mode) -> String {
    let mut groups = Vec::new();
    let mut i = mode.opcode_bytes().min(bytes.len());
    groups.push(hex(&bytes[..i]));
    let a = mode.addr_bytes();
    let kinds = crate::isa::shape(inst.opcode, mode)
        .map(|s| s.1)
        .unwrap_or_default();
    for (k, o) in kinds.iter().zip(&inst.operands) {
        let widths: Vec<usize> = match (k, o) {
            (Kind::Data | Kind::Code, _) => vec![a],
            (Kind::Byte, _) => vec![1],
            (Kind::Word, _) => vec![2],
            (Kind::Dword, _) => vec![4],
            (Kind::Bytes, Operand::Bytes(b)) => vec![1, b.len()],
            (Kind::Bytes4A, Operand::Bytes(b)) => vec![4, crate::isa::padded4(b.len())],
            _ => vec![],
        };
        for w in widths {
            let end = (i + w).min(bytes.len());
            groups.push(hex(&bytes[i..end]));
            i = end;
        }
    }
    if i < bytes.len() {
        groups.push(hex(&bytes[i..]));
    }
    groups.retain(|g| !g.is_empty());
    groups.join(" ")
}

/// The hint for the data operand `k` of an instruction.
fn hint(inst: &Inst, k: usize) -> Hint {
    let o = inst.opcode;
    let count = |i: usize| match inst.operands.get(i) {
        Some(Operand::Imm(n)) => Hint::Size(*n),
        Some(Operand::Bytes(b)) => Hint::Size(b.len() as u32),
        _ => Hint::Any,
    };
    match o {
        op::CALB | op::CALF | op::CALBR if k == 0 => Hint::Instance,
        op::MCD | op::MCD4A => count(1),
        op::MEMCP | op::MEMCP4A => count(2),
        op::FPAT | op::FPAT4A => count(2),
        op::DPRDL | op::DPWRL if k == 0 => count(2),
        _ => Hint::Any,
    }
}

/// The mnemonic text of an instruction, with names from `names` in `scope`.
pub fn format_inst(inst: &Inst, mode: Mode, scope: &Scope, names: Option<&dyn Names>) -> String {
    let Some((name, kinds)) = crate::isa::shape(inst.opcode, mode) else {
        return format!("?{}", inst.opcode);
    };
    let a = mode.addr_bytes();
    let mut ops = Vec::new();
    for (k, (kind, o)) in kinds.iter().zip(&inst.operands).enumerate() {
        match (kind, o) {
            (Kind::Data, Operand::Data(x)) => {
                let n = names.and_then(|n| n.data_name(scope, *x, hint(inst, k)));
                ops.push(n.unwrap_or_else(|| format!("#{}", hex(&x.to_le_bytes()[..a]))));
            }
            (Kind::Code, Operand::Code(x)) => {
                let n = names.and_then(|n| n.label_name(*x));
                ops.push(match n {
                    Some(l) => format!(":{l}"),
                    None => format!(":{:0w$x}", x, w = 2 * a),
                });
            }
            (Kind::Byte, Operand::Imm(x)) => ops.push(format!("#{}", hex(&x.to_le_bytes()[..1]))),
            (Kind::Word, Operand::Imm(x)) => ops.push(format!("#{}", hex(&x.to_le_bytes()[..2]))),
            (Kind::Dword, Operand::Imm(x)) => ops.push(format!("#{}", hex(&x.to_le_bytes()))),
            (Kind::Bytes, Operand::Bytes(b)) => {
                ops.push(format!("#{:02X}", b.len() as u8));
                ops.push(format!("#{}", hex(b)));
            }
            (Kind::Bytes4A, Operand::Bytes(b)) => {
                let mut p = b.clone();
                p.resize(crate::isa::padded4(b.len()), crate::isa::MCD4A_PAD);
                ops.push(format!("#{}", hex(&(b.len() as u32).to_le_bytes())));
                ops.push(format!("#{}", hex(&p)));
            }
            _ => ops.push(format!("{o:?}")),
        }
    }
    if inst.opcode.group() == op::group::MMV {
        ops.push(format!("#{:02X}", inst.opcode.func()));
    }
    if ops.is_empty() {
        name.to_string()
    } else {
        format!("{name} {}", ops.join(", "))
    }
}

/// Decodes a whole code image, instruction after instruction from address 0.
pub fn decode_all(code: &[u8], mode: Mode) -> Result<Vec<(u32, Inst, usize)>, DecodeError> {
    let mut out = Vec::new();
    let mut at = 0usize;
    while at < code.len() {
        let a = u32::try_from(at).map_err(|_| DecodeError {
            at: u32::MAX,
            message: "image too large".into(),
        })?;
        let (inst, n) = Inst::decode(code, a, mode)?;
        out.push((a, inst, n));
        at += n;
    }
    Ok(out)
}

/// Decodes a whole code image into listing lines, with names where `names` knows them.
pub fn disassemble_lines(
    code: &[u8],
    mode: Mode,
    names: Option<&dyn Names>,
) -> Result<Vec<Line>, DecodeError> {
    let mut scope = Scope::Task;
    let mut out = Vec::new();
    for (addr, inst, n) in decode_all(code, mode)? {
        let labels = names.map(|n| n.labels_at(addr)).unwrap_or_default();
        for l in &labels {
            if let Some(s) = label_scope(l) {
                scope = s;
            }
        }
        let bytes = code[addr as usize..addr as usize + n].to_vec();
        out.push(Line {
            addr,
            labels,
            hex: hex_groups(&inst, &bytes, mode),
            text: format_inst(&inst, mode, &scope, names),
            inst,
            bytes,
            scope: scope.clone(),
        });
    }
    Ok(out)
}

/// One `MNEMONIC_MAP` line (or more, when the hex column is wrapped).
fn push_line(out: &mut String, addr: &str, hex: &str, text: &str) {
    let chars: Vec<char> = hex.chars().collect();
    let mut rest: &[char] = &chars;
    let mut text = text;
    loop {
        let (now, more) = if rest.len() > 33 {
            let mut s: String = rest[..32].iter().collect();
            s.push('…');
            (s, &rest[32..])
        } else {
            (rest.iter().collect(), &rest[rest.len()..])
        };
        let _ = writeln!(out, ":{addr}| {now:<33} | {text:<80}");
        rest = more;
        text = "";
        if rest.is_empty() {
            break;
        }
    }
}

/// The listing of a code image in the `MNEMONIC_MAP` format (see the module
/// documentation). Fails on bytes that do not decode, naming their address.
pub fn disassemble(
    code: &[u8],
    mode: Mode,
    names: Option<&dyn Names>,
) -> Result<String, DecodeError> {
    let w = 2 * mode.addr_bytes();
    let mut out = String::new();
    for l in disassemble_lines(code, mode, names)? {
        let a = format!("{:0w$x}", l.addr);
        for lab in &l.labels {
            push_line(&mut out, &a, "", &format!(":{lab}"));
        }
        push_line(&mut out, &a, &l.hex, &l.text);
    }
    let end = format!("{:0w$x}", code.len());
    for lab in names
        .map(|n| n.labels_at(code.len() as u32))
        .unwrap_or_default()
    {
        push_line(&mut out, &end, "", &format!(":{lab}"));
    }
    let _ = writeln!(out, ":{end} ");
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_without_names() {
        let code = [
            0x1C, 0x16, 0, 0, 0x10, 0, 0x1C, 0x15, 0x0C, 0, 4, 0xE8, 3, 0, 0, 0x1C, 0x13,
        ];
        let s = disassemble(&code, Mode::M16, None).unwrap();
        let lines: Vec<&str> = s.lines().map(str::trim_end).collect();
        assert_eq!(
            lines[0],
            ":0000| 1C16 0000 1000                    | $VMSYS.CALB #0000, :0010"
        );
        assert_eq!(
            lines[1],
            ":0006| 1C15 0C00 04 E8030000             | $VMSYS.MCD #0C00, #04, #E8030000"
        );
        assert_eq!(
            lines[2],
            ":000f| 1C13                              | $VMSYS.RETURN"
        );
        assert_eq!(lines[3], ":0011");
    }

    #[test]
    fn wraps_wide_hex_and_rejects_bad_bytes() {
        let code = [
            0x1C, 0x37, 0, 0, 0x50, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0xFF, 0xFF,
        ];
        let s = disassemble(&code, Mode::M32A, None).unwrap();
        let lines: Vec<&str> = s.lines().map(str::trim_end).collect();
        assert_eq!(lines[0], ":00000000| 1C370000 50000000 02000000 0000F… | $VMSYS.MCD4A #50000000, #02000000, #0000FFFF");
        assert_eq!(lines[1], ":00000000| FFF                               |");
        let e = disassemble(&[0x1C, 0x13, 0xEE, 0xEE], Mode::M16, None).unwrap_err();
        assert_eq!(e.at, 2);
        assert!(disassemble(&[0x1C, 0x15, 0, 0, 9, 1], Mode::M16, None).is_err());
        assert!(disassemble(&[0x1C], Mode::M16, None).is_err());
    }

    #[test]
    fn never_panics_on_junk() {
        let mut rng = plcc_ir::rng::Rng::new(1);
        for len in 0..400 {
            let code: Vec<u8> = (0..len)
                .map(|_| {
                    let x = rng.next_u64();
                    // Mostly valid groups so decoding goes deep.
                    if x.is_multiple_of(3) {
                        0x1C
                    } else {
                        (x >> 8) as u8 % 0x20
                    }
                })
                .collect();
            for mode in Mode::ALL {
                let _ = disassemble(&code, mode, None);
            }
        }
    }
}
