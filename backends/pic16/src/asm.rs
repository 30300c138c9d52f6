//! Assembly code as the code generator produces it (instructions with symbolic code
//! labels), plcc's own assembler (to program words), and the MPASM text printer.

use crate::isa::{reg, Dest, Inst};
use std::fmt::Write;

/// A code label, an index into [`Program::labels`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Label(pub u32);

/// One instruction of generated code.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Op {
    /// An instruction whose file operands are full data addresses (not CALL/GOTO).
    I(Inst),
    /// `goto label`
    Goto(Label),
    /// `call label`
    Call(Label),
    /// Pseudo-instruction: the indirect bank bit must be this from here on. The bank
    /// pass turns it into `bcf/bsf STATUS,IRP`, or into nothing when IRP is known.
    Irp(bool),
    /// `goto label` as an entry of a jump table: reached by a computed jump (a write
    /// to PCL), so the code after it runs too, in the same bank state.
    TableGoto(Label),
    /// `movlw HIGH(label)` (`true`) or `movlw LOW(label)`: a byte of a code address.
    MovlwAddr(Label, bool),
}

/// An element of a code unit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Item {
    /// A code label.
    Label(Label),
    /// An instruction.
    Op(Op),
    /// A comment line (source lines, explanations).
    Comment(String),
}

/// A named sequence of code (a function, a runtime routine, a vector).
#[derive(Clone, Debug, Default)]
pub struct Unit {
    /// The unit's name, for comments.
    pub name: String,
    /// Fixed word address, if it must sit somewhere (the vectors).
    pub org: Option<u16>,
    /// Its code.
    pub items: Vec<Item>,
    /// The unit's frame (`start..end` in data memory) and the symbol its addresses
    /// are printed relative to.
    pub frame: Option<(u16, u16, String)>,
}

/// A named data address for the listing (`main_count EQU 0x21`).
#[derive(Clone, Debug)]
pub struct DataSymbol {
    /// Assembler name.
    pub name: String,
    /// Address.
    pub addr: u16,
    /// Bytes it covers.
    pub size: u16,
    /// For a BOOL, its bit.
    pub bit: Option<u8>,
    /// The comment after it (source path and type).
    pub comment: String,
}

/// A whole program.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Code units in address order.
    pub units: Vec<Unit>,
    /// Names of the labels.
    pub labels: Vec<String>,
    /// The configuration word.
    pub config: u16,
    /// Named data addresses.
    pub symbols: Vec<DataSymbol>,
    /// Lines for the header comment.
    pub header: Vec<String>,
}

/// The assembled program: words from address 0 and the label addresses.
#[derive(Clone, Debug)]
pub struct Image {
    /// Program memory from address 0 (unused words are 0x3FFF).
    pub words: Vec<u16>,
    /// Address of every label.
    pub label_addr: Vec<u16>,
    /// The configuration word.
    pub config: u16,
}

impl Image {
    /// The address of the label called `name`.
    pub fn label(&self, prog: &Program, name: &str) -> Option<u16> {
        prog.labels
            .iter()
            .position(|l| l == name)
            .map(|i| self.label_addr[i])
    }

    /// Words actually used (not counting the gap before the ISR).
    pub fn used_words(&self) -> u32 {
        self.words.iter().filter(|&&w| w != 0x3FFF).count() as u32
    }
}

/// Words of program memory on the chip.
pub const FLASH_WORDS: u32 = 8192;

/// Words of one program-memory page (the reach of CALL and GOTO).
pub const PAGE_WORDS: u32 = 2048;

impl Program {
    /// Adds a label name and returns its id.
    pub fn label(&mut self, name: impl Into<String>) -> Label {
        self.labels.push(name.into());
        Label(self.labels.len() as u32 - 1)
    }

