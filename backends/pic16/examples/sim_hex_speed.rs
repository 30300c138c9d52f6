//! Simulated cycles per second on a program given as Intel HEX (plcc's or SDCC's
//! output), run free; and, stepping one instruction at a time through the first
//! cycles, the share of executed instructions that are bank selects
//! (`bcf`/`bsf STATUS,RP0|RP1`).
//!
//! `cargo run --release -p plcc-pic16 --example sim_hex_speed PROG.hex [CYCLES [PROFILE_CYCLES]]`
//! (defaults 2e8 and 1e6). Prints `cycles_per_s = N` and `bank_selects = K of N`.

use plcc_pic16::isa::{reg, Inst};
use plcc_pic16::sim::Pic16;
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: sim_hex_speed PROG.hex [CYCLES [PROFILE_CYCLES]]");
    let num = |a: Option<String>, d: f64| {
        a.map(|c| c.parse::<f64>().expect("a number")).unwrap_or(d) as u64
    };
    let cycles = num(args.next(), 2e8);
    let profile = num(args.next(), 1e6);
    let text = std::fs::read_to_string(&path).expect("hex file");
    let words = Pic16::load_hex(&text).expect("Intel HEX");

    let mut sim = Pic16::new(&words);
    sim.reset();
    let t = Instant::now();
    sim.run_until(&[], cycles).expect("runs");
    let s = t.elapsed().as_secs_f64();
    println!("cycles = {}", sim.cycles());
    println!("seconds = {s:.3}");
    println!("cycles_per_s = {:.0}", sim.cycles() as f64 / s);

    let mut sim = Pic16::new(&words);
    sim.reset();
    let (mut executed, mut selects) = (0u64, 0u64);
    while sim.cycles() < profile {
        let pc = sim.pc() as usize;
        let word = words.get(pc).copied().unwrap_or(0x3FFF);
        sim.step().expect("runs");
        // An interrupt entry moves the PC to 4 without executing the word there.
        let decoded = Inst::decode(word);
        let entered_isr = sim.pc() == 4 && !matches!(decoded, Some(Inst::Goto(_) | Inst::Call(_)));
        if !entered_isr {
            executed += 1;
            if matches!(
                decoded,
                Some(Inst::Bcf(reg::STATUS, reg::RP0 | reg::RP1))
                    | Some(Inst::Bsf(reg::STATUS, reg::RP0 | reg::RP1))
            ) {
                selects += 1;
            }
        }
    }
    println!("bank_selects = {selects} of {executed}");
}
