//! A cycle-counting simulator of the PIC16F876A: the 14-bit core with its 35
//! instructions, banked data memory, the 8-level hardware stack, PORTA/B/C with TRIS
//! and ADCON1, Timer0, Timer1 with CCP1 compare (special event trigger), and
//! interrupts.
//!
//! Program memory is decoded once per bank into tables of compact ops (STATUS<RP1:RP0>
//! selects the table), so that direct file operands name their storage at decode time
//! and only special registers take an out-of-line path; frequent pairs of consecutive
//! instructions are fused into one op (its second instruction runs only if no check is
//! due in between). The run loop dispatches on the decoded kind and never ticks the
//! timers per instruction: each timer keeps the cycle it was last synchronised at and
//! its value then, and the cycle of its next event (overflow, compare match) is
//! computed in advance. The loop only leaves its fast path when the cycle counter
//! reaches the next event, the cycle budget, or after a write to a register that can
//! change an event or an interrupt condition.
//!
//! Timing follows gpsim 0.31 (checked cycle by cycle, see `tests/sim_against_gpsim.rs`):
//! - An instruction that starts at cycle `c` reads the timers' values at `c`; a write
//!   to TMR1L/TMR1H or T1CON at `c` restarts the Timer1 prescaler at `c`, so the next
//!   increment is at `c + prescale`. A write to TMR0 inhibits its increments for two
//!   cycles: the prescaler restarts at `c + 2`, so the next increment is at
//!   `c + 2 + prescale`.
//! - TMR1 rolling over to 0 (visible at cycle `o`) sets TMR1IF at `o + 1`. A compare
//!   match (TMR1 counting up to CCPR1, visible for one cycle at `m`) sets CCP1IF at
//!   `m + 1`; in mode `1011` TMR1 is cleared at `m`, so the period is CCPR1 × prescale
//!   cycles. TMR0 rolling over sets T0IF in the same cycle, but it can interrupt only
//!   from the next cycle on.
//! - Interrupts are taken at an instruction boundary `b` when GIE and an enabled flag
//!   are set: the PC is pushed, GIE cleared and execution goes on at 0x0004. Entry
//!   costs 1 cycle, or 0 cycles if the condition became true during the second cycle
//!   of the instruction that just finished (gpsim takes the interrupt in that cycle):
//!   so an interrupt raised by a 1-cycle instruction at `c` runs its first ISR
//!   instruction at `c + 2`, and a RETFIE with a flag still pending re-enters the ISR
//!   right after its own 2 cycles. (Real silicon takes 3–4 cycles from flag to vector;
//!   gpsim's model is used so that cycle counts can be compared with it.)
//!
//! Where gpsim 0.31 departs from the data sheet, the simulator follows the data sheet:
//! `CLRF STATUS` keeps C and DC (gpsim clears them); a TMR1H write keeps TMR1L and
//! clears the prescaler (gpsim, with a prescaler, moves TMR1L back); an OPTION_REG write
//! lets Timer0 go on counting (gpsim pauses it until TMR0 is written).
//!
//! Not modelled: the watchdog (the configuration word is not loaded), SLEEP (an error),
//! external clocks of Timer0/Timer1 (T0CKI, T1OSC: the timers then stand still), Timer2,
//! the CCP pins and PWM, CCP2, the A/D converter, comparators, the USART and MSSP, data
//! EEPROM (its registers are plain storage), and PORTB interrupt-on-change (RB0/INT
//! edges do set INTF). Those registers read back what was written.

use crate::isa::{Dest, Inst};
use decode::{Kind, Op};
use std::fmt;

mod decode;
mod exec;
mod hex;
#[cfg(test)]
mod tests;

/// Words of program memory.
const PROG_WORDS: usize = 0x2000;
/// Bytes of the data address space (4 banks of 128).
const RAM_SIZE: usize = 0x200;
/// Map entries at or above this are special registers (`SPECIAL + canonical address`).
const SPECIAL: u16 = 0x200;

// Canonical addresses of the registers the simulator models.
const INDF: u16 = 0x00;
const TMR0: u16 = 0x01;
const PCL: u16 = 0x02;
const STATUS: u16 = 0x03;
const FSR: usize = 0x04;
const PORTA: u16 = 0x05;
const PORTB: u16 = 0x06;
const PORTC: u16 = 0x07;
const PCLATH: u16 = 0x0A;
const INTCON: u16 = 0x0B;
const PIR1: u16 = 0x0C;
const PIR2: u16 = 0x0D;
const TMR1L: u16 = 0x0E;
const TMR1H: u16 = 0x0F;
const T1CON: u16 = 0x10;
const CCPR1L: u16 = 0x15;
const CCPR1H: u16 = 0x16;
const CCP1CON: u16 = 0x17;
const OPTION_REG: u16 = 0x81;
const TRISA: u16 = 0x85;
const TRISB: u16 = 0x86;
const TRISC: u16 = 0x87;
const PIE1: u16 = 0x8C;
const PIE2: u16 = 0x8D;
const ADCON1: u16 = 0x9F;
/// Storage slot (a mirror address, never canonical) that unimplemented addresses read.
const ZERO_SLOT: u16 = 0xF0;
/// Storage slot that writes to unimplemented addresses go to.
const SINK_SLOT: u16 = 0xF1;

