//! The PLC runtime around the compiled programs: reset and interrupt vectors, the
//! 1 ms clock (Timer1 with CCP1's special event trigger, 5000 instruction cycles at
//! 20 MHz), cold-start initialisation, and the scan loop, which latches the inputs,
//! runs every program, writes the outputs and passes the global label
//! `plc_scan_end` once per scan.
//!
//! Located BOOLs map to pins by default as `%IX0.0-7` = RB0-7, `%IX1.0-5` = RA0-5
//! (ADCON1 makes them digital) and `%QX0.0-7` = RC0-7; the `pin.%IX0.3=RA1` setting
//! overrides one. Other located variables are plain RAM.

use crate::asm::{Item, Label, Op, Unit};
use crate::isa::{reg, Dest, Inst};

/// Bit of the flags byte that is the PLC fault flag.
pub const FAULT_BIT: u8 = 0;

/// Instruction cycles per millisecond at 20 MHz.
pub const CYCLES_PER_MS: u16 = 5000;

/// Fixed runtime addresses.
#[derive(Copy, Clone, Debug, Default)]
pub struct Rt {
    /// Flags byte: bit 0 is the fault flag.
    pub flags: u16,
    /// Where the interrupt saves STATUS, PCLATH and FSR (3 bytes, bank 0).
    pub isr_save: u16,
    /// The running clock in ms (4 bytes), advanced by the interrupt.
    pub clk_ms: u16,
    /// The running clock in ns (8 bytes), if the program reads LTIME.
    pub clk_ns: Option<u16>,
    /// The clock sampled at scan start (4 bytes).
    pub now_ms: u16,
    /// The ns clock sampled at scan start (8 bytes).
    pub now_ns: u16,
    /// The program reads the clock: the 1 ms timer, its interrupt and the sampling
    /// at scan start are built. A program that never reads it gets none of them (the
    /// clock's RAM stays reserved, unused).
    pub ticks: bool,
}

/// Where the interrupt saves W: the one byte it must reach before it can select a
/// bank (common RAM); the rest of its context goes to bank 0.
pub const ISR_W: u16 = 0x70;

/// A port pin.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Pin {
    /// The port register (PORTA/B/C).
    pub port: u16,
    /// The bit.
    pub bit: u8,
}

impl Pin {
    /// Parses `RA0`…`RC7`.
    pub fn parse(s: &str) -> Option<Pin> {
        let s = s.trim().to_ascii_uppercase();
        let b = s.strip_prefix('R')?;
        let mut c = b.chars();
        let port = match c.next()? {
            'A' => reg::PORTA,
            'B' => reg::PORTB,
            'C' => reg::PORTC,
            _ => return None,
        };
        let bit: u8 = c.as_str().parse().ok()?;
        let max = if port == reg::PORTA { 5 } else { 7 };
        (bit <= max).then_some(Pin { port, bit })
    }

    /// `RB3`.
    pub fn name(self) -> String {
        let p = match self.port {
            reg::PORTA => 'A',
            reg::PORTB => 'B',
            _ => 'C',
        };
        format!("R{p}{}", self.bit)
    }
}

/// The default pin of a located address (`%IX0.3` → RB3), if it has one.
pub fn default_pin(loc: &str) -> Option<Pin> {
    let (input, byte, bit) = parse_bit_location(loc)?;
    match (input, byte) {
        (true, 0) => Some(Pin {
            port: reg::PORTB,
            bit,
        }),
        (true, 1) if bit <= 5 => Some(Pin {
            port: reg::PORTA,
            bit,
        }),
        (false, 0) => Some(Pin {
            port: reg::PORTC,
            bit,
        }),
        _ => None,
    }
}

/// `%IX1.2` → (input, 1, 2); `%QX0.7` → (output, 0, 7). Other forms give `None`.
pub fn parse_bit_location(loc: &str) -> Option<(bool, u32, u8)> {
    let l = loc.trim().to_ascii_uppercase();
    let rest = l.strip_prefix('%')?;
    let (input, rest) = match rest.as_bytes().first()? {
        b'I' => (true, &rest[1..]),
        b'Q' => (false, &rest[1..]),
        _ => return None,
    };
    let rest = rest.strip_prefix('X').unwrap_or(rest);
    let (a, b) = rest.split_once('.')?;
    let byte: u32 = a.parse().ok()?;
    let bit: u8 = b.parse().ok()?;
    (bit < 8).then_some((input, byte, bit))
}

