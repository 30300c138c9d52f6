//! Random, well-typed Structured Text programs: a small program model, a generator
//! that only builds what IEC 61131-3 typing allows (every conversion explicit), and a
//! printer. The model is what the shrinker edits.

use std::fmt::Write;

/// A small deterministic random generator (xorshift64*), so a seed names a program
/// on every machine.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }

    /// True with probability `p` percent.
    pub fn chance(&mut self, p: u64) -> bool {
        self.below(100) < p
    }

    /// One of `items`.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len() as u64) as usize]
    }
}

/// The elementary types the generator uses.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum T {
    /// BOOL
    Bool,
    /// SINT
    Sint,
    /// INT
    Int,
    /// DINT
    Dint,
    /// LINT
    Lint,
    /// USINT
    Usint,
    /// UINT
    Uint,
    /// UDINT
    Udint,
    /// ULINT
    Ulint,
    /// BYTE
    Byte,
    /// WORD
    Word,
    /// DWORD
    Dword,
    /// LWORD
    Lword,
    /// REAL
    Real,
    /// LREAL
    Lreal,
    /// TIME
    Time,
    /// DATE
    Date,
    /// TIME_OF_DAY
    Tod,
    /// DATE_AND_TIME
    Dt,
}

/// Every type, for picking.
pub const ALL: [T; 19] = [
    T::Bool,
    T::Sint,
    T::Int,
    T::Dint,
    T::Lint,
    T::Usint,
    T::Uint,
    T::Udint,
    T::Ulint,
    T::Byte,
    T::Word,
    T::Dword,
    T::Lword,
    T::Real,
    T::Lreal,
    T::Time,
    T::Date,
    T::Tod,
    T::Dt,
];

impl T {
    /// The IEC name.
    pub fn name(self) -> &'static str {
        match self {
            T::Bool => "BOOL",
            T::Sint => "SINT",
            T::Int => "INT",
            T::Dint => "DINT",
            T::Lint => "LINT",
            T::Usint => "USINT",
            T::Uint => "UINT",
            T::Udint => "UDINT",
            T::Ulint => "ULINT",
            T::Byte => "BYTE",
            T::Word => "WORD",
            T::Dword => "DWORD",
            T::Lword => "LWORD",
            T::Real => "REAL",
            T::Lreal => "LREAL",
            T::Time => "TIME",
            T::Date => "DATE",
            T::Tod => "TOD",
            T::Dt => "DT",
        }
    }

    /// Width in bits.
    pub fn bits(self) -> u32 {
        match self {
            T::Bool => 1,
            T::Sint | T::Usint | T::Byte => 8,
            T::Int | T::Uint | T::Word => 16,
            T::Dint | T::Udint | T::Dword | T::Real | T::Time => 32,
            T::Date | T::Tod | T::Dt => 32,
            _ => 64,
        }
    }

    fn is_signed(self) -> bool {
        matches!(self, T::Sint | T::Int | T::Dint | T::Lint)
    }

    fn is_int(self) -> bool {
        matches!(
            self,
            T::Sint | T::Int | T::Dint | T::Lint | T::Usint | T::Uint | T::Udint | T::Ulint
        )
    }

    fn is_bits(self) -> bool {
        matches!(self, T::Byte | T::Word | T::Dword | T::Lword)
    }

    fn is_real(self) -> bool {
        matches!(self, T::Real | T::Lreal)
    }

    fn is_date(self) -> bool {
        matches!(self, T::Date | T::Tod | T::Dt)
    }
}