/// STATUS bits.
const C: u8 = 0x01;
const DC: u8 = 0x02;
const Z: u8 = 0x04;

/// General-purpose RAM ranges (inclusive), 0x70–0x7F being the common bytes.
const GPR: [(u16, u16); 4] = [(0x20, 0x7F), (0xA0, 0xEF), (0x110, 0x16F), (0x190, 0x1EF)];

/// The canonical address of `a` (mirrors resolved), or `None` if unimplemented.
const fn canonical(a: u16) -> Option<u16> {
    let low = a & 0x7F;
    let bank = (a >> 7) & 3;
    if matches!(low, 0x00 | 0x02 | 0x03 | 0x04 | 0x0A | 0x0B) || low >= 0x70 {
        return Some(low);
    }
    if low >= 0x20 {
        return Some(a);
    }
    match bank {
        0 => match low {
            0x08 | 0x09 => None,
            _ => Some(a),
        },
        1 => match low {
            0x08 | 0x09 | 0x0F | 0x10 | 0x15 | 0x16 | 0x17 | 0x1A | 0x1B => None,
            _ => Some(a),
        },
        2 => match low {
            0x01 => Some(TMR0),
            0x06 => Some(PORTB),
            0x0C..=0x1F => Some(a),
            _ => None,
        },
        _ => match low {
            0x01 => Some(OPTION_REG),
            0x06 => Some(TRISB),
            0x0C | 0x0D | 0x10..=0x1F => Some(a),
            _ => None,
        },
    }
}

const fn special_read(c: u16) -> bool {
    matches!(
        c,
        INDF | TMR0 | PCL | STATUS | PORTA | PORTB | PORTC | TMR1L | TMR1H
    )
}

const fn special_write(c: u16) -> bool {
    matches!(
        c,
        INDF | TMR0
            | PCL
            | STATUS
            | PCLATH
            | INTCON
            | PIR1
            | PIR2
            | TMR1L
            | TMR1H
            | T1CON
            | CCPR1L
            | CCPR1H
            | CCP1CON
            | OPTION_REG
            | TRISA
            | PIE1
            | PIE2
    )
}

const fn build_map(write: bool) -> [u16; RAM_SIZE] {
    let mut m = [0u16; RAM_SIZE];
    let mut a = 0;
    while a < RAM_SIZE {
        m[a] = match canonical(a as u16) {
            None => {
                if write {
                    SINK_SLOT
                } else {
                    ZERO_SLOT
                }
            }
            Some(c) => {
                let special = if write {
                    special_write(c)
                } else {
                    special_read(c)
                };
                if special {
                    SPECIAL + c
                } else {
                    c
                }
            }
        };
        a += 1;
    }
    m
}

/// Data address → storage index (or `SPECIAL + canonical`) for reads.
static RMAP: [u16; RAM_SIZE] = build_map(false);
/// Data address → storage index (or `SPECIAL + canonical`) for writes.
static WMAP: [u16; RAM_SIZE] = build_map(true);

/// SFR power-on values that are not zero (data sheet table 2-1; `x` bits read as 0).
const POR_VALUES: [(u16, u8); 8] = [
    (STATUS, 0x18),
    (OPTION_REG, 0xFF),
    (TRISA, 0x3F),
    (TRISB, 0xFF),
    (TRISC, 0xFF),
    (0x92, 0xFF), // PR2
    (0x98, 0x02), // TXSTA
    (0x9C, 0x07), // CMCON
];

/// RA pins (bit mask) that ADCON1's PCFG<3:0> makes analog (they read 0).
const fn analog_mask(adcon1: u8) -> u8 {
    match adcon1 & 0x0F {
        0..=3 | 8..=12 => 0x2F,
        4 | 5 => 0x0B,
        6 | 7 => 0x00,
        13 => 0x0F,
        14 => 0x01,
        _ => 0x0D,
    }
}

/// A simulation error: a program did something the PLC runtime never should (or the
/// input was malformed).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimError(pub String);

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SimError {}

/// Why [`Pic16::run_until`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The PC reached this stop address (the instruction there is not executed yet).
    Breakpoint(u16),
    /// The cycle budget is used up.
    CycleLimit,
}

/// An I/O port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Port {
    /// PORTA, RA0–RA5 (analog at power-on, see ADCON1).
    A,
    /// PORTB, RB0–RB7 (RB0 is the INT pin).
    B,
    /// PORTC, RC0–RC7.
    C,
}

/// The registers the run loop keeps in machine registers.
#[derive(Debug, Clone, Copy, Default)]
struct Hot {
    /// Address of the next instruction (13 bits).
    pc: usize,
    /// The decoded table of the current bank: `PROG_WORDS` × STATUS<RP1:RP0>.
    table: usize,
    cycles: u64,
    w: u8,
    /// STATUS but for Z (its Z bit is stale).
    st: u8,
    /// Z is set when this is 0: the result of the last instruction that set Z.
    zv: u8,
}

