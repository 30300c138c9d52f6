//! The types of the values on the wires of a graphical body, where the lowering must
//! know them: a function's result is kept in a variable of the POU (as the editors
//! keep it), which must be declared with a type.
//!
//! The type comes, as the editors infer it, from what the block is (a comparison is
//! BOOL, `INT_TO_REAL` is REAL, a project function has its return type, a function
//! block's outputs are declared), from what is wired to its inputs when the function
//! passes their type on (`ADD`, `SEL`, `LIMIT`...), and from what its result is wired
//! to (a variable, a block input, power flow).

use super::graph::{input_name, output_name, Graph, Src};
use super::xml::{Kind, Method, PouKind, Project, Section, Type, Var, VarGroup};
use std::sync::OnceLock;

/// What the POU can see: its variables, the globals, the project's POUs.
pub(crate) struct Scope<'a> {
    /// The project.
    pub project: &'a Project,
    /// The POU's variable groups.
    pub pou_vars: &'a [VarGroup],
    /// The globals of the configurations.
    pub globals: &'a [&'a Var],
}

/// A type as IEC text, if it is a simple one.
pub(crate) fn type_text(t: &Type) -> Option<String> {
    match t {
        Type::Named(n) => Some(n.value.clone()),
        Type::String { wide, len } => {
            let base = if *wide { "WSTRING" } else { "STRING" };
            Some(match len {
                Some(l) => format!("{base}[{}]", l.value),
                None => base.to_string(),
            })
        }
        _ => None,
    }
}

/// The type of a typed literal (`INT#5`, `T#5s`), or of TRUE and FALSE.
fn literal_type(s: &str) -> Option<String> {
    let u = s.trim().to_ascii_uppercase();
    if u == "TRUE" || u == "FALSE" {
        return Some("BOOL".into());
    }
    if u.starts_with('\'') {
        return Some("STRING".into());
    }
    let (prefix, _) = u.split_once('#')?;
    Some(match prefix {
        "T" | "TIME" => "TIME".into(),
        "LT" | "LTIME" => "LTIME".into(),
        "D" | "DATE" => "DATE".into(),
        "TOD" | "TIME_OF_DAY" => "TOD".into(),
        "DT" | "DATE_AND_TIME" => "DT".into(),
        p if p.bytes().all(|b| b.is_ascii_alphabetic()) => p.to_string(),
        _ => return None,
    })
}

/// The inputs and outputs of the standard function blocks, read from plcc's own
/// declarations of them: (block, pin, type, is an output).
fn std_fb_pins() -> &'static [(String, String, String, bool)] {
    static PINS: OnceLock<Vec<(String, String, String, bool)>> = OnceLock::new();
    PINS.get_or_init(|| {
        let text = include_str!("../stdlib/std_fbs.st");
        let mut out = Vec::new();
        let mut fb = String::new();
        let mut section: Option<bool> = None;
        for line in text.lines() {
            let l = line.trim();
            if let Some(rest) = l.strip_prefix("FUNCTION_BLOCK ") {
                fb = rest.trim().to_ascii_uppercase();
                continue;
            }
            for part in l.split_inclusive(';') {
                let mut p = part.trim();
                for (kw, out_sec) in [("VAR_INPUT", Some(false)), ("VAR_OUTPUT", Some(true))] {
                    if let Some(r) = p.strip_prefix(kw) {
                        section = out_sec;
                        p = r.trim();
                    }
                }
                if let Some(r) = p.strip_prefix("VAR") {
                    if r.is_empty() || r.starts_with(' ') {
                        section = None;
                    }
                }
                if p.starts_with("END_VAR") {
                    section = None;
                    continue;
                }
                let (Some(is_out), Some((names, ty))) = (section, p.split_once(':')) else {
                    continue;
                };
                let ty = ty
                    .split(":=")
                    .next()
                    .unwrap_or("")
                    .trim()
                    .trim_end_matches(';');
                for n in names.split(',') {
                    out.push((
                        fb.clone(),
                        n.trim().to_ascii_uppercase(),
                        ty.trim().to_string(),
                        is_out,
                    ));
                }
            }
        }
        out
    })
}

