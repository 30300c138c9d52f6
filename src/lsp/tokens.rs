//! Semantic tokens (`textDocument/semanticTokens/full`) of a Structured Text or
//! Instruction List file: what each word is, for editors that colour by meaning
//! rather than by a grammar. In IL, an operator (`LD`, `JMPC`, `CAL`...) that starts
//! a line or follows the line's label is a keyword.
//!
//! The text is lexed again; keywords, numbers, strings and comments come from the
//! tokens and the gaps between them, names from the index ([`Index::names_in`]): a
//! variable, a parameter (VAR_INPUT, VAR_OUTPUT, VAR_IN_OUT), a function, a function
//! block or class, a program, a method, a property, a type, a field, an enumeration
//! value, an interface. A name that resolves to nothing is an elementary type, a
//! standard function, or left uncoloured. Tokens never span lines (comments and
//! strings over several lines become one token per line), as clients without
//! multiline support need.

use super::index::{Decl, Index};
use super::text::Lines;
use lsp_types::{SemanticToken, SemanticTokenType, SemanticTokensLegend};
use plcc_frontend::ast::{PouKind, VarKind};
use plcc_frontend::intern::Interner;
use plcc_frontend::st::lexer::{self, Tok};
use plcc_ir::diag::FileId;

/// The token types, in the order of the legend (a token's type is its index here).
const TYPES: &[SemanticTokenType] = &[
    SemanticTokenType::KEYWORD,
    SemanticTokenType::COMMENT,
    SemanticTokenType::STRING,
    SemanticTokenType::NUMBER,
    SemanticTokenType::VARIABLE,
    SemanticTokenType::PARAMETER,
    SemanticTokenType::FUNCTION,
    SemanticTokenType::CLASS,
    SemanticTokenType::NAMESPACE,
    SemanticTokenType::METHOD,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::TYPE,
    SemanticTokenType::ENUM_MEMBER,
    SemanticTokenType::INTERFACE,
];

/// The elementary types of IEC 61131-3 (names, not keywords, to the lexer).
pub(super) const ELEMENTARY: &[&str] = &[
    "BOOL",
    "SINT",
    "INT",
    "DINT",
    "LINT",
    "USINT",
    "UINT",
    "UDINT",
    "ULINT",
    "BYTE",
    "WORD",
    "DWORD",
    "LWORD",
    "REAL",
    "LREAL",
    "TIME",
    "LTIME",
    "DATE",
    "LDATE",
    "TIME_OF_DAY",
    "TOD",
    "LTOD",
    "DATE_AND_TIME",
    "DT",
    "LDT",
    "STRING",
    "WSTRING",
    "CHAR",
    "WCHAR",
];

/// The legend the server announces.
pub fn legend() -> SemanticTokensLegend {
    SemanticTokensLegend {
        token_types: TYPES.to_vec(),
        token_modifiers: Vec::new(),
    }
}

fn type_index(t: &SemanticTokenType) -> u32 {
    TYPES.iter().position(|x| x == t).expect("in the legend") as u32
}

/// The type of a name that resolves to `d`.
fn of_decl(d: &Decl<'_>) -> SemanticTokenType {
    match *d {
        Decl::Var { block, .. } => match block.kind {
            VarKind::Input | VarKind::Output | VarKind::InOut => SemanticTokenType::PARAMETER,
            _ => SemanticTokenType::VARIABLE,
        },
        Decl::Pou(p) => match p.kind {
            PouKind::Function => SemanticTokenType::FUNCTION,
            PouKind::FunctionBlock => SemanticTokenType::CLASS,
            PouKind::Program => SemanticTokenType::NAMESPACE,
        },
        Decl::Method(..) => SemanticTokenType::METHOD,
        Decl::Property(..) | Decl::Field { .. } => SemanticTokenType::PROPERTY,
        Decl::Action(_) => SemanticTokenType::FUNCTION,
        Decl::Type(_) => SemanticTokenType::TYPE,
        Decl::EnumValue { .. } => SemanticTokenType::ENUM_MEMBER,
        Decl::Interface(_) => SemanticTokenType::INTERFACE,
        Decl::Config(_) | Decl::Resource(_) => SemanticTokenType::NAMESPACE,
        Decl::Task(_) | Decl::Instance(_) => SemanticTokenType::VARIABLE,
    }
}

