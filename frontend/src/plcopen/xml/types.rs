//! Declarations in a PLCopen file: data types, variables with their types and
//! initial values, and variable groups (with CODESYS's global variable lists).

use super::*;

impl Reader<'_, '_> {
    /// `<dataType>`: a type declaration.
    pub(super) fn data_type(&mut self, n: Node) -> Option<DataType> {
        let name = self.need_attr(n, "name")?;
        let Some(base) = kid(n, "baseType") else {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("data type `{}` has no `<baseType>`", name.value),
                self.qname(n),
            );
            return None;
        };
        let ty = self.type_in(base)?;
        let init = kid(n, "initialValue").and_then(|v| self.value_in(v));
        let extends = self.struct_base(n, &name.value);
        Some(DataType {
            name,
            ty,
            init,
            extends,
        })
    }

    /// The variables of a variable group (`<inputVars>`, `<globalVars>`...) of the
    /// given section.
    pub(super) fn vars(&mut self, g: Node, section: Section) -> VarGroup {
        let constant = g.attribute("constant").is_some_and(truthy);
        let retain = g.attribute("retain").is_some_and(truthy)
            || g.attribute("persistent").is_some_and(truthy);
        let non_retain = g.attribute("nonretain").is_some_and(truthy);
        let vars = kids(g, "variable").filter_map(|v| self.var(v)).collect();
        VarGroup {
            section,
            name: self.attr(g, "name").filter(|n| !n.value.is_empty()),
            constant,
            retain,
            non_retain,
            tag: self.qname(g),
            vars,
        }
    }

    /// The global variable lists of a `<globalVars>` element. CODESYS writes a list
    /// whose variables have different attributes (some CONSTANT, some not) as one
    /// element with the attributes of the first, and keeps the true lists in its
    /// `<addData>` (`mixedattrsvarlist`): those are read instead.
    pub(super) fn global_vars(&mut self, g: Node) -> Vec<VarGroup> {
        let mixed: Vec<Node> = add_data(g, "mixedattrsvarlist")
            .flat_map(|d| kids(d, "MixedAttrsVarList"))
            .flat_map(|m| kids(m, "globalVars"))
            .collect();
        if mixed.is_empty() {
            vec![self.vars(g, Section::Global)]
        } else {
            mixed
                .into_iter()
                .map(|m| self.vars(m, Section::Global))
                .collect()
        }
    }

    /// `<variable>` with its type, address and initial value.
    pub(super) fn var(&mut self, v: Node) -> Option<Var> {
        let name = self.need_attr(v, "name")?;
        let Some(t) = kid(v, "type") else {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("variable `{}` has no `<type>`", name.value),
                self.qname(v),
            );
            return None;
        };
        let ty = self.type_in(t)?;
        let address = self.attr(v, "address").filter(|a| !a.value.is_empty());
        let init = kid(v, "initialValue").and_then(|i| self.value_in(i));
        Some(Var {
            name,
            ty,
            address,
            init,
        })
    }

    /// The type inside `<type>`, `<baseType>` or `<returnType>`.
    pub(super) fn type_in(&mut self, n: Node) -> Option<Type> {
        let Some(t) = elements(n).next() else {
            self.error(
                codes::LD_BAD_PROJECT,
                "a type element is empty",
                self.qname(n),
            );
            return None;
        };
        self.type_of(t)
    }

    /// A type element (`<INT/>`, `<derived>`, `<array>`...).
    fn type_of(&mut self, t: Node) -> Option<Type> {
        let tag = t.tag_name().name();
        let qname = self.qname(t);
        let named = |value: &str| Text {
            value: value.to_string(),
            range: qname.clone(),
            exact: vec![Piece {
                at: 0,
                src: qname.start,
                len: value.len() as u32,
            }],
        };
        Some(match tag {
            "derived" => Type::Named(self.need_attr(t, "name")?),
            "string" | "wstring" => Type::String {
                wide: tag == "wstring",
                len: self.attr(t, "length"),
            },
            "array" => {
                let mut dims = Vec::new();
                for d in kids(t, "dimension") {
                    let lo = self.need_attr(d, "lower")?;
                    let hi = self.need_attr(d, "upper")?;
                    dims.push((lo, hi));
                }
                let Some(b) = kid(t, "baseType") else {
                    self.error(codes::LD_BAD_PROJECT, "an array has no `<baseType>`", qname);
                    return None;
                };
                Type::Array {
                    dims,
                    elem: Box::new(self.type_in(b)?),
                }
            }
            "enum" => {
                let mut values = Vec::new();
                if let Some(vs) = kid(t, "values") {
                    for v in kids(vs, "value") {
                        let name = self.need_attr(v, "name")?;
                        values.push((name, self.attr(v, "value")));
                    }
                }
                let base = match kid(t, "baseType") {
                    Some(b) => Some(Box::new(self.type_in(b)?)),
                    None => None,
                };
                Type::Enum { values, base }
            }
            "struct" => Type::Struct(kids(t, "variable").filter_map(|v| self.var(v)).collect()),
            "subrangeSigned" | "subrangeUnsigned" => {
                let Some(r) = kid(t, "range") else {
                    self.error(codes::LD_BAD_PROJECT, "a subrange has no `<range>`", qname);
                    return None;
                };
                let lo = self.need_attr(r, "lower")?;
                let hi = self.need_attr(r, "upper")?;
                let Some(b) = kid(t, "baseType") else {
                    self.error(
                        codes::LD_BAD_PROJECT,
                        "a subrange has no `<baseType>`",
                        qname,
                    );
                    return None;
                };
                Type::Subrange {
                    base: Box::new(self.type_in(b)?),
                    lo,
                    hi,
                }
            }
            "pointer" => {
                let Some(b) = kid(t, "baseType") else {
                    self.error(
                        codes::LD_BAD_PROJECT,
                        "a pointer has no `<baseType>`",
                        qname,
                    );
                    return None;
                };
                let to = Box::new(self.type_in(b)?);
                match self.dialect {
                    Dialect::Codesys => Type::Pointer(to),
                    Dialect::Iec => Type::Ref(to),
                }
            }
            // The elementary types are elements named after them (`<INT/>`, `<TIME/>`).
            _ if !tag.is_empty()
                && tag
                    .bytes()
                    .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_') =>
            {
                let t = named(tag);
                Type::Named(t)
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown type element `<{other}>`"),
                    qname,
                );
                return None;
            }
        })
    }

    /// The value inside `<initialValue>` (or an array or struct member).
    pub(super) fn value_in(&mut self, n: Node) -> Option<Value> {
        let Some(v) = elements(n).next() else {
            self.error(
                codes::LD_BAD_PROJECT,
                "an initial value is empty",
                self.qname(n),
            );
            return None;
        };
        match v.tag_name().name() {
            "simpleValue" => Some(Value::Simple(self.need_attr(v, "value")?)),
            "arrayValue" => {
                let mut out = Vec::new();
                for e in kids(v, "value") {
                    let rep = self.attr(e, "repetitionValue");
                    out.push((rep, self.value_in(e)?));
                }
                Some(Value::Array(out))
            }
            "structValue" => {
                let mut out = Vec::new();
                for e in kids(v, "value") {
                    let m = self.need_attr(e, "member")?;
                    out.push((m, self.value_in(e)?));
                }
                Some(Value::Struct(out))
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown value element `<{other}>`"),
                    self.qname(v),
                );
                None
            }
        }
    }
}