impl Scope<'_> {
    /// The declared type of a variable of the POU or a global.
    fn declared(&self, name: &str) -> Option<&Type> {
        self.pou_vars
            .iter()
            .flat_map(|g| &g.vars)
            .chain(self.globals.iter().copied())
            .find(|v| v.name.value.eq_ignore_ascii_case(name))
            .map(|v| &v.ty)
    }

    /// The method a block calls whose type is `inst.M` (plcc's reading of a method
    /// call drawn as a block): `M` of the class of the variable `inst` (a function
    /// block of the project, through its bases, or an interface).
    pub(crate) fn method_call(&self, block: &str) -> Option<&Method> {
        let (inst, m) = block.rsplit_once('.')?;
        let Type::Named(class) = self.declared(inst.trim())? else {
            return None;
        };
        let m = m.trim();
        // The class and its bases, or the interface and those it extends (a few
        // levels at most: a circle is the lowering's error).
        let mut todo = vec![class.value.as_str()];
        for _ in 0..32 {
            let class = todo.pop()?;
            let same = |x: &&Method| x.name.value.eq_ignore_ascii_case(m);
            let project = self.project;
            if let Some(itf) = project
                .interfaces
                .iter()
                .find(|i| i.name.value.eq_ignore_ascii_case(class))
            {
                if let Some(x) = itf.methods.iter().find(same) {
                    return Some(x);
                }
                todo.extend(itf.extends.iter().map(|e| e.value.as_str()));
                continue;
            }
            if let Some(pou) = project
                .pous
                .iter()
                .find(|p| p.name.value.eq_ignore_ascii_case(class))
            {
                if let Some(x) = pou.oo.methods.iter().find(same) {
                    return Some(x);
                }
                todo.extend(pou.oo.extends.iter().map(|e| e.value.as_str()));
            }
        }
        None
    }

    /// The type of a pin of a block type (a function block or function of the project,
    /// a method called as `inst.M`, or a standard function block).
    pub(crate) fn pin_type(&self, block: &str, pin: &str, output: bool) -> Option<String> {
        if let Some(m) = self.method_call(block) {
            if output && is_result_pin(m, block, pin) {
                return m.ret.as_ref().and_then(type_text);
            }
            let wanted: &[Section] = if output {
                &[Section::Output, Section::InOut]
            } else {
                &[Section::Input, Section::InOut]
            };
            return m
                .groups
                .iter()
                .filter(|g| wanted.contains(&g.section))
                .flat_map(|g| &g.vars)
                .find(|v| v.name.value.eq_ignore_ascii_case(pin))
                .and_then(|v| type_text(&v.ty));
        }
        if let Some(p) = self
            .project
            .pous
            .iter()
            .find(|p| p.name.value.eq_ignore_ascii_case(block))
        {
            let wanted: &[Section] = if output {
                &[Section::Output, Section::InOut]
            } else {
                &[Section::Input, Section::InOut]
            };
            if output
                && p.kind == PouKind::Function
                && (pin.eq_ignore_ascii_case("OUT") || pin.is_empty())
            {
                if let Some(r) = &p.ret {
                    return type_text(r);
                }
            }
            return p
                .groups
                .iter()
                .filter(|g| wanted.contains(&g.section))
                .flat_map(|g| &g.vars)
                .find(|v| v.name.value.eq_ignore_ascii_case(pin))
                .and_then(|v| type_text(&v.ty));
        }
        let (b, p) = (block.to_ascii_uppercase(), pin.to_ascii_uppercase());
        std_fb_pins()
            .iter()
            .find(|(fb, n, _, o)| *fb == b && *n == p && *o == output)
            .map(|(_, _, t, _)| t.clone())
    }

    /// The type of a variable expression: a name, a member of an instance or a
    /// structure (`ton0.ET`, `s.x`), an array element, or a typed literal.
    pub(crate) fn expr_type(&self, expr: &str) -> Option<String> {
        let e = expr.trim();
        if let Some(t) = literal_type(e) {
            return Some(t);
        }
        let path: Vec<&str> = e.split('.').map(str::trim).collect();
        fn ident(s: &str) -> Option<&str> {
            let s = s.split('[').next().unwrap_or("").trim();
            (!s.is_empty()
                && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
                && !s.as_bytes()[0].is_ascii_digit())
            .then_some(s)
        }
        let first = ident(path[0])?;
        let mut ty = self.declared(first)?;
        if path[0].contains('[') {
            match ty {
                Type::Array { elem, .. } => ty = elem,
                _ => return None,
            }
        }
        let mut named: Option<String> = None;
        for member in &path[1..] {
            let m = ident(member)?;
            let owner = match named.take() {
                Some(n) => n,
                None => type_text(ty)?,
            };
            if let Some(t) = self.pin_type(&owner, m, true) {
                named = Some(t);
                continue;
            }
            // A member of a structure type of the project.
            let dt = self
                .project
                .types
                .iter()
                .find(|d| d.name.value.eq_ignore_ascii_case(&owner))?;
            let Type::Struct(fields) = &dt.ty else {
                return None;
            };
            let f = fields
                .iter()
                .find(|v| v.name.value.eq_ignore_ascii_case(m))?;
            named = Some(type_text(&f.ty)?);
        }
        named.or_else(|| type_text(ty))
    }
}