impl Hot {
    /// STATUS.
    #[inline(always)]
    fn status(&self) -> u8 {
        (self.st & !Z) | u8::from(self.zv == 0) << 2
    }

    /// Sets STATUS (and the bank).
    #[inline(always)]
    fn set_status(&mut self, v: u8) {
        self.zv = u8::from(v & Z == 0);
        self.set_st(v);
    }

    /// Sets STATUS but for Z (and the bank).
    #[inline(always)]
    fn set_st(&mut self, v: u8) {
        self.st = v;
        self.table = usize::from(v >> 5 & 3) * PROG_WORDS;
    }

    /// The full data address of direct file operand `f` (bank from RP1:RP0).
    #[inline(always)]
    fn addr(&self, f: u16) -> usize {
        usize::from(self.st & 0x60) << 2 | usize::from(f & 0x7F)
    }

    #[inline(always)]
    fn set_c(&mut self, c: u8) {
        self.st = (self.st & !C) | c;
    }

    /// `a + b` with C, DC and Z.
    #[inline(always)]
    fn add(&mut self, a: u8, b: u8) -> u8 {
        let s = u16::from(a) + u16::from(b);
        let r = s as u8;
        self.st = (self.st & !(C | DC)) | (s >> 8) as u8 | ((a ^ b ^ r) & 0x10) >> 3;
        self.zv = r;
        r
    }

    /// `a - b` with C = no borrow, DC = no borrow from the low nibble, Z.
    #[inline(always)]
    fn sub(&mut self, a: u8, b: u8) -> u8 {
        let nb = !b;
        let s = u16::from(a) + u16::from(nb) + 1;
        let r = s as u8;
        self.st = (self.st & !(C | DC)) | (s >> 8) as u8 | ((a ^ nb ^ r) & 0x10) >> 3;
        self.zv = r;
        r
    }
}

/// Entries of the decoded program: one table of `PROG_WORDS` per bank.
const TABLE: usize = 4 * PROG_WORDS;

/// The simulated chip. Construct with [`Pic16::new`], then [`run_until`](Pic16::run_until)
/// or [`step`](Pic16::step); inspect and poke with [`read`](Pic16::read) and
/// [`write`](Pic16::write).
#[derive(Clone)]
pub struct Pic16 {
    /// Decoded program memory, one table per bank (see [`Kind`]); consecutive plain
    /// instructions are fused into one op where [`Op::fuse`] can.
    prog: Box<[Op; TABLE]>,
    /// The program words (program memory beyond them reads 0x3FFF).
    words: Box<[u16]>,
    /// Table entries replaced during `run_until` (by `Kind::Break`, or a fused op
    /// before a stop address by its single op), with the op to restore.
    saved: Vec<(usize, Op)>,
    c: Core,
}

/// Everything but program memory, so that the run loop can hold both apart.
#[derive(Clone)]
struct Core {
    h: Hot,
    /// Run loop: leave the fast path when `cycles >= next` (0 in `step`, so that a
    /// fused pair executes one instruction there).
    next: u64,
    /// Storage by canonical address (plus the zero and sink slots).
    ram: [u8; RAM_SIZE],
    stack: [u16; 8],
    sp: u8,
    max_sp: u8,
    /// External levels of the port pins (A, B, C).
    inputs: [u8; 3],
    /// Cycle budget of the current `run_until`.
    limit: u64,
    /// Cycle at which the last change to an interrupt condition became visible.
    irq_change_at: u64,
    /// No interrupt is taken before this cycle (a Timer0 overflow raises T0IF at
    /// once but, as in gpsim, interrupts one cycle later).
    irq_hold: u64,
    /// Timer1: value `t1_base` at tick boundary `t1_origin`.
    t1_origin: u64,
    t1_base: u16,
    /// Cycle at which TMR1IF becomes visible (`u64::MAX`: none).
    t1_ovf_at: u64,
    /// Cycle at which CCP1IF becomes visible (`u64::MAX`: none).
    t1_cmp_at: u64,
    /// Timer0: value `t0_base` at `t0_origin` (which can lie ahead: write inhibit).
    t0_origin: u64,
    t0_base: u8,
    /// Cycle at which T0IF becomes visible (`u64::MAX`: none).
    t0_ovf_at: u64,
}

impl fmt::Debug for Pic16 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Pic16")
            .field("pc", &format_args!("{:#06x}", self.c.h.pc))
            .field("w", &format_args!("{:#04x}", self.c.h.w))
            .field("status", &format_args!("{:#04x}", self.c.h.status()))
            .field("cycles", &self.c.h.cycles)
            .field("stack_depth", &self.c.sp)
            .finish_non_exhaustive()
    }
}

#[cold]
#[inline(never)]
fn invalid(word: u16, at: usize) -> SimError {
    err_at(&format!("invalid instruction word 0x{word:04X}"), at)
}

#[cold]
#[inline(never)]
fn err_at(what: &str, at: usize) -> SimError {
    SimError(format!("{what} at 0x{at:04X}"))
}

/// The bank offset (0, 0x80, 0x100, 0x180) of decoded table entry `i`.
fn table_bank(i: usize) -> u16 {
    (i / PROG_WORDS) as u16 * 0x80
}