    /// Places every unit and encodes every instruction. Fails if a unit would have
    /// to cross a 2K page (the code is placed so that it never needs PCLATH changes
    /// within one page; programs over one page are rejected by the caller before).
    pub fn assemble(&self) -> Result<Image, String> {
        let mut addr_of = vec![u16::MAX; self.labels.len()];
        let mut pc: u32 = 0;
        for u in &self.units {
            if let Some(o) = u.org {
                if (o as u32) < pc {
                    return Err(format!("unit {} overlaps the code before it", u.name));
                }
                pc = o as u32;
            }
            for it in &u.items {
                match it {
                    Item::Label(l) => addr_of[l.0 as usize] = pc as u16,
                    Item::Op(_) => pc += 1,
                    Item::Comment(_) => {}
                }
            }
        }
        if pc > FLASH_WORDS {
            return Err(format!(
                "the program needs {pc} words of program memory; the chip has {FLASH_WORDS} ({} too many)",
                pc - FLASH_WORDS
            ));
        }
        let mut words = vec![0x3FFFu16; pc as usize];
        let mut pc = 0usize;
        for u in &self.units {
            if let Some(o) = u.org {
                pc = o as usize;
            }
            for it in &u.items {
                if let Item::Op(op) = it {
                    let inst = match *op {
                        Op::I(i) => i,
                        Op::Goto(l) | Op::TableGoto(l) => Inst::Goto(addr_of[l.0 as usize]),
                        Op::MovlwAddr(l, high) => {
                            let a = addr_of[l.0 as usize];
                            Inst::Movlw(if high { (a >> 8) as u8 } else { a as u8 })
                        }
                        Op::Call(l) => Inst::Call(addr_of[l.0 as usize]),
                        Op::Irp(_) => return Err("IRP pseudo-instruction left in code".into()),
                    };
                    words[pc] = inst.encode();
                    pc += 1;
                }
            }
        }
        Ok(Image {
            words,
            label_addr: addr_of,
            config: self.config,
        })
    }

    /// Words of code the units take (gaps before fixed addresses not counted).
    fn unit_words(u: &Unit) -> u32 {
        u.items.iter().filter(|i| matches!(i, Item::Op(_))).count() as u32
    }