/// The semantic tokens of the Structured Text (or, `il`, Instruction List) file
/// `file`, whose text `lines` holds.
pub fn tokens(
    index: &Index,
    file: FileId,
    text: &str,
    lines: &Lines<'_>,
    il: bool,
) -> Vec<SemanticToken> {
    let mut interner = Interner::new();
    let mut diags = Vec::new();
    let lexed = lexer::lex(file, text, &mut interner, &mut diags);
    let mut names = Names::new(index, file);
    // (start, end, type) in text order.
    let mut raw: Vec<(u32, u32, u32)> = Vec::new();
    let mut gap_start = 0u32;
    // The kinds of the tokens on the line so far (IL: where an operator may stand).
    let mut on_line: Vec<Tok> = Vec::new();
    for (k, t) in lexed.tokens.iter().enumerate() {
        if t.newline_before() {
            on_line.clear();
        }
        // First on its line, or after `label:`; not a variable an ST statement
        // assigns (`S := 1;`).
        let operator_place = (on_line.is_empty() || on_line.as_slice() == [Tok::Ident, Tok::Colon])
            && lexed
                .tokens
                .get(k + 1)
                .is_none_or(|n| n.kind != Tok::Assign);
        on_line.push(t.kind);
        comments(text, gap_start, t.start, &mut raw);
        gap_start = t.end;
        let word = &text[t.start as usize..t.end as usize];
        let ty = match t.kind {
            Tok::Eof => break,
            Tok::Ident if il && operator_place && plcc_frontend::il::is_operator(word) => {
                Some(SemanticTokenType::KEYWORD)
            }
            Tok::Ident => names.at(t.start, word),
            Tok::Lit if word.starts_with(['\'', '"']) => Some(SemanticTokenType::STRING),
            Tok::Lit => Some(SemanticTokenType::NUMBER),
            // STRING and WSTRING are reserved (for `STRING(n)`), but types.
            k if k.is_keyword() && ELEMENTARY.iter().any(|e| e.eq_ignore_ascii_case(word)) => {
                Some(SemanticTokenType::TYPE)
            }
            k if k.is_keyword() => Some(SemanticTokenType::KEYWORD),
            _ => None,
        };
        if let Some(ty) = ty {
            raw.push((t.start, t.end, type_index(&ty)));
        }
    }
    encode(&raw, text, lines)
}

/// The names of a file in text order, walked along with its tokens.
struct Names<'i> {
    names: Vec<(plcc_ir::diag::Span, Decl<'i>)>,
    next: usize,
}

