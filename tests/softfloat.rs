//! The PIC16 soft-float library (`backends/pic16/softfloat/softfloat.st`, IEEE 754
//! binary32 in Structured Text over DWORD bit patterns) against Rust's `f32`.
//!
//! The library is built together with a test PROGRAM that calls every function on
//! `LANES` operand pairs per scan, and run on the `host` machine (Cranelift JIT). Every
//! result must be bit-exact; where Rust's result is a NaN, the library must return its
//! canonical quiet NaN 16#7FC0_0000. Operands: every pair of special values, then a
//! fixed-seed random set mixing uniformly random bit patterns with values of nearby
//! exponents, half-ulp ties, short significands, products and quotients near the
//! subnormal range, and integer-like patterns; a generator check makes sure these
//! hard cases (ties, cancellations, subnormal results, ...) stay frequent. The IR
//! interpreter runs the special pairs and a few thousand random ones too.
//!
//! Ignored tests, for changes to the library or the PIC16 backend (run with
//! `cargo test --release --test softfloat -- --ignored --nocapture`):
//! `softfloat_long_run` (16M sweep of the bit patterns plus 20M random pairs on the
//! host) and `softfloat_on_pic16` (the library compiled by the PIC16 backend, on its
//! simulator; `SOFTFLOAT_TARGET` picks another target, `SOFTFLOAT_PIC_PAIRS` the number
//! of random pairs).

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::ElemType;
use std::cmp::Ordering;
use std::fmt::Write as _;

/// Operand pairs per scan.
const LANES: usize = 8;

/// Random operand pairs (besides the special values crossed with each other).
const RANDOM_PAIRS: usize = 200_000;

/// Random operand pairs also run on the IR interpreter.
const INTERP_RANDOM_PAIRS: usize = 4_000;

/// The library's NaN.
const QNAN: u32 = 0x7FC0_0000;

/// The name of the test PROGRAM.
const PROG: &str = "sftest";

/// The functions under test, as `(output variable prefix, IEC type of the result,
/// ST call with `$a` and `$b` standing for the operands)`.
const CALLS: &[(&str, &str, &str)] = &[
    ("add", "DWORD", "SF_ADD($a, $b)"),
    ("sub", "DWORD", "SF_SUB($a, $b)"),
    ("mul", "DWORD", "SF_MUL($a, $b)"),
    ("div", "DWORD", "SF_DIV($a, $b)"),
    ("cmp", "SINT", "SF_CMP($a, $b)"),
    ("sqrt", "DWORD", "SF_SQRT($a)"),
    ("trunc", "DWORD", "SF_TRUNC($a)"),
    ("floor", "DWORD", "SF_FLOOR($a)"),
    ("ceil", "DWORD", "SF_CEIL($a)"),
    ("nearest", "DWORD", "SF_NEAREST($a)"),
    ("from_dint", "DWORD", "SF_FROM_DINT(DWORD_TO_DINT($a))"),
    ("from_udint", "DWORD", "SF_FROM_UDINT(DWORD_TO_UDINT($b))"),
    (
        "from_lint",
        "DWORD",
        "SF_FROM_LINT(LWORD_TO_LINT(SHL(DWORD_TO_LWORD($a), 32) OR DWORD_TO_LWORD($b)))",
    ),
    (
        "from_ulint",
        "DWORD",
        "SF_FROM_ULINT(LWORD_TO_ULINT(SHL(DWORD_TO_LWORD($b), 32) OR DWORD_TO_LWORD($a)))",
    ),
    ("to_dint", "DINT", "SF_TO_DINT($a)"),
    ("to_udint", "UDINT", "SF_TO_UDINT($a)"),
    ("to_lint", "LINT", "SF_TO_LINT($a)"),
    ("to_ulint", "ULINT", "SF_TO_ULINT($a)"),
];