impl Pic16 {
    /// A chip programmed with `program` (words from address 0; the rest of program
    /// memory reads 0x3FFF), after a power-on reset, with all RAM zero (as in gpsim).
    ///
    /// # Panics
    /// If `program` has more than 8192 words.
    pub fn new(program: &[u16]) -> Pic16 {
        assert!(
            program.len() <= PROG_WORDS,
            "program has {} words; program memory holds {PROG_WORDS}",
            program.len()
        );
        let mut prog: Box<[Op; TABLE]> = vec![Op::decode(0x3FFF, 0); TABLE]
            .into_boxed_slice()
            .try_into()
            .expect("decoded program size");
        for (t, table) in prog.chunks_exact_mut(PROG_WORDS).enumerate() {
            let bank = t as u16 * 0x80;
            for (o, &w) in table.iter_mut().zip(program) {
                *o = Op::decode(w, bank);
            }
            // table[i + 1] is still single when table[i] is fused
            for i in 1..program.len() {
                if let Some(op) = table[i - 1].fuse(table[i]) {
                    table[i - 1] = op;
                }
            }
        }
        let mut p = Pic16 {
            prog,
            words: program.into(),
            saved: Vec::new(),
            c: Core {
                h: Hot::default(),
                next: 0,
                ram: [0; RAM_SIZE],
                stack: [0; 8],
                sp: 0,
                max_sp: 0,
                inputs: [0; 3],
                limit: u64::MAX,
                irq_change_at: 0,
                irq_hold: 0,
                t1_origin: 0,
                t1_base: 0,
                t1_ovf_at: u64::MAX,
                t1_cmp_at: u64::MAX,
                t0_origin: 0,
                t0_base: 0,
                t0_ovf_at: u64::MAX,
            },
        };
        p.reset();
        p
    }

    /// Parses an Intel HEX file (INHX8M/INHX32 as gpasm writes it: byte address = 2 ×
    /// word address, low byte first) into program words 0..=highest used, gaps 0x3FFF.
    /// The configuration word (byte 0x400E), user IDs and EEPROM data are skipped. Bad
    /// records (syntax, length, checksum, type) and a missing end record are errors.
    pub fn load_hex(text: &str) -> Result<Vec<u16>, SimError> {
        hex::parse(text)
    }

    /// Power-on reset: SFRs get their POR values (data sheet table 2-1, unknown bits 0),
    /// PC = 0, W = 0, the stack is emptied, the cycle counter and the maximum stack depth
    /// are cleared. General-purpose RAM and the external pin levels are kept.
    pub fn reset(&mut self) {
        self.c.reset();
    }

    /// Sets every general-purpose RAM byte (0x20–0x7F, 0xA0–0xEF, 0x110–0x16F,
    /// 0x190–0x1EF) to `byte`, e.g. to catch reads of uninitialised variables.
    pub fn fill_ram(&mut self, byte: u8) {
        for (lo, hi) in GPR {
            self.c.ram[lo as usize..=hi as usize].fill(byte);
        }
    }

    /// The address of the next instruction.
    pub fn pc(&self) -> u16 {
        self.c.h.pc as u16
    }

    /// Sets the PC (13 bits), e.g. to call a routine from the host.
    pub fn set_pc(&mut self, pc: u16) {
        self.c.h.pc = usize::from(pc & 0x1FFF);
    }

    /// The W register.
    pub fn w(&self) -> u8 {
        self.c.h.w
    }

    /// Sets the W register.
    pub fn set_w(&mut self, w: u8) {
        self.c.h.w = w;
    }

    /// Instruction cycles since reset.
    pub fn cycles(&self) -> u64 {
        self.c.h.cycles
    }

    /// Return addresses on the hardware stack now.
    pub fn stack_depth(&self) -> u8 {
        self.c.sp
    }

    /// The deepest hardware-stack use seen since reset (interrupts included).
    pub fn max_stack_depth(&self) -> u8 {
        self.c.max_sp
    }

    /// Reads data memory at a full 9-bit address (0x000–0x1FF; higher bits are
    /// ignored) with mirrors resolved, as an instruction would see it now, but without
    /// side effects: INDF reads 0, unimplemented addresses read 0.
    pub fn read(&self, addr: u16) -> u8 {
        self.c.read(addr)
    }

    /// Writes data memory at a full 9-bit address (mirrors resolved) for the host: no
    /// instruction side effects (writing STATUS sets all its bits, PCL sets PC<7:0>,
    /// INDF and unimplemented addresses are ignored), but the peripherals see the
    /// write: TMR0/TMR1 restart from the value, flags and enables can raise an interrupt.
    pub fn write(&mut self, addr: u16, v: u8) {
        self.c.write(addr, v);
    }

    /// Sets the external level of an input pin (`bit` 0–7; RA6/RA7 do not exist and
    /// are ignored). A rising or falling edge on RB0, as selected by `OPTION_REG<INTEDG>`,
    /// sets INTF when RB0 is an input. (Interrupt-on-change of RB7:RB4 is not modelled.)
    pub fn set_input(&mut self, port: Port, bit: u8, level: bool) {
        self.c.set_input(port, bit, level);
    }

