//! Unit tests of the VM on hand-assembled programs.

use super::*;
use crate::isa::{Inst, Opcode, Operand};

fn d(x: u32) -> Operand {
    Operand::Data(x)
}
fn l(x: u32) -> Operand {
    Operand::Code(x)
}
fn imm(x: u32) -> Operand {
    Operand::Imm(x)
}
fn bytes(b: &[u8]) -> Operand {
    Operand::Bytes(b.to_vec())
}
fn i(op: u16, ops: Vec<Operand>) -> Inst {
    Inst::new(Opcode(op), ops)
}

/// Assembles `f(addresses)`: `addresses[j]` is the code address of instruction `j`
/// (and one past the end), found with a first pass on placeholder addresses.
fn build(mode: Mode, f: impl Fn(&[u32]) -> Vec<Inst>) -> Vec<u8> {
    build_at(mode, f).0
}

/// [`build`], with the addresses of the instructions.
fn build_at(mode: Mode, f: impl Fn(&[u32]) -> Vec<Inst>) -> (Vec<u8>, Vec<u32>) {
    let first = f(&[0; 256]);
    let mut at = vec![0u32];
    let mut out = Vec::new();
    for x in &first {
        x.encode(mode, &mut out);
        at.push(out.len() as u32);
    }
    let n = at.len() - 1;
    at.resize(256, 0);
    let mut out = Vec::new();
    for x in f(&at) {
        x.encode(mode, &mut out);
    }
    at.truncate(n);
    (out, at)
}

/// Straight-line code ending with `TRML 0`, run for one scan on 256 bytes of data
/// prepared by `init`.
fn scan(mode: Mode, body: Vec<Inst>, init: impl FnOnce(&mut [u8])) -> Vm {
    let mut body = body;
    body.push(i(0x1C1D, vec![l(0)]));
    let mut code = Vec::new();
    for x in &body {
        x.encode(mode, &mut code);
    }
    let mut vm = Vm::new(&code, 256, mode).unwrap();
    init(vm.data_mut());
    vm.run_cycle(10_000).unwrap();
    vm
}

fn scan16(body: Vec<Inst>, init: impl FnOnce(&mut [u8])) -> Vm {
    scan(Mode::M16, body, init)
}

fn put<const N: usize>(m: &mut [u8], at: usize, b: [u8; N]) {
    m[at..at + N].copy_from_slice(&b);
}
fn get<const N: usize>(vm: &Vm, at: usize) -> [u8; N] {
    vm.data()[at..at + N].try_into().unwrap()
}
fn i16_at(vm: &Vm, at: usize) -> i16 {
    i16::from_le_bytes(get(vm, at))
}
fn i32_at(vm: &Vm, at: usize) -> i32 {
    i32::from_le_bytes(get(vm, at))
}
fn f32_at(vm: &Vm, at: usize) -> f32 {
    f32::from_le_bytes(get(vm, at))
}
fn f64_at(vm: &Vm, at: usize) -> f64 {
    f64::from_le_bytes(get(vm, at))
}

#[test]
fn integer_arithmetic_wraps_and_guards_division() {
    let vm = scan16(
        vec![
            i(0x0122, vec![d(0), d(100), d(102)]),  // ADD INT: 32767 + 1
            i(0x0202, vec![d(2), d(104), d(102)]),  // SUB INT: -32768 - 1
            i(0x0402, vec![d(4), d(100), d(106)]),  // DIV INT by 0
            i(0x0412, vec![d(6), d(100), d(106)]),  // MOD INT by 0
            i(0x0402, vec![d(8), d(104), d(108)]),  // MIN / -1
            i(0x0412, vec![d(10), d(104), d(108)]), // MIN MOD -1
            i(0x0412, vec![d(12), d(110), d(112)]), // -7 MOD 3
            i(0x0402, vec![d(14), d(110), d(112)]), // -7 / 3
            i(0x0325, vec![d(16), d(114), d(114)]), // MUL BYTE 200*200
            i(0x0409, vec![d(20), d(120), d(124)]), // DIV REAL 1/0
        ],
        |m| {
            put(m, 100, 32767i16.to_le_bytes());
            put(m, 102, 1i16.to_le_bytes());
            put(m, 104, i16::MIN.to_le_bytes());
            put(m, 106, 0i16.to_le_bytes());
            put(m, 108, (-1i16).to_le_bytes());
            put(m, 110, (-7i16).to_le_bytes());
            put(m, 112, 3i16.to_le_bytes());
            m[114] = 200;
            put(m, 120, 1f32.to_le_bytes());
            put(m, 124, 0f32.to_le_bytes());
        },
    );
    assert_eq!(i16_at(&vm, 0), i16::MIN);
    assert_eq!(i16_at(&vm, 2), i16::MAX);
    assert_eq!(i16_at(&vm, 4), 0);
    assert_eq!(i16_at(&vm, 6), 0);
    assert_eq!(i16_at(&vm, 8), i16::MIN);
    assert_eq!(i16_at(&vm, 10), 0);
    assert_eq!(i16_at(&vm, 12), -1);
    assert_eq!(i16_at(&vm, 14), -2);
    assert_eq!(vm.data()[16], (200u32 * 200 % 256) as u8);
    assert_eq!(f32_at(&vm, 20), f32::INFINITY);
}

#[test]
fn variadic_and_bitwise_groups() {
    let vm = scan16(
        vec![
            i(0x0132, vec![d(0), d(100), d(102), d(104)]), // ADD INT of 3
            i(0x0342, vec![d(2), d(100), d(102), d(104), d(104)]), // MUL INT of 4
            i(0x0820, vec![d(4), d(110), d(111)]),         // AND BOOL
            i(0x0930, vec![d(5), d(110), d(111), d(110)]), // OR BOOL of 3
            i(0x0A24, vec![d(8), d(112), d(116)]),         // XOR DWORD (code 4)
            i(0x0A25, vec![d(24), d(120), d(120)]),        // XOR LWORD (code 5)
            i(0x0510, vec![d(12), d(113)]),                // NOT BOOL of 0xF0: 0
            i(0x0510, vec![d(13), d(111)]),                // NOT BOOL of 0: 1
            i(0x0512, vec![d(14), d(100)]),                // NOT WORD
            i(0x0E33, vec![d(16), d(130), d(134), d(138)]), // MAX DINT of 3
            i(0x0F33, vec![d(20), d(130), d(134), d(138)]), // MIN DINT of 3
        ],
        |m| {
            put(m, 100, 2i16.to_le_bytes());
            put(m, 102, 3i16.to_le_bytes());
            put(m, 104, 5i16.to_le_bytes());
            m[110] = 1;
            m[111] = 0;
            put(m, 112, 0x00F0_FF00u32.to_le_bytes());
            put(m, 116, 0x0FF0_0FF0u32.to_le_bytes());
            put(m, 120, u64::MAX.to_le_bytes());
            put(m, 130, (-5i32).to_le_bytes());
            put(m, 134, 7i32.to_le_bytes());
            put(m, 138, 3i32.to_le_bytes());
        },
    );
    assert_eq!(i16_at(&vm, 0), 10);
    assert_eq!(i16_at(&vm, 2), 150);
    assert_eq!(vm.data()[4], 0);
    assert_eq!(vm.data()[5], 1);
    assert_eq!(u32::from_le_bytes(get(&vm, 8)), 0x00F0_FF00 ^ 0x0FF0_0FF0);
    assert_eq!(u64::from_le_bytes(get(&vm, 24)), 0);
    assert_eq!(vm.data()[12], 0);
    assert_eq!(vm.data()[13], 1);
    assert_eq!(i16_at(&vm, 14), !2i16);
    assert_eq!(i32_at(&vm, 16), 7);
    assert_eq!(i32_at(&vm, 20), -5);
}

