//! Scenarios: the `corpus-expect v1` format of `../shared/corpus/README.md`.
//!
//! A scenario drives a [`Machine`] scan by scan (`run N`, `run_at_us T`), writes
//! variables (`set`), and checks them (`expect`, `expect ~=`). Lines starting with `#`
//! are comments.

use plcc_ir::machine::{read_string, write_string, Machine};
use plcc_ir::value::{format_string_literal, PlcValue};
use plcc_ir::vars::StrRef;
use plcc_ir::{ElemType, Module};

/// The cycle of `run N` for a build whose tasks have no interval (or that has no
/// configuration), when none is asked for.
pub const DEFAULT_CYCLE_MS: u64 = 10;

/// Where the cycle of a run comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleFrom {
    /// Asked for (`--cycle-ms`).
    Asked,
    /// The common tick of the configuration's tasks.
    Tasks,
    /// [`DEFAULT_CYCLE_MS`]: nothing else gives one.
    Default,
}

/// The cycle of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cycle {
    /// Microseconds between scans: scan k (from 0) runs with the clock at k * us.
    pub us: u64,
    /// Where it comes from.
    pub from: CycleFrom,
}

impl Cycle {
    /// The cycle `plcc run` and `plcc test` use for `module`: the one asked for, else
    /// the common tick of its tasks (the greatest common divisor of their intervals,
    /// as matiec's `common_ticktime__`, so that each task runs exactly at the ticks it
    /// is due), else [`DEFAULT_CYCLE_MS`].
    /// `asked` is in microseconds.
    pub fn of(module: &Module, asked: Option<u64>) -> Cycle {
        match (asked, module.task_tick_us()) {
            (Some(us), _) => Cycle {
                us,
                from: CycleFrom::Asked,
            },
            (None, Some(tick)) => Cycle {
                us: tick,
                from: CycleFrom::Tasks,
            },
            (None, None) => Cycle {
                us: DEFAULT_CYCLE_MS * 1000,
                from: CycleFrom::Default,
            },
        }
    }
}

impl std::fmt::Display for Cycle {
    /// `cycle: 5 ms (the common tick of the tasks)`, the line `run` and `test` print.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let why = match self.from {
            CycleFrom::Asked => "--cycle-ms",
            CycleFrom::Tasks => "the common tick of the tasks: the GCD of their intervals",
            CycleFrom::Default => "the default: no task has an interval",
        };
        write!(f, "cycle: {} ms ({why})", format_ms(self.us))
    }
}

/// `us` microseconds as milliseconds: `20`, `0.5`, `1.25`.
pub fn format_ms(us: u64) -> String {
    if us.is_multiple_of(1000) {
        (us / 1000).to_string()
    } else {
        let frac = format!("{:03}", us % 1000);
        format!("{}.{}", us / 1000, frac.trim_end_matches('0'))
    }
}

/// Reads a decimal number with at most three decimals (`20`, `0.5`, `.25`) in
/// thousandths of its unit; `None` for anything else or a value past `u64`.
pub fn parse_thousandths(text: &str) -> Option<u64> {
    let (whole, frac) = text.split_once('.').unwrap_or((text, ""));
    if whole.is_empty() && frac.is_empty()
        || !whole.bytes().all(|b| b.is_ascii_digit())
        || !frac.bytes().all(|b| b.is_ascii_digit())
        || frac.len() > 3
    {
        return None;
    }
    let whole: u64 = if whole.is_empty() {
        0
    } else {
        whole.parse().ok()?
    };
    let frac: u64 = format!("{frac:0<3}").parse().ok()?;
    whole.checked_mul(1000)?.checked_add(frac)
}

/// Reads a number of milliseconds (`20`, `0.5`) as microseconds: positive, in whole
/// microseconds. The parser of `--cycle-ms`.
pub fn parse_ms(text: &str) -> Result<u64, String> {
    match parse_thousandths(text) {
        Some(us) if us > 0 => Ok(us),
        _ => Err(format!(
            "`{text}` is not a positive number of milliseconds in whole µs"
        )),
    }
}

/// One command of a scenario.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// `run N`: N scans, the clock advancing one cycle after each.
    Run(u64),
    /// `run_at_us T`: one scan with the clock at T microseconds.
    RunAt(i64),
    /// `duration_s = S`: scans for S seconds of cycles (steady state).
    Duration(f64),
    /// `set VAR = V`
    Set {
        /// The variable, relative to the program.
        var: String,
        /// The value as written.
        value: String,
    },
    /// `expect VAR = V` or `expect VAR ~= V tol T`
    Expect {
        /// The variable, relative to the program.
        var: String,
        /// The expected value as written.
        value: String,
        /// The absolute tolerance of a `~=` check.
        tol: Option<f64>,
    },
}

