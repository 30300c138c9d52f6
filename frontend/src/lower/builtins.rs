//! The standard functions of IEC 61131-3: type conversions, numeric, bit-shift,
//! selection and comparison functions, and the function forms of the operators.

use super::body::BodyCx;
use super::expr::Val;
use super::strings::StrFn;
use super::typing::{concretize, unify};
use crate::ast::{Arg, ArgKind, BinaryOp as Op, Expr};
use crate::codes;
use crate::types::Ty;
use plcc_ir::diag::Span;
use plcc_ir::{BinaryOp, ConvOp, ElemType, IntCC, Intrinsic, Type, UnaryOp, Value};

/// A standard function.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(super) enum Builtin {
    /// `X_TO_Y`, `TO_Y` (from the argument's type), `X_TRUNC_Y`/`TRUNC_Y` (toward
    /// zero).
    Convert {
        from: Option<ElemType>,
        to: ElemType,
        trunc: bool,
    },
    /// `TRUNC(x)`: REAL/LREAL to an integer (DINT/LINT) toward zero.
    Trunc,
    /// `ABS`
    Abs,
    /// `SQRT LN LOG EXP SIN COS TAN ASIN ACOS ATAN`
    Math(UnaryOp),
    /// `EXPT(a, b)`
    Expt,
    /// `ADD MUL SUB DIV MOD` (ADD and MUL take any number of inputs).
    Arith(Op),
    /// `GT GE EQ LE LT NE` (GT, GE, EQ, LE, LT chain over several inputs).
    Compare(Op),
    /// `AND OR XOR` (extensible).
    Logic(Op),
    /// `NOT`
    Not,
    /// `MOVE`
    Move,
    /// `SHL SHR ROL ROR`
    Shift(BinaryOp),
    /// `SEL(G, IN0, IN1)`
    Sel,
    /// `MAX` (extensible)
    Max,
    /// `MIN` (extensible)
    Min,
    /// `LIMIT(MN, IN, MX)`
    Limit,
    /// `MUX(K, IN0, IN1, ...)`
    Mux,
    /// `ADD_TIME SUB_TIME MUL_TIME DIV_TIME` (also `MULTIME DIVTIME`, edition 2's
    /// names) and their LTIME forms `ADD_LTIME ...`: the duration type they take.
    TimeOp(Op, ElemType),
    /// `__PLC_CLOCK()`: the PLC clock (TIME), used by the standard timers; also
    /// CPDev's `CUR_TIME()`, so user code reads the same clock the timers do (sampled
    /// once per scan).
    Clock,
    /// The PLC-UD STL's standard operations (`INC DEC SWAP SET CLR`), which the STL
    /// front end calls by internal names (`__STL_INC`, ...).
    Stl(StlOp),
    /// A string function or a conversion to or from a string.
    Str(StrFn),
    /// `REF(x)`, or CODESYS `ADR(x)` (`pointer`).
    Ref { pointer: bool },
    /// `SIZEOF(x)`
    SizeOf,
    /// The date and time functions of table 30 (`ADD_TOD_TIME`, ...).
    Date(super::dates::DateFn),
    /// The BCD conversions (`WORD_BCD_TO_UINT`, `UINT_TO_BCD_WORD`, ...).
    Bcd(super::bcd::BcdFn),
}

/// The standard operations of the PLC-UD STL that IEC 61131-3 does not have.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum StlOp {
    /// `INC(x)`: x + 1
    Inc,
    /// `DEC(x)`: x - 1
    Dec,
    /// `SWAP(x)`: the two halves of x exchanged (the nibbles of a byte)
    Swap,
    /// `SET(x, n)`: x with bit n set
    Set,
    /// `CLR(x, n)`: x with bit n cleared
    Clr,
}