#[test]
fn shifts_and_rotates() {
    let vm = scan16(
        vec![
            i(0x0B01, vec![d(0), d(100), d(102)]), // SHL BYTE by 1
            i(0x0B01, vec![d(1), d(100), d(104)]), // SHL BYTE by 8: 0
            i(0x0B11, vec![d(2), d(100), d(106)]), // SHR BYTE by -1: 0
            i(0x0B21, vec![d(3), d(100), d(106)]), // ROL BYTE by -1 = ROR 1
            i(0x0B33, vec![d(4), d(108), d(104)]), // ROR DWORD by 8
            i(0x0B04, vec![d(8), d(112), d(102)]), // SHL LWORD by 1
        ],
        |m| {
            m[100] = 0x81;
            put(m, 102, 1i16.to_le_bytes());
            put(m, 104, 8i16.to_le_bytes());
            put(m, 106, (-1i16).to_le_bytes());
            put(m, 108, 0x1234_5678u32.to_le_bytes());
            put(m, 112, (1u64 << 63 | 1).to_le_bytes());
        },
    );
    assert_eq!(vm.data()[0], 0x02);
    assert_eq!(vm.data()[1], 0);
    assert_eq!(vm.data()[2], 0);
    assert_eq!(vm.data()[3], 0xC0);
    assert_eq!(u32::from_le_bytes(get(&vm, 4)), 0x7812_3456);
    assert_eq!(u64::from_le_bytes(get(&vm, 8)), 2);
}

#[test]
fn comparisons_selection_and_limits() {
    let nan = f32::NAN.to_le_bytes();
    let vm = scan16(
        vec![
            i(0x1009, vec![d(0), d(100), d(104)]),          // GT REAL NaN
            i(0x1509, vec![d(1), d(100), d(104)]),          // NE REAL NaN
            i(0x1209, vec![d(2), d(100), d(100)]),          // EQ REAL NaN NaN
            i(0x1402, vec![d(3), d(110), d(112)]),          // LT INT -1 < 1
            i(0x1406, vec![d(4), d(110), d(112)]),          // LT WORD 0xFFFF < 1
            i(0x110B, vec![d(5), d(120), d(124)]),          // GE TIME
            i(0x0C02, vec![d(10), d(130), d(110), d(112)]), // SEL INT g=1
            i(0x0C02, vec![d(12), d(131), d(110), d(112)]), // SEL INT g=0
            i(0x0D02, vec![d(14), d(112), d(110), d(140)]), // LIMIT INT(1, -1, 10)
            i(0x0D02, vec![d(16), d(112), d(142), d(140)]), // LIMIT INT(1, 50, 10)
            i(0x1632, vec![d(18), d(144), d(110), d(112)]), // MUX INT K=1 of 2
            i(0x1632, vec![d(20), d(146), d(110), d(112)]), // MUX INT K=2: unchanged
        ],
        |m| {
            put(m, 100, nan);
            put(m, 104, 1f32.to_le_bytes());
            put(m, 110, (-1i16).to_le_bytes());
            put(m, 112, 1i16.to_le_bytes());
            put(m, 120, 3_000_000_000u32.to_le_bytes());
            put(m, 124, 5u32.to_le_bytes());
            m[130] = 7;
            m[131] = 0;
            put(m, 140, 10i16.to_le_bytes());
            put(m, 142, 50i16.to_le_bytes());
            put(m, 144, 1i16.to_le_bytes());
            put(m, 146, 2i16.to_le_bytes());
            put(m, 20, 0x5555u16.to_le_bytes());
        },
    );
    assert_eq!(get(&vm, 0), [0, 1, 0, 1, 0, 1]);
    assert_eq!(i16_at(&vm, 10), 1);
    assert_eq!(i16_at(&vm, 12), -1);
    assert_eq!(i16_at(&vm, 14), 1);
    assert_eq!(i16_at(&vm, 16), 10);
    assert_eq!(i16_at(&vm, 18), 1);
    assert_eq!(u16::from_le_bytes(get(&vm, 20)), 0x5555);
}

#[test]
fn math_and_conversions() {
    let vm = scan16(
        vec![
            i(0x0620, vec![d(0), d(100)]),  // SQRT REAL 2.25
            i(0x0621, vec![d(4), d(104)]),  // SQRT LREAL 2.25
            i(0x0634, vec![d(12), d(112)]), // TRUNC REAL -2.5 → DINT
            i(0x0636, vec![d(16), d(112)]), // ROUND REAL -2.5 → -3
            i(0x0636, vec![d(20), d(116)]), // ROUND REAL 1e20 saturates
            i(0x0612, vec![d(24), d(120)]), // ABS INT MIN
            i(0x0507, vec![d(26), d(100)]), // NEG REAL
            // EXPT as the C VMs number it (reference/cpdev-vm-opcodes.md §2.1).
            i(0x0601, vec![d(84), d(122), d(123)]), // SINT 3**4 → DINT 81
            i(0x0601, vec![d(48), d(124), d(125)]), // SINT 2**8: the SINT square wraps → 0
            i(0x0602, vec![d(52), d(126), d(128)]), // INT 2**16 → 0
            i(0x0601, vec![d(72), d(122), d(129)]), // 3**-1 → 1
            i(0x0604, vec![d(76), d(100), d(123)]), // REAL**SINT 2.25**4
            i(0x0607, vec![d(80), d(132), d(136)]), // REAL (-3.0)**2.0 → NaN
            i(0x0608, vec![d(64), d(140), d(148)]), // LREAL 100.0**0.5 → 10.000000000000002
            i(0x0625, vec![d(40), d(160)]),         // LOG LREAL 1000
        ],
        |m| {
            put(m, 100, 2.25f32.to_le_bytes());
            put(m, 104, 2.25f64.to_le_bytes());
            put(m, 112, (-2.5f32).to_le_bytes());
            put(m, 116, 1e20f32.to_le_bytes());
            put(m, 120, i16::MIN.to_le_bytes());
            put(m, 122, [3, 4, 2, 8]);
            put(m, 126, 2i16.to_le_bytes());
            put(m, 128, [16, 0xFF]);
            put(m, 132, (-3f32).to_le_bytes());
            put(m, 136, 2f32.to_le_bytes());
            put(m, 140, 100f64.to_le_bytes());
            put(m, 148, 0.5f64.to_le_bytes());
            put(m, 160, 1000f64.to_le_bytes());
        },
    );
    assert_eq!(f32_at(&vm, 0), 1.5);
    assert_eq!(f64_at(&vm, 4), 1.5);
    assert_eq!(i32_at(&vm, 12), -2);
    assert_eq!(i32_at(&vm, 16), -3);
    assert_eq!(i32_at(&vm, 20), i32::MAX);
    assert_eq!(i16_at(&vm, 24), i16::MIN);
    assert_eq!(f32_at(&vm, 26), -2.25);
    assert_eq!(i32_at(&vm, 84), 81);
    assert_eq!(i32_at(&vm, 48), 0);
    assert_eq!(i32_at(&vm, 52), 0);
    assert_eq!(i32_at(&vm, 72), 1);
    assert_eq!(f32_at(&vm, 76), (2.25f64.ln() * 4.0).exp() as f32);
    assert!(f32_at(&vm, 80).is_nan());
    assert_eq!(f64_at(&vm, 64), 10.000000000000002);
    assert_eq!(f64_at(&vm, 40), 3.0);

    let vm = scan16(
        vec![
            i(0x1900, vec![d(0), d(100)]),  // INT_TO_REAL -3
            i(0x1905, vec![d(4), d(104)]),  // REAL_TO_TIME -1.5 → 0
            i(0x1906, vec![d(8), d(108)]),  // BCD BYTE 0x42 → 42
            i(0x1907, vec![d(10), d(110)]), // BCD WORD 0x1234 → 1234
            i(0x1908, vec![d(12), d(112)]), // INT_TO_BCD BYTE 57
            i(0x1909, vec![d(14), d(114)]), // INT_TO_BCD WORD 9876
            i(0x190A, vec![d(16), d(116)]), // REAL_TO_INT 1e9 saturates
            i(0x190B, vec![d(18), d(120)]), // INT_TO_BOOL 256 → FALSE
            i(0x190B, vec![d(19), d(100)]), // INT_TO_BOOL -3 → TRUE
            i(0x190C, vec![d(20), d(100)]), // INT_TO_DINT -3
            i(0x190D, vec![d(24), d(124)]), // REAL_TO_LREAL
            i(0x1911, vec![d(32), d(104)]), // REAL_TO_DWORD -1.5 → 0
            i(0x1902, vec![d(36), d(128)]), // TIME_TO_DINT bits
        ],
        |m| {
            put(m, 100, (-3i16).to_le_bytes());
            put(m, 104, (-1.5f32).to_le_bytes());
            m[108] = 0x42;
            put(m, 110, 0x1234u16.to_le_bytes());
            put(m, 112, 57i16.to_le_bytes());
            put(m, 114, 9876i16.to_le_bytes());
            put(m, 116, 1e9f32.to_le_bytes());
            put(m, 120, 256i16.to_le_bytes());
            put(m, 124, 0.1f32.to_le_bytes());
            put(m, 128, 0xFFFF_FFFFu32.to_le_bytes());
        },
    );
    assert_eq!(f32_at(&vm, 0), -3.0);
    assert_eq!(u32::from_le_bytes(get(&vm, 4)), 0);
    assert_eq!(i16_at(&vm, 8), 42);
    assert_eq!(i16_at(&vm, 10), 1234);
    assert_eq!(vm.data()[12], 0x57);
    assert_eq!(u16::from_le_bytes(get(&vm, 14)), 0x9876);
    assert_eq!(i16_at(&vm, 16), i16::MAX);
    assert_eq!(vm.data()[18], 0);
    assert_eq!(vm.data()[19], 1);
    assert_eq!(i32_at(&vm, 20), -3);
    assert_eq!(f64_at(&vm, 24), 0.1f32 as f64);
    assert_eq!(u32::from_le_bytes(get(&vm, 32)), 0);
    assert_eq!(i32_at(&vm, 36), -1);
}

