//! Unit tests of the simulator. The timing tests reproduce runs of gpsim 0.31 (the
//! expected numbers were read off gpsim cycle by cycle).

use super::*;
use crate::isa::reg;
use crate::isa::Dest::{F, W};
use crate::isa::Inst::{self, *};

const GIE: u8 = reg::GIE;
const ST: u16 = reg::STATUS;

fn words(insts: &[Inst]) -> Vec<u16> {
    insts.iter().map(|i| i.encode()).collect()
}

fn chip(insts: &[Inst]) -> Pic16 {
    Pic16::new(&words(insts))
}

/// Runs `insts` until the PC reaches the end of the program.
fn run(insts: &[Inst]) -> Pic16 {
    let mut p = chip(insts);
    let end = insts.len() as u16;
    assert_eq!(p.run_until(&[end], 100_000), Ok(Stop::Breakpoint(end)));
    p
}

fn flags(p: &Pic16) -> (bool, bool, bool) {
    let s = p.read(ST);
    (s & C != 0, s & DC != 0, s & Z != 0)
}

/// Executes one instruction on fresh operands: f = 0x20 holds `f`, W holds `w`,
/// STATUS<C> = `c`.
fn one(p: &mut Pic16, f: u8, w: u8, c: bool) {
    p.write(0x20, f);
    p.set_w(w);
    let s = p.read(ST);
    p.write(ST, (s & !C) | u8::from(c));
    p.set_pc(0);
    p.step().unwrap();
}

#[test]
fn add_and_subtract_flags_match_a_reference_for_all_operands() {
    let mut add = chip(&[Addwf(0x20, W)]);
    let mut addf = chip(&[Addwf(0x20, F)]);
    let mut sub = chip(&[Subwf(0x20, W)]);
    let mut subf = chip(&[Subwf(0x20, F)]);
    for a in 0..=255u8 {
        for b in 0..=255u8 {
            // ADD: a + b
            let sum = u16::from(a) + u16::from(b);
            let want = (sum > 0xFF, (a & 0xF) + (b & 0xF) > 0xF, sum & 0xFF == 0);
            one(&mut add, a, b, false);
            assert_eq!((add.w(), flags(&add)), (sum as u8, want), "addwf {a} {b}");
            one(&mut addf, a, b, true);
            assert_eq!(
                (addf.read(0x20), addf.w(), flags(&addf)),
                (sum as u8, b, want)
            );
            // SUB: a - b computed as a + !b + 1 (the ALU's way)
            let d = u16::from(a) + u16::from(!b) + 1;
            let want = (d > 0xFF, (a & 0xF) + (!b & 0xF) + 1 > 0xF, d & 0xFF == 0);
            one(&mut sub, a, b, false);
            assert_eq!((sub.w(), flags(&sub)), (d as u8, want), "subwf {a} {b}");
            one(&mut subf, a, b, true);
            assert_eq!((subf.read(0x20), flags(&subf)), (d as u8, want));
        }
    }
}

#[test]
fn literal_arithmetic_flags() {
    // (instruction, W before, W after, C, DC, Z)
    let cases = [
        (Addlw(0x01), 0xFF, 0x00, true, true, true),
        (Addlw(0x08), 0x08, 0x10, false, true, false),
        (Addlw(0x80), 0x80, 0x00, true, false, true),
        (Addlw(0x12), 0x34, 0x46, false, false, false),
        (Sublw(0x05), 0x03, 0x02, true, true, false),
        (Sublw(0x03), 0x05, 0xFE, false, false, false),
        (Sublw(0x05), 0x05, 0x00, true, true, true),
        (Sublw(0x10), 0x01, 0x0F, true, false, false),
        (Sublw(0x00), 0x00, 0x00, true, true, true),
        (Sublw(0x00), 0x01, 0xFF, false, false, false),
    ];
    for (i, w0, w1, c, dc, z) in cases {
        let mut p = chip(&[i]);
        one(&mut p, 0, w0, !c);
        assert_eq!((p.w(), flags(&p)), (w1, (c, dc, z)), "{i:?} with W={w0:#x}");
    }
}