/// The standard functions plcc compiles (conversions `X_TO_Y` aside, which are too
/// many to list) with their signatures in IEC 61131-3's generic types (`ANY_NUM`,
/// ...; `*` for any number of inputs of that kind): names upper case, for editors'
/// completion and hovers.
pub const STANDARD_FUNCTIONS: &[(&str, &str)] = &[
    ("ABS", "ABS(IN : ANY_NUM) : ANY_NUM"),
    ("SQRT", "SQRT(IN : ANY_REAL) : ANY_REAL"),
    ("LN", "LN(IN : ANY_REAL) : ANY_REAL"),
    ("LOG", "LOG(IN : ANY_REAL) : ANY_REAL"),
    ("EXP", "EXP(IN : ANY_REAL) : ANY_REAL"),
    ("SIN", "SIN(IN : ANY_REAL) : ANY_REAL"),
    ("COS", "COS(IN : ANY_REAL) : ANY_REAL"),
    ("TAN", "TAN(IN : ANY_REAL) : ANY_REAL"),
    ("ASIN", "ASIN(IN : ANY_REAL) : ANY_REAL"),
    ("ACOS", "ACOS(IN : ANY_REAL) : ANY_REAL"),
    ("ATAN", "ATAN(IN : ANY_REAL) : ANY_REAL"),
    ("EXPT", "EXPT(IN1 : ANY_REAL, IN2 : ANY_NUM) : ANY_REAL"),
    ("TRUNC", "TRUNC(IN : ANY_REAL) : ANY_INT"),
    ("ADD", "ADD(IN1, IN2, * : ANY_MAGNITUDE) : ANY_MAGNITUDE"),
    ("SUB", "SUB(IN1, IN2 : ANY_MAGNITUDE) : ANY_MAGNITUDE"),
    ("MUL", "MUL(IN1, IN2, * : ANY_NUM) : ANY_NUM"),
    ("DIV", "DIV(IN1, IN2 : ANY_NUM) : ANY_NUM"),
    ("MOD", "MOD(IN1, IN2 : ANY_INT) : ANY_INT"),
    ("GT", "GT(IN1, IN2, * : ANY_ELEMENTARY) : BOOL"),
    ("GE", "GE(IN1, IN2, * : ANY_ELEMENTARY) : BOOL"),
    ("EQ", "EQ(IN1, IN2, * : ANY_ELEMENTARY) : BOOL"),
    ("LE", "LE(IN1, IN2, * : ANY_ELEMENTARY) : BOOL"),
    ("LT", "LT(IN1, IN2, * : ANY_ELEMENTARY) : BOOL"),
    ("NE", "NE(IN1, IN2 : ANY_ELEMENTARY) : BOOL"),
    ("AND", "AND(IN1, IN2, * : ANY_BIT) : ANY_BIT"),
    ("OR", "OR(IN1, IN2, * : ANY_BIT) : ANY_BIT"),
    ("XOR", "XOR(IN1, IN2, * : ANY_BIT) : ANY_BIT"),
    ("NOT", "NOT(IN : ANY_BIT) : ANY_BIT"),
    ("MOVE", "MOVE(IN : ANY) : ANY"),
    ("SHL", "SHL(IN : ANY_BIT, N : ANY_INT) : ANY_BIT"),
    ("SHR", "SHR(IN : ANY_BIT, N : ANY_INT) : ANY_BIT"),
    ("ROL", "ROL(IN : ANY_BIT, N : ANY_INT) : ANY_BIT"),
    ("ROR", "ROR(IN : ANY_BIT, N : ANY_INT) : ANY_BIT"),
    ("SEL", "SEL(G : BOOL, IN0, IN1 : ANY) : ANY"),
    ("MAX", "MAX(IN1, IN2, * : ANY_ELEMENTARY) : ANY_ELEMENTARY"),
    ("MIN", "MIN(IN1, IN2, * : ANY_ELEMENTARY) : ANY_ELEMENTARY"),
    (
        "LIMIT",
        "LIMIT(MN, IN, MX : ANY_ELEMENTARY) : ANY_ELEMENTARY",
    ),
    ("MUX", "MUX(K : ANY_INT, IN0, IN1, * : ANY) : ANY"),
    ("ADD_TIME", "ADD_TIME(IN1, IN2 : TIME) : TIME"),
    ("SUB_TIME", "SUB_TIME(IN1, IN2 : TIME) : TIME"),
    ("MUL_TIME", "MUL_TIME(IN1 : TIME, IN2 : ANY_NUM) : TIME"),
    ("DIV_TIME", "DIV_TIME(IN1 : TIME, IN2 : ANY_NUM) : TIME"),
    ("LEN", "LEN(IN : ANY_STRING) : INT"),
    ("LEFT", "LEFT(IN : ANY_STRING, L : ANY_INT) : ANY_STRING"),
    ("RIGHT", "RIGHT(IN : ANY_STRING, L : ANY_INT) : ANY_STRING"),
    ("MID", "MID(IN : ANY_STRING, L, P : ANY_INT) : ANY_STRING"),
    ("CONCAT", "CONCAT(IN1, IN2, * : ANY_STRING) : ANY_STRING"),
    (
        "INSERT",
        "INSERT(IN1, IN2 : ANY_STRING, P : ANY_INT) : ANY_STRING",
    ),
    (
        "DELETE",
        "DELETE(IN : ANY_STRING, L, P : ANY_INT) : ANY_STRING",
    ),
    (
        "REPLACE",
        "REPLACE(IN1, IN2 : ANY_STRING, L, P : ANY_INT) : ANY_STRING",
    ),
    ("FIND", "FIND(IN1, IN2 : ANY_STRING) : INT"),
    ("REF", "REF(IN : ANY) : REF_TO ANY"),
    ("ADR", "ADR(IN : ANY) : POINTER TO ANY (CODESYS)"),
    (
        "SIZEOF",
        "SIZEOF(IN : ANY) : ANY_INT (CODESYS: the size in bytes)",
    ),
];