/// Rust's result of `CALLS[i]` on `(a, b)` as raw bits (signed results
/// sign-extended to 64 bits, as `PlcValue::as_i64` gives them).
fn expected(i: usize, a: u32, b: u32) -> u64 {
    let (fa, fb) = (f32::from_bits(a), f32::from_bits(b));
    let wide = |hi: u32, lo: u32| ((hi as u64) << 32) | lo as u64;
    let f = |x: f32| x.to_bits() as u64;
    match CALLS[i].0 {
        "add" => f(fa + fb),
        "sub" => f(fa - fb),
        "mul" => f(fa * fb),
        "div" => f(fa / fb),
        "cmp" => match fa.partial_cmp(&fb) {
            Some(Ordering::Less) => -1i64 as u64,
            Some(Ordering::Equal) => 0,
            Some(Ordering::Greater) => 1,
            None => 2,
        },
        "sqrt" => f(fa.sqrt()),
        "trunc" => f(fa.trunc()),
        "floor" => f(fa.floor()),
        "ceil" => f(fa.ceil()),
        "nearest" => f(fa.round_ties_even()),
        "from_dint" => f(a as i32 as f32),
        "from_udint" => f(b as f32),
        "from_lint" => f(wide(a, b) as i64 as f32),
        "from_ulint" => f(wide(b, a) as f32),
        "to_dint" => fa as i32 as i64 as u64,
        "to_udint" => fa as u32 as u64,
        "to_lint" => fa as i64 as u64,
        "to_ulint" => fa as u64,
        other => unreachable!("{other}"),
    }
}

/// True when the library's `got` is right for Rust's `want`: equal bits, and a NaN
/// result must be the library's canonical one.
fn matches(ty: &str, want: u64, got: u64) -> bool {
    if ty == "DWORD" && f32::from_bits(want as u32).is_nan() {
        return got == QNAN as u64;
    }
    want == got
}

/// The test PROGRAM: `lanes` operand pairs in, every function's result out.
fn test_program(lanes: usize) -> String {
    let mut s = format!("PROGRAM {PROG}\nVAR_INPUT\n");
    for k in 0..lanes {
        writeln!(s, "    a{k} : DWORD;\n    b{k} : DWORD;").unwrap();
    }
    s.push_str("END_VAR\nVAR_OUTPUT\n");
    for k in 0..lanes {
        for (name, ty, _) in CALLS {
            writeln!(s, "    {name}{k} : {ty};").unwrap();
        }
    }
    s.push_str("END_VAR\n");
    for k in 0..lanes {
        for (name, _, call) in CALLS {
            let call = call
                .replace("$a", &format!("a{k}"))
                .replace("$b", &format!("b{k}"));
            writeln!(s, "    {name}{k} := {call};").unwrap();
        }
    }
    s.push_str("END_PROGRAM\n");
    s
}

#[allow(dead_code)]
#[path = "common/rng.rs"]
mod rng;
use rng::Rng;

/// The draws of this file's cases.
trait FloatDraws {
    /// A random float with biased exponent `e` (clamped to 0..=254), a random sign,
    /// and a fraction that is either full or has only its top few bits random (so
    /// that sums and products can be exact or exact ties).
    fn float(&mut self, e: i32) -> u32;
    /// An integer-like bit pattern: a random value shifted right by a random count,
    /// sometimes negated, sometimes a power of two or a tie pattern.
    fn int_like(&mut self) -> u32;
    /// A random operand pair of one of several kinds.
    fn pair(&mut self) -> (u32, u32);
}

impl FloatDraws for Rng {
    fn float(&mut self, e: i32) -> u32 {
        let sign = self.word() & 0x8000_0000;
        let e = e.clamp(0, 254) as u32;
        let mut frac = self.word() & 0x7F_FFFF;
        if self.below(2) == 0 {
            let keep = self.below(24);
            frac &= !(0x7F_FFFF >> keep) & 0x7F_FFFF;
        }
        sign | (e << 23) | frac
    }

    fn int_like(&mut self) -> u32 {
        let v = match self.below(4) {
            0 => self.word() >> self.below(32),
            1 => 1u32 << self.below(32),
            // 25 significant bits ending in 1: a tie when converted
            2 => ((self.word() >> 7) | 0x0100_0001) >> self.below(8),
            _ => (self.word() >> self.below(32)) & !((1u32 << self.below(20)) - 1),
        };
        if self.below(2) == 0 {
            v.wrapping_neg()
        } else {
            v
        }
    }

