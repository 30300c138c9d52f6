//! CODESYS's object orientation, which its PLCopen exports keep in `<addData>`:
//! the methods (`method` data) and properties (`property` data) of a POU, its base
//! and interfaces (`pouinheritance` in the interface's `<addData>`), the access
//! modifiers of POUs, methods and accessors (`accessmodifiers`), the project's
//! interfaces (`interface` data of the project or an application), and the base of
//! a STRUCT (`datatypeinheritance`). ABSTRACT and FINAL are in none of these: they
//! are read from the declaration CODESYS writes as plain text beside them
//! (`InterfaceAsPlainText`).

use super::*;

/// ABSTRACT, FINAL and an access specifier of a POU, a method or a property.
#[derive(Clone, Debug, Default)]
pub(crate) struct Mods {
    /// PUBLIC, PRIVATE, PROTECTED or INTERNAL (the keyword), at its
    /// `<AccessModifiers>`.
    pub access: Option<Text>,
    /// ABSTRACT.
    pub abstract_: bool,
    /// FINAL.
    pub final_: bool,
}

/// A POU's object-oriented parts.
#[derive(Debug, Default)]
pub(crate) struct Oo {
    /// `<Extends>`: the base FUNCTION_BLOCK.
    pub extends: Option<Text>,
    /// `<Implements>`: the interfaces.
    pub implements: Vec<Text>,
    /// The POU's modifiers (ABSTRACT, FINAL; its access modifier is a library's
    /// matter and is not kept).
    pub mods: Mods,
    /// `<Method>`s, in document order.
    pub methods: Vec<Method>,
    /// `<Property>`s, in document order.
    pub properties: Vec<Property>,
}

/// `<Method name="...">`: of a POU (with a body) or of an interface (without).
#[derive(Debug)]
pub(crate) struct Method {
    /// Its name.
    pub name: Text,
    /// Its modifiers.
    pub mods: Mods,
    /// Its result type (`<returnType>`).
    pub ret: Option<Type>,
    /// Its variable groups (inputs, outputs, in-outs, locals).
    pub groups: Vec<VarGroup>,
    /// Its body (ST, IL, LD or FBD).
    pub body: Body,
    /// Its tag name, for messages about it.
    pub tag: Range<u32>,
}

/// `<Property name="...">` with its accessors.
#[derive(Debug)]
pub(crate) struct Property {
    /// Its name.
    pub name: Text,
    /// Its modifiers (an accessor's access modifier: CODESYS keeps one per
    /// accessor, plcc one per property).
    pub mods: Mods,
    /// Its type (`<interface><returnType>`).
    pub ty: Type,
    /// `<GetAccessor>`.
    pub get: Option<Accessor>,
    /// `<SetAccessor>`.
    pub set: Option<Accessor>,
    /// Its tag name.
    pub tag: Range<u32>,
}

/// `<GetAccessor>` or `<SetAccessor>` of a property.
#[derive(Debug)]
pub(crate) struct Accessor {
    /// Its local variables.
    pub groups: Vec<VarGroup>,
    /// Its body (ST or IL).
    pub body: Body,
    /// Its tag name.
    pub tag: Range<u32>,
}

/// `<Interface name="...">` of the project's `<addData>`.
#[derive(Debug)]
pub(crate) struct Interface {
    /// Its name.
    pub name: Text,
    /// `<Inheritance><Extends>`: the interfaces it extends.
    pub extends: Vec<Text>,
    /// Its methods (without bodies).
    pub methods: Vec<Method>,
    /// Its properties (accessors without bodies).
    pub properties: Vec<Property>,
    /// Its tag name.
    pub tag: Range<u32>,
}

/// The access modifiers of CODESYS's `<AccessModifiers>`, as attributes and
/// keywords.
const ACCESS: [(&str, &str); 4] = [
    ("Private", "PRIVATE"),
    ("Protected", "PROTECTED"),
    ("Internal", "INTERNAL"),
    ("Public", "PUBLIC"),
];