/// True if output `pin` of a block calling method `m` (as `block`, `inst.M`) is the
/// method's result: a method with a result gives it on the output named as the
/// method, as the block, `OUT`, or not named, or on any output that is none of
/// the method's outputs and in-outs.
pub(crate) fn is_result_pin(m: &Method, block: &str, pin: &str) -> bool {
    if m.ret.is_none() || pin.eq_ignore_ascii_case("ENO") {
        return false;
    }
    let p = pin.trim();
    p.is_empty()
        || p.eq_ignore_ascii_case("OUT")
        || p.eq_ignore_ascii_case(&m.name.value)
        || p.eq_ignore_ascii_case(block)
        || !m
            .groups
            .iter()
            .filter(|g| matches!(g.section, Section::Output | Section::InOut))
            .flat_map(|g| &g.vars)
            .any(|v| v.name.value.eq_ignore_ascii_case(p))
}

/// The standard functions whose result has the type of their (data) inputs.
pub(crate) fn passes_type(name: &str) -> bool {
    matches!(
        name,
        "ADD"
            | "SUB"
            | "MUL"
            | "DIV"
            | "MOD"
            | "MOVE"
            | "ABS"
            | "NEG"
            | "MIN"
            | "MAX"
            | "LIMIT"
            | "AND"
            | "OR"
            | "XOR"
            | "NOT"
            | "SHL"
            | "SHR"
            | "ROL"
            | "ROR"
            | "EXPT"
            | "SQRT"
            | "LN"
            | "LOG"
            | "EXP"
            | "SIN"
            | "COS"
            | "TAN"
            | "ASIN"
            | "ACOS"
            | "ATAN"
            | "SEL"
            | "MUX"
    )
}

/// Inputs that do not give the result's type (selectors, shift counts).
pub(crate) fn control_input(func: &str, pin: &str) -> bool {
    let p = pin.to_ascii_uppercase();
    p == "EN"
        || (func == "SEL" && p == "G")
        || (func == "MUX" && p == "K")
        || (matches!(func, "SHL" | "SHR" | "ROL" | "ROR") && p == "N")
        || (func == "EXPT" && p == "IN2")
}

/// The type of the value an output `s` puts on its wires, if it can be told.
pub(crate) fn source_type(g: &Graph, scope: &Scope, s: Src, depth: u32) -> Option<String> {
    if depth > 32 {
        return None;
    }
    match &g.elems[s.elem].kind {
        Kind::LeftRail | Kind::Contact { .. } | Kind::Coil { .. } => Some("BOOL".into()),
        Kind::InVariable { expr, .. } | Kind::InOutVariable { expr } => {
            scope.expr_type(&expr.value)
        }
        Kind::Block { .. } => output_type(g, scope, s.elem, s.port, depth + 1),
        _ => None,
    }
}