#[test]
fn memory_instructions() {
    let vm = scan16(
        vec![
            i(0x1C15, vec![d(0), bytes(&[1, 2, 3, 4, 5])]), // MCD
            i(0x1C1F, vec![d(1), d(0), imm(4)]),            // MEMCP overlapping
            i(0x1C23, vec![d(10), imm(0xAB), imm(3)]),      // FPAT
            i(0x0703, vec![d(20), d(0)]),                   // MMV 3 in
            i(0x1C17, vec![d(24)]),                         // CUR_TIME
            i(0x1C31, vec![d(28)]),                         // TASK_CYCLE
            i(0x1C32, vec![d(32)]),                         // GET_VMACH_VERSION
            i(0x1C2F, vec![d(34)]),                         // GET_STATUS_WORD1
            i(0x1C2E, vec![d(100), d(102), d(104)]),        // CEAC 5-2 in 0..=3
            i(0x1C2A, vec![d(40), d(120), d(100)]),         // AFRD [3]
            i(0x1C27, vec![d(0), d(140), d(100)]),          // AOWR [3]
            i(0x1C24, vec![d(50), d(120), d(106), d(108)]), // AURD idx 1, size 8
            i(0x1C25, vec![d(0), d(150), d(106), d(108)]),  // AUWR idx 1, size 8
        ],
        |m| {
            put(m, 100, 5i16.to_le_bytes());
            put(m, 102, 2i16.to_le_bytes());
            put(m, 104, 3i16.to_le_bytes());
            put(m, 106, 1i16.to_le_bytes());
            put(m, 108, 8i16.to_le_bytes());
            for (j, b) in m[120..140].iter_mut().enumerate() {
                *b = j as u8;
            }
        },
    );
    assert_eq!(get(&vm, 0), [1, 1, 2, 3, 4]);
    assert_eq!(get(&vm, 10), [0xAB; 3]);
    assert_eq!(get(&vm, 20), [1, 1, 2]);
    assert_eq!(u32::from_le_bytes(get(&vm, 24)), 0);
    assert_eq!(u16::from_le_bytes(get(&vm, 32)), 0x2900);
    assert_eq!(u16::from_le_bytes(get(&vm, 34)), 0);
    assert_eq!(i16_at(&vm, 100), 3);
    assert_eq!(vm.status() & status::ARRAYBOUND, 0);
    assert_eq!(get(&vm, 40), [12, 13, 14, 15]);
    assert_eq!(vm.data()[143], 1);
    assert_eq!(get(&vm, 50), [8, 9, 10, 11, 12, 13, 14, 15]);
    assert_eq!(get(&vm, 158), [1, 1, 2, 3, 4, 0, 0, 0]);

    // CUR_TIME / TASK_CYCLE follow the setters; CEAC out of range sets ARRAYBOUND and
    // stops the VM.
    let mut code = Vec::new();
    for x in [
        i(0x1C17, vec![d(0)]),
        i(0x1C31, vec![d(4)]),
        i(0x1C2E, vec![d(100), d(102), d(104)]),
        i(0x1C2F, vec![d(8)]),
        i(0x1C1D, vec![l(0)]),
    ] {
        x.encode(Mode::M16, &mut code);
    }
    let mut vm = Vm::new(&code, 256, Mode::M16).unwrap();
    put(vm.data_mut(), 100, 1i16.to_le_bytes());
    put(vm.data_mut(), 102, 2i16.to_le_bytes());
    put(vm.data_mut(), 104, 3i16.to_le_bytes());
    vm.set_clock_ms(1234);
    vm.set_task_cycle_ms(50);
    let e = vm.run_cycle(100).unwrap_err();
    assert!(e.to_string().contains("CEAC"), "{e}");
    assert_eq!(i16_at(&vm, 100), -1);
    assert_eq!(vm.status(), status::ARRAYBOUND);
    assert_eq!(u32::from_le_bytes(get(&vm, 0)), 1234);
    assert_eq!(u32::from_le_bytes(get(&vm, 4)), 50);
    assert_eq!(
        u16::from_le_bytes(get(&vm, 8)),
        0,
        "GET_STATUS_WORD1 never ran"
    );
}

#[test]
fn calls_dptr_and_pointers() {
    for mode in Mode::ALL {
        let w = mode.addr_bytes();
        // main: CALB 16, f; MMV-out; DPSTO; CALBR p, g; TRML 0
        // f: MCD 0 (= 16 abs) := 7; DPSTO 1 (= 17 abs); RETURN
        // g: MEMCP 0, 1, 1 (local to ptr target 64); RETFB
        let code = build(mode, |a| {
            let (mcd, memcp) = if mode == Mode::M32A {
                (0x1C37, 0x1C39)
            } else {
                (0x1C15, 0x1C1F)
            };
            vec![
                i(0x1C16, vec![d(16), l(a[5])]),    // 0 CALB 16, f
                i(0x0782, vec![d(40), d(16)]),      // 1 MMV abs 40 := local 16 (2 bytes)
                i(0x1E00, vec![d(48)]),             // 2 DPSTO 48 (DPTR 0 again)
                i(0x1E03, vec![d(60), l(a[8])]),    // 3 CALBR [60], g
                i(0x1C1D, vec![l(0)]),              // 4 TRML
                i(mcd, vec![d(0), bytes(&[7])]),    // 5 f: MCD
                i(0x1E00, vec![d(1)]),              // 6 DPSTO
                i(0x1C13, vec![]),                  // 7 RETURN
                i(memcp, vec![d(0), d(1), imm(1)]), // 8 g: MEMCP
                i(0x1C18, vec![]),                  // 9 RETFB
            ]
        });
        let mut vm = Vm::new(&code, 256, mode).unwrap();
        put(vm.data_mut(), 60, 64u32.to_le_bytes());
        vm.data_mut()[65] = 99;
        let o = vm.run(None, 1000).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::Trml,
                executed: 10
            },
            "{mode:?}"
        );
        assert_eq!(vm.data()[16], 7);
        assert_eq!(vm.data()[17], 16);
        assert_eq!(&vm.data()[40..42], &[7, 16]);
        assert_eq!(
            vm.data()[48..48 + w].iter().map(|&x| x as u32).sum::<u32>(),
            0
        );
        assert_eq!(vm.data()[64], 99, "{mode:?}");
        assert_eq!(vm.dptr(), 0);
        assert_eq!(vm.call_depth(), 0);
        assert_eq!(vm.pc(), 0);
    }
}