/// A parsed scenario.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scenario {
    /// `program = NAME`, if given.
    pub program: Option<String>,
    /// Commands with their line numbers.
    pub steps: Vec<(usize, Step)>,
    /// Why plcc cannot run it, if it uses a kind of scenario plcc does not support
    /// (RuSTy's printf checks).
    pub unsupported: Option<String>,
}

/// Parses a scenario file.
pub fn parse(text: &str) -> Result<Scenario, String> {
    let mut s = Scenario::default();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let err = |m: &str| Err(format!("line {line_no}: {m}: `{line}`"));
        let (word, rest) = line.split_once(char::is_whitespace).unwrap_or((line, ""));
        let rest = rest.trim();
        match word {
            "program" | "entry" | "duration_s" => {
                let Some(v) = rest.strip_prefix('=') else {
                    return err("expected `=`");
                };
                let v = v.trim();
                match word {
                    "program" => s.program = Some(v.to_string()),
                    "entry" => {
                        s.unsupported =
                            Some("RuSTy-style scenario (FUNCTION entry with printf checks)".into())
                    }
                    _ => match v.parse::<f64>() {
                        Ok(d) if d >= 0.0 => s.steps.push((line_no, Step::Duration(d))),
                        _ => return err("expected a duration in seconds"),
                    },
                }
            }
            "run" => match rest.parse::<u64>() {
                Ok(n) => s.steps.push((line_no, Step::Run(n))),
                Err(_) => return err("expected `run N`"),
            },
            "run_at_us" => match rest.parse::<i64>() {
                Ok(t) => s.steps.push((line_no, Step::RunAt(t))),
                Err(_) => return err("expected `run_at_us T`"),
            },
            "run_once" | "check" | "check_next" => {
                s.unsupported =
                    Some("RuSTy-style scenario (FUNCTION entry with printf checks)".into())
            }
            "set" => {
                let Some((var, value)) = rest.split_once('=') else {
                    return err("expected `set VAR = VALUE`");
                };
                s.steps.push((
                    line_no,
                    Step::Set {
                        var: var.trim().to_string(),
                        value: value.trim().to_string(),
                    },
                ));
            }
            "expect" => {
                if let Some((var, rhs)) = rest.split_once("~=") {
                    let rhs = rhs.trim();
                    let Some((value, tol)) = rhs.split_once(" tol ") else {
                        return err("expected `expect VAR ~= VALUE tol T`");
                    };
                    let Ok(tol) = tol.trim().parse::<f64>() else {
                        return err("bad tolerance");
                    };
                    s.steps.push((
                        line_no,
                        Step::Expect {
                            var: var.trim().to_string(),
                            value: value.trim().to_string(),
                            tol: Some(tol),
                        },
                    ));
                } else {
                    let Some((var, value)) = rest.split_once('=') else {
                        return err("expected `expect VAR = VALUE`");
                    };
                    s.steps.push((
                        line_no,
                        Step::Expect {
                            var: var.trim().to_string(),
                            value: value.trim().to_string(),
                            tol: None,
                        },
                    ));
                }
            }
            _ => return err("unknown command"),
        }
    }
    Ok(s)
}

/// The result of one `expect`.
#[derive(Clone, Debug)]
pub struct Check {
    /// Its line in the scenario.
    pub line: usize,
    /// The check as written.
    pub text: String,
    /// Whether it held.
    pub ok: bool,
    /// What was found, when it did not hold.
    pub detail: String,
}

/// What running a scenario gave.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// Every check in order.
    pub checks: Vec<Check>,
    /// A failure that stopped the scenario (unknown variable, machine error).
    pub error: Option<String>,
    /// True if the runtime fault flag was raised at some point.
    pub fault: bool,
}

impl Outcome {
    /// True if every check held and nothing failed.
    pub fn passed(&self) -> bool {
        self.error.is_none() && self.checks.iter().all(|c| c.ok)
    }
}

