//! POUs: their interface, their body, and their actions and transitions.

use super::*;

impl Reader<'_, '_> {
    /// `<pou name="..." pouType="...">`.
    pub(super) fn pou(&mut self, n: Node) -> Option<Pou> {
        let name = self.need_attr(n, "name")?;
        let kind_text = self.need_attr(n, "pouType")?;
        let kind = match kind_text.value.as_str() {
            "program" => PouKind::Program,
            "function" => PouKind::Function,
            "functionBlock" => PouKind::FunctionBlock,
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!(
                        "unknown pouType `{other}` of POU `{}` (expected program, function or functionBlock)",
                        name.value
                    ),
                    kind_text.range.clone(),
                );
                return None;
            }
        };
        let iface = kid(n, "interface");
        let (ret, groups) = self.interface_of(iface, &name.value);
        let tag = self.tag(n);
        let bodies: Vec<Node> = kids(n, "body").collect();
        if bodies.len() > 1 {
            self.error(
                codes::E_UNSUPPORTED,
                format!("not supported yet: several bodies in POU `{}`", name.value),
                self.qname(bodies[1]),
            );
        }
        let body = match bodies.first() {
            None => Body::None,
            Some(&b) => self.body(b, &name.value, "POU")?,
        };
        let actions = self.named_bodies(n, "actions", "action", &name.value);
        let transitions = self.named_bodies(n, "transitions", "transition", &name.value);
        let oo = self.pou_oo(n, iface, &name.value);
        if kind == PouKind::Function && !(oo.methods.is_empty() && oo.properties.is_empty()) {
            self.error(
                codes::E_OO_DECLARATION,
                format!(
                    "FUNCTION `{}` has methods or properties: only a FUNCTION_BLOCK or a PROGRAM may",
                    name.value
                ),
                self.qname(n),
            );
        }
        Some(Pou {
            name,
            kind,
            ret,
            groups,
            body,
            actions,
            transitions,
            oo,
            tag,
        })
    }

    /// The actions (`list` = `actions`, `item` = `action`) or transitions of a POU:
    /// each has a name and a body in any language. One that cannot be read is
    /// reported and left out.
    fn named_bodies(
        &mut self,
        pou: Node,
        list: &'static str,
        item: &'static str,
        pou_name: &str,
    ) -> Vec<NamedBody> {
        let mut out: Vec<NamedBody> = Vec::new();
        for a in kids(pou, list).flat_map(|l| kids(l, item)) {
            let Some(name) = self.need_attr(a, "name") else {
                continue;
            };
            if let Some(first) = out
                .iter()
                .find(|b| b.name.value.eq_ignore_ascii_case(&name.value))
            {
                let d = Diagnostic::error(
                    codes::E_DUPLICATE,
                    format!("POU `{pou_name}` has two {item}s named `{}`", name.value),
                    self.span(name.range.clone()),
                )
                .with_secondary(self.span(first.name.range.clone()), "the first one");
                self.diags.push(d);
                continue;
            }
            let label = format!("{pou_name}.{}", name.value);
            let body = match kid(a, "body") {
                Some(b) => match self.body(b, &label, item) {
                    Some(b) => b,
                    None => continue,
                },
                None => Body::None,
            };
            out.push(NamedBody {
                tag: self.qname(a),
                name,
                body,
            });
        }
        out
    }

    /// A `<body>`: its language element read. `label` names what it is the body of
    /// in messages (`P`, or `P.A` for an action), `kind` says what that is (`POU`,
    /// `action`, `transition`).
    pub(super) fn body(&mut self, b: Node, label: &str, kind: &str) -> Option<Body> {
        let Some(lang) = elements(b).find(|e| {
            !matches!(
                e.tag_name().name(),
                "documentation" | "addData" | "vendorData"
            )
        }) else {
            return Some(Body::None);
        };
        Some(match lang.tag_name().name() {
            "ST" => Body::St(self.text(lang).trimmed()),
            "IL" => Body::Il(self.text(lang).trimmed()),
            "LD" | "FBD" => {
                // A body with a malformed element is not checked further: its rungs
                // would be incomplete, and every check would report consequences.
                let before = self.diags.iter().filter(|d| d.is_error()).count();
                let elems = self.ld(lang, label);
                if self.diags.iter().filter(|d| d.is_error()).count() > before {
                    return Some(Body::None);
                }
                let g = if lang.tag_name().name() == "LD" {
                    Graphic::Ld
                } else {
                    Graphic::Fbd
                };
                Body::Graph(g, elems)
            }
            "SFC" if kind == "POU" || kind == "action" => Body::Sfc(self.sfc(lang, label)),
            other => {
                let what_lang = match other {
                    "SFC" => "sequential function charts (SFC)",
                    _ => "this body language",
                };
                self.diags.push(
                    Diagnostic::error(
                        codes::E_LANGUAGE_UNSUPPORTED,
                        format!("not supported yet: {what_lang}, in {kind} `{label}`"),
                        self.span(self.qname(lang)),
                    )
                    .with_note("plcc compiles LD, FBD, ST and IL bodies of PLCopen XML files"),
                );
                return None;
            }
        })
    }

    /// A variable group of a POU's interface.
    pub(super) fn group(&mut self, g: Node) -> Option<VarGroup> {
        let section = match g.tag_name().name() {
            "inputVars" => Section::Input,
            "outputVars" => Section::Output,
            "inOutVars" => Section::InOut,
            "localVars" => Section::Local,
            "tempVars" => Section::Temp,
            "externalVars" => Section::External,
            "globalVars" => Section::Global,
            "accessVars" => {
                self.error(
                    codes::E_UNSUPPORTED,
                    "not supported yet: access variables",
                    self.qname(g),
                );
                return None;
            }
            other => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("unknown variable section `<{other}>`"),
                    self.qname(g),
                );
                return None;
            }
        };
        Some(self.vars(g, section))
    }

    /// `<varList>` in an interface is not a variable section (it is the schema's
    /// name of their type, which some tools write as an element, and which the
    /// editors drop): skipped, with one warning per interface.
    pub(super) fn var_lists(&mut self, iface: Node, pou: &str) {
        let lists: Vec<Node> = kids(iface, "varList").collect();
        let Some(&first) = lists.first() else {
            return;
        };
        let what = match lists.len() {
            1 => "`<varList>`".to_string(),
            n => format!("{n} `<varList>` elements"),
        };
        let d = Diagnostic::warning(
            codes::W_PLCOPEN_SKIPPED,
            format!("{what} in the interface of POU `{pou}`: skipped"),
            self.span(self.qname(first)),
        )
        .with_note(
            "`<varList>` is not a variable section of PLCopen TC6 (those are `<inputVars>`, \
             `<localVars>`...), and Beremiz and OpenPLC drop it too",
        );
        self.diags.push(d);
    }
}
