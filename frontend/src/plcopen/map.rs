//! The IL made from a ladder file, and the map from its text back to the XML.
//!
//! The view is a source file of its own (so that it can be parsed by the IL front
//! end, printed by `--emit il` and shown in listings); the map sends a diagnostic about
//! it back to the XML element it was made from: exactly where the text is copied
//! verbatim from the file (a variable's name, an ST body), else to the element.

use super::xml::{Piece, Text};
use plcc_ir::diag::{Diagnostic, FileId, Span};
use std::ops::Range;

/// A region of the generated text and where it comes from in the XML.
#[derive(Debug, Clone)]
struct Seg {
    /// The region in the generated text.
    start: u32,
    end: u32,
    /// Where it comes from, as a whole.
    fallback: Range<u32>,
    /// Parts copied verbatim (`at` is an offset in the generated text).
    exact: Vec<Piece>,
}

/// From offsets in the generated IL to offsets in the XML.
#[derive(Debug, Clone, Default)]
pub struct SpanMap {
    segs: Vec<Seg>,
}

impl SpanMap {
    /// The XML range a range of the generated text comes from, if any: the innermost
    /// region that contains its start.
    fn lookup(&self, start: u32, end: u32) -> Option<Range<u32>> {
        let seg = self
            .segs
            .iter()
            .filter(|s| s.start <= start && start < s.end.max(s.start + 1))
            .min_by_key(|s| s.end - s.start)?;
        let end = end.max(start);
        for p in &seg.exact {
            let (lo, hi) = (p.at, p.at + p.len);
            if lo <= start && start < hi.max(lo + 1) {
                let s = p.src + (start - lo);
                let e = if end <= hi {
                    p.src + (end - lo)
                } else {
                    p.src + p.len
                };
                return Some(s..e);
            }
        }
        Some(seg.fallback.clone())
    }

    /// The XML range the range `start..end` of the generated text is copied from
    /// verbatim: `Some` only when the whole (non-empty) range lies inside one part
    /// copied from the file (a variable's name, a POU's name, an ST or IL body, the
    /// variable of a contact or coil), never for text the view makes up or changes
    /// (keywords, names it derives, a value it quotes) and that therefore maps only to
    /// its element. What the language server renames in the XML.
    pub fn exact(&self, start: u32, end: u32) -> Option<Range<u32>> {
        if end <= start {
            return None;
        }
        self.segs
            .iter()
            .flat_map(|s| &s.exact)
            .find(|p| p.at <= start && end <= p.at + p.len)
            .map(|p| p.src + (start - p.at)..p.src + (end - p.at))
    }

    /// The offset in the generated text that the XML offset `xml` is copied to, if it
    /// lies in (or just after) a part copied verbatim: the first such part when the
    /// view writes one text more than once. The inverse of [`SpanMap::exact`], for
    /// requests made on the XML file.
    pub fn view_offset(&self, xml: u32) -> Option<u32> {
        self.segs
            .iter()
            .flat_map(|s| &s.exact)
            .filter(|p| p.src <= xml && xml <= p.src + p.len)
            .map(|p| p.at + (xml - p.src))
            .min()
    }

    /// The XML range a range of the generated text comes from, exact or its element
    /// (as diagnostics are moved); `None` for text made up with no origin.
    pub fn place(&self, start: u32, end: u32) -> Option<Range<u32>> {
        self.lookup(start, end)
    }

    /// Moves the spans of `d` that point into the generated file `il` to the XML file
    /// `xml`, where the map knows their origin.
    pub fn remap(&self, d: &mut Diagnostic, il: FileId, xml: FileId) {
        let map = |s: Span| -> Span {
            if s.file != il {
                return s;
            }
            match self.lookup(s.start, s.end) {
                Some(r) => Span::new(xml, r.start, r.end),
                None => s,
            }
        };
        d.span = d.span.map(map);
        for (s, _) in &mut d.secondary {
            *s = map(*s);
        }
    }
}