/// A BOOL variable bound to a pin.
#[derive(Clone, Debug)]
pub struct PinBinding {
    /// The variable's source path.
    pub path: String,
    /// Its address and bit.
    pub addr: u16,
    /// Its bit.
    pub bit: u8,
    /// The pin.
    pub pin: Pin,
    /// True for an input (latched at scan start).
    pub input: bool,
}

/// What the runtime code needs to know about the program.
pub struct RuntimePlan<'a> {
    /// Runtime addresses.
    pub rt: Rt,
    /// `init_globals`, then every program's init, in order.
    pub inits: Vec<EntryCall>,
    /// Every program's body, in order.
    pub bodies: Vec<EntryCall>,
    /// Pins.
    pub pins: &'a [PinBinding],
}

/// A call the runtime makes (a program's init or body) and what it passes.
pub struct EntryCall {
    /// The function.
    pub label: Label,
    /// Bytes to store before the call (address, value): the instance's address in
    /// the callee's parameter, when the callee does not know it as a constant.
    pub stores: Vec<(u16, u8)>,
}

/// Labels the runtime defines.
pub struct RuntimeLabels {
    /// Start of cold-start code.
    pub start: Label,
    /// Top of the scan loop.
    pub scan: Label,
    /// End of a scan.
    pub scan_end: Label,
}

/// Creates the runtime's labels.
pub fn labels(labels: &mut Vec<String>) -> RuntimeLabels {
    let mut l = |n: &str| {
        labels.push(n.to_string());
        Label(labels.len() as u32 - 1)
    };
    RuntimeLabels {
        start: l("plc_start"),
        scan: l("plc_scan"),
        scan_end: l("plc_scan_end"),
    }
}

struct Code(Vec<Item>);

impl Code {
    fn i(&mut self, i: Inst) {
        self.0.push(Item::Op(Op::I(i)));
    }
    fn c(&mut self, s: &str) {
        self.0.push(Item::Comment(s.to_string()));
    }
    fn lit(&mut self, f: u16, k: u8) {
        if k == 0 {
            self.i(Inst::Clrf(f));
            return;
        }
        // W still holds k when the last two instructions were `movlw k; movwf _`.
        let mut last = self.0.iter().rev().filter_map(|it| match it {
            Item::Comment(_) => None,
            other => Some(other),
        });
        let held = matches!(
            (last.next(), last.next()),
            (Some(Item::Op(Op::I(Inst::Movwf(_)))), Some(Item::Op(Op::I(Inst::Movlw(w))))) if *w == k
        );
        if !held {
            self.i(Inst::Movlw(k));
        }
        self.i(Inst::Movwf(f));
    }
    /// Stores what the callee is passed, then calls it.
    fn entry_call(&mut self, e: &EntryCall) {
        for &(a, k) in &e.stores {
            self.lit(a, k);
        }
        self.0.push(Item::Op(Op::Call(e.label)));
    }
    /// `d += 1` over n bytes: each byte after the first is incremented when the one
    /// below it wrapped to zero.
    fn increment(&mut self, d: u16, n: u16) {
        self.i(Inst::Incf(d, Dest::F));
        for i in 1..n {
            self.i(Inst::Btfsc(reg::STATUS, reg::Z));
            self.i(Inst::Incf(d + i, Dest::F));
        }
    }
    /// `d += k` over n bytes of a constant (carry chained).
    fn add_const(&mut self, d: u16, k: u64, n: u16) {
        for i in 0..n {
            let b = (k >> (8 * i)) as u8;
            if i == 0 {
                self.i(Inst::Movlw(b));
                self.i(Inst::Addwf(d, Dest::F));
            } else if b == 0xFF {
                self.i(Inst::Movlw(0xFF));
                self.i(Inst::Btfss(reg::STATUS, reg::C));
                self.i(Inst::Addwf(d + i, Dest::F));
            } else {
                self.i(Inst::Movlw(b));
                self.i(Inst::Btfsc(reg::STATUS, reg::C));
                self.i(Inst::Movlw(b + 1));
                self.i(Inst::Addwf(d + i, Dest::F));
            }
        }
    }
    /// Copies one bit through Z (works across banks, and never glitches the target).
    fn bit_copy(&mut self, from: (u16, u8), to: (u16, u8)) {
        self.i(Inst::Movf(from.0, Dest::W));
        self.i(Inst::Andlw(1 << from.1));
        self.i(Inst::Btfsc(reg::STATUS, reg::Z));
        self.i(Inst::Bcf(to.0, to.1));
        self.i(Inst::Btfss(reg::STATUS, reg::Z));
        self.i(Inst::Bsf(to.0, to.1));
    }
}

