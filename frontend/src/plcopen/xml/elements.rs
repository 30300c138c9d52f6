//! The elements of graphical bodies (LD and FBD): rails, contacts, coils, blocks,
//! variables, connectors, jumps, labels and returns, with their connections.

use super::*;

impl Reader<'_, '_> {
    /// The number of a `localId` attribute, else an error with `code`.
    pub(super) fn local_id(&mut self, t: Text, code: &'static str) -> Option<u64> {
        match t.value.parse::<u64>() {
            Ok(id) => Some(id),
            Err(_) => {
                self.error(
                    code,
                    format!("`localId=\"{}\"` is not a number", t.value),
                    t.range,
                );
                None
            }
        }
    }

    pub(super) fn ld(&mut self, body: Node, pou: &str) -> Vec<Element> {
        let mut out = Vec::new();
        for e in elements(body) {
            let name = e.tag_name().name();
            if matches!(
                name,
                "comment" | "documentation" | "addData" | "vendorElement"
            ) {
                continue;
            }
            if let Some(el) = self.element(e, name, pou) {
                out.push(el);
            }
        }
        out
    }

    fn position(n: Node) -> Option<(f64, f64)> {
        let p = kid(n, "position")?;
        let x = p.attribute("x")?.trim().parse().ok()?;
        let y = p.attribute("y")?.trim().parse().ok()?;
        Some((x, y))
    }

    /// Absolute y of a connection point: the element's y plus the point's `relPosition`.
    fn point_y(pos: Option<(f64, f64)>, cp: Option<Node>) -> Option<f64> {
        let (_, y) = pos?;
        let rel = cp
            .and_then(|c| kid(c, "relPosition"))
            .and_then(|r| r.attribute("y"))
            .and_then(|v| v.trim().parse::<f64>().ok())
            .unwrap_or(0.0);
        Some(y + rel)
    }

    /// The connections of every `connectionPointIn` child of `n`.
    pub(super) fn conns(&mut self, n: Node) -> Vec<Conn> {
        let mut out = Vec::new();
        for cp in kids(n, "connectionPointIn") {
            out.extend(self.point_conns(cp));
        }
        out
    }

    /// The connections of one `connectionPointIn`.
    pub(super) fn point_conns(&mut self, cp: Node) -> Vec<Conn> {
        let mut out = Vec::new();
        for c in kids(cp, "connection") {
            let Some(r) = self.attr(c, "refLocalId") else {
                self.error(
                    codes::LD_BAD_ELEMENT,
                    "`<connection>` needs a `refLocalId` attribute",
                    self.qname(c),
                );
                continue;
            };
            let Ok(from) = r.value.parse::<u64>() else {
                self.error(
                    codes::LD_BAD_ELEMENT,
                    format!("`refLocalId=\"{}\"` is not a number", r.value),
                    r.range,
                );
                continue;
            };
            let param = self
                .attr(c, "formalParameter")
                .filter(|p| !p.value.is_empty());
            let tag = {
                let start = c.range().start as u32;
                let a = c.attribute_node("refLocalId").expect("checked above");
                start..(a.range_value().end as u32 + 1).min(self.src.len() as u32)
            };
            out.push(Conn {
                from,
                param,
                range: tag,
            });
        }
        out
    }

    /// The text of a child element (`<variable>`, `<expression>`), trimmed; reports it
    /// missing.
    fn child_text(
        &mut self,
        e: Node,
        child: &'static str,
        what: &str,
        id: u64,
        pou: &str,
    ) -> Option<Text> {
        let t = kid(e, child).map(|c| self.text(c).trimmed());
        match t {
            Some(t) if !t.value.is_empty() => Some(t),
            _ => {
                self.error(
                    codes::LD_BAD_ELEMENT,
                    format!("{what} (localId {id}) of `{pou}` has no `<{child}>`"),
                    self.tag(e),
                );
                None
            }
        }
    }

    fn edge_attr(&mut self, e: Node) -> Edge {
        match e.attribute("edge").map(str::trim) {
            Some("rising") => Edge::Rising,
            Some("falling") => Edge::Falling,
            None | Some("none") | Some("") => Edge::None,
            Some(other) => {
                let r = e
                    .attribute_node("edge")
                    .map_or(0..0, |a| range32(a.range_value()));
                self.error(
                    codes::LD_BAD_ELEMENT,
                    format!("unknown edge `{other}` (expected none, rising or falling)"),
                    r,
                );
                Edge::None
            }
        }
    }

