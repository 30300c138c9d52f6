//! The PIC16 soft-float elementary functions (`backends/pic16/softfloat/softmath.st`,
//! built on `softfloat.st`) against Rust's `f32` functions (the host's libm).
//!
//! The two libraries are built together with a test PROGRAM that calls every
//! function on `LANES` inputs of its own per scan, and run on the `host` machine
//! (Cranelift JIT). Every result must be within `MAX_ULP` ulp of Rust's (the
//! distance between the bit patterns as ordered integers, +0 and -0 one apart);
//! where Rust gives a NaN the library must give its canonical quiet NaN
//! 16#7FC0_0000. On the special inputs (zeros, infinities, NaNs, +-1, ...), and
//! wherever Rust's result is a NaN, an infinity, a zero or +-1 there, the result
//! must be bit-exact. Inputs: the special values, then a fixed-seed random set
//! for every function mixing uniformly random bit patterns with values in the
//! ranges where each function is interesting. The maximum error per function is
//! printed (`--nocapture`).

use plcc::driver::{build_sources, BuildOptions};
use plcc::targets;
use plcc_ir::machine::Machine;
use plcc_ir::value::PlcValue;
use plcc_ir::ElemType;
use std::fmt::Write as _;

/// Inputs per function per scan.
const LANES: usize = 8;

/// Random inputs per function (besides the special values).
const RANDOM: usize = 100_000;

/// Random inputs per function also run on the IR interpreter.
const INTERP_RANDOM: usize = 1_000;

/// The accepted distance from Rust's result, in ulp.
const MAX_ULP: u64 = 2;

/// The library's NaN.
const QNAN: u32 = 0x7FC0_0000;

/// The name of the test PROGRAM.
const PROG: &str = "smtest";

/// One function under test.
struct Func {
    /// Prefix of its variables in the test PROGRAM.
    name: &'static str,
    /// Its ST call, with `$a` and `$b` standing for the operands.
    call: &'static str,
    /// Whether it takes a second operand.
    binary: bool,
    /// Rust's function.
    rust: fn(f32, f32) -> f32,
    /// The same in f64: nearly the exact value, to measure the library's own error.
    exact: fn(f64, f64) -> f64,
}

const FUNCS: &[Func] = &[
    Func {
        name: "sin",
        call: "SF_SIN($a)",
        binary: false,
        rust: |a, _| a.sin(),
        exact: |a, _| a.sin(),
    },
    Func {
        name: "cos",
        call: "SF_COS($a)",
        binary: false,
        rust: |a, _| a.cos(),
        exact: |a, _| a.cos(),
    },
    Func {
        name: "tan",
        call: "SF_TAN($a)",
        binary: false,
        rust: |a, _| a.tan(),
        exact: |a, _| a.tan(),
    },
    Func {
        name: "asin",
        call: "SF_ASIN($a)",
        binary: false,
        rust: |a, _| a.asin(),
        exact: |a, _| a.asin(),
    },
    Func {
        name: "acos",
        call: "SF_ACOS($a)",
        binary: false,
        rust: |a, _| a.acos(),
        exact: |a, _| a.acos(),
    },
    Func {
        name: "atan",
        call: "SF_ATAN($a)",
        binary: false,
        rust: |a, _| a.atan(),
        exact: |a, _| a.atan(),
    },
    Func {
        name: "exp",
        call: "SF_EXP($a)",
        binary: false,
        rust: |a, _| a.exp(),
        exact: |a, _| a.exp(),
    },
    Func {
        name: "ln",
        call: "SF_LN($a)",
        binary: false,
        rust: |a, _| a.ln(),
        exact: |a, _| a.ln(),
    },
    Func {
        name: "log10",
        call: "SF_LOG10($a)",
        binary: false,
        rust: |a, _| a.log10(),
        exact: |a, _| a.log10(),
    },
    Func {
        name: "pow",
        call: "SF_POW($a, $b)",
        binary: true,
        rust: |a, b| a.powf(b),
        exact: |a, b| a.powf(b),
    },
    Func {
        name: "atan2",
        call: "SF_ATAN2($a, $b)",
        binary: true,
        rust: |a, b| a.atan2(b),
        exact: |a, b| a.atan2(b),
    },
];

/// One input: the operands, and whether the result must be bit-exact.
#[derive(Clone, Copy)]
struct Input {
    a: u32,
    b: u32,
    exact: bool,
}