    /// The level the chip drives on a pin: the output latch bit when the TRIS bit is 0,
    /// `false` for an input pin.
    pub fn output(&self, port: Port, bit: u8) -> bool {
        let mask = 1u8 << (bit & 7);
        let (latch, tris) = self.c.port_regs(port);
        tris & mask == 0 && latch & mask != 0
    }

    /// Executes one instruction, or enters the interrupt if one is pending.
    pub fn step(&mut self) -> Result<(), SimError> {
        let c = &mut self.c;
        c.advance_timers(c.h.cycles);
        if c.irq_pending() && c.h.cycles >= c.irq_hold {
            return c.enter_irq();
        }
        let mut h = c.h;
        // a fused op stops after its first instruction
        c.next = 0;
        let op = self.prog[(h.table | h.pc) & (TABLE - 1)];
        let r = c.exec(&mut h, op);
        c.h = h;
        match r {
            Ok(()) => {}
            Err(Exit::Fault(e)) => return Err(e),
            Err(Exit::Break) => {
                return Err(err_at("internal error: breakpoint executed", h.pc));
            }
        }
        c.advance_timers(c.h.cycles);
        Ok(())
    }

    /// Runs until the PC is at one of `stop_at` (checked before the instruction there
    /// executes, and only after at least one instruction or interrupt entry in this
    /// call) or until `max_cycles` more cycles have passed (checked at instruction
    /// boundaries, so a 2-cycle instruction can end one cycle past the budget).
    pub fn run_until(&mut self, stop_at: &[u16], max_cycles: u64) -> Result<Stop, SimError> {
        if max_cycles == 0 {
            return Ok(Stop::CycleLimit);
        }
        self.c.limit = self.c.h.cycles.saturating_add(max_cycles);
        if let Err(e) = self.step() {
            self.c.limit = u64::MAX;
            return Err(e);
        }
        for &a in stop_at {
            let a = usize::from(a);
            if a >= PROG_WORDS {
                continue;
            }
            for t in (0..TABLE).step_by(PROG_WORDS) {
                // a fused op must not run past the stop address
                if a > 0 && self.prog[t + a - 1].is_fused() {
                    let word = self.words.get(a - 1).copied().unwrap_or(0x3FFF);
                    self.saved.push((t + a - 1, self.prog[t + a - 1]));
                    self.prog[t + a - 1] = Op::decode(word, table_bank(t));
                }
                if self.prog[t + a].kind != Kind::Break {
                    self.saved.push((t + a, self.prog[t + a]));
                    self.prog[t + a].kind = Kind::Break;
                }
            }
        }
        self.c.next = 0;
        let r = run_loop(&self.prog, &mut self.c);
        // in reverse: an entry can be saved twice (unfused, then a stop address)
        while let Some((i, op)) = self.saved.pop() {
            self.prog[i] = op;
        }
        self.c.limit = u64::MAX;
        r
    }
}

/// The run loop: the fast path executes instructions until the cycle counter reaches
/// `next`, where [`Core::service`] handles timers, interrupts and the budget.
fn run_loop(prog: &[Op; TABLE], c: &mut Core) -> Result<Stop, SimError> {
    let mut h = c.h;
    let r = loop {
        if h.cycles >= c.next {
            c.h = h;
            match c.service() {
                Ok(None) => {}
                Ok(Some(stop)) => break Ok(stop),
                Err(e) => break Err(e),
            }
            h = c.h;
        }
        let op = prog[(h.table | h.pc) & (TABLE - 1)];
        match c.exec(&mut h, op) {
            Ok(()) => {}
            Err(Exit::Break) => break Ok(Stop::Breakpoint(h.pc as u16)),
            Err(Exit::Fault(e)) => break Err(e),
        }
    };
    c.h = h;
    r
}

/// Why `exec` did not complete an instruction.
enum Exit {
    /// The PC is at a stop address.
    Break,
    /// The program did something wrong.
    Fault(SimError),
}

impl Core {
    fn reset(&mut self) {
        for a in 0..RAM_SIZE as u16 {
            if canonical(a) == Some(a) && !GPR.iter().any(|&(lo, hi)| (lo..=hi).contains(&a)) {
                self.ram[a as usize] = 0;
            }
        }
        self.ram[ZERO_SLOT as usize] = 0;
        for (a, v) in POR_VALUES {
            self.ram[a as usize] = v;
        }
        self.h = Hot::default();
        self.h.set_status(0x18);
        self.sp = 0;
        self.max_sp = 0;
        self.stack = [0; 8];
        self.irq_change_at = 0;
        self.irq_hold = 0;
        self.t1_origin = 0;
        self.t1_base = 0;
        self.t1_ovf_at = u64::MAX;
        self.t1_cmp_at = u64::MAX;
        self.t0_origin = 0;
        self.t0_base = 0;
        self.t0_ovf_at = u64::MAX;
    }

    fn read(&self, addr: u16) -> u8 {
        let m = RMAP[usize::from(addr) & 0x1FF];
        if m < SPECIAL {
            return self.ram[usize::from(m)];
        }
        match m - SPECIAL {
            INDF => 0,
            STATUS => self.h.status(),
            PCL => self.h.pc as u8,
            c => self.rd_periph(c, self.h.cycles),
        }
    }