#[test]
fn dprdl_dpwrl() {
    for mode in [Mode::M16, Mode::M32, Mode::M32A] {
        // DPRDL/DPWRL in every mode: vmdef.h's DPRDL4A/DPWRL4A (1E11/1E12) are
        // executed by no C VM.
        let (rd, wr) = (0x1E01, 0x1E02);
        let code = build(mode, |a| {
            vec![
                i(0x1C16, vec![d(100), l(a[2])]), // CALB 100, f
                i(0x1C1D, vec![l(0)]),
                i(rd, vec![d(0), d(10), imm(3)]), // local 0..3 := [ptr]
                i(wr, vec![d(20), d(10), imm(2)]), // [ptr] := local 20..22
                i(0x1C13, vec![]),
            ]
        });
        let mut vm = Vm::new(&code, 256, mode).unwrap();
        let m = vm.data_mut();
        put(m, 110, 30u32.to_le_bytes());
        put(m, 30, [1, 2, 3]);
        put(m, 120, [8, 9]);
        vm.run_cycle(100).unwrap();
        assert_eq!(get(&vm, 100), [1, 2, 3]);
        assert_eq!(get(&vm, 30), [8, 9, 3]);
    }
    for op in [[0x1E, 0x11], [0x1E, 0x12]] {
        let mut code = vec![op[0], op[1], 0, 0];
        code.extend([0u8; 12]);
        match Vm::new(&code, 256, Mode::M32A) {
            Err(_) => {}
            Ok(mut vm) => assert!(vm.run_cycle(10).is_err(), "{op:02X?} ran"),
        }
    }
}

#[test]
fn jumps_trml_stop_and_budget() {
    // 0: MCD 0 := 3           (init, first scan only)
    // 1: loop: ADD 0 := 0 + 2 (INT; 2 at data 2 holds -1)
    // 2: GT 4 := 0 > 6 (0)
    // 3: JNZ 4, 1
    // 4: TRML 1
    let code = build(Mode::M16, |a| {
        vec![
            i(0x1C15, vec![d(0), bytes(&[3, 0])]),
            i(0x0122, vec![d(0), d(0), d(2)]),
            i(0x1002, vec![d(4), d(0), d(6)]),
            i(0x1C01, vec![d(4), l(a[1])]),
            i(0x1C1D, vec![l(a[1])]),
        ]
    });
    let mut vm = Vm::new(&code, 16, Mode::M16).unwrap();
    put(vm.data_mut(), 2, (-1i16).to_le_bytes());
    put(vm.data_mut(), 6, 0i16.to_le_bytes());
    let o = vm.run(None, 1000).unwrap();
    assert_eq!(o.end, End::Trml);
    assert_eq!(o.executed, 1 + 3 * 3 + 1);
    assert_eq!(i16_at(&vm, 0), 0);
    let loop_pc = vm.pc();
    assert_eq!(loop_pc, 7);
    put(vm.data_mut(), 0, 2i16.to_le_bytes());
    // Stop before the JNZ.
    let jnz = loop_pc + 16;
    let o = vm.run(Some(jnz), 1000).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::StopAt,
            executed: 2
        }
    );
    assert_eq!(vm.pc(), jnz);
    // Starting at stop_at returns at once, whatever the budget.
    for b in [1, 2, 3, 4, 1000] {
        let o = vm.run(Some(jnz), b).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::StopAt,
                executed: 0
            },
            "budget {b}"
        );
    }
    // A breakpoint is seen in the last instructions of a budget too.
    let mut w = Vm::new(&code, 16, Mode::M16).unwrap();
    put(w.data_mut(), 2, (-1i16).to_le_bytes());
    let o = w.run(Some(loop_pc + 8), 3).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::StopAt,
            executed: 2
        }
    );
    // When the budget runs out where the PC reaches stop_at, the budget wins.
    w.reset();
    let o = w.run(Some(loop_pc + 8), 2).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Budget,
            executed: 2
        }
    );
    assert_eq!(w.pc(), loop_pc + 8);
    // The breakpoint is gone afterwards; a budget ends the run without an error.
    let o = vm.run(None, 3).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Budget,
            executed: 3
        }
    );
    assert_eq!(vm.pc(), jnz);
    assert_eq!(i16_at(&vm, 0), 0);
    let o = vm.run(None, 100).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Trml,
            executed: 2
        }
    );
    assert_eq!(vm.executed(), 11 + 2 + 3 + 2);
    // JZ and JMP.
    let code = build(Mode::M16, |a| {
        vec![
            i(0x1C02, vec![d(0), l(a[3])]),     // JZ [0] → 3
            i(0x1C15, vec![d(1), bytes(&[1])]), // skipped
            i(0x1C00, vec![l(a[4])]),
            i(0x1C15, vec![d(2), bytes(&[1])]), // 3
            i(0x1C1D, vec![l(0)]),              // 4
        ]
    });
    let mut vm = Vm::new(&code, 16, Mode::M16).unwrap();
    vm.run_cycle(100).unwrap();
    assert_eq!(get(&vm, 1), [0, 1]);
    vm.reset();
    vm.data_mut()[0] = 5;
    vm.data_mut()[2] = 0;
    vm.run_cycle(100).unwrap();
    assert_eq!(get(&vm, 1), [1, 0]);
}

#[test]
fn faults_are_errors_naming_the_pc() {
    let err = |code: &[u8], data: usize| {
        let mut vm = Vm::new(code, data, Mode::M16).unwrap();
        let e = vm.run(None, 10_000).unwrap_err();
        (e.0, vm.pc())
    };
    // Out-of-range access at PC 6.
    let mut code = Vec::new();
    i(0x1C15, vec![d(0), bytes(&[1])]).encode(Mode::M16, &mut code);
    i(0x0122, vec![d(0), d(15), d(0)]).encode(Mode::M16, &mut code);
    let (m, pc) = err(&code, 16);
    assert_eq!(pc, 6);
    assert!(
        m.contains("at PC 0006") && m.contains("outside data memory"),
        "{m}"
    );
    // RETURN with an empty stack.
    let (m, pc) = err(&[0x1C, 0x13], 16);
    assert_eq!(pc, 0);
    assert!(m.contains("empty"), "{m}");
    // Unbounded recursion.
    let (m, _) = err(&[0x1C, 0x16, 0, 0, 0, 0], 16);
    assert!(m.contains("overflow"), "{m}");
    // An opcode that does not decode, reached by falling through.
    let (m, pc) = err(&[0x00, 0x00, 0xFF, 0xFF], 16);
    assert_eq!(pc, 2);
    assert!(m.contains("unknown opcode"), "{m}");
    // Running off the end of the code and jumping outside it.
    let (m, pc) = err(&[0x00, 0x00], 16);
    assert_eq!(pc, 2);
    assert!(m.contains("outside the code"), "{m}");
    let (m, pc) = err(&[0x1C, 0x00, 0x00, 0x10], 16);
    assert_eq!(pc, 0x1000);
    assert!(m.contains("outside the code"), "{m}");
    // Undecodable bytes that are never executed are fine.
    let mut vm = Vm::new(&[0x1C, 0x1D, 0, 0, 0xFF, 0xFF], 0, Mode::M16).unwrap();
    assert_eq!(vm.run(None, 10).unwrap().end, End::Trml);
    // Data memory larger than the address space.
    assert!(Vm::new(&[], 0x10001, Mode::M16).is_err());
}

