//! Differential testing: random well-typed programs ([`gen`]) are compiled once and
//! run scan by scan on every machine, with random inputs between scans; every variable
//! and the fault flag must be the same on all of them after cold start and after
//! every scan. A mismatch is shrunk ([`shrink`]) to a small reproducer.
//!
//! `plcc difftest` runs campaigns; `tests/difftest.rs` runs a fixed-seed batch.

pub mod gen;
mod model;
pub mod oo;
pub mod plcopen;
mod print;
pub mod sfc;
pub mod shrink;

use crate::driver::{build_sources, BuildOptions};
use crate::targets;
use gen::{Gen, Prog, Rng, T};
use plcc_ir::machine::Machine;
use plcc_ir::passes::promote::Promotion;
use plcc_ir::value::PlcValue;
use plcc_ir::Module;

/// What running one program on every machine showed.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Every machine agreed on every variable after every scan.
    Agree {
        /// Machines that ran it (some may not fit the program).
        machines: usize,
    },
    /// Two machines disagreed; the text says where.
    Mismatch(String),
    /// The front end rejected the program: a bug of the generator.
    Rejected(String),
}

/// Backend codes that mean "this program does not fit the target".
const UNFIT: [&str; 6] = ["E9001", "E9002", "E9003", "E9004", "E9101", "E9102"];

/// Builds a program in its dialect (CODESYS's for an OO part that uses its
/// constructs).
pub fn compile(p: &Prog) -> Result<Module, String> {
    build(p, plcc_frontend::ParallelBodies::default())
}

/// Builds a program in its dialect, its POU bodies lowered on two threads as `how`
/// says.
fn build(p: &Prog, how: plcc_frontend::ParallelBodies) -> Result<Module, String> {
    let opts = BuildOptions {
        codesys: p.oo.as_ref().is_some_and(|o| o.codesys),
        parallel_bodies: how,
        ..Default::default()
    };
    build_text("difftest.st", &p.to_st(), &opts)
}

fn random_value(rng: &mut Rng, t: T) -> u64 {
    match t {
        T::Bool => rng.below(2),
        T::Real => match rng.below(4) {
            0 => 0,
            1 => (rng.below(20000) as f32 / 8.0 - 1000.0).to_bits() as u64,
            _ => rng.next_u64() & 0xFFFF_FFFF,
        },
        T::Lreal => (rng.below(2_000_000) as f64 / 16.0 - 50_000.0).to_bits(),
        _ => match rng.below(3) {
            0 => rng.below(10),
            _ => rng.next_u64(),
        },
    }
}

/// The machine a name stands for with a seed: `vmasm` without a setting runs in
/// the addressing mode the seed picks (the default 16-bit mode for half of the
/// seeds, `32a` for 35%, `32` for 15%), so that campaigns cover all three; any
/// other name, `vmasm:mode=16` among them, stands for itself.
pub fn machine_for_seed(name: &str, seed: u64) -> String {
    if name != "vmasm" {
        return name.to_string();
    }
    match Rng::new(seed ^ 0x7A5D_0DE5).below(20) {
        0..=9 => "vmasm".into(),
        10..=16 => "vmasm:mode=32a".into(),
        _ => "vmasm:mode=32".into(),
    }
}

/// Runs `p` on `machines` (the first is the reference; a machine may carry target
/// settings, `vmasm:mode=32a`; plain `vmasm` gets a mode from the seed, see
/// [`machine_for_seed`]) for `scans` scans.
///
/// Each machine runs the build its target gets (the VM's promotes instance
/// variables in loops only: [`targets::promotion`]). Two kinds of machine run
/// another build of the program: the tiered
/// JIT's (`host:tier=quick`, `host:tier=swap-at-2`) runs it as `plcc run` builds it,
/// each function optimised and the whole-program passes left to the machine
/// ([`targets::machine_staged`]); `interp:ir=raw` runs the IR as the front end made
/// it, unoptimised: the oracle of the optimiser, which every other machine trusts.
pub fn check(p: &Prog, machines: &[&str], scans: u32, seed: u64) -> Verdict {
    match compile(p) {
        Ok(module) => match split_differs(p, &module) {
            Some(d) => Verdict::Mismatch(d),
            None => {
                let mut builds = vec![(Build::Full(Promotion::Everywhere), module)];
                for b in machines.iter().map(|m| Build::of(m)) {
                    if builds.iter().any(|(x, _)| *x == b) {
                        continue;
                    }
                    match build_as(p, b) {
                        Ok(m) => builds.push((b, m)),
                        Err(e) => return Verdict::Mismatch(format!("the {b:?} build fails: {e}")),
                    }
                }
                let builds: Vec<(Build, &Module)> = builds.iter().map(|(b, m)| (*b, m)).collect();
                check_builds(&builds, &p.input_paths(), machines, scans, seed)
            }
        },
        Err(e) => Verdict::Rejected(e),
    }
}

