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
use std::fmt;

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

/// Decoded instruction kinds. There is one decoded table per bank (STATUS<RP1:RP0>
/// selects the table the run loop reads), so a direct file operand is resolved when
/// the program is decoded: the byte- and bit-oriented kinds below name a storage index
/// (`Op::a`) of general-purpose RAM or of a register without side effects; MOVF INDF,W
/// and MOVWF INDF have their own kinds, and every other file operand becomes
/// [`Kind::Slow`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Kind {
    AddwfW,
    AddwfF,
    AndwfW,
    AndwfF,
    Clrf,
    ComfW,
    ComfF,
    DecfW,
    DecfF,
    DecfszW,
    DecfszF,
    IncfW,
    IncfF,
    IncfszW,
    IncfszF,
    IorwfW,
    IorwfF,
    MovfW,
    MovfF,
    Movwf,
    RlfW,
    RlfF,
    RrfW,
    RrfF,
    SubwfW,
    SubwfF,
    SwapfW,
    SwapfF,
    XorwfW,
    XorwfF,
    /// Bit operations: `b` holds the bit mask.
    Bcf,
    Bsf,
    Btfsc,
    Btfss,
    /// BCF/BSF on STATUS bits other than Z (`b`: the mask without TO and PD, which are
    /// read-only), and BTFSC/BTFSS on them (`b`: the mask).
    BcfStatus,
    BsfStatus,
    BtfscStatus,
    BtfssStatus,
    /// The same on STATUS<Z>.
    BcfZ,
    BsfZ,
    BtfscZ,
    BtfssZ,
    /// MOVF INDF,W and MOVWF INDF.
    MovfWIndf,
    MovwfIndf,
    /// Literal instructions: `b` holds the literal.
    Addlw,
    Andlw,
    Iorlw,
    Xorlw,
    Movlw,
    Sublw,
    Retlw,
    Clrw,
    Nop,
    /// CALL/GOTO: `a` holds the 11-bit target.
    Call,
    Goto,
    Return,
    Retfie,
    Clrwdt,
    Sleep,
    /// A byte- or bit-oriented instruction on a special or unimplemented address (`a`
    /// holds the word), executed by [`Core::exec_slow`].
    Slow,
    /// An unused encoding (`a` holds the word).
    Invalid,
    /// A stop address of the current `run_until` (the real op is saved aside).
    Break,
    // Fused pairs (see `PAIRS`): the first instruction with `a`, `b`, the second with
    // `a2`, `b2`; one dispatch for two instructions.
    MovfWMovwf,
    MovwfMovfW,
    AddwfFMovfW,
    RlfFRlfF,
    BcfStatusRlfF,
    MovwfGoto,
    MovfWXorlw,
    MovwfClrf,
    MovfWAddwfF,
    ClrfMovfW,
    MovwfIncfF,
    MovfWBtfscStatus,
    MovwfMovlw,
    ClrfClrf,
    IncfFMovfW,
    MovlwAddwfF,
    MovfWSublw,
    MovfWBtfscZ,
    BcfBtfsc,
    SublwBtfssStatus,
    MovwfBcfStatus,
    SubwfFMovfW,
    RlfFDecfszF,
    RrfFBtfssStatus,
    BcfStatusRrfF,
    MovfWBtfssStatus,
    XorlwMovwf,
    MovlwMovwf,
    MovfWSubwfF,
    AndlwMovwf,
    MovfWAndlw,
    MovfWSubwfW,
    RlfFBtfscStatus,
    SubwfFBtfscStatus,
    MovfWBtfssZ,
    IncfFGoto,
    MovwfBsf,
    MovwfBcf,
    MovfWIndfMovwf,
    BcfStatusBtfsc,
    IncfFBtfscZ,
    AddwfFGoto,
    AddwfWMovwf,
    IncfFMovfWIndf,
    BsfBtfss,
    MovlwAddwfW,
    SubwfWBtfssZ,
    RlfFMovlw,
    MovlwSubwfW,
    BcfBtfssStatus,
    SublwBtfssZ,
    BcfBtfssZ,
    BcfBtfss,
    MovlwBtfscStatus,
    MovlwBtfssStatus,
    DecfszFGoto,
    BtfssZGoto,
    BtfscStatusGoto,
    BtfssStatusGoto,
    IncfszWAddwfF,
    IncfszWSubwfF,
    BtfssBcf,
    BtfssGoto,
}

/// A decoded instruction: `a` a storage index (plain file operands), a CALL/GOTO
/// target or a word; `b` a bit mask or a literal; `a2`, `b2` the same for the second
/// instruction of a fused pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C, align(8))]
struct Op {
    kind: Kind,
    b: u8,
    a: u16,
    a2: u16,
    b2: u8,
}