    fn pair(&mut self) -> (u32, u32) {
        match self.below(10) {
            0 | 1 => (self.word(), self.word()),
            2 => {
                let a = self.range(0, 255);
                let b = self.range(0, 255);
                (self.float(a), self.float(b))
            }
            // nearly equal magnitudes: massive cancellation in a - b or a + b
            3 => {
                let e = self.range(0, 254);
                let a = self.float(e);
                let b = if self.below(2) == 0 {
                    a ^ (self.word() & ((1u32 << self.below(24)) - 1))
                } else {
                    a.wrapping_add(self.range(-4, 4) as u32)
                };
                (a, b ^ (self.word() & 0x8000_0000))
            }
            // nearby exponents: alignment by a few bits
            4 | 5 => {
                let e = self.range(0, 254);
                let d = if self.below(2) == 0 {
                    self.range(-3, 3)
                } else {
                    self.range(-30, 30)
                };
                (self.float(e), self.float(e + d))
            }
            // b is half an ulp of a (or a little more or less): ties in additions
            6 => {
                let e = self.range(1, 254);
                let a = self.float(e);
                let be = (e - 24 + self.range(-1, 1)).max(0) as u32;
                let frac = match self.below(3) {
                    0 => 0,
                    1 => 0x7F_FFFF,
                    _ => self.word() & 0x40_0001,
                };
                (a, (self.word() & 0x8000_0000) | (be << 23) | frac)
            }
            // products and quotients near or below the smallest normal
            7 => {
                let e = self.range(0, 254);
                let d = self.range(-30, 5);
                if self.below(2) == 0 {
                    (self.float(e), self.float(127 - e + d))
                } else {
                    (self.float(e), self.float(e - 127 - d))
                }
            }
            8 => (self.int_like(), self.int_like()),
            _ => {
                let s = SPECIALS[self.index(SPECIALS.len())];
                if self.below(2) == 0 {
                    (s, self.word())
                } else {
                    let e = self.range(0, 254);
                    (self.float(e), s)
                }
            }
        }
    }
}

/// Special values: zeros, subnormals, normals at the edges, integers at the
/// conversion limits, ties, infinities and NaNs, each with both signs.
const SPECIALS: &[u32] = &[
    0x0000_0000, // 0
    0x0000_0001, // smallest subnormal
    0x0000_0002,
    0x0000_0003,
    0x0040_0000, // a subnormal with only the top fraction bit
    0x007F_FFFF, // largest subnormal
    0x0080_0000, // smallest normal
    0x0080_0001,
    0x00FF_FFFF,
    0x3400_0000, // 2^-23
    0x3380_0000, // 2^-24
    0x3EFF_FFFF, // below 0.5
    0x3F00_0000, // 0.5
    0x3F00_0001,
    0x3F7F_FFFF, // below 1
    0x3F80_0000, // 1
    0x3F80_0001, // 1 + ulp
    0x3FC0_0000, // 1.5
    0x4000_0000, // 2
    0x4020_0000, // 2.5
    0x4040_0000, // 3
    0x4060_0000, // 3.5
    0x4B00_0000, // 2^23
    0x4AFF_FFFF, // 2^23 - 0.5
    0x4B7F_FFFF, // 2^24 - 1
    0x4B80_0000, // 2^24
    0x4EFF_FFFF, // below 2^31
    0x4F00_0000, // 2^31
    0x4F7F_FFFF, // below 2^32
    0x4F80_0000, // 2^32
    0x5EFF_FFFF, // below 2^63
    0x5F00_0000, // 2^63
    0x5F7F_FFFF, // below 2^64
    0x5F80_0000, // 2^64
    0x7F00_0000, // 2^127
    0x7F7F_FFFF, // largest finite
    0x7F80_0000, // infinity
    0x7F80_0001, // signalling NaN
    0x7FC0_0000, // quiet NaN
    0x7FFF_FFFF, // NaN with every fraction bit
];

/// Every special value with both signs.
fn specials() -> Vec<u32> {
    SPECIALS
        .iter()
        .flat_map(|&s| [s, s | 0x8000_0000])
        .collect()
}

/// True when `v` (exact) lies exactly halfway between two neighbouring finite
/// floats.
fn is_f32_tie(v: f64) -> bool {
    let r = v as f32 as f64;
    if r == v || !r.is_finite() {
        return false;
    }
    let other = 2.0 * v - r;
    other.is_finite() && other as f32 as f64 == other
}

/// True when converting `v` to a float is a tie.
fn is_int_tie(v: u64) -> bool {
    let bits = 64 - v.leading_zeros();
    if bits <= 24 {
        return false;
    }
    let shift = bits - 24;
    v & ((1u64 << shift) - 1) == 1u64 << (shift - 1)
}