/// The reset vector (at 0).
pub fn reset_unit(l: &RuntimeLabels) -> Unit {
    Unit {
        name: "reset vector".into(),
        org: Some(0),
        items: vec![
            Item::Op(Op::I(Inst::Clrf(reg::PCLATH))),
            Item::Op(Op::Goto(l.start)),
        ],
        frame: None,
    }
}

/// The interrupt service routine (at 4): counts milliseconds.
pub fn isr_unit(rt: &Rt, labels: &mut Vec<String>) -> Unit {
    labels.push("plc_isr_out".into());
    let out = Label(labels.len() as u32 - 1);
    let mut c = Code(Vec::new());
    c.c("save W, STATUS, PCLATH, FSR; select bank 0");
    let (isr_status, isr_pclath, isr_fsr) = (rt.isr_save, rt.isr_save + 1, rt.isr_save + 2);
    c.i(Inst::Movwf(ISR_W));
    c.i(Inst::Swapf(reg::STATUS, Dest::W));
    c.i(Inst::Clrf(reg::STATUS));
    c.i(Inst::Movwf(isr_status));
    c.i(Inst::Movf(reg::PCLATH, Dest::W));
    c.i(Inst::Movwf(isr_pclath));
    c.i(Inst::Clrf(reg::PCLATH));
    c.i(Inst::Movf(reg::FSR, Dest::W));
    c.i(Inst::Movwf(isr_fsr));
    c.i(Inst::Btfss(reg::PIR1, reg::CCP1IF));
    c.0.push(Item::Op(Op::Goto(out)));
    c.i(Inst::Bcf(reg::PIR1, reg::CCP1IF));
    c.c("one more millisecond");
    c.increment(rt.clk_ms, 4);
    if let Some(ns) = rt.clk_ns {
        c.add_const(ns, 1_000_000, 8);
    }
    c.0.push(Item::Label(out));
    c.i(Inst::Movf(isr_fsr, Dest::W));
    c.i(Inst::Movwf(reg::FSR));
    c.i(Inst::Movf(isr_pclath, Dest::W));
    c.i(Inst::Movwf(reg::PCLATH));
    c.i(Inst::Swapf(isr_status, Dest::W));
    c.i(Inst::Movwf(reg::STATUS));
    c.i(Inst::Swapf(ISR_W, Dest::F));
    c.i(Inst::Swapf(ISR_W, Dest::W));
    c.i(Inst::Retfie);
    Unit {
        name: "interrupt: 1 ms clock".into(),
        org: Some(4),
        items: c.0,
        frame: None,
    }
}

/// The cold start's part for the clock's timer: Timer1 and CCP1 set up (interrupts
/// are enabled after the programs' initialisation).
fn start_timer(c: &mut Code) {
    c.c("1 ms tick: Timer1 at Fosc/4, CCP1 special event every 5000 cycles");
    c.i(Inst::Clrf(reg::TMR1L));
    c.i(Inst::Clrf(reg::TMR1H));
    c.lit(reg::CCPR1L, (CYCLES_PER_MS & 0xFF) as u8);
    c.lit(reg::CCPR1H, (CYCLES_PER_MS >> 8) as u8);
    c.lit(reg::CCP1CON, 0x0B);
    c.i(Inst::Bcf(reg::PIR1, reg::CCP1IF));
    c.i(Inst::Bsf(reg::PIE1, reg::CCP1IF));
    c.lit(reg::T1CON, 0x01);
}

/// The clock cleared at cold start.
fn clear_clock(c: &mut Code, rt: &Rt) {
    for k in 0..4 {
        c.i(Inst::Clrf(rt.clk_ms + k));
    }
    if let Some(ns) = rt.clk_ns {
        for k in 0..8 {
            c.i(Inst::Clrf(ns + k));
        }
    }
}

/// The scan's start: the clock copied with interrupts off, so that TIME and the
/// timers see one value per scan.
fn sample_clock(c: &mut Code, rt: &Rt) {
    c.c("sample the clock");
    c.i(Inst::Bcf(reg::INTCON, reg::GIE));
    for k in 0..4 {
        c.i(Inst::Movf(rt.clk_ms + k, Dest::W));
        c.i(Inst::Movwf(rt.now_ms + k));
    }
    if let Some(ns) = rt.clk_ns {
        for k in 0..8 {
            c.i(Inst::Movf(ns + k, Dest::W));
            c.i(Inst::Movwf(rt.now_ns + k));
        }
    }
    c.i(Inst::Bsf(reg::INTCON, reg::GIE));
}