/// The pairs of consecutive instructions fused into one op: (first, second, fused).
/// The first is a plain instruction that goes on to the next address or skips it (then
/// the second does not run); the pairs are the most frequent in plcc's code
/// (bench/pic16).
const PAIRS: [(Kind, Kind, Kind); 63] = [
    (Kind::MovfW, Kind::Movwf, Kind::MovfWMovwf),
    (Kind::Movwf, Kind::MovfW, Kind::MovwfMovfW),
    (Kind::AddwfF, Kind::MovfW, Kind::AddwfFMovfW),
    (Kind::RlfF, Kind::RlfF, Kind::RlfFRlfF),
    (Kind::BcfStatus, Kind::RlfF, Kind::BcfStatusRlfF),
    (Kind::Movwf, Kind::Goto, Kind::MovwfGoto),
    (Kind::MovfW, Kind::Xorlw, Kind::MovfWXorlw),
    (Kind::Movwf, Kind::Clrf, Kind::MovwfClrf),
    (Kind::MovfW, Kind::AddwfF, Kind::MovfWAddwfF),
    (Kind::Clrf, Kind::MovfW, Kind::ClrfMovfW),
    (Kind::Movwf, Kind::IncfF, Kind::MovwfIncfF),
    (Kind::MovfW, Kind::BtfscStatus, Kind::MovfWBtfscStatus),
    (Kind::Movwf, Kind::Movlw, Kind::MovwfMovlw),
    (Kind::Clrf, Kind::Clrf, Kind::ClrfClrf),
    (Kind::IncfF, Kind::MovfW, Kind::IncfFMovfW),
    (Kind::Movlw, Kind::AddwfF, Kind::MovlwAddwfF),
    (Kind::MovfW, Kind::Sublw, Kind::MovfWSublw),
    (Kind::MovfW, Kind::BtfscZ, Kind::MovfWBtfscZ),
    (Kind::Bcf, Kind::Btfsc, Kind::BcfBtfsc),
    (Kind::Sublw, Kind::BtfssStatus, Kind::SublwBtfssStatus),
    (Kind::Movwf, Kind::BcfStatus, Kind::MovwfBcfStatus),
    (Kind::SubwfF, Kind::MovfW, Kind::SubwfFMovfW),
    (Kind::RlfF, Kind::DecfszF, Kind::RlfFDecfszF),
    (Kind::RrfF, Kind::BtfssStatus, Kind::RrfFBtfssStatus),
    (Kind::BcfStatus, Kind::RrfF, Kind::BcfStatusRrfF),
    (Kind::MovfW, Kind::BtfssStatus, Kind::MovfWBtfssStatus),
    (Kind::Xorlw, Kind::Movwf, Kind::XorlwMovwf),
    (Kind::Movlw, Kind::Movwf, Kind::MovlwMovwf),
    (Kind::MovfW, Kind::SubwfF, Kind::MovfWSubwfF),
    (Kind::Andlw, Kind::Movwf, Kind::AndlwMovwf),
    (Kind::MovfW, Kind::Andlw, Kind::MovfWAndlw),
    (Kind::MovfW, Kind::SubwfW, Kind::MovfWSubwfW),
    (Kind::RlfF, Kind::BtfscStatus, Kind::RlfFBtfscStatus),
    (Kind::SubwfF, Kind::BtfscStatus, Kind::SubwfFBtfscStatus),
    (Kind::MovfW, Kind::BtfssZ, Kind::MovfWBtfssZ),
    (Kind::IncfF, Kind::Goto, Kind::IncfFGoto),
    (Kind::Movwf, Kind::Bsf, Kind::MovwfBsf),
    (Kind::Movwf, Kind::Bcf, Kind::MovwfBcf),
    (Kind::MovfWIndf, Kind::Movwf, Kind::MovfWIndfMovwf),
    (Kind::BcfStatus, Kind::Btfsc, Kind::BcfStatusBtfsc),
    (Kind::IncfF, Kind::BtfscZ, Kind::IncfFBtfscZ),
    (Kind::AddwfF, Kind::Goto, Kind::AddwfFGoto),
    (Kind::AddwfW, Kind::Movwf, Kind::AddwfWMovwf),
    (Kind::IncfF, Kind::MovfWIndf, Kind::IncfFMovfWIndf),
    (Kind::Bsf, Kind::Btfss, Kind::BsfBtfss),
    (Kind::Movlw, Kind::AddwfW, Kind::MovlwAddwfW),
    (Kind::SubwfW, Kind::BtfssZ, Kind::SubwfWBtfssZ),
    (Kind::RlfF, Kind::Movlw, Kind::RlfFMovlw),
    (Kind::Movlw, Kind::SubwfW, Kind::MovlwSubwfW),
    (Kind::Bcf, Kind::BtfssStatus, Kind::BcfBtfssStatus),
    (Kind::Sublw, Kind::BtfssZ, Kind::SublwBtfssZ),
    (Kind::Bcf, Kind::BtfssZ, Kind::BcfBtfssZ),
    (Kind::Bcf, Kind::Btfss, Kind::BcfBtfss),
    (Kind::Movlw, Kind::BtfscStatus, Kind::MovlwBtfscStatus),
    (Kind::Movlw, Kind::BtfssStatus, Kind::MovlwBtfssStatus),
    (Kind::DecfszF, Kind::Goto, Kind::DecfszFGoto),
    (Kind::BtfssZ, Kind::Goto, Kind::BtfssZGoto),
    (Kind::BtfscStatus, Kind::Goto, Kind::BtfscStatusGoto),
    (Kind::BtfssStatus, Kind::Goto, Kind::BtfssStatusGoto),
    (Kind::IncfszW, Kind::AddwfF, Kind::IncfszWAddwfF),
    (Kind::IncfszW, Kind::SubwfF, Kind::IncfszWSubwfF),
    (Kind::Btfss, Kind::Bcf, Kind::BtfssBcf),
    (Kind::Btfss, Kind::Goto, Kind::BtfssGoto),
];