impl<'i> Names<'i> {
    fn new(index: &'i Index, file: FileId) -> Names<'i> {
        Names {
            names: index.names_in(file),
            next: 0,
        }
    }

    /// The type of the name `word` starting at byte `start` (names are asked for in
    /// text order): what it resolves to, else an elementary type or a standard
    /// function, else nothing.
    fn at(&mut self, start: u32, word: &str) -> Option<SemanticTokenType> {
        while self.next < self.names.len() && self.names[self.next].0.start < start {
            self.next += 1;
        }
        match self.names.get(self.next) {
            Some((span, d)) if span.start == start => Some(of_decl(d)),
            _ if ELEMENTARY.iter().any(|e| e.eq_ignore_ascii_case(word)) => {
                Some(SemanticTokenType::TYPE)
            }
            _ if plcc_frontend::lower::STANDARD_FUNCTIONS
                .iter()
                .any(|(f, _)| f.eq_ignore_ascii_case(word)) =>
            {
                Some(SemanticTokenType::FUNCTION)
            }
            _ => None,
        }
    }
}

/// The semantic tokens of the PLC-UD STL file `file`, whose text `lines` holds: its
/// reserved words, numbers, comments and pragma lines, and its names as in ST.
pub fn stl_tokens(
    index: &Index,
    file: FileId,
    text: &str,
    lines: &Lines<'_>,
) -> Vec<SemanticToken> {
    use plcc_frontend::stl::lexer::{self as stl, Tok as T};
    let mut interner = Interner::new();
    let lexed = stl::lex(file, text, &mut interner, &mut Vec::new());
    let mut names = Names::new(index, file);
    let mut raw: Vec<(u32, u32, u32)> = Vec::new();
    let mut gap_start = 0u32;
    for t in &lexed.tokens {
        comments(text, gap_start, t.start, &mut raw);
        gap_start = t.end;
        let word = &text[t.start as usize..t.end as usize];
        let ty = match t.kind {
            T::Eof => break,
            T::Ident(_) => names.at(t.start, word),
            T::Int(_) | T::Real => Some(SemanticTokenType::NUMBER),
            T::Pragma => Some(SemanticTokenType::COMMENT),
            k if k.is_keyword() => Some(SemanticTokenType::KEYWORD),
            _ => None,
        };
        if let Some(ty) = ty {
            raw.push((t.start, t.end, type_index(&ty)));
        }
    }
    encode(&raw, text, lines)
}

/// The comments and pragmas in `text[from..to]` (a gap between tokens): each line's
/// stretch from its first to its last non-blank character.
fn comments(text: &str, from: u32, to: u32, out: &mut Vec<(u32, u32, u32)>) {
    let Some(gap) = text.get(from as usize..to as usize) else {
        return;
    };
    let mut at = from;
    for line in gap.split_inclusive('\n') {
        let trimmed = line.trim_start();
        let lead = (line.len() - trimmed.len()) as u32;
        let body = trimmed.trim_end();
        if !body.is_empty() {
            let start = at + lead;
            out.push((
                start,
                start + body.len() as u32,
                type_index(&SemanticTokenType::COMMENT),
            ));
        }
        at += line.len() as u32;
    }
}

/// The protocol's relative encoding; a token over several lines becomes one per line.
fn encode(raw: &[(u32, u32, u32)], text: &str, lines: &Lines<'_>) -> Vec<SemanticToken> {
    let mut out = Vec::new();
    let (mut line, mut col) = (0u32, 0u32);
    let mut push = |start: u32, end: u32, ty: u32| {
        let (a, b) = (lines.position(start), lines.position(end));
        if b.line != a.line || b.character <= a.character {
            return;
        }
        let delta_line = a.line - line;
        let delta_start = if delta_line == 0 {
            a.character - col
        } else {
            a.character
        };
        out.push(SemanticToken {
            delta_line,
            delta_start,
            length: b.character - a.character,
            token_type: ty,
            token_modifiers_bitset: 0,
        });
        (line, col) = (a.line, a.character);
    };
    for &(start, end, ty) in raw {
        let piece = &text[start as usize..end as usize];
        let mut at = start;
        for part in piece.split_inclusive('\n') {
            let body = part.trim_end_matches(['\n', '\r']);
            push(at, at + body.len() as u32, ty);
            at += part.len() as u32;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_type_is_in_the_legend_once() {
        for (k, t) in TYPES.iter().enumerate() {
            assert_eq!(type_index(t), k as u32);
        }
    }

    #[test]
    fn a_gap_gives_one_comment_token_per_line() {
        let text = "x (* one\n   two *) // three\ny";
        let mut out = Vec::new();
        comments(text, 1, text.len() as u32 - 1, &mut out);
        let pieces: Vec<&str> = out
            .iter()
            .map(|&(a, b, _)| &text[a as usize..b as usize])
            .collect();
        assert_eq!(pieces, ["(* one", "two *) // three"]);
    }
}