/// The test PROGRAM: for every function of `funcs`, `lanes` operand pairs in and
/// results out.
fn test_program(funcs: &[&Func], lanes: usize) -> String {
    let mut s = format!("PROGRAM {PROG}\nVAR_INPUT\n");
    for f in funcs {
        for k in 0..lanes {
            writeln!(s, "    {}_a{k} : DWORD;", f.name).unwrap();
            if f.binary {
                writeln!(s, "    {}_b{k} : DWORD;", f.name).unwrap();
            }
        }
    }
    s.push_str("END_VAR\nVAR_OUTPUT\n");
    for f in funcs {
        for k in 0..lanes {
            writeln!(s, "    {}_r{k} : DWORD;", f.name).unwrap();
        }
    }
    s.push_str("END_VAR\n");
    for f in funcs {
        for k in 0..lanes {
            let call = f
                .call
                .replace("$a", &format!("{}_a{k}", f.name))
                .replace("$b", &format!("{}_b{k}", f.name));
            writeln!(s, "    {}_r{k} := {call};", f.name).unwrap();
        }
    }
    s.push_str("END_PROGRAM\n");
    s
}

/// The bit pattern as an integer in the order of the values (+0 and -0 one apart,
/// the infinities one beyond the largest finite values).
fn ordered(x: u32) -> i64 {
    if x & 0x8000_0000 != 0 {
        -((x & 0x7FFF_FFFF) as i64) - 1
    } else {
        x as i64
    }
}

/// The distance in ulp between two non-NaN results.
fn ulps(a: u32, b: u32) -> u64 {
    (ordered(a) - ordered(b)).unsigned_abs()
}

#[allow(dead_code)]
#[path = "common/rng.rs"]
mod rng;
use rng::Rng;

/// The draws of this file's cases.
trait MathDraws {
    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64;
    /// Uniform in `[lo, hi]` (rounded to a float).
    fn uniform(&mut self, lo: f64, hi: f64) -> u32;
    /// A random sign bit.
    fn sign(&mut self) -> u32;
    /// A positive float with a random significand and a biased exponent uniform in
    /// `lo..=hi` (clamped to the finite range; 0 gives subnormals).
    fn magnitude(&mut self, lo: i32, hi: i32) -> u32;
    /// `x` moved by a few ulp (or by up to 2^16 ulp), staying finite.
    fn nudge(&mut self, x: u32) -> u32;
    /// A random input for the function `name`.
    fn input(&mut self, name: &str) -> (u32, u32);
}

impl MathDraws for Rng {
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> u32 {
        ((lo + (hi - lo) * self.unit()) as f32).to_bits()
    }

    fn sign(&mut self) -> u32 {
        self.word() & 0x8000_0000
    }

    fn magnitude(&mut self, lo: i32, hi: i32) -> u32 {
        let e = self.range(lo, hi).clamp(0, 254) as u32;
        (e << 23) | (self.word() & 0x7F_FFFF)
    }

    fn nudge(&mut self, x: u32) -> u32 {
        let d = if self.below(2) == 0 {
            self.range(-4, 4)
        } else {
            self.range(-65536, 65536)
        };
        let m = ((x & 0x7FFF_FFFF) as i64 + d as i64).clamp(0, 0x7F7F_FFFF) as u32;
        (x & 0x8000_0000) | m
    }

