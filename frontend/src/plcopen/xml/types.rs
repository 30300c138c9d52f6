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
        Some(DataType { name, ty, init })
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
