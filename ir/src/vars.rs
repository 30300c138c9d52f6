//! Variables by source path (`main.timer.Q`, `main.a[3]`): how the runner names them.
//!
//! Every machine reads and writes variables through these resolved paths and turns the
//! steps into an address with its own layout.

use crate::entities::{AggId, DataId};
use crate::module::{AggDef, ArrayDef, FieldRole, Module};
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
    let p = place(module, path)?;
    match (p.ty, p.elem) {
        (MemType::Scalar(t), Some(e)) => Ok(VarRef {
            path: p.path,
            root: p.root,
            steps: p.steps,
            ty: t,
            elem: e,
        }),
        _ => match string_place(module, &p) {
            Some(_) => Err(PathError(format!(
                "`{}` is a string; read its characters as `{}[0]`, ...",
                p.path, p.path
            ))),
            None => Err(PathError(format!(
                "`{}` is not an elementary variable",
                p.path
            ))),
        },
    }
}

/// A STRING or WSTRING variable found by its path: its characters are elementary
/// variables of their own, `path[0]` to `path[cap]` (CHAR or WCHAR), the text ending
/// at the first NUL.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StrRef {
    /// The canonical path, with the declared spelling of every name.
    pub path: String,
    /// WSTRING rather than STRING.
    pub wide: bool,
    /// The capacity in characters (`STRING[80]`: 80; the array holds one more, the
    /// NUL).
    pub cap: u32,
}

/// If `def` is the array of a STRING or WSTRING: whether it is wide, and its
/// capacity. By the front end's convention (`frontend/src/lower/strings.rs`), the
/// array of `STRING[N]` is named `strN` and that of `WSTRING[N]` `wstrN`, with N + 1
/// `i8` (`i16`) elements and no IEC element type, so that [`variables`] does not list
/// the characters past the end, which hold anything.
pub fn string_kind(def: &ArrayDef) -> Option<(bool, u32)> {
    let (wide, digits) = if let Some(d) = def.name.strip_prefix("wstr") {
        (true, d)
    } else {
        (false, def.name.strip_prefix("str")?)
    };
    let cap: u32 = digits.parse().ok()?;
    let elem = if wide { Type::I16 } else { Type::I8 };
    (def.elem == MemType::Scalar(elem) && def.elem_type.is_none() && def.len == cap + 1)
        .then_some((wide, cap))
}

/// The STRING or WSTRING variable at `path` (see [`StrRef`]).
pub fn resolve_string(module: &Module, path: &str) -> Result<StrRef, PathError> {
    let p = place(module, path)?;
    string_place(module, &p)
        .ok_or_else(|| PathError(format!("`{}` is not a STRING or WSTRING", p.path)))
}

fn string_place(module: &Module, p: &Place) -> Option<StrRef> {
    let MemType::Agg(agg) = p.ty else {
        return None;
    };
    let AggDef::Array(a) = module.agg(agg) else {
        return None;
    };
    let (wide, cap) = string_kind(a)?;
    Some(StrRef {
        path: p.path.clone(),
        wide,
        cap,
    })
}

/// Where a path leads, whatever its type.
struct Place {
    path: String,
    root: DataId,
    steps: Vec<PathStep>,
    ty: MemType,
    elem: Option<ElemType>,
}

fn place(module: &Module, path: &str) -> Result<Place, PathError> {
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
                // A string's characters are CHARs (WCHARs) when named one by one.
                elem = match string_kind(a) {
                    Some((wide, _)) => Some(if wide {
                        ElemType::WChar
                    } else {
                        ElemType::Char
                    }),
                    None => a.elem_type,
                };
            }
            rest = &r[close + 1..];
        } else {
            return err(format!("cannot read `{rest}` in path `{path}`"));
        }
    }
    Ok(Place {
        path: canon,
        root,
        steps,
        ty,
        elem,
    })
}