impl Op {
    const fn new(kind: Kind, b: u8, a: u16) -> Op {
        Op {
            kind,
            b,
            a,
            a2: 0,
            b2: 0,
        }
    }

    /// Decodes `word` as executed with STATUS<RP1:RP0> giving data address offset
    /// `bank` (0, 0x80, 0x100 or 0x180).
    fn decode(word: u16, bank: u16) -> Op {
        use Inst::*;
        use Kind as K;
        let op = Op::new;
        let slow = op(K::Slow, 0, word & 0x3FFF);
        let Some(i) = Inst::decode(word) else {
            return op(K::Invalid, 0, word & 0x3FFF);
        };
        let addr = |f: u16| usize::from(bank | (f & 0x7F));
        let rd = |f: u16| Some(RMAP[addr(f)]).filter(|&m| m < SPECIAL);
        let wr = |f: u16| Some(WMAP[addr(f)]).filter(|&m| m < SPECIAL);
        let rmw = |f: u16| rd(f).filter(|&m| wr(f) == Some(m));
        let read = |kind, f, b| rd(f).map_or(slow, |m| op(kind, b, m));
        let modify = |kind, f, b| rmw(f).map_or(slow, |m| op(kind, b, m));
        let bo = |f, d, kw, kf| {
            if d == Dest::W {
                read(kw, f, 0)
            } else {
                modify(kf, f, 0)
            }
        };
        let indf = |f: u16, map: &[u16; RAM_SIZE]| map[addr(f)] == SPECIAL + INDF;
        let status = |f: u16| f & 0x7F == STATUS;
        match i {
            Addwf(f, d) => bo(f, d, K::AddwfW, K::AddwfF),
            Andwf(f, d) => bo(f, d, K::AndwfW, K::AndwfF),
            Clrf(f) => wr(f).map_or(slow, |m| op(K::Clrf, 0, m)),
            Clrw => op(K::Clrw, 0, 0),
            Comf(f, d) => bo(f, d, K::ComfW, K::ComfF),
            Decf(f, d) => bo(f, d, K::DecfW, K::DecfF),
            Decfsz(f, d) => bo(f, d, K::DecfszW, K::DecfszF),
            Incf(f, d) => bo(f, d, K::IncfW, K::IncfF),
            Incfsz(f, d) => bo(f, d, K::IncfszW, K::IncfszF),
            Iorwf(f, d) => bo(f, d, K::IorwfW, K::IorwfF),
            Movf(f, Dest::W) if indf(f, &RMAP) => op(K::MovfWIndf, 0, 0),
            Movf(f, d) => bo(f, d, K::MovfW, K::MovfF),
            Movwf(f) if indf(f, &WMAP) => op(K::MovwfIndf, 0, 0),
            Movwf(f) => wr(f).map_or(slow, |m| op(K::Movwf, 0, m)),
            Nop => op(K::Nop, 0, 0),
            Rlf(f, d) => bo(f, d, K::RlfW, K::RlfF),
            Rrf(f, d) => bo(f, d, K::RrfW, K::RrfF),
            Subwf(f, d) => bo(f, d, K::SubwfW, K::SubwfF),
            Swapf(f, d) => bo(f, d, K::SwapfW, K::SwapfF),
            Xorwf(f, d) => bo(f, d, K::XorwfW, K::XorwfF),
            Bcf(f, b) | Bsf(f, b) | Btfsc(f, b) | Btfss(f, b) if status(f) => {
                let mask = 1u8 << (b & 7);
                let z = mask == Z;
                match (i, z) {
                    (Bcf(..), true) => op(K::BcfZ, 0, 0),
                    (Bsf(..), true) => op(K::BsfZ, 0, 0),
                    (Btfsc(..), true) => op(K::BtfscZ, 0, 0),
                    (Btfss(..), true) => op(K::BtfssZ, 0, 0),
                    (Bcf(..), _) => op(K::BcfStatus, mask & 0xE7, 0),
                    (Bsf(..), _) => op(K::BsfStatus, mask & 0xE7, 0),
                    (Btfsc(..), _) => op(K::BtfscStatus, mask, 0),
                    _ => op(K::BtfssStatus, mask, 0),
                }
            }
            Bcf(f, b) => modify(K::Bcf, f, 1 << (b & 7)),
            Bsf(f, b) => modify(K::Bsf, f, 1 << (b & 7)),
            Btfsc(f, b) => read(K::Btfsc, f, 1 << (b & 7)),
            Btfss(f, b) => read(K::Btfss, f, 1 << (b & 7)),
            Addlw(k) => op(K::Addlw, k, 0),
            Andlw(k) => op(K::Andlw, k, 0),
            Call(k) => op(K::Call, 0, k & 0x7FF),
            Clrwdt => op(K::Clrwdt, 0, 0),
            Goto(k) => op(K::Goto, 0, k & 0x7FF),
            Iorlw(k) => op(K::Iorlw, k, 0),
            Movlw(k) => op(K::Movlw, k, 0),
            Retfie => op(K::Retfie, 0, 0),
            Retlw(k) => op(K::Retlw, k, 0),
            Return => op(K::Return, 0, 0),
            Sleep => op(K::Sleep, 0, 0),
            Sublw(k) => op(K::Sublw, k, 0),
            Xorlw(k) => op(K::Xorlw, k, 0),
        }
    }