/// An expression; each knows its type.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A literal, as written.
    Lit(T, String),
    /// A variable.
    Var(T, String),
    /// An element of the array (its type is the array's).
    Elem(T, Box<Expr>),
    /// `a op b` with a result of type `T`.
    Bin(T, &'static str, Box<Expr>, Box<Expr>),
    /// `op a`.
    Un(T, &'static str, Box<Expr>),
    /// A call of a standard or user function.
    Call(T, String, Vec<Expr>),
}

impl Expr {
    /// The expression's type.
    pub fn ty(&self) -> T {
        match self {
            Expr::Lit(t, _)
            | Expr::Var(t, _)
            | Expr::Elem(t, _)
            | Expr::Bin(t, ..)
            | Expr::Un(t, ..)
            | Expr::Call(t, ..) => *t,
        }
    }

    /// Direct subexpressions.
    pub fn children_mut(&mut self) -> Vec<&mut Expr> {
        match self {
            Expr::Lit(..) | Expr::Var(..) => Vec::new(),
            Expr::Elem(_, i) | Expr::Un(_, _, i) => vec![i.as_mut()],
            Expr::Bin(_, _, a, b) => vec![a.as_mut(), b.as_mut()],
            Expr::Call(_, _, args) => args.iter_mut().collect(),
        }
    }
}

/// A statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `v := e;`
    Assign(String, Expr),
    /// `arr[i] := e;`
    AssignElem(Expr, Expr),
    /// `IF c THEN … ELSE … END_IF;`
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `FOR kN := lo TO hi BY step DO … END_FOR;` (N: the nesting depth, so nested
    /// loops have their own control variables).
    For(i64, i64, i64, Vec<Stmt>),
    /// `CASE sel OF n: … ELSE … END_CASE;` (`sel` an INT expression).
    Case(Expr, Vec<(i64, Vec<Stmt>)>, Vec<Stmt>),
    /// `WHILE wN < n DO … wN := wN + 1; END_WHILE;` (bounded by its counter).
    While(i64, Vec<Stmt>),
    /// `fb(a := e1, b := e2); v := fb.r;`
    CallFb(Expr, Expr, String),
    /// A fixed statement on the STRUCT and enumeration variables (`r2 := r1;`).
    Raw(String),
}

/// A generated program: its variables, array, inputs, and body, with a FUNCTION and
/// an FB it may call.
#[derive(Clone, Debug, PartialEq)]
pub struct Prog {
    /// Variables and their initial values.
    pub vars: Vec<(String, T, Expr)>,
    /// VAR_INPUT variables (the runner sets them between scans).
    pub inputs: Vec<(String, T)>,
    /// The array's element type and bounds.
    pub array: (T, i64, i64),
    /// The program body.
    pub body: Vec<Stmt>,
}

/// Generation state.
pub struct Gen<'r> {
    rng: &'r mut Rng,
    prog: Prog,
    depth: u32,
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

fn lit(rng: &mut Rng, t: T) -> Expr {
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
                inputs: Vec::new(),
                array: (T::Int, 0, 0),
                body: Vec::new(),
            },
            depth: 0,
        }
    }

    /// A whole program.
    pub fn program(mut self) -> Prog {
        let n = 3 + self.rng.below(7);
        for i in 0..n {
            let t = *self.rng.pick(&ALL);
            let init = lit(self.rng, t);
            self.prog.vars.push((format!("v{i}"), t, init));
        }
        for i in 0..self.rng.below(3) {
            let t = *self.rng.pick(&ALL);
            self.prog.inputs.push((format!("in{i}"), t));
        }
        let et = *self
            .rng
            .pick(&[T::Int, T::Dint, T::Byte, T::Real, T::Lword, T::Bool]);
        let lo = *self.rng.pick(&[0i64, 1, -3, 10]);
        let hi = lo + 2 + self.rng.below(8) as i64;
        self.prog.array = (et, lo, hi);
        let count = 3 + self.rng.below(10);
        for _ in 0..count {
            let s = self.stmt();
            self.prog.body.push(s);
        }
        self.prog
    }

    fn readable(&self, t: T) -> Vec<String> {
        let mut v: Vec<String> = self
            .prog
            .vars
            .iter()
            .filter(|(_, vt, _)| *vt == t)
            .map(|(n, _, _)| n.clone())
            .collect();
        v.extend(
            self.prog
                .inputs
                .iter()
                .filter(|(_, vt)| *vt == t)
                .map(|(n, _)| n.clone()),
        );
        v.extend(struct_fields(t));
        v
    }

    /// An expression of type `t`.
    pub fn expr(&mut self, t: T) -> Expr {
        self.depth += 1;
        let e = self.expr_inner(t);
        self.depth -= 1;
        e
    }

    fn index(&mut self) -> Expr {
        let (_, lo, hi) = self.prog.array;
        if self.rng.chance(40) {
            return Expr::Lit(
                T::Int,
                format!("{}", lo + self.rng.below((hi - lo + 1) as u64) as i64),
            );
        }
        // Out-of-range indexes are part of the semantics (fault flag, read 0).
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

    fn expr_inner(&mut self, t: T) -> Expr {
        let vars = self.readable(t);
        if self.depth > 3 || self.rng.chance(25) {
            if !vars.is_empty() && self.rng.chance(65) {
                return Expr::Var(t, self.rng.pick(&vars).clone());
            }
            if t == self.prog.array.0 && self.rng.chance(30) {
                let i = self.index();
                return Expr::Elem(t, Box::new(i));
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
                80..=84 => {
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

    /// A statement.
    pub fn stmt(&mut self) -> Stmt {
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
                let step = *self.rng.pick(&[1i64, 1, 2, -1]);
                let (a, z) = if step < 0 { (hi, lo) } else { (lo, hi) };
                let body = (0..1 + self.rng.below(3)).map(|_| self.stmt()).collect();
                self.depth -= 1;
                Stmt::For(a, z, step, body)
            }
            78..=84 if nested => {
                self.depth += 1;
                let sel = self.expr(T::Int);
                let arms = (0..1 + self.rng.below(3))
                    .map(|i| {
                        (
                            i as i64 * 2 - 1,
                            (0..1 + self.rng.below(2)).map(|_| self.stmt()).collect(),
                        )
                    })
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
                Stmt::While(n, body)
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

fn print_expr(e: &Expr, out: &mut String) {
    match e {
        Expr::Lit(_, s) | Expr::Var(_, s) => out.push_str(s),
        Expr::Elem(_, i) => {
            out.push_str("arr[");
            print_expr(i, out);
            out.push(']');
        }
        Expr::Bin(_, op, a, b) => {
            out.push('(');
            print_expr(a, out);
            let _ = write!(out, " {op} ");
            print_expr(b, out);
            out.push(')');
        }
        Expr::Un(_, op, a) => {
            let _ = write!(out, "({op} ");
            print_expr(a, out);
            out.push(')');
        }
        Expr::Call(_, f, args) => {
            out.push_str(f);
            out.push('(');
            for (i, a) in args.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                print_expr(a, out);
            }
            out.push(')');
        }
    }
}

fn print_stmts(body: &[Stmt], ind: usize, out: &mut String) {
    let pad = "    ".repeat(ind);
    for s in body {
        match s {
            Stmt::Assign(v, e) => {
                let _ = write!(out, "{pad}{v} := ");
                print_expr(e, out);
                out.push_str(";\n");
            }
            Stmt::AssignElem(i, e) => {
                let _ = write!(out, "{pad}arr[");
                print_expr(i, out);
                out.push_str("] := ");
                print_expr(e, out);
                out.push_str(";\n");
            }
            Stmt::If(c, a, b) => {
                let _ = write!(out, "{pad}IF ");
                print_expr(c, out);
                out.push_str(" THEN\n");
                print_stmts(a, ind + 1, out);
                if !b.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    print_stmts(b, ind + 1, out);
                }
                let _ = writeln!(out, "{pad}END_IF;");
            }
            Stmt::For(a, z, step, body) => {
                let _ = writeln!(out, "{pad}FOR k{ind} := {a} TO {z} BY {step} DO");
                print_stmts(body, ind + 1, out);
                let _ = writeln!(out, "{pad}END_FOR;");
            }
            Stmt::Case(sel, arms, other) => {
                let _ = write!(out, "{pad}CASE ");
                print_expr(sel, out);
                out.push_str(" OF\n");
                for (n, body) in arms {
                    let _ = writeln!(out, "{pad}    {n}:");
                    print_stmts(body, ind + 2, out);
                }
                if !other.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    print_stmts(other, ind + 2, out);
                }
                let _ = writeln!(out, "{pad}END_CASE;");
            }
            Stmt::While(n, body) => {
                let _ = writeln!(out, "{pad}w{ind} := 0;\n{pad}WHILE w{ind} < {n} DO");
                print_stmts(body, ind + 1, out);
                let _ = writeln!(out, "{pad}    w{ind} := w{ind} + 1;\n{pad}END_WHILE;");
            }
            Stmt::Raw(text) => {
                let _ = writeln!(out, "{pad}{text}");
            }
            Stmt::CallFb(a, b, target) => {
                let _ = write!(out, "{pad}fb(a := ");
                print_expr(a, out);
                out.push_str(", b := ");
                print_expr(b, out);
                let _ = writeln!(out, ");\n{pad}{target} := fb.r;");
            }
        }
    }
}

impl Prog {
    /// The ST text: a FUNCTION, an FB and PROGRAM `main`.
    pub fn to_st(&self) -> String {
        let mut o = String::new();
        o.push_str(
            "FUNCTION fun : DINT\nVAR_INPUT x, y : DINT; END_VAR\n    IF y <> 0 THEN\n        fun := x / y + x MOD 3;\n    ELSE\n        fun := x * 2 - 1;\n    END_IF;\nEND_FUNCTION\n\n",
        );
        o.push_str(
            "FUNCTION_BLOCK FB1\nVAR_INPUT a, b : INT; END_VAR\nVAR_OUTPUT r : INT; END_VAR\nVAR acc : INT; END_VAR\n    acc := acc + a - b;\n    r := acc * 2;\nEND_FUNCTION_BLOCK\n\n",
        );
        o.push_str(
            "TYPE\n    Rec : STRUCT\n        a : INT := 3;\n        b : REAL;\n        c : BOOL;\n        d : ARRAY[0..2] OF DINT := [1, 2, 3];\n    END_STRUCT;\n    Mode : (Idle, Run := 5, Stop);\nEND_TYPE\n\n",
        );
        o.push_str("PROGRAM main\n");
        if !self.inputs.is_empty() {
            o.push_str("VAR_INPUT\n");
            for (n, t) in &self.inputs {
                let _ = writeln!(o, "    {n} : {};", t.name());
            }
            o.push_str("END_VAR\n");
        }
        o.push_str("VAR\n");
        for (n, t, init) in &self.vars {
            let _ = write!(o, "    {n} : {} := ", t.name());
            print_expr(init, &mut o);
            o.push_str(";\n");
        }
        let (et, lo, hi) = self.array;
        let _ = writeln!(o, "    arr : ARRAY[{lo}..{hi}] OF {};", et.name());
        o.push_str("    r1, r2 : Rec;\n    m1 : Mode := Mode#Run;\n");
        o.push_str("    k1, k2, k3, k4 : INT;\n    w1, w2, w3, w4 : INT;\n    q : INT;\n    fb : FB1;\nEND_VAR\n");
        print_stmts(&self.body, 1, &mut o);
        o.push_str("END_PROGRAM\n");
        o
    }
}