impl Reader<'_, '_> {
    /// The object-oriented parts of `<pou>` `n`, whose interface is `iface`.
    pub(super) fn pou_oo(&mut self, n: Node, iface: Option<Node>, pou: &str) -> Oo {
        let mut oo = Oo::default();
        // The declaration as text: in the POU's `<addData>`, or in one of its
        // interface's variable groups.
        let plain = add_data(n, "interfaceasplaintext")
            .flat_map(|d| kids(d, "InterfaceAsPlainText"))
            .map(plain_text)
            .next()
            .or_else(|| iface.and_then(|i| header_text(i, None)));
        if let Some(iface) = iface {
            oo.mods = self.mods(iface, plain.as_deref());
            oo.mods.access = None;
            for inh in add_data(iface, "pouinheritance").flat_map(|d| kids(d, "Inheritance")) {
                for e in kids(inh, "Extends") {
                    let t = self.text(e).trimmed();
                    if t.value.is_empty() {
                        self.error(
                            codes::LD_BAD_PROJECT,
                            format!("`<Extends>` of POU `{pou}` names no base"),
                            self.qname(e),
                        );
                    } else if let Some(first) = &oo.extends {
                        let d = Diagnostic::error(
                            codes::LD_BAD_PROJECT,
                            format!("POU `{pou}` extends two function blocks"),
                            self.span(self.qname(e)),
                        )
                        .with_secondary(self.span(first.range.clone()), "the first base");
                        self.diags.push(d);
                    } else {
                        oo.extends = Some(t);
                    }
                }
                oo.implements.extend(self.names_in(inh, "Implements", pou));
            }
        }
        for m in add_data(n, "method").flat_map(|d| kids(d, "Method")) {
            if let Some(m) = self.method(m, pou, true) {
                if self.not_twice(pou, "method", &m.name, oo.methods.iter().map(|m| &m.name)) {
                    oo.methods.push(m);
                }
            }
        }
        for p in add_data(n, "property").flat_map(|d| kids(d, "Property")) {
            if let Some(p) = self.property(p, pou, true) {
                let names = oo.properties.iter().map(|p| &p.name);
                if self.not_twice(pou, "property", &p.name, names) {
                    oo.properties.push(p);
                }
            }
        }
        oo
    }