/// Which build of a program a machine runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Build {
    /// Optimised for the machine's target, as `plcc build` makes it (most machines;
    /// the VM's promotes in loops only, [`targets::promotion`]).
    Full(Promotion),
    /// Each function optimised, the whole-program passes left to the machine
    /// ([`BuildOptions::staged`]): the tiered JIT's (`host:tier=...`).
    Staged,
    /// Unoptimised ([`BuildOptions::no_opt`]): `interp:ir=raw`.
    Raw,
}

impl Build {
    /// The build a machine spec asks for.
    fn of(spec: &str) -> Build {
        let (target, settings) = targets::split_spec(spec);
        if settings.iter().any(|(k, _)| k == "tier") {
            Build::Staged
        } else if settings.iter().any(|(k, v)| k == "ir" && v == "raw") {
            Build::Raw
        } else {
            Build::Full(targets::promotion(target))
        }
    }
}

/// Builds a program as [`compile`] does, but as `how` says.
fn build_as(p: &Prog, how: Build) -> Result<Module, String> {
    let opts = BuildOptions {
        codesys: p.oo.as_ref().is_some_and(|o| o.codesys),
        staged: how == Build::Staged,
        no_opt: how == Build::Raw,
        promotion: match how {
            Build::Full(p) => p,
            _ => Promotion::Everywhere,
        },
        ..Default::default()
    };
    build_text("difftest.st", &p.to_st(), &opts)
}

/// Builds `p` again with its POU bodies lowered on two threads as often as they can
/// be (the random programs are too small for a build to do it on its own) and says
/// how the module differs from `module`, built in order; `None` if it does not.
fn split_differs(p: &Prog, module: &Module) -> Option<String> {
    match build(p, plcc_frontend::ParallelBodies::Always) {
        Ok(split) if split == *module => None,
        Ok(split) => {
            let (a, b) = (module.to_string(), split.to_string());
            let line = a
                .lines()
                .zip(b.lines())
                .position(|(x, y)| x != y)
                .unwrap_or(a.lines().count().min(b.lines().count()));
            Some(format!(
                "the build with the POU bodies lowered on two threads differs from the build in order, at line {} of the IR:\n  in order: {}\n  split:    {}",
                line + 1,
                a.lines().nth(line).unwrap_or("(end)"),
                b.lines().nth(line).unwrap_or("(end)")
            ))
        }
        Err(e) => Some(format!(
            "the build with the POU bodies lowered on two threads fails, the build in order does not: {e}"
        )),
    }
}

/// Builds one source text (the language from the name's extension).
pub(crate) fn build_text(name: &str, text: &str, opts: &BuildOptions) -> Result<Module, String> {
    build_sources(vec![(name.into(), text.as_bytes().to_vec())], opts)
        .map_err(|e| e.0)?
        .into_module()
}

/// The machine of a name with its setting (`vmasm:mode=32a`). A machine of the
/// tiered JIT (`host:tier=quick`) given an optimised module optimises it again in
/// its background tier, which changes nothing of its meaning; `interp:ir=raw` is the
/// interpreter of whatever module it is given.
pub(crate) fn machine(name: &str, module: &Module) -> Result<Option<Box<dyn Machine>>, String> {
    let (target, settings) = targets::split_spec(name);
    let made = match Build::of(name) {
        Build::Staged => targets::machine_staged(target, module.clone(), &settings),
        Build::Raw if target == "interp" => targets::machine("interp", module),
        Build::Raw => return Err(format!("{name}: only the interpreter runs the raw IR")),
        Build::Full(_) => targets::machine_spec(name, module),
    };
    match made {
        Ok(m) => Ok(Some(m)),
        Err(d) if d.iter().any(|x| UNFIT.contains(&x.code)) => Ok(None),
        Err(d) => Err(format!(
            "{name} cannot build it: {}",
            d.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        )),
    }
}

