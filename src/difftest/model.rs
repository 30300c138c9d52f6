//! The model of a random Structured Text program (types, expressions, statements,
//! configurations): what the generator (`gen.rs`) builds, the printer (`print.rs`)
//! prints and the shrinker edits.

pub use plcc_ir::rng::Rng;

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

    /// A signed integer type.
    pub(crate) fn is_signed(self) -> bool {
        matches!(self, T::Sint | T::Int | T::Dint | T::Lint)
    }

    /// An integer type.
    pub(crate) fn is_int(self) -> bool {
        matches!(
            self,
            T::Sint | T::Int | T::Dint | T::Lint | T::Usint | T::Uint | T::Udint | T::Ulint
        )
    }

    /// A bit string of more than one bit.
    pub(crate) fn is_bits(self) -> bool {
        matches!(self, T::Byte | T::Word | T::Dword | T::Lword)
    }

    /// REAL or LREAL.
    pub(crate) fn is_real(self) -> bool {
        matches!(self, T::Real | T::Lreal)
    }

    /// DATE, TOD or DT.
    pub(crate) fn is_date(self) -> bool {
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
    /// A place reached through a run-time address: a field of an element of the
    /// ARRAY OF STRUCT or of the ARRAY OF FB1 at a computed index, or what a
    /// reference points to (`recs[i].d[j]`, `fbs[i].r`, `pr^.b`).
    At(T, Path),
    /// EXPT of a REAL or LREAL whose exact result the type holds.
    Pow(Box<Pow>),
}

/// A place written as text with computed indexes between the pieces:
/// `parts[0] [idx[0]] parts[1] [idx[1]] …`, so `recs[i].d[j]` is the parts `recs[`,
/// `].d[`, `]` around `i` and `j`.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// The text pieces (one more than the indexes).
    pub parts: Vec<String>,
    /// The INT index expressions.
    pub idx: Vec<Expr>,
}

impl Path {
    /// A place with no computed index.
    pub fn fixed(text: &str) -> Path {
        Path {
            parts: vec![text.to_string()],
            idx: Vec::new(),
        }
    }
}

/// An operand of [`Pow`]: an integer value of type `T` (REAL, LREAL or an integer
/// type) that stays in a range whatever its inner INT expression gives.
#[derive(Clone, Debug, PartialEq)]
pub enum Operand {
    /// A literal of the value.
    Lit(T, i64),
    /// `INT_TO_T(LIMIT(lo, e, hi))`.
    Clamp(T, i64, i64, Box<Expr>),
    /// `INT_TO_T(MUX(LIMIT(0, e, n - 1), v0, …))`: one of the values.
    Choice(T, Vec<i64>, Box<Expr>),
}

/// `base ** exp` or `EXPT(base, exp)` with `base` of type `t` (REAL or LREAL). The
/// operands are integers small enough that the exact result fits the mantissa of
/// `t` (a negative exponent only with a base that is a power of two), so every
/// correct machine gives the same bits.
#[derive(Clone, Debug, PartialEq)]
pub struct Pow {
    /// The base's type, which is the result's.
    pub t: T,
    /// `EXPT(a, b)` rather than `a ** b`.
    pub call: bool,
    /// The base.
    pub base: Operand,
    /// The exponent.
    pub exp: Operand,
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
            | Expr::Call(t, ..)
            | Expr::At(t, _) => *t,
            Expr::Pow(p) => p.t,
        }
    }

    /// Direct subexpressions.
    pub fn children_mut(&mut self) -> Vec<&mut Expr> {
        match self {
            Expr::Lit(..) | Expr::Var(..) => Vec::new(),
            Expr::Elem(_, i) | Expr::Un(_, _, i) => vec![i.as_mut()],
            Expr::Bin(_, _, a, b) => vec![a.as_mut(), b.as_mut()],
            Expr::Call(_, _, args) => args.iter_mut().collect(),
            Expr::At(_, p) => p.idx.iter_mut().collect(),
            Expr::Pow(p) => [&mut p.base, &mut p.exp]
                .into_iter()
                .filter_map(|o| match o {
                    Operand::Lit(..) => None,
                    Operand::Clamp(.., e) | Operand::Choice(_, _, e) => Some(e.as_mut()),
                })
                .collect(),
        }
    }

    /// Direct subexpressions.
    pub fn children(&self) -> Vec<&Expr> {
        match self {
            Expr::Lit(..) | Expr::Var(..) => Vec::new(),
            Expr::Elem(_, i) | Expr::Un(_, _, i) => vec![i.as_ref()],
            Expr::Bin(_, _, a, b) => vec![a.as_ref(), b.as_ref()],
            Expr::Call(_, _, args) => args.iter().collect(),
            Expr::At(_, p) => p.idx.iter().collect(),
            Expr::Pow(p) => [&p.base, &p.exp]
                .into_iter()
                .filter_map(|o| match o {
                    Operand::Lit(..) => None,
                    Operand::Clamp(.., e) | Operand::Choice(_, _, e) => Some(e.as_ref()),
                })
                .collect(),
        }
    }
}

