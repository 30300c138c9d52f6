//! Random, well-typed Structured Text programs: a generator that only builds what
//! IEC 61131-3 typing allows (every conversion explicit), over the program model of
//! `model.rs` (re-exported here); the printer is `print.rs`.

pub use super::model::*;

/// Generation state.
pub struct Gen<'r> {
    rng: &'r mut Rng,
    prog: Prog,
    depth: u32,
    /// Names expressions may read besides the program's variables (an SFC's step
    /// and action flags: `S1.X`, `S1.T`, `A0.Q`); nothing assigns them.
    pub extra: Vec<(String, T)>,
    /// Expressions for a scope other than `main`'s (a method's body): no array
    /// element, STRUCT field or enumeration variable of `main`.
    pub local: bool,
}

/// The fields of the STRUCT variables `r1`, `r2` (type `Rec`, see [`Prog::to_st`])
/// that hold a `t`.
fn struct_fields(t: T) -> Vec<String> {
    let fields: &[&str] = match t {
        T::Int => &["a"],
        T::Real => &["b"],
        T::Bool => &["c"],
        T::Dint => &["d[0]", "d[2]"],
        _ => &[],
    };
    ["r1", "r2"]
        .iter()
        .flat_map(|r| fields.iter().map(move |f| format!("{r}.{f}")))
        .collect()
}

/// Statements on the STRUCT and enumeration variables.
const RAW: [&str; 6] = [
    "r2 := r1;",
    "r1 := r2;",
    "m1 := Mode#Stop;",
    "IF m1 = Mode#Run THEN r1.a := r1.a + 1; ELSE m1 := Mode#Run; END_IF;",
    "CASE m1 OF Mode#Idle: r2.c := NOT r2.c; Mode#Run: m1 := Mode#Idle; ELSE r1.d[1] := r1.d[1] - 1; END_CASE;",
    "r1.d[LIMIT(0, r2.a, 2)] := r1.d[0] * 3;",
];

/// A random literal of type `t`.
pub(crate) fn lit(rng: &mut Rng, t: T) -> Expr {
    let text = match t {
        T::Bool => if rng.chance(50) { "TRUE" } else { "FALSE" }.to_string(),
        T::Real | T::Lreal => {
            let v: f64 = match rng.below(6) {
                0 => 0.0,
                1 => 1.0,
                2 => -2.5,
                3 => (rng.below(2_000_000) as f64 - 1_000_000.0) / 64.0,
                4 => 3.0e9,
                _ => (rng.below(1000) as f64 - 500.0) / 7.0,
            };
            format!("{}#{v:?}", t.name())
        }
        T::Time => format!("T#{}ms", rng.below(5000)),
        // Days up to 28 are valid in every month; years within DATE's 32 bits.
        T::Date => format!(
            "D#{}-{:02}-{:02}",
            1970 + rng.below(130),
            1 + rng.below(12),
            1 + rng.below(28)
        ),
        T::Tod => format!(
            "TOD#{:02}:{:02}:{:02}.{:03}",
            rng.below(24),
            rng.below(60),
            rng.below(60),
            rng.below(1000)
        ),
        T::Dt => format!(
            "DT#{}-{:02}-{:02}-{:02}:{:02}:{:02}",
            1970 + rng.below(130),
            1 + rng.below(12),
            1 + rng.below(28),
            rng.below(24),
            rng.below(60),
            rng.below(60)
        ),
        _ => {
            let bits = t.bits();
            let raw = match rng.below(6) {
                0 => 0,
                1 => 1,
                2 => u64::MAX,
                3 => rng.below(100),
                4 => 1u64 << (bits - 1),
                _ => rng.next_u64(),
            };
            let masked = if bits == 64 {
                raw
            } else {
                raw & ((1u64 << bits) - 1)
            };
            if t.is_signed() {
                let v = ((masked << (64 - bits)) as i64) >> (64 - bits);
                // The most negative value is left out: `-(INT#-32768)` is a constant
                // out of range, which the front end rightly rejects.
                let min = -(1i128 << (bits - 1));
                let v = if v as i128 == min { v + 1 } else { v };
                format!("({}#{v})", t.name())
            } else {
                format!("{}#{masked}", t.name())
            }
        }
    };
    Expr::Lit(t, text)
}