/// Counts of the hard cases among the pairs, so that a change of the generator that
/// stops exercising them fails: `(name, count)`.
fn hard_cases(pairs: &[(u32, u32)]) -> Vec<(&'static str, usize)> {
    let mut n = [0usize; 8];
    for &(a, b) in pairs {
        let (fa, fb) = (f32::from_bits(a), f32::from_bits(b));
        let (da, db) = (fa as f64, fb as f64);
        if fa.is_finite() && fb.is_finite() {
            // the f64 sum is exact when subtracting an operand gives the other back
            let sum = da + db;
            if sum - da == db && sum - db == da && is_f32_tie(sum) {
                n[0] += 1;
            }
            let diff = da - db;
            if diff - da == -db && is_f32_tie(diff) {
                n[0] += 1;
            }
            for s in [fa + fb, fa - fb] {
                if s != 0.0 && s.abs() < fa.abs().max(fb.abs()) / 256.0 {
                    n[1] += 1;
                }
            }
            if is_f32_tie(da * db) {
                n[2] += 1;
            }
        }
        for r in [fa + fb, fa * fb, fa / fb] {
            if r.is_subnormal() {
                n[3] += 1;
            }
        }
        if fa.is_finite() && fb.is_finite() && !(fa * fb).is_finite() {
            n[4] += 1;
        }
        if fa.is_finite() && fa.fract().abs() == 0.5 {
            n[5] += 1;
        }
        let wide = ((a as u64) << 32) | b as u64;
        for v in [
            (a as i32).unsigned_abs() as u64,
            b as u64,
            (wide as i64).unsigned_abs(),
            ((b as u64) << 32) | a as u64,
        ] {
            if is_int_tie(v) {
                n[6] += 1;
            }
        }
        if fa.is_subnormal() || fb.is_subnormal() {
            n[7] += 1;
        }
    }
    let names = [
        "add/sub ties",
        "cancellations by 8+ bits",
        "mul ties",
        "subnormal results",
        "mul overflows",
        "nearest ties",
        "int-to-float ties",
        "subnormal operands",
    ];
    names.into_iter().zip(n).collect()
}

/// One failure, for the report.
struct Failure {
    call: usize,
    a: u32,
    b: u32,
    want: u64,
    got: u64,
}

/// Runs every pair through the library on `m` (built with `lanes` lanes); returns
/// the failures and the number of checks.
fn run(m: &mut dyn Machine, lanes: usize, pairs: &[(u32, u32)]) -> (Vec<Failure>, usize) {
    let out_paths: Vec<Vec<String>> = (0..lanes)
        .map(|k| {
            CALLS
                .iter()
                .map(|(name, _, _)| format!("{PROG}.{name}{k}"))
                .collect()
        })
        .collect();
    let in_paths: Vec<(String, String)> = (0..lanes)
        .map(|k| (format!("{PROG}.a{k}"), format!("{PROG}.b{k}")))
        .collect();
    let mut failures = Vec::new();
    let mut checks = 0;
    for chunk in pairs.chunks(lanes) {
        for (k, &(a, b)) in chunk.iter().enumerate() {
            let (pa, pb) = &in_paths[k];
            m.write(pa, PlcValue::from_bits(ElemType::DWord, a as u64))
                .unwrap();
            m.write(pb, PlcValue::from_bits(ElemType::DWord, b as u64))
                .unwrap();
        }
        m.scan().unwrap();
        for (k, &(a, b)) in chunk.iter().enumerate() {
            for (i, (_, ty, _)) in CALLS.iter().enumerate() {
                let v = m.read(&out_paths[k][i]).unwrap();
                let got = v.as_i64() as u64;
                let want = expected(i, a, b);
                checks += 1;
                if !matches(ty, want, got) {
                    failures.push(Failure {
                        call: i,
                        a,
                        b,
                        want,
                        got,
                    });
                }
            }
        }
    }
    (failures, checks)
}

/// The library and the test PROGRAM with `lanes` lanes on `target`, cold-started.
fn machine(target: &str, lanes: usize) -> Box<dyn Machine> {
    let lib = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/backends/pic16/softfloat/softfloat.st"
    );
    let lib_text = std::fs::read(lib).unwrap_or_else(|e| panic!("cannot read {lib}: {e}"));
    let texts = vec![
        ("softfloat.st".to_string(), lib_text),
        ("sftest.st".to_string(), test_program(lanes).into_bytes()),
    ];
    let built = build_sources(texts, &BuildOptions::default()).expect("build");
    let errors: Vec<String> = built
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.to_string())
        .collect();
    let module = built
        .module
        .unwrap_or_else(|| panic!("does not compile: {}", errors.join("; ")));
    let mut m = targets::machine(target, &module).unwrap_or_else(|d| {
        let msgs: Vec<String> = d.iter().map(|x| x.to_string()).collect();
        panic!("no {target} machine: {}", msgs.join("; "))
    });
    m.cold_start().unwrap();
    m
}