impl Builtin {
    /// The standard function with this (upper-case) name.
    pub(super) fn lookup(name: &str) -> Option<Builtin> {
        use Builtin::*;
        Some(match name {
            "TRUNC" => Trunc,
            "ABS" => Abs,
            "SQRT" => Math(UnaryOp::Fsqrt),
            "LN" => Math(UnaryOp::Ln),
            "LOG" => Math(UnaryOp::Log10),
            "EXP" => Math(UnaryOp::Exp),
            "SIN" => Math(UnaryOp::Sin),
            "COS" => Math(UnaryOp::Cos),
            "TAN" => Math(UnaryOp::Tan),
            "ASIN" => Math(UnaryOp::Asin),
            "ACOS" => Math(UnaryOp::Acos),
            "ATAN" => Math(UnaryOp::Atan),
            "EXPT" => Expt,
            "ADD" => Arith(Op::Add),
            "SUB" => Arith(Op::Sub),
            "MUL" => Arith(Op::Mul),
            "DIV" => Arith(Op::Div),
            "MOD" => Arith(Op::Mod),
            "GT" => Compare(Op::Gt),
            "GE" => Compare(Op::Ge),
            "EQ" => Compare(Op::Eq),
            "LE" => Compare(Op::Le),
            "LT" => Compare(Op::Lt),
            "NE" => Compare(Op::Ne),
            "AND" => Logic(Op::And),
            "OR" => Logic(Op::Or),
            "XOR" => Logic(Op::Xor),
            "NOT" => Not,
            "MOVE" => Move,
            "SHL" => Shift(BinaryOp::Ishl),
            "SHR" => Shift(BinaryOp::Ushr),
            "ROL" => Shift(BinaryOp::Rotl),
            "ROR" => Shift(BinaryOp::Rotr),
            "SEL" => Sel,
            "MAX" => Max,
            "MIN" => Min,
            "LIMIT" => Limit,
            "MUX" => Mux,
            "ADD_TIME" => TimeOp(Op::Add, ElemType::Time),
            "SUB_TIME" => TimeOp(Op::Sub, ElemType::Time),
            "MUL_TIME" | "MULTIME" => TimeOp(Op::Mul, ElemType::Time),
            "DIV_TIME" | "DIVTIME" => TimeOp(Op::Div, ElemType::Time),
            "ADD_LTIME" => TimeOp(Op::Add, ElemType::LTime),
            "SUB_LTIME" => TimeOp(Op::Sub, ElemType::LTime),
            "MUL_LTIME" => TimeOp(Op::Mul, ElemType::LTime),
            "DIV_LTIME" => TimeOp(Op::Div, ElemType::LTime),
            // CODESYS's TIME() is its millisecond clock.
            "__PLC_CLOCK" | "CUR_TIME" | "TIME" => Clock,
            "__STL_INC" => Stl(StlOp::Inc),
            "__STL_DEC" => Stl(StlOp::Dec),
            "__STL_SWAP" => Stl(StlOp::Swap),
            "__STL_SET" => Stl(StlOp::Set),
            "__STL_CLR" => Stl(StlOp::Clr),
            "REF" => Ref { pointer: false },
            "ADR" => Ref { pointer: true },
            "SIZEOF" => SizeOf,
            n if super::bcd::BcdFn::lookup(n).is_some() => {
                Bcd(super::bcd::BcdFn::lookup(n).expect("checked"))
            }
            n if super::dates::DateFn::lookup(n).is_some() => {
                Date(super::dates::DateFn::lookup(n).expect("checked"))
            }
            _ => {
                if let Some(f) = StrFn::lookup(name) {
                    return Some(Str(f));
                }
                if let Some(f) = super::bcd::BcdFn::lookup(name) {
                    return Some(Bcd(f));
                }
                return Self::conversion(name);
            }
        })
    }

    /// Standard functions (and common dialect ones) that plcc does not compile yet:
    /// the feature they belong to, for a not-supported diagnostic.
    pub(super) fn unsupported(name: &str) -> Option<&'static str> {
        Some(match name {
            "CONCAT_DATE" | "CONCAT_TOD" | "CONCAT_DT" | "SPLIT_DATE" | "SPLIT_TOD"
            | "SPLIT_DT" | "DAY_OF_WEEK" => "date and time functions",
            "REFERENCE" => "REFERENCE (write REF)",
            "PRINTF" => "printf (a RuSTy extension)",
            _ if name.contains("STRING") || name.contains("CHAR") => "string conversions",
            _ if name.starts_with("DATE_")
                || name.starts_with("DT_")
                || name.starts_with("TOD_")
                || name.contains("_TO_DATE")
                || name.contains("_TO_DT")
                || name.contains("_TO_TOD") =>
            {
                "date and time conversions"
            }
            _ => return None,
        })
    }

    /// `X_TO_Y`, `TO_Y`, `X_TRUNC_Y`, `TRUNC_Y`.
    fn conversion(name: &str) -> Option<Builtin> {
        let elem = |s: &str| ElemType::from_name(s).filter(|e| *e != ElemType::Ref);
        if let Some(to) = name.strip_prefix("TO_") {
            return Some(Builtin::Convert {
                from: None,
                to: elem(to)?,
                trunc: false,
            });
        }
        if let Some(to) = name.strip_prefix("TRUNC_") {
            return Some(Builtin::Convert {
                from: None,
                to: elem(to)?,
                trunc: true,
            });
        }
        if let Some(i) = name.find("_TRUNC_") {
            return Some(Builtin::Convert {
                from: Some(elem(&name[..i])?),
                to: elem(&name[i + 7..])?,
                trunc: true,
            });
        }
        let i = name.find("_TO_")?;
        Some(Builtin::Convert {
            from: Some(elem(&name[..i])?),
            to: elem(&name[i + 4..])?,
            trunc: false,
        })
    }

    /// Formal parameter names, in positional order. Extensible functions repeat their
    /// last pattern (`IN1, IN2, ...`).
    fn param_name(self, i: usize) -> String {
        use Builtin::*;
        match self {
            Convert { .. } | Trunc | Abs | Math(_) | Not | Move | Bcd(_) => "IN".into(),
            Stl(_) => ["IN", "N"].get(i).unwrap_or(&"?").to_string(),
            Shift(_) => ["IN", "N"].get(i).unwrap_or(&"?").to_string(),
            Sel => ["G", "IN0", "IN1"].get(i).unwrap_or(&"?").to_string(),
            Limit => ["MN", "IN", "MX"].get(i).unwrap_or(&"?").to_string(),
            Mux => {
                if i == 0 {
                    "K".into()
                } else {
                    format!("IN{}", i - 1)
                }
            }
            Str(f) => f.param_name(i),
            _ => format!("IN{}", i + 1),
        }
    }

    /// (minimum, maximum) number of inputs.
    fn arity(self) -> (usize, usize) {
        use Builtin::*;
        match self {
            Convert { .. } | Trunc | Abs | Math(_) | Not | Move | Ref { .. } | SizeOf | Bcd(_) => {
                (1, 1)
            }
            Clock => (0, 0),
            Stl(StlOp::Set) | Stl(StlOp::Clr) => (2, 2),
            Stl(_) => (1, 1),
            Expt | Shift(_) | TimeOp(..) | Date(_) => (2, 2),
            Arith(Op::Add) | Arith(Op::Mul) | Logic(_) | Max | Min => (2, usize::MAX),
            Arith(_) | Compare(Op::Ne) => (2, 2),
            Compare(_) => (2, usize::MAX),
            Sel | Limit => (3, 3),
            Mux => (2, usize::MAX),
            Str(f) => f.arity(),
        }
    }
}