/// Generated text with its map.
#[derive(Debug, Default)]
pub(crate) struct Out {
    /// The text so far.
    pub text: String,
    /// Its map.
    pub map: SpanMap,
}

impl Out {
    /// The current length, as an offset.
    pub fn pos(&self) -> u32 {
        self.text.len() as u32
    }

    /// Appends generated text.
    pub fn push(&mut self, s: &str) {
        self.text.push_str(s);
    }

    /// Appends `s`, which stands for `t`: exact where `s` is `t`'s value.
    pub fn push_as(&mut self, s: &str, t: &Text) {
        let start = self.pos();
        self.text.push_str(s);
        let exact = if s == t.value {
            t.exact
                .iter()
                .map(|p| Piece {
                    at: start + p.at,
                    src: p.src,
                    len: p.len,
                })
                .collect()
        } else {
            Vec::new()
        };
        self.map.segs.push(Seg {
            start,
            end: self.pos(),
            fallback: t.range.clone(),
            exact,
        });
    }

    /// Appends a text's value.
    pub fn push_text(&mut self, t: &Text) {
        self.push_as(&t.value, t);
    }

    /// Maps the text from `start` to here to `fallback` (for whatever inside it has no
    /// more precise origin).
    pub fn mark(&mut self, start: u32, fallback: Range<u32>) {
        let end = self.pos();
        if end > start {
            self.map.segs.push(Seg {
                start,
                end,
                fallback,
                exact: Vec::new(),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(value: &str, src: u32) -> Text {
        Text {
            value: value.into(),
            range: src - 10..src + value.len() as u32 + 10,
            exact: vec![Piece {
                at: 0,
                src,
                len: value.len() as u32,
            }],
        }
    }

    #[test]
    fn exact_parts_map_byte_for_byte_and_the_rest_to_the_element() {
        let mut o = Out::default();
        o.push("    ");
        let line = o.pos();
        o.push("AND ");
        o.push_text(&text("start", 100));
        o.mark(line, 40..60);
        let m = &o.map;
        // `start` itself, and a part of it.
        assert_eq!(m.lookup(8, 13), Some(100..105));
        assert_eq!(m.lookup(9, 11), Some(101..103));
        // The operator: the element.
        assert_eq!(m.lookup(4, 7), Some(40..60));
        // Before the line: nothing.
        assert_eq!(m.lookup(0, 2), None);
    }

    #[test]
    fn exact_only_inside_one_verbatim_part_and_back() {
        let mut o = Out::default();
        o.push("    ");
        let line = o.pos();
        o.push("AND ");
        o.push_text(&text("start", 100));
        o.push(" ");
        o.push_as("STOP", &text("stop", 300));
        o.mark(line, 40..60);
        let m = &o.map;
        // The name, and a part of it: exact.
        assert_eq!(m.exact(8, 13), Some(100..105));
        assert_eq!(m.exact(9, 11), Some(101..103));
        // Past its end, on the operator, empty, or a text written otherwise: not.
        assert_eq!(m.exact(8, 14), None);
        assert_eq!(m.exact(4, 7), None);
        assert_eq!(m.exact(8, 8), None);
        assert_eq!(m.exact(14, 18), None);
        assert_eq!(m.place(14, 18), Some(290..314));
        // Back from the XML: inside the name or just after it.
        assert_eq!(m.view_offset(100), Some(8));
        assert_eq!(m.view_offset(105), Some(13));
        assert_eq!(m.view_offset(99), None);
        assert_eq!(m.view_offset(300), None);
    }

    #[test]
    fn remap_moves_only_spans_of_the_generated_file() {
        let mut o = Out::default();
        o.push_text(&text("motor", 200));
        let (il, xml, other) = (FileId(3), FileId(2), FileId(1));
        let mut d = Diagnostic::error("E0201", "x", Span::new(il, 0, 5))
            .with_secondary(Span::new(other, 7, 9), "elsewhere");
        o.map.remap(&mut d, il, xml);
        assert_eq!(d.span, Some(Span::new(xml, 200, 205)));
        assert_eq!(d.secondary[0].0, Span::new(other, 7, 9));
    }
}