/// The type of output `port` of block `e`.
pub(crate) fn output_type(
    g: &Graph,
    scope: &Scope,
    e: usize,
    port: usize,
    depth: u32,
) -> Option<String> {
    let Kind::Block { ty, instance, .. } = &g.elems[e].kind else {
        return None;
    };
    let pin = output_name(&g.elems[e].kind, port).unwrap_or("");
    if pin.eq_ignore_ascii_case("ENO") {
        return Some("BOOL".into());
    }
    if instance.is_some() {
        return scope.pin_type(&ty.value, pin, true);
    }
    let name = ty.value.to_ascii_uppercase();
    if let Some(t) = scope.pin_type(&ty.value, pin, true) {
        return Some(t);
    }
    if matches!(name.as_str(), "GT" | "GE" | "EQ" | "NE" | "LE" | "LT") {
        return Some("BOOL".into());
    }
    if let Some((_, to)) = name.split_once("_TO_") {
        return Some(to.to_string());
    }
    match name.as_str() {
        "TRUNC" => return Some("DINT".into()),
        "LEN" | "FIND" => return Some("INT".into()),
        "CONCAT" | "LEFT" | "RIGHT" | "MID" | "INSERT" | "DELETE" | "REPLACE" => {
            return Some("STRING".into())
        }
        _ => {}
    }
    // Time and date arithmetic: SUB of two dates, times of day or dates and times is
    // a TIME; ADD and SUB of a TIME to one of those keep its type.
    if name == "SUB" {
        let ins: Vec<Option<String>> = g.ins[e]
            .iter()
            .enumerate()
            .filter(|(p, _)| !control_input(&name, input_name(&g.elems[e].kind, *p).unwrap_or("")))
            .map(|(_, srcs)| {
                srcs.first()
                    .and_then(|&s| source_type(g, scope, s, depth + 1))
            })
            .collect();
        let date = |t: &str| {
            matches!(
                t.to_ascii_uppercase().as_str(),
                "DATE" | "TOD" | "TIME_OF_DAY" | "DT" | "DATE_AND_TIME" | "LDATE" | "LTOD" | "LDT"
            )
        };
        // IEC's SUB has no overload subtracting a date from a TIME: a date as the
        // second input means two dates, a TIME.
        if let [_, Some(b)] = ins.as_slice() {
            if date(b) {
                let long = b.to_ascii_uppercase().starts_with('L');
                return Some(if long { "LTIME" } else { "TIME" }.into());
            }
        }
        // A date minus something unknown is a TIME or a date: what the result is
        // wired to tells.
        if ins.iter().flatten().any(|t| date(t)) && ins.iter().any(Option::is_none) {
            if let Some(t) = consumer_type(g, scope, e, port) {
                return Some(t);
            }
        }
    }
    if passes_type(&name) {
        let k = &g.elems[e].kind;
        for (p, srcs) in g.ins[e].iter().enumerate() {
            if control_input(&name, input_name(k, p).unwrap_or("")) {
                continue;
            }
            for &s in srcs {
                if let Some(t) = source_type(g, scope, s, depth + 1) {
                    return Some(t);
                }
            }
        }
    }
    consumer_type(g, scope, e, port)
}

/// The type of output `port` of block `e` from what it is wired to.
fn consumer_type(g: &Graph, scope: &Scope, e: usize, port: usize) -> Option<String> {
    for &(c, cp) in &g.outs[e][port] {
        match &g.elems[c].kind {
            Kind::Contact { .. } | Kind::Coil { .. } | Kind::Jump { .. } | Kind::Return => {
                return Some("BOOL".into())
            }
            Kind::OutVariable { expr, .. } | Kind::InOutVariable { expr } => {
                if let Some(t) = scope.expr_type(&expr.value) {
                    return Some(t);
                }
            }
            Kind::Block { ty, instance, .. } => {
                let pin = input_name(&g.elems[c].kind, cp).unwrap_or("");
                if let Some(t) = scope.pin_type(&ty.value, pin, false) {
                    return Some(t);
                }
                // A comparison or a function that takes one type for its inputs:
                // the type of its other inputs.
                let name = ty.value.to_ascii_uppercase();
                let same = matches!(name.as_str(), "GT" | "GE" | "EQ" | "NE" | "LE" | "LT")
                    || (passes_type(&name) && name != "SUB" && name != "ADD");
                if instance.is_none() && same && !control_input(&name, pin) {
                    for (p, srcs) in g.ins[c].iter().enumerate() {
                        let other = input_name(&g.elems[c].kind, p).unwrap_or("");
                        if p == cp || control_input(&name, other) {
                            continue;
                        }
                        for &s in srcs {
                            if s.elem == e {
                                continue;
                            }
                            if let Some(t) = source_type(g, scope, s, 16) {
                                return Some(t);
                            }
                        }
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// A part of a hidden variable's name made from a block's type or pin: a method
/// call's `inst.M` becomes `inst_M`.
pub(crate) fn hidden_part(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
