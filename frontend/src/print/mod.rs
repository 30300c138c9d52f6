//! The syntax tree printed back as Structured Text (matiec's iec2iec, for plcc).
//!
//! [`Printer`] writes any [`SourceUnit`] (whichever front end made it: ST, IL, STL,
//! or a PLCopen file's view) as ST that the ST parser reads back to a tree meaning
//! the same. What it writes:
//!
//! - keywords in upper case, one statement per line, four spaces per level;
//! - names as written where the tree's span still shows them (else as interned);
//! - literals by value in a canonical spelling (`T#1h2m`, `D#2024-01-31`,
//!   `'a$N'`), a typed literal with its type (`INT#-7`);
//! - parentheses where the tree has them ([`ExprKind::Paren`]) and where precedence
//!   needs them (trees built by IL and STL have none of their own);
//! - IL's jumps as the CODESYS statements `JMP name;` and `name:`; its compiler
//!   temporaries ([`StmtKind::Let`]) as assignments to variables declared in a
//!   `VAR_TEMP` block of their POU, with the types lowering gave them
//!   ([`TempTypes`]);
//! - what the tree holds only as a span (the steps' and transitions' conditions and
//!   durations of a chart) copied from the source text.
//!
//! Comments are not in the tree: those before an item, between and inside the
//! statements of a body and between the declarations of a VAR block are found in
//! the source text and printed on lines of their own before what they preceded; a
//! comment after a statement or a declaration on its line stays after it. (Comments
//! elsewhere, inside an expression or a type, are not printed; `plcc fmt` keeps every
//! comment where it was.)
//! [`Style::Parenthesised`] and [`Style::Tree`] print every operation in parentheses
//! ([`Style::Tree`] one line per
//! statement, the form the front ends' tests compare.

mod expr;
mod items;
mod stmt;

use crate::ast::*;
use crate::intern::{Interner, Symbol};
use crate::source::SourceMap;
use plcc_ir::diag::{FileId, Span};
use std::collections::HashMap;

/// What lowering made of a compiler temporary ([`StmtKind::Let`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TempType {
    /// It holds a value of this type (an IEC type name).
    Value(String),
    /// Its value is a call that gives none: the call is a statement.
    Void,
}

/// The types of the compiler temporaries of a build, by file and name.
pub type TempTypes = HashMap<(FileId, Symbol), TempType>;

/// How much parenthesising and layout the printer does.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Style {
    /// Source text: parentheses only where written or needed, statements on lines
    /// of their own, indented.
    Source,
    /// Laid out as [`Style::Source`], every operation (binary and prefix) in
    /// parentheses: the parser's reading made visible, for tests.
    Parenthesised,
    /// Every operation in parentheses as in [`Style::Parenthesised`], each statement of the outermost list on
    /// one line (the statements inside it too): the shape of a tree, for tests.
    Tree,
}

/// Where the printer finds the text a tree's spans point into.
#[derive(Copy, Clone)]
enum Source<'a> {
    /// The text of the unit's own file.
    One(&'a str),
    /// Every file of a build (charts' and PLCopen files' trees point into the
    /// texts made of them).
    Map(&'a SourceMap),
}

/// Writes syntax trees as Structured Text.
pub struct Printer<'a> {
    interner: &'a Interner,
    source: Option<Source<'a>>,
    temps: Option<&'a TempTypes>,
    file: FileId,
    style: Style,
    out: String,
    depth: usize,
    /// The file and offset up to which the body's comments are printed.
    seen: (FileId, u32),
}

