// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
#![warn(missing_docs)]
//! plcc's front ends: source files, the shared syntax tree, the Structured Text parser,
//! the Instruction List, PLC-UD STL and ladder (PLCopen XML) front ends, semantic
//! analysis and lowering to the IR.
//!
//! [`compile`] is the entry point: it parses every input file in its language, adds the
//! standard function blocks, checks everything, and lowers it to one IR module.

pub mod ast;
pub mod codes;
pub mod direct;
pub mod edges;
pub mod eno;
pub mod fmt;
pub mod il;
pub mod intern;
pub mod lower;
pub mod plcopen;
pub mod print;
pub mod sfc;
pub mod source;
pub mod st;
pub mod stl;
#[cfg(test)]
mod test_files;
pub mod types;
pub mod visit;

use plcc_ir::diag::{Diagnostic, FileId};
use plcc_ir::Module;
use source::{SourceFile, SourceMap};

pub use lower::{LowerOptions, ParallelBodies, PrintAs};

/// The source languages plcc reads.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Lang {
    /// IEC 61131-3 Structured Text (`.st`).
    St,
    /// Structured Text in the dialect of the CPDev compiler (`.cst`, the text it
    /// consumes): ST, where an FB instance's internal variables may be used from
    /// outside (warning W0208) and REAL to integer conversions truncate, as CPDev's do.
    Cst,
    /// IEC 61131-3 Instruction List (`.il`).
    Il,
    /// The STL of the PLC-UD controller (`.stl`).
    Stl,
    /// Ladder diagrams in PLCopen TC6 XML (`.xml`).
    Ld,
}

impl Lang {
    /// The language of a file from its extension (case-insensitive).
    pub fn from_path(path: &str) -> Option<Lang> {
        let ext = std::path::Path::new(path).extension()?.to_str()?;
        Lang::from_name(ext)
    }

    /// The language named on the command line (`st`, `il`, `stl`, `xml`/`ld`).
    pub fn from_name(name: &str) -> Option<Lang> {
        Some(match name.to_ascii_lowercase().as_str() {
            "st" => Lang::St,
            "cst" => Lang::Cst,
            "il" => Lang::Il,
            "stl" => Lang::Stl,
            "xml" | "ld" => Lang::Ld,
            _ => return None,
        })
    }

    /// The language's name.
    pub fn name(self) -> &'static str {
        match self {
            Lang::St => "Structured Text",
            Lang::Cst => "CPDev Structured Text",
            Lang::Il => "Instruction List",
            Lang::Stl => "PLC-UD STL",
            Lang::Ld => "ladder (PLCopen XML)",
        }
    }
}

/// The file name the standard library's diagnostics point at.
pub const STDLIB_NAME: &str = "<plcc standard library>";