impl<'s> BodyCx<'_, 's> {
    /// Orders the arguments of a standard function by its formal parameter names.
    fn builtin_args(
        &mut self,
        b: Builtin,
        name: &str,
        args: &'s [Arg],
        span: Span,
    ) -> Option<Vec<&'s Expr>> {
        // EN and ENO are handled around the call (`with_en_eno`).
        let en_eno = |a: &Arg| match &a.kind {
            ArgKind::Input { name, .. } | ArgKind::Output { name, .. } => {
                super::en_eno::is_en_eno(self.l.sym_name(name.sym))
            }
            ArgKind::Positional(_) => false,
        };
        let args: Vec<&'s Arg> = args.iter().filter(|a| !en_eno(a)).collect();
        let positional = args
            .iter()
            .all(|a| matches!(a.kind, ArgKind::Positional(_)));
        let mut out: Vec<Option<&'s Expr>> = Vec::new();
        if positional {
            out = args
                .iter()
                .map(|a| match &a.kind {
                    ArgKind::Positional(e) => Some(e),
                    _ => None,
                })
                .collect();
        } else {
            for &a in &args {
                match &a.kind {
                    ArgKind::Input { name: pn, value } => {
                        let pname = self.l.sym_name(pn.sym).to_string();
                        let idx = (0..args.len().max(3) + 1).find(|&i| b.param_name(i) == pname);
                        let Some(i) = idx else {
                            let n = self.l.text(pn.span).to_string();
                            self.l.error(
                                codes::E_NO_MEMBER,
                                format!("`{name}` has no parameter named `{n}`"),
                                pn.span,
                            );
                            return None;
                        };
                        if out.len() <= i {
                            out.resize(i + 1, None);
                        }
                        if out[i].is_some() {
                            self.l.error(
                                codes::E_ARG_COUNT,
                                "this parameter is given twice",
                                a.span,
                            );
                            return None;
                        }
                        out[i] = Some(value);
                    }
                    ArgKind::Positional(_) => {
                        self.l.error(
                            codes::E_ARG_COUNT,
                            "positional and named arguments cannot be mixed in a standard function call",
                            a.span,
                        );
                        return None;
                    }
                    ArgKind::Output { .. } => {
                        self.l.error(
                            codes::E_ARG_DIRECTION,
                            format!("`{name}` has no outputs besides its result"),
                            a.span,
                        );
                        return None;
                    }
                }
            }
        }
        let (min, max) = b.arity();
        if out.len() < min || out.len() > max || out.iter().any(|a| a.is_none()) {
            let want = if min == max {
                format!("{min}")
            } else if max == usize::MAX {
                format!("at least {min}")
            } else {
                format!("{min} to {max}")
            };
            let missing: Vec<String> = (0..out.len().max(min))
                .filter(|&i| out.get(i).is_none_or(|a| a.is_none()))
                .map(|i| b.param_name(i))
                .collect();
            let mut d = plcc_ir::diag::Diagnostic::error(
                codes::E_ARG_COUNT,
                format!("`{name}` takes {want} argument(s), {} given", args.len()),
                span,
            );
            if !missing.is_empty() && out.len() >= min {
                d = d.with_note(format!("missing: {}", missing.join(", ")));
            }
            self.l.diags.push(d);
            return None;
        }
        Some(out.into_iter().map(|a| a.expect("checked")).collect())
    }

    /// The input expressions of a standard function call in positional order (named
    /// ones put where their names say, EN and ENO left out), without reporting
    /// anything: `None` where an input is missing.
    fn infer_arg_order<'a>(&self, b: Builtin, args: &'a [Arg]) -> Vec<Option<&'a Expr>> {
        let mut out: Vec<Option<&'a Expr>> = Vec::new();
        for a in args {
            match &a.kind {
                ArgKind::Positional(e) => out.push(Some(e)),
                ArgKind::Input { name, value } => {
                    let n = self.l.sym_name(name.sym).to_ascii_uppercase();
                    if super::en_eno::is_en_eno(&n) {
                        continue;
                    }
                    let Some(i) = (0..args.len() + 3).find(|&i| b.param_name(i) == n) else {
                        out.push(None);
                        continue;
                    };
                    if out.len() <= i {
                        out.resize(i + 1, None);
                    }
                    out[i] = Some(value);
                }
                ArgKind::Output { .. } => {}
            }
        }
        out
    }

    /// The result type of a standard function call, without emitting anything.
    pub(super) fn builtin_infer(&mut self, b: Builtin, args: &[Arg]) -> Ty {
        let args = self.infer_arg_order(b, args);
        let arg_ty = |cx: &mut Self, i: usize| -> Ty {
            match args.get(i) {
                Some(Some(e)) => cx.infer(e),
                _ => Ty::Error,
            }
        };
        if super::selection::is_selection(b) {
            let tys: Vec<Ty> = (0..args.len()).map(|i| arg_ty(self, i)).collect();
            if let Some(t) = super::selection::string_selection_type(&tys) {
                return t;
            }
        }
        use Builtin::*;
        match b {
            Convert { to, .. } => Ty::Elem(to),
            // On an untyped literal these give an untyped result, which takes its type
            // from the context as a literal would (see `builtin_call`).
            Trunc => match arg_ty(self, 0) {
                Ty::Elem(ElemType::LReal) => Ty::Elem(ElemType::LInt),
                t if t.is_literal() => Ty::AnyInt,
                _ => Ty::DINT,
            },
            Math(_) => match arg_ty(self, 0) {
                Ty::AnyInt => Ty::AnyReal,
                t => t,
            },
            Abs | Not | Move => arg_ty(self, 0),
            Expt => {
                // As emitted: an integer base with a real exponent computes in the
                // exponent's type (LREAL for a literal, unless the base is a literal
                // too: then both follow the context).
                let (base, exp) = (arg_ty(self, 0), arg_ty(self, 1));
                if base == Ty::AnyInt && exp == Ty::AnyReal {
                    Ty::AnyReal
                } else if !base.is_real() && exp.is_real() {
                    concretize(exp, None)
                } else {
                    base
                }
            }
            Shift(_) => arg_ty(self, 0),
            Compare(_) => Ty::BOOL,
            // The data inputs' common type, as `builtin_call` emits them
            // (`MUX(k, 7, x_ulint)` is a ULINT, not an untyped literal).
            Sel | Mux | Limit => {
                let from = if b == Limit { 0 } else { 1 };
                let mut t = arg_ty(self, from);
                for i in from + 1..args.len() {
                    let u = arg_ty(self, i);
                    t = unify(t, u).unwrap_or(Ty::Error);
                }
                t
            }
            TimeOp(_, e) => Ty::Elem(e),
            Clock => Ty::TIME,
            Stl(_) => arg_ty(self, 0),
            Str(f) => {
                let mut at = arg_ty;
                self.string_fn_infer(f, &mut at, args.len())
            }
            SizeOf => Ty::AnyInt,
            Date(f) => f.result(),
            Bcd(f) => f.result(),
            Ref { pointer } => match arg_ty(self, 0) {
                Ty::Error => Ty::Error,
                t => Ty::Ref(self.l.types.reference(crate::types::RefTy {
                    iface: None,
                    target: t,
                    tag: None,
                    pointer,
                    auto: false,
                })),
            },
            Arith(_) | Logic(_) | Max | Min => {
                if let Arith(op @ (Op::Add | Op::Sub | Op::Mul | Op::Div)) = b {
                    let tys: Vec<Ty> = (0..args.len()).map(|i| arg_ty(self, i)).collect();
                    if tys.iter().any(|&t| super::dates::is_time_or_date(t)) {
                        // Table 30: two inputs, typed as the operator types them.
                        return match tys[..] {
                            [l, r] => super::dates::time_fn_type(op, l, r).unwrap_or(Ty::Error),
                            _ => Ty::Error,
                        };
                    }
                }
                let mut t = arg_ty(self, 0);
                for i in 1..args.len() {
                    let u = arg_ty(self, i);
                    t = unify(t, u).unwrap_or(Ty::Error);
                }
                t
            }
        }
    }

    /// Emits a standard function call.
    pub(super) fn builtin_call(
        &mut self,
        b: Builtin,
        args: &'s [Arg],
        want: Option<Ty>,
        span: Span,
    ) -> Option<Val> {
        let name = self
            .l
            .text(span)
            .split('(')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_uppercase();
        let xs = self.builtin_args(b, &name, args, span)?;
        match b {
            Builtin::Ref { pointer } => return self.ref_of(xs[0], &name, pointer),
            Builtin::SizeOf => return self.size_of(xs[0], want, span),
            _ => {}
        }
        for x in &xs {
            let t = self.infer(x);
            if matches!(t, Ty::Struct(_) | Ty::Array(_) | Ty::Fb(_)) {
                return self.bad_arg(&name, "elementary values", t, x.span);
            }
        }
        use Builtin::*;
        if super::selection::is_selection(b) && self.selects_strings(b, &xs) {
            return self.string_selection(b, &xs, &name);
        }
        if let Arith(op @ (Op::Add | Op::Sub | Op::Mul | Op::Div)) = b {
            if xs.iter().any(|x| {
                let t = self.infer(x);
                super::dates::is_time_or_date(t)
            }) {
                return self.time_arith_fn(op, &xs, &name, want, span);
            }
        }
        match b {
            Clock => {
                let v = self.b.intrinsic(Intrinsic::ClockMs, vec![])?;
                Some(Val { v, ty: Ty::TIME })
            }
            Stl(op) => self.stl_op(op, &xs, want, &name),
            Str(f) => self.string_fn_call(f, &xs, &name, want),
            Ref { .. } | SizeOf => None,
            Date(f) => self.date_fn_call(f, &xs),
            Bcd(f) => self.bcd_call(f, xs[0], &name),
            Convert { from, to, trunc } => self.conversion_call(xs[0], from, to, trunc, &name),
            Trunc => {
                let literal = self.infer(xs[0]).is_literal();
                let x = self.real_arg(xs[0], &name, None)?;
                let to = match want {
                    // An untyped result (`TRUNC(2.5)`) takes the integer or bit-string
                    // type the context wants, as an integer literal would.
                    Some(w @ Ty::Elem(we)) if literal && w.is_int_like() => we,
                    _ if x.ty == Ty::Elem(ElemType::LReal) && !literal => ElemType::LInt,
                    _ => ElemType::DInt,
                };
                let op = if to.is_signed() {
                    ConvOp::FToSi
                } else {
                    ConvOp::FToUi
                };
                let v = self.b.convert(op, to.ir_type(), x.v);
                Some(Val {
                    v,
                    ty: Ty::Elem(to),
                })
            }
            Abs => {
                let x = self.emit(xs[0], want);
                match x.ty {
                    t if t.is_real() => Some(Val {
                        v: self.b.unary(UnaryOp::Fabs, x.v),
                        ty: t,
                    }),
                    t if t.is_signed() && t.elem().is_some_and(|e| e.is_integer()) => Some(Val {
                        v: self.b.unary(UnaryOp::Iabs, x.v),
                        ty: t,
                    }),
                    t if t.is_int_like() => Some(x),
                    Ty::Error => None,
                    t => self.bad_arg(&name, "a number", t, xs[0].span),
                }
            }
            Math(op) => {
                let x = self.real_arg(xs[0], &name, want)?;
                Some(Val {
                    v: self.b.unary(op, x.v),
                    ty: x.ty,
                })
            }
            Expt => {
                let x = self.emit(xs[0], want);
                if x.ty == Ty::Error {
                    return None;
                }
                if !x.ty.is_numeric() {
                    return self.bad_arg(&name, "a number", x.ty, xs[0].span);
                }
                // A real literal exponent of a real base takes the base's type (one
                // rounding, straight to REAL).
                let exp_want = (x.ty.is_real() && self.infer(xs[1]) == Ty::AnyReal).then_some(x.ty);
                let n = self.emit(xs[1], exp_want);
                let x = if x.ty.is_real() || !n.ty.is_real() {
                    x
                } else {
                    // An integer base with a real exponent: compute in the exponent's type.
                    let (Some(f), Some(t)) = (x.ty.elem(), n.ty.elem()) else {
                        return None;
                    };
                    Val {
                        v: self.convert(x.v, f, t),
                        ty: n.ty,
                    }
                };
                let e = x.ty.elem()?;
                let v = if e.is_real() {
                    let nv = match n.ty.elem() {
                        Some(ne) if ne.is_real() || ne.is_integer() => self.convert(n.v, ne, e),
                        _ => return self.bad_arg(&name, "a number", n.ty, xs[1].span),
                    };
                    self.b.binary(BinaryOp::Fpow, x.v, nv)
                } else {
                    let ne =
                        n.ty.elem()
                            .filter(|ne| ne.is_integer() || ne.is_bit_string());
                    let Some(ne) = ne else {
                        return self.bad_arg(&name, "an integer exponent", n.ty, xs[1].span);
                    };
                    let exp = self.convert(n.v, ne, ElemType::LInt);
                    let f = self.l.ipow_helper(e.ir_type());
                    self.b.call(f, Some(e.ir_type()), vec![x.v, exp])?
                };
                Some(Val { v, ty: x.ty })
            }
            Arith(op) | Logic(op) => {
                let t = self.common_type(&xs, want, &name)?;
                if matches!(b, Logic(_)) && !(t == Ty::BOOL || t.is_int_like()) {
                    return self.bad_arg(&name, "BOOL or a bit string", t, span);
                }
                if matches!(b, Arith(Op::Mod)) && !t.is_int_like() {
                    return self.bad_arg(&name, "an integer", t, span);
                }
                if matches!(b, Arith(_)) && !t.is_numeric() {
                    return self.bad_arg(&name, "a number", t, span);
                }
                let e = t.elem()?;
                let mut acc = self.emit_as(xs[0], t);
                for x in &xs[1..] {
                    let y = self.emit_as(x, t);
                    acc = self.arith(op, acc, y, e);
                }
                Some(Val { v: acc, ty: t })
            }
            Compare(op) => {
                if xs.iter().any(|x| matches!(self.infer(x), Ty::Str(_))) {
                    return self.compare_string_args(op, &xs);
                }
                let t = self.common_type(&xs, None, &name)?;
                let e = match t {
                    Ty::Enum(_, base) if matches!(op, Op::Eq | Op::Ne) => base,
                    Ty::Elem(e) => e,
                    t => return self.bad_arg(&name, "numbers or other elementary values", t, span),
                };
                let vals: Vec<Value> = xs.iter().map(|x| self.emit_as(x, t)).collect();
                let mut acc: Option<Value> = None;
                for w in vals.windows(2) {
                    let c = self.arith(op, w[0], w[1], e);
                    acc = Some(match acc {
                        Some(a) => self.b.binary(BinaryOp::Band, a, c),
                        None => c,
                    });
                }
                Some(Val {
                    v: acc?,
                    ty: Ty::BOOL,
                })
            }
            Not => {
                let x = self.emit(xs[0], want);
                match x.ty {
                    t if t == Ty::BOOL || t.is_int_like() => Some(Val {
                        v: self.b.unary(UnaryOp::Bnot, x.v),
                        ty: t,
                    }),
                    Ty::Error => None,
                    t => self.bad_arg(&name, "BOOL or a bit string", t, xs[0].span),
                }
            }
            Move => {
                let x = self.emit(xs[0], want);
                (x.ty != Ty::Error).then_some(x)
            }
            Shift(op) => {
                let x = self.emit(xs[0], want);
                let e = match x.ty.elem() {
                    Some(e) if x.ty.is_int_like() => e,
                    _ if x.ty == Ty::Error => return None,
                    _ => {
                        return self.bad_arg(&name, "a bit string or an integer", x.ty, xs[0].span)
                    }
                };
                let n = self.emit(xs[1], Some(Ty::Elem(ElemType::UDInt)));
                let Some(ne) = n
                    .ty
                    .elem()
                    .filter(|ne| ne.is_integer() || (ne.is_bit_string() && *ne != ElemType::Bool))
                else {
                    if n.ty == Ty::Error {
                        return None;
                    }
                    return self.bad_arg(&name, "an integer shift count", n.ty, xs[1].span);
                };
                // The count is read unsigned at the value's width; a wider count that
                // does not fit saturates to the width (so a shift gives 0), or is
                // reduced modulo the width for a rotation.
                let t = e.ir_type();
                let rotate = matches!(op, BinaryOp::Rotl | BinaryOp::Rotr);
                let count = self.shift_count(n.v, ne, t, rotate);
                Some(Val {
                    v: self.b.binary(op, x.v, count),
                    ty: x.ty,
                })
            }
            Sel => {
                let g = self.emit_as(xs[0], Ty::BOOL);
                let t = self.common_type(&xs[1..], want, &name)?;
                let a = self.emit_as(xs[1], t);
                let c = self.emit_as(xs[2], t);
                Some(Val {
                    v: self.b.select(g, c, a),
                    ty: t,
                })
            }
            Max | Min => {
                let t = self.common_type(&xs, want, &name)?;
                let Some(e) = t.elem() else {
                    return self.bad_arg(&name, "elementary values", t, span);
                };
                let mut acc = self.emit_as(xs[0], t);
                for x in &xs[1..] {
                    let y = self.emit_as(x, t);
                    let op = if b == Max { Op::Gt } else { Op::Lt };
                    let c = self.arith(op, y, acc, e);
                    acc = self.b.select(c, y, acc);
                }
                Some(Val { v: acc, ty: t })
            }
            Limit => {
                let t = self.common_type(&xs, want, &name)?;
                let Some(e) = t.elem() else {
                    return self.bad_arg(&name, "elementary values", t, span);
                };
                let mn = self.emit_as(xs[0], t);
                let x = self.emit_as(xs[1], t);
                let mx = self.emit_as(xs[2], t);
                let below = self.arith(Op::Lt, x, mn, e);
                let lo = self.b.select(below, mn, x);
                let above = self.arith(Op::Gt, lo, mx, e);
                Some(Val {
                    v: self.b.select(above, mx, lo),
                    ty: t,
                })
            }
            Mux => {
                let k = self.mux_selector(xs[0], &name)?;
                let t = self.common_type(&xs[1..], want, &name)?;
                let vals: Vec<Value> = xs[1..].iter().map(|x| self.emit_as(x, t)).collect();
                Some(Val {
                    v: self.mux_pick(k, &vals),
                    ty: t,
                })
            }
            TimeOp(op, e) => {
                let t = Ty::Elem(e);
                let x = self.emit_as(xs[0], t);
                let v = if matches!(op, Op::Add | Op::Sub) {
                    let y = self.emit_as(xs[1], t);
                    self.arith(op, x, y, e)
                } else {
                    let n = self.emit(xs[1], None);
                    match n.ty {
                        Ty::Error => return None,
                        nt if nt.is_integer() || nt.is_real() => {}
                        nt => return self.bad_arg(&name, "a number", nt, xs[1].span),
                    }
                    self.scale_duration(op, x, e, n)
                };
                Some(Val { v, ty: t })
            }
        }
    }

    /// The STL's INC, DEC, SWAP, SET and CLR on an integer or bit string.
    fn stl_op(&mut self, op: StlOp, xs: &[&'s Expr], want: Option<Ty>, name: &str) -> Option<Val> {
        let name = name.trim_start_matches("__STL_");
        let x = self.emit(xs[0], want);
        let e = match x.ty.elem() {
            Some(e) if x.ty.is_int_like() => e,
            _ if x.ty == Ty::Error => return None,
            _ => return self.bad_arg(name, "an integer or a bit string", x.ty, xs[0].span),
        };
        let t = e.ir_type();
        let v =
            match op {
                StlOp::Inc | StlOp::Dec => {
                    let one = self.b.iconst(t, 1);
                    let bop = if op == StlOp::Inc {
                        BinaryOp::Iadd
                    } else {
                        BinaryOp::Isub
                    };
                    self.b.binary(bop, x.v, one)
                }
                StlOp::Swap => {
                    let half = self.b.iconst(t, t.bits() as i64 / 2);
                    self.b.binary(BinaryOp::Rotl, x.v, half)
                }
                StlOp::Set | StlOp::Clr => {
                    let n = self.emit(xs[1], Some(Ty::Elem(ElemType::UDInt)));
                    let Some(ne) = n.ty.elem().filter(|ne| {
                        ne.is_integer() || (ne.is_bit_string() && *ne != ElemType::Bool)
                    }) else {
                        if n.ty == Ty::Error {
                            return None;
                        }
                        return self.bad_arg(name, "an integer bit number", n.ty, xs[1].span);
                    };
                    let count = self.shift_count(n.v, ne, t, false);
                    let one = self.b.iconst(t, 1);
                    let mask = self.b.binary(BinaryOp::Ishl, one, count);
                    if op == StlOp::Set {
                        self.b.binary(BinaryOp::Bor, x.v, mask)
                    } else {
                        let inv = self.b.unary(UnaryOp::Bnot, mask);
                        self.b.binary(BinaryOp::Band, x.v, inv)
                    }
                }
            };
        Some(Val { v, ty: x.ty })
    }

    /// A shift count converted to type `t`: saturated to `t`'s width when wider (for
    /// a shift), or reduced modulo the width (for a rotation, `rotate`).
    fn shift_count(&mut self, n: Value, ne: ElemType, t: Type, rotate: bool) -> Value {
        // A negative count reads as a huge unsigned one, so the shift gives 0.
        let nt = ne.ir_type();
        if nt.bits() <= t.bits() {
            return if nt == t {
                n
            } else {
                self.b.convert(ConvOp::Uext, t, n)
            };
        }
        if rotate {
            // The widths are powers of two: the low bits are the count modulo the
            // width, and they survive the truncation.
            let mask = self.b.iconst(nt, t.bits() as i64 - 1);
            let m = self.b.binary(BinaryOp::Band, n, mask);
            return self.b.convert(ConvOp::Itrunc, t, m);
        }
        let width = self.b.iconst(nt, t.bits() as i64);
        let big = self.b.icmp(IntCC::Uge, n, width);
        let sat = self.b.select(big, width, n);
        self.b.convert(ConvOp::Itrunc, t, sat)
    }

    /// The common type of several arguments (literals adapt; `want` types literal-only
    /// lists).
    fn common_type(&mut self, xs: &[&'s Expr], want: Option<Ty>, name: &str) -> Option<Ty> {
        let mut t = Ty::AnyInt;
        let mut first = true;
        let tys: Vec<Ty> = xs.iter().map(|x| self.infer(x)).collect();
        // `AND(b, 1)`, `SEL(g, 0, 1)` for a BOOL: the 0s and 1s are BOOL literals.
        let bools = super::literals::bool_digit_args(xs, &tys, want);
        for (x, &u) in xs.iter().zip(&tys) {
            let u = if bools { Ty::BOOL } else { u };
            let next = if first { Some(u) } else { unify(t, u) };
            first = false;
            match next {
                Some(n) => t = n,
                None => {
                    let (a, b) = (self.l.ty_name(t), self.l.ty_name(u));
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!("the arguments of `{name}` must have one type: {a} and {b} differ"),
                        x.span,
                    );
                    for y in xs {
                        let _ = self.emit(y, None);
                    }
                    return None;
                }
            }
        }
        if t == Ty::Error {
            for y in xs {
                let _ = self.emit(y, None);
            }
            return None;
        }
        Some(concretize(t, want))
    }

    /// An argument that must be REAL or LREAL. An untyped literal takes the type
    /// the context `want`s for the function's result when that is REAL or LREAL (so
    /// `SQRT(2.0) * r` computes in REAL, as `1.414 * r` would), else LREAL.
    fn real_arg(&mut self, e: &'s Expr, name: &str, want: Option<Ty>) -> Option<Val> {
        let t = self.infer(e);
        let target = if t.is_literal() {
            match want {
                Some(w @ Ty::Elem(we)) if we.is_real() => w,
                _ => Ty::Elem(ElemType::LReal),
            }
        } else {
            t
        };
        let x = self.emit(e, Some(target));
        match x.ty {
            t if t.is_real() => Some(x),
            Ty::Error => None,
            t => self.bad_arg(name, "REAL or LREAL", t, e.span),
        }
    }

    pub(super) fn bad_arg(&mut self, name: &str, wants: &str, got: Ty, span: Span) -> Option<Val> {
        let g = self.l.ty_name(got);
        self.l.error(
            codes::E_TYPE_MISMATCH,
            format!("`{name}` needs {wants}, not {g}"),
            span,
        );
        None
    }

    /// `X_TO_Y(v)` and friends.
    fn conversion_call(
        &mut self,
        e: &'s Expr,
        from: Option<ElemType>,
        to: ElemType,
        trunc: bool,
        name: &str,
    ) -> Option<Val> {
        let inferred = self.infer(e);
        let want = match from {
            Some(f) => Ty::Elem(f),
            None => concretize(inferred, None),
        };
        let x = self.emit(e, Some(want));
        if x.ty == Ty::Error {
            return None;
        }
        let Some(xe) = x.ty.elem() else {
            return self.bad_arg(name, "an elementary value", x.ty, e.span);
        };
        // CODESYS converts from whatever integer or bit string it is given.
        let loose = |t: ElemType| t != ElemType::Bool && (t.is_integer() || t.is_bit_string());
        let from = match from {
            Some(f) if self.l.codesys && f != xe && loose(f) && loose(xe) => Some(xe),
            f => f,
        };
        let src = match from {
            Some(f) if f != xe => {
                if crate::types::implicit(xe, f) {
                    self.convert(x.v, xe, f)
                } else {
                    let d = plcc_ir::diag::Diagnostic::error(
                        codes::E_TYPE_MISMATCH,
                        format!(
                            "`{name}` converts from {}, not from {}",
                            f.name(),
                            xe.name()
                        ),
                        e.span,
                    );
                    self.l.diags.push(d);
                    return None;
                }
            }
            _ => x.v,
        };
        let from = from.unwrap_or(xe);
        let dated = |t: ElemType| super::dates::is_date(Ty::Elem(t));
        if dated(from) || dated(to) {
            return match self.date_conversion(src, from, to) {
                Some(v) => Some(Val {
                    v,
                    ty: Ty::Elem(to),
                }),
                None => {
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!(
                            "there is no conversion from {} to {}",
                            from.name(),
                            to.name()
                        ),
                        e.span,
                    );
                    None
                }
            };
        }
        let convertible = |t: ElemType| {
            t != ElemType::Ref
                && !matches!(
                    t,
                    ElemType::Char
                        | ElemType::WChar
                        | ElemType::Date
                        | ElemType::Tod
                        | ElemType::Dt
                )
        };
        if !convertible(from) || !convertible(to) {
            self.l.error(
                codes::E_UNSUPPORTED,
                format!("not supported yet: `{name}`"),
                e.span,
            );
            return None;
        }
        if trunc {
            if !from.is_real() || !(to.is_integer() || to.is_bit_string()) || to == ElemType::Bool {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("`{name}` truncates a REAL or LREAL to an integer"),
                    e.span,
                );
                return None;
            }
            let op = if to.is_signed() {
                ConvOp::FToSi
            } else {
                ConvOp::FToUi
            };
            let v = self.b.convert(op, to.ir_type(), src);
            return Some(Val {
                v,
                ty: Ty::Elem(to),
            });
        }
        let v = self.convert(src, from, to);
        Some(Val {
            v,
            ty: Ty::Elem(to),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_standard_function_is_one() {
        for (name, signature) in STANDARD_FUNCTIONS {
            assert!(
                Builtin::lookup(name).is_some(),
                "{name} is not a standard function"
            );
            assert!(signature.starts_with(&format!("{name}(")), "{signature}");
        }
    }
}
