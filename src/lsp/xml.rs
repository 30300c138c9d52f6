//! PLCopen XML projects in references, rename, hover and the outline.
//!
//! The front end writes each PLCopen file as a view, IEC text that is a source file
//! of the build of its own, with a map back to the XML
//! ([`plcc_frontend::plcopen::map::SpanMap`]). The index parses the views as it parses
//! an IL file, so names declared or used in an XML project resolve like any other.
//! A use found in a view is shown in the XML only where the map says its text is
//! copied verbatim from the file (a variable's or a POU's name, an ST or IL body, the
//! variable of a contact, a coil or a variable box): there the XML can be edited byte
//! for byte. A use the view makes up from an element (an output of a FUNCTION or
//! METHOD block besides its result, written `name => …`) has no such place:
//! references leave it out, and a rename it would need is refused.

use plcc_frontend::plcopen::View;
use plcc_frontend::source::SourceMap;
use plcc_ir::diag::{FileId, Span};

/// Where a span of the build is for the editor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mapped {
    /// Not in a view: the span itself.
    Text(Span),
    /// In a view, copied verbatim from the XML: the same text there.
    Exact(Span),
    /// In a view, not written verbatim in the XML: the XML element it comes from
    /// (`None` for text the view makes up with no origin).
    Element(Option<Span>),
}

/// The view whose generated file is `file`.
pub fn view_of(views: &[View], file: FileId) -> Option<&View> {
    views.iter().find(|v| v.il == file)
}

/// Where `span` is shown: in its own file, or for a span of a view, in the XML
/// (exactly only when the XML holds the very same text there).
pub fn map(views: &[View], sources: &SourceMap, span: Span) -> Mapped {
    let Some(v) = view_of(views, span.file) else {
        return Mapped::Text(span);
    };
    let text = |file: FileId, start: u32, end: u32| {
        sources.get(file).text.get(start as usize..end as usize)
    };
    if let Some(r) = v.map.exact(span.start, span.end) {
        let written = text(v.xml, r.start, r.end);
        if written.is_some() && written == text(v.il, span.start, span.end) {
            return Mapped::Exact(Span::new(v.xml, r.start, r.end));
        }
    }
    Mapped::Element(
        v.map
            .place(span.start, span.end)
            .map(|r| Span::new(v.xml, r.start, r.end)),
    )
}

/// Where `span` is shown when an element will do: as [`map`], but a span of a view
/// not copied verbatim is the XML element it comes from; `None` for text the view
/// makes up with no origin (for definitions and the outline).
pub fn place(views: &[View], sources: &SourceMap, span: Span) -> Option<Span> {
    match map(views, sources, span) {
        Mapped::Text(s) | Mapped::Exact(s) | Mapped::Element(Some(s)) => Some(s),
        Mapped::Element(None) => None,
    }
}

/// Where `span` is shown when only the same text will do: itself outside views, the
/// XML text a view copies verbatim; `None` for the rest of a view (for hovers).
pub fn exact(views: &[View], sources: &SourceMap, span: Span) -> Option<Span> {
    match map(views, sources, span) {
        Mapped::Text(s) | Mapped::Exact(s) => Some(s),
        Mapped::Element(_) => None,
    }
}

/// The place in a view of an offset in an XML file, where the XML text there is
/// copied verbatim into the view: the file and offset to resolve a name at.
pub fn to_view(views: &[View], xml: FileId, offset: u32) -> Option<(FileId, u32)> {
    let v = views.iter().find(|v| v.xml == xml)?;
    Some((v.il, v.map.view_offset(offset)?))
}

/// The spans of a rename in the files of the folder: the spans found in views moved
/// to the XML, each once. Refused (the message names the XML file and the place)
/// when a use in a view is not written verbatim in the XML, and when two edits
/// would overlap.
pub fn rename_spans(
    views: &[View],
    sources: &SourceMap,
    spans: &[Span],
    old: &str,
) -> Result<Vec<Span>, String> {
    let mut out = Vec::with_capacity(spans.len());
    for &s in spans {
        match map(views, sources, s) {
            Mapped::Text(t) | Mapped::Exact(t) => out.push(t),
            Mapped::Element(element) => {
                let xml = view_of(views, s.file).map_or(s.file, |v| v.xml);
                let name = &sources.get(xml).name;
                let place = match element {
                    Some(e) => {
                        let (line, col) = sources.get(xml).line_col(e.start);
                        format!("at {line}:{col}")
                    }
                    None => {
                        let (line, _) = sources.get(s.file).line_col(s.start);
                        format!("in the text plcc writes for it (line {line} of its view)")
                    }
                };
                return Err(format!(
                    "`{old}` is used in the PLCopen project {name} {place}, where the name is not \
                     written as such (plcc makes that use from the element), so the XML cannot \
                     be edited there safely: rename by hand"
                ));
            }
        }
    }
    out.sort_by_key(|s| (s.file, s.start, s.end));
    out.dedup();
    if let Some(w) = out
        .windows(2)
        .find(|w| w[0].file == w[1].file && w[1].start < w[0].end)
    {
        return Err(format!(
            "two uses of `{old}` overlap at {}: rename by hand",
            sources.describe(w[1])
        ));
    }
    Ok(out)
}

/// A PLCopen file of the folder that has no view (it did not convert: it has
/// errors) and holds `name` as a word: its uses are not known.
pub fn unconverted_use<'a>(
    views: &[View],
    sources: &'a SourceMap,
    xml_files: impl IntoIterator<Item = FileId>,
    name: &str,
) -> Option<&'a str> {
    xml_files
        .into_iter()
        .filter(|&f| !views.iter().any(|v| v.xml == f))
        .map(|f| sources.get(f))
        .find(|src| holds_word(&src.text, name))
        .map(|src| src.name.as_str())
}

/// True if `text` holds `word` (ASCII case ignored) not inside a longer name.
fn holds_word(text: &str, word: &str) -> bool {
    let (t, w) = (text.as_bytes(), word.as_bytes());
    if w.is_empty() || t.len() < w.len() {
        return false;
    }
    let part = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    (0..=t.len() - w.len()).any(|i| {
        t[i..i + w.len()].eq_ignore_ascii_case(w)
            && (i == 0 || !part(t[i - 1]))
            && t.get(i + w.len()).is_none_or(|&b| !part(b))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_found_whole_and_in_any_case() {
        assert!(holds_word("<variable>Motor</variable>", "motor"));
        assert!(holds_word("motor", "MOTOR"));
        assert!(!holds_word("<variable>motor_1</variable>", "motor"));
        assert!(!holds_word("amotor", "motor"));
        assert!(!holds_word("mot", "motor"));
    }
}