    /// Makes a program larger than one 2K page work: no unit crosses a page (a unit
    /// that would is moved to the next page), and a call to another page sets
    /// PCLATH<4:3> before the CALL and restores it to the caller's page after. Gotos
    /// stay inside their unit, so they never need PCLATH. Programs that fit one page
    /// are left alone.
    pub fn paginate(&mut self) -> Result<(), String> {
        let total: u32 = self.units.iter().map(Self::unit_words).sum::<u32>() + 4;
        if total <= PAGE_WORDS {
            return Ok(());
        }
        let original = self.units.clone();
        let mut far: std::collections::HashSet<(usize, usize)> = Default::default();
        for _round in 0..32 {
            // Lay out with the current far calls.
            let mut units = original.clone();
            // Where each unit's far calls are among its new items.
            let mut expanded: Vec<Vec<usize>> = vec![Vec::new(); units.len()];
            for (ui, u) in units.iter_mut().enumerate() {
                let mut items = Vec::with_capacity(u.items.len());
                for (ii, it) in std::mem::take(&mut u.items).into_iter().enumerate() {
                    if far.contains(&(ui, ii)) {
                        // Placeholders, fixed once the pages are known.
                        items.push(Item::Op(Op::I(Inst::Bcf(reg::PCLATH, 3))));
                        items.push(Item::Op(Op::I(Inst::Bcf(reg::PCLATH, 4))));
                        expanded[ui].push(items.len());
                        items.push(it);
                        items.push(Item::Op(Op::I(Inst::Bcf(reg::PCLATH, 3))));
                        items.push(Item::Op(Op::I(Inst::Bcf(reg::PCLATH, 4))));
                    } else {
                        items.push(it);
                    }
                }
                u.items = items;
            }
            // Place: a unit that would cross a page starts the next one.
            let mut pc: u32 = 0;
            let mut starts = Vec::with_capacity(units.len());
            for u in units.iter_mut() {
                if let Some(o) = u.org {
                    pc = o as u32;
                }
                let n = Self::unit_words(u);
                if n > PAGE_WORDS {
                    return Err(format!(
                        "{} takes {n} words, more than a 2048-word page",
                        u.name
                    ));
                }
                if pc / PAGE_WORDS != (pc + n.max(1) - 1) / PAGE_WORDS {
                    pc = (pc / PAGE_WORDS + 1) * PAGE_WORDS;
                    u.org = Some(pc as u16);
                }
                starts.push(pc);
                pc += n;
            }
            // Label addresses.
            let mut addr = vec![0u32; self.labels.len()];
            for (u, &st) in units.iter().zip(&starts) {
                let mut a = st;
                for it in &u.items {
                    match it {
                        Item::Label(l) => addr[l.0 as usize] = a,
                        Item::Op(_) => a += 1,
                        Item::Comment(_) => {}
                    }
                }
            }
            let mut grew = false;
            for (ui, u) in original.iter().enumerate() {
                let page = starts[ui] / PAGE_WORDS;
                for (ii, it) in u.items.iter().enumerate() {
                    if let Item::Op(Op::Call(l)) = it {
                        if addr[l.0 as usize] / PAGE_WORDS != page && far.insert((ui, ii)) {
                            grew = true;
                        }
                    }
                }
            }
            if !grew {
                // Fill in the PCLATH bits.
                for (ui, u) in units.iter_mut().enumerate() {
                    let own = starts[ui] / PAGE_WORDS;
                    // Only the calls expanded above: a near call right after a far
                    // one also follows a `bcf PCLATH,4`, but has no placeholders.
                    for &k in &expanded[ui] {
                        if let Item::Op(Op::Call(l)) = u.items[k] {
                            let to = addr[l.0 as usize] / PAGE_WORDS;
                            {
                                let set = |page: u32, bit: u8| {
                                    if page >> (bit - 3) & 1 != 0 {
                                        Item::Op(Op::I(Inst::Bsf(reg::PCLATH, bit)))
                                    } else {
                                        Item::Op(Op::I(Inst::Bcf(reg::PCLATH, bit)))
                                    }
                                };
                                u.items[k - 2] = set(to, 3);
                                u.items[k - 1] = set(to, 4);
                                u.items[k + 1] = set(own, 3);
                                u.items[k + 2] = set(own, 4);
                                if k >= 3 {
                                    if let Item::Op(Op::I(i)) = u.items[k - 3] {
                                        if i.is_skip() {
                                            return Err(format!(
                                                "{}: a far call follows a skip",
                                                u.name
                                            ));
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
                self.units = units;
                return Ok(());
            }
        }
        Err("the page layout does not settle".into())
    }

    /// The MPASM source: gpasm assembles it to the same words as [`Program::assemble`].
    pub fn mpasm(&self) -> String {
        let mut s = String::new();
        for h in &self.header {
            let _ = writeln!(s, "; {h}");
        }
        s.push_str("\n\tLIST\tP=16F876A, R=DEC\n\tERRORLEVEL\t-302\n");
        let _ = writeln!(s, "\t__CONFIG\t0x{:04X}\n", self.config);
        s.push_str("; core and peripheral registers\n");
        for (name, v) in SFR_NAMES {
            let _ = writeln!(s, "{name:<15} EQU 0x{v:02X}");
        }
        s.push_str("; bits and destinations\n");
        for (name, v) in BIT_NAMES {
            let _ = writeln!(s, "{name:<15} EQU {v}");
        }
        if !self.symbols.is_empty() {
            s.push_str("\n; data memory\n");
        }
        for d in &self.symbols {
            let _ = writeln!(s, "{:<15} EQU 0x{:03X}\t; {}", d.name, d.addr, d.comment);
        }
        let names = Names::new(self);
        for u in &self.units {
            let _ = writeln!(s, "\n; ---- {} ----", u.name);
            if let Some(o) = u.org {
                let _ = writeln!(s, "\tORG\t0x{o:03X}");
            }
            for it in &u.items {
                match it {
                    Item::Label(l) => {
                        let _ = writeln!(s, "{}", self.labels[l.0 as usize]);
                    }
                    Item::Comment(c) => {
                        let _ = writeln!(s, "\t; {c}");
                    }
                    Item::Op(op) => {
                        let _ = writeln!(s, "\t{}", names.op(self, u, *op));
                    }
                }
            }
        }
        s.push_str("\n\tEND\n");
        s
    }
}

/// Register names the listing defines (so it needs no include file).
const SFR_NAMES: &[(&str, u16)] = &[
    ("INDF", reg::INDF),
    ("TMR0", reg::TMR0),
    ("PCL", reg::PCL),
    ("STATUS", reg::STATUS),
    ("FSR", reg::FSR),
    ("PORTA", reg::PORTA),
    ("PORTB", reg::PORTB),
    ("PORTC", reg::PORTC),
    ("PCLATH", reg::PCLATH),
    ("INTCON", reg::INTCON),
    ("PIR1", reg::PIR1),
    ("TMR1L", reg::TMR1L),
    ("TMR1H", reg::TMR1H),
    ("T1CON", reg::T1CON),
    ("CCPR1L", reg::CCPR1L),
    ("CCPR1H", reg::CCPR1H),
    ("CCP1CON", reg::CCP1CON),
    ("OPTION_REG", reg::OPTION_REG),
    ("TRISA", reg::TRISA),
    ("TRISB", reg::TRISB),
    ("TRISC", reg::TRISC),
    ("PIE1", reg::PIE1),
    ("ADCON1", reg::ADCON1),
];

const BIT_NAMES: &[(&str, u8)] = &[
    ("W", 0),
    ("F", 1),
    ("C", reg::C),
    ("DC", reg::DC),
    ("Z", reg::Z),
    ("RP0", reg::RP0),
    ("RP1", reg::RP1),
    ("IRP", reg::IRP),
    ("GIE", reg::GIE),
    ("PEIE", reg::PEIE),
    ("CCP1IF", reg::CCP1IF),
    ("TMR1ON", reg::TMR1ON),
];

/// Every name the listing defines itself, which user symbols must not take.
pub fn reserved_names() -> impl Iterator<Item = &'static str> {
    SFR_NAMES
        .iter()
        .map(|(n, _)| *n)
        .chain(BIT_NAMES.iter().map(|(n, _)| *n))
}

/// Turns data addresses back into names for the listing.
struct Names {
    /// (start, end, name) of data symbols, sorted by start.
    data: Vec<(u16, u16, String)>,
    /// Frames of every unit, with the unit's entry label.
    frames: Vec<(u16, u16, String, Option<Label>)>,
}

impl Names {
    fn new(p: &Program) -> Names {
        let mut data: Vec<(u16, u16, String)> = p
            .symbols
            .iter()
            .map(|d| (d.addr, d.addr + d.size.max(1), d.name.clone()))
            .collect();
        data.sort_by_key(|d| (d.0, std::cmp::Reverse(d.1)));
        let frames = p
            .units
            .iter()
            .filter_map(|u| {
                let entry = u.items.iter().find_map(|it| match it {
                    Item::Label(l) => Some(*l),
                    _ => None,
                });
                u.frame.clone().map(|(s, e, n)| (s, e, n, entry))
            })
            .collect();
        Names { data, frames }
    }

    fn file(&self, p: &Program, u: &Unit, f: u16, bit: Option<u8>) -> String {
        let rel = |s: u16, name: &str| {
            if f == s {
                name.to_string()
            } else {
                format!("{name}+{}", f - s)
            }
        };
        if let Some(b) = bit {
            if let Some(d) = p.symbols.iter().find(|d| d.addr == f && d.bit == Some(b)) {
                return d.name.clone();
            }
        }
        if let Some((s, _, n)) = SFR_NAMES
            .iter()
            .find(|(_, a)| *a == f)
            .map(|(n, a)| (*a, 0, n))
        {
            return rel(s, n);
        }
        if let Some((s, end, n)) = &u.frame {
            if f >= *s && f < *end {
                return rel(*s, n);
            }
        }
        if let Some((s, _, n)) = self.data.iter().find(|(s, e, _)| f >= *s && f < *e) {
            return rel(*s, n);
        }
        // Frames overlap: the frame of a function this unit calls (its arguments and
        // result) before any other.
        let called = |l: &Label| {
            u.items
                .iter()
                .any(|it| matches!(it, Item::Op(Op::Call(c)) if c == l))
        };
        let frame = self
            .frames
            .iter()
            .filter(|(s, e, _, _)| f >= *s && f < *e)
            .min_by_key(|(_, _, _, entry)| !entry.as_ref().is_some_and(called));
        if let Some((s, _, n, _)) = frame {
            return rel(*s, n);
        }
        format!("0x{f:03X}")
    }

    fn op(&self, p: &Program, u: &Unit, op: Op) -> String {
        use Inst::*;
        let d = |d: Dest| if d == Dest::W { "W" } else { "F" };
        match op {
            Op::Goto(l) | Op::TableGoto(l) => format!("goto\t{}", p.labels[l.0 as usize]),
            Op::MovlwAddr(l, high) => format!(
                "movlw\t{}({})",
                if high { "HIGH" } else { "LOW" },
                p.labels[l.0 as usize]
            ),
            Op::Call(l) => format!("call\t{}", p.labels[l.0 as usize]),
            Op::Irp(b) => format!("; irp {b}"),
            Op::I(i) => {
                let fd = |m: &str, f: u16, x: Dest| {
                    format!("{m}\t{},{}", self.file(p, u, f, None), d(x))
                };
                let fb = |m: &str, f: u16, b: u8| {
                    let bitname = if f == reg::STATUS {
                        match b {
                            reg::C => "C".to_string(),
                            reg::Z => "Z".to_string(),
                            reg::DC => "DC".to_string(),
                            reg::RP0 => "RP0".to_string(),
                            reg::RP1 => "RP1".to_string(),
                            reg::IRP => "IRP".to_string(),
                            _ => b.to_string(),
                        }
                    } else {
                        b.to_string()
                    };
                    format!("{m}\t{},{bitname}", self.file(p, u, f, Some(b)))
                };
                let k = |m: &str, k: u8| format!("{m}\t0x{k:02X}");
                match i {
                    Addwf(f, x) => fd("addwf", f, x),
                    Andwf(f, x) => fd("andwf", f, x),
                    Clrf(f) => format!("clrf\t{}", self.file(p, u, f, None)),
                    Clrw => "clrw".into(),
                    Comf(f, x) => fd("comf", f, x),
                    Decf(f, x) => fd("decf", f, x),
                    Decfsz(f, x) => fd("decfsz", f, x),
                    Incf(f, x) => fd("incf", f, x),
                    Incfsz(f, x) => fd("incfsz", f, x),
                    Iorwf(f, x) => fd("iorwf", f, x),
                    Movf(f, x) => fd("movf", f, x),
                    Movwf(f) => format!("movwf\t{}", self.file(p, u, f, None)),
                    Nop => "nop".into(),
                    Rlf(f, x) => fd("rlf", f, x),
                    Rrf(f, x) => fd("rrf", f, x),
                    Subwf(f, x) => fd("subwf", f, x),
                    Swapf(f, x) => fd("swapf", f, x),
                    Xorwf(f, x) => fd("xorwf", f, x),
                    Bcf(f, b) => fb("bcf", f, b),
                    Bsf(f, b) => fb("bsf", f, b),
                    Btfsc(f, b) => fb("btfsc", f, b),
                    Btfss(f, b) => fb("btfss", f, b),
                    Addlw(x) => k("addlw", x),
                    Andlw(x) => k("andlw", x),
                    Call(a) => format!("call\t0x{a:03X}"),
                    Clrwdt => "clrwdt".into(),
                    Goto(a) => format!("goto\t0x{a:03X}"),
                    Iorlw(x) => k("iorlw", x),
                    Movlw(x) => k("movlw", x),
                    Retfie => "retfie".into(),
                    Retlw(x) => k("retlw", x),
                    Return => "return".into(),
                    Sleep => "sleep".into(),
                    Sublw(x) => k("sublw", x),
                    Xorlw(x) => k("xorlw", x),
                }
            }
        }
    }
}

/// Intel HEX (INHX32, as gpasm writes it) of an image, configuration word included.
pub fn intel_hex(img: &Image) -> String {
    let mut out = String::new();
    let mut rec = |addr: u32, kind: u8, data: &[u8]| {
        let mut sum: u32 = data.len() as u32 + (addr >> 8) + (addr & 0xFF) + kind as u32;
        let _ = write!(out, ":{:02X}{:04X}{:02X}", data.len(), addr & 0xFFFF, kind);
        for b in data {
            sum += *b as u32;
            let _ = write!(out, "{b:02X}");
        }
        let _ = writeln!(out, "{:02X}", (0x100 - (sum & 0xFF)) & 0xFF);
    };
    rec(0, 4, &[0, 0]);
    // Runs of used words, 8 words (16 bytes) a record; unused words are skipped.
    let mut i = 0;
    while i < img.words.len() {
        if img.words[i] == 0x3FFF {
            i += 1;
            continue;
        }
        let start = i;
        let mut bytes = Vec::new();
        while i < img.words.len() && img.words[i] != 0x3FFF && i - start < 8 {
            bytes.push((img.words[i] & 0xFF) as u8);
            bytes.push((img.words[i] >> 8) as u8);
            i += 1;
        }
        rec(start as u32 * 2, 0, &bytes);
    }
    rec(
        0x2007 * 2,
        0,
        &[(img.config & 0xFF) as u8, (img.config >> 8) as u8],
    );
    rec(0, 1, &[]);
    out
}

/// Reads the program words and the configuration word back from Intel HEX text.
pub fn parse_hex(text: &str) -> Result<(Vec<u16>, Option<u16>), String> {
    let mut upper = 0u32;
    let mut bytes: std::collections::BTreeMap<u32, u8> = Default::default();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let hex = line
            .strip_prefix(':')
            .ok_or_else(|| format!("line {}: no ':'", n + 1))?;
        let raw: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("line {}: {e}", n + 1))?;
        if raw.len() < 5 || raw.len() != raw[0] as usize + 5 {
            return Err(format!("line {}: bad length", n + 1));
        }
        if raw.iter().fold(0u8, |a, b| a.wrapping_add(*b)) != 0 {
            return Err(format!("line {}: bad checksum", n + 1));
        }
        let addr = (raw[1] as u32) << 8 | raw[2] as u32;
        let data = &raw[4..raw.len() - 1];
        match raw[3] {
            0 => {
                for (i, b) in data.iter().enumerate() {
                    bytes.insert(upper + addr + i as u32, *b);
                }
            }
            1 => break,
            4 => upper = ((data[0] as u32) << 8 | data[1] as u32) << 16,
            t => return Err(format!("line {}: record type {t}", n + 1)),
        }
    }
    let mut words = Vec::new();
    let mut config = None;
    for (&a, &b) in &bytes {
        let w = (a / 2) as usize;
        let shift = if a % 2 == 0 { 0 } else { 8 };
        if w == 0x2007 {
            let c = config.get_or_insert(0u16);
            *c |= (b as u16) << shift;
        } else if w < 0x2000 {
            if words.len() <= w {
                words.resize(w + 1, 0x3FFF);
            }
            if shift == 0 {
                words[w] = (words[w] & 0xFF00) | b as u16;
            } else {
                words[w] = (words[w] & 0x00FF) | (b as u16) << 8;
            }
        }
    }
    Ok((words, config))
}