/// Runs a compiled program on `machines` for `scans` scans, setting `inputs` to
/// random values before each (see [`check`]).
pub fn check_module(
    module: &Module,
    inputs: &[(String, T)],
    machines: &[&str],
    scans: u32,
    seed: u64,
) -> Verdict {
    check_builds(
        &[(Build::Full(Promotion::Everywhere), module)],
        inputs,
        machines,
        scans,
        seed,
    )
}

/// [`check_module`] with the builds each machine runs ([`Build::of`]); the
/// full build first.
fn check_builds(
    builds: &[(Build, &Module)],
    inputs: &[(String, T)],
    machines: &[&str],
    scans: u32,
    seed: u64,
) -> Verdict {
    let module = builds[0].1;
    if module.programs.is_empty() {
        return Verdict::Rejected("no program".into());
    }
    // Every variable of every program instance, and the globals.
    let vars: Vec<String> = crate::scenario::all_variables(module)
        .into_iter()
        .map(|v| v.path)
        .collect();
    let machines: Vec<String> = machines.iter().map(|m| machine_for_seed(m, seed)).collect();
    let mut ms: Vec<(String, Box<dyn Machine>)> = Vec::new();
    for name in &machines {
        let build = Build::of(name);
        if build == Build::Raw && !builds.iter().any(|(b, _)| *b == build) {
            return Verdict::Mismatch(format!(
                "{name} runs the unoptimised IR, which this kind of program is not built to"
            ));
        }
        let module = builds
            .iter()
            .find(|(b, _)| *b == build)
            .map_or(module, |&(_, m)| m);
        match machine(name, module) {
            Ok(Some(m)) => ms.push((name.clone(), m)),
            Ok(None) => {}
            Err(e) => return Verdict::Mismatch(e),
        }
    }
    run(ms, &vars, inputs, scans, seed)
}

/// Runs machines side by side (the first is the reference), comparing the variables
/// `vars` and the fault flag after cold start and after every scan.
pub(crate) fn run(
    mut ms: Vec<(String, Box<dyn Machine>)>,
    vars: &[String],
    inputs: &[(String, T)],
    scans: u32,
    seed: u64,
) -> Verdict {
    let compare = |ms: &[(String, Box<dyn Machine>)], when: &str| -> Result<(), String> {
        let (rname, r) = &ms[0];
        for (name, m) in &ms[1..] {
            for v in vars {
                let a = r.read(v).map_err(|e| format!("{rname}: {e}"))?;
                let b = m.read(v).map_err(|e| format!("{name}: {e}"))?;
                if !a.same(b) {
                    return Err(format!("{when}: {v} is {a} on {rname}, {b} on {name}"));
                }
            }
            if r.fault() != m.fault() {
                return Err(format!(
                    "{when}: the fault flag is {} on {rname}, {} on {name}",
                    r.fault(),
                    m.fault()
                ));
            }
        }
        Ok(())
    };
    for (name, m) in ms.iter_mut() {
        if let Err(e) = m.cold_start() {
            return Verdict::Mismatch(format!("{name}: cold start: {e}"));
        }
    }
    if let Err(e) = compare(&ms, "after cold start") {
        return Verdict::Mismatch(e);
    }
    let mut rng = Rng::new(seed ^ 0x5EED_1A7A);
    for s in 0..scans {
        for (path, t) in inputs {
            let bits = random_value(&mut rng, *t);
            for (i, (name, m)) in ms.iter_mut().enumerate() {
                let cur = match m.read(path) {
                    Ok(cur) => cur,
                    // The reference holds every variable: a path it does not know
                    // is the generator's mistake.
                    Err(e) if i == 0 => {
                        return Verdict::Rejected(format!("{name} cannot read {path}: {e}"))
                    }
                    Err(_) => continue,
                };
                let _ = m.write(path, PlcValue::from_bits(cur.ty, bits));
            }
        }
        for (name, m) in ms.iter_mut() {
            m.set_clock_us(s as i64 * 10_000);
            if let Err(e) = m.scan() {
                return Verdict::Mismatch(format!("scan {s}: {name} failed: {e}"));
            }
        }
        if let Err(e) = compare(&ms, &format!("after scan {s}")) {
            return Verdict::Mismatch(e);
        }
    }
    Verdict::Agree { machines: ms.len() }
}

