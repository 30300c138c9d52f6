//! What the server shows of declarations: the outline of a file
//! (`textDocument/documentSymbol`) and the text of a hover.

use super::index::Decl;
use super::text::Lines;
use lsp_types::{DocumentSymbol, Range, SymbolKind};
use plcc_frontend::ast::*;
use plcc_frontend::plcopen::View;
use plcc_frontend::source::SourceMap;
use plcc_ir::diag::{FileId, Span};

/// At most this many lines of a TYPE's text go into a hover.
const MAX_HOVER_LINES: usize = 20;

/// The text of a span, without surrounding blanks and a final `;`.
fn text(sources: &SourceMap, span: Span) -> &str {
    let t = sources.get(span.file).slice(span).trim();
    t.strip_suffix(';').unwrap_or(t).trim_end()
}

/// The keyword of a declaration block, with its qualifiers.
pub fn block_keyword(b: &VarBlock) -> String {
    let kw = b.kind.keyword();
    let mut s = kw.to_string();
    if b.constant {
        s.push_str(" CONSTANT");
    }
    if b.retain {
        s.push_str(" RETAIN");
    }
    s
}

fn pou_keyword(kind: PouKind) -> &'static str {
    match kind {
        PouKind::Program => "PROGRAM",
        PouKind::Function => "FUNCTION",
        PouKind::FunctionBlock => "FUNCTION_BLOCK",
    }
}

/// A POU's header and its interface (inputs, outputs, in-outs), as IEC text.
fn pou_signature(sources: &SourceMap, keyword: &str, p: &Pou) -> String {
    let mut s = format!("{keyword} {}", text(sources, p.name.span));
    if let Some(t) = &p.return_type {
        s.push_str(" : ");
        s.push_str(text(sources, t.span()));
    }
    for b in &p.var_blocks {
        if !matches!(b.kind, VarKind::Input | VarKind::Output | VarKind::InOut) {
            continue;
        }
        s.push('\n');
        s.push_str(&block_keyword(b));
        for d in &b.decls {
            s.push_str("\n    ");
            s.push_str(text(sources, d.span));
            s.push(';');
        }
        s.push_str("\nEND_VAR");
    }
    s
}

fn code(s: &str) -> String {
    format!("```iecst\n{s}\n```")
}

/// The Markdown shown when hovering a name that resolves to `d`: its declaration
/// as written and, for a variable, its block, owner and type; then its doc comment
/// ([`super::doc`]).
pub fn hover_text(sources: &SourceMap, d: &Decl<'_>) -> String {
    let declaration = declaration_text(sources, d);
    match super::doc::doc_comment(sources, d) {
        Some(doc) => format!("{declaration}\n\n{doc}"),
        None => declaration,
    }
}

/// The hover of a name no file declares: a standard function (its signature) or a
/// type conversion `A_TO_B`; with the span of the word at `offset`.
pub fn builtin_hover(sources: &SourceMap, file: FileId, offset: u32) -> Option<(Span, String)> {
    let text: &str = &sources.get(file).text;
    let at = (offset as usize).min(text.len());
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let start = text[..at].rfind(|c: char| !is_word(c)).map_or(0, |k| k + 1);
    let end = text[at..]
        .find(|c: char| !is_word(c))
        .map_or(text.len(), |k| at + k);
    let word = text.get(start..end).filter(|w| !w.is_empty())?;
    let span = Span {
        file,
        start: start as u32,
        end: end as u32,
    };
    if text[..start].ends_with('#') || word.starts_with(|c: char| c.is_ascii_digit()) {
        return None;
    }
    let upper = word.to_ascii_uppercase();
    if let Some((_, signature)) = plcc_frontend::lower::STANDARD_FUNCTIONS
        .iter()
        .find(|(n, _)| *n == upper)
    {
        return Some((span, format!("{}\n\nstandard function", code(signature))));
    }
    let (from, to) = upper.split_once("_TO_")?;
    let known = |t: &str| t == "BCD" || super::tokens::ELEMENTARY.contains(&t);
    (known(from) && known(to)).then(|| {
        (
            span,
            format!(
                "{}\n\ntype conversion from `{from}` to `{to}`",
                code(&format!("{upper}(IN : {from}) : {to}"))
            ),
        )
    })
}

