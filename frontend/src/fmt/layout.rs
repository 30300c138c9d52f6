//! Where each line goes: the items split into the lines the user wrote, and each
//! line's indentation from the blocks open at its start (POUs and their members, VAR
//! blocks, TYPE and STRUCT, IF, CASE with its labels, the loops), the statement or
//! declaration a line continues, and the declarations whose `:` are aligned.

use super::items::Item;
use crate::st::lexer::Tok;
use std::ops::Range;

/// One output line.
#[derive(Clone, Debug)]
pub(super) struct Line {
    /// Its items.
    pub items: Range<usize>,
    /// An empty line comes before it.
    pub blank_before: bool,
    /// Indentation in levels.
    pub indent: usize,
    /// A declaration of a VAR block or STRUCT: the block's number and the item index
    /// of its `:`, aligned with the others of the block.
    pub decl: Option<(usize, usize)>,
}

/// The lines, and the `:` of CASE labels and of `ACTION name:` and `STEP name:`
/// (written against what comes before them).
pub(super) struct Layout {
    /// The lines in order.
    pub lines: Vec<Line>,
    /// Per item: written without a space before it (the `:` of CASE labels, of
    /// `ACTION name:` and of IL labels; the `N` of IL's `&N`).
    pub glued: Vec<bool>,
    /// Per item: the operator of an Instruction List instruction (written in upper
    /// case, against a `(` after it).
    pub il_op: Vec<bool>,
}

#[derive(Copy, Clone, PartialEq, Eq, Debug)]
enum Kind {
    /// PROGRAM, FUNCTION, FUNCTION_BLOCK, CLASS, INTERFACE.
    Pou,
    /// METHOD, PROPERTY, its GET and SET, ACTION: written at their owner's level.
    Member,
    /// STEP, INITIAL_STEP, TRANSITION, ACTIONS.
    Sfc,
    /// CONFIGURATION, RESOURCE.
    Config,
    Type,
    Struct,
    Var,
    If,
    Case,
    For,
    While,
    Repeat,
}

#[derive(Copy, Clone, PartialEq, Eq, Debug)]
enum Arm {
    /// Before the first label.
    None,
    /// After a label: statements one level deeper than the labels.
    Label,
    /// After the CASE's ELSE.
    Else,
}

#[derive(Clone, Debug)]
struct Frame {
    kind: Kind,
    closer: Tok,
    /// The level of the line that opens it (and of its END_ line).
    level: usize,
    /// Still in the header (POUs: until the end of the line; IF, CASE and the loops:
    /// until THEN, OF, DO); for REPEAT: after UNTIL.
    header: bool,
    id: usize,
    arm: Arm,
    /// A TRANSITION whose condition is Instruction List (its header ends with `:`):
    /// each line is an instruction, never a continuation.
    il: bool,
}

impl Frame {
    fn content(&self) -> usize {
        match (self.kind, self.arm) {
            (Kind::Case, Arm::Label) => self.level + 2,
            _ => self.level + 1,
        }
    }
}

struct State<'a> {
    text: &'a str,
    items: &'a [Item],
    stack: Vec<Frame>,
    paren: usize,
    /// In the middle of a statement, declaration or header.
    open: bool,
    next_id: usize,
    glued: Vec<bool>,
    /// The previous token's kind.
    prev: Option<Tok>,
    /// The byte ranges of the Instruction List bodies, in order.
    il: &'a [Range<usize>],
    il_op: Vec<bool>,
}

fn is_var_keyword(t: Tok) -> bool {
    matches!(
        t,
        Tok::Var
            | Tok::VarInput
            | Tok::VarOutput
            | Tok::VarInOut
            | Tok::VarTemp
            | Tok::VarGlobal
            | Tok::VarExternal
            | Tok::VarAccess
            | Tok::VarConfig
            | Tok::VarStat
            | Tok::VarInst
    )
}

/// True for the words that close a block or start its next part.
fn ends_block(t: Tok) -> bool {
    t.is_end_keyword() || matches!(t, Tok::Else | Tok::Elsif | Tok::Until)
}