    fn is_fused(self) -> bool {
        self.kind as u8 >= PAIRS[0].2 as u8
    }

    /// The op that executes `self` and then `next` (the instruction after it) in one
    /// dispatch, if there is one.
    fn fuse(self, next: Op) -> Option<Op> {
        // the second instruction must see the bank the first one leaves
        if matches!(self.kind, Kind::BcfStatus | Kind::BsfStatus) && self.b & 0x60 != 0 {
            return None;
        }
        let &(_, _, kind) = PAIRS
            .iter()
            .find(|&&(first, second, _)| (first, second) == (self.kind, next.kind))?;
        Some(Op {
            kind,
            b: self.b,
            a: self.a,
            a2: next.a,
            b2: next.b,
        })
    }
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
    /// are ignored). A rising or falling edge on RB0, as selected by OPTION_REG<INTEDG>,
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

    // ---- the instructions ----------------------------------------------------------

    /// Executes `op`, the instruction at `h.pc` (a fused op: both instructions, unless
    /// the cycle counter reaches `next` after the first).
    #[inline(always)]
    fn exec(&mut self, h: &mut Hot, op: Op) -> Result<(), Exit> {
        use Kind as K;
        let at = h.pc;
        h.pc = (at + 1) & 0x1FFF;
        let k = op.b;
        // A fused pair: the first instruction, its cycle, and the second unless the
        // first skipped it or the run loop has to check first.
        macro_rules! pair {
            ($first:ident, $second:ident) => {{
                self.simple(h, K::$first, op.a, op.b);
                h.cycles += 1;
                if h.pc != (at + 1) & 0x1FFF || h.cycles >= self.next {
                    return Ok(());
                }
                h.pc = (h.pc + 1) & 0x1FFF;
                self.simple(h, K::$second, op.a2, op.b2);
            }};
        }
        match op.kind {
            K::AddwfW => self.simple(h, K::AddwfW, op.a, k),
            K::AddwfF => self.simple(h, K::AddwfF, op.a, k),
            K::AndwfW => self.simple(h, K::AndwfW, op.a, k),
            K::AndwfF => self.simple(h, K::AndwfF, op.a, k),
            K::Clrf => self.simple(h, K::Clrf, op.a, k),
            K::Clrw => self.simple(h, K::Clrw, op.a, k),
            K::ComfW => self.simple(h, K::ComfW, op.a, k),
            K::ComfF => self.simple(h, K::ComfF, op.a, k),
            K::DecfW => self.simple(h, K::DecfW, op.a, k),
            K::DecfF => self.simple(h, K::DecfF, op.a, k),
            K::DecfszW => self.simple(h, K::DecfszW, op.a, k),
            K::DecfszF => self.simple(h, K::DecfszF, op.a, k),
            K::IncfW => self.simple(h, K::IncfW, op.a, k),
            K::IncfF => self.simple(h, K::IncfF, op.a, k),
            K::IncfszW => self.simple(h, K::IncfszW, op.a, k),
            K::IncfszF => self.simple(h, K::IncfszF, op.a, k),
            K::IorwfW => self.simple(h, K::IorwfW, op.a, k),
            K::IorwfF => self.simple(h, K::IorwfF, op.a, k),
            K::MovfW => self.simple(h, K::MovfW, op.a, k),
            K::MovfF => self.simple(h, K::MovfF, op.a, k),
            K::Movwf => self.simple(h, K::Movwf, op.a, k),
            K::Nop => self.simple(h, K::Nop, op.a, k),
            K::RlfW => self.simple(h, K::RlfW, op.a, k),
            K::RlfF => self.simple(h, K::RlfF, op.a, k),
            K::RrfW => self.simple(h, K::RrfW, op.a, k),
            K::RrfF => self.simple(h, K::RrfF, op.a, k),
            K::SubwfW => self.simple(h, K::SubwfW, op.a, k),
            K::SubwfF => self.simple(h, K::SubwfF, op.a, k),
            K::SwapfW => self.simple(h, K::SwapfW, op.a, k),
            K::SwapfF => self.simple(h, K::SwapfF, op.a, k),
            K::XorwfW => self.simple(h, K::XorwfW, op.a, k),
            K::XorwfF => self.simple(h, K::XorwfF, op.a, k),
            K::Bcf => self.simple(h, K::Bcf, op.a, k),
            K::Bsf => self.simple(h, K::Bsf, op.a, k),
            K::Btfsc => self.simple(h, K::Btfsc, op.a, k),
            K::Btfss => self.simple(h, K::Btfss, op.a, k),
            K::BcfStatus => self.simple(h, K::BcfStatus, op.a, k),
            K::BsfStatus => self.simple(h, K::BsfStatus, op.a, k),
            K::BtfscStatus => self.simple(h, K::BtfscStatus, op.a, k),
            K::BtfssStatus => self.simple(h, K::BtfssStatus, op.a, k),
            K::BcfZ => self.simple(h, K::BcfZ, op.a, k),
            K::BsfZ => self.simple(h, K::BsfZ, op.a, k),
            K::BtfscZ => self.simple(h, K::BtfscZ, op.a, k),
            K::BtfssZ => self.simple(h, K::BtfssZ, op.a, k),
            K::MovfWIndf => self.simple(h, K::MovfWIndf, op.a, k),
            K::MovwfIndf => self.simple(h, K::MovwfIndf, op.a, k),
            K::Addlw => self.simple(h, K::Addlw, op.a, k),
            K::Andlw => self.simple(h, K::Andlw, op.a, k),
            K::Iorlw => self.simple(h, K::Iorlw, op.a, k),
            K::Xorlw => self.simple(h, K::Xorlw, op.a, k),
            K::Movlw => self.simple(h, K::Movlw, op.a, k),
            K::Sublw => self.simple(h, K::Sublw, op.a, k),
            K::Goto => self.simple(h, K::Goto, op.a, k),
            K::Clrwdt => self.simple(h, K::Clrwdt, op.a, k),
            K::Call => {
                if let Err(e) = self.push(h.pc as u16, at) {
                    h.pc = at;
                    return Err(Exit::Fault(e));
                }
                h.pc = usize::from(self.ram[PCLATH as usize] & 0x18) << 8 | usize::from(op.a);
                h.cycles += 1;
            }
            K::Return | K::Retlw | K::Retfie => {
                let name = match op.kind {
                    K::Return => "RETURN",
                    K::Retlw => "RETLW",
                    _ => "RETFIE",
                };
                match self.pop(name, at) {
                    Ok(ret) => h.pc = usize::from(ret),
                    Err(e) => {
                        h.pc = at;
                        return Err(Exit::Fault(e));
                    }
                }
                if op.kind == K::Retlw {
                    h.w = k;
                } else if op.kind == K::Retfie {
                    self.ram[INTCON as usize] |= 0x80;
                    self.irq_changed(h.cycles + 1);
                    self.next = 0;
                }
                h.cycles += 1;
            }
            K::Slow => {
                self.h = *h;
                self.exec_slow(op.a);
                *h = self.h;
            }
            K::Sleep => {
                h.pc = at;
                return Err(Exit::Fault(err_at("SLEEP executed", at)));
            }
            K::Invalid => {
                h.pc = at;
                return Err(Exit::Fault(invalid(op.a, at)));
            }
            K::Break => {
                h.pc = at;
                return Err(Exit::Break);
            }
            K::MovfWMovwf => pair!(MovfW, Movwf),
            K::MovwfMovfW => pair!(Movwf, MovfW),
            K::AddwfFMovfW => pair!(AddwfF, MovfW),
            K::RlfFRlfF => pair!(RlfF, RlfF),
            K::BcfStatusRlfF => pair!(BcfStatus, RlfF),
            K::MovwfGoto => pair!(Movwf, Goto),
            K::MovfWXorlw => pair!(MovfW, Xorlw),
            K::MovwfClrf => pair!(Movwf, Clrf),
            K::MovfWAddwfF => pair!(MovfW, AddwfF),
            K::ClrfMovfW => pair!(Clrf, MovfW),
            K::MovwfIncfF => pair!(Movwf, IncfF),
            K::MovfWBtfscStatus => pair!(MovfW, BtfscStatus),
            K::MovwfMovlw => pair!(Movwf, Movlw),
            K::ClrfClrf => pair!(Clrf, Clrf),
            K::IncfFMovfW => pair!(IncfF, MovfW),
            K::MovlwAddwfF => pair!(Movlw, AddwfF),
            K::MovfWSublw => pair!(MovfW, Sublw),
            K::MovfWBtfscZ => pair!(MovfW, BtfscZ),
            K::BcfBtfsc => pair!(Bcf, Btfsc),
            K::SublwBtfssStatus => pair!(Sublw, BtfssStatus),
            K::MovwfBcfStatus => pair!(Movwf, BcfStatus),
            K::SubwfFMovfW => pair!(SubwfF, MovfW),
            K::RlfFDecfszF => pair!(RlfF, DecfszF),
            K::RrfFBtfssStatus => pair!(RrfF, BtfssStatus),
            K::BcfStatusRrfF => pair!(BcfStatus, RrfF),
            K::MovfWBtfssStatus => pair!(MovfW, BtfssStatus),
            K::XorlwMovwf => pair!(Xorlw, Movwf),
            K::MovlwMovwf => pair!(Movlw, Movwf),
            K::MovfWSubwfF => pair!(MovfW, SubwfF),
            K::AndlwMovwf => pair!(Andlw, Movwf),
            K::MovfWAndlw => pair!(MovfW, Andlw),
            K::MovfWSubwfW => pair!(MovfW, SubwfW),
            K::RlfFBtfscStatus => pair!(RlfF, BtfscStatus),
            K::SubwfFBtfscStatus => pair!(SubwfF, BtfscStatus),
            K::MovfWBtfssZ => pair!(MovfW, BtfssZ),
            K::IncfFGoto => pair!(IncfF, Goto),
            K::MovwfBsf => pair!(Movwf, Bsf),
            K::MovwfBcf => pair!(Movwf, Bcf),
            K::MovfWIndfMovwf => pair!(MovfWIndf, Movwf),
            K::BcfStatusBtfsc => pair!(BcfStatus, Btfsc),
            K::IncfFBtfscZ => pair!(IncfF, BtfscZ),
            K::AddwfFGoto => pair!(AddwfF, Goto),
            K::AddwfWMovwf => pair!(AddwfW, Movwf),
            K::IncfFMovfWIndf => pair!(IncfF, MovfWIndf),
            K::BsfBtfss => pair!(Bsf, Btfss),
            K::MovlwAddwfW => pair!(Movlw, AddwfW),
            K::SubwfWBtfssZ => pair!(SubwfW, BtfssZ),
            K::RlfFMovlw => pair!(RlfF, Movlw),
            K::MovlwSubwfW => pair!(Movlw, SubwfW),
            K::BcfBtfssStatus => pair!(Bcf, BtfssStatus),
            K::SublwBtfssZ => pair!(Sublw, BtfssZ),
            K::BcfBtfssZ => pair!(Bcf, BtfssZ),
            K::BcfBtfss => pair!(Bcf, Btfss),
            K::MovlwBtfscStatus => pair!(Movlw, BtfscStatus),
            K::MovlwBtfssStatus => pair!(Movlw, BtfssStatus),
            K::DecfszFGoto => pair!(DecfszF, Goto),
            K::BtfssZGoto => pair!(BtfssZ, Goto),
            K::BtfscStatusGoto => pair!(BtfscStatus, Goto),
            K::BtfssStatusGoto => pair!(BtfssStatus, Goto),
            K::IncfszWAddwfF => pair!(IncfszW, AddwfF),
            K::IncfszWSubwfF => pair!(IncfszW, SubwfF),
            K::BtfssBcf => pair!(Btfss, Bcf),
            K::BtfssGoto => pair!(Btfss, Goto),
        }
        h.cycles += 1;
        Ok(())
    }