    fn write(&mut self, addr: u16, v: u8) {
        let m = WMAP[usize::from(addr) & 0x1FF];
        if m < SPECIAL {
            self.ram[usize::from(m)] = v;
            return;
        }
        match m - SPECIAL {
            INDF => {}
            STATUS => self.h.set_status(v),
            PCL => self.h.pc = (self.h.pc & 0x1F00) | usize::from(v),
            c => self.wr_periph(c, v, self.h.cycles),
        }
        self.next = 0;
    }

    fn set_input(&mut self, port: Port, bit: u8, level: bool) {
        let mask = 1u8 << (bit & 7);
        let i = port as usize;
        let old = self.inputs[i] & mask != 0;
        if level {
            self.inputs[i] |= mask;
        } else {
            self.inputs[i] &= !mask;
        }
        if port == Port::B
            && mask == 1
            && old != level
            && self.ram[TRISB as usize] & 1 != 0
            && level == (self.ram[OPTION_REG as usize] & 0x40 != 0)
        {
            self.ram[INTCON as usize] |= 0x02;
            self.irq_change_at = self.h.cycles;
            self.next = 0;
        }
    }

    fn port_regs(&self, port: Port) -> (u8, u8) {
        let (l, t) = match port {
            Port::A => (PORTA, TRISA),
            Port::B => (PORTB, TRISB),
            Port::C => (PORTC, TRISC),
        };
        let (latch, tris) = (self.ram[l as usize], self.ram[t as usize]);
        if port == Port::A {
            (latch & 0x3F, tris | 0xC0)
        } else {
            (latch, tris)
        }
    }

    /// What reading a port gives: the latch for outputs, the pin level for inputs;
    /// analog RA pins read 0.
    fn port_read(&self, port: Port) -> u8 {
        let (latch, tris) = self.port_regs(port);
        let v = (latch & !tris) | (self.inputs[port as usize] & tris);
        if port == Port::A {
            v & 0x3F & !analog_mask(self.ram[ADCON1 as usize])
        } else {
            v
        }
    }

    /// The slow path of the run loop: timer events, the cycle budget, interrupts, and
    /// the cycle of the next check.
    #[cold]
    #[inline(never)]
    fn service(&mut self) -> Result<Option<Stop>, SimError> {
        self.advance_timers(self.h.cycles);
        if self.h.cycles >= self.limit {
            return Ok(Some(Stop::CycleLimit));
        }
        let mut next = self.t1_ovf_at.min(self.t1_cmp_at).min(self.t0_ovf_at);
        if self.irq_pending() {
            if self.h.cycles >= self.irq_hold {
                self.enter_irq()?;
            } else {
                next = next.min(self.irq_hold);
            }
        }
        self.next = next.min(self.limit);
        Ok(None)
    }

    fn irq_pending(&self) -> bool {
        let intcon = self.ram[INTCON as usize];
        if intcon & 0x80 == 0 {
            return false;
        }
        // T0IE/T0IF, INTE/INTF, RBIE/RBIF
        if (intcon >> 3) & intcon & 0x07 != 0 {
            return true;
        }
        let r = |a: u16| self.ram[a as usize];
        intcon & 0x40 != 0 && ((r(PIR1) & r(PIE1)) | (r(PIR2) & r(PIE2))) != 0
    }

    fn enter_irq(&mut self) -> Result<(), SimError> {
        let b = self.h.cycles;
        self.push(self.h.pc as u16, self.h.pc)?;
        self.ram[INTCON as usize] &= !0x80;
        self.h.pc = 4;
        self.h.cycles += u64::from(self.irq_change_at >= b);
        Ok(())
    }

    #[inline(always)]
    fn push(&mut self, ret: u16, at: usize) -> Result<(), SimError> {
        if self.sp >= 8 {
            return Err(err_at("hardware stack overflow: 9 levels", at));
        }
        self.stack[usize::from(self.sp)] = ret;
        self.sp += 1;
        self.max_sp = self.max_sp.max(self.sp);
        Ok(())
    }

    #[inline(always)]
    fn pop(&mut self, what: &str, at: usize) -> Result<u16, SimError> {
        if self.sp == 0 {
            return Err(err_at(&format!("{what} with an empty stack"), at));
        }
        self.sp -= 1;
        Ok(self.stack[usize::from(self.sp)])
    }

    /// An interrupt condition may have changed, visible from cycle `at` (the caller
    /// makes the run loop check: `next = 0`).
    fn irq_changed(&mut self, at: u64) {
        self.irq_change_at = at;
    }

    // ---- data memory as instructions see it ----------------------------------------

    #[inline(always)]
    fn rd(&self, h: &Hot, a: usize) -> u8 {
        let m = RMAP[a & (RAM_SIZE - 1)];
        if m < SPECIAL {
            return self.ram[usize::from(m)];
        }
        self.rd_special(h, m - SPECIAL)
    }

    #[inline(always)]
    fn rd_special(&self, h: &Hot, c: u16) -> u8 {
        if c == INDF {
            return self.rd_indf(h);
        }
        self.rd_direct(h, c)
    }