impl<'a> State<'a> {
    fn text(&self, i: usize) -> &'a str {
        &self.text[self.items[i].start..self.items[i].end]
    }

    fn tok(&self, i: usize) -> Tok {
        self.items[i].tok.unwrap_or(Tok::Eof)
    }

    /// The index of the first token after item `i`.
    fn next_token(&self, i: usize) -> Option<usize> {
        (i + 1..self.items.len()).find(|&j| !self.items[j].is_comment())
    }

    fn top(&self) -> Option<&Frame> {
        self.stack.last()
    }

    /// The level of the lines inside the innermost block.
    fn content(&self) -> usize {
        self.top().map_or(0, Frame::content)
    }

    /// The block the token `i` opens, with its END_ keyword.
    fn opener(&self, i: usize) -> Option<(Kind, Tok)> {
        let t = self.tok(i);
        let in_config = self.stack.iter().any(|f| f.kind == Kind::Config);
        Some(match t {
            Tok::Program if !in_config => (Kind::Pou, Tok::EndProgram),
            Tok::Function => (Kind::Pou, Tok::EndFunction),
            Tok::FunctionBlock => (Kind::Pou, Tok::EndFunctionBlock),
            Tok::Configuration => (Kind::Config, Tok::EndConfiguration),
            Tok::Type => (Kind::Type, Tok::EndType),
            Tok::Struct => (Kind::Struct, Tok::EndStruct),
            t if is_var_keyword(t) => (Kind::Var, Tok::EndVar),
            Tok::If => (Kind::If, Tok::EndIf),
            Tok::Case => (Kind::Case, Tok::EndCase),
            Tok::For => (Kind::For, Tok::EndFor),
            Tok::While => (Kind::While, Tok::EndWhile),
            Tok::Repeat => (Kind::Repeat, Tok::EndRepeat),
            Tok::Ident if !self.open && self.paren == 0 => return self.word_opener(i),
            _ => return None,
        })
    }

    /// The words that open a block without being reserved: only where a statement or
    /// member may start and followed by what follows them there (never `:=`, `(`,
    /// `.`, ...: then they are names).
    fn word_opener(&self, i: usize) -> Option<(Kind, Tok)> {
        let word = self.text(i).to_ascii_uppercase();
        let next = self.next_token(i).map(|j| self.tok(j));
        let name_like = matches!(
            next,
            None | Some(
                Tok::Assign
                    | Tok::Arrow
                    | Tok::LParen
                    | Tok::LBracket
                    | Tok::Dot
                    | Tok::Caret
                    | Tok::Colon
                    | Tok::Comma
                    | Tok::Semi
                    | Tok::Eof
            )
        );
        let in_property = self
            .top()
            .is_some_and(|f| f.kind == Kind::Member && f.closer == Tok::EndProperty);
        if matches!(word.as_str(), "GET" | "SET") && in_property {
            if matches!(next, Some(Tok::Assign | Tok::Dot | Tok::LParen)) {
                return None;
            }
            let closer = if word == "GET" {
                Tok::EndGet
            } else {
                Tok::EndSet
            };
            return Some((Kind::Member, closer));
        }
        // In a list of declarations they are names (`step AT %IX0.0 : BOOL`).
        let in_decls = self
            .top()
            .is_some_and(|f| matches!(f.kind, Kind::Var | Kind::Struct | Kind::Type));
        if name_like || in_decls {
            return None;
        }
        Some(match word.as_str() {
            "CLASS" => (Kind::Pou, Tok::EndClass),
            "INTERFACE" => (Kind::Pou, Tok::EndInterface),
            "METHOD" => (Kind::Member, Tok::EndMethod),
            "PROPERTY" => (Kind::Member, Tok::EndProperty),
            "ACTION" => (Kind::Member, Tok::EndAction),
            "RESOURCE" => (Kind::Config, Tok::EndResource),
            "STEP" | "INITIAL_STEP" => (Kind::Sfc, Tok::EndStep),
            "TRANSITION" => (Kind::Sfc, Tok::EndTransition),
            "ACTIONS" if next == Some(Tok::Ident) => (Kind::Sfc, Tok::EndActions),
            _ => return None,
        })
    }

    /// The frame an END_ keyword closes (the innermost with that closer).
    fn closed_by(&self, t: Tok) -> Option<usize> {
        self.stack.iter().rposition(|f| f.closer == t)
    }

    /// At the start of a statement inside a CASE: the index of the `:` ending the
    /// label that starts at token `i`, if one does.
    fn label_colon(&self, i: usize) -> Option<usize> {
        let f = self.top()?;
        if f.kind != Kind::Case || f.header || f.arm == Arm::Else || self.open || self.paren > 0 {
            return None;
        }
        let mut j = i;
        for _ in 0..256 {
            match self.tok(j) {
                Tok::Colon => return Some(j),
                Tok::True | Tok::False => {}
                t if t.is_keyword() => return None,
                Tok::Assign | Tok::Semi | Tok::Arrow | Tok::LParen | Tok::Eof => return None,
                _ => {}
            }
            j = self.next_token(j)?;
        }
        None
    }

    /// At the first token `i` of a line in a body: the index of the `:` of a jump
    /// label (`retry:`) that starts there, if one does.
    fn jump_label_colon(&self, i: usize) -> Option<usize> {
        let f = self.top()?;
        let body = matches!(
            f.kind,
            Kind::Pou
                | Kind::Member
                | Kind::If
                | Kind::Case
                | Kind::For
                | Kind::While
                | Kind::Repeat
        );
        if !body || self.open || self.paren > 0 || self.tok(i) != Tok::Ident {
            return None;
        }
        let c = self.next_token(i)?;
        (self.tok(c) == Tok::Colon).then_some(c)
    }

    /// The indentation of a line whose first token is `i` (before stepping over it).
    fn line_indent(&self, i: usize, label: bool) -> usize {
        let t = self.tok(i);
        let top = self.top();
        if t.is_end_keyword() {
            return self
                .closed_by(t)
                .map_or(self.content(), |k| self.stack[k].level);
        }
        if let Some(f) = top {
            let mid = match t {
                Tok::Else | Tok::Elsif => matches!(f.kind, Kind::If | Kind::Case),
                Tok::Until => f.kind == Kind::Repeat,
                Tok::Then => f.kind == Kind::If,
                Tok::Do => matches!(f.kind, Kind::For | Kind::While),
                Tok::Of => f.kind == Kind::Case && f.header,
                _ => false,
            };
            if mid {
                return f.level;
            }
            if label {
                return f.level + 1;
            }
        }
        if let Some(level) = self.member_level(i) {
            return level;
        }
        // A block opened on a line of its own (`TYPE T :` then `STRUCT`) is no
        // continuation.
        if self.paren == 0 && self.opener(i).is_some() {
            return self.content();
        }
        let closing = matches!(t, Tok::RParen | Tok::RBracket) && self.paren <= 1;
        // UNTIL's condition on lines of its own: one level in from UNTIL.
        let until = top.is_some_and(|f| f.kind == Kind::Repeat && f.header);
        if (self.open || self.paren > 0) && !closing && !until {
            self.content() + 1
        } else {
            self.content()
        }
    }

    /// VAR blocks and methods, properties, accessors and actions of a POU or member
    /// are written at its level; `None` for other tokens.
    fn member_level(&self, i: usize) -> Option<usize> {
        let f = self.top()?;
        if !matches!(f.kind, Kind::Pou | Kind::Member) {
            return None;
        }
        match self.opener(i) {
            Some((Kind::Var | Kind::Member, _)) => Some(f.level),
            _ => None,
        }
    }

    /// The indentation of a line holding only comments, from the state after the
    /// previous line.
    fn comment_indent(&self) -> usize {
        if self.open || self.paren > 0 {
            self.content() + 1
        } else {
            self.content()
        }
    }

    /// Steps over token `i`.
    fn step(&mut self, i: usize) {
        let t = self.tok(i);
        let opener = self.opener(i);
        let level = self.member_level(i).unwrap_or_else(|| self.content());
        let prev = self.prev.replace(t);
        match t {
            Tok::LParen | Tok::LBracket => {
                self.paren += 1;
                self.open = true;
            }
            Tok::RParen | Tok::RBracket => {
                self.paren = self.paren.saturating_sub(1);
                self.open = true;
            }
            Tok::Semi => {
                if self.paren == 0 {
                    self.open = false;
                }
            }
            t if t.is_end_keyword() => {
                if let Some(k) = self.closed_by(t) {
                    self.stack.truncate(k);
                }
                self.open = false;
            }
            Tok::Then | Tok::Do => {
                if let Some(f) = self.stack.last_mut() {
                    f.header = false;
                }
                self.open = false;
            }
            Tok::Of if self.top().is_some_and(|f| f.kind == Kind::Case && f.header) => {
                if let Some(f) = self.stack.last_mut() {
                    f.header = false;
                }
                self.open = false;
            }
            Tok::Until => {
                if let Some(f) = self.stack.last_mut() {
                    if f.kind == Kind::Repeat {
                        f.header = true;
                    }
                }
                self.open = true;
            }
            Tok::Else => {
                if let Some(f) = self.stack.last_mut() {
                    if f.kind == Kind::Case {
                        f.arm = Arm::Else;
                    }
                }
                self.open = false;
            }
            Tok::Colon if self.glued[i] => {
                if let Some(f) = self.stack.last_mut() {
                    if f.kind == Kind::Case {
                        f.arm = Arm::Label;
                    }
                }
                self.open = false;
            }
            Tok::Constant | Tok::Retain | Tok::NonRetain | Tok::Persistent
                if prev.is_some_and(|p| {
                    is_var_keyword(p)
                        || matches!(
                            p,
                            Tok::Constant | Tok::Retain | Tok::NonRetain | Tok::Persistent
                        )
                }) => {}
            _ => match opener {
                Some((kind, closer)) => {
                    if kind == Kind::Var {
                        if let Some(f) = self.stack.last_mut() {
                            f.header = false;
                        }
                    }
                    let header = matches!(
                        kind,
                        Kind::Pou
                            | Kind::Member
                            | Kind::Sfc
                            | Kind::Config
                            | Kind::If
                            | Kind::Case
                            | Kind::For
                            | Kind::While
                    );
                    self.stack.push(Frame {
                        kind,
                        closer,
                        level,
                        header,
                        id: self.next_id,
                        arm: Arm::None,
                        il: false,
                    });
                    self.next_id += 1;
                    self.open = header;
                    if matches!(kind, Kind::Member | Kind::Sfc) {
                        self.glue_header_colon(i);
                    }
                }
                None => self.open = true,
            },
        }
    }

    /// `ACTION name:`, `STEP name:`: the colon against the name.
    fn glue_header_colon(&mut self, i: usize) {
        let Some(n) = self.next_token(i) else { return };
        if self.tok(n) != Tok::Ident {
            return;
        }
        if let Some(c) = self.next_token(n) {
            let word = self.text(i).to_ascii_uppercase();
            if self.tok(c) == Tok::Colon
                && matches!(word.as_str(), "ACTION" | "STEP" | "INITIAL_STEP")
            {
                self.glued[c] = true;
            }
        }
    }

    /// At the end of a line: a POU's or member's header ends there.
    fn line_end(&mut self) {
        if self.paren > 0 {
            return;
        }
        let after_colon = self.prev == Some(Tok::Colon);
        if let Some(f) = self.stack.last_mut() {
            if f.header && matches!(f.kind, Kind::Pou | Kind::Member | Kind::Sfc | Kind::Config) {
                f.header = false;
                self.open = false;
                f.il = f.closer == Tok::EndTransition && after_colon;
            }
            if f.il {
                self.open = false;
            }
        }
    }

    /// True if the token `i` is in an Instruction List body.
    fn in_il(&self, i: usize) -> bool {
        let at = self.items[i].start;
        let k = self.il.partition_point(|r| r.end <= at);
        self.il.get(k).is_some_and(|r| r.contains(&at))
    }

    /// An instruction line of `items` (outside parentheses): its label's `:` glued to
    /// the label, its operator marked.
    fn il_instruction(&mut self, items: Range<usize>) {
        let tokens: Vec<usize> = items.filter(|&j| !self.items[j].is_comment()).collect();
        let mut k = 0;
        if tokens.len() >= 2
            && self.tok(tokens[0]) == Tok::Ident
            && self.tok(tokens[1]) == Tok::Colon
        {
            self.glued[tokens[1]] = true;
            k = 2;
        }
        let Some(&op) = tokens.get(k) else { return };
        let is_op = match self.tok(op) {
            Tok::Ident => crate::il::instr::is_operator(self.text(op)),
            t => matches!(
                t,
                Tok::And | Tok::Or | Tok::Xor | Tok::Mod | Tok::Not | Tok::Amp
            ),
        };
        self.il_op[op] = is_op;
        // `&N` lexes as `&` and the name `N`.
        if let Some(&n) = tokens.get(k + 1) {
            if self.tok(op) == Tok::Amp
                && self.items[n].start == self.items[op].end
                && self.text(n).eq_ignore_ascii_case("N")
            {
                self.glued[n] = true;
            }
        }
    }

    /// For a line whose first token is `first`, in a VAR block or STRUCT: the item
    /// index of the declaration's `:`.
    fn decl_colon(&self, first: usize, items: Range<usize>) -> Option<(usize, usize)> {
        let f = self.top()?;
        if !matches!(f.kind, Kind::Var | Kind::Struct)
            || self.open
            || self.paren > 0
            || self.tok(first) != Tok::Ident
        {
            return None;
        }
        let mut depth = 0usize;
        for j in first..items.end {
            match self.items[j].tok {
                Some(Tok::LParen | Tok::LBracket) => depth += 1,
                Some(Tok::RParen | Tok::RBracket) => depth = depth.saturating_sub(1),
                Some(Tok::Colon) if depth == 0 => return Some((f.id, j)),
                Some(Tok::Semi | Tok::Assign) => return None,
                _ => {}
            }
        }
        None
    }
}

