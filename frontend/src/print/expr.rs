//! Expressions and literals.

use super::Printer;
use crate::ast::*;
use plcc_ir::value::{format_string_literal, PlcValue};
use plcc_ir::ElemType;

/// Prefix operators bind tighter than any binary one.
const UNARY: u8 = 9;
/// The base of `.member`, `[i]`, `^` and calls binds tighter still.
const POSTFIX: u8 = 10;

const NS_PER_DAY: i128 = 86_400_000_000_000;

impl Printer<'_> {
    /// Prints `e` where an operator binding at least `min` is expected: with
    /// parentheses if `e` binds less tightly.
    pub(super) fn expression(&mut self, e: &Expr, min: u8) {
        match &e.kind {
            ExprKind::Binary(op, a, b) => {
                let p = op.binding();
                let parens = p < min || self.all_parens();
                if parens {
                    self.push("(");
                }
                self.expression(a, p);
                self.push(" ");
                self.push(op.symbol());
                self.push(" ");
                self.expression(b, p + 1);
                if parens {
                    self.push(")");
                }
            }
            ExprKind::Unary(op, a) => {
                let parens = UNARY < min || self.all_parens();
                if parens {
                    self.push("(");
                }
                self.push(match op {
                    UnaryOp::Not => "NOT ",
                    UnaryOp::Neg => "-",
                    UnaryOp::Plus => "+",
                });
                // `- -5` would read as one token pair too, but `(-5)` is plainer.
                let signed = matches!(&a.kind, ExprKind::Unary(..)) && !self.all_parens()
                    || matches!(&a.kind, ExprKind::Literal(l) if literal_is_signed(l));
                if signed {
                    self.push("(");
                    self.expression(a, 0);
                    self.push(")");
                } else {
                    self.expression(a, UNARY);
                }
                if parens {
                    self.push(")");
                }
            }
            ExprKind::Literal(l) => {
                let parens = min > UNARY && literal_is_signed(l);
                if parens {
                    self.push("(");
                }
                let s = literal(l, |id| self.name(id));
                self.push(&s);
                if parens {
                    self.push(")");
                }
            }
            ExprKind::Name(id) => self.push_name(id),
            ExprKind::Member(b, m) => {
                self.expression(b, POSTFIX);
                self.push(".");
                self.push_name(m);
            }
            ExprKind::Bit(b, n) => {
                self.expression(b, POSTFIX);
                self.push(".");
                self.expression(n, POSTFIX);
            }
            ExprKind::Partial(b, size, n) => {
                self.expression(b, POSTFIX);
                let letter = match size {
                    1 => 'X',
                    8 => 'B',
                    16 => 'W',
                    32 => 'D',
                    _ => 'L',
                };
                self.push(&format!(".%{letter}{n}"));
            }
            ExprKind::Index(b, ix) => {
                self.expression(b, POSTFIX);
                self.push("[");
                for (k, i) in ix.iter().enumerate() {
                    if k > 0 {
                        self.push(", ");
                    }
                    self.expression(i, 0);
                }
                self.push("]");
            }
            ExprKind::Deref(b) => {
                self.expression(b, POSTFIX);
                self.push("^");
            }
            ExprKind::EnumValue { ty, value } => {
                self.push_name(ty);
                self.push("#");
                self.push_name(value);
            }
            ExprKind::DirectAddress(a) => self.push(a),
            ExprKind::Call { callee, args } => {
                self.expression(callee, POSTFIX);
                self.push("(");
                self.arguments(args);
                self.push(")");
            }
            ExprKind::Paren(a) => {
                self.push("(");
                self.expression(a, 0);
                self.push(")");
            }
            // The instruction that uses the value is not part of the ST it reads as.
            ExprKind::UsedBy { value, .. } => self.expression(value, min),
        }
    }

    /// A call's arguments, separated by `, `.
    pub(super) fn arguments(&mut self, args: &[Arg]) {
        for (k, a) in args.iter().enumerate() {
            if k > 0 {
                self.push(", ");
            }
            match &a.kind {
                ArgKind::Positional(v) => self.expression(v, 0),
                ArgKind::Input { name, value } => {
                    self.push_name(name);
                    self.push(" := ");
                    self.expression(value, 0);
                }
                ArgKind::Output {
                    name,
                    negated,
                    target,
                } => {
                    if *negated {
                        self.push("NOT ");
                    }
                    self.push_name(name);
                    self.push(" =>");
                    if let Some(t) = target {
                        self.push(" ");
                        self.expression(t, 0);
                    }
                }
            }
        }
    }
}

/// Whether the literal's text starts with a sign.
fn literal_is_signed(l: &Literal) -> bool {
    l.type_prefix.is_none()
        && match &l.kind {
            LiteralKind::Int(v) => *v < 0,
            LiteralKind::Real(t) => t.starts_with(['-', '+']),
            _ => false,
        }
}

/// A literal in its canonical spelling; `name` spells a type prefix.
pub(super) fn literal(l: &Literal, name: impl Fn(&Ident) -> String) -> String {
    let (kind_prefix, body) = match &l.kind {
        LiteralKind::Int(v) => (None, v.to_string()),
        LiteralKind::Real(t) => (None, t.to_string()),
        LiteralKind::Bool(b) => (None, if *b { "TRUE" } else { "FALSE" }.to_string()),
        LiteralKind::Duration { ns, long } => (Some(if *long { "LT" } else { "T" }), duration(*ns)),
        LiteralKind::Date { days, long } => {
            let v = PlcValue::from_i64(ElemType::LDate, (*days as i128 * NS_PER_DAY) as i64);
            (Some(if *long { "LD" } else { "D" }), after_hash(v))
        }
        LiteralKind::TimeOfDay { ns, long } => {
            let v = PlcValue::from_i64(ElemType::LTod, *ns);
            (Some(if *long { "LTOD" } else { "TOD" }), after_hash(v))
        }
        LiteralKind::DateTime { ns, long } => {
            let v = PlcValue::from_i64(ElemType::LDt, *ns as i64);
            (Some(if *long { "LDT" } else { "DT" }), after_hash(v))
        }
        LiteralKind::String { wide, units } => (None, format_string_literal(units, *wide)),
    };
    match (&l.type_prefix, kind_prefix) {
        (Some(t), _) => format!("{}#{body}", name(t)),
        (None, Some(p)) => format!("{p}#{body}"),
        (None, None) => body,
    }
}

/// The text of a value's literal after its `#`.
fn after_hash(v: PlcValue) -> String {
    let s = v.to_string();
    match s.split_once('#') {
        Some((_, rest)) => rest.to_string(),
        None => s,
    }
}

/// A duration in nanoseconds as `1d2h3m4s5ms6us7ns` (zero parts left out; `0s`).
fn duration(ns: i128) -> String {
    if ns == 0 {
        return "0s".to_string();
    }
    let mut s = String::new();
    if ns < 0 {
        s.push('-');
    }
    let mut rest = ns.unsigned_abs();
    for (unit, size) in [
        ("d", NS_PER_DAY as u128),
        ("h", 3_600_000_000_000),
        ("m", 60_000_000_000),
        ("s", 1_000_000_000),
        ("ms", 1_000_000),
        ("us", 1_000),
        ("ns", 1),
    ] {
        if rest >= size {
            s.push_str(&format!("{}{unit}", rest / size));
            rest %= size;
        }
    }
    s
}