    /// Reads INDF: the address in IRP:FSR (INDF itself reads 0).
    #[inline(always)]
    fn rd_indf(&self, h: &Hot) -> u8 {
        let a = (usize::from(h.st & 0x80) << 1) | usize::from(self.ram[FSR]);
        if a & 0x7F == 0 {
            return 0;
        }
        let m = RMAP[a];
        if m < SPECIAL {
            return self.ram[usize::from(m)];
        }
        self.rd_direct_cold(h.status(), h.pc, h.cycles, m - SPECIAL)
    }

    // The cold paths do not take the run loop's registers by reference (it would then
    // keep them in memory): they take values, or work on `self.h`.
    #[inline(never)]
    fn rd_direct_cold(&self, status: u8, pc: usize, now: u64, c: u16) -> u8 {
        match c {
            STATUS => status,
            PCL => pc as u8,
            _ => self.rd_periph(c, now),
        }
    }

    #[inline(always)]
    fn rd_direct(&self, h: &Hot, c: u16) -> u8 {
        match c {
            STATUS => h.status(),
            PCL => h.pc as u8,
            _ => self.rd_periph(c, h.cycles),
        }
    }

    /// Ports and timers (canonical address `c`) read at cycle `now`.
    #[inline(never)]
    fn rd_periph(&self, c: u16, now: u64) -> u8 {
        match c {
            PORTA => self.port_read(Port::A),
            PORTB => self.port_read(Port::B),
            PORTC => self.port_read(Port::C),
            TMR0 => self.t0_value(now),
            TMR1L => self.t1_value(now) as u8,
            TMR1H => (self.t1_value(now) >> 8) as u8,
            _ => self.ram[usize::from(c)],
        }
    }

    /// Writes `v` to data address `a`. `flags` tells that the instruction sets some of
    /// Z/DC/C, whose write through STATUS is then disabled.
    #[inline(always)]
    fn wr(&mut self, h: &mut Hot, a: usize, v: u8, flags: bool) {
        let m = WMAP[a & (RAM_SIZE - 1)];
        if m < SPECIAL {
            self.ram[usize::from(m)] = v;
            return;
        }
        let c = m - SPECIAL;
        if c == INDF {
            self.wr_indf(h, v, flags);
            return;
        }
        self.wr_direct(h, c, v, flags);
    }

    /// Writes INDF: the address in IRP:FSR (writes to INDF itself are lost).
    #[inline(always)]
    fn wr_indf(&mut self, h: &mut Hot, v: u8, flags: bool) {
        let a = (usize::from(h.st & 0x80) << 1) | usize::from(self.ram[FSR]);
        if a & 0x7F == 0 {
            return;
        }
        let m = WMAP[a];
        if m < SPECIAL {
            self.ram[usize::from(m)] = v;
        } else {
            self.h = *h;
            self.wr_direct_cold(m - SPECIAL, v, flags);
            *h = self.h;
        }
    }

    /// [`Core::wr_direct`] on `self.h`.
    #[inline(never)]
    fn wr_direct_cold(&mut self, c: u16, v: u8, flags: bool) {
        let mut h = self.h;
        self.wr_direct(&mut h, c, v, flags);
        self.h = h;
    }

    #[inline(always)]
    fn wr_direct(&mut self, h: &mut Hot, c: u16, v: u8, flags: bool) {
        match c {
            STATUS => {
                let mask = if flags { 0xE0 } else { 0xE7 };
                h.set_status((h.status() & !mask) | (v & mask));
            }
            PCL => {
                h.pc = (usize::from(self.ram[PCLATH as usize] & 0x1F) << 8) | usize::from(v);
                h.cycles += 1;
            }
            _ => {
                self.wr_periph(c, v, h.cycles);
                self.next = 0;
            }
        }
    }

    /// A write to a peripheral or interrupt register by an instruction starting at
    /// cycle `now` (or by the host at `now`).
    #[inline(never)]
    fn wr_periph(&mut self, c: u16, v: u8, now: u64) {
        let ci = usize::from(c);
        match c {
            PCLATH => self.ram[ci] = v & 0x1F,
            TRISA => self.ram[ci] = v & 0x3F,
            INTCON | PIR1 | PIR2 | PIE1 | PIE2 => {
                self.ram[ci] = v;
                self.irq_changed(now + 1);
            }
            TMR1L | TMR1H => {
                let t = self.t1_value(now);
                self.t1_base = if c == TMR1L {
                    (t & 0xFF00) | u16::from(v)
                } else {
                    (t & 0x00FF) | u16::from(v) << 8
                };
                self.t1_origin = now;
                self.t1_schedule(now);
            }
            T1CON => {
                self.t1_base = self.t1_value(now);
                self.t1_origin = now;
                self.ram[ci] = v & 0x3F;
                self.t1_schedule(now);
            }
            CCPR1L | CCPR1H => {
                self.ram[ci] = v;
                self.t1_schedule(now);
            }
            CCP1CON => {
                self.ram[ci] = v & 0x3F;
                self.t1_schedule(now);
            }
            TMR0 => {
                self.t0_base = v;
                // two inhibited cycles, then the prescaler starts from 0
                self.t0_origin = now + 2;
                self.t0_schedule(now);
            }
            OPTION_REG => {
                self.t0_base = self.t0_value(now);
                self.t0_origin = now;
                self.ram[ci] = v;
                self.t0_schedule(now);
            }
            _ => self.ram[ci] = v,
        }
    }

