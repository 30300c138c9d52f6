//! Source files of a build and the mapping from byte offsets to lines and columns.

use std::borrow::Cow;

use plcc_ir::diag::{FileId, Span};

/// Byte offsets where each line of `text` starts.
pub fn line_starts(text: &str) -> Vec<u32> {
    let mut starts = Vec::with_capacity(text.len() / 16);
    starts.push(0u32);
    starts.extend(memchr::memchr_iter(b'\n', text.as_bytes()).map(|i| i as u32 + 1));
    starts
}

/// One source file: its name, its text (decoded to UTF-8), and where its lines start.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The name diagnostics show (the path as given on the command line).
    pub name: String,
    /// The text (borrowed for the standard library, which every build shares).
    pub text: Cow<'static, str>,
    line_starts: Cow<'static, [u32]>,
}

impl SourceFile {
    /// A file with the given name and text.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let text = text.into();
        SourceFile {
            name: name.into(),
            line_starts: Cow::Owned(line_starts(&text)),
            text: Cow::Owned(text),
        }
    }

    /// A file over text that lives as long as the process, with its line table
    /// (from [`line_starts`]) computed once: no copy per build.
    pub fn from_static(
        name: impl Into<String>,
        text: &'static str,
        line_starts: &'static [u32],
    ) -> SourceFile {
        SourceFile {
            name: name.into(),
            text: Cow::Borrowed(text),
            line_starts: Cow::Borrowed(line_starts),
        }
    }

    /// Decodes raw file bytes: UTF-8 (a BOM is dropped), else ISO-8859-1, which maps
    /// every byte to the code point of the same value.
    /// Takes the bytes over: UTF-8 without a BOM is not copied.
    pub fn from_bytes(name: impl Into<String>, bytes: impl Into<Vec<u8>>) -> SourceFile {
        let mut bytes = bytes.into();
        if bytes.starts_with(b"\xEF\xBB\xBF") {
            bytes.drain(..3);
        }
        let text = String::from_utf8(bytes)
            .unwrap_or_else(|e| e.as_bytes().iter().map(|&b| b as char).collect());
        SourceFile::new(name, text)
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: u32) -> (u32, u32) {
        let line = match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        };
        let start = self.line_starts[line] as usize;
        let end = (offset as usize).min(self.text.len());
        let col = self
            .text
            .get(start..end)
            .map_or(end - start, |s| s.chars().count());
        (line as u32 + 1, col as u32 + 1)
    }

    /// Byte offsets where each line starts.
    pub fn line_starts(&self) -> &[u32] {
        &self.line_starts
    }

    /// The text of a span (empty if the span is out of range).
    pub fn slice(&self, span: Span) -> &str {
        self.text
            .get(span.start as usize..span.end as usize)
            .unwrap_or("")
    }
}

/// All source files of a build, indexed by [`FileId`].
#[derive(Debug, Default, Clone)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    /// Adds a file and returns its id.
    pub fn add(&mut self, file: SourceFile) -> FileId {
        self.files.push(file);
        FileId(self.files.len() as u32 - 1)
    }

    /// The file with the given id.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// All files with their ids.
    pub fn iter(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| (FileId(i as u32), f))
    }

    /// How many files there are.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// `file:line:col` of the start of a span.
    pub fn describe(&self, span: Span) -> String {
        let f = self.get(span.file);
        let (l, c) = f.line_col(span.start);
        format!("{}:{}:{}", f.name, l, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_columns() {
        let f = SourceFile::new("a.st", "ab\ncd\n\nx");
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(1), (1, 2));
        assert_eq!(f.line_col(3), (2, 1));
        assert_eq!(f.line_col(7), (4, 1));
    }

    #[test]
    fn latin1_fallback_and_bom() {
        let f = SourceFile::from_bytes("a.st", &b"(* \xE4 *)"[..]);
        assert_eq!(f.text, "(* \u{e4} *)");
        let g = SourceFile::from_bytes("b.st", &b"\xEF\xBB\xBFx"[..]);
        assert_eq!(g.text, "x");
    }
}