/// The share (percent) of the programs of [`program`] that have an
/// object-oriented part ([`oo`]).
pub const OO_SHARE: u64 = 20;

/// The program of a seed: one of [`OO_SHARE`] percent has an object-oriented part,
/// added to the program the seed gives otherwise (drawn from a generator of its
/// own, so that the other parts do not depend on it).
pub fn program(seed: u64) -> Prog {
    let mut rng = Rng::new(seed);
    let mut p = Gen::new(&mut rng).program();
    let mut orng = Rng::new(seed ^ 0x0B1E_C7ED);
    if orng.chance(OO_SHARE) {
        oo::add(&mut p, &mut orng);
    }
    p
}

/// The program of a seed with an object-oriented part always (`plcc difftest
/// --lang oo`): the part of [`program`]'s OO programs, and the rest of the seed's
/// program without its CONFIGURATION.
pub fn program_oo(seed: u64) -> Prog {
    let mut rng = Rng::new(seed);
    let mut p = Gen::new(&mut rng).program();
    let mut orng = Rng::new(seed ^ 0x0B1E_C7ED);
    orng.chance(OO_SHARE);
    oo::add(&mut p, &mut orng);
    p
}

/// The result of one seed of a campaign.
#[derive(Clone, Debug)]
pub struct Finding {
    /// The seed.
    pub seed: u64,
    /// What was wrong.
    pub verdict: Verdict,
    /// The shrunk reproducer (ST text, or PLCopen XML).
    pub reproducer: String,
    /// The reproducer's file extension: `st` or `xml`.
    pub ext: &'static str,
}

/// The error codes of a rejected program (`E0204,E0751`), to shrink it to one
/// rejected for the same reasons; empty for other verdicts.
pub(crate) fn codes(v: &Verdict) -> String {
    match v {
        Verdict::Rejected(e) => {
            let mut c: Vec<&str> = e
                .split("error[")
                .skip(1)
                .filter_map(|x| x.split(']').next())
                .collect();
            c.sort();
            c.dedup();
            c.join(",")
        }
        _ => String::new(),
    }
}

/// Checks seed `seed`; on a mismatch or a rejected program, shrinks it.
pub fn run_seed(seed: u64, machines: &[&str], scans: u32) -> Option<Finding> {
    run_program(program(seed), seed, machines, scans)
}

/// [`run_seed`] for the program of [`program_oo`] (`--lang oo`).
pub fn run_seed_oo(seed: u64, machines: &[&str], scans: u32) -> Option<Finding> {
    run_program(program_oo(seed), seed, machines, scans)
}

fn run_program(p: Prog, seed: u64, machines: &[&str], scans: u32) -> Option<Finding> {
    let verdict = check(&p, machines, scans, seed);
    let bad = |v: &Verdict| !matches!(v, Verdict::Agree { .. });
    if !bad(&verdict) {
        return None;
    }
    // A rejected program shrinks to one rejected for the same reasons (codes), not
    // to one that uses what a step took away.
    let want = codes(&verdict);
    let mismatch = matches!(verdict, Verdict::Mismatch(_));
    let small = shrink::shrink(
        &p,
        &mut |q| {
            let v = check(q, machines, scans, seed);
            if mismatch {
                matches!(v, Verdict::Mismatch(_))
            } else {
                matches!(v, Verdict::Rejected(_)) && codes(&v) == want
            }
        },
        2000,
    );
    let verdict = check(&small, machines, scans, seed);
    Some(Finding {
        seed,
        verdict,
        reproducer: small.to_st(),
        ext: "st",
    })
}