#[test]
fn dptr_relative_addresses_wrap() {
    // CALB 0xFFF0, f; TRML; f: MCD 0x14 := 9 (0xFFF0 + 0x14 wraps to 4); RETURN.
    let code = build(Mode::M16, |a| {
        vec![
            i(0x1C16, vec![d(0xFFF0), l(a[2])]),
            i(0x1C1D, vec![l(0)]),
            i(0x1C15, vec![d(0x14), bytes(&[9])]),
            i(0x1C13, vec![]),
        ]
    });
    let mut vm = Vm::new(&code, 16, Mode::M16).unwrap();
    vm.run_cycle(100).unwrap();
    assert_eq!(vm.data()[4], 9);
}

#[test]
fn jump_into_the_middle_of_an_instruction() {
    // 0: JMP 9, into the payload of `4: MCD 0, #04, #1C1D0400`, where the bytes are
    // `TRML 4`; 13: TRML 0. The MCD falls through to 13, past the entry at 9.
    let mut code = vec![0x1C, 0x00, 0x09, 0x00];
    i(0x1C15, vec![d(0), bytes(&[0x1C, 0x1D, 0x04, 0x00])]).encode(Mode::M16, &mut code);
    i(0x1C1D, vec![l(0)]).encode(Mode::M16, &mut code);
    let mut vm = Vm::new(&code, 16, Mode::M16).unwrap();
    assert!(vm.is_instruction(9) && vm.is_instruction(13) && !vm.is_instruction(8));
    let o = vm.run(None, 10).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Trml,
            executed: 2
        }
    );
    assert_eq!(vm.pc(), 4);
    // From 4: the MCD (falls through to 13, a TRML) — not the TRML at 7.
    let o = vm.run(None, 10).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Trml,
            executed: 2
        }
    );
    assert_eq!(&vm.data()[..4], &[0x1C, 0x1D, 0x04, 0x00]);
    assert_eq!(vm.pc(), 0);
}

#[test]
fn aligned_mode_forms() {
    let vm = scan(
        Mode::M32A,
        vec![
            i(0x1C37, vec![d(0), bytes(&[1, 2, 3, 4, 5])]),
            i(0x1C38, vec![d(8), imm(0xEE), imm(2)]),
            i(0x1C39, vec![d(12), d(0), imm(5)]),
            i(0x0122, vec![d(20), d(0), d(2)]),
        ],
        |_| {},
    );
    assert_eq!(get(&vm, 0), [1, 2, 3, 4, 5]);
    assert_eq!(get(&vm, 8), [0xEE, 0xEE]);
    assert_eq!(get(&vm, 12), [1, 2, 3, 4, 5]);
    assert_eq!(u16::from_le_bytes(get(&vm, 20)), 0x0201 + 0x0403);
}

/// `I := start; loop: LE c := I <= 3; JZ c, end; MEMCP lac, I, 2; CEAC lac, low, span;
/// AFRD x, BUF, lac; ADD I := I + 1; JMP loop; end: TRML 0` — superinstruction material.
fn array_loop() -> (Vec<u8>, Vec<u32>) {
    build_at(Mode::M16, |a| {
        vec![
            i(0x1C15, vec![d(0), bytes(&[0, 0])]), // 0 I := 0
            i(0x1302, vec![d(2), d(0), d(4)]),     // 1 LE c, I, three
            i(0x1C02, vec![d(2), l(a[8])]),        // 2 JZ c, end
            i(0x1C1F, vec![d(6), d(0), imm(2)]),   // 3 MEMCP lac, I
            i(0x1C2E, vec![d(6), d(8), d(10)]),    // 4 CEAC lac, low, span
            i(0x1C2A, vec![d(12), d(20), d(6)]),   // 5 AFRD x, BUF, lac
            i(0x0122, vec![d(0), d(0), d(16)]),    // 6 ADD I, I, one
            i(0x1C00, vec![l(a[1])]),              // 7 JMP loop
            i(0x1C1D, vec![l(0)]),                 // 8 TRML
        ]
    })
}

fn array_vm(data: usize) -> Vm {
    let (code, _) = array_loop();
    let mut vm = Vm::new(&code, data, Mode::M16).unwrap();
    let m = vm.data_mut();
    put(m, 4, 3i16.to_le_bytes()); // three
    put(m, 8, 0i16.to_le_bytes()); // low
    put(m, 10, 3i16.to_le_bytes()); // span
    put(m, 16, 1i16.to_le_bytes()); // one
    for j in 0..4u32 {
        let a = 20 + 4 * j as usize;
        if a + 4 <= m.len() {
            put(m, a, (100 + j).to_le_bytes());
        }
    }
    vm
}

#[test]
fn superinstructions_count_and_stop_exactly() {
    let (_, at) = array_loop();
    // A whole scan: 1 + 4 × 7 + 2 (LE, JZ) + 1 (TRML).
    let mut vm = array_vm(64);
    assert_eq!(vm.superinstructions(), 3);
    // The ADD, JMP, LE and JZ of the back edge are one loop step.
    assert_eq!(vm.steps, [(6, 1)]);
    let o = vm.run(None, u64::MAX).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Trml,
            executed: 1 + 4 * 7 + 2 + 1
        }
    );
    let full = vm.data().to_vec();
    assert_eq!(u32::from_le_bytes(get(&vm, 12)), 103);
    assert_eq!(i16_at(&vm, 6), 3);
    // Every budget stops after exactly that many instructions, at the right PC, and
    // stepping through gives the same state.
    let trace: Vec<u32> = {
        let mut vm = array_vm(64);
        let mut t = vec![vm.pc()];
        while vm.run(None, 1).unwrap().end == End::Budget {
            t.push(vm.pc());
        }
        assert_eq!(vm.data(), full.as_slice());
        t
    };
    assert_eq!(trace.len(), 32);
    for b in 1..32u64 {
        let mut vm = array_vm(64);
        let o = vm.run(None, b).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::Budget,
                executed: b
            },
            "budget {b}"
        );
        assert_eq!(vm.pc(), trace[b as usize], "budget {b}");
        let o = vm.run(None, u64::MAX).unwrap();
        assert_eq!(o.executed, 32 - b, "budget {b}");
    }
    // stop_at inside the sequences (LE and JZ, which the loop step jumps over too,
    // CEAC, AFRD, JMP).
    for (s, first) in [(at[1], 1), (at[2], 2), (at[4], 4), (at[5], 5), (at[7], 7)] {
        let mut vm = array_vm(64);
        let o = vm.run(Some(s), u64::MAX).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::StopAt,
                executed: first
            },
            "stop at {s:#x}"
        );
        assert_eq!(vm.pc(), s);
        // And the superinstructions are back afterwards.
        let o = vm.run(None, u64::MAX).unwrap();
        assert_eq!(o.executed, 32 - first);
    }
    // A stop at the comparison or the branch that the loop step at the ADD reaches by
    // its jump: the step runs as ADD and JMP only.
    for (s, n) in [(at[1], 2), (at[2], 3)] {
        let mut vm = array_vm(64);
        assert_eq!(vm.run(Some(at[6]), u64::MAX).unwrap().executed, 6);
        let o = vm.run(Some(s), u64::MAX).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::StopAt,
                executed: n
            },
            "stop at {s:#x}"
        );
        assert_eq!(vm.run(None, u64::MAX).unwrap().executed, 32 - 6 - n);
    }
}