    fn input(&mut self, name: &str) -> (u32, u32) {
        let k = self.below(20);
        let b = self.word();
        if k < 4 {
            // uniformly random bit patterns
            return (self.word(), b);
        }
        match name {
            "sin" | "cos" | "tan" => {
                let a = match k {
                    4..=10 => self.uniform(-10.0, 10.0),
                    11..=13 => self.magnitude(97, 160) | self.sign(),
                    // near multiples of pi/2, up to about 2^40
                    14..=16 => {
                        let n = (self.next_u64() >> self.range(24, 63)) as f64;
                        let x = (n * std::f64::consts::FRAC_PI_2) as f32;
                        self.nudge(x.to_bits()) | self.sign()
                    }
                    17 => {
                        let x = HARD_REDUCTIONS[self.index(HARD_REDUCTIONS.len())];
                        let x = if self.below(2) == 0 { x } else { self.nudge(x) };
                        x | self.sign()
                    }
                    _ => self.magnitude(0, 254) | self.sign(),
                };
                (a, b)
            }
            "asin" | "acos" => {
                let a = match k {
                    4..=11 => self.uniform(-1.0, 1.0),
                    // near +-1
                    12..=15 => {
                        let d = (self.next_u64() >> self.range(40, 63)) as u32;
                        (0x3F80_0000 - d.min(0x3F7F_FFFF)) | self.sign()
                    }
                    16..=17 => self.magnitude(90, 126) | self.sign(),
                    _ => self.magnitude(0, 126) | self.sign(),
                };
                (a, b)
            }
            "atan" => {
                let a = match k {
                    4..=10 => self.uniform(-10.0, 10.0),
                    11..=15 => self.magnitude(97, 157) | self.sign(),
                    // near 1 and tan(pi/8) (the reduction thresholds)
                    16..=17 => self.nudge(0x3F80_0000) | self.sign(),
                    18 => self.nudge(0x3ED4_13CD) | self.sign(),
                    _ => self.magnitude(0, 254) | self.sign(),
                };
                (a, b)
            }
            "exp" => {
                let a = match k {
                    4..=12 => self.uniform(-90.0, 90.0),
                    13..=14 => self.magnitude(90, 127) | self.sign(),
                    // overflow, and subnormal results and underflow
                    15..=16 => self.uniform(88.0, 89.0),
                    17..=18 => self.uniform(-104.5, -86.0),
                    _ => self.magnitude(0, 134) | self.sign(),
                };
                (a, b)
            }
            "ln" | "log10" => {
                let a = match k {
                    4..=11 => self.uniform(0.0, 100.0),
                    // near 1
                    12..=15 => self.nudge(0x3F80_0000),
                    _ => self.magnitude(0, 254),
                };
                (a, b)
            }
            "pow" => match k {
                4..=8 => (self.uniform(0.0, 10.0), self.uniform(-20.0, 20.0)),
                // x near 1, large |y|
                9..=11 => {
                    let y = self.magnitude(127, 157) | self.sign();
                    (self.nudge(0x3F80_0000), y)
                }
                // negative x, integral or not y
                12..=13 => {
                    let y = if self.below(2) == 0 {
                        self.range(-40, 40) as f32
                    } else {
                        f32::from_bits(self.uniform(-40.0, 40.0))
                    };
                    (self.uniform(-10.0, 0.0), y.to_bits())
                }
                // any x, small y: results overflowing and underflowing
                14..=16 => {
                    let x = self.magnitude(0, 254) | (self.sign() & self.word());
                    (x, self.uniform(-3.0, 3.0))
                }
                // integral y
                _ => (
                    self.uniform(0.0, 4.0) | self.sign(),
                    (self.range(-64, 64) as f32).to_bits(),
                ),
            },
            "atan2" => match k {
                4..=9 => (self.uniform(-10.0, 10.0), self.uniform(-10.0, 10.0)),
                10..=14 => (
                    self.magnitude(0, 254) | self.sign(),
                    self.magnitude(0, 254) | self.sign(),
                ),
                // nearby exponents, near the diagonal
                _ => {
                    let e = self.range(1, 250);
                    let x = self.magnitude(e, e) | self.sign();
                    let y = if self.below(2) == 0 {
                        self.magnitude(e - 2, e + 2)
                    } else {
                        self.nudge(x)
                    };
                    (y | self.sign(), x)
                }
            },
            other => unreachable!("{other}"),
        }
    }
}

/// The floats whose argument reduction modulo pi/2 cancels the most (the 24
/// smallest |x - k pi/2| relative to pi/2, from an exhaustive search: 2^-29.9 down
/// to 2^-26.5).
const HARD_REDUCTIONS: &[u32] = &[
    0x6F79BE45, 0x50A3E87F, 0x6FF9BE45, 0x5123E87F, 0x437CE5F1, 0x7079BE45, 0x6A1976F1, 0x53B146A6,
    0x65898498, 0x51A3E87F, 0x43FCE5F1, 0x77584625, 0x4C2332E9, 0x4096CBE4, 0x6C55DA58, 0x70F9BE45,
    0x6A9976F1, 0x5C07BCD0, 0x543146A6, 0x66098498, 0x5223E87F, 0x474D246F, 0x723FA09A, 0x447CE5F1,
];