/// The result of compiling: the module if there was no error, and every diagnostic
/// (warnings included) in the order found.
pub struct Compiled {
    /// The unoptimised IR module, if there were no errors (without function bodies
    /// under [`LowerOptions::check_only`]).
    pub module: Option<Module>,
    /// Errors and warnings.
    pub diagnostics: Vec<Diagnostic>,
    /// Wall time of each phase (`parse`, `lower`), for `PLCC_TIME_PASSES`.
    pub timings: Vec<(&'static str, std::time::Duration)>,
    /// The syntax trees, handed back so that a short-lived caller (the command line)
    /// can skip freeing them node by node.
    pub syntax: Vec<ast::SourceUnit>,
    /// The PLCopen files of the build and their views (for `--emit st`, `ld-text`).
    pub ladder: Vec<plcopen::View>,
    /// The files with charts, their ST and drawings (for `--emit sfc-text`).
    pub charts: Vec<sfc::View>,
    /// With [`LowerOptions::print`], when the build has no error: its files printed
    /// as Structured Text ([`print`](mod@crate::print)), each after a comment naming it, or as one
    /// PLCopen XML project ([`plcopen::export`]).
    pub printed: Option<String>,
}

/// Parses, checks and lowers the given files (already in `sources`) to one module.
/// The standard library is added to `sources` so diagnostics can point into it. The
/// files of `opts.library` are compiled like the others, but their PROGRAMs run only
/// when named (see [`LowerOptions::library`]).
pub fn compile(
    sources: &mut SourceMap,
    inputs: &[(FileId, Lang)],
    opts: &LowerOptions,
) -> Compiled {
    let started = std::time::Instant::now();
    let (std_text, std_lines) = lower::std_library_source();
    let std_file = sources.add(SourceFile::from_static(STDLIB_NAME, std_text, std_lines));
    let (std_unit, mut interner, mut diagnostics) = parse_std_library(std_file);
    let mut units = Vec::with_capacity(inputs.len() + 1);
    let mut ladder = Vec::new();
    // The bodies each IL file holds in IL (for `--emit plcopen`).
    let mut il_bodies = Vec::new();
    // A library's units: a ladder file's unit is its IL view.
    let mut opts = std::borrow::Cow::Borrowed(opts);
    for &(file, lang) in inputs {
        match lang {
            Lang::St | Lang::Cst => units.push(st::parse(
                file,
                &sources.get(file).text,
                &mut interner,
                &mut diagnostics,
            )),
            Lang::Il => {
                let (unit, bodies) = il::parse_with_bodies(
                    file,
                    &sources.get(file).text,
                    &mut interner,
                    &mut diagnostics,
                );
                il_bodies.push((file, bodies));
                units.push(unit);
            }
            Lang::Stl => units.push(stl::parse(
                file,
                &sources.get(file).text,
                &mut interner,
                &mut diagnostics,
            )),
            Lang::Ld => {
                // The ladder file becomes IL text, a source file of its own, which the
                // IL front end reads; diagnostics about it go back to the XML below.
                let name = sources.get(file).name.clone();
                let Some(c) = plcopen::convert(
                    file,
                    &name,
                    &sources.get(file).text,
                    &opts.plcopen,
                    &mut diagnostics,
                ) else {
                    // Reported; an empty unit keeps `units` in step with `inputs`.
                    units.push(ast::SourceUnit {
                        file,
                        items: Vec::new(),
                    });
                    continue;
                };
                let il_file = sources.add(SourceFile::new(plcopen::il_view_name(&name), c.il));
                if opts.library.contains(&file) {
                    opts.to_mut().library.push(il_file);
                }
                units.push(il::parse(
                    il_file,
                    &sources.get(il_file).text,
                    &mut interner,
                    &mut diagnostics,
                ));
                ladder.push(plcopen::View {
                    xml: file,
                    il: il_file,
                    map: c.map,
                    ld_text: c.ld_text,
                    dialect: c.dialect,
                });
            }
        }
    }
    for (k, &(file, lang)) in inputs.iter().enumerate() {
        nothing_to_compile(sources, file, lang, units.get(k), &mut diagnostics);
    }
    // The units the IL front end read (IL files, the ST views of PLCopen files).
    let il_files: Vec<FileId> = units
        .iter()
        .zip(inputs)
        .filter(|(_, (_, lang))| matches!(lang, Lang::Il | Lang::Ld))
        .map(|(u, _)| u.file)
        .collect();
    let charts = sfc::expand(
        &mut units,
        sources,
        &mut interner,
        opts.sfc,
        &il_files,
        &mut diagnostics,
    );
    // Printed as the user wrote them: before addresses become names and globals move.
    let printable = (opts.print != PrintAs::Nothing).then(|| units.clone());
    direct::resolve(&mut units, sources, &mut interner, &mut diagnostics);
    if let Some(g) = globals_unit(&mut units, &mut interner) {
        units.push(g);
    }
    eno::declare(&mut units, sources, &mut interner);
    edges::expand(&mut units, &mut interner, &mut diagnostics);
    let mut timings = vec![("parse", started.elapsed())];
    if diagnostics.iter().any(|d| d.is_error()) {
        sfc::remap_all(&charts, &mut diagnostics);
        plcopen::remap_all(&ladder, &mut diagnostics);
        return Compiled {
            module: None,
            diagnostics,
            timings,
            syntax: units,
            ladder,
            charts,
            printed: None,
        };
    }
    let started = std::time::Instant::now();
    let all: Vec<&ast::SourceUnit> = std::iter::once(std_unit).chain(&units).collect();
    let mut lowerer = lower::Lowerer::new(sources, &mut interner, &all);
    lowerer.cpdev_files = inputs
        .iter()
        .filter(|(_, l)| *l == Lang::Cst)
        .map(|(f, _)| *f)
        .collect();
    let lower_opts = dialect_of_files(&opts, &ladder);
    let mut lowered = lowerer.run(1, &lower_opts);
    let module = lowered.module;
    diagnostics.append(&mut lowered.diagnostics);
    timings.push(("check and lower", started.elapsed()));
    sfc::remap_all(&charts, &mut diagnostics);
    plcopen::remap_all(&ladder, &mut diagnostics);
    let printed = printable.filter(|_| module.is_some()).and_then(|units| {
        let build = Printable {
            units: &units,
            inputs,
            il_bodies: &il_bodies,
            sources,
            interner: &interner,
            codesys: lower_opts.codesys,
        };
        match opts.print {
            PrintAs::Plcopen => build
                .plcopen()
                .map_err(|mut d| diagnostics.append(&mut d))
                .ok(),
            _ => Some(build.st(&lowered.temp_types)),
        }
    });
    Compiled {
        module,
        diagnostics,
        timings,
        syntax: units,
        ladder,
        charts,
        printed,
    }
}

/// A build that compiled, as [`LowerOptions::print`] prints it: its units before
/// addresses became names and globals moved.
struct Printable<'a> {
    units: &'a [ast::SourceUnit],
    inputs: &'a [(FileId, Lang)],
    /// The bodies each IL file holds in IL.
    il_bodies: &'a [(FileId, Vec<std::ops::Range<usize>>)],
    sources: &'a SourceMap,
    interner: &'a intern::Interner,
    /// Built in the CODESYS dialect.
    codesys: bool,
}

