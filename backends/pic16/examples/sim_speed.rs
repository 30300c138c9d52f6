//! Simulated cycles per second of the PIC16F876A simulator on a loop of straight-line
//! code (8- and 16-bit arithmetic on banked RAM, a skip, a counted loop), and on the
//! same loop with a Timer1/CCP1 tick interrupt every 1000 cycles.
//!
//! `cargo run --release -p plcc-pic16 --example sim_speed [CYCLES]` (default 2e9).

use plcc_pic16::isa::reg;
use plcc_pic16::isa::Dest::{F, W};
use plcc_pic16::isa::Inst::{self, *};
use plcc_pic16::sim::{Pic16, Stop};
use std::time::Instant;

fn program(with_irq: bool) -> Vec<u16> {
    let mut p: Vec<Inst> = vec![Goto(24), Nop, Nop, Nop];
    // ISR at 4: save W and STATUS, count ticks in 0x7D..0x7F, clear CCP1IF
    p.extend([
        Movwf(0x7B),
        Swapf(reg::STATUS, W),
        Clrf(reg::STATUS),
        Movwf(0x7C),
        Incf(0x7D, F),
        Btfsc(reg::STATUS, reg::Z),
        Incf(0x7E, F),
        Btfsc(reg::STATUS, reg::Z),
        Incf(0x7F, F),
        Bcf(reg::PIR1, reg::CCP1IF),
        Swapf(0x7C, W),
        Movwf(reg::STATUS),
        Swapf(0x7B, F),
        Swapf(0x7B, W),
        Retfie,
    ]);
    p.resize(24, Nop);
    // main at 24
    if with_irq {
        p.extend([
            Movlw(0xE8), // CCPR1 = 1000
            Movwf(reg::CCPR1L),
            Movlw(0x03),
            Movwf(reg::CCPR1H),
            Movlw(0x0B),
            Movwf(reg::CCP1CON),
            Bsf(reg::STATUS, reg::RP0),
            Bsf(reg::PIE1, reg::CCP1IF),
            Bcf(reg::STATUS, reg::RP0),
            Movlw(0xC0),
            Movwf(reg::INTCON),
            Movlw(0x01),
            Movwf(reg::T1CON),
        ]);
    }
    let top = p.len() as u16;
    p.extend([
        Movf(0x20, W),
        Addwf(0x21, F),
        Btfsc(reg::STATUS, reg::C),
        Incf(0x22, F),
        Incf(0x23, F),
        Bsf(reg::STATUS, reg::RP0),
        Movf(0x21, W),
        Xorwf(0x25, F), // bank 1: 0xA5
        Rlf(0x26, F),
        Bcf(reg::STATUS, reg::RP0),
        Decfsz(0x24, F),
        Goto(top),
        Goto(top),
    ]);
    p.iter().map(|i| i.encode()).collect()
}

fn main() {
    let cycles: u64 = std::env::args()
        .nth(1)
        .map(|a| a.parse::<f64>().expect("CYCLES") as u64)
        .unwrap_or(2_000_000_000);
    for (name, irq) in [
        ("straight-line loop", false),
        ("loop + 1 kHz tick interrupt", true),
    ] {
        let mut chip = Pic16::new(&program(irq));
        chip.write(0x20, 3);
        let t = Instant::now();
        let stop = chip.run_until(&[], cycles).expect("runs");
        let dt = t.elapsed().as_secs_f64();
        assert_eq!(stop, Stop::CycleLimit);
        println!(
            "{name}: {} cycles in {dt:.3} s = {:.0} M simulated cycles/s (ticks: {})",
            chip.cycles(),
            chip.cycles() as f64 / dt / 1e6,
            (0..3)
                .map(|i| u32::from(chip.read(0x7D + i)) << (8 * i))
                .sum::<u32>()
        );
    }
}