#[test]
fn logic_and_rotate_instructions() {
    let (c0, c1) = (false, true);
    /// (instruction, f, W, C before, W after, f after, C after, Z after)
    type Case = (Inst, u8, u8, bool, u8, u8, bool, bool);
    let cases: [Case; 20] = [
        (Andwf(0x20, W), 0xF0, 0x3C, c0, 0x30, 0xF0, c0, false),
        (Andwf(0x20, F), 0xF0, 0x0F, c1, 0x0F, 0x00, c1, true),
        (Iorwf(0x20, W), 0x00, 0x00, c0, 0x00, 0x00, c0, true),
        (Iorwf(0x20, F), 0x50, 0x05, c0, 0x05, 0x55, c0, false),
        (Xorwf(0x20, W), 0xAA, 0xAA, c0, 0x00, 0xAA, c0, true),
        (Xorwf(0x20, F), 0xAA, 0x55, c0, 0x55, 0xFF, c0, false),
        (Comf(0x20, W), 0xFF, 0x12, c0, 0x00, 0xFF, c0, true),
        (Comf(0x20, F), 0x0F, 0x12, c1, 0x12, 0xF0, c1, false),
        (Decf(0x20, W), 0x01, 0x12, c0, 0x00, 0x01, c0, true),
        (Decf(0x20, F), 0x00, 0x12, c0, 0x12, 0xFF, c0, false),
        (Incf(0x20, W), 0xFF, 0x12, c0, 0x00, 0xFF, c0, true),
        (Incf(0x20, F), 0x7F, 0x12, c1, 0x12, 0x80, c1, false),
        (Movf(0x20, W), 0x00, 0x12, c0, 0x00, 0x00, c0, true),
        (Movf(0x20, F), 0x34, 0x12, c0, 0x12, 0x34, c0, false),
        (Rlf(0x20, W), 0x80, 0x12, c0, 0x00, 0x80, c1, false),
        (Rlf(0x20, F), 0x41, 0x12, c1, 0x12, 0x83, c0, false),
        (Rrf(0x20, W), 0x01, 0x12, c0, 0x00, 0x01, c1, false),
        (Rrf(0x20, F), 0x82, 0x12, c1, 0x12, 0xC1, c0, false),
        (Swapf(0x20, W), 0xA5, 0x12, c0, 0x5A, 0xA5, c0, false),
        (Swapf(0x20, F), 0xA5, 0x12, c1, 0x12, 0x5A, c1, false),
    ];
    for (i, f, w, c, w1, f1, c1_, z) in cases {
        let mut p = chip(&[i]);
        // Z starts opposite to what a Z-setting instruction must leave
        let s = p.read(ST);
        p.write(ST, (s & !Z) | if z { 0 } else { Z });
        one(&mut p, f, w, c);
        let (c_after, _, z_after) = flags(&p);
        assert_eq!((p.w(), p.read(0x20), c_after), (w1, f1, c1_), "{i:?}");
        let sets_z = !matches!(i, Rlf(..) | Rrf(..) | Swapf(..));
        if sets_z {
            assert_eq!(z_after, z, "Z after {i:?}");
        } else {
            assert_eq!(z_after, !z, "{i:?} must not touch Z");
        }
        assert_eq!(p.cycles(), 1);
    }
    let p = run(&[Movlw(0x55), Clrw]);
    assert_eq!((p.w(), flags(&p).2), (0, true));
    let p = run(&[Movlw(0x55), Movwf(0x21), Clrf(0x21)]);
    assert_eq!((p.read(0x21), flags(&p).2), (0, true));
}

#[test]
fn status_as_destination() {
    // CLRF STATUS: 000u u1uu (C, DC kept; PD/TO read-only)
    let p = run(&[Movlw(0x03), Addlw(0xFF), Clrf(ST)]);
    assert_eq!(p.read(ST), 0x18 | Z | C | DC);
    // MOVWF STATUS writes IRP/RP and the flags, not TO/PD
    let p = run(&[Movlw(0xE7), Movwf(ST)]);
    assert_eq!(p.read(ST), 0xE7 | 0x18);
    let p = run(&[Movlw(0x00), Movwf(ST)]);
    assert_eq!(p.read(ST), 0x18);
    // BSF RP0 selects bank 1: MOVWF 0x20 then writes 0xA0
    let p = run(&[Bsf(ST, reg::RP0), Movlw(9), Movwf(0x20), Bcf(ST, reg::RP0)]);
    assert_eq!((p.read(0xA0), p.read(0x20)), (9, 0));
    // ADDWF STATUS,F: Z/DC/C come from the addition, the written value is ignored for them
    let p = run(&[Movlw(0x20), Addwf(ST, F)]);
    assert_eq!(p.read(ST) & 0xE7, 0x38 & 0xE0);
    // CLRWDT sets TO and PD
    let p = run(&[Clrwdt]);
    assert_eq!(p.read(ST) & 0x18, 0x18);
}

#[test]
fn skips_and_their_cycles() {
    // DECFSZ: 2 -> 1 no skip, 1 -> 0 skip
    let prog = [
        Movlw(2),
        Movwf(0x20),
        Decfsz(0x20, F), // 2: 1 cycle
        Incf(0x21, F),   // executed
        Decfsz(0x20, F), // 4: skip, 2 cycles
        Incf(0x22, F),   // skipped
        Incfsz(0x23, W), // 6: 0 -> 1 in W, no skip
        Incf(0x24, F),
        Movlw(0xFF),
        Movwf(0x25),
        Incfsz(0x25, F), // skip
        Incf(0x26, F),
        Btfsc(0x25, 0), // bit clear: skip
        Incf(0x27, F),
        Btfss(0x25, 0), // bit clear: no skip
        Incf(0x28, F),
        Decfsz(0x25, W), // 0xFF in W: no skip
        Nop,
    ];
    let p = run(&prog);
    let got: Vec<u8> = (0x20..=0x28).map(|a| p.read(a)).collect();
    assert_eq!(got, [0, 1, 0, 0, 1, 0, 0, 0, 1]);
    assert_eq!(p.w(), 0xFF);
    // 18 instructions, 3 skipped, each skip costs one more cycle
    assert_eq!(p.cycles(), 18 - 3 + 3);
}