/// Special operands, each also with the sign bit set.
const SPECIALS: &[u32] = &[
    0x0000_0000, // 0
    0x0000_0001, // smallest subnormal
    0x0040_0000,
    0x007F_FFFF, // largest subnormal
    0x0080_0000, // smallest normal
    0x3380_0000, // 2^-24
    0x3900_0000, // 2^-13
    0x3F00_0000, // 0.5
    0x3F49_0FDA, // below pi/4
    0x3F49_0FDB, // pi/4
    0x3F7F_FFFF, // below 1
    0x3F80_0000, // 1
    0x3F80_0001, // above 1
    0x3FC0_0000, // 1.5
    0x3FC9_0FDB, // pi/2
    0x4000_0000, // 2
    0x402D_F854, // e
    0x4040_0000, // 3
    0x4049_0FDB, // pi
    0x4096_CBE4, // 3pi/2, a hard reduction
    0x4120_0000, // 10
    0x42B1_7217, // 88.72283: below the overflow of exp
    0x42B1_7218, // 88.72284: overflows exp
    0x42AE_AC4F, // 87.33654: exp(-x) is the smallest normal, nearly
    0x42CF_E0AB, // 103.97: exp(-x) is half the smallest subnormal, nearly
    0x42D0_0000, // 104
    0x42C8_0000, // 100
    0x4B80_0000, // 2^24
    0x4F00_0000, // 2^31
    0x5F80_0000, // 2^64
    0x6F79_BE45, // the hardest reduction
    0x7E96_7699, // 1e38
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

/// True for operands whose result is a special value: zeros, infinities, NaNs.
fn is_special(x: u32) -> bool {
    x & 0x7FFF_FFFF == 0 || x & 0x7F80_0000 == 0x7F80_0000
}

/// True for results that must come out bit-exact on special inputs.
fn is_special_result(x: u32) -> bool {
    is_special(x) || x & 0x7FFF_FFFF == 0x3F80_0000
}

/// The inputs of `f`: the special values (crossed with each other for binary
/// functions, every `cross_step`th pair), some exact cases, then `n` random inputs.
fn inputs(f: &Func, n: usize, cross_step: usize, seed: u64) -> Vec<Input> {
    let sp = specials();
    let mut v = Vec::new();
    let exact_for = |a: u32, b: u32| {
        let want = (f.rust)(f32::from_bits(a), f32::from_bits(b)).to_bits();
        is_special(a) || (f.binary && is_special(b)) || is_special_result(want)
    };
    if f.binary {
        let pairs = sp.iter().flat_map(|&a| sp.iter().map(move |&b| (a, b)));
        for (a, b) in pairs.step_by(cross_step) {
            v.push(Input {
                a,
                b,
                exact: exact_for(a, b),
            });
        }
    } else {
        for &a in &sp {
            v.push(Input {
                a,
                b: 0,
                exact: exact_for(a, 0),
            });
        }
    }
    // results that are exactly representable
    let exact = |a: f32, b: f32| Input {
        a: a.to_bits(),
        b: b.to_bits(),
        exact: true,
    };
    match f.name {
        "pow" => {
            for x in [2.0f32, -2.0, 3.0, -3.0, 10.0, 0.5, -0.5, 4.0, 0.25, 7.0] {
                for y in -6..=8 {
                    v.push(exact(x, y as f32));
                }
            }
            for (x, y) in [(4.0f32, 0.5f32), (16.0, 0.25), (0.25, -0.5), (9.0, 1.5)] {
                v.push(exact(x, y));
            }
        }
        "log10" => {
            for k in 0..=10 {
                v.push(exact(10f32.powi(k), 0.0));
            }
        }
        "asin" | "acos" | "atan" => {
            for x in [1.0f32, -1.0, 0.0, -0.0] {
                v.push(exact(x, 0.0));
            }
        }
        "exp" | "ln" => v.push(exact(1.0, 0.0)),
        _ => {}
    }
    let mut rng = Rng(seed);
    for _ in 0..n {
        let (a, b) = rng.input(f.name);
        v.push(Input { a, b, exact: false });
    }
    v
}

/// The result of one function over its inputs.
#[derive(Default)]
struct Stats {
    checks: usize,
    /// How many results are 0, 1, 2, more ulp away.
    hist: [usize; 4],
    max_ulp: u64,
    worst: Option<(Input, u32, u32)>,
    /// The largest distance from the f64 result, in ulp of the f32 result.
    max_err: f64,
    worst_err: Option<(Input, u32, u32)>,
    failures: Vec<(Input, u32, u32)>,
}

/// The distance of `got` from `v` in ulp of the floats near `v` (an ulp below
/// the smallest normal is that of the subnormals).
fn ulp_error(v: f64, got: u32) -> f64 {
    let e = (((v.abs().to_bits() >> 52) as i32) - 1023).max(-126);
    (f32::from_bits(got) as f64 - v).abs() / 2f64.powi(e - 23)
}

/// Checks one result, recording a failure; `v` is the f64 result.
fn check_one(st: &mut Stats, inp: Input, want: u32, got: u32, v: f64) {
    st.checks += 1;
    let want_nan = f32::from_bits(want).is_nan();
    let got_nan = f32::from_bits(got).is_nan();
    let ok = if want_nan || got_nan {
        want_nan && got == QNAN
    } else if inp.exact {
        want == got
    } else {
        let d = ulps(want, got);
        st.hist[d.min(3) as usize] += 1;
        if d > st.max_ulp || st.worst.is_none() {
            st.max_ulp = d;
            st.worst = Some((inp, want, got));
        }
        if v.is_finite() && f32::from_bits(got).is_finite() {
            let err = ulp_error(v, got);
            if err > st.max_err {
                st.max_err = err;
                st.worst_err = Some((inp, want, got));
            }
        }
        d <= MAX_ULP
    };
    if !ok {
        st.failures.push((inp, want, got));
    }
}

/// The libraries and the test PROGRAM of `funcs` with `lanes` lanes on `target`,
/// cold-started.
fn machine(target: &str, lanes: usize, funcs: &[&Func]) -> Box<dyn Machine> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/backends/pic16/softfloat/");
    let mut texts = Vec::new();
    for file in ["softfloat.st", "softmath.st"] {
        let path = format!("{dir}{file}");
        let text = std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
        texts.push((file.to_string(), text));
    }
    texts.push((
        "smtest.st".to_string(),
        test_program(funcs, lanes).into_bytes(),
    ));
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

/// Runs every function of `funcs` on its inputs (`sets`, in the same order) on
/// `target` (all functions in the same scans, each on its own inputs) and panics
/// with a report on any failure.
fn check(target: &str, lanes: usize, funcs: &[&Func], sets: &[Vec<Input>], what: &str) {
    let mut m = machine(target, lanes, funcs);
    let t = std::time::Instant::now();
    let path = |f: &Func, v: &str, k: usize| format!("{PROG}.{}_{v}{k}", f.name);
    let paths: Vec<Vec<[String; 3]>> = funcs
        .iter()
        .map(|f| {
            (0..lanes)
                .map(|k| [path(f, "a", k), path(f, "b", k), path(f, "r", k)])
                .collect()
        })
        .collect();
    let mut stats: Vec<Stats> = funcs.iter().map(|_| Stats::default()).collect();
    let scans = sets.iter().map(|s| s.len().div_ceil(lanes)).max().unwrap();
    let dword = |x: u32| PlcValue::from_bits(ElemType::DWord, x as u64);
    for scan in 0..scans {
        for (i, f) in funcs.iter().enumerate() {
            for (k, inp) in sets[i].iter().skip(scan * lanes).take(lanes).enumerate() {
                m.write(&paths[i][k][0], dword(inp.a)).unwrap();
                if f.binary {
                    m.write(&paths[i][k][1], dword(inp.b)).unwrap();
                }
            }
        }
        m.scan().unwrap();
        for (i, f) in funcs.iter().enumerate() {
            for (k, &inp) in sets[i].iter().skip(scan * lanes).take(lanes).enumerate() {
                let got = m.read(&paths[i][k][2]).unwrap().as_i64() as u32;
                let (a, b) = (f32::from_bits(inp.a), f32::from_bits(inp.b));
                let want = (f.rust)(a, b).to_bits();
                let v = (f.exact)(a as f64, b as f64);
                check_one(&mut stats[i], inp, want, got, v);
            }
        }
    }
    assert!(!m.fault(), "the library raised the fault flag");
    let total: usize = stats.iter().map(|s| s.checks).sum();
    println!(
        "softmath on {target}: {total} results ({what}) checked in {:.1?}",
        t.elapsed()
    );
    let show = |(inp, want, got): &(Input, u32, u32), f: &Func| {
        let args = if f.binary {
            format!(
                "{:#010x} {:e}, {:#010x} {:e}",
                inp.a,
                f32::from_bits(inp.a),
                inp.b,
                f32::from_bits(inp.b)
            )
        } else {
            format!("{:#010x} {:e}", inp.a, f32::from_bits(inp.a))
        };
        format!(
            "{}({args}): want {want:#010x} {:e}, got {got:#010x} {:e}",
            f.name,
            f32::from_bits(*want),
            f32::from_bits(*got)
        )
    };
    let mut msg = String::new();
    for (f, st) in funcs.iter().zip(&stats) {
        let worst = st.worst.as_ref().map(|w| show(w, f)).unwrap_or_default();
        let worst_err = st
            .worst_err
            .as_ref()
            .map(|w| show(w, f))
            .unwrap_or_default();
        println!(
            "  {:6} {:7} results: max {} ulp from Rust's (0/1/2/more ulp: {:?}), worst {worst}; \
             max {:.3} ulp from f64, worst {worst_err}",
            f.name, st.checks, st.max_ulp, st.hist, st.max_err
        );
        if !st.failures.is_empty() {
            writeln!(msg, "{}: {} failures", f.name, st.failures.len()).unwrap();
            for x in st.failures.iter().take(12) {
                writeln!(msg, "  {}", show(x, f)).unwrap();
            }
        }
    }
    if !msg.is_empty() {
        panic!("results differ from Rust's f32:\n{msg}");
    }
}

/// The inputs of every function, `n` random ones each.
fn all_inputs(n: usize, cross_step: usize) -> Vec<Vec<Input>> {
    FUNCS
        .iter()
        .enumerate()
        .map(|(i, f)| {
            inputs(
                f,
                n,
                cross_step,
                0x9E37_79B9_7F4A_7C15 ^ ((i as u64 + 1) * 0x1234_5678_9ABC),
            )
        })
        .collect()
}

/// Every function.
fn all_funcs() -> Vec<&'static Func> {
    FUNCS.iter().collect()
}

