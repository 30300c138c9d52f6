//! How each variable is held in C, as matiec holds it: a located variable of a
//! PROGRAM or FUNCTION_BLOCK (or a located global) is an `__IEC_<T>_p` field bound to
//! the runtime's storage (see [`located`]); every other field of a
//! PROGRAM or FUNCTION_BLOCK, and every global, is wrapped with its flags
//! (`__IEC_<T>_t`, or `__IEC_<NAME>_t` for a STRUCT or array variable), so that a
//! runtime's debugger can force it; FB instances are nested by value, unwrapped;
//! STRUCT fields, array elements, `VAR_IN_OUT` addresses and plcc's own state are
//! plain.
//!
//! `T` is the elementary type of the IR's representation: the IEC type itself where
//! matiec's C type holds the same bits, else the integer of that width plcc keeps it
//! as (TIME is plcc's count of milliseconds, a `DINT`; LTIME's nanoseconds a `LINT`;
//! DATE, TOD and DT are `UDINT` counts; CHAR and WCHAR are `BYTE` and `WORD`).

use crate::codes;
use crate::located::{self, Located, Location};
use plcc_ir::diag::Diagnostic;
use plcc_ir::module::{AggDef, StructKind};
use plcc_ir::types::MemType;
use plcc_ir::{ElemType, Module, Type};
use std::collections::HashMap;

/// How a field is held.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Repr {
    /// Its plain C type.
    Plain,
    /// `__IEC_<T>_t` with `T` the elementary type named.
    Var(&'static str),
    /// `__IEC_<NAME>_t` of its STRUCT or array type.
    AggVar,
    /// `__IEC_<T>_p` bound to the located variable of that index.
    Located(usize),
}

/// The representation of every field of a module.
#[derive(Clone, Debug, Default)]
pub struct Reprs {
    /// Per aggregate, per field (empty for arrays).
    pub fields: Vec<Vec<Repr>>,
    /// The runtime's located variables, one per distinct address, in the order the
    /// module declares them.
    pub located: Vec<Located>,
    /// Per aggregate: its storage is prepared before it is used (flags cleared and
    /// located fields bound, its own or its members').
    pub prep: Vec<bool>,
    /// Per aggregate: it holds a located field (its own or a member's), so even
    /// storage that starts zeroed must be prepared.
    pub binds: Vec<bool>,
    /// Per aggregate: some variable is of this type, wrapped (`__IEC_<NAME>_t`).
    pub wrapped: Vec<bool>,
}

/// The elementary type whose C type holds the IR's representation of a scalar of
/// type `ty` declared as `elem`; `None` for pointers (references, addresses).
pub fn iec_name(ty: Type, elem: Option<ElemType>) -> Option<&'static str> {
    use ElemType as E;
    if let Some(e) = elem.filter(|e| e.ir_type() == ty) {
        return match e {
            E::Bool => Some("BOOL"),
            E::SInt => Some("SINT"),
            E::Int => Some("INT"),
            E::DInt | E::Time => Some("DINT"),
            E::LInt | E::LTime => Some("LINT"),
            E::USInt => Some("USINT"),
            E::UInt => Some("UINT"),
            E::UDInt | E::Date | E::Tod | E::Dt => Some("UDINT"),
            E::ULInt | E::LDate | E::LTod | E::LDt => Some("ULINT"),
            E::Byte | E::Char => Some("BYTE"),
            E::Word | E::WChar => Some("WORD"),
            E::DWord => Some("DWORD"),
            E::LWord => Some("LWORD"),
            E::Real => Some("REAL"),
            E::LReal => Some("LREAL"),
            E::Ref => None,
        };
    }
    match ty {
        Type::I1 => Some("BOOL"),
        Type::I8 => Some("BYTE"),
        Type::I16 => Some("WORD"),
        Type::I32 => Some("DWORD"),
        Type::I64 => Some("LWORD"),
        Type::F32 => Some("REAL"),
        Type::F64 => Some("LREAL"),
        Type::Ptr => None,
    }
}

/// True for the structs whose variables matiec wraps: PROGRAMs and FUNCTION_BLOCKs.
pub fn wraps(module: &Module, agg: plcc_ir::AggId) -> bool {
    matches!(
        module.agg(agg),
        AggDef::Struct(s) if matches!(s.kind, StructKind::Program | StructKind::FunctionBlock)
    )
}