/// Splits `items` into lines and indents them.
pub(super) fn layout(text: &str, items: &[Item], il: &[Range<usize>]) -> Layout {
    let mut st = State {
        il,
        il_op: vec![false; items.len()],
        text,
        items,
        stack: Vec::new(),
        paren: 0,
        open: false,
        next_id: 0,
        glued: vec![false; items.len()],
        prev: None,
    };
    let mut lines: Vec<Line> = Vec::new();
    // Lines holding only comments, with the indentation the state gives them.
    let mut comment_only: Vec<bool> = Vec::new();
    let breaks: Vec<u8> = items.iter().map(|it| it.breaks).collect();
    for (range, blank_before) in super::items::source_lines(&breaks) {
        let first = range.clone().find(|&j| !items[j].is_comment());
        let mut line = Line {
            items: range.clone(),
            blank_before,
            indent: st.comment_indent(),
            decl: None,
        };
        if let Some(first) = first {
            // An Instruction List line is one instruction: nothing continues onto it
            // but what is inside parentheses.
            let il_line = st.paren == 0 && st.in_il(first);
            if il_line {
                st.open = false;
                st.il_instruction(range.clone());
            }
            line.decl = st.decl_colon(first, range.clone());
            for j in range.clone() {
                if items[j].is_comment() {
                    continue;
                }
                let label = st
                    .label_colon(j)
                    .or_else(|| (j == first).then(|| st.jump_label_colon(j)).flatten());
                if let Some(c) = label {
                    st.glued[c] = true;
                }
                if j == first {
                    line.indent = st.line_indent(j, label.is_some());
                }
                st.step(j);
            }
            st.line_end();
            if il_line && st.paren == 0 {
                st.open = false;
            }
        }
        comment_only.push(first.is_none());
        lines.push(line);
    }
    // A line of comments is indented like the next line of code, unless that one
    // closes a block (the comments then stay inside it).
    let mut next_code: Option<(usize, bool)> = None;
    for k in (0..lines.len()).rev() {
        if comment_only[k] {
            if let Some((indent, false)) = next_code {
                lines[k].indent = indent;
            }
        } else {
            let first = lines[k]
                .items
                .clone()
                .find(|&j| !items[j].is_comment())
                .and_then(|j| items[j].tok);
            next_code = Some((lines[k].indent, first.is_some_and(ends_block)));
        }
    }
    Layout {
        lines,
        glued: st.glued,
        il_op: st.il_op,
    }
}