/// A CASE label `lo..hi` (a single value when `lo == hi`).
pub type Label = (i64, i64);

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
    /// `CASE sel OF labels: … ELSE … END_CASE;` (`sel` an integer expression; each
    /// arm's labels are `lo..hi` ranges, a single value when `lo == hi`). Half of
    /// them are dense, so that the front end makes jump tables of them.
    Case(Expr, Vec<(Vec<Label>, Vec<Stmt>)>, Vec<Stmt>),
    /// `FOR kN := lo TO hi DO arr[kN] := e; END_FOR;`: every element set to one
    /// value (a loop `passes::fill` makes one `fill` of).
    Fill(i64, i64, Expr),
    /// `WHILE wN < n DO … wN := wN + 1; END_WHILE;` (bounded by its counter), or,
    /// with `Some((start, step))`, `wN := start; wsN := step; wtN := 0; WHILE wN < n
    /// DO …; wtN := wtN + 1; IF wtN > 4 THEN EXIT; END_IF; wN := wN + wsN;
    /// END_WHILE;`: a counter whose start and step are known only at run time (the
    /// loops the watchdog pass copies without checks), bounded by `wtN`.
    While(i64, Option<(Expr, Expr)>, Vec<Stmt>),
    /// `fb(a := e1, b := e2); v := fb.r;`
    CallFb(Expr, Expr, String),
    /// A fixed statement on the STRUCT and enumeration variables (`r2 := r1;`).
    Raw(String),
    /// `place := e;` through a run-time address (see [`Expr::At`]).
    Set(Path, Expr),
    /// `fbs[i](a := e1, b := e2); v := fbs[i].r;`: a call of an element of the
    /// ARRAY OF FB1.
    CallFbAt(Expr, Expr, Expr, String),
    /// VAR_IN_OUT arguments: `v := fio(x := X, s := S, d := D, k := e);` or, for the
    /// FB, `f2(n := X, s := S, d := D, k := e); v := f2.r;` (X an INT, S a `Rec`, D
    /// an `ARRAY[0..2] OF DINT`).
    InOut(bool, [Path; 3], Expr, String),
    /// `ptr := REF(place);`, or `ptr := NULL;`.
    Ref(String, Option<Path>),
    /// `a := b;` of two `Rec`s or two `ARRAY[0..2] OF DINT`s, one of them (at least)
    /// reached through a run-time address (`recs[i] := pr^;`).
    Copy(Path, Path),
    /// A statement on the object-oriented part ([`super::oo`]): a method call, a
    /// loop over an array of interfaces, an interface or reference bound.
    Oo(Box<super::oo::OoStmt>),
}

impl Stmt {
    /// The expressions of the statement itself (not of its bodies).
    pub fn exprs(&self) -> Vec<&Expr> {
        match self {
            Stmt::Assign(_, e) => vec![e],
            Stmt::AssignElem(i, e) => vec![i, e],
            Stmt::Fill(_, _, e) => vec![e],
            Stmt::If(c, ..) | Stmt::Case(c, ..) => vec![c],
            Stmt::While(_, Some((a, b)), _) => vec![a, b],
            Stmt::For(..) | Stmt::While(..) | Stmt::Raw(_) => Vec::new(),
            Stmt::CallFb(a, b, _) => vec![a, b],
            Stmt::Set(p, e) => p.idx.iter().chain([e]).collect(),
            Stmt::CallFbAt(i, a, b, _) => vec![i, a, b],
            Stmt::InOut(_, places, k, _) => places
                .iter()
                .flat_map(|p| p.idx.iter())
                .chain([k])
                .collect(),
            Stmt::Ref(_, p) => p.iter().flat_map(|p| p.idx.iter()).collect(),
            Stmt::Copy(a, b) => a.idx.iter().chain(b.idx.iter()).collect(),
            Stmt::Oo(o) => o.exprs(),
        }
    }

    /// The expressions of the statement itself, to edit.
    pub fn exprs_mut(&mut self) -> Vec<&mut Expr> {
        match self {
            Stmt::Assign(_, e) => vec![e],
            Stmt::AssignElem(i, e) => vec![i, e],
            Stmt::Fill(_, _, e) => vec![e],
            Stmt::If(c, ..) | Stmt::Case(c, ..) => vec![c],
            Stmt::While(_, Some((a, b)), _) => vec![a, b],
            Stmt::For(..) | Stmt::While(..) | Stmt::Raw(_) => Vec::new(),
            Stmt::CallFb(a, b, _) => vec![a, b],
            Stmt::Set(p, e) => p.idx.iter_mut().chain([e]).collect(),
            Stmt::CallFbAt(i, a, b, _) => vec![i, a, b],
            Stmt::InOut(_, places, k, _) => places
                .iter_mut()
                .flat_map(|p| p.idx.iter_mut())
                .chain([k])
                .collect(),
            Stmt::Ref(_, p) => p.iter_mut().flat_map(|p| p.idx.iter_mut()).collect(),
            Stmt::Copy(a, b) => a.idx.iter_mut().chain(b.idx.iter_mut()).collect(),
            Stmt::Oo(o) => o.exprs_mut(),
        }
    }