/// Runs a scenario on a machine that has the program `program` (the instance name
/// variables are relative to). `cycle_us` is the clock step of `run N`.
pub fn run(s: &Scenario, m: &mut dyn Machine, program: &str, cycle_us: u64) -> Outcome {
    let mut out = Outcome::default();
    // The clock of the next scan: `run` scans at it and steps it by one cycle;
    // `run_at_us T` scans at T and continues from T + cycle.
    let mut next_us: i64 = 0;
    let cycle_us = cycle_us as i64;
    if let Err(e) = m.cold_start() {
        out.error = Some(format!("cold start failed: {e}"));
        return out;
    }
    let scan = |m: &mut dyn Machine, t: i64| -> Result<(), String> {
        m.set_clock_us(t);
        m.scan().map_err(|e| format!("scan failed: {e}"))
    };
    for (line, step) in &s.steps {
        let res: Result<(), String> = match step {
            Step::Run(n) => (0..*n).try_for_each(|_| {
                let t = next_us;
                next_us += cycle_us;
                scan(m, t)
            }),
            Step::RunAt(t) => {
                next_us = *t + cycle_us;
                scan(m, *t)
            }
            Step::Duration(secs) => {
                let n = ((secs * 1e6) / cycle_us.max(1) as f64).ceil().max(1.0) as u64;
                (0..n).try_for_each(|_| {
                    let t = next_us;
                    next_us += cycle_us;
                    scan(m, t)
                })
            }
            Step::Set { var, value } => {
                let path = path_of(m, program, var);
                set(m, &path, value)
            }
            Step::Expect { var, value, tol } => {
                let text = match tol {
                    Some(t) => format!("expect {var} ~= {value} tol {t}"),
                    None => format!("expect {var} = {value}"),
                };
                let path = path_of(m, program, var);
                match expect(m, &path, value, *tol) {
                    Ok(()) => out.checks.push(Check {
                        line: *line,
                        text,
                        ok: true,
                        detail: String::new(),
                    }),
                    Err(detail) => out.checks.push(Check {
                        line: *line,
                        text,
                        ok: false,
                        detail,
                    }),
                }
                Ok(())
            }
        };
        out.fault |= m.fault();
        if let Err(e) = res {
            out.error = Some(format!("line {line}: {e}"));
            return out;
        }
    }
    out
}

/// Every elementary variable of the module's program instances, then the globals':
/// what the machines are compared on.
pub fn all_variables(module: &Module) -> Vec<plcc_ir::vars::VarRef> {
    let mut v: Vec<_> = module
        .programs
        .iter()
        .flat_map(|e| plcc_ir::vars::variables(module, e.data))
        .collect();
    if let Some(g) = module.data_by_name(plcc_frontend::GLOBALS_DATA) {
        v.extend(plcc_ir::vars::variables(module, g));
    }
    v
}

/// The path of a scenario variable: the program's, else a global's, else the path
/// as written (`inst.var` when no program is chosen).
pub fn path_of(m: &dyn Machine, program: &str, var: &str) -> String {
    let exists = |p: &str| m.read(p).is_ok() || m.string_var(p).is_ok();
    let own = format!("{program}.{var}");
    if !program.is_empty() && exists(&own) {
        return own;
    }
    let global = format!("{}.{var}", plcc_frontend::GLOBALS_DATA);
    if exists(&global) {
        return global;
    }
    if program.is_empty() {
        var.to_string()
    } else {
        own
    }
}

/// The characters of a string literal written in a scenario (`'abc'`, `"abc"` for a
/// WSTRING, with the `$` escapes of ST).
fn string_value(text: &str, s: &StrRef) -> Result<Vec<u16>, String> {
    let t = text.trim();
    let quote = if s.wide { '"' } else { '\'' };
    let inner = t
        .strip_prefix(quote)
        .and_then(|r| r.strip_suffix(quote))
        .filter(|_| t.len() >= 2)
        .ok_or_else(|| {
            format!(
                "`{}` is a {}: write its value as {quote}text{quote}",
                s.path,
                if s.wide { "WSTRING" } else { "STRING" }
            )
        })?;
    let mut errors = Vec::new();
    let chars = plcc_frontend::st::literals::decode_string(inner, s.wide, &mut errors);
    match errors.first() {
        Some(e) => Err(format!("in `{t}`: {}", e.message)),
        None => Ok(chars),
    }
}

/// A scenario's `set`: writes `text` (a value as the scenario writes it: an IEC
/// literal, a string in quotes) into the variable at `path`.
pub fn set(m: &mut dyn Machine, path: &str, text: &str) -> Result<(), String> {
    if let Ok(s) = m.string_var(path) {
        let chars = string_value(text, &s)?;
        return write_string(m, &s, &chars).map_err(|e| e.to_string());
    }
    let current = m.read(path).map_err(|e| e.to_string())?;
    let v = PlcValue::parse(current.ty, text)?;
    m.write(path, v).map_err(|e| e.to_string())
}