impl<'a> Printer<'a> {
    /// A printer of trees whose names are in `interner`.
    pub fn new(interner: &'a Interner) -> Printer<'a> {
        Printer {
            interner,
            source: None,
            temps: None,
            file: FileId(0),
            style: Style::Source,
            out: String::new(),
            depth: 0,
            seen: (FileId(0), 0),
        }
    }

    /// The text the tree was parsed from: names keep their spelling, and the parts of
    /// charts the tree holds as spans can be printed.
    pub fn with_source(mut self, text: &'a str) -> Self {
        self.source = Some(Source::One(text));
        self
    }

    /// Like [`Printer::with_source`], for trees whose spans point into any file of
    /// `sources`.
    pub fn with_sources(mut self, sources: &'a SourceMap) -> Self {
        self.source = Some(Source::Map(sources));
        self
    }

    /// The types of the compiler temporaries (see [`TempTypes`]).
    pub fn with_temps(mut self, temps: &'a TempTypes) -> Self {
        self.temps = Some(temps);
        self
    }

    /// Prints in `style`.
    pub fn with_style(mut self, style: Style) -> Self {
        self.style = style;
        self
    }

    /// The whole unit as ST, items separated by a blank line.
    pub fn unit(mut self, unit: &SourceUnit) -> String {
        self.file = unit.file;
        self.seen = (unit.file, 0);
        for (k, item) in unit.items.iter().enumerate() {
            if k > 0 {
                self.out.push('\n');
            }
            let span = item_span(item);
            self.comments_before(span.file, span.start);
            self.item(item);
            self.start_body(span.file, span.end.max(self.seen.1));
        }
        self.out
    }

    /// One expression.
    pub fn expr(mut self, e: &Expr) -> String {
        self.expression(e, 0);
        self.out
    }

    /// Statements, one per line (one line in [`Style::Tree`]).
    pub fn stmts(mut self, stmts: &[Stmt]) -> String {
        self.statements(stmts);
        if self.style == Style::Tree {
            return self.out.trim_end().to_string();
        }
        self.out
    }

    /// A type as declarations write it.
    pub fn type_spec(mut self, t: &TypeSpec) -> String {
        self.type_text(t);
        self.out
    }

    /// One type declaration `T : spec := init;` (without a line break).
    pub fn type_decl(mut self, t: &TypeDecl) -> String {
        self.type_declaration(t);
        self.out.trim().to_string()
    }

    /// One declaration `a, b : T := init;` (without a line break).
    pub fn var_decl(mut self, d: &VarDecl) -> String {
        self.declaration(d);
        self.out.trim_end().to_string()
    }

    // ------------------------------------------------------------------ helpers

    fn push(&mut self, s: &str) {
        self.out.push_str(s);
    }

    /// Starts a line at the current depth (in [`Style::Tree`], a space inside a
    /// statement).
    fn line(&mut self) {
        if self.style == Style::Tree {
            if !self.out.is_empty() && !self.out.ends_with([' ', '\n']) {
                self.out.push(' ');
            }
            return;
        }
        if !self.out.is_empty() && !self.out.ends_with('\n') {
            self.out.push('\n');
        }
        for _ in 0..self.depth {
            self.out.push_str("    ");
        }
    }

    /// Whether every operation is printed in parentheses.
    fn all_parens(&self) -> bool {
        self.style != Style::Source
    }

    /// Ends the current line.
    fn end_line(&mut self) {
        if self.style != Style::Tree {
            self.out.push('\n');
        }
    }

    /// A name as written, if the span shows it (in the source given), else as
    /// interned.
    pub fn name(&self, id: &Ident) -> String {
        let interned = self.interner.name(id.sym);
        if let Some(text) = self.span_text(id.span) {
            if text.eq_ignore_ascii_case(interned) {
                return text.to_string();
            }
        }
        interned.to_string()
    }

    fn push_name(&mut self, id: &Ident) {
        let n = self.name(id);
        self.push(&n);
    }

    /// Names joined by `, `.
    fn push_names(&mut self, ids: &[Ident]) {
        for (k, id) in ids.iter().enumerate() {
            if k > 0 {
                self.push(", ");
            }
            self.push_name(id);
        }
    }

    /// The text of `file`, if the printer has it.
    fn text_of(&self, file: FileId) -> Option<&'a str> {
        match self.source? {
            Source::One(text) => (file == self.file).then_some(text),
            Source::Map(m) => Some(&m.get(file).text),
        }
    }