#[test]
fn call_return_depth_and_overflow() {
    // main calls f1, f1 calls f2, ... f7: depth 7; RETLW returns a value
    let mut prog = vec![Call(3), Goto(2), Goto(2)];
    for d in 0..7u16 {
        if d < 6 {
            prog.push(Call(3 + 2 * (d + 1)));
            prog.push(Return);
        } else {
            prog.push(Retlw(0x42));
            prog.push(Nop);
        }
    }
    let mut p = chip(&prog);
    assert_eq!(p.run_until(&[2], 1000), Ok(Stop::Breakpoint(2)));
    assert_eq!(p.max_stack_depth(), 7);
    assert_eq!(p.stack_depth(), 0);
    assert_eq!(p.w(), 0x42, "RETURN leaves W as the innermost RETLW set it");
    // 2 cycles each: 7 CALLs, 6 RETURNs, 1 RETLW, then GOTO 2
    assert_eq!(p.cycles(), 30);

    // 9 nested calls: the 9th overflows
    let prog: Vec<Inst> = (0..10).map(|i| Call(i + 1)).collect();
    let mut p = chip(&prog);
    let e = p.run_until(&[], 1000).unwrap_err();
    assert_eq!(e.0, "hardware stack overflow: 9 levels at 0x0008");
    assert_eq!(p.pc(), 8);
    assert_eq!(p.max_stack_depth(), 8);

    let mut p = chip(&[Nop, Return]);
    let e = p.run_until(&[], 1000).unwrap_err();
    assert_eq!(e.to_string(), "RETURN with an empty stack at 0x0001");
    let mut p = chip(&[Sleep]);
    assert_eq!(p.step().unwrap_err().0, "SLEEP executed at 0x0000");
    let mut p = Pic16::new(&[0x0001]);
    assert_eq!(
        p.step().unwrap_err().0,
        "invalid instruction word 0x0001 at 0x0000"
    );
}

#[test]
fn pcl_writes_use_pclath() {
    // computed jump: W = 2 -> ADDWF PCL lands on the third RETLW
    let mut prog = vec![
        Movlw(2),
        Call(4),
        Movwf(0x20),
        Goto(3),
        Addwf(reg::PCL, F), // 4: PCL reads 5
        Retlw(10),
        Retlw(11),
        Retlw(12),
        Retlw(13),
    ];
    let mut p = chip(&prog);
    assert_eq!(p.run_until(&[3], 1000), Ok(Stop::Breakpoint(3)));
    assert_eq!(p.read(0x20), 12);
    // movlw, call 2, addwf PCL 2, retlw 2, movwf
    assert_eq!(p.cycles(), 8);

    // MOVWF PCL with PCLATH = 0x01 jumps to 0x1xx; MOVF PCL reads the next address
    prog = vec![
        Movlw(0x01),
        Movwf(reg::PCLATH),
        Movlw(0x10),
        Movwf(reg::PCL), // -> 0x110
    ];
    let mut words = words(&prog);
    words.resize(0x110, 0);
    words.push(Movf(reg::PCL, W).encode()); // 0x110: W = 0x11
    words.push(Movwf(0x21).encode());
    let mut p = Pic16::new(&words);
    assert_eq!(p.run_until(&[0x112], 1000), Ok(Stop::Breakpoint(0x112)));
    assert_eq!(p.read(0x21), 0x11);
    assert_eq!(p.cycles(), 1 + 1 + 1 + 2 + 1 + 1);

    // GOTO/CALL take PCLATH<4:3>: PCLATH = 0x0F -> page 1 (0x800)
    let mut words = super::tests::words(&[Movlw(0x0F), Movwf(reg::PCLATH), Call(0x005)]);
    words.resize(0x805, 0);
    words.push(Retlw(0x77).encode());
    let mut p = Pic16::new(&words);
    assert_eq!(p.run_until(&[3], 1000), Ok(Stop::Breakpoint(3)));
    assert_eq!((p.w(), p.max_stack_depth()), (0x77, 1));
}

#[test]
fn banks_mirrors_and_unimplemented_addresses() {
    let mut p = chip(&[]);
    p.write(0x70, 0x11);
    for a in [0x70, 0xF0, 0x170, 0x1F0] {
        assert_eq!(p.read(a), 0x11);
    }
    p.write(0x1FF, 0x22);
    assert_eq!(p.read(0x7F), 0x22);
    p.write(0x0A, 0xFF);
    assert_eq!(p.read(0x18A), 0x1F, "PCLATH mirrors, 5 bits");
    p.write(0x183, 0x18 | 0x60);
    assert_eq!(p.read(0x03), 0x78);
    p.write(0x03, 0x18);
    p.write(0x186, 0x0F);
    assert_eq!(p.read(0x86), 0x0F, "TRISB at 0x186");
    p.write(0x106, 0x05);
    assert_eq!(p.read(0x06) & !0x0F, 0, "PORTB at 0x106 (inputs read low)");
    assert_eq!(p.read(0x06) & 0x0F, 0, "inputs low");
    for a in [0x08, 0x09, 0x88, 0x8F, 0x105, 0x107, 0x18E] {
        p.write(a, 0x5A);
        assert_eq!(p.read(a), 0, "unimplemented {a:#x}");
    }
    // direct addressing in every bank
    let p = run(&[
        Movlw(1),
        Movwf(0x30), // bank 0: 0x30
        Bsf(ST, reg::RP0),
        Movlw(2),
        Movwf(0x30), // bank 1: 0xB0
        Bsf(ST, reg::RP1),
        Movlw(3),
        Movwf(0x30), // bank 3: 0x1B0
        Bcf(ST, reg::RP0),
        Movlw(4),
        Movwf(0x30), // bank 2: 0x130
        Movwf(0x75), // common
        Movlw(5),
        Movwf(0x10), // bank 2: 0x110 is RAM
        Bcf(ST, reg::RP1),
    ]);
    let got: Vec<u8> = [0x30, 0xB0, 0x130, 0x1B0, 0x75, 0x110]
        .iter()
        .map(|&a| p.read(a))
        .collect();
    assert_eq!(got, [1, 2, 4, 3, 4, 5]);
    assert_eq!(p.read(0x10), 0, "T1CON untouched");
}