    /// The statement lists inside the statement.
    pub fn bodies(&self) -> Vec<&Vec<Stmt>> {
        match self {
            Stmt::If(_, a, b) => vec![a, b],
            Stmt::For(_, _, _, b) | Stmt::While(_, _, b) => vec![b],
            Stmt::Case(_, arms, other) => arms.iter().map(|(_, b)| b).chain([other]).collect(),
            _ => Vec::new(),
        }
    }

    /// The statement lists inside the statement, to edit.
    pub fn bodies_mut(&mut self) -> Vec<&mut Vec<Stmt>> {
        match self {
            Stmt::If(_, a, b) => vec![a, b],
            Stmt::For(_, _, _, b) | Stmt::While(_, _, b) => vec![b],
            Stmt::Case(_, arms, other) => arms.iter_mut().map(|(_, b)| b).chain([other]).collect(),
            _ => Vec::new(),
        }
    }
}

/// A CONFIGURATION that makes several instances of PROGRAM `main`.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// VAR_GLOBAL variables and their initial values.
    pub globals: Vec<(String, T, Expr)>,
    /// TASKs: INTERVAL in ms and PRIORITY (task `tN` is the Nth).
    pub tasks: Vec<(u32, u32)>,
    /// The tasks and instances are inside a RESOURCE.
    pub resource: bool,
    /// The instances.
    pub instances: Vec<Instance>,
}

/// `PROGRAM name WITH tN : main (conns);`
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// The instance's name.
    pub name: String,
    /// Its task, if any (without one it runs every scan).
    pub task: Option<usize>,
    /// Its connections.
    pub conns: Vec<Conn>,
}

/// A connection of a configured instance.
#[derive(Clone, Debug, PartialEq)]
pub enum Conn {
    /// `input := value` (a global or a literal).
    In(String, Expr),
    /// `output => global`.
    Out(String, String),
}

/// A generated program: its variables, array, inputs, and body, with a FUNCTION and
/// an FB it may call, the parts that are reached through run-time addresses (each
/// declared only when the program has it), and a CONFIGURATION, if any.
#[derive(Clone, Debug, PartialEq)]
pub struct Prog {
    /// Variables and their initial values (the first `outputs` are VAR_OUTPUTs).
    pub vars: Vec<(String, T, Expr)>,
    /// How many of `vars` are VAR_OUTPUTs.
    pub outputs: usize,
    /// VAR_INPUT variables (the runner sets them between scans).
    pub inputs: Vec<(String, T)>,
    /// The array's element type and bounds.
    pub array: (T, i64, i64),
    /// The bounds of `recs : ARRAY OF Rec`, if the program has it.
    pub recs: Option<(i64, i64)>,
    /// The bounds of `fbs : ARRAY OF FB1`, if the program has it.
    pub fbs: Option<(i64, i64)>,
    /// The program has the FUNCTION `fio` and the FB `FB2` (instance `f2`) with
    /// VAR_IN_OUT parameters.
    pub inout: bool,
    /// The program has the references `p1 : REF_TO INT`, `pr : REF_TO Rec`,
    /// `pd : REF_TO ARRAY[0..2] OF DINT` and `pa : REF_TO` the array's type.
    pub refs: bool,
    /// The program body.
    pub body: Vec<Stmt>,
    /// Instances of `main` in a CONFIGURATION (without one, `main` is the program).
    pub config: Option<Config>,
    /// The fixed declarations the shrinker took away (of [`FIXED`]).
    pub dropped: Vec<String>,
    /// The object-oriented part (interfaces, function blocks with methods and
    /// their instances), if the program has one ([`super::oo`]).
    pub oo: Option<super::oo::Oo>,
}

/// The declarations every program has until the shrinker takes them away: the
/// FUNCTION `fun`, the FB `FB1`, the types `Rec` and `Mode`, and `main`'s `arr`,
/// `r1`, `r2`, `m1`, `q` and `fb`.
pub const FIXED: [&str; 10] = [
    "fun", "FB1", "Rec", "Mode", "arr", "r1", "r2", "m1", "q", "fb",
];

impl Prog {
    /// The variables the runner sets before every scan, by path: the VAR_INPUTs of
    /// every instance that no connection sets, and the globals no output writes.
    pub fn input_paths(&self) -> Vec<(String, T)> {
        let Some(c) = &self.config else {
            return self
                .inputs
                .iter()
                .map(|(n, t)| (format!("main.{n}"), *t))
                .collect();
        };
        let mut out = Vec::new();
        for inst in &c.instances {
            for (n, t) in &self.inputs {
                let connected = inst
                    .conns
                    .iter()
                    .any(|k| matches!(k, Conn::In(i, _) if i == n));
                if !connected {
                    out.push((format!("{}.{n}", inst.name), *t));
                }
            }
        }
        for (g, t, _) in &c.globals {
            let written = c.instances.iter().any(|i| {
                i.conns
                    .iter()
                    .any(|k| matches!(k, Conn::Out(_, x) if x == g))
            });
            if !written {
                out.push((format!("{}.{g}", plcc_frontend::GLOBALS_DATA), *t));
            }
        }
        out
    }
}