impl Reprs {
    /// Decides the representation of every field of `module`, and checks and
    /// collects its located variables.
    pub fn new(module: &Module) -> Result<Reprs, Vec<Diagnostic>> {
        let n = module.aggs.len();
        let mut r = Reprs {
            fields: Vec::with_capacity(n),
            located: Vec::new(),
            prep: vec![false; n],
            binds: vec![false; n],
            wrapped: vec![false; n],
        };
        let mut by_name: HashMap<String, usize> = HashMap::new();
        for (k, a) in module.aggs.iter().enumerate() {
            let AggDef::Struct(s) = a else {
                r.fields.push(Vec::new());
                continue;
            };
            let wrap = wraps(module, plcc_ir::AggId::new(k));
            let mut fields = Vec::with_capacity(s.fields.len());
            for f in &s.fields {
                let what = format!("`{}.{}`", s.name, f.name);
                let location = match (&f.location, wrap) {
                    (Some(l), true) => Some(located::parse(l).map_err(|m| {
                        vec![Diagnostic::error_nowhere(
                            codes::E_LOCATION,
                            format!("{what}: {m}"),
                        )]
                    })?),
                    _ => None,
                };
                let repr = match (location, f.ty) {
                    (Some(Location::Full(addr)), MemType::Scalar(t)) => {
                        let addr = located::check(addr, t, &what)?;
                        let ty = iec_name(t, f.elem).ok_or_else(|| {
                            vec![Diagnostic::error_nowhere(
                                codes::E_LOCATION,
                                format!("{what} is a reference, which cannot be located"),
                            )]
                        })?;
                        let l = Located { addr, ty };
                        let name = l.name();
                        let i = match by_name.get(&name) {
                            Some(&i) if r.located[i].ty == ty => i,
                            Some(&i) => {
                                return Err(vec![Diagnostic::error_nowhere(
                                    codes::E_LOCATION_TYPES,
                                    format!(
                                        "{what} is a {ty} at `{}`, where another variable is a {}: the runtime's storage there has one type",
                                        f.location.as_deref().unwrap_or_default(),
                                        r.located[i].ty
                                    ),
                                )])
                            }
                            None => {
                                by_name.insert(name, r.located.len());
                                r.located.push(l);
                                r.located.len() - 1
                            }
                        };
                        Repr::Located(i)
                    }
                    (Some(Location::Full(_)), MemType::Agg(_)) => {
                        return Err(vec![Diagnostic::error_nowhere(
                            codes::E_LOCATION,
                            format!("{what} is a STRUCT, array or string at a direct address: the runtime locates only elementary variables"),
                        )])
                    }
                    _ if !wrap => Repr::Plain,
                    (_, MemType::Scalar(t)) => iec_name(t, f.elem).map_or(Repr::Plain, Repr::Var),
                    (_, MemType::Agg(b)) => match module.agg(b) {
                        AggDef::Struct(bs) if bs.kind != StructKind::Struct => Repr::Plain,
                        _ => {
                            r.wrapped[b.index()] = true;
                            Repr::AggVar
                        }
                    },
                };
                fields.push(repr);
            }
            r.fields.push(fields);
        }
        // Preparation, members first.
        let mut done = vec![false; n];
        for k in 0..n {
            r.mark(module, k, &mut done);
        }
        Ok(r)
    }

    fn mark(&mut self, module: &Module, k: usize, done: &mut [bool]) {
        if done[k] {
            return;
        }
        done[k] = true;
        let members: Vec<(Repr, MemType)> = match &module.aggs[k] {
            AggDef::Struct(s) => self.fields[k]
                .iter()
                .copied()
                .zip(s.fields.iter().map(|f| f.ty))
                .collect(),
            AggDef::Array(a) => vec![(Repr::Plain, a.elem)],
        };
        for (repr, ty) in members {
            if let MemType::Agg(b) = ty {
                self.mark(module, b.index(), done);
                self.prep[k] |= self.prep[b.index()];
                self.binds[k] |= self.binds[b.index()];
            }
            match repr {
                Repr::Plain => {}
                Repr::Var(_) | Repr::AggVar => self.prep[k] = true,
                Repr::Located(_) => {
                    self.prep[k] = true;
                    self.binds[k] = true;
                }
            }
        }
    }

    /// The representation of field `f` of struct `agg`.
    pub fn field(&self, agg: plcc_ir::AggId, f: u32) -> Repr {
        self.fields[agg.index()]
            .get(f as usize)
            .copied()
            .unwrap_or(Repr::Plain)
    }
}