#[test]
fn faults_inside_superinstructions_name_the_instruction() {
    let (_, at) = array_loop();
    // BUF[2] is outside 28 bytes of data: the AFRD of the third iteration faults.
    let mut vm = array_vm(28);
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert!(e.0.starts_with(&format!("at PC {:04x}:", at[5])), "{e}");
    assert_eq!(vm.pc(), at[5]);
    assert_eq!(vm.executed(), 1 + 2 * 7 + 2 + 2);
    assert_eq!(i16_at(&vm, 6), 2);
    // A CEAC whose `low` is outside data memory faults at the CEAC, after the MEMCP.
    let (code, _) = array_loop();
    let mut code = code;
    // Patch the CEAC's `low` operand (instruction 4: opcode 2 bytes, lac 2 bytes).
    let o = at[4] as usize + 4;
    code[o..o + 2].copy_from_slice(&0x0100u16.to_le_bytes());
    let mut vm = Vm::new(&code, 64, Mode::M16).unwrap();
    put(vm.data_mut(), 4, 3i16.to_le_bytes());
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[4], "{e}");
    assert_eq!(vm.executed(), 1 + 2 + 1);
    // The loop step's ADD reading outside data memory faults at the ADD.
    let (mut code, _) = array_loop();
    let o = at[6] as usize + 6;
    code[o..o + 2].copy_from_slice(&0x0100u16.to_le_bytes());
    let mut vm = Vm::new(&code, 64, Mode::M16).unwrap();
    assert_eq!(vm.steps, [(6, 1)]);
    put(vm.data_mut(), 4, 3i16.to_le_bytes());
    put(vm.data_mut(), 10, 3i16.to_le_bytes());
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[6], "{e}");
    assert_eq!(vm.executed(), 1 + 2 + 3);
}

/// `Vm::for_port` stops where the C VM of the port is undefined or misreads
/// (reference/cpdev-vm-opcodes.md §3), and runs what is defined there.
#[test]
fn port_checks_stop_on_what_c_leaves_undefined() {
    use crate::port::Port;
    // One instruction on operands at 100 and 108 (result at 0), then TRML.
    let run = |port: Port, op: u16, x: &[u8], y: &[u8]| -> Result<(), String> {
        let code = build(Mode::M16, |a| {
            vec![
                i(
                    op,
                    if op >> 8 == 0x05 || op >> 8 == 0x19 || matches!(op, 0x0611..=0x0637) {
                        vec![d(0), d(100)]
                    } else {
                        vec![d(0), d(100), d(108)]
                    },
                ),
                i(0x1C1D, vec![l(a[0])]),
            ]
        });
        let mut vm = Vm::for_port(&code, 256, Mode::M16, port).unwrap();
        vm.data_mut()[100..100 + x.len()].copy_from_slice(x);
        vm.data_mut()[108..108 + y.len()].copy_from_slice(y);
        vm.run_cycle(10).map(|_| ()).map_err(|e| e.to_string())
    };
    let w = 0xFFFFu16.to_le_bytes();
    let i300 = 300i16.to_le_bytes();
    // MUL WORD: the uint16 operands are promoted to a signed 32-bit int.
    assert!(run(Port::Full, 0x0326, &w, &w)
        .unwrap_err()
        .contains("overflows"));
    assert!(run(Port::Avr, 0x0326, &w, &w).is_ok());
    // MUL INT: fine in a 32-bit int, overflows a 16-bit one.
    assert!(run(Port::Full, 0x0322, &i300, &i300).is_ok());
    assert!(run(Port::Avr, 0x0322, &i300, &i300).is_err());
    // NEG DINT MIN, ABS DINT MIN (labs), DIV by zero, DINT MIN / -1.
    let dmin = i32::MIN.to_le_bytes();
    assert!(run(Port::Full, 0x0503, &dmin, &[]).is_err());
    assert!(run(Port::Full, 0x0613, &dmin, &[]).is_err());
    assert!(run(Port::Full, 0x0403, &dmin, &0i32.to_le_bytes()).is_err());
    assert!(run(Port::Full, 0x0403, &dmin, &(-1i32).to_le_bytes()).is_err());
    assert!(run(Port::Full, 0x0403, &dmin, &(-2i32).to_le_bytes()).is_ok());
    // INT MIN / -1 only where int has 16 bits.
    let imin = i16::MIN.to_le_bytes();
    let m1 = (-1i16).to_le_bytes();
    assert!(run(Port::Full, 0x0402, &imin, &m1).is_ok());
    assert!(run(Port::Avr, 0x0402, &imin, &m1).is_err());
    // A LINT with bit 31 set and a high half not all ones is misread on `full`.
    let big = (1i64 << 31).to_le_bytes();
    let zero = 0i64.to_le_bytes();
    assert!(run(Port::Full, 0x1004, &big, &zero)
        .unwrap_err()
        .contains("misread"));
    assert!(run(Port::Full, 0x1008, &big, &zero).is_ok());
    assert!(run(Port::Full, 0x1004, &(-5i64).to_le_bytes(), &zero).is_ok());
    // ROL DWORD by 0 shifts by 32 in C; by 1 is fine; SHL WORD 0x8000 by 16.
    let dw = 0x8000_0001u32.to_le_bytes();
    assert!(run(Port::Full, 0x0B23, &dw, &0i16.to_le_bytes()).is_err());
    assert!(run(Port::Full, 0x0B23, &dw, &1i16.to_le_bytes()).is_ok());
    assert!(run(
        Port::Full,
        0x0B02,
        &0x8000u16.to_le_bytes(),
        &16i16.to_le_bytes()
    )
    .is_err());
    // TRUNC out of range, and NaN.
    assert!(run(Port::Full, 0x0634, &1e10f32.to_le_bytes(), &[]).is_err());
    assert!(run(Port::Full, 0x0634, &f32::NAN.to_le_bytes(), &[]).is_err());
    assert!(run(Port::Full, 0x0634, &(-2.5f32).to_le_bytes(), &[]).is_ok());
    // An instruction the port's VM lacks is an error there, and runs elsewhere.
    let lreal = 1.5f64.to_le_bytes();
    assert!(run(Port::Esp32, 0x012A, &lreal, &lreal)
        .unwrap_err()
        .contains("port `esp32` lacks"));
    assert!(run(Port::Full, 0x012A, &lreal, &lreal).is_ok());
    // Plain Vm::new computes them all.
    let code = build(Mode::M16, |a| {
        vec![i(0x0503, vec![d(0), d(100)]), i(0x1C1D, vec![l(a[0])])]
    });
    let mut vm = Vm::new(&code, 256, Mode::M16).unwrap();
    vm.data_mut()[100..104].copy_from_slice(&dmin);
    vm.run_cycle(10).unwrap();
    assert_eq!(i32_at(&vm, 0), i32::MIN);
}