    /// Executes an instruction that cannot fail (`kind` a constant where inlined): its
    /// operands `a`, `k` (see [`Op`]); `h.pc` already points past it.
    #[inline(always)]
    fn simple(&mut self, h: &mut Hot, kind: Kind, target: u16, k: u8) {
        use Kind as K;
        let a = usize::from(target) & (RAM_SIZE - 1);
        match kind {
            K::AddwfW => h.w = h.add(self.ram[a], h.w),
            K::AddwfF => self.ram[a] = h.add(self.ram[a], h.w),
            K::AndwfW => {
                h.w &= self.ram[a];
                h.zv = h.w;
            }
            K::AndwfF => {
                let r = self.ram[a] & h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::Clrf => {
                self.ram[a] = 0;
                h.zv = 0;
            }
            K::Clrw => {
                h.w = 0;
                h.zv = 0;
            }
            K::ComfW => {
                h.w = !self.ram[a];
                h.zv = h.w;
            }
            K::ComfF => {
                let r = !self.ram[a];
                self.ram[a] = r;
                h.zv = r;
            }
            K::DecfW => {
                h.w = self.ram[a].wrapping_sub(1);
                h.zv = h.w;
            }
            K::DecfF => {
                let r = self.ram[a].wrapping_sub(1);
                self.ram[a] = r;
                h.zv = r;
            }
            K::DecfszW => {
                h.w = self.ram[a].wrapping_sub(1);
                if h.w == 0 {
                    skip(h);
                }
            }
            K::DecfszF => {
                let r = self.ram[a].wrapping_sub(1);
                self.ram[a] = r;
                if r == 0 {
                    skip(h);
                }
            }
            K::IncfW => {
                h.w = self.ram[a].wrapping_add(1);
                h.zv = h.w;
            }
            K::IncfF => {
                let r = self.ram[a].wrapping_add(1);
                self.ram[a] = r;
                h.zv = r;
            }
            K::IncfszW => {
                h.w = self.ram[a].wrapping_add(1);
                if h.w == 0 {
                    skip(h);
                }
            }
            K::IncfszF => {
                let r = self.ram[a].wrapping_add(1);
                self.ram[a] = r;
                if r == 0 {
                    skip(h);
                }
            }
            K::IorwfW => {
                h.w |= self.ram[a];
                h.zv = h.w;
            }
            K::IorwfF => {
                let r = self.ram[a] | h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::MovfW => {
                h.w = self.ram[a];
                h.zv = h.w;
            }
            K::MovfF => h.zv = self.ram[a],
            K::Movwf => self.ram[a] = h.w,
            K::Nop => {}
            K::RlfW => {
                let v = self.ram[a];
                h.w = v << 1 | (h.st & C);
                h.set_c(v >> 7);
            }
            K::RlfF => {
                let v = self.ram[a];
                self.ram[a] = v << 1 | (h.st & C);
                h.set_c(v >> 7);
            }
            K::RrfW => {
                let v = self.ram[a];
                h.w = v >> 1 | (h.st & C) << 7;
                h.set_c(v & 1);
            }
            K::RrfF => {
                let v = self.ram[a];
                self.ram[a] = v >> 1 | (h.st & C) << 7;
                h.set_c(v & 1);
            }
            K::SubwfW => h.w = h.sub(self.ram[a], h.w),
            K::SubwfF => self.ram[a] = h.sub(self.ram[a], h.w),
            K::SwapfW => h.w = self.ram[a].rotate_left(4),
            K::SwapfF => self.ram[a] = self.ram[a].rotate_left(4),
            K::XorwfW => {
                h.w ^= self.ram[a];
                h.zv = h.w;
            }
            K::XorwfF => {
                let r = self.ram[a] ^ h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::Bcf => self.ram[a] &= !k,
            K::Bsf => self.ram[a] |= k,
            K::Btfsc => {
                if self.ram[a] & k == 0 {
                    skip(h);
                }
            }
            K::Btfss => {
                if self.ram[a] & k != 0 {
                    skip(h);
                }
            }
            K::BcfStatus => h.set_st(h.st & !k),
            K::BsfStatus => h.set_st(h.st | k),
            K::BtfscStatus => {
                if h.st & k == 0 {
                    skip(h);
                }
            }
            K::BtfssStatus => {
                if h.st & k != 0 {
                    skip(h);
                }
            }
            K::BcfZ => h.zv = 1,
            K::BsfZ => h.zv = 0,
            K::BtfscZ => {
                if h.zv != 0 {
                    skip(h);
                }
            }
            K::BtfssZ => {
                if h.zv == 0 {
                    skip(h);
                }
            }
            K::MovfWIndf => {
                h.w = self.rd_indf(h);
                h.zv = h.w;
            }
            K::MovwfIndf => self.wr_indf(h, h.w, false),
            K::Addlw => h.w = h.add(k, h.w),
            K::Andlw => {
                h.w &= k;
                h.zv = h.w;
            }
            K::Iorlw => {
                h.w |= k;
                h.zv = h.w;
            }
            K::Xorlw => {
                h.w ^= k;
                h.zv = h.w;
            }
            K::Movlw => h.w = k,
            K::Sublw => h.w = h.sub(k, h.w),
            K::Goto => {
                h.pc = usize::from(self.ram[PCLATH as usize] & 0x18) << 8 | usize::from(target);
                h.cycles += 1;
            }
            K::Clrwdt => h.st |= 0x18,
            _ => unreachable!("{kind:?} is no simple instruction"),
        }
    }

    /// Executes a byte- or bit-oriented instruction `word` on any file address (the
    /// instruction's cycle is counted by the caller, `h.pc` already points past it).
    #[inline(never)]
    fn exec_slow(&mut self, word: u16) {
        let mut h = self.h;
        self.exec_file_op(&mut h, word);
        self.h = h;
    }

    fn exec_file_op(&mut self, h: &mut Hot, word: u16) {
        use Inst::*;
        let Some(i) = Inst::decode(word) else {
            unreachable!("slow op 0x{word:04X} is no instruction");
        };
        match i {
            Addwf(f, d)
            | Andwf(f, d)
            | Comf(f, d)
            | Decf(f, d)
            | Incf(f, d)
            | Iorwf(f, d)
            | Movf(f, d)
            | Rlf(f, d)
            | Rrf(f, d)
            | Subwf(f, d)
            | Xorwf(f, d) => {
                // The flags first: a write to STATUS keeps them (and takes its other
                // bits from the result), so the order does not matter.
                let a = h.addr(f);
                let v = self.rd(h, a);
                let r = match i {
                    Addwf(..) => h.add(v, h.w),
                    Subwf(..) => h.sub(v, h.w),
                    Rlf(..) => {
                        let r = v << 1 | (h.st & C);
                        h.set_c(v >> 7);
                        r
                    }
                    Rrf(..) => {
                        let r = v >> 1 | (h.st & C) << 7;
                        h.set_c(v & 1);
                        r
                    }
                    _ => {
                        let r = match i {
                            Andwf(..) => v & h.w,
                            Comf(..) => !v,
                            Decf(..) => v.wrapping_sub(1),
                            Incf(..) => v.wrapping_add(1),
                            Iorwf(..) => v | h.w,
                            Xorwf(..) => v ^ h.w,
                            _ => v,
                        };
                        h.zv = r;
                        r
                    }
                };
                if d == Dest::W {
                    h.w = r;
                } else {
                    self.wr(h, a, r, true);
                }
            }
            Decfsz(f, d) | Incfsz(f, d) | Swapf(f, d) => {
                let a = h.addr(f);
                let v = self.rd(h, a);
                let r = match i {
                    Decfsz(..) => v.wrapping_sub(1),
                    Incfsz(..) => v.wrapping_add(1),
                    _ => v.rotate_left(4),
                };
                if d == Dest::W {
                    h.w = r;
                } else {
                    self.wr(h, a, r, false);
                }
                if r == 0 && !matches!(i, Swapf(..)) {
                    skip(h);
                }
            }
            Clrf(f) => {
                self.wr(h, h.addr(f), 0, true);
                h.zv = 0;
            }
            Movwf(f) => self.wr(h, h.addr(f), h.w, false),
            Bcf(f, b) | Bsf(f, b) => {
                let a = h.addr(f);
                let m = 1u8 << (b & 7);
                let v = self.rd(h, a);
                let r = if matches!(i, Bcf(..)) { v & !m } else { v | m };
                self.wr(h, a, r, false);
            }
            Btfsc(f, b) | Btfss(f, b) => {
                let set = self.rd(h, h.addr(f)) & 1 << (b & 7) != 0;
                if set == matches!(i, Btfss(..)) {
                    skip(h);
                }
            }
            _ => unreachable!("slow op 0x{word:04X} is no file operation"),
        }
    }
}

/// Skips the next instruction: one extra cycle.
#[inline(always)]
fn skip(h: &mut Hot) {
    h.pc = (h.pc + 1) & 0x1FFF;
    h.cycles += 1;
}