fn declaration_text(sources: &SourceMap, d: &Decl<'_>) -> String {
    let name = |id: &Ident| text(sources, id.span).to_string();
    match *d {
        Decl::Pou(p) => code(&pou_signature(sources, pou_keyword(p.kind), p)),
        Decl::Method(owner, m) => format!(
            "{}\n\nMETHOD of `{}`",
            code(&pou_signature(sources, "METHOD", &m.pou)),
            name(owner)
        ),
        Decl::Property(owner, p) => format!(
            "{}\n\nPROPERTY of `{}`",
            code(&format!(
                "PROPERTY {} : {}",
                name(&p.name),
                text(sources, p.ty.span())
            )),
            name(owner)
        ),
        Decl::Action(a) => {
            let owner = a
                .pou
                .map(|o| format!(" of `{}`", name(&o)))
                .unwrap_or_default();
            format!(
                "{}\n\nACTION{owner}",
                code(&format!("ACTION {}", name(&a.name)))
            )
        }
        Decl::Var {
            decl, block, owner, ..
        } => {
            let of = owner
                .map(|o| format!(" of `{}`", name(o)))
                .unwrap_or_default();
            format!(
                "{}\n\n{}{of}; type `{}`",
                code(text(sources, decl.span)),
                block_keyword(block),
                text(sources, decl.ty.span())
            )
        }
        Decl::Field { decl, ty, .. } => format!(
            "{}\n\nfield of `{}`; type `{}`",
            code(text(sources, decl.span)),
            name(&ty.name),
            text(sources, decl.ty.span())
        ),
        Decl::EnumValue { name: v, ty } => format!(
            "{}\n\nvalue of the enumeration `{}`",
            code(&format!("{}#{}", name(&ty.name), name(v))),
            name(&ty.name)
        ),
        Decl::Type(t) => {
            let body = text(sources, t.span);
            let mut lines: Vec<&str> = body.lines().take(MAX_HOVER_LINES).collect();
            if body.lines().count() > MAX_HOVER_LINES {
                lines.push("...");
            }
            code(&format!("TYPE {}\nEND_TYPE", lines.join("\n")))
        }
        Decl::Interface(i) => code(&format!("INTERFACE {}", name(&i.name))),
        Decl::Config(c) => code(&format!("CONFIGURATION {}", name(&c.name))),
        Decl::Resource(r) => code(&format!("RESOURCE {}", name(&r.name))),
        Decl::Task(t) => code(text(sources, t.span)),
        Decl::Instance(p) => code(text(sources, p.span)),
    }
}

/// Builds LSP document symbols against one file's lines.
pub struct Outline<'s> {
    /// Every source of the build.
    pub sources: &'s SourceMap,
    /// The lines of the file the outline is of.
    pub lines: Lines<'s>,
    /// The views of the PLCopen files: the outline of an XML file is its view's,
    /// each span shown in the XML ([`super::xml::place`]).
    pub views: &'s [View],
}