/// `I := 0; loop: LT c := I < four; SEL s := c ? I : zero; JZ c, end; MEMCP lac, s, #2;
/// CEAC lac, low, span; AFRD x, BUF, lac; JMP next; next: ADD sum := sum + x;
/// ADD I := I + one; JMP loop; end: TRML 0` — the comparison-SEL-JZ, array-access-JMP
/// and ADD-JMP superinstructions.
fn guarded_loop() -> (Vec<u8>, Vec<u32>) {
    build_at(Mode::M16, |a| {
        vec![
            i(0x1C15, vec![d(0), bytes(&[0, 0])]),     // 0 I := 0
            i(0x1402, vec![d(2), d(0), d(4)]),         // 1 LT c, I, four
            i(0x0C02, vec![d(18), d(2), d(36), d(0)]), // 2 SEL s, c, zero, I
            i(0x1C02, vec![d(2), l(a[11])]),           // 3 JZ c, end
            i(0x1C1F, vec![d(6), d(18), imm(2)]),      // 4 MEMCP lac, s
            i(0x1C2E, vec![d(6), d(8), d(10)]),        // 5 CEAC lac, low, span
            i(0x1C2A, vec![d(12), d(20), d(6)]),       // 6 AFRD x, BUF, lac
            i(0x1C00, vec![l(a[8])]),                  // 7 JMP next
            i(0x0127, vec![d(38), d(38), d(12)]),      // 8 ADD sum, sum, x
            i(0x0122, vec![d(0), d(0), d(16)]),        // 9 ADD I, I, one
            i(0x1C00, vec![l(a[1])]),                  // 10 JMP loop
            i(0x1C1D, vec![l(0)]),                     // 11 TRML
        ]
    })
}

fn guarded_vm() -> Vm {
    let (code, _) = guarded_loop();
    let mut vm = Vm::new(&code, 64, Mode::M16).unwrap();
    let m = vm.data_mut();
    put(m, 4, 4i16.to_le_bytes()); // four
    put(m, 8, 0i16.to_le_bytes()); // low
    put(m, 10, 3i16.to_le_bytes()); // span
    put(m, 16, 1i16.to_le_bytes()); // one
    put(m, 36, 0i16.to_le_bytes()); // zero
    put(m, 38, 0u32.to_le_bytes()); // sum
    for j in 0..4u32 {
        put(m, 20 + 4 * j as usize, (100 + j).to_le_bytes());
    }
    vm
}

#[test]
fn fused_guards_and_jumps_run_as_single_steps() {
    let (_, at) = guarded_loop();
    assert_eq!(guarded_vm().superinstructions(), 4);
    // Single steps: the PC and data after each instruction.
    let mut trace = Vec::new();
    let mut vm = guarded_vm();
    trace.push((vm.pc(), vm.data().to_vec()));
    while vm.run(None, 1).unwrap().end == End::Budget {
        trace.push((vm.pc(), vm.data().to_vec()));
    }
    let total = trace.len() as u64;
    assert_eq!(total, 1 + 4 * 10 + 3 + 1);
    assert_eq!(u32::from_le_bytes(get(&vm, 38)), 100 + 101 + 102 + 103);
    let o = guarded_vm().run(None, u64::MAX).unwrap();
    assert_eq!(
        o,
        Outcome {
            end: End::Trml,
            executed: total
        }
    );
    for b in 1..total {
        let mut vm = guarded_vm();
        let o = vm.run(None, b).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::Budget,
                executed: b
            },
            "budget {b}"
        );
        assert_eq!(vm.pc(), trace[b as usize].0, "budget {b}");
        assert_eq!(vm.data(), trace[b as usize].1.as_slice(), "budget {b}");
        assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total - b);
    }
    // stop_at inside every sequence.
    for s in [2, 3, 5, 6, 7, 10] {
        let first = trace.iter().position(|t| t.0 == at[s]).unwrap() as u64;
        let mut vm = guarded_vm();
        let o = vm.run(Some(at[s]), u64::MAX).unwrap();
        assert_eq!(
            o,
            Outcome {
                end: End::StopAt,
                executed: first
            },
            "stop at {s}"
        );
        assert_eq!(vm.data(), trace[first as usize].1.as_slice());
        assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total - first);
    }
}

/// `AORD v, BUF, idx; JZ v, zero; MCD r := 1; TRML; zero: MCD r := 2; TRML` (and JNZ):
/// the read and the branch are one entry that counts two instructions, branches on
/// the element read, and faults at the AORD when the element is outside data memory.
#[test]
fn an_array_read_and_its_branch_run_as_one_entry() {
    for (jump, taken_on_zero) in [(0x1C02u16, true), (0x1C01, false)] {
        let (code, at) = build_at(Mode::M16, |a| {
            vec![
                i(0x1C26, vec![d(0), d(16), d(2)]), // AORD v, BUF, idx
                i(jump, vec![d(0), l(a[4])]),       // JZ/JNZ v, other
                i(0x1C15, vec![d(4), bytes(&[1])]), // r := 1
                i(0x1C1D, vec![l(0)]),              // TRML
                i(0x1C15, vec![d(4), bytes(&[2])]), // other: r := 2
                i(0x1C1D, vec![l(0)]),
            ]
        });
        for (idx, elem) in [(0i16, 0u8), (3, 7), (40, 0)] {
            let mut vm = Vm::new(&code, 32, Mode::M16).unwrap();
            assert_eq!(vm.superinstructions(), 1);
            let m = vm.data_mut();
            put(m, 2, idx.to_le_bytes());
            if let Some(x) = m.get_mut(16 + idx as usize) {
                *x = elem;
            }
            let r = vm.run(None, u64::MAX);
            if idx == 40 {
                // BUF[40] is outside 32 bytes: the AORD faults, nothing else ran.
                assert!(r.is_err());
                assert_eq!((vm.pc(), vm.executed()), (at[0], 0));
                continue;
            }
            assert_eq!(r.unwrap().executed, 4);
            let jumped = (elem == 0) == taken_on_zero;
            assert_eq!(get::<1>(&vm, 4)[0], if jumped { 2 } else { 1 });
            assert_eq!(get::<1>(&vm, 0)[0], elem);
        }
    }
}

/// The VM `make` builds runs `total` instructions to TRML; every budget below that
/// stops after exactly that many, at the PC single steps reach, and the rest of the
/// run ends in the same memory. Returns that memory.
fn budgets_stop_exactly(make: impl Fn() -> Vm, total: u64) -> Vec<u8> {
    let mut vm = make();
    assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total);
    let full = vm.data().to_vec();
    let mut one = make();
    let mut trace = vec![one.pc()];
    while one.run(None, 1).unwrap().end == End::Budget {
        trace.push(one.pc());
    }
    assert_eq!(one.data(), full.as_slice());
    assert_eq!(trace.len() as u64, total);
    for b in 1..total {
        let mut vm = make();
        assert_eq!(vm.run(None, b).unwrap().executed, b, "budget {b}");
        assert_eq!(vm.pc(), trace[b as usize], "budget {b}");
        assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total - b);
        assert_eq!(vm.data(), full.as_slice());
    }
    full
}

/// After stopping at `first` (`before` instructions in), a stop at each `(s, n)` comes
/// `n` instructions later, and the run then ends in `full` after `total`.
fn stops_after(
    make: impl Fn() -> Vm,
    (first, before): (u32, u64),
    stops: &[(u32, u64)],
    total: u64,
    full: &[u8],
) {
    for &(s, n) in stops {
        let mut vm = make();
        assert_eq!(vm.run(Some(first), u64::MAX).unwrap().executed, before);
        let o = vm.run(Some(s), u64::MAX).unwrap();
        assert_eq!((o.end, o.executed), (End::StopAt, n), "stop at {s:#x}");
        assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total - before - n);
        assert_eq!(vm.data(), full);
    }
}

/// `I := 0; loop: LE c, I, three; JZ c, end; AOWR v, BUF, I; ADD I, I, one; JMP loop;
/// end: TRML`: the write and the loop step are one entry (and the ADD's own step
/// stays for jumps to it).
fn write_loop() -> (Vec<u8>, Vec<u32>) {
    build_at(Mode::M16, |a| {
        vec![
            i(0x1C15, vec![d(0), bytes(&[0, 0])]), // 0 I := 0
            i(0x1302, vec![d(2), d(0), d(4)]),     // 1 LE c, I, three
            i(0x1C02, vec![d(2), l(a[6])]),        // 2 JZ c, end
            i(0x1C27, vec![d(6), d(20), d(0)]),    // 3 AOWR v, BUF, I
            i(0x0122, vec![d(0), d(0), d(16)]),    // 4 ADD I, I, one
            i(0x1C00, vec![l(a[1])]),              // 5 JMP loop
            i(0x1C1D, vec![l(0)]),                 // 6 TRML
        ]
    })
}