/// Every scalar variable the user declared in a data object, in declaration order,
/// descending into FB instances, structs and arrays (fields the front end added, and
/// in-out and external references, are skipped).
pub fn variables(module: &Module, root: DataId) -> Vec<VarRef> {
    variables_and_strings(module, root)
        .into_iter()
        .filter_map(|v| match v {
            Var::Scalar(v) => Some(v),
            Var::Str(_) => None,
        })
        .collect()
}

/// A variable `plcc run` prints: elementary, or a whole string.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Var {
    /// An elementary variable.
    Scalar(VarRef),
    /// A STRING or WSTRING.
    Str(StrRef),
}

/// [`variables`] with the STRING and WSTRING variables too, each in its place.
pub fn variables_and_strings(module: &Module, root: DataId) -> Vec<Var> {
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
    out: &mut Vec<Var>,
) {
    match ty {
        MemType::Scalar(t) => {
            if let Some(e) = elem {
                out.push(Var::Scalar(VarRef {
                    path: path.to_string(),
                    root,
                    steps: steps.clone(),
                    ty: t,
                    elem: e,
                }));
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
            AggDef::Array(a) if string_kind(a).is_some() => {
                let (wide, cap) = string_kind(a).expect("a string");
                out.push(Var::Str(StrRef {
                    path: path.to_string(),
                    wide,
                    cap,
                }));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::module::{DataDef, DataKind, Field, StructDef, StructKind};

    /// `main` with `n : INT` and `s : STRING[5]`.
    fn module_with_a_string() -> Module {
        let mut m = Module::default();
        let s = m.add_agg(AggDef::Array(ArrayDef {
            name: "str5".into(),
            elem: MemType::Scalar(Type::I8),
            elem_type: None,
            len: 6,
            lower: 0,
        }));
        let field = |name: &str, ty, elem| Field {
            name: name.into(),
            ty,
            elem,
            role: FieldRole::Var,
            location: None,
        };
        let main = m.add_agg(AggDef::Struct(StructDef {
            name: "main".into(),
            kind: StructKind::Program,
            fields: vec![
                field("n", MemType::Scalar(Type::I16), Some(ElemType::Int)),
                field("s", MemType::Agg(s), None),
            ],
        }));
        m.add_data(DataDef {
            name: "main".into(),
            ty: MemType::Agg(main),
            elem: None,
            kind: DataKind::Program,
            location: None,
        });
        m
    }

    #[test]
    fn strings_are_found_whole_and_by_character() {
        let m = module_with_a_string();
        let s = resolve_string(&m, "MAIN.S").unwrap();
        assert_eq!(
            s,
            StrRef {
                path: "main.s".into(),
                wide: false,
                cap: 5
            }
        );
        assert!(resolve(&m, "main.s").unwrap_err().0.contains("is a string"));
        let c = resolve(&m, "main.s[5]").unwrap();
        assert_eq!((c.ty, c.elem), (Type::I8, ElemType::Char));
        assert!(resolve(&m, "main.s[6]").is_err());
        assert!(resolve_string(&m, "main.n").is_err());
        let all = variables_and_strings(&m, DataId::new(0));
        assert_eq!(all.len(), 2);
        assert!(matches!(&all[1], Var::Str(s) if s.cap == 5));
        assert_eq!(variables(&m, DataId::new(0)).len(), 1);
    }

    #[test]
    fn strings_are_told_by_their_arrays() {
        let m = module_with_a_string();
        let AggDef::Array(a) = &m.aggs[0] else {
            panic!()
        };
        assert_eq!(string_kind(a), Some((false, 5)));
        let mut not = a.clone();
        not.len = 5;
        assert_eq!(string_kind(&not), None);
        not = a.clone();
        not.elem_type = Some(ElemType::SInt);
        assert_eq!(string_kind(&not), None);
        not = a.clone();
        not.name = "strx".into();
        assert_eq!(string_kind(&not), None);
        let wide = ArrayDef {
            name: "wstr2".into(),
            elem: MemType::Scalar(Type::I16),
            elem_type: None,
            len: 3,
            lower: 0,
        };
        assert_eq!(string_kind(&wide), Some((true, 2)));
    }
}