#[test]
fn indirect_addressing() {
    let p = run(&[
        Movlw(0x20),
        Movwf(reg::FSR),
        Movlw(0xAB),
        Movwf(reg::INDF), // 0x20
        Incf(reg::FSR, F),
        Movwf(reg::INDF), // 0x21
        Bsf(ST, reg::IRP),
        Movlw(0x10),
        Movwf(reg::FSR),
        Movlw(0xCD),
        Movwf(reg::INDF), // 0x110
        Movlw(0xA0),
        Movwf(reg::FSR),
        Movlw(0xEF),
        Movwf(reg::INDF), // 0x1A0
        Movlw(0xF3),
        Movwf(reg::FSR),
        Movlw(0x99),
        Movwf(reg::INDF), // 0x1F3 = 0x73
        Bcf(ST, reg::IRP),
        Clrf(reg::FSR),
        Movlw(0x55),
        Movwf(reg::INDF),   // FSR = 0: nothing
        Movf(reg::INDF, W), // reads 0
        Movwf(0x30),
        Movlw(0x83),
        Movwf(reg::FSR),
        Movf(reg::INDF, W), // STATUS through INDF
        Movwf(0x31),
    ]);
    let got: Vec<u8> = [0x20, 0x21, 0x110, 0x1A0, 0x73, 0x30]
        .iter()
        .map(|&a| p.read(a))
        .collect();
    assert_eq!(got, [0xAB, 0xAB, 0xCD, 0xEF, 0x99, 0]);
    assert_eq!(p.read(0x31), 0x18 | Z, "MOVF INDF,W of 0 set Z just before");
    assert_eq!(p.read(reg::INDF), 0, "host reads of INDF give 0");
}

#[test]
fn ports_tris_and_adcon1() {
    let mut p = chip(&[]);
    // PORTB: high nibble input, low nibble output
    p.write(reg::TRISB, 0xF0);
    p.write(reg::PORTB, 0x5A);
    p.set_input(Port::B, 7, true);
    p.set_input(Port::B, 0, true); // output pin: the latch wins
    assert_eq!(p.read(reg::PORTB), 0x8A);
    assert!(p.output(Port::B, 1) && !p.output(Port::B, 0));
    assert!(!p.output(Port::B, 6), "input pins are not driven");
    // PORTA is analog at reset
    p.set_input(Port::A, 0, true);
    p.set_input(Port::A, 4, true);
    assert_eq!(p.read(reg::PORTA), 0x10, "RA4 has no analog function");
    p.write(reg::ADCON1, 0x06);
    assert_eq!(p.read(reg::PORTA), 0x11);
    p.write(reg::ADCON1, 0x0E);
    assert_eq!(p.read(reg::PORTA), 0x10, "AN0 analog");
    assert_eq!(p.read(reg::TRISA), 0x3F);

    // read-modify-write on PORTC reads the pins: an input pin that is high gets latched
    let mut p = chip(&[
        Bsf(ST, reg::RP0),
        Movlw(0x0F),
        Movwf(reg::TRISC),
        Bcf(ST, reg::RP0),
        Clrf(reg::PORTC),
        Bsf(reg::PORTC, 7),
        Bsf(ST, reg::RP0),
        Clrf(reg::TRISC),
        Bcf(ST, reg::RP0),
    ]);
    p.set_input(Port::C, 1, true);
    assert_eq!(p.run_until(&[9], 100), Ok(Stop::Breakpoint(9)));
    assert_eq!(p.read(reg::PORTC), 0x82);
    assert!(p.output(Port::C, 1) && p.output(Port::C, 7));
}

#[test]
fn rb0_edge_raises_intf() {
    let mut p = chip(&[
        Goto(0),
        Nop,
        Nop,
        Nop,
        Incf(0x70, F),
        Bcf(reg::INTCON, 1),
        Retfie,
    ]);
    p.write(reg::INTCON, 0x90); // GIE, INTE
    p.set_input(Port::B, 0, true); // rising edge, INTEDG = 1 at reset
    assert_eq!(p.run_until(&[6], 100), Ok(Stop::Breakpoint(6)));
    assert_eq!(p.read(0x70), 1);
}

/// Runs a program instruction by instruction and records (cycles, value of `addr`)
/// before each instruction.
fn trace(p: &mut Pic16, steps: usize, addr: u16) -> Vec<(u64, u8)> {
    (0..steps)
        .map(|_| {
            let r = (p.cycles(), p.read(addr));
            p.step().unwrap();
            r
        })
        .collect()
}

