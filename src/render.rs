//! Renders diagnostics like rustc: code, message, `file:line:col`, the source line and
//! a caret (through codespan-reporting).

use codespan_reporting::diagnostic::{Diagnostic as CsDiagnostic, Label, Severity as CsSeverity};
use codespan_reporting::files::{Error as FilesError, Files};
use codespan_reporting::term::{self, termcolor};
use plcc_frontend::source::SourceMap;
use plcc_ir::diag::{Diagnostic, Severity};
use std::ops::Range;

/// Adapts the front end's source map to codespan-reporting.
struct SourceFiles<'a>(&'a SourceMap);

impl<'a> Files<'a> for SourceFiles<'a> {
    type FileId = u32;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: u32) -> Result<&'a str, FilesError> {
        self.get(id).map(|f| f.name.as_str())
    }

    fn source(&'a self, id: u32) -> Result<&'a str, FilesError> {
        self.get(id).map(|f| &*f.text)
    }

    fn line_index(&'a self, id: u32, byte_index: usize) -> Result<usize, FilesError> {
        let f = self.get(id)?;
        Ok(match f.line_starts().binary_search(&(byte_index as u32)) {
            Ok(i) => i,
            Err(i) => i - 1,
        })
    }

    fn line_range(&'a self, id: u32, line_index: usize) -> Result<Range<usize>, FilesError> {
        let f = self.get(id)?;
        let starts = f.line_starts();
        let start = *starts.get(line_index).ok_or(FilesError::LineTooLarge {
            given: line_index,
            max: starts.len() - 1,
        })? as usize;
        let end = starts
            .get(line_index + 1)
            .map_or(f.text.len(), |&s| s as usize);
        Ok(start..end)
    }
}

impl SourceFiles<'_> {
    fn get(&self, id: u32) -> Result<&plcc_frontend::source::SourceFile, FilesError> {
        if (id as usize) < self.0.len() {
            Ok(self.0.get(plcc_ir::diag::FileId(id)))
        } else {
            Err(FilesError::FileMissing)
        }
    }
}

fn clamp(map: &SourceMap, file: u32, start: u32, end: u32) -> Range<usize> {
    let len = if (file as usize) < map.len() {
        map.get(plcc_ir::diag::FileId(file)).text.len()
    } else {
        0
    };
    let s = (start as usize).min(len);
    let e = (end as usize).clamp(s, len);
    s..e
}

/// Renders diagnostics to a string (no colour).
pub fn render(map: &SourceMap, diags: &[Diagnostic]) -> String {
    let mut first = termcolor::NoColor::new(Vec::new());
    let mut second = termcolor::NoColor::new(Vec::new());
    write_in_halves(map, diags, &mut first, &mut second);
    let mut out = first.into_inner();
    out.extend(second.into_inner());
    String::from_utf8_lossy(&out).into_owned()
}

/// Renders diagnostics to standard error, in colour when it is a terminal.
pub fn to_stderr(map: &SourceMap, diags: &[Diagnostic]) {
    use std::io::IsTerminal;
    let choice = if std::io::stderr().is_terminal() {
        termcolor::ColorChoice::Auto
    } else {
        termcolor::ColorChoice::Never
    };
    // Buffered: thousands of warnings should not cost thousands of syscalls.
    let writer = termcolor::BufferWriter::stderr(choice);
    let (mut first, mut second) = (writer.buffer(), writer.buffer());
    write_in_halves(map, diags, &mut first, &mut second);
    let _ = writer.print(&first);
    let _ = writer.print(&second);
}

/// From this many diagnostics on, they are rendered on two threads.
const PARALLEL_DIAGS: usize = 200;

/// Renders `diags` into `first` then `second`: the first half into `first` and the
/// second half, on another thread, into `second` when there are many; all into
/// `first` otherwise.
fn write_in_halves<W: termcolor::WriteColor + Send>(
    map: &SourceMap,
    diags: &[Diagnostic],
    first: &mut W,
    second: &mut W,
) {
    if diags.len() < PARALLEL_DIAGS || plcc_ir::parallel::threads() < 2 {
        return write(map, diags, first);
    }
    let (a, b) = diags.split_at(diags.len() / 2);
    plcc_ir::parallel::join(|| write(map, a, first), || write(map, b, second));
}

fn write(map: &SourceMap, diags: &[Diagnostic], out: &mut dyn termcolor::WriteColor) {
    let files = SourceFiles(map);
    let config = term::Config {
        chars: term::Chars::ascii(),
        ..Default::default()
    };
    for d in diags {
        let severity = match d.severity {
            Severity::Error => CsSeverity::Error,
            Severity::Warning => CsSeverity::Warning,
        };
        let mut labels = Vec::new();
        if let Some(s) = d.span {
            labels.push(
                Label::primary(s.file.0, clamp(map, s.file.0, s.start, s.end))
                    .with_message(d.label.clone()),
            );
        }
        for (s, m) in &d.secondary {
            labels.push(
                Label::secondary(s.file.0, clamp(map, s.file.0, s.start, s.end))
                    .with_message(m.clone()),
            );
        }
        let cs = CsDiagnostic::new(severity)
            .with_code(d.code)
            .with_message(d.message.clone())
            .with_labels(labels)
            .with_notes(d.notes.clone());
        if term::emit(out, &config, &files, &cs).is_err() {
            // A span the map cannot show: fall back to the plain form.
            let _ = std::io::Write::write_fmt(out, format_args!("{d}\n"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plcc_frontend::source::SourceFile;
    use plcc_ir::diag::Span;

    #[test]
    fn many_diagnostics_render_in_halves_as_in_one_pass() {
        let mut map = SourceMap::new();
        let text: String = (0..600).map(|k| format!("x{k} := {k};\n")).collect();
        let file = map.add(SourceFile::new("many.st", text.clone()));
        let diags: Vec<Diagnostic> = (0..600)
            .map(|k| {
                let start = text.find(&format!("x{k} :=")).unwrap() as u32;
                Diagnostic::warning(
                    "W0001",
                    format!("warning {k}"),
                    Span::new(file, start, start + 2),
                )
                .with_label("here")
            })
            .collect();
        assert!(diags.len() >= PARALLEL_DIAGS);
        let mut one = termcolor::NoColor::new(Vec::new());
        write(&map, &diags, &mut one);
        let one = String::from_utf8(one.into_inner()).unwrap();
        assert_eq!(render(&map, &diags), one);
        assert!(one.find("warning 17\n").unwrap() < one.find("warning 599\n").unwrap());
        assert_eq!(one.matches("many.st:").count(), 600);
    }
}