    // ---- timers --------------------------------------------------------------------

    fn t1_running(&self) -> bool {
        self.ram[T1CON as usize] & 0x03 == 0x01
    }

    fn t1_shift(&self) -> u32 {
        u32::from(self.ram[T1CON as usize] >> 4 & 3)
    }

    fn t1_value(&self, now: u64) -> u16 {
        if !self.t1_running() {
            return self.t1_base;
        }
        let ticks = now.saturating_sub(self.t1_origin) >> self.t1_shift();
        self.t1_base.wrapping_add(ticks as u16)
    }

    /// Computes the next Timer1 overflow and compare events that happen at a tick at or
    /// after cycle `from`.
    fn t1_schedule(&mut self, from: u64) {
        if !self.t1_running() {
            self.t1_ovf_at = u64::MAX;
            self.t1_cmp_at = u64::MAX;
            return;
        }
        let shift = self.t1_shift();
        let ps = 1u64 << shift;
        let jmin = ((from.saturating_sub(self.t1_origin) + ps - 1) >> shift).max(1);
        // First tick number j >= jmin with j = j0 (mod 65536), j0 in 1..=65536.
        let next = |j0: u64| {
            if j0 >= jmin {
                j0
            } else {
                j0 + (jmin - j0).div_ceil(0x10000) * 0x10000
            }
        };
        let base = u64::from(self.t1_base);
        self.t1_ovf_at = self.t1_origin + (next(0x10000 - base) << shift) + 1;
        let mode = self.ram[CCP1CON as usize] & 0x0F;
        self.t1_cmp_at = if (0x08..=0x0B).contains(&mode) {
            let ccpr =
                u64::from(self.ram[CCPR1L as usize]) | u64::from(self.ram[CCPR1H as usize]) << 8;
            let d = (ccpr + 0x10000 - base) & 0xFFFF;
            self.t1_origin + (next(if d == 0 { 0x10000 } else { d }) << shift) + 1
        } else {
            u64::MAX
        };
    }

    fn t0_shift(&self) -> u32 {
        let opt = self.ram[OPTION_REG as usize];
        if opt & 0x08 != 0 {
            0
        } else {
            u32::from(opt & 7) + 1
        }
    }

    fn t0_running(&self) -> bool {
        self.ram[OPTION_REG as usize] & 0x20 == 0
    }

    fn t0_value(&self, now: u64) -> u8 {
        if !self.t0_running() {
            return self.t0_base;
        }
        let ticks = now.saturating_sub(self.t0_origin) >> self.t0_shift();
        self.t0_base.wrapping_add(ticks as u8)
    }

    fn t0_schedule(&mut self, from: u64) {
        if !self.t0_running() {
            self.t0_ovf_at = u64::MAX;
            return;
        }
        let shift = self.t0_shift();
        let ps = 1u64 << shift;
        let jmin = ((from.saturating_sub(self.t0_origin) + ps - 1) >> shift).max(1);
        let j0 = 0x100 - u64::from(self.t0_base);
        let j = if j0 >= jmin {
            j0
        } else {
            j0 + (jmin - j0).div_ceil(0x100) * 0x100
        };
        self.t0_ovf_at = self.t0_origin + (j << shift);
    }

    /// Applies every timer event visible at or before cycle `now`.
    #[inline(always)]
    fn advance_timers(&mut self, now: u64) {
        if self.t1_ovf_at.min(self.t1_cmp_at) <= now {
            self.t1_advance(now);
        }
        if self.t0_ovf_at <= now {
            self.t0_advance(now);
        }
    }

    #[inline(never)]
    fn t1_advance(&mut self, now: u64) {
        loop {
            let e = self.t1_ovf_at.min(self.t1_cmp_at);
            if e > now {
                break;
            }
            let tick = e - 1;
            let ticks = (tick - self.t1_origin) >> self.t1_shift();
            self.t1_base = self.t1_base.wrapping_add(ticks as u16);
            self.t1_origin = tick;
            if self.t1_ovf_at == e {
                self.ram[PIR1 as usize] |= 0x01;
            }
            if self.t1_cmp_at == e {
                self.ram[PIR1 as usize] |= 0x04;
                if self.ram[CCP1CON as usize] & 0x0F == 0x0B {
                    self.t1_base = 0;
                }
            }
            self.irq_change_at = e;
            self.t1_schedule(tick);
        }
    }

    #[inline(never)]
    fn t0_advance(&mut self, now: u64) {
        while self.t0_ovf_at <= now {
            let e = self.t0_ovf_at;
            self.ram[INTCON as usize] |= 0x04;
            self.t0_origin = e;
            self.t0_base = 0;
            self.irq_change_at = e + 1;
            self.irq_hold = e + 1;
            self.t0_schedule(e);
        }
    }
}