fn value_at(t: &[(u64, u8)], cycle: u64) -> u8 {
    t.iter().find(|(c, _)| *c == cycle).unwrap().1
}

#[test]
fn timer1_reads_and_writes_match_gpsim() {
    let prog = [
        Clrf(reg::TMR1L),
        Clrf(reg::TMR1H),
        Movlw(1),
        Movwf(reg::T1CON), // cycle 3
        Movf(reg::TMR1L, W),
        Movwf(0x20),
        Movf(reg::TMR1L, W),
        Movwf(0x21),
        Nop,
        Nop,
        Movf(reg::TMR1L, W),
        Movwf(0x22),
        Movlw(0x50),
        Movwf(reg::TMR1L), // cycle 13
        Movf(reg::TMR1L, W),
        Movwf(0x23),
        Movf(reg::TMR1L, W),
        Movwf(0x24),
    ];
    let p = run(&prog);
    let got: Vec<u8> = (0x20..=0x24).map(|a| p.read(a)).collect();
    assert_eq!(got, [1, 3, 7, 0x51, 0x53]);
    assert_eq!(p.cycles(), 18);
}

#[test]
fn ccp1_special_event_matches_gpsim() {
    // CCPR1 = 10, prescale 1: CCP1IF polled (gpsim: 34 cycles, TMR1L 5 then 3)
    let prog = [
        Clrf(reg::TMR1L),
        Clrf(reg::TMR1H),
        Movlw(10),
        Movwf(reg::CCPR1L),
        Clrf(reg::CCPR1H),
        Movlw(0x0B),
        Movwf(reg::CCP1CON),
        Clrf(reg::PIR1),
        Movlw(1),
        Movwf(reg::T1CON),   // 9
        Btfss(reg::PIR1, 2), // 10: loop
        Goto(10),
        Movf(reg::TMR1L, W),
        Movwf(0x20),
        Bcf(reg::PIR1, 2),
        Btfss(reg::PIR1, 2), // 15
        Goto(15),
        Movf(reg::TMR1L, W),
        Movwf(0x21),
    ];
    let p = run(&prog);
    assert_eq!((p.read(0x20), p.read(0x21), p.cycles()), (5, 3, 34));

    // CCPR1 = 3, prescale 1:8, T1CON written at cycle 6
    let mut prog = vec![
        Movlw(3),
        Movwf(reg::CCPR1L),
        Clrf(reg::CCPR1H),
        Movlw(0x0B),
        Movwf(reg::CCP1CON),
        Movlw(0x31),
        Movwf(reg::T1CON),
    ];
    prog.resize(80, Nop);
    let mut p = chip(&prog);
    let t = trace(&mut p, 70, reg::TMR1L);
    let mut pc = chip(&prog);
    let f = trace(&mut pc, 70, reg::PIR1);
    let expect = [
        (13, 0, 0),
        (14, 1, 0),
        (22, 2, 0),
        (30, 3, 0),
        (31, 0, 4),
        (37, 0, 4),
        (38, 1, 4),
        (54, 3, 4),
        (55, 0, 4),
    ];
    for (c, v, fl) in expect {
        assert_eq!((value_at(&t, c), value_at(&f, c)), (v, fl), "cycle {c}");
    }
}

#[test]
fn timer1_overflow_and_prescaler_restart_match_gpsim() {
    // TMR1 = 0xFFFE, 1:8 from cycle 6: 0xFFFF at 14, 0 at 22, TMR1IF at 23
    let mut prog = vec![
        Movlw(0xFE),
        Movwf(reg::TMR1L),
        Comf(reg::TMR1H, F),
        Nop,
        Nop,
        Movlw(0x31),
        Movwf(reg::T1CON),
    ];
    prog.resize(60, Nop);
    let t = trace(&mut chip(&prog), 50, reg::TMR1L);
    let f = trace(&mut chip(&prog), 50, reg::PIR1);
    for (c, v, fl) in [
        (13, 0xFE, 0),
        (14, 0xFF, 0),
        (21, 0xFF, 0),
        (22, 0, 0),
        (23, 0, 1),
        (30, 1, 1),
    ] {
        assert_eq!((value_at(&t, c), value_at(&f, c)), (v, fl), "cycle {c}");
    }
    // a T1CON write restarts the prescaler: 1:8 from cycle 6, BSF T1CON,3 at cycle 40
    let mut prog = vec![Nop; 64];
    prog[5] = Movlw(0x31);
    prog[6] = Movwf(reg::T1CON);
    prog[40] = Bsf(reg::T1CON, 3);
    let t = trace(&mut chip(&prog), 60, reg::TMR1L);
    for (c, v) in [(37, 3), (38, 4), (47, 4), (48, 5), (56, 6)] {
        assert_eq!(value_at(&t, c), v, "cycle {c}");
    }
}