#[test]
fn softmath_is_accurate() {
    let funcs = all_funcs();
    check(
        "host",
        LANES,
        &funcs,
        &all_inputs(RANDOM, 1),
        "special and random",
    );
    // The IR interpreter (the reference semantics every backend follows) agrees on
    // a smaller set: the library relies on nothing the JIT happens to do.
    check(
        "interp",
        LANES,
        &funcs,
        &all_inputs(INTERP_RANDOM, 13),
        "special and random",
    );
}

/// A longer run: `cargo test --release --test softmath -- --ignored --nocapture`,
/// `SOFTMATH_RANDOM` (default 2M) random inputs per function with another seed,
/// then for every function one random bit pattern (the first operand) in every
/// block of 2^`SOFTMATH_STRIDE_LOG` (default 10: 4M patterns).
#[test]
#[ignore]
fn softmath_long_run() {
    let env = |name: &str, default: u64| -> u64 {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let n = env("SOFTMATH_RANDOM", 2_000_000) as usize;
    let stride_log = env("SOFTMATH_STRIDE_LOG", 10).min(31);
    let funcs = all_funcs();
    let sets: Vec<Vec<Input>> = FUNCS
        .iter()
        .enumerate()
        .map(|(i, f)| {
            inputs(
                f,
                n,
                1,
                0xD1B5_4A32_D192_ED03 ^ ((i as u64 + 1) * 0x0009_8765_4321),
            )
        })
        .collect();
    check("host", LANES, &funcs, &sets, "random");
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let sweep: Vec<Vec<Input>> = FUNCS
        .iter()
        .map(|f| {
            (0..1u64 << (32 - stride_log))
                .map(|i| Input {
                    a: ((i << stride_log) as u32) | rng.below(1 << stride_log) as u32,
                    b: if f.binary { rng.word() } else { 0 },
                    exact: false,
                })
                .collect()
        })
        .collect();
    check(
        "host",
        LANES,
        &funcs,
        &sweep,
        &format!("one random pattern per 2^{stride_log}"),
    );
}

/// The library compiled by the PIC16 backend, on its simulator: `cargo test
/// --release --test softmath -- --ignored --nocapture`. One function per
/// program (all of them together do not fit the chip's 8K words of flash), one
/// lane; the special values (every 29th crossed pair for the binary functions)
/// and `SOFTMATH_PIC_RANDOM` (default 200) random inputs.
#[test]
#[ignore]
fn softmath_on_pic16() {
    let n = std::env::var("SOFTMATH_PIC_RANDOM")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let target = std::env::var("SOFTMATH_TARGET").unwrap_or("pic16f876a".into());
    for (i, f) in FUNCS.iter().enumerate() {
        let set = inputs(
            f,
            n,
            29,
            0x9E37_79B9_7F4A_7C15 ^ ((i as u64 + 1) * 0x1234_5678_9ABC),
        );
        check(&target, 1, &[f], &[set], "special and random");
    }
}
