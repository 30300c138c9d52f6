//! The instructions the public CPDev C VMs execute, transcribed from
//! `../shared/reference/cpdev-vm-opcodes.md` (§1 sizes, §2 opcodes) independently of
//! the backend's own tables (`plcc_vmasm::isa`), so that a test can check every
//! instruction plcc emits against the reference rather than against plcc itself.

/// One operand of an instruction, as the reference's §1 writes its forms.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Opd {
    /// An address: 2 bytes in mode 16, 4 in modes 32 and 32A.
    A,
    /// A 1-byte immediate.
    B,
    /// A 2-byte immediate.
    W,
    /// A 4-byte immediate.
    D,
    /// MCD's payload: the count given by the preceding `B`.
    Bytes,
    /// MCD4A's payload: the count given by the preceding `A`, padded to 4.
    Bytes4,
}

/// The operands of `op` if some public C VM executes it (family A, all parts
/// compiled in), else `None`. Only what a compiler may emit is listed: the
/// "for FPGA" forms, DOW (broken outside mode 16) and the string group are left out.
pub fn operands(op: u16) -> Option<Vec<Opd>> {
    use Opd::*;
    let (g, f) = ((op >> 8) as u8, op as u8);
    let (n, t) = ((f >> 4) as usize, f & 0xF);
    let a = |k: usize| Some(vec![A; k]);
    match g {
        0x01 if n >= 1 && matches!(t, 1..=0xB) => a(n + 1),
        0x02 if n == 0 && matches!(t, 1..=0xB) => a(3),
        0x03 if n >= 1 && matches!(t, 1..=0xA) => a(n + 1),
        0x04 if n == 0 && matches!(t, 1..=0xA) => a(3),
        0x04 if n == 1 && matches!(t, 1..=8) => a(3),
        0x05 if n == 0 && matches!(t, 1 | 2 | 3 | 4 | 7 | 9) => a(2),
        0x05 if n == 1 && t <= 4 => a(2),
        0x06 if matches!(f, 0x01..=0x08) => a(3),
        0x06 if n == 1 && matches!(t, 1..=0xA) => a(2),
        0x06 if matches!(f, 0x20..=0x37) => a(2),
        0x07 => a(2),
        0x08 | 0x09 if n >= 1 && t <= 4 => a(n + 1),
        0x0A if n >= 1 && matches!(t, 0 | 1 | 2 | 4 | 5) => a(n + 1),
        0x0B if n <= 3 && matches!(t, 1..=4) => a(3),
        0x0C | 0x0D if n == 0 => a(4),
        0x0E | 0x0F if n == 0 => a(3),
        0x10..=0x15 if n == 0 => a(3),
        0x16 if n >= 1 => a(n + 1),
        0x19 if f <= 0x11 => a(2),
        0x1C => match f {
            0x00 | 0x03 | 0x17 | 0x1D | 0x20 | 0x22 | 0x2F | 0x30 | 0x31 | 0x32 => a(1),
            0x01 | 0x02 | 0x04 | 0x05 | 0x10 | 0x16 | 0x21 => a(2),
            0x13 | 0x18 => Some(vec![]),
            0x15 => Some(vec![A, B, Bytes]),
            0x1E | 0x26..=0x2E => a(3),
            0x1F => Some(vec![A, A, W]),
            0x23 => Some(vec![A, B, B]),
            0x24 | 0x25 | 0x34 | 0x35 => a(4),
            0x37 => Some(vec![A, A, Bytes4]),
            0x38 => Some(vec![A, W, W]),
            0x39 => Some(vec![A, A, D]),
            _ => None,
        },
        0x1E => match f {
            0x00 => a(1),
            0x01 | 0x02 | 0x05 => Some(vec![A, A, W]),
            0x03 | 0x04 => a(2),
            _ => None,
        },
        _ => None,
    }
}

/// Walks a code image of mode `mode` ("16", "32" or "32a") instruction by
/// instruction with the reference's forms. Returns each instruction's address and
/// opcode, or the first address whose opcode no C VM executes.
pub fn walk(code: &[u8], mode: &str) -> Result<Vec<(usize, u16)>, String> {
    let abytes = if mode == "16" { 2 } else { 4 };
    let opbytes = if mode == "32a" { 4 } else { 2 };
    let le = |b: &[u8]| b.iter().rev().fold(0usize, |x, &y| x << 8 | y as usize);
    let mut out = Vec::new();
    let mut pc = 0;
    while pc < code.len() {
        let at = pc;
        let Some(opb) = code.get(pc..pc + 2) else {
            return Err(format!("{at:#x}: a truncated opcode"));
        };
        let op = u16::from_be_bytes([opb[0], opb[1]]);
        let forms = operands(op)
            .ok_or_else(|| format!("{at:#x}: opcode {op:04X} is executed by no CPDev VM"))?;
        pc += opbytes;
        let mut count: usize = 0;
        for o in forms {
            let len = match o {
                Opd::A => abytes,
                Opd::B => 1,
                Opd::W => 2,
                Opd::D => 4,
                Opd::Bytes => count,
                Opd::Bytes4 => count.div_ceil(4) * 4,
            };
            let field = code
                .get(pc..pc + len)
                .ok_or_else(|| format!("{at:#x}: opcode {op:04X} runs past the image"))?;
            count = le(field);
            pc += len;
        }
        out.push((at, op));
    }
    Ok(out)
}