#[test]
fn timer0_matches_gpsim() {
    let mut prog = vec![
        Bsf(ST, reg::RP0),
        Movlw(0x88),
        Movwf(reg::OPTION_REG), // 2: internal clock, no prescaler
        Bcf(ST, reg::RP0),
        Movlw(0xF8),
        Movwf(reg::TMR0), // 5
    ];
    prog.resize(40, Nop);
    let t = trace(&mut chip(&prog), 30, reg::TMR0);
    let f = trace(&mut chip(&prog), 30, reg::INTCON);
    for (c, v, fl) in [
        (3, 1, 0),
        (5, 3, 0),
        (6, 0xF8, 0),
        (7, 0xF8, 0),
        (8, 0xF9, 0),
        (14, 0xFF, 0),
        (15, 0, 4),
        (16, 1, 4),
    ] {
        assert_eq!((value_at(&t, c), value_at(&f, c)), (v, fl), "cycle {c}");
    }
    // 1:4 prescaler, TMR0 written at cycle 43: two inhibited cycles, then 4 per tick
    let mut prog = vec![Nop; 64];
    prog[0] = Bsf(ST, reg::RP0);
    prog[1] = Movlw(0x81);
    prog[2] = Movwf(reg::OPTION_REG);
    prog[3] = Bcf(ST, reg::RP0);
    prog[42] = Movlw(0x10);
    prog[43] = Movwf(reg::TMR0);
    let t = trace(&mut chip(&prog), 60, reg::TMR0);
    for (c, v) in [(44, 0x10), (48, 0x10), (49, 0x11), (52, 0x11), (53, 0x12)] {
        assert_eq!(value_at(&t, c), v, "cycle {c}");
    }
}

/// ISR at 4: INCF 0x70; BCF PIR1,TMR1IF (when `clear`); RETFIE.
fn with_isr(main: &[Inst], clear: bool) -> Vec<Inst> {
    let mut v = vec![Goto(8), Nop, Nop, Nop, Incf(0x70, F)];
    v.push(if clear { Bcf(reg::PIR1, 0) } else { Nop });
    v.push(Retfie);
    v.push(Nop);
    v.extend_from_slice(main);
    v
}

fn enable_tmr1_irq() -> Vec<Inst> {
    vec![
        Bsf(ST, reg::RP0),
        Bsf(reg::PIE1, 0),
        Bcf(ST, reg::RP0),
        Movlw(0xC0),
        Movwf(reg::INTCON),
    ]
}

#[test]
fn interrupt_entry_and_retfie_match_gpsim() {
    // BSF PIR1,TMR1IF at cycle 7: first ISR instruction at cycle 9
    let mut main = enable_tmr1_irq();
    main.push(Bsf(reg::PIR1, 0)); // 13
    main.extend([
        Nop,
        Nop,
        Nop,
        Nop,
        Bcf(reg::INTCON, GIE),
        Bsf(reg::PIR1, 0),
        Nop,
    ]);
    main.push(Bsf(reg::INTCON, GIE)); // 20
    main.extend([Nop, Nop]);
    let prog = with_isr(&main, true);
    let mut p = chip(&prog);
    assert_eq!(p.run_until(&[4], 100), Ok(Stop::Breakpoint(4)));
    assert_eq!((p.cycles(), p.stack_depth()), (9, 1));
    assert_eq!(p.read(reg::INTCON) & 0x80, 0, "GIE cleared on entry");
    assert_eq!(p.run_until(&[4], 100), Ok(Stop::Breakpoint(4)));
    assert_eq!(p.cycles(), 22, "BSF GIE at 20 with a flag pending");
    let end = prog.len() as u16;
    assert_eq!(p.run_until(&[end], 100), Ok(Stop::Breakpoint(end)));
    assert_eq!(p.read(reg::INTCON) & 0x80, 0x80, "RETFIE sets GIE");
    assert_eq!((p.read(0x70), p.max_stack_depth()), (2, 1));

    // RETFIE with the flag still set: re-entry in RETFIE's second cycle
    let mut main = vec![Clrf(0x70)];
    main.extend(enable_tmr1_irq());
    main.push(Bsf(reg::PIR1, 0)); // 14 at cycle 8
    main.push(Nop);
    main.push(Goto(16));
    let mut prog = vec![
        Goto(8),
        Nop,
        Nop,
        Nop,
        Incf(0x70, F),
        Btfsc(0x70, 1),
        Bcf(reg::PIR1, 0),
        Retfie,
    ];
    prog.extend(main);
    let mut p = chip(&prog);
    let mut entries = Vec::new();
    for _ in 0..3 {
        if p.run_until(&[4], 100) == Ok(Stop::Breakpoint(4)) {
            entries.push(p.cycles());
        }
    }
    assert_eq!(entries, [10, 15]);
}

#[test]
fn timer1_interrupt_latency_matches_gpsim() {
    // TMR1 = 0xFFF0 / 0xFFF1, on at cycle 12, main loop `goto $`
    for (start, isr_at) in [(0xF0, 30), (0xF1, 29)] {
        let mut main = vec![
            Movlw(start),
            Movwf(reg::TMR1L),
            Movlw(0xFF),
            Movwf(reg::TMR1H),
        ];
        main.extend(enable_tmr1_irq());
        main.extend([Movlw(1), Movwf(reg::T1CON)]);
        let here = 8 + main.len() as u16;
        main.push(Goto(here));
        let mut p = chip(&with_isr(&main, true));
        assert_eq!(p.run_until(&[4], 100), Ok(Stop::Breakpoint(4)));
        assert_eq!(p.cycles(), isr_at, "TMR1 from {start:#x}");
    }
}

