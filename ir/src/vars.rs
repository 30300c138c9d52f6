//! Variables by source path (`main.timer.Q`, `main.a[3]`): how the runner names them.
//!
//! Every machine reads and writes variables through these resolved paths and turns the
//! steps into an address with its own layout.

use crate::entities::{AggId, DataId};
use crate::module::{AggDef, FieldRole, Module};
use crate::types::{ElemType, MemType, Type};

/// One step from an aggregate to a member.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum PathStep {
    /// Field `1` of struct `0`.
    Field(AggId, u32),
    /// Element `1` (zero-based) of array `0`.
    Elem(AggId, u32),
}

/// A scalar variable found by its path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VarRef {
    /// The canonical path, with the declared spelling of every name.
    pub path: String,
    /// The data object it lives in.
    pub root: DataId,
    /// The way from the start of the object to the variable.
    pub steps: Vec<PathStep>,
    /// Its IR type.
    pub ty: Type,
    /// Its IEC type.
    pub elem: ElemType,
}

/// Why a path does not name a scalar variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathError(pub String);

impl std::fmt::Display for PathError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PathError {}

/// Resolves a path such as `main.timer.Q` or `main.grid[2,3]` (names ignore case;
/// indexes are the source's, `a[1][2]` and `a[1,2]` both work for nested arrays).
pub fn resolve(module: &Module, path: &str) -> Result<VarRef, PathError> {
    let err = |m: String| Err(PathError(m));
    let mut rest = path.trim();
    let root_len = rest.find(['.', '[']).unwrap_or(rest.len());
    let root_name = &rest[..root_len];
    rest = &rest[root_len..];
    let Some(root) = module.data_by_name(root_name) else {
        return err(format!("no program or global named `{root_name}`"));
    };
    let data = &module.data[root.index()];
    let mut canon = data.name.clone();
    let mut ty = data.ty;
    let mut elem = data.elem;
    let mut steps = Vec::new();
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('.') {
            let n = r.find(['.', '[']).unwrap_or(r.len());
            let name = &r[..n];
            rest = &r[n..];
            let MemType::Agg(agg) = ty else {
                return err(format!("`{canon}` has no member `{name}`"));
            };
            let AggDef::Struct(s) = module.agg(agg) else {
                return err(format!("`{canon}` is an array; index it with [..]"));
            };
            let Some(fi) = s
                .fields
                .iter()
                .position(|f| f.name.eq_ignore_ascii_case(name))
            else {
                return err(format!("`{canon}` has no member `{name}`"));
            };
            let f = &s.fields[fi];
            canon.push('.');
            canon.push_str(&f.name);
            steps.push(PathStep::Field(agg, fi as u32));
            ty = f.ty;
            elem = f.elem;
        } else if let Some(r) = rest.strip_prefix('[') {
            let Some(close) = r.find(']') else {
                return err(format!("missing `]` in `{path}`"));
            };
            for part in r[..close].split(',') {
                let idx: i64 = part
                    .trim()
                    .parse()
                    .map_err(|_| PathError(format!("`{}` is not an index", part.trim())))?;
                let MemType::Agg(agg) = ty else {
                    return err(format!("`{canon}` is not an array"));
                };
                let AggDef::Array(a) = module.agg(agg) else {
                    return err(format!("`{canon}` is not an array"));
                };
                let zero = idx - a.lower;
                if zero < 0 || zero >= a.len as i64 {
                    return err(format!(
                        "index {idx} is outside `{canon}` ({}..{})",
                        a.lower,
                        a.lower + a.len as i64 - 1
                    ));
                }
                canon.push_str(&format!("[{idx}]"));
                steps.push(PathStep::Elem(agg, zero as u32));
                ty = a.elem;
                elem = a.elem_type;
            }
            rest = &r[close + 1..];
        } else {
            return err(format!("cannot read `{rest}` in path `{path}`"));
        }
    }
    match (ty, elem) {
        (MemType::Scalar(t), Some(e)) => Ok(VarRef {
            path: canon,
            root,
            steps,
            ty: t,
            elem: e,
        }),
        _ => err(format!("`{canon}` is not an elementary variable")),
    }
}

/// Every scalar variable the user declared in a data object, in declaration order,
/// descending into FB instances, structs and arrays (fields the front end added, and
/// in-out and external references, are skipped).
pub fn variables(module: &Module, root: DataId) -> Vec<VarRef> {
    let data = &module.data[root.index()];
    let mut out = Vec::new();
    let mut steps = Vec::new();
    walk(
        module,
        root,
        data.ty,
        data.elem,
        &data.name.clone(),
        &mut steps,
        &mut out,
    );
    out
}

fn walk(
    module: &Module,
    root: DataId,
    ty: MemType,
    elem: Option<ElemType>,
    path: &str,
    steps: &mut Vec<PathStep>,
    out: &mut Vec<VarRef>,
) {
    match ty {
        MemType::Scalar(t) => {
            if let Some(e) = elem {
                out.push(VarRef {
                    path: path.to_string(),
                    root,
                    steps: steps.clone(),
                    ty: t,
                    elem: e,
                });
            }
        }
        MemType::Agg(agg) => match module.agg(agg) {
            AggDef::Struct(s) => {
                for (i, f) in s.fields.iter().enumerate() {
                    if matches!(
                        f.role,
                        FieldRole::Hidden | FieldRole::InOut | FieldRole::External
                    ) {
                        continue;
                    }
                    steps.push(PathStep::Field(agg, i as u32));
                    walk(
                        module,
                        root,
                        f.ty,
                        f.elem,
                        &format!("{path}.{}", f.name),
                        steps,
                        out,
                    );
                    steps.pop();
                }
            }
            AggDef::Array(a) => {
                for i in 0..a.len {
                    steps.push(PathStep::Elem(agg, i));
                    let p = format!("{path}[{}]", a.lower + i as i64);
                    walk(module, root, a.elem, a.elem_type, &p, steps, out);
                    steps.pop();
                }
            }
        },
    }
}
