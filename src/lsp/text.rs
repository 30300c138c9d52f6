//! Positions: plcc's byte offsets into a source file against LSP's lines and UTF-16
//! columns (the protocol's default encoding, the only one this server speaks).

use lsp_types::{Position, Range};
use plcc_frontend::source::SourceFile;
use plcc_ir::diag::Span;

/// A file's text as the editor counts it: the decoded text plcc read, and whether a
/// byte order mark was dropped from its front (the editor still counts it as the
/// first character of line 0).
pub struct Lines<'a> {
    text: &'a str,
    starts: &'a [u32],
    bom: bool,
}

impl<'a> Lines<'a> {
    /// The lines of `file`; `bom` tells whether the editor's text began with a byte
    /// order mark that decoding dropped.
    pub fn new(file: &'a SourceFile, bom: bool) -> Lines<'a> {
        Lines {
            text: &file.text,
            starts: file.line_starts(),
            bom,
        }
    }

    /// The LSP position of a byte offset (clamped to the text, and down to the start
    /// of the character it falls in).
    pub fn position(&self, offset: u32) -> Position {
        let mut offset = (offset as usize).min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = match self.starts.binary_search(&(offset as u32)) {
            Ok(i) => i,
            Err(i) => i.saturating_sub(1),
        };
        let start = self.starts.get(line).copied().unwrap_or(0) as usize;
        let mut col = self.text[start.min(offset)..offset].encode_utf16().count() as u32;
        if line == 0 && self.bom {
            col += 1;
        }
        Position::new(line as u32, col)
    }

    /// The LSP range of a span.
    pub fn range(&self, span: Span) -> Range {
        Range::new(self.position(span.start), self.position(span.end))
    }

    /// The byte offset of an LSP position: a column past the end of its line is the
    /// line's end, a line past the last is the end of the text, and a column inside a
    /// surrogate pair is the start of its character.
    pub fn offset(&self, pos: Position) -> u32 {
        let Some(&start) = self.starts.get(pos.line as usize) else {
            return self.text.len() as u32;
        };
        let line = &self.text[start as usize..];
        let line = &line[..line.find('\n').unwrap_or(line.len())];
        let line = line.strip_suffix('\r').unwrap_or(line);
        let mut want = pos.character;
        if pos.line == 0 && self.bom {
            want = want.saturating_sub(1);
        }
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            let next = units + c.len_utf16() as u32;
            if next > want {
                return start + i as u32;
            }
            units = next;
        }
        start + line.len() as u32
    }
}

/// The position just past the end of `text` (UTF-16 columns).
pub fn end_of(text: &str) -> Position {
    let line = text.matches('\n').count() as u32;
    let last = text.rsplit('\n').next().unwrap_or("");
    Position::new(line, last.encode_utf16().count() as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_columns_count_surrogate_pairs_and_accents() {
        // `é` is 2 bytes and 1 UTF-16 unit; `𝄞` is 4 bytes and 2 units.
        let f = SourceFile::new("a.st", "x\né𝄞y := 1;\r\nz");
        let l = Lines::new(&f, false);
        let y = "x\né𝄞".len() as u32;
        assert_eq!(l.position(y), Position::new(1, 3));
        assert_eq!(l.offset(Position::new(1, 3)), y);
        // Inside the surrogate pair: the start of its character.
        assert_eq!(l.offset(Position::new(1, 2)), "x\né".len() as u32);
        // Past the end of the line (before its \r\n): the line's end.
        assert_eq!(l.offset(Position::new(1, 99)), "x\né𝄞y := 1;".len() as u32);
        assert_eq!(l.offset(Position::new(9, 0)), f.text.len() as u32);
        assert_eq!(l.position(f.text.len() as u32), Position::new(2, 1));
        // An offset inside a character counts from that character's start.
        assert_eq!(l.position(y - 1), Position::new(1, 1));
    }

    #[test]
    fn a_dropped_byte_order_mark_still_counts_on_line_zero() {
        let f = SourceFile::from_bytes("a.st", &b"\xEF\xBB\xBFab\ncd"[..]);
        let l = Lines::new(&f, true);
        assert_eq!(l.position(1), Position::new(0, 2));
        assert_eq!(l.offset(Position::new(0, 2)), 1);
        assert_eq!(l.position(4), Position::new(1, 1));
    }
}