#[test]
fn timer0_interrupt_latency_matches_gpsim() {
    // OPTION_REG written at cycle 4: TMR0 wraps at 260, T0IF is readable then, the
    // first ISR instruction runs at 262 (as in gpsim with this main loop); with no
    // reload, TMR0 then wraps every 256 cycles
    let mut prog = vec![
        Goto(8),
        Nop,
        Nop,
        Nop,
        Bcf(reg::INTCON, 2),
        Retfie,
        Nop,
        Nop,
    ];
    prog.extend([
        Bsf(ST, reg::RP0),
        Movlw(0x88),
        Movwf(reg::OPTION_REG),
        Bcf(ST, reg::RP0),
        Movlw(0xA0),
        Movwf(reg::INTCON),
        Incf(0x70, F), // 14: loop
        Movf(0x71, W),
        Xorlw(20),
        Btfss(ST, reg::Z),
        Goto(14),
    ]);
    let mut p = chip(&prog);
    let mut entries = Vec::new();
    for _ in 0..3 {
        assert_eq!(p.run_until(&[4], 1000), Ok(Stop::Breakpoint(4)));
        entries.push(p.cycles());
    }
    assert_eq!(entries[0], 262);
    assert!(
        entries.windows(2).all(|w| w[1] - w[0] == 256),
        "{entries:?}"
    );
}

#[test]
fn run_until_semantics() {
    let mut p = chip(&[Nop, Nop, Goto(0)]);
    // the PC is at a stop address: at least one instruction runs first
    assert_eq!(p.run_until(&[0], 100), Ok(Stop::Breakpoint(0)));
    assert_eq!(p.cycles(), 4);
    assert_eq!(p.run_until(&[5], 0), Ok(Stop::CycleLimit));
    assert_eq!(p.run_until(&[5], 10), Ok(Stop::CycleLimit));
    assert_eq!(p.cycles(), 14);
    // a 2-cycle instruction can end one cycle past the budget
    assert_eq!(p.run_until(&[], 2), Ok(Stop::CycleLimit));
    assert_eq!(p.cycles(), 16);
    assert_eq!(p.run_until(&[], 1), Ok(Stop::CycleLimit));
    assert_eq!((p.cycles(), p.pc()), (17, 1));
    // breakpoints are gone after the call
    assert_eq!(p.run_until(&[2], 10), Ok(Stop::Breakpoint(2)));
    p.step().unwrap();
    assert_eq!(p.pc(), 0);
}

#[test]
fn fused_pairs_run_one_instruction_at_a_time_where_they_must() {
    // MOVF/MOVWF at 1 and 2 are one op in the run loop
    let prog = [Nop, Movf(0x20, W), Movwf(0x21), Goto(0)];
    let mut p = chip(&prog);
    p.write(0x20, 0x5A);
    // a stop address on the second instruction: the first runs alone
    assert_eq!(p.run_until(&[2], 100), Ok(Stop::Breakpoint(2)));
    assert_eq!((p.cycles(), p.w(), p.read(0x21)), (2, 0x5A, 0));
    assert_eq!(p.run_until(&[], 1), Ok(Stop::CycleLimit));
    assert_eq!((p.cycles(), p.pc(), p.read(0x21)), (3, 3, 0x5A));
    // the cycle budget ends between the two
    let mut p = chip(&prog);
    assert_eq!(p.run_until(&[], 2), Ok(Stop::CycleLimit));
    assert_eq!((p.cycles(), p.pc()), (2, 2));
    // so does step
    p.set_pc(1);
    p.step().unwrap();
    assert_eq!(p.pc(), 2);
    // the pair runs whole again once the stop addresses are gone
    let mut p = chip(&prog);
    p.write(0x20, 7);
    assert_eq!(p.run_until(&[3], 100), Ok(Stop::Breakpoint(3)));
    assert_eq!((p.cycles(), p.read(0x21)), (3, 7));
}

#[test]
fn fused_pairs_see_the_bank_and_the_skip_of_the_first() {
    let mut p = run(&[
        Movlw(0x11),
        Bsf(ST, reg::RP0),
        Movwf(0x20), // 0xA0
        Bcf(ST, reg::C),
        Rlf(0x20, F), // 0xA0
        Bcf(ST, reg::RP0),
        Movlw(1),
        Movwf(0x21),
        Decfsz(0x21, F), // skips the GOTO
        Goto(0),
        Nop,
    ]);
    assert_eq!((p.read(0xA0), p.read(0x20), p.read(0x21)), (0x22, 0, 0));
    assert_eq!(p.cycles(), 11);
    p.set_pc(8);
    p.write(0x21, 2);
    p.step().unwrap();
    assert_eq!(p.pc(), 9);
}