/// The initial values of STRING and WSTRING variables and types, quoted where the
/// file leaves the quotes out, as Beremiz's and OpenPLC's translator does: a value of
/// a string type (or of an alias of one) that neither starts nor ends with the quote
/// is put between quotes (`hello` is `'hello'`); SVGHMI's `HMI_STRING` counts as a
/// string type. CODESYS writes initial values as
/// expressions (`CONCAT(a, 'b')`), so its files are left as they are.
pub(super) fn quote_string_values(p: &mut Project) {
    if p.dialect == Dialect::Codesys {
        return;
    }
    // The string types: their names (uppercase) and whether they are wide. Beremiz's
    // SVGHMI extension declares HMI_STRING (a STRING) in a library of its own, which
    // its translator knows when it quotes.
    let mut strings: Vec<(String, bool)> = vec![("HMI_STRING".into(), false)];
    loop {
        let before = strings.len();
        for t in &p.types {
            let name = t.name.value.to_ascii_uppercase();
            if strings.iter().all(|(n, _)| *n != name) {
                if let Some(wide) = string_kind(&t.ty, &strings) {
                    strings.push((name, wide));
                }
            }
        }
        if strings.len() == before {
            break;
        }
    }
    for t in &mut p.types {
        if let Some(wide) = string_kind(&t.ty, &strings) {
            if let Some(v) = &mut t.init {
                quote(v, wide);
            }
        }
        if let Type::Struct(fields) = &mut t.ty {
            quote_vars(fields, &strings);
        }
    }
    let groups = p
        .pous
        .iter_mut()
        .flat_map(|pou| {
            pou.groups
                .iter_mut()
                .chain(pou.oo.methods.iter_mut().flat_map(|m| &mut m.groups))
                .chain(pou.oo.properties.iter_mut().flat_map(|p| {
                    p.get
                        .iter_mut()
                        .chain(p.set.iter_mut())
                        .flat_map(|a| &mut a.groups)
                }))
        })
        .chain(&mut p.globals);
    let config_groups = p.configs.iter_mut().flat_map(|c| {
        c.globals
            .iter_mut()
            .chain(c.resources.iter_mut().flat_map(|r| &mut r.globals))
    });
    for g in groups.chain(config_groups) {
        quote_vars(&mut g.vars, &strings);
    }
}

/// Quotes the initial values of the string variables of `vars`.
fn quote_vars(vars: &mut [Var], strings: &[(String, bool)]) {
    for v in vars {
        if let (Some(wide), Some(init)) = (string_kind(&v.ty, strings), &mut v.init) {
            quote(init, wide);
        }
    }
}

/// `Some(wide)` if `t` is STRING or WSTRING, or a type named in `strings`.
fn string_kind(t: &Type, strings: &[(String, bool)]) -> Option<bool> {
    match t {
        Type::String { wide, .. } => Some(*wide),
        Type::Named(n) => {
            let name = n.value.to_ascii_uppercase();
            match name.as_str() {
                "STRING" => Some(false),
                "WSTRING" => Some(true),
                _ => strings.iter().find(|(s, _)| *s == name).map(|(_, w)| *w),
            }
        }
        _ => None,
    }
}

/// Puts a simple value between quotes unless it starts or ends with one; `$` and
/// the quote inside are escaped.
fn quote(v: &mut Value, wide: bool) {
    let Value::Simple(t) = v else {
        return;
    };
    let q = if wide { '"' } else { '\'' };
    if t.value.starts_with(q) || t.value.ends_with(q) {
        return;
    }
    let escaped: String = t
        .value
        .chars()
        .flat_map(|c| match c {
            '$' => vec!['$', '$'],
            c if c == q => vec!['$', q],
            c => vec![c],
        })
        .collect();
    // The text is still the file's where nothing was escaped.
    t.exact = if escaped == t.value {
        t.exact
            .iter()
            .map(|p| Piece { at: p.at + 1, ..*p })
            .collect()
    } else {
        Vec::new()
    };
    t.value = format!("{q}{escaped}{q}");
}