impl Printable<'_> {
    /// The units as Structured Text, each after a comment naming its file.
    fn st(&self, temps: &print::TempTypes) -> String {
        let mut out = String::new();
        if self.codesys {
            out.push_str("(* built in the CODESYS dialect: compile with --dialect codesys *)\n");
        }
        for (k, u) in self.units.iter().enumerate() {
            if k > 0 {
                out.push('\n');
            }
            out.push_str(&format!("(* {} *)\n", self.sources.get(u.file).name));
            let text = print::Printer::new(self.interner)
                .with_sources(self.sources)
                .with_temps(temps)
                .unit(u);
            out.push_str(&text);
        }
        out
    }

    /// The units as one PLCopen project named after the first file.
    fn plcopen(&self) -> Result<String, Vec<Diagnostic>> {
        let units: Vec<plcopen::export::ExportUnit> = self
            .units
            .iter()
            .zip(self.inputs)
            .map(|(unit, &(_, lang))| plcopen::export::ExportUnit {
                unit,
                lang,
                il_bodies: self
                    .il_bodies
                    .iter()
                    .find(|(f, _)| *f == unit.file)
                    .map_or(Vec::new(), |(_, r)| r.clone()),
            })
            .collect();
        let first = self.inputs.first().map(|&(f, _)| &self.sources.get(f).name);
        let name = first
            .and_then(|n| std::path::Path::new(n).file_stem())
            .map_or("project".to_string(), |s| s.to_string_lossy().into_owned());
        plcopen::export::export(&units, self.sources, self.interner, &name, self.codesys)
    }
}

/// The options to lower with: in the CODESYS dialect when a PLCopen file of the
/// build was written by a CODESYS-based editor, unless `--dialect` chose one.
fn dialect_of_files(opts: &LowerOptions, ladder: &[plcopen::View]) -> LowerOptions {
    let mut opts = opts.clone();
    if !opts.dialect_given
        && ladder
            .iter()
            .any(|v| v.dialect == plcopen::Dialect::Codesys)
    {
        opts.codesys = true;
    }
    opts
}