impl<'r> Gen<'r> {
    /// A generator over `rng`.
    pub fn new(rng: &'r mut Rng) -> Gen<'r> {
        Gen {
            rng,
            prog: Prog {
                vars: Vec::new(),
                outputs: 0,
                inputs: Vec::new(),
                array: (T::Int, 0, 0),
                recs: None,
                fbs: None,
                inout: false,
                refs: false,
                body: Vec::new(),
                config: None,
                dropped: Vec::new(),
                oo: None,
            },
            depth: 0,
            extra: Vec::new(),
            local: false,
        }
    }

    /// A generator of statements and expressions over the declarations of `prog`
    /// (its body is not used).
    pub fn over(rng: &'r mut Rng, prog: Prog) -> Gen<'r> {
        Gen {
            rng,
            prog,
            depth: 0,
            extra: Vec::new(),
            local: false,
        }
    }

    /// The random generator.
    pub fn rng(&mut self) -> &mut Rng {
        self.rng
    }

    /// The program the generator works on.
    pub fn prog(&self) -> &Prog {
        &self.prog
    }

    /// A whole program.
    pub fn program(mut self) -> Prog {
        // Most programs with a CONFIGURATION are slim, so that two or three
        // instances fit the PIC16 (on which an instance reached through a pointer
        // must fit one 96-byte bank): fewer and narrower variables, a short array,
        // no ARRAY OF STRUCT.
        let config = self.rng.chance(30);
        let slim = config && self.rng.chance(85);
        let narrow = |t: &T| t.bits() <= 32;
        let types: Vec<T> = ALL.iter().copied().filter(|t| !slim || narrow(t)).collect();
        let n = if slim {
            1 + self.rng.below(4)
        } else {
            3 + self.rng.below(7)
        };
        for i in 0..n {
            let t = *self.rng.pick(&types);
            let init = lit(self.rng, t);
            self.prog.vars.push((format!("v{i}"), t, init));
        }
        self.prog.outputs = self.rng.below(3).min(n) as usize;
        for i in 0..self.rng.below(3) {
            let t = *self.rng.pick(&types);
            self.prog.inputs.push((format!("in{i}"), t));
        }
        let (et, lo, hi) = if slim {
            let et = *self.rng.pick(&[T::Int, T::Byte, T::Bool]);
            let lo = *self.rng.pick(&[0i64, 1, -3, 10]);
            (et, lo, lo + 1 + self.rng.below(2) as i64)
        } else {
            let et = *self
                .rng
                .pick(&[T::Int, T::Dint, T::Byte, T::Real, T::Lword, T::Bool]);
            let lo = *self.rng.pick(&[0i64, 1, -3, 10]);
            (et, lo, lo + 2 + self.rng.below(8) as i64)
        };
        self.prog.array = (et, lo, hi);
        // The parts reached through run-time addresses, each in some programs (kept
        // small: the PIC16 has 368 bytes of RAM).
        if self.rng.chance(35) && !slim {
            let lo = *self.rng.pick(&[0i64, 1, -2]);
            self.prog.recs = Some((lo, lo + 1 + self.rng.below(2) as i64));
        }
        if self.rng.chance(30) {
            let lo = *self.rng.pick(&[1i64, 0, -1]);
            let n = if slim {
                1
            } else {
                1 + self.rng.below(2) as i64
            };
            self.prog.fbs = Some((lo, lo + n));
        }
        self.prog.inout = self.rng.chance(30);
        self.prog.refs = self.rng.chance(30);
        if config {
            if self.prog.inputs.is_empty() {
                let t = *self.rng.pick(&ALL);
                self.prog.inputs.push(("in0".into(), t));
            }
            self.prog.config = Some(self.config());
        }
        let count = 3 + self.rng.below(10);
        for _ in 0..count {
            let s = self.stmt();
            self.prog.body.push(s);
        }
        self.prog
    }

    /// A CONFIGURATION of two or three instances of `main`, with tasks of different
    /// intervals and priorities (or none), the instances' inputs connected to
    /// globals or literals and some outputs to globals.
    fn config(&mut self) -> Config {
        let ntasks = *self.rng.pick(&[0usize, 1, 2, 2, 3]);
        let tasks = (0..ntasks)
            .map(|_| {
                (
                    *self.rng.pick(&[10u32, 20, 20, 30, 40, 25, 15]),
                    self.rng.below(4) as u32,
                )
            })
            .collect();
        let mut globals: Vec<(String, T, Expr)> = Vec::new();
        let mut instances = Vec::new();
        for name in ["a", "b", "c"].iter().take(2 + self.rng.below(2) as usize) {
            let task =
                (ntasks > 0 && self.rng.chance(75)).then(|| self.rng.below(ntasks as u64) as usize);
            let mut conns = Vec::new();
            for (n, t) in self.prog.inputs.clone() {
                match self.rng.below(100) {
                    0..=44 => {
                        let g = self.global(&mut globals, t);
                        conns.push(Conn::In(n, Expr::Var(t, g)));
                    }
                    45..=79 => conns.push(Conn::In(n, lit(self.rng, t))),
                    _ => {}
                }
            }
            let outputs: Vec<(String, T)> = self.prog.vars[..self.prog.outputs]
                .iter()
                .map(|(n, t, _)| (n.clone(), *t))
                .collect();
            for (n, t) in outputs {
                if self.rng.chance(40) {
                    let g = self.global(&mut globals, t);
                    conns.push(Conn::Out(n, g));
                }
            }
            instances.push(Instance {
                name: name.to_string(),
                task,
                conns,
            });
        }
        Config {
            globals,
            tasks,
            resource: self.rng.chance(40),
            instances,
        }
    }

    /// A global of type `t`: one there is, or a new one.
    fn global(&mut self, globals: &mut Vec<(String, T, Expr)>, t: T) -> String {
        let there: Vec<String> = globals
            .iter()
            .filter(|g| g.1 == t)
            .map(|g| g.0.clone())
            .collect();
        if !there.is_empty() && self.rng.chance(50) {
            return self.rng.pick(&there).clone();
        }
        let name = format!("g{}", globals.len());
        let init = lit(self.rng, t);
        globals.push((name.clone(), t, init));
        name
    }

    fn readable(&self, t: T) -> Vec<String> {
        let mut v = self.writable(t);
        v.extend(
            self.prog
                .inputs
                .iter()
                .filter(|(_, vt)| *vt == t)
                .map(|(n, _)| n.clone()),
        );
        v.extend(
            self.extra
                .iter()
                .filter(|(_, vt)| *vt == t)
                .map(|(n, _)| n.clone()),
        );
        v
    }

    /// The named variables of type `t` a statement may assign.
    fn writable(&self, t: T) -> Vec<String> {
        let mut v: Vec<String> = self
            .prog
            .vars
            .iter()
            .filter(|(_, vt, _)| *vt == t)
            .map(|(n, _, _)| n.clone())
            .collect();
        if !self.local {
            v.extend(struct_fields(t));
        }
        v
    }

    /// An index into `lo..hi`: a literal in range, a clamped expression, or any
    /// INT expression (out of range is part of the semantics: the fault flag, a
    /// read gives 0, a write is dropped).
    fn index_in(&mut self, lo: i64, hi: i64) -> Expr {
        if self.rng.chance(40) {
            return Expr::Lit(
                T::Int,
                format!("{}", lo + self.rng.below((hi - lo + 1) as u64) as i64),
            );
        }
        let i = self.expr(T::Int);
        if self.rng.chance(70) {
            Expr::Call(
                T::Int,
                "LIMIT".into(),
                vec![
                    Expr::Lit(T::Int, format!("({lo})")),
                    i,
                    Expr::Lit(T::Int, format!("({hi})")),
                ],
            )
        } else {
            i
        }
    }

    fn index(&mut self) -> Expr {
        let (_, lo, hi) = self.prog.array;
        self.index_in(lo, hi)
    }

    /// `base[i]rest`, the index into `lo..hi`.
    fn indexed(&mut self, base: &str, lo: i64, hi: i64, rest: &str) -> Path {
        let i = self.index_in(lo, hi);
        Path {
            parts: vec![format!("{base}["), format!("]{rest}")],
            idx: vec![i],
        }
    }

    /// `recs[i].d[j]`, `pr^.d[j]`, `pd^[j]`: an element of a `Rec`'s array.
    fn d_elem(&mut self, mut base: Path) -> Path {
        let j = self.index_in(0, 2);
        base.parts.last_mut().expect("a path has a part").push('[');
        base.idx.push(j);
        base.parts.push("]".into());
        base
    }

    /// The places of type `t` reached through a run-time address that the program
    /// has (FB outputs only when not `write`): one of them, if any.
    fn computed(&mut self, t: T, write: bool) -> Option<Path> {
        let mut kinds: Vec<u8> = Vec::new();
        if self.prog.recs.is_some() && matches!(t, T::Int | T::Real | T::Bool | T::Dint) {
            kinds.push(0);
        }
        if self.prog.fbs.is_some() && t == T::Int {
            kinds.push(1);
        }
        if self.prog.refs {
            if matches!(t, T::Int | T::Real | T::Bool | T::Dint) {
                kinds.push(2);
            }
            if t == T::Int || t == T::Dint {
                kinds.push(3);
            }
            if t == self.prog.array.0 {
                kinds.push(4);
            }
        }
        if kinds.is_empty() {
            return None;
        }
        let field = match t {
            T::Int => ".a",
            T::Real => ".b",
            T::Bool => ".c",
            _ => ".d",
        };
        Some(match *self.rng.pick(&kinds) {
            0 => {
                let (lo, hi) = self.prog.recs.expect("recs");
                let p = self.indexed("recs", lo, hi, field);
                if t == T::Dint {
                    self.d_elem(p)
                } else {
                    p
                }
            }
            1 => {
                let (lo, hi) = self.prog.fbs.expect("fbs");
                let f = if write || self.rng.chance(50) {
                    ".a"
                } else {
                    ".r"
                };
                self.indexed("fbs", lo, hi, f)
            }
            2 => {
                let p = Path::fixed(&format!("pr^{field}"));
                if t == T::Dint {
                    self.d_elem(p)
                } else {
                    p
                }
            }
            3 if t == T::Int => Path::fixed("p1^"),
            3 => self.d_elem(Path::fixed("pd^")),
            _ => {
                let (_, lo, hi) = self.prog.array;
                self.indexed("pa^", lo, hi, "")
            }
        })
    }

    /// An INT place for a VAR_IN_OUT or for `REF()`.
    fn int_place(&mut self) -> Path {
        let mut named = self.writable(T::Int);
        named.push("q".into());
        if self.prog.array.0 == T::Int && self.rng.chance(20) {
            let (_, lo, hi) = self.prog.array;
            return self.indexed("arr", lo, hi, "");
        }
        if self.rng.chance(50) {
            if let Some(p) = self.computed(T::Int, true) {
                return p;
            }
        }
        let n = self.rng.pick(&named).clone();
        Path::fixed(&n)
    }

    /// A `Rec` place.
    fn rec_place(&mut self) -> Path {
        match self.rng.below(4) {
            0 => Path::fixed("r1"),
            1 => Path::fixed("r2"),
            2 if self.prog.recs.is_some() => {
                let (lo, hi) = self.prog.recs.expect("recs");
                self.indexed("recs", lo, hi, "")
            }
            _ if self.prog.refs => Path::fixed("pr^"),
            _ => Path::fixed("r1"),
        }
    }

    /// An `ARRAY[0..2] OF DINT` place.
    fn darr_place(&mut self) -> Path {
        match self.rng.below(5) {
            0 => Path::fixed("r1.d"),
            1 => Path::fixed("r2.d"),
            2 if self.prog.recs.is_some() => {
                let (lo, hi) = self.prog.recs.expect("recs");
                self.indexed("recs", lo, hi, ".d")
            }
            3 if self.prog.refs => Path::fixed("pd^"),
            _ if self.prog.refs => Path::fixed("pr^.d"),
            _ => Path::fixed("r2.d"),
        }
    }

    /// `SIZEOF` of a variable or of its type, as a `t`: a scalar takes its width on
    /// every machine (a struct would not: the targets lay them out differently, see
    /// `tests/e2e.rs`), so the machines must agree.
    fn size_of(&mut self, t: T) -> Option<Expr> {
        let u = *self.rng.pick(&ALL);
        let vars = self.readable(u);
        if vars.is_empty() {
            return None;
        }
        let arg = if self.rng.chance(50) {
            Expr::Var(u, self.rng.pick(&vars).clone())
        } else {
            Expr::Lit(u, u.name().to_string())
        };
        Some(Expr::Call(t, "SIZEOF".into(), vec![arg]))
    }

    /// The selector and the arms' labels of a dense CASE: 4 to 6 arms of one or two
    /// labels each, single values or ranges of 2 to 4, mostly consecutive (sometimes
    /// a gap of 1 or 2), from a start near 0 or near the top of the selector's type
    /// (INT, SINT, DINT, LINT, USINT or UDINT). The selector is often `e MOD 16 +
    /// start`, so that it lands among the labels.
    fn dense_case(&mut self) -> (Expr, Vec<Vec<Label>>) {
        let t = *self.rng.pick(&[
            T::Int,
            T::Int,
            T::Sint,
            T::Dint,
            T::Lint,
            T::Usint,
            T::Udint,
        ]);
        let max = match t {
            T::Sint => 127,
            T::Usint => 255,
            T::Int => 32767,
            _ => 1_000_000,
        };
        let start = match (self.rng.below(4), t.is_signed()) {
            (0, _) => max - 12,
            (_, true) => self.rng.range(-8, 4) as i64,
            (_, false) => self.rng.range(0, 4) as i64,
        };
        let mut next = start;
        let mut arms = Vec::new();
        for _ in 0..4 + self.rng.below(3) {
            let mut labels = Vec::new();
            for _ in 0..1 + self.rng.below(2) {
                if self.rng.chance(20) {
                    next += 1 + self.rng.below(2) as i64;
                }
                let len = if self.rng.chance(25) {
                    1 + self.rng.below(3) as i64
                } else {
                    0
                };
                if next + len > max {
                    break;
                }
                labels.push((next, next + len));
                next += len + 1;
            }
            if !labels.is_empty() {
                arms.push(labels);
            }
        }
        let e = self.expr(t);
        let sel = if self.rng.chance(60) {
            let m = Expr::Bin(t, "MOD", Box::new(e), Box::new(Expr::Lit(t, "16".into())));
            let k = if start < 0 {
                format!("({}#{start})", t.name())
            } else {
                format!("{}#{start}", t.name())
            };
            Expr::Bin(t, "+", Box::new(m), Box::new(Expr::Lit(t, k)))
        } else {
            e
        };
        (sel, arms)
    }

    /// An expression of type `t`.
    pub fn expr(&mut self, t: T) -> Expr {
        self.depth += 1;
        let e = self.expr_inner(t);
        self.depth -= 1;
        e
    }

    fn expr_inner(&mut self, t: T) -> Expr {
        let vars = self.readable(t);
        if self.depth > 3 || self.rng.chance(25) {
            if self.rng.chance(25) {
                if let Some(p) = self.computed(t, false) {
                    return Expr::At(t, p);
                }
            }
            if !vars.is_empty() && self.rng.chance(65) {
                return Expr::Var(t, self.rng.pick(&vars).clone());
            }
            if t == self.prog.array.0 && !self.local && self.rng.chance(30) {
                let i = self.index();
                return Expr::Elem(t, Box::new(i));
            }
            if (t.is_int() || t.is_bits()) && self.rng.chance(6) {
                if let Some(e) = self.size_of(t) {
                    return e;
                }
            }
            return lit(self.rng, t);
        }
        let k = self.rng.below(100);
        let b = |e: Expr| Box::new(e);
        match t {
            T::Bool => match k {
                0..=34 => {
                    let u = *self.rng.pick(&ALL);
                    let ops: &[&'static str] = if u == T::Bool {
                        &["=", "<>"]
                    } else {
                        &["<", ">", "=", "<>", "<=", ">="]
                    };
                    let op = *self.rng.pick(ops);
                    Expr::Bin(T::Bool, op, b(self.expr(u)), b(self.expr(u)))
                }
                35..=69 => {
                    let op = *self.rng.pick(&["AND", "OR", "XOR"]);
                    Expr::Bin(T::Bool, op, b(self.expr(T::Bool)), b(self.expr(T::Bool)))
                }
                70..=79 => Expr::Un(T::Bool, "NOT", b(self.expr(T::Bool))),
                80..=84 if !self.local => {
                    let v = *self.rng.pick(&["Idle", "Run", "Stop"]);
                    let op = *self.rng.pick(&["=", "<>"]);
                    Expr::Lit(T::Bool, format!("(m1 {op} Mode#{v})"))
                }
                _ => self.conversion(t),
            },
            _ if t.is_real() => match k {
                0..=49 => {
                    let op = *self.rng.pick(&["+", "-", "*", "/"]);
                    Expr::Bin(t, op, b(self.expr(t)), b(self.expr(t)))
                }
                50..=57 => Expr::Call(t, "ABS".into(), vec![self.expr(t)]),
                58..=62 => Expr::Call(t, "SQRT".into(), vec![self.expr(t)]),
                63..=67 => Expr::Un(t, "-", b(self.expr(t))),
                68..=75 => self.selection(t),
                76..=89 => self.pow(t),
                _ => self.conversion(t),
            },
            T::Time => match k {
                0..=49 => {
                    let op = *self.rng.pick(&["+", "-"]);
                    Expr::Bin(t, op, b(self.expr(t)), b(self.expr(t)))
                }
                50..=64 => self.selection(t),
                65..=79 => {
                    // The time between two dates, times of day or DTs.
                    let u = *self.rng.pick(&[T::Date, T::Tod, T::Dt]);
                    Expr::Bin(t, "-", b(self.expr(u)), b(self.expr(u)))
                }
                _ => self.conversion(t),
            },
            T::Tod | T::Dt => match k {
                0..=39 => {
                    let op = *self.rng.pick(&["+", "-"]);
                    Expr::Bin(t, op, b(self.expr(t)), b(self.expr(T::Time)))
                }
                40..=59 => self.selection(t),
                60..=69 if t == T::Tod => Expr::Call(t, "DT_TO_TOD".into(), vec![self.expr(T::Dt)]),
                60..=69 => Expr::Call(
                    t,
                    "CONCAT_DATE_TOD".into(),
                    vec![self.expr(T::Date), self.expr(T::Tod)],
                ),
                _ => self.conversion(t),
            },
            T::Date => match k {
                0..=29 => Expr::Call(t, "DT_TO_DATE".into(), vec![self.expr(T::Dt)]),
                30..=59 => self.selection(t),
                _ => self.conversion(t),
            },
            _ => match k {
                0..=39 => {
                    let ops: &[&'static str] = if t.is_bits() {
                        &["AND", "OR", "XOR"]
                    } else {
                        &["+", "-", "*", "/", "MOD", "+", "-"]
                    };
                    let op = *self.rng.pick(ops);
                    Expr::Bin(t, op, b(self.expr(t)), b(self.expr(t)))
                }
                40..=49 if t.is_bits() => {
                    let f = *self.rng.pick(&["SHL", "SHR", "ROL", "ROR"]);
                    let n = if self.rng.chance(50) {
                        Expr::Lit(T::Int, format!("{}", self.rng.below(70)))
                    } else {
                        self.expr(T::Int)
                    };
                    Expr::Call(t, f.into(), vec![self.expr(t), n])
                }
                40..=49 if t.is_signed() => {
                    if self.rng.chance(50) {
                        Expr::Call(t, "ABS".into(), vec![self.expr(t)])
                    } else {
                        Expr::Un(t, "-", b(self.expr(t)))
                    }
                }
                50..=54 if t.is_bits() => Expr::Un(t, "NOT", b(self.expr(t))),
                55..=69 => self.selection(t),
                70..=74 if t == T::Int || t == T::Dint => {
                    let (a1, a2) = (self.expr(T::Dint), self.expr(T::Dint));
                    let call = Expr::Call(T::Dint, "fun".into(), vec![a1, a2]);
                    if t == T::Int {
                        Expr::Call(T::Int, "DINT_TO_INT".into(), vec![call])
                    } else {
                        call
                    }
                }
                _ => self.conversion(t),
            },
        }
    }

    /// EXPT of a REAL or LREAL with an exact result: an integer base and a
    /// non-negative integer exponent whose power fits the mantissa, or a base that
    /// is a power of two (positive or negative) and an exponent of either sign.
    fn pow(&mut self, t: T) -> Expr {
        let lreal = t == T::Lreal;
        let (base, emin, emax) = if self.rng.chance(30) {
            let mut vals: Vec<i64> = Vec::new();
            for _ in 0..2 + self.rng.below(4) {
                vals.push(*self.rng.pick(&[1i64, -1, 2, -2, 4, -4, 8, -8]));
            }
            let emax = if lreal { 12 } else { 6 };
            let base = if self.rng.chance(30) {
                Operand::Lit(t, *self.rng.pick(&vals))
            } else {
                Operand::Choice(t, vals, Box::new(self.expr(T::Int)))
            };
            (base, -emax, emax)
        } else {
            // |base| <= b and 0 <= exponent <= e: b^e < 2^24 (REAL), 2^53 (LREAL).
            let (bmax, emax) = if lreal {
                *self
                    .rng
                    .pick(&[(15i64, 6i64), (100, 7), (1000, 5), (3, 33)])
            } else {
                *self
                    .rng
                    .pick(&[(15i64, 6i64), (3, 15), (255, 3), (4095, 2)])
            };
            let base = if self.rng.chance(25) {
                Operand::Lit(t, self.rng.below(2 * bmax as u64 + 1) as i64 - bmax)
            } else {
                let lo = if self.rng.chance(70) { -bmax } else { 0 };
                Operand::Clamp(t, lo, bmax, Box::new(self.expr(T::Int)))
            };
            (base, 0, emax)
        };
        let et = if emin < 0 {
            *self
                .rng
                .pick(&[T::Int, T::Int, T::Dint, T::Sint, T::Lint, T::Real, T::Lreal])
        } else {
            *self.rng.pick(&[
                T::Int,
                T::Int,
                T::Dint,
                T::Sint,
                T::Usint,
                T::Udint,
                T::Ulint,
                T::Real,
                T::Lreal,
            ])
        };
        let exp = if self.rng.chance(30) {
            Operand::Lit(et, emin + self.rng.below((emax - emin + 1) as u64) as i64)
        } else {
            Operand::Clamp(et, emin, emax, Box::new(self.expr(T::Int)))
        };
        Expr::Pow(Box::new(Pow {
            t,
            call: self.rng.chance(40),
            base,
            exp,
        }))
    }

    fn selection(&mut self, t: T) -> Expr {
        match self.rng.below(4) {
            0 => Expr::Call(
                t,
                "SEL".into(),
                vec![self.expr(T::Bool), self.expr(t), self.expr(t)],
            ),
            1 => {
                let f = if self.rng.chance(50) { "MIN" } else { "MAX" };
                Expr::Call(t, f.into(), vec![self.expr(t), self.expr(t)])
            }
            2 => Expr::Call(
                t,
                "LIMIT".into(),
                vec![self.expr(t), self.expr(t), self.expr(t)],
            ),
            _ => {
                let k = Expr::Call(
                    T::Int,
                    "LIMIT".into(),
                    vec![
                        Expr::Lit(T::Int, "0".into()),
                        self.expr(T::Int),
                        Expr::Lit(T::Int, "2".into()),
                    ],
                );
                Expr::Call(
                    t,
                    "MUX".into(),
                    vec![k, self.expr(t), self.expr(t), self.expr(t)],
                )
            }
        }
    }

    /// `FROM_TO_T(e)` from a type that converts to `t`.
    fn conversion(&mut self, t: T) -> Expr {
        let from = loop {
            let u = *self.rng.pick(&ALL);
            if u == t {
                continue;
            }
            // Dates, times of day and DTs convert to and from integers and bit
            // strings; a DT to its date or time of day, a TOD to and from TIME.
            // TIME converts only to and from integers.
            let ok = match (u, t) {
                (T::Dt, T::Date | T::Tod) | (T::Tod, T::Time) | (T::Time, T::Tod) => true,
                (d, x) | (x, d) if d.is_date() => x.is_int() || x.is_bits(),
                (T::Time, x) | (x, T::Time) => x.is_int() || x.is_bits(),
                _ => true,
            };
            if ok {
                break u;
            }
        };
        let arg = self.expr(from);
        Expr::Call(t, format!("{}_TO_{}", from.name(), t.name()), vec![arg])
    }

    /// A statement on the parts reached through run-time addresses the program
    /// has, if it has any.
    fn pointer_stmt(&mut self) -> Option<Stmt> {
        let mut kinds: Vec<u8> = Vec::new();
        if self.prog.recs.is_some() || self.prog.refs || self.prog.fbs.is_some() {
            kinds.extend([0, 0]);
        }
        if self.prog.fbs.is_some() {
            kinds.push(1);
        }
        if self.prog.inout {
            kinds.extend([2, 2]);
        }
        if self.prog.refs {
            kinds.extend([3, 3]);
        }
        if self.prog.recs.is_some() || self.prog.refs {
            kinds.push(4);
        }
        if kinds.is_empty() {
            return None;
        }
        Some(match *self.rng.pick(&kinds) {
            0 => {
                let t = *self
                    .rng
                    .pick(&[T::Int, T::Real, T::Bool, T::Dint, self.prog.array.0]);
                let p = self.computed(t, true)?;
                Stmt::Set(p, self.expr(t))
            }
            1 => {
                let (lo, hi) = self.prog.fbs.expect("fbs");
                let i = self.index_in(lo, hi);
                let mut targets = self.writable(T::Int);
                targets.push("q".into());
                let target = self.rng.pick(&targets).clone();
                Stmt::CallFbAt(i, self.expr(T::Int), self.expr(T::Int), target)
            }
            2 => {
                let places = [self.int_place(), self.rec_place(), self.darr_place()];
                let mut targets = self.writable(T::Dint);
                if targets.is_empty() {
                    targets.push("r1.d[1]".into());
                }
                let target = self.rng.pick(&targets).clone();
                Stmt::InOut(self.rng.chance(50), places, self.expr(T::Int), target)
            }
            4 if self.rng.chance(50) => Stmt::Copy(self.rec_place(), self.rec_place()),
            4 => Stmt::Copy(self.darr_place(), self.darr_place()),
            _ => match self.rng.below(10) {
                0 => Stmt::Ref((*self.rng.pick(&["p1", "pr", "pd", "pa"])).into(), None),
                1..=4 => Stmt::Ref("p1".into(), Some(self.int_place())),
                5..=6 => Stmt::Ref("pr".into(), Some(self.rec_place())),
                7..=8 => Stmt::Ref("pd".into(), Some(self.darr_place())),
                _ => Stmt::Ref("pa".into(), Some(Path::fixed("arr"))),
            },
        })
    }

    /// A statement on directly represented memory used without a declaration
    /// (`%MW11 := INT_TO_WORD(e);`, `%MX2.5 := c;`, `v := WORD_TO_INT(%MW11) + e;`).
    fn direct_stmt(&mut self) -> Stmt {
        let w = 10 + self.rng.below(3);
        match self.rng.below(3) {
            0 => {
                let e = crate::difftest::print::expr_text(&self.expr(T::Int));
                Stmt::Raw(format!("%MW{w} := INT_TO_WORD({e});"))
            }
            1 => {
                let e = crate::difftest::print::expr_text(&self.expr(T::Bool));
                Stmt::Raw(format!(
                    "%MX{}.{} := {e};",
                    self.rng.below(2),
                    self.rng.below(8)
                ))
            }
            _ => {
                let ints: Vec<String> = self
                    .prog
                    .vars
                    .iter()
                    .filter(|v| v.1 == T::Int)
                    .map(|v| v.0.clone())
                    .collect();
                let e = crate::difftest::print::expr_text(&self.expr(T::Int));
                match ints.is_empty() {
                    true => Stmt::Raw(format!("%MW{w} := %MW{w} + INT_TO_WORD({e});")),
                    false => {
                        let v = self.rng.pick(&ints).clone();
                        Stmt::Raw(format!("{v} := WORD_TO_INT(%MW{w}) + {e};"))
                    }
                }
            }
        }
    }

    /// A statement.
    pub fn stmt(&mut self) -> Stmt {
        if self.rng.chance(25) {
            if let Some(s) = self.pointer_stmt() {
                return s;
            }
        }
        let k = self.rng.below(100);
        let nested = self.depth < 2;
        let (et, lo, hi) = self.prog.array;
        match k {
            0..=36 => {
                let (n, t, _) = self.rng.pick(&self.prog.vars).clone();
                Stmt::Assign(n, self.expr(t))
            }
            37..=40 => {
                let t = *self.rng.pick(&[T::Int, T::Real, T::Bool, T::Dint]);
                let fields = struct_fields(t);
                let f = self.rng.pick(&fields).clone();
                Stmt::Assign(f, self.expr(t))
            }
            41..=44 if self.rng.chance(40) => self.direct_stmt(),
            41..=44 => Stmt::Raw(self.rng.pick(&RAW).to_string()),
            45..=59 => {
                let i = self.index();
                Stmt::AssignElem(i, self.expr(et))
            }
            60..=69 if nested => {
                self.depth += 1;
                let c = self.expr(T::Bool);
                let a = (0..1 + self.rng.below(3)).map(|_| self.stmt()).collect();
                let e = (0..self.rng.below(3)).map(|_| self.stmt()).collect();
                self.depth -= 1;
                Stmt::If(c, a, e)
            }
            70..=77 if nested => {
                self.depth += 1;
                if self.rng.chance(20) {
                    self.depth -= 1;
                    let e = self.rng.chance(50).then(|| lit(self.rng, et));
                    return Stmt::Fill(lo, hi, e.unwrap_or_else(|| self.expr(et)));
                }
                let step = *self.rng.pick(&[1i64, 1, 2, -1]);
                let (a, z) = if step < 0 { (hi, lo) } else { (lo, hi) };
                let body = (0..1 + self.rng.below(3)).map(|_| self.stmt()).collect();
                self.depth -= 1;
                Stmt::For(a, z, step, body)
            }
            78..=84 if nested => {
                self.depth += 1;
                let (sel, labels) = if self.rng.chance(50) {
                    self.dense_case()
                } else {
                    // Sparse: one value per arm, -1, 1, 3.
                    let n = 1 + self.rng.below(3) as i64;
                    let labels = (0..n).map(|i| vec![(i * 2 - 1, i * 2 - 1)]).collect();
                    (self.expr(T::Int), labels)
                };
                let arms = labels
                    .into_iter()
                    .map(|l| (l, (0..1 + self.rng.below(2)).map(|_| self.stmt()).collect()))
                    .collect();
                let other = (0..self.rng.below(2)).map(|_| self.stmt()).collect();
                self.depth -= 1;
                Stmt::Case(sel, arms, other)
            }
            85..=89 if nested => {
                self.depth += 1;
                let n = 1 + self.rng.below(5) as i64;
                let body = (0..1 + self.rng.below(2)).map(|_| self.stmt()).collect();
                self.depth -= 1;
                let stepped = self
                    .rng
                    .chance(50)
                    .then(|| (self.expr(T::Int), self.expr(T::Int)));
                Stmt::While(n, stepped, body)
            }
            _ => {
                let ints = self.readable(T::Int);
                let target = if ints.is_empty() {
                    "q".to_string()
                } else {
                    self.rng.pick(&ints).clone()
                };
                Stmt::CallFb(self.expr(T::Int), self.expr(T::Int), target)
            }
        }
    }
}