#[test]
fn reset_and_fill_ram() {
    let mut p = chip(&[
        Movlw(1),
        Movwf(0x20),
        Movwf(reg::FSR),
        Call(5),
        Goto(4),
        Return,
    ]);
    p.fill_ram(0xA5);
    for a in [0x20, 0x7F, 0xA0, 0xEF, 0x110, 0x16F, 0x190, 0x1EF] {
        assert_eq!(p.read(a), 0xA5);
    }
    assert_eq!(p.read(0xF0), 0xA5, "mirror of 0x70");
    assert_eq!(p.run_until(&[4], 100), Ok(Stop::Breakpoint(4)));
    assert_eq!(p.max_stack_depth(), 1);
    p.reset();
    assert_eq!(
        (p.pc(), p.cycles(), p.max_stack_depth(), p.stack_depth()),
        (0, 0, 0, 0)
    );
    assert_eq!(p.read(0x20), 1, "GPR kept");
    assert_eq!(p.read(reg::FSR), 0);
    for (a, v) in [
        (ST, 0x18),
        (reg::OPTION_REG, 0xFF),
        (reg::TRISA, 0x3F),
        (reg::TRISB, 0xFF),
        (reg::TRISC, 0xFF),
        (reg::ADCON1, 0),
    ] {
        assert_eq!(p.read(a), v, "{a:#x}");
    }
}

#[test]
fn host_writes_to_timer_and_flags() {
    // the machine layer restarts TMR1 and clears CCP1IF from the host
    let mut p = chip(&[Goto(0)]);
    p.write(reg::CCPR1L, 100);
    p.write(reg::CCP1CON, 0x0B);
    p.write(reg::T1CON, 1);
    assert_eq!(p.run_until(&[], 250), Ok(Stop::CycleLimit));
    assert_eq!(p.read(reg::PIR1) & 4, 4);
    p.write(reg::TMR1L, 0);
    p.write(reg::TMR1H, 0);
    p.write(reg::PIR1, 0);
    let c0 = p.cycles();
    assert_eq!(p.read(reg::TMR1L), 0);
    p.run_until(&[], 50).unwrap();
    assert_eq!(u64::from(p.read(reg::TMR1L)), p.cycles() - c0);
    assert_eq!(p.read(reg::PIR1), 0);
}

#[test]
fn hex_files() {
    // words 0x2805 0x0000, then the configuration word (skipped)
    let text = ":0400000005280000CF\n:02400E00323F3F\n:00000001FF\n";
    assert_eq!(Pic16::load_hex(text), Ok(vec![0x2805, 0x0000]));
    let ext = ":020000040000FA\n:0400040008000000F0\n:00000001FF\n";
    assert_eq!(
        Pic16::load_hex(ext),
        Ok(vec![0x3FFF, 0x3FFF, 0x0008, 0x0000])
    );
    let err = |t: &str| Pic16::load_hex(t).unwrap_err().0;
    assert!(err(":0400000005280000CE\n:00000001FF\n").contains("checksum"));
    assert!(err(":0400000005280000CF\n").contains("end-of-file"));
    assert!(err("0400000005280000CF\n:00000001FF\n").contains("':'"));
    assert!(err(":0500000005280000CE\n:00000001FF\n").contains("length"));
    assert!(err(":04000000052800G0CF\n:00000001FF\n").contains("hex digit"));
    assert!(err(":02000006FFFFFA\n:00000001FF\n").contains("type"));
    assert!(err(":00000001FF\n:00000001FF\n").contains("after"));
    assert_eq!(Pic16::load_hex(":00000001FF\n"), Ok(vec![]));
}

/// The computed GOTO of `isel::flow::br_table`, assembled with its table across a
/// 256-word boundary: every index lands on its own entry (the carry of `LOW(table) +
/// index` goes into PCLATH).
#[test]
fn a_jump_table_across_a_256_word_boundary() {
    use crate::asm::{Item, Op, Program, Unit};
    let mut prog = Program::default();
    let table = prog.label("table");
    let done = prog.label("done");
    let entries: Vec<_> = (0..4).map(|k| prog.label(format!("e{k}"))).collect();
    let mut items = vec![
        Item::Op(Op::MovlwAddr(table, true)),
        Item::Op(Op::I(Movwf(reg::PCLATH))),
        Item::Op(Op::MovlwAddr(table, false)),
        Item::Op(Op::I(Addwf(0x20, W))),
        Item::Op(Op::I(Btfsc(reg::STATUS, reg::C))),
        Item::Op(Op::I(Incf(reg::PCLATH, F))),
        Item::Op(Op::I(Movwf(reg::PCL))),
    ];
    // Pad so that the table starts at 0x0FE: entries 2 and 3 lie past 0x0FF.
    items.extend((items.len()..0xFE).map(|_| Item::Op(Op::I(Nop))));
    items.push(Item::Label(table));
    items.extend(entries.iter().map(|&e| Item::Op(Op::TableGoto(e))));
    for (k, &e) in entries.iter().enumerate() {
        items.push(Item::Label(e));
        items.push(Item::Op(Op::I(Movlw(0x40 + k as u8))));
        items.push(Item::Op(Op::Goto(done)));
    }
    items.push(Item::Label(done));
    items.push(Item::Op(Op::I(Movwf(0x21))));
    items.push(Item::Op(Op::I(Sleep)));
    prog.units.push(Unit {
        name: "t".into(),
        org: Some(0),
        items,
        ..Default::default()
    });
    let image = prog.assemble().unwrap();
    assert_eq!(image.label_addr[table.0 as usize], 0x0FE);
    let end = image.label_addr[done.0 as usize] + 1;
    for k in 0..4u8 {
        let mut p = Pic16::new(&image.words);
        p.write(0x20, k);
        assert_eq!(p.run_until(&[end], 1000), Ok(Stop::Breakpoint(end)));
        assert_eq!(p.read(0x21), 0x40 + k, "index {k}");
    }
}