impl Outline<'_> {
    /// The outline of a file's items: POUs with their variables, METHODs,
    /// PROPERTYs and ACTIONs; types with their fields or values; global variable
    /// lists; configurations with their variables, resources, tasks and program
    /// instances; interfaces. For a view, a symbol whose name has no place in the
    /// XML is left out, with its children.
    pub fn items(&self, items: &[Item]) -> Vec<DocumentSymbol> {
        items.iter().filter_map(|item| self.item(item)).collect()
    }

    fn item(&self, item: &Item) -> Option<DocumentSymbol> {
        match item {
            Item::Pou(p) => {
                let kind = match p.kind {
                    PouKind::Program => SymbolKind::MODULE,
                    PouKind::Function => SymbolKind::FUNCTION,
                    PouKind::FunctionBlock => SymbolKind::CLASS,
                };
                self.pou(p, kind, pou_keyword(p.kind))
            }
            Item::Type(t) => {
                let (kind, children) = match &t.spec {
                    TypeSpec::Struct { fields, .. } => (
                        SymbolKind::STRUCT,
                        fields
                            .iter()
                            .flat_map(|d| self.vars(d, "", SymbolKind::FIELD))
                            .collect(),
                    ),
                    TypeSpec::Enum { values, .. } => (
                        SymbolKind::ENUM,
                        values
                            .iter()
                            .filter_map(|(v, _)| {
                                self.symbol(v, v.span, SymbolKind::ENUM_MEMBER, None, vec![])
                            })
                            .collect(),
                    ),
                    _ => (SymbolKind::TYPE_PARAMETER, vec![]),
                };
                let detail = format!(
                    "TYPE : {}",
                    self.text(t.spec.span()).lines().next().unwrap_or("")
                );
                self.symbol(&t.name, t.span, kind, Some(detail), children)
            }
            Item::Globals(b) => {
                let children = self.block(b);
                let keyword = block_keyword(b);
                match &b.list {
                    Some(list) => {
                        self.symbol(list, b.span, SymbolKind::NAMESPACE, Some(keyword), children)
                    }
                    None => self.named(&keyword, b.span, SymbolKind::NAMESPACE, children),
                }
            }
            Item::Configuration(c) => {
                let mut children: Vec<_> =
                    c.var_blocks.iter().flat_map(|b| self.block(b)).collect();
                for r in &c.resources {
                    let mut inner: Vec<_> =
                        r.var_blocks.iter().flat_map(|b| self.block(b)).collect();
                    for t in &r.tasks {
                        inner.extend(self.symbol(
                            &t.name,
                            t.span,
                            SymbolKind::EVENT,
                            Some("TASK".into()),
                            vec![],
                        ));
                    }
                    for p in &r.programs {
                        let detail = format!("PROGRAM instance of {}", self.text(p.pou.span));
                        inner.extend(self.symbol(
                            &p.name,
                            p.span,
                            SymbolKind::OBJECT,
                            Some(detail),
                            vec![],
                        ));
                    }
                    children.extend(self.symbol(
                        &r.name,
                        r.span,
                        SymbolKind::NAMESPACE,
                        Some("RESOURCE".into()),
                        inner,
                    ));
                }
                self.symbol(
                    &c.name,
                    c.span,
                    SymbolKind::PACKAGE,
                    Some("CONFIGURATION".into()),
                    children,
                )
            }
            Item::Action(a) => self.symbol(
                &a.name,
                a.span,
                SymbolKind::FUNCTION,
                Some("ACTION".into()),
                vec![],
            ),
            Item::Interface(i) => {
                let mut children: Vec<_> = i
                    .methods
                    .iter()
                    .filter_map(|m| self.pou(&m.pou, SymbolKind::METHOD, "METHOD"))
                    .collect();
                children.extend(i.properties.iter().filter_map(|p| self.property(p)));
                self.symbol(
                    &i.name,
                    i.span,
                    SymbolKind::INTERFACE,
                    Some("INTERFACE".into()),
                    children,
                )
            }
        }
    }

    fn pou(&self, p: &Pou, kind: SymbolKind, keyword: &str) -> Option<DocumentSymbol> {
        let mut children: Vec<_> = p.var_blocks.iter().flat_map(|b| self.block(b)).collect();
        children.extend(
            p.oo.methods
                .iter()
                .filter_map(|m| self.pou(&m.pou, SymbolKind::METHOD, "METHOD")),
        );
        children.extend(p.oo.properties.iter().filter_map(|pr| self.property(pr)));
        children.extend(p.actions.iter().filter_map(|a| {
            self.symbol(
                &a.name,
                a.span,
                SymbolKind::FUNCTION,
                Some("ACTION".into()),
                vec![],
            )
        }));
        let detail = match &p.return_type {
            Some(t) => format!("{keyword} : {}", self.text(t.span())),
            None => keyword.to_string(),
        };
        self.symbol(&p.name, p.span, kind, Some(detail), children)
    }

    fn property(&self, p: &Property) -> Option<DocumentSymbol> {
        let detail = format!("PROPERTY : {}", self.text(p.ty.span()));
        self.symbol(&p.name, p.span, SymbolKind::PROPERTY, Some(detail), vec![])
    }

    fn block(&self, b: &VarBlock) -> Vec<DocumentSymbol> {
        let kind = if b.constant {
            SymbolKind::CONSTANT
        } else {
            SymbolKind::VARIABLE
        };
        let keyword = block_keyword(b);
        b.decls
            .iter()
            .flat_map(|d| self.vars(d, &keyword, kind))
            .collect()
    }

    /// One symbol per name of a declaration; the detail is `KEYWORD : TYPE`.
    fn vars(&self, d: &VarDecl, keyword: &str, kind: SymbolKind) -> Vec<DocumentSymbol> {
        let ty = self.text(d.ty.span());
        let detail = if keyword.is_empty() {
            ty.to_string()
        } else {
            format!("{keyword} : {ty}")
        };
        d.names
            .iter()
            .filter_map(|n| self.symbol(n, d.span, kind, Some(detail.clone()), vec![]))
            .collect()
    }

    fn text(&self, span: Span) -> &str {
        text(self.sources, span)
    }

    /// The range of `span` in the file: for a span of a view, where it is in the XML
    /// (the same text, else its element); `None` where it has no place there.
    fn range(&self, span: Span) -> Option<(Span, Range)> {
        let s = super::xml::place(self.views, self.sources, span)?;
        Some((s, self.lines.range(s)))
    }

    /// The symbol of `name`, declared by the text `whole`; `None` when the name has
    /// no place in the file (a view's text made up with no origin in the XML). The
    /// range holds the selection range.
    fn symbol(
        &self,
        name: &Ident,
        whole: Span,
        kind: SymbolKind,
        detail: Option<String>,
        children: Vec<DocumentSymbol>,
    ) -> Option<DocumentSymbol> {
        let whole = if whole.file == name.span.file {
            whole.to(name.span)
        } else {
            name.span
        };
        let (at, selection_range) = self.range(name.span)?;
        let range = match self.range(whole) {
            Some((w, _)) if w.file == at.file => self.lines.range(w.to(at)),
            _ => selection_range,
        };
        #[allow(deprecated)] // `deprecated` is a field every literal must give.
        Some(DocumentSymbol {
            name: self.text(name.span).to_string(),
            detail,
            kind,
            tags: None,
            deprecated: None,
            range,
            selection_range,
            children: (!children.is_empty()).then_some(children),
        })
    }

    /// A symbol with no name of its own in the text (an unnamed global block).
    fn named(
        &self,
        name: &str,
        whole: Span,
        kind: SymbolKind,
        children: Vec<DocumentSymbol>,
    ) -> Option<DocumentSymbol> {
        let (whole, range) = self.range(whole)?;
        let at = Span::new(whole.file, whole.start, whole.start);
        #[allow(deprecated)]
        Some(DocumentSymbol {
            name: name.to_string(),
            detail: None,
            kind,
            tags: None,
            deprecated: None,
            range,
            selection_range: self.lines.range(at),
            children: (!children.is_empty()).then_some(children),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plcc_frontend::source::SourceFile;

    #[test]
    fn names_no_file_declares() {
        let mut sources = SourceMap::new();
        let text = "x := int_to_dint(a) + ABS(b) + GO_TO_START + 16#FF_TO_AB;";
        let f = sources.add(SourceFile::new("a.st", text));
        let hover = |word: &str| builtin_hover(&sources, f, text.find(word).unwrap() as u32 + 1);
        let (span, conv) = hover("int_to_dint").expect("a conversion");
        assert_eq!(&text[span.start as usize..span.end as usize], "int_to_dint");
        assert_eq!(
            conv,
            "```iecst\nINT_TO_DINT(IN : INT) : DINT\n```\n\ntype conversion from `INT` to `DINT`"
        );
        assert!(hover("ABS")
            .expect("ABS")
            .1
            .starts_with("```iecst\nABS(IN : ANY_NUM)"));
        assert_eq!(hover("GO_TO_START"), None);
        assert_eq!(hover("FF_TO_AB"), None);
    }
}