    /// The names of the `<what>` children of `n` (`<Implements>`, `<Extends>`);
    /// each element may hold one name or several separated by commas.
    fn names_in(&mut self, n: Node, what: &'static str, owner: &str) -> Vec<Text> {
        let mut out = Vec::new();
        for e in kids(n, what) {
            let t = self.text(e).trimmed();
            if t.value.is_empty() {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("`<{what}>` of `{owner}` names nothing"),
                    self.qname(e),
                );
                continue;
            }
            if !t.value.contains(',') {
                out.push(t);
                continue;
            }
            for part in t.value.split(',') {
                let part = part.trim();
                if !part.is_empty() {
                    out.push(Text {
                        value: part.to_string(),
                        range: t.range.clone(),
                        exact: Vec::new(),
                    });
                }
            }
        }
        out
    }

    /// False (and reported) if `name` is among `before`: a member of one name twice.
    fn not_twice<'t>(
        &mut self,
        owner: &str,
        what: &str,
        name: &Text,
        mut before: impl Iterator<Item = &'t Text>,
    ) -> bool {
        let Some(first) = before.find(|b| b.value.eq_ignore_ascii_case(&name.value)) else {
            return true;
        };
        let d = Diagnostic::error(
            codes::E_DUPLICATE,
            format!("`{owner}` has two {what}s named `{}`", name.value),
            self.span(name.range.clone()),
        )
        .with_secondary(self.span(first.range.clone()), "the first one");
        self.diags.push(d);
        false
    }

    /// The access modifier of the `accessmodifiers` data of `n`, and ABSTRACT and
    /// FINAL from the declaration as plain text `plain` (its first line).
    fn mods(&mut self, n: Node, plain: Option<&str>) -> Mods {
        let mut m = Mods::default();
        for a in add_data(n, "accessmodifiers").flat_map(|d| kids(d, "AccessModifiers")) {
            for (attr, kw) in ACCESS {
                if a.attribute(attr).is_some_and(truthy) && m.access.is_none() {
                    m.access = Some(Text {
                        value: kw.to_string(),
                        range: self.qname(a),
                        exact: Vec::new(),
                    });
                }
            }
            m.abstract_ |= a.attribute("Abstract").is_some_and(truthy);
            m.final_ |= a.attribute("Final").is_some_and(truthy);
        }
        // The header line (after pragmas such as `{attribute 'qualified_only'}`).
        let header = |l: &&str| {
            let w = l.split_whitespace().next().unwrap_or("");
            [
                "FUNCTION_BLOCK",
                "PROGRAM",
                "FUNCTION",
                "METHOD",
                "PROPERTY",
            ]
            .iter()
            .any(|k| w.eq_ignore_ascii_case(k))
        };
        if let Some(line) = plain.and_then(|p| p.lines().map(str::trim).find(header)) {
            // `FUNCTION_BLOCK INTERNAL ABSTRACT Name EXTENDS ...`: the words between
            // the keyword and the name.
            for w in line.split_whitespace().skip(1) {
                match w.to_ascii_uppercase().as_str() {
                    "ABSTRACT" => m.abstract_ = true,
                    "FINAL" => m.final_ = true,
                    "PUBLIC" | "PRIVATE" | "PROTECTED" | "INTERNAL" | "OVERRIDE" => {}
                    _ => break,
                }
            }
        }
        m
    }

    /// The variable groups and result type of a member's `<interface>`. `owner`
    /// names the member in messages.
    pub(super) fn interface_of(
        &mut self,
        iface: Option<Node>,
        owner: &str,
    ) -> (Option<Type>, Vec<VarGroup>) {
        let mut ret = None;
        let mut groups = Vec::new();
        if let Some(iface) = iface {
            for g in elements(iface) {
                match g.tag_name().name() {
                    "returnType" => ret = self.type_in(g),
                    "documentation" | "addData" | "varList" => {}
                    _ => {
                        if let Some(grp) = self.group(g) {
                            groups.push(grp);
                        }
                    }
                }
            }
            self.var_lists(iface, owner);
        }
        (ret, groups)
    }

    /// `<Method name="...">`; `with_body`: of a POU (else of an interface).
    fn method(&mut self, m: Node, owner: &str, with_body: bool) -> Option<Method> {
        let name = self.need_attr(m, "name")?;
        let label = format!("{owner}.{}", name.value);
        let iface = kid(m, "interface");
        let (ret, groups) = self.interface_of(iface, &label);
        let plain = header_text(m, iface);
        let mods = match iface {
            Some(i) => self.mods(i, plain.as_deref()),
            None => Mods::default(),
        };
        let body = match kid(m, "body") {
            Some(b) if with_body => self.member_body(b, &label, "method")?,
            Some(b) => {
                self.diags.push(Diagnostic::warning(
                    codes::W_PLCOPEN_SKIPPED,
                    format!("the body of method `{label}` of an interface: skipped"),
                    self.span(self.qname(b)),
                ));
                Body::None
            }
            None => Body::None,
        };
        Some(Method {
            name,
            mods,
            ret,
            groups,
            body,
            tag: self.qname(m),
        })
    }

    /// The body of a method (ST, IL, LD or FBD) or accessor (ST or IL; graphical
    /// bodies of accessors and charts are not supported yet).
    fn member_body(&mut self, b: Node, label: &str, kind: &str) -> Option<Body> {
        let body = self.body(b, label, kind)?;
        if let (Body::Graph(g, _), false) = (&body, kind == "method") {
            let lang = match g {
                Graphic::Ld => "LD",
                Graphic::Fbd => "FBD",
            };
            self.diags.push(
                Diagnostic::error(
                    codes::E_LANGUAGE_UNSUPPORTED,
                    format!("not supported yet: a {kind} body in {lang}, in `{label}`"),
                    self.span(self.qname(b)),
                )
                .with_note(
                    "plcc compiles the bodies of methods and properties written in ST or IL",
                ),
            );
            return None;
        }
        Some(body)
    }

    /// `<Property name="...">`; `with_body`: of a POU (else of an interface).
    fn property(&mut self, p: Node, owner: &str, with_body: bool) -> Option<Property> {
        let name = self.need_attr(p, "name")?;
        let label = format!("{owner}.{}", name.value);
        let (ty, groups) = self.interface_of(kid(p, "interface"), &label);
        if let Some(g) = groups.first() {
            self.error(
                codes::LD_BAD_PROJECT,
                format!(
                    "property `{label}` declares variables (`<{}>`): only its accessors may",
                    self.src_name(g.tag.clone())
                ),
                g.tag.clone(),
            );
            return None;
        }
        let Some(ty) = ty else {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("property `{label}` has no type (`<interface><returnType>`)"),
                self.qname(p),
            );
            return None;
        };
        let mut mods = Mods::default();
        let (mut get, mut set) = (None, None);
        let mut ok = true;
        for a in elements(p) {
            let (is_get, which) = match a.tag_name().name() {
                "GetAccessor" => (true, "GET"),
                "SetAccessor" => (false, "SET"),
                "interface" | "InterfaceAsPlainText" | "addData" | "documentation" => continue,
                other => {
                    self.error(
                        codes::LD_BAD_PROJECT,
                        format!(
                            "`<{other}>` in property `{label}`: expected `<GetAccessor>` or `<SetAccessor>`"
                        ),
                        self.qname(a),
                    );
                    ok = false;
                    continue;
                }
            };
            if (is_get && get.is_some()) || (!is_get && set.is_some()) {
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!("property `{label}` has two {which} accessors"),
                    self.qname(a),
                );
                ok = false;
                continue;
            }
            let acc_label = format!("{label}.{which}");
            let iface = kid(a, "interface");
            let (ret, groups) = self.interface_of(iface, &acc_label);
            let bad = ret.is_some().then_some("`<returnType>`").or_else(|| {
                groups
                    .iter()
                    .find(|g| !matches!(g.section, Section::Local | Section::Temp))
                    .map(|_| "inputs, outputs or in-outs")
            });
            if let Some(what) = bad {
                let at = iface.map_or_else(|| self.qname(a), |i| self.qname(i));
                self.error(
                    codes::LD_BAD_PROJECT,
                    format!(
                        "the {which} accessor of property `{label}` declares {what}: an accessor has local variables only (its value is the property's)"
                    ),
                    at,
                );
                ok = false;
                continue;
            }
            if let Some(i) = iface {
                let m = self.mods(i, None);
                // The least restrictive of the accessors' access modifiers.
                let rank = |t: &Option<Text>| {
                    t.as_ref().map_or(0, |t| match t.value.as_str() {
                        "PRIVATE" => 3,
                        "PROTECTED" => 2,
                        "INTERNAL" => 1,
                        _ => 0,
                    })
                };
                let first = get.is_none() && set.is_none();
                if first || rank(&m.access) < rank(&mods.access) {
                    mods.access = m.access;
                }
            } else {
                mods.access = None;
            }
            let body = match kid(a, "body") {
                Some(b) if with_body => {
                    match self.member_body(b, &acc_label, "property accessor") {
                        Some(b) => b,
                        None => {
                            ok = false;
                            continue;
                        }
                    }
                }
                _ => Body::None,
            };
            let acc = Some(Accessor {
                groups,
                body,
                tag: self.qname(a),
            });
            if is_get {
                get = acc;
            } else {
                set = acc;
            }
        }
        let plain = header_text(p, None);
        let m = self.mods(p, plain.as_deref());
        mods.abstract_ = m.abstract_;
        mods.final_ = m.final_;
        ok.then(|| Property {
            name,
            mods,
            ty,
            get,
            set,
            tag: self.qname(p),
        })
    }

    /// The source text of a range (an element's tag name).
    fn src_name(&self, r: Range<u32>) -> String {
        self.src
            .get(r.start as usize..r.end as usize)
            .unwrap_or("")
            .to_string()
    }

    /// The interfaces CODESYS keeps in the `<addData>` of `n` (the project, an
    /// application's resource).
    pub(super) fn add_data_interfaces(&mut self, n: Node, out: &mut Vec<Interface>) {
        for i in add_data(n, "interface").flat_map(|d| kids(d, "Interface")) {
            let Some(name) = self.need_attr(i, "name") else {
                continue;
            };
            let label = name.value.clone();
            let mut extends = Vec::new();
            for inh in kids(i, "Inheritance") {
                extends.extend(self.names_in(inh, "Extends", &label));
            }
            let mut methods: Vec<Method> = Vec::new();
            for m in kids(i, "Methods").flat_map(|l| kids(l, "Method")) {
                if let Some(m) = self.method(m, &label, false) {
                    if self.not_twice(&label, "method", &m.name, methods.iter().map(|m| &m.name)) {
                        methods.push(m);
                    }
                }
            }
            let mut properties: Vec<Property> = Vec::new();
            for p in kids(i, "Properties").flat_map(|l| kids(l, "Property")) {
                if let Some(p) = self.property(p, &label, false) {
                    let names = properties.iter().map(|p| &p.name);
                    if self.not_twice(&label, "property", &p.name, names) {
                        properties.push(p);
                    }
                }
            }
            if let Some(first) = out
                .iter()
                .find(|x| x.name.value.eq_ignore_ascii_case(&name.value))
            {
                let d = Diagnostic::error(
                    codes::E_DUPLICATE,
                    format!("two interfaces named `{}`", name.value),
                    self.span(name.range.clone()),
                )
                .with_secondary(self.span(first.name.range.clone()), "the first one");
                self.diags.push(d);
                continue;
            }
            out.push(Interface {
                tag: self.qname(i),
                name,
                extends,
                methods,
                properties,
            });
        }
    }

    /// The base of a STRUCT (`datatypeinheritance` in the `<dataType>`'s
    /// `<addData>`).
    pub(super) fn struct_base(&mut self, dt: Node, name: &str) -> Option<Text> {
        let mut bases = add_data(dt, "datatypeinheritance")
            .flat_map(|d| kids(d, "Inheritance"))
            .flat_map(|i| kids(i, "Extends"));
        let e = bases.next()?;
        let t = self.text(e).trimmed();
        if t.value.is_empty() {
            self.error(
                codes::LD_BAD_PROJECT,
                format!("`<Extends>` of data type `{name}` names no base"),
                self.qname(e),
            );
            return None;
        }
        Some(t)
    }
}

/// The declaration CODESYS writes as plain text for a POU, method or property: the
/// `<InterfaceAsPlainText>` child of `n`, else the first one inside `iface`.
fn header_text(n: Node, iface: Option<Node>) -> Option<String> {
    if let Some(p) = kid(n, "InterfaceAsPlainText") {
        return Some(plain_text(p));
    }
    let iface = iface.unwrap_or(n);
    iface
        .descendants()
        .find(|d| d.is_element() && d.tag_name().name() == "InterfaceAsPlainText")
        .map(plain_text)
}

/// The text of an `<InterfaceAsPlainText>`.
fn plain_text(p: Node) -> String {
    p.descendants()
        .filter(|d| d.is_text())
        .filter_map(|d| d.text())
        .collect()
}