/// `code` with the third operand of the 16-bit-mode instruction at `pc` (opcode 2
/// bytes, operands 2 each) set to `to`, if given.
fn third_operand(mut code: Vec<u8>, pc: u32, to: Option<u16>) -> Vec<u8> {
    if let Some(o) = to {
        let p = pc as usize + 6;
        code[p..p + 2].copy_from_slice(&o.to_le_bytes());
    }
    code
}

fn write_vm(data: usize, one_at: Option<u16>) -> Vm {
    write_vm_to(3, data, one_at)
}

/// [`write_vm`] with `last` in place of `three`.
fn write_vm_to(last: i16, data: usize, one_at: Option<u16>) -> Vm {
    // `one_at`: where the ADD's `one` operand points instead.
    let (code, at) = write_loop();
    let code = third_operand(code, at[4], one_at);
    let mut vm = Vm::new(&code, data, Mode::M16).unwrap();
    let m = vm.data_mut();
    put(m, 4, last.to_le_bytes()); // three
    m[6] = 0x5A; // v
    put(m, 16, 1i16.to_le_bytes()); // one
    vm
}

#[test]
fn an_array_write_and_the_loop_step_run_as_one_entry() {
    let (_, at) = write_loop();
    let mut vm = write_vm(64, None);
    // LE-JZ, the write with the step, the ADD's own step.
    assert_eq!(vm.superinstructions(), 3);
    assert_eq!(vm.steps, [(3, 1), (4, 1)]);
    let total = 1 + 4 * 5 + 2 + 1;
    assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total);
    assert_eq!(get::<4>(&vm, 20), [0x5A; 4]);
    assert_eq!(i16_at(&vm, 0), 4);
    let make = || write_vm(64, None);
    let full = budgets_stop_exactly(make, total);
    // A stop at the comparison or its branch, reached by the step's jump after the
    // write (the second round: the first reaches them by falling through).
    stops_after(make, (at[3], 3), &[(at[1], 3), (at[2], 4)], total, &full);
    // The write out of data memory (BUF[2] of 22 bytes) faults at the AOWR.
    let mut vm = write_vm(22, None);
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[3], "{e}");
    assert_eq!(vm.executed(), 1 + 2 * 5 + 2);
    // The step's operand out of data memory: the write runs, then the ADD faults.
    let mut vm = write_vm(64, Some(0x0100));
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[4], "{e}");
    assert_eq!(vm.executed(), 1 + 2 + 1);
    assert_eq!(vm.data()[20], 0x5A);
}

#[test]
fn a_loop_step_going_round_its_own_entry_keeps_budgets_and_faults_exact() {
    // The write and the step lead back to their own entry: the entry goes round
    // without returning while its fuel lasts. 61 rounds of 5 instructions.
    let make = || write_vm_to(60, 128, None);
    let total = 1 + 61 * 5 + 2 + 1;
    let full = budgets_stop_exactly(make, total);
    assert_eq!(&full[20..81], &[0x5A; 61]);
    assert_eq!(full[81], 0);
    // BUF[50] is outside 70 bytes: the fiftieth round's write faults, at the AOWR,
    // with every instruction of the rounds before it counted.
    let (_, at) = write_loop();
    for budget in [u64::MAX, 1 + 50 * 5 + 2, 1 + 50 * 5 + 3, 400] {
        let mut vm = write_vm_to(60, 70, None);
        match vm.run(None, budget) {
            Err(e) => assert_eq!((vm.pc(), vm.executed()), (at[3], 1 + 50 * 5 + 2), "{e}"),
            Ok(o) => {
                assert_eq!((o.end, o.executed, vm.pc()), (End::Budget, budget, at[3]));
                assert_eq!(budget, 1 + 50 * 5 + 2);
            }
        }
    }
}

/// `I := 0; loop: GT c, I, three; JNZ c, end; AORD v, BUF, I; JZ v, next; ADD n, n,
/// one; next: ADD I, I, one; JMP loop; end: TRML` (an `IF BUF[I] THEN n := n + 1`
/// loop): the read, its branch and the loop step at the branch's target are one entry.
fn count_loop() -> (Vec<u8>, Vec<u32>) {
    build_at(Mode::M16, |a| {
        vec![
            i(0x1C15, vec![d(0), bytes(&[0, 0])]), // 0 I := 0
            i(0x1002, vec![d(2), d(0), d(4)]),     // 1 GT c, I, three
            i(0x1C01, vec![d(2), l(a[8])]),        // 2 JNZ c, end
            i(0x1C26, vec![d(6), d(20), d(0)]),    // 3 AORD v, BUF, I
            i(0x1C02, vec![d(6), l(a[6])]),        // 4 JZ v, next
            i(0x0122, vec![d(8), d(8), d(16)]),    // 5 ADD n, n, one
            i(0x0122, vec![d(0), d(0), d(16)]),    // 6 next: ADD I, I, one
            i(0x1C00, vec![l(a[1])]),              // 7 JMP loop
            i(0x1C1D, vec![l(0)]),                 // 8 TRML
        ]
    })
}

fn count_vm(data: usize, one_at: Option<u16>) -> Vm {
    // `one_at`: where the step's ADD's `one` operand points instead.
    let (code, at) = count_loop();
    let code = third_operand(code, at[6], one_at);
    let mut vm = Vm::new(&code, data, Mode::M16).unwrap();
    let m = vm.data_mut();
    put(m, 4, 3i16.to_le_bytes()); // three
    put(m, 8, 0i16.to_le_bytes()); // n
    put(m, 16, 1i16.to_le_bytes()); // one
    for (j, x) in [0u8, 7, 0, 3].into_iter().enumerate() {
        if let Some(b) = m.get_mut(20 + j) {
            *b = x;
        }
    }
    vm
}

#[test]
fn an_array_read_its_branch_and_the_loop_step_run_as_one_entry() {
    let (_, at) = count_loop();
    let mut vm = count_vm(64, None);
    // GT-JNZ, the read with the branch and the step, the ADD's own step.
    assert_eq!(vm.superinstructions(), 3);
    assert_eq!(vm.steps, [(3, 6), (3, 1), (6, 1)]);
    // Four rounds of GT, JNZ, AORD, JZ, ADD, JMP, two with the ADD of n.
    let total = 1 + 4 * 6 + 2 + 2 + 1;
    assert_eq!(vm.run(None, u64::MAX).unwrap().executed, total);
    assert_eq!(i16_at(&vm, 8), 2);
    let make = || count_vm(64, None);
    let full = budgets_stop_exactly(make, total);
    // Stops at the step's ADD and JMP and at the comparison and its branch, reached
    // from the read's branch on BUF[0] = 0.
    let stops = [(at[6], 2), (at[7], 3), (at[1], 4), (at[2], 5)];
    stops_after(make, (at[3], 3), &stops, total, &full);
    // BUF[1] outside 21 bytes: the read faults, at the AORD.
    let mut vm = count_vm(21, None);
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[3], "{e}");
    assert_eq!(vm.executed(), 1 + 6 + 2);
    // The step's operand outside data memory: the read and the branch run, then the
    // step's ADD faults.
    let mut vm = count_vm(64, Some(0x0100));
    let e = vm.run(None, u64::MAX).unwrap_err();
    assert_eq!(vm.pc(), at[6], "{e}");
    assert_eq!(vm.executed(), 1 + 2 + 2);
}