    /// The source text under `span`, when there is a source and the span is in it.
    fn span_text(&self, span: Span) -> Option<&'a str> {
        self.text_of(span.file)?
            .get(span.start as usize..span.end as usize)
    }

    /// Starts a body at `start` in `file`: comments before it are not its own.
    fn start_body(&mut self, file: FileId, start: u32) {
        self.seen = (file, start);
    }

    /// Prints, each on a line of its own, the comments of `file` between the last one
    /// printed and offset `end` (none if the last thing printed was in another file).
    fn comments_before(&mut self, file: FileId, end: u32) {
        if self.style == Style::Tree {
            return;
        }
        let (seen_file, seen) = self.seen;
        self.seen = (file, end.max(seen));
        if seen_file != file || end <= seen {
            return;
        }
        let Some(text) = self.text_of(file) else {
            return;
        };
        let gap = text.get(seen as usize..end as usize).unwrap_or("");
        for c in comments_in(gap) {
            self.line();
            self.push(c);
            self.end_line();
        }
    }

    /// After what was printed for the source text ending at `end` in `file`: the
    /// comment that follows it on the same source line (after a `;` and blanks),
    /// printed on the same line.
    fn trailing_comment(&mut self, file: FileId, end: u32) {
        let (seen_file, seen) = self.seen;
        if self.style == Style::Tree || seen_file != file || end < seen {
            return;
        }
        let Some(rest) = self.text_of(file).and_then(|t| t.get(end as usize..)) else {
            return;
        };
        let line = &rest[..rest.find('\n').unwrap_or(rest.len())];
        let skipped = line.len() - line.trim_start_matches([' ', '\t', ';']).len();
        if let Some(c) = comment_at(&rest[skipped..]) {
            self.push(" ");
            self.push(c.trim_end());
            self.seen = (file, end + (skipped + c.len()) as u32);
        }
    }

    /// The source text under `span`, or a comment saying it is not there.
    fn copied(&self, span: Span) -> String {
        match self.span_text(span) {
            Some(t) => t.trim().to_string(),
            None => "(* not available without the source text *)".to_string(),
        }
    }
}

/// The whole declaration an item is.
fn item_span(item: &Item) -> Span {
    match item {
        Item::Pou(p) => p.span,
        Item::Type(t) => t.span,
        Item::Globals(b) => b.span,
        Item::Configuration(c) => c.span,
        Item::Action(a) => a.span,
        Item::Interface(i) => i.span,
    }
}

/// The comment (`(* *)`, `/* */`, `//`) that `text` starts with, if it starts with
/// one (to its end, or to the end of `text` if it is not closed).
fn comment_at(text: &str) -> Option<&str> {
    let until = |end: &str| {
        text[2..]
            .find(end)
            .map_or(text.len(), |k| 2 + k + end.len())
    };
    let len = match text.get(..2)? {
        "(*" => until("*)"),
        "/*" => until("*/"),
        "//" => text.find('\n').unwrap_or(text.len()),
        _ => return None,
    };
    Some(&text[..len])
}

/// The comments (`(* *)`, `/* */`, `//`) in `text`, a stretch of ST, IL or STL
/// source: strings and pragmas are stepped over.
fn comments_in(text: &str) -> Vec<&str> {
    let b = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if let Some(c) = text.get(i..).and_then(comment_at) {
            found.push(c.trim_end());
            i += c.len();
            continue;
        }
        i = match b[i] {
            b'{' => text[i..].find('}').map_or(b.len(), |k| i + k + 1),
            q @ (b'\'' | b'"') => {
                let mut j = i + 1;
                while j < b.len() && b[j] != q {
                    j += if b[j] == b'$' { 2 } else { 1 };
                }
                j + 1
            }
            _ => i + 1,
        };
    }
    found
}

/// Prints `e` in [`Style::Tree`] (for tests and messages).
pub fn tree(e: &Expr, interner: &Interner) -> String {
    Printer::new(interner).with_style(Style::Tree).expr(e)
}

#[cfg(test)]
mod tests;