fn expect(m: &mut dyn Machine, path: &str, text: &str, tol: Option<f64>) -> Result<(), String> {
    if let Ok(s) = m.string_var(path) {
        if tol.is_some() {
            return Err(format!("`{}` is a string: compare it with `=`", s.path));
        }
        let want = string_value(text, &s)?;
        let got = read_string(m, &s).map_err(|e| e.to_string())?;
        return if got == want {
            Ok(())
        } else {
            Err(format!("got {}", format_string_literal(&got, s.wide)))
        };
    }
    let got = m.read(path).map_err(|e| e.to_string())?;
    if let Some(tol) = tol {
        let want =
            plcc_ir::value::parse_real(text).ok_or_else(|| format!("`{text}` is not a number"))?;
        let g = got.as_f64();
        return if (g - want).abs() <= tol {
            Ok(())
        } else {
            Err(format!("got {got}"))
        };
    }
    let want = PlcValue::parse(got.ty, text)?;
    let same = match got.ty {
        ElemType::Real | ElemType::LReal => {
            let (a, b) = (got.as_f64(), want.as_f64());
            a == b || (a.is_nan() && b.is_nan())
        }
        _ => got.bits == want.bits,
    };
    if same {
        Ok(())
    } else {
        Err(format!("got {got}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_command() {
        let s = parse(
            "# comment\nprogram = main\nrun 3\nrun_at_us 5000\nset a = TRUE\nexpect b = 5\nexpect r ~= 1.5 tol 0.01\nduration_s = 1.0\n",
        )
        .unwrap();
        assert_eq!(s.program.as_deref(), Some("main"));
        assert_eq!(s.steps.len(), 6);
        assert_eq!(s.steps[0].1, Step::Run(3));
        assert_eq!(s.steps[1].1, Step::RunAt(5000));
        assert!(matches!(&s.steps[4].1, Step::Expect { tol: Some(t), .. } if *t == 0.01));
        assert_eq!(s.steps[5].1, Step::Duration(1.0));
    }

    #[test]
    fn rejects_garbage_and_flags_rusty() {
        assert!(parse("run x\n").is_err());
        assert!(parse("frobnicate\n").is_err());
        let s = parse("entry = main\nrun_once\ncheck 5\n").unwrap();
        assert!(s.unsupported.is_some());
    }

    fn module_with_intervals(intervals: &[Option<u64>]) -> Module {
        let mut m = Module::default();
        for (i, &interval_us) in intervals.iter().enumerate() {
            m.programs.push(plcc_ir::ProgramEntry {
                name: format!("p{i}"),
                data: plcc_ir::DataId::new(0),
                body: plcc_ir::FuncId::new(0),
                init: plcc_ir::FuncId::new(0),
                interval_us,
                priority: None,
            });
        }
        m
    }

    #[test]
    fn the_cycle_is_the_one_asked_else_the_tasks_tick_else_10_ms() {
        let tasks = module_with_intervals(&[Some(10_000), None, Some(15_000)]);
        assert_eq!(
            Cycle::of(&tasks, None),
            Cycle {
                us: 5_000,
                from: CycleFrom::Tasks
            }
        );
        assert_eq!(
            Cycle::of(&tasks, Some(7_000)),
            Cycle {
                us: 7_000,
                from: CycleFrom::Asked
            }
        );
        let none = module_with_intervals(&[None]);
        assert_eq!(
            Cycle::of(&none, None),
            Cycle {
                us: DEFAULT_CYCLE_MS * 1000,
                from: CycleFrom::Default
            }
        );
        assert_eq!(
            Cycle::of(&tasks, None).to_string(),
            "cycle: 5 ms (the common tick of the tasks: the GCD of their intervals)"
        );
        let fine = module_with_intervals(&[Some(500), Some(1_250)]);
        assert_eq!(
            Cycle::of(&fine, None).to_string(),
            "cycle: 0.25 ms (the common tick of the tasks: the GCD of their intervals)"
        );
    }

    #[test]
    fn cycle_ms_reads_whole_microseconds() {
        assert_eq!(parse_ms("20"), Ok(20_000));
        assert_eq!(parse_ms("0.5"), Ok(500));
        assert_eq!(parse_ms("1.250"), Ok(1_250));
        assert_eq!(parse_ms(".5"), Ok(500));
        for bad in [
            "0",
            "0.0",
            "",
            ".",
            "-1",
            "1.0001",
            "1e3",
            "x",
            "99999999999999999999",
        ] {
            assert!(parse_ms(bad).is_err(), "{bad}");
        }
        assert_eq!(format_ms(1_250), "1.25");
        assert_eq!(format_ms(20_000), "20");
    }
}