/// Cold start and the scan loop (the clock's parts only when `rt.ticks`).
pub fn main_unit(plan: &RuntimePlan, l: &RuntimeLabels) -> Unit {
    let rt = plan.rt;
    let mut c = Code(Vec::new());
    c.0.push(Item::Label(l.start));
    c.c("ports: inputs, outputs off, PORTA digital");
    c.i(Inst::Clrf(reg::STATUS));
    c.i(Inst::Clrf(reg::PORTA));
    c.i(Inst::Clrf(reg::PORTB));
    c.i(Inst::Clrf(reg::PORTC));
    c.lit(reg::ADCON1, 0x06);
    let mut tris = [0xFFu8; 3];
    for p in plan.pins.iter().filter(|p| !p.input) {
        let k = (p.pin.port - reg::PORTA) as usize;
        tris[k] &= !(1 << p.pin.bit);
    }
    c.lit(reg::TRISA, tris[0] & 0x3F);
    c.lit(reg::TRISB, tris[1]);
    c.lit(reg::TRISC, tris[2]);
    if rt.ticks {
        start_timer(&mut c);
        c.c("clock, flags and every variable");
    } else {
        c.c("no clock (the program never reads it): flags and every variable");
    }
    c.i(Inst::Clrf(rt.flags));
    if rt.ticks {
        clear_clock(&mut c, &rt);
    }
    for i in &plan.inits {
        c.entry_call(i);
    }
    if rt.ticks {
        c.i(Inst::Bsf(reg::INTCON, reg::PEIE));
        c.i(Inst::Bsf(reg::INTCON, reg::GIE));
    }
    c.0.push(Item::Label(l.scan));
    if rt.ticks {
        sample_clock(&mut c, &rt);
    }
    let inputs: Vec<&PinBinding> = plan.pins.iter().filter(|p| p.input).collect();
    if !inputs.is_empty() {
        c.c("latch the inputs");
    }
    for p in inputs {
        c.c(&format!("{} <- {}", p.path, p.pin.name()));
        c.bit_copy((p.pin.port, p.pin.bit), (p.addr, p.bit));
    }
    for b in &plan.bodies {
        c.entry_call(b);
    }
    let outputs: Vec<&PinBinding> = plan.pins.iter().filter(|p| !p.input).collect();
    if !outputs.is_empty() {
        c.c("write the outputs");
    }
    for p in outputs {
        c.c(&format!("{} -> {}", p.path, p.pin.name()));
        c.bit_copy((p.addr, p.bit), (p.pin.port, p.pin.bit));
    }
    c.0.push(Item::Label(l.scan_end));
    c.0.push(Item::Op(Op::Goto(l.scan)));
    Unit {
        name: "cold start and scan loop".into(),
        org: None,
        items: c.0,
        frame: None,
    }
}

/// Common-RAM addresses the runtime reserves, with their names, sizes and comments
/// for the listing. The rest of common RAM (`COMMON_FREE`) takes hot frames.
pub fn common_symbols() -> Vec<(&'static str, u16, u16, &'static str)> {
    vec![
        ("plc_isr_w", ISR_W, 1, "interrupt: saved W"),
        (
            "plc_t",
            crate::isel::SCRATCH[0],
            crate::isel::SCRATCH.len() as u16,
            "scratch of the generated code",
        ),
    ]
}

/// Common RAM left for the frames of hot functions.
pub const COMMON_FREE: (u16, u16) = (0x77, 0x80);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_pins() {
        assert_eq!(
            default_pin("%IX0.3"),
            Some(Pin {
                port: reg::PORTB,
                bit: 3
            })
        );
        assert_eq!(
            default_pin("%IX1.5"),
            Some(Pin {
                port: reg::PORTA,
                bit: 5
            })
        );
        assert_eq!(default_pin("%IX1.6"), None);
        assert_eq!(
            default_pin("%QX0.7"),
            Some(Pin {
                port: reg::PORTC,
                bit: 7
            })
        );
        assert_eq!(default_pin("%QW1"), None);
        assert_eq!(default_pin("%MX0.1"), None);
        assert_eq!(Pin::parse("ra5").map(|p| p.name()), Some("RA5".into()));
        assert_eq!(Pin::parse("RA6"), None);
    }
}