/// Runs the pairs on `target` and panics with a report if any result differs.
fn check(target: &str, lanes: usize, pairs: &[(u32, u32)], what: &str) {
    let mut m = machine(target, lanes);
    let t = std::time::Instant::now();
    let (failures, checks) = run(m.as_mut(), lanes, pairs);
    assert!(!m.fault(), "the library raised the fault flag");
    println!(
        "softfloat on {target}: {} operand pairs ({what}), {checks} results checked in {:.1?}",
        pairs.len(),
        t.elapsed()
    );
    if failures.is_empty() {
        return;
    }
    let mut per_call = vec![0usize; CALLS.len()];
    for f in &failures {
        per_call[f.call] += 1;
    }
    let mut msg = format!(
        "{} of {checks} results differ from Rust's f32:\n",
        failures.len()
    );
    for (i, n) in per_call.iter().enumerate().filter(|(_, n)| **n > 0) {
        writeln!(msg, "  {}: {n}", CALLS[i].0).unwrap();
    }
    for f in failures.iter().take(30) {
        writeln!(
            msg,
            "  {}(a = {:#010x} {:e}, b = {:#010x} {:e}): want {:#x}, got {:#x}",
            CALLS[f.call].0,
            f.a,
            f32::from_bits(f.a),
            f.b,
            f32::from_bits(f.b),
            f.want,
            f.got
        )
        .unwrap();
    }
    panic!("{msg}");
}

/// The special values crossed with each other, then `n` random pairs.
fn operand_pairs(n: usize, seed: u64) -> Vec<(u32, u32)> {
    let sp = specials();
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for &a in &sp {
        for &b in &sp {
            pairs.push((a, b));
        }
    }
    let mut rng = Rng(seed);
    for _ in 0..n {
        pairs.push(rng.pair());
    }
    pairs
}

#[test]
fn softfloat_is_bit_exact() {
    let pairs = operand_pairs(RANDOM_PAIRS, 0x9E37_79B9_7F4A_7C15);
    let hard = hard_cases(&pairs);
    let hard_text: Vec<String> = hard.iter().map(|(n, c)| format!("{c} {n}")).collect();
    println!("softfloat: hard cases: {}", hard_text.join(", "));
    for (name, count) in &hard {
        assert!(
            *count >= 1000,
            "only {count} {name}: the operand generator is broken"
        );
    }
    let n_special = pairs.len() - RANDOM_PAIRS;
    check(
        "host",
        LANES,
        &pairs,
        &format!("{n_special} special, {RANDOM_PAIRS} random"),
    );
    // The IR interpreter (the reference semantics every backend follows) agrees: the
    // library relies on nothing the JIT happens to do.
    check(
        "interp",
        LANES,
        &pairs[..n_special + INTERP_RANDOM_PAIRS],
        &format!("{n_special} special, {INTERP_RANDOM_PAIRS} random"),
    );
}

/// A longer run, for changes to the library: `cargo test --release --test softfloat
/// -- --ignored --nocapture`. As `a` (every unary function), one random bit pattern
/// in every block of 2^`SOFTFLOAT_STRIDE_LOG` (default 8: 16M patterns), with a
/// random `b`; then `SOFTFLOAT_PAIRS` (default 20M) random pairs with another seed.
#[test]
#[ignore]
fn softfloat_long_run() {
    let env = |name: &str, default: u64| -> u64 {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let stride_log = env("SOFTFLOAT_STRIDE_LOG", 8).min(31);
    let n = env("SOFTFLOAT_PAIRS", 20_000_000) as usize;
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let sweep: Vec<(u32, u32)> = (0..1u64 << (32 - stride_log))
        .map(|i| {
            let a = ((i << stride_log) as u32) | rng.below(1 << stride_log) as u32;
            (a, rng.pair().1)
        })
        .collect();
    check(
        "host",
        LANES,
        &sweep,
        &format!("a: one random pattern per 2^{stride_log}"),
    );
    check(
        "host",
        LANES,
        &operand_pairs(n, 0xD1B5_4A32_D192_ED03),
        "random",
    );
}

/// The library compiled by the PIC16 backend, on its simulator: `cargo test --release
/// --test softfloat -- --ignored --nocapture`. One lane (the chip's RAM holds one);
/// the special values crossed with each other and `SOFTFLOAT_PIC_PAIRS` (default
/// 2000) random pairs.
#[test]
#[ignore]
fn softfloat_on_pic16() {
    let n = std::env::var("SOFTFLOAT_PIC_PAIRS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000);
    let target = std::env::var("SOFTFLOAT_TARGET").unwrap_or("pic16f876a".into());
    check(
        &target,
        1,
        &operand_pairs(n, 0x9E37_79B9_7F4A_7C15),
        "special and random",
    );
}