    pub(super) fn element(&mut self, e: Node, name: &str, pou: &str) -> Option<Element> {
        let tag = self.tag(e);
        let Some(id_text) = self.attr(e, "localId") else {
            let known = matches!(
                name,
                "leftPowerRail"
                    | "rightPowerRail"
                    | "contact"
                    | "coil"
                    | "block"
                    | "inVariable"
                    | "outVariable"
                    | "inOutVariable"
                    | "jump"
                    | "label"
                    | "return"
                    | "connector"
                    | "continuation"
            );
            let msg = if known {
                format!("`<{name}>` in the ladder body of `{pou}` needs a `localId` attribute")
            } else {
                format!("`<{name}>` in the ladder body of `{pou}` is not an element of a ladder diagram")
            };
            self.error(codes::LD_BAD_ELEMENT, msg, tag);
            return None;
        };
        let id = self.local_id(id_text, codes::LD_BAD_ELEMENT)?;
        let pos = Self::position(e);
        let negated = e.attribute("negated").is_some_and(truthy);
        let out_y = Self::point_y(pos, kid(e, "connectionPointOut"));
        let in_y = Self::point_y(pos, kid(e, "connectionPointIn"));
        let single_input = |r: &mut Self| Port {
            conns: r.conns(e),
            y: in_y,
            ..Default::default()
        };
        let (kind, input) = match name {
            "leftPowerRail" => (Kind::LeftRail, Port::default()),
            "rightPowerRail" => (Kind::RightRail, single_input(self)),
            "contact" => {
                let var = self.child_text(e, "variable", "a contact", id, pou)?;
                let edge = self.edge_attr(e);
                (Kind::Contact { var, negated, edge }, single_input(self))
            }
            "coil" => {
                let var = self.child_text(e, "variable", "a coil", id, pou)?;
                let edge = self.edge_attr(e);
                let storage = match e.attribute("storage").map(str::trim) {
                    Some("set") => Storage::Set,
                    Some("reset") => Storage::Reset,
                    None | Some("none") | Some("") => Storage::None,
                    Some(other) => {
                        let r = e
                            .attribute_node("storage")
                            .map_or(0..0, |a| range32(a.range_value()));
                        self.error(
                            codes::LD_BAD_ELEMENT,
                            format!("unknown storage `{other}` (expected none, set or reset)"),
                            r,
                        );
                        Storage::None
                    }
                };
                (
                    Kind::Coil {
                        var,
                        negated,
                        storage,
                        edge,
                    },
                    single_input(self),
                )
            }
            "block" => {
                let Some(ty) = self.attr(e, "typeName").filter(|t| !t.value.is_empty()) else {
                    self.error(
                        codes::LD_BAD_ELEMENT,
                        format!("a block (localId {id}) of `{pou}` needs a `typeName` attribute"),
                        tag,
                    );
                    return None;
                };
                let instance = self.attr(e, "instanceName").filter(|t| !t.value.is_empty());
                let ports = |r: &mut Self, group: &'static str, input: bool| -> Vec<Port> {
                    let Some(g) = kid(e, group) else {
                        return Vec::new();
                    };
                    kids(g, "variable")
                        .map(|v| {
                            let cp = if input {
                                kid(v, "connectionPointIn")
                            } else {
                                kid(v, "connectionPointOut")
                            };
                            Port {
                                name: r.attr(v, "formalParameter"),
                                negated: v.attribute("negated").is_some_and(truthy),
                                edge: v.attribute("edge").map(|_| r.edge_attr(v)),
                                conns: if input { r.conns(v) } else { Vec::new() },
                                y: Self::point_y(pos, cp),
                            }
                        })
                        .collect()
                };
                let mut inputs = ports(self, "inputVariables", true);
                let in_outs = ports(self, "inOutVariables", true);
                let mut outputs = ports(self, "outputVariables", false);
                // Pins written without names (`formalParameter=""`, as some tools
                // export a standard function's box): the inputs by position, IN1,
                // IN2…, and the only output OUT, when every pin of the kind is
                // unnamed.
                let unnamed = |p: &Port| p.name.as_ref().is_none_or(|n| n.value.is_empty());
                let named = |p: &mut Port, n: String| {
                    p.name = Some(Text {
                        value: n,
                        range: tag.clone(),
                        exact: Vec::new(),
                    });
                };
                if !inputs.is_empty() && inputs.iter().all(unnamed) {
                    for (k, p) in inputs.iter_mut().enumerate() {
                        named(p, format!("IN{}", k + 1));
                    }
                }
                if outputs.len() == 1 && unnamed(&outputs[0]) {
                    named(&mut outputs[0], "OUT".into());
                }
                for p in inputs.iter().chain(&in_outs).chain(&outputs) {
                    if p.name.as_ref().is_none_or(|n| n.value.is_empty()) {
                        self.error(
                            codes::LD_BAD_ELEMENT,
                            format!(
                                "a variable of block {} (localId {id}) has no `formalParameter`",
                                ty.value
                            ),
                            tag.clone(),
                        );
                        return None;
                    }
                }
                (
                    Kind::Block {
                        ty,
                        instance,
                        inputs,
                        in_outs,
                        outputs,
                    },
                    Port::default(),
                )
            }
            "inVariable" => {
                let expr = self.child_text(e, "expression", "an input variable", id, pou)?;
                (Kind::InVariable { expr, negated }, Port::default())
            }
            "outVariable" => {
                let expr = self.child_text(e, "expression", "an output variable", id, pou)?;
                (Kind::OutVariable { expr, negated }, single_input(self))
            }
            "inOutVariable" => {
                let expr = self.child_text(e, "expression", "an in-out variable", id, pou)?;
                (Kind::InOutVariable { expr }, single_input(self))
            }
            "jump" => {
                let label = self.need_attr(e, "label")?;
                (Kind::Jump { label }, single_input(self))
            }
            "label" => {
                let label = self.need_attr(e, "label")?;
                (Kind::Label { label }, Port::default())
            }
            "return" => (Kind::Return, single_input(self)),
            "connector" => {
                let name = self.need_attr(e, "name")?;
                (Kind::Connector { name }, single_input(self))
            }
            "continuation" => {
                let name = self.need_attr(e, "name")?;
                (Kind::Continuation { name }, Port::default())
            }
            other => {
                self.error(
                    codes::LD_BAD_ELEMENT,
                    format!("`<{other}>` in the ladder body of `{pou}` is not an element of a ladder diagram"),
                    tag,
                );
                return None;
            }
        };
        let order = e
            .attribute("executionOrderId")
            .and_then(|v| v.trim().parse::<u32>().ok())
            .filter(|&n| n > 0);
        Some(Element {
            id,
            tag,
            pos,
            kind,
            input,
            out_y,
            order,
        })
    }
}