/// The standard library's syntax tree, a copy of the interner holding its names, and
/// its diagnostics (none, unless plcc is broken). Parsing it was most of the cost of
/// checking a small program, so it is parsed once per process for each file id it
/// gets (its spans carry the id; a process sees very few) and shared by every build.
fn parse_std_library(
    std_file: FileId,
) -> (&'static ast::SourceUnit, intern::Interner, Vec<Diagnostic>) {
    type Parsed = (ast::SourceUnit, intern::Interner, Vec<Diagnostic>);
    static CACHE: std::sync::Mutex<Vec<(FileId, &'static Parsed)>> =
        std::sync::Mutex::new(Vec::new());
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    let parsed = match cache.iter().find(|(id, _)| *id == std_file) {
        Some(&(_, parsed)) => parsed,
        None => {
            let mut interner = intern::Interner::new();
            let mut diagnostics = Vec::new();
            let unit = st::parse(
                std_file,
                lower::std_library_source().0,
                &mut interner,
                &mut diagnostics,
            );
            // Leaked on purpose: one per file id, kept for the life of the process.
            let parsed: &'static Parsed = Box::leak(Box::new((unit, interner, diagnostics)));
            cache.push((std_file, parsed));
            parsed
        }
    };
    (&parsed.0, parsed.1.clone(), parsed.2.clone())
}

/// The name of the synthetic POU that holds every `VAR_GLOBAL` of a build (no user
/// can write it: IEC names cannot contain two underscores in a row).
pub const GLOBALS_POU: &str = "__GLOBALS";

/// The name of the data object that holds the globals (variable paths start with it:
/// `$globals.x`).
pub const GLOBALS_DATA: &str = "$globals";

/// Moves every top-level `VAR_GLOBAL` block of the user's units (the standard library
/// declares none) into one synthetic POU (a unit of its own), so that globals get the
/// same declarations, types, constants and initial values as the variables of any POU.
fn globals_unit(
    units: &mut [ast::SourceUnit],
    interner: &mut intern::Interner,
) -> Option<ast::SourceUnit> {
    let mut blocks = Vec::new();
    for unit in units.iter_mut() {
        let items = std::mem::take(&mut unit.items);
        for item in items {
            match item {
                ast::Item::Globals(mut b) => {
                    b.kind = ast::VarKind::Var;
                    blocks.push(b);
                }
                ast::Item::Configuration(mut c) => {
                    // The globals of a configuration and its resources are globals
                    // too (the configuration itself is reported elsewhere).
                    // A resource keeps its blocks: lowering names the resource's
                    // globals after them (see `lower::tasks`).
                    let own = std::mem::take(&mut c.var_blocks);
                    let res = c
                        .resources
                        .iter()
                        .flat_map(|r| r.var_blocks.iter().cloned());
                    for mut b in own.into_iter().chain(res.collect::<Vec<_>>()) {
                        if b.kind == ast::VarKind::Global {
                            b.kind = ast::VarKind::Var;
                            blocks.push(b);
                        }
                    }
                    unit.items.push(ast::Item::Configuration(c));
                }
                other => unit.items.push(other),
            }
        }
    }
    let first = blocks.first()?.span;
    let name = ast::Ident {
        sym: interner.intern(GLOBALS_POU),
        span: plcc_ir::diag::Span::new(first.file, first.start, first.start),
    };
    Some(ast::SourceUnit {
        file: first.file,
        items: vec![ast::Item::Pou(ast::Pou {
            kind: ast::PouKind::Program,
            name,
            return_type: None,
            extends: None,
            var_blocks: blocks,
            body: ast::Body::default(),
            actions: Vec::new(),
            unsupported_members: Vec::new(),
            oo: Default::default(),
            sfc: None,
            span: first,
        })],
    })
}

/// A file that declares nothing (no POU, type, configuration or global) compiles to
/// nothing, which is an error, not a success (E0109) — unless its own errors already
/// say why. A PLCopen file with POUs in `<addData>` where plcc does not look for them
/// gets a note saying so.
fn nothing_to_compile(
    sources: &SourceMap,
    file: FileId,
    lang: Lang,
    unit: Option<&ast::SourceUnit>,
    diagnostics: &mut Vec<Diagnostic>,
) {
    if unit.is_some_and(|u| !u.items.is_empty())
        || diagnostics
            .iter()
            .any(|d| d.is_error() && d.span.is_some_and(|s| s.file == file))
    {
        return;
    }
    let src = sources.get(file);
    let d = Diagnostic::error(
        codes::NOTHING_TO_COMPILE,
        format!("`{}` declares nothing to compile", src.name),
        plcc_ir::diag::Span::new(file, 0, 0),
    );
    let d = if lang == Lang::Ld && src.text.contains("<addData") && src.text.contains("<pou ") {
        d.with_note("its POUs are kept inside `<addData>` where plcc does not look for them: it reads those of CODESYS's `pou` data, in the project, an `application` or a resource")
    } else {
        d.with_note(
            "a PROGRAM, FUNCTION, FUNCTION_BLOCK, TYPE, CONFIGURATION or VAR_GLOBAL was expected",
        )
    };
    diagnostics.push(d);
}
