//! The workbench of `plcc serve` (`docs/workbench.md`): the page, embedded in the
//! binary, and the API calls it needs beside those of [`super::http`]:
//!
//! - `GET /api/project`: the files, the POUs (kind, language, file, where), the data
//!   types, the configurations (resources, tasks, program instances), and the
//!   program instances that run (which POU each is);
//! - `GET /api/files/{n}`: a file's text;
//! - `POST /api/check?file=NAME` (or `?lang=st|il|stl|xml`): the diagnostics of a
//!   text, built with the other files of the project in place of the file NAME (or
//!   alone), without loading it;
//! - `GET /api/diagram/{pou}`: the graphical body (LD, FBD or SFC) of a POU of a
//!   PLCopen file, as JSON: every element with its kind, `localId`, position, size,
//!   text (variable, expression, block type and instance, step name...), modifiers,
//!   and its connection points with their connections (and the editor's wire
//!   points).
//!
//! The POUs of textual files come from the syntax tree of the build; those of
//! PLCopen files are read from the XML here (with `roxmltree`), which keeps the
//! diagram as the editor drew it.

use super::Loader;
use crate::driver::Build;
use plcc_frontend::ast;
use plcc_ir::diag::Severity;
use serde_json::{json, Map, Value as Json};

/// The page and its assets, built from `web/` by `npm run build` (`web/dist/`).
const ASSETS: &[(&str, &str, &[u8])] = &[
    (
        "/",
        "text/html; charset=utf-8",
        include_bytes!("../../web/dist/index.html"),
    ),
    (
        "/assets/app.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../../web/dist/app.js"),
    ),
    (
        "/assets/editor.js",
        "text/javascript; charset=utf-8",
        include_bytes!("../../web/dist/editor.js"),
    ),
    (
        "/assets/app.css",
        "text/css; charset=utf-8",
        include_bytes!("../../web/dist/app.css"),
    ),
    (
        "/assets/LICENSES.txt",
        "text/plain; charset=utf-8",
        include_bytes!("../../web/dist/LICENSES.txt"),
    ),
];

/// An asset of the page: its content type and bytes; `None` if there is none at
/// `path` (`/index.html` is `/`).
pub fn asset(path: &str) -> Option<(&'static str, &'static [u8])> {
    let path = if path == "/index.html" { "/" } else { path };
    ASSETS
        .iter()
        .find(|(p, _, _)| *p == path)
        .map(|(_, ty, bytes)| (*ty, *bytes))
}

/// A source file of the project.
pub struct File {
    /// Its name, as given on the command line.
    pub name: String,
    /// Its language: `st`, `il`, `stl`, `xml` (the extension).
    pub lang: String,
    /// Its text.
    pub text: String,
}

/// A POU of the project.
struct Pou {
    name: String,
    /// `program`, `function`, `functionBlock`.
    kind: &'static str,
    /// `ST`, `IL`, `STL`, `LD`, `FBD`, `SFC`.
    lang: String,
    /// The file it is in.
    file: usize,
    /// Where it is in a textual file (bytes).
    range: Option<(usize, usize)>,
    /// A function's or function block's pins, as the ladder editor places it:
    /// `{"inputs": [[name, type]], "outputs": [[name, type]], "result": type}`
    /// (types as written).
    pins: Option<Json>,
}

/// The pins JSON of a POU (see [`Pou::pins`]).
fn pins_json(
    kind: &str,
    inputs: Vec<(String, String)>,
    outputs: Vec<(String, String)>,
    result: Option<String>,
) -> Option<Json> {
    (kind != "program").then(|| json!({"inputs": inputs, "outputs": outputs, "result": result}))
}

/// The project `plcc serve` was started with, as the workbench shows it.
pub struct Project {
    /// The source files, in command-line order.
    pub files: Vec<File>,
    pous: Vec<Pou>,
    /// The data types: name and file.
    types: Vec<(String, usize)>,
    /// The configurations, as JSON.
    configs: Vec<Json>,
    /// The program instances that run: name and the PROGRAM it instantiates.
    instances: Vec<(String, String)>,
}

/// A file's language as the API names it, from its name.
fn lang_of(name: &str) -> String {
    std::path::Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map_or_else(|| "st".to_string(), |e| e.to_ascii_lowercase())
}

/// Byte offset to a JavaScript string offset (UTF-16 code units).
fn utf16(text: &str, byte: usize) -> usize {
    let byte = byte.min(text.len());
    let mut b = byte;
    while !text.is_char_boundary(b) {
        b -= 1;
    }
    text[..b].encode_utf16().count()
}

impl Project {
    /// The project of a build of `names` (the command line's files, the first
    /// sources of the build).
    pub fn new(build: &Build, names: &[std::path::PathBuf], module: &plcc_ir::Module) -> Project {
        let mut p = Project {
            files: Vec::new(),
            pous: Vec::new(),
            types: Vec::new(),
            configs: Vec::new(),
            instances: Vec::new(),
        };
        let mut ids = Vec::new();
        for (i, (id, f)) in build.sources.iter().take(names.len()).enumerate() {
            ids.push(id);
            p.files.push(File {
                name: f.name.clone(),
                lang: lang_of(&f.name),
                text: f.text.to_string(),
            });
            if p.files[i].lang == "xml" {
                p.read_xml(i);
            }
        }
        for unit in &build.syntax {
            let Some(file) = ids.iter().position(|&id| id == unit.file) else {
                continue;
            };
            let text = &p.files[file].text;
            let name = |i: &ast::Ident| {
                text.get(i.span.start as usize..i.span.end as usize)
                    .unwrap_or("")
                    .to_string()
            };
            for item in &unit.items {
                match item {
                    ast::Item::Pou(pou) => {
                        let kind = match pou.kind {
                            ast::PouKind::Program => "program",
                            ast::PouKind::Function => "function",
                            ast::PouKind::FunctionBlock => "functionBlock",
                        };
                        let lang = p.files[file].lang.to_ascii_uppercase();
                        let lang = if pou.sfc.is_some() {
                            "SFC".into()
                        } else {
                            lang
                        };
                        let source = |s: plcc_ir::diag::Span| {
                            text.get(s.start as usize..s.end as usize)
                                .unwrap_or("")
                                .to_string()
                        };
                        let section = |k: ast::VarKind| -> Vec<(String, String)> {
                            pou.var_blocks
                                .iter()
                                .filter(|b| b.kind == k)
                                .flat_map(|b| &b.decls)
                                .flat_map(|d| {
                                    d.names.iter().map(|n| (name(n), source(d.ty.span())))
                                })
                                .collect()
                        };
                        p.pous.push(Pou {
                            name: name(&pou.name),
                            kind,
                            lang,
                            file,
                            range: Some((pou.span.start as usize, pou.span.end as usize)),
                            pins: pins_json(
                                kind,
                                section(ast::VarKind::Input),
                                section(ast::VarKind::Output),
                                pou.return_type.as_ref().map(|t| source(t.span())),
                            ),
                        });
                    }
                    ast::Item::Type(t) => p.types.push((name(&t.name), file)),
                    ast::Item::Configuration(c) => {
                        let source = |e: &ast::Expr| {
                            text.get(e.span.start as usize..e.span.end as usize)
                                .unwrap_or("")
                                .to_string()
                        };
                        let resources: Vec<Json> = c
                            .resources
                            .iter()
                            .map(|r| {
                                let tasks: Vec<Json> = r
                                    .tasks
                                    .iter()
                                    .map(|t| {
                                        let mut props = Map::new();
                                        for (k, v) in &t.props {
                                            props.insert(
                                                name(k).to_ascii_lowercase(),
                                                json!(source(v)),
                                            );
                                        }
                                        json!({"name": name(&t.name), "props": props})
                                    })
                                    .collect();
                                let programs: Vec<Json> = r
                                    .programs
                                    .iter()
                                    .map(|pc| {
                                        json!({
                                            "name": name(&pc.name),
                                            "task": pc.task.as_ref().map(name),
                                            "type": name(&pc.pou),
                                        })
                                    })
                                    .collect();
                                json!({"name": name(&r.name), "tasks": tasks, "programs": programs})
                            })
                            .collect();
                        p.configs.push(json!({
                            "name": name(&c.name),
                            "file": file,
                            "resources": resources,
                        }));
                    }
                    _ => {}
                }
            }
        }
        // The PROGRAM each configured instance instantiates.
        let program_types: Vec<(String, String)> = p
            .configs
            .iter()
            .flat_map(|c| c["resources"].as_array().cloned().unwrap_or_default())
            .flat_map(|r| r["programs"].as_array().cloned().unwrap_or_default())
            .map(|i| {
                let s = |k: &str| i[k].as_str().unwrap_or("").to_string();
                (s("name"), s("type"))
            })
            .collect();
        for e in &module.programs {
            let ty = program_types
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(&e.name))
                .map_or_else(|| e.name.clone(), |(_, t)| t.clone());
            p.instances.push((e.name.clone(), ty));
        }
        p
    }

    /// The POUs, data types and configurations of PLCopen file `file`.
    fn read_xml(&mut self, file: usize) {
        let Ok(doc) = roxmltree::Document::parse(&self.files[file].text) else {
            return;
        };
        let root = doc.root_element();
        for n in root.descendants().filter(|n| n.is_element()) {
            match n.tag_name().name() {
                "pou" => {
                    let kind = match n.attribute("pouType") {
                        Some("function") => "function",
                        Some("functionBlock") => "functionBlock",
                        _ => "program",
                    };
                    let lang = child(n, "body")
                        .and_then(|b| b.children().find(|c| c.is_element()))
                        .map_or("", |b| b.tag_name().name())
                        .to_string();
                    let iface = child(n, "interface");
                    let section = |tag: &str| -> Vec<(String, String)> {
                        iface
                            .into_iter()
                            .flat_map(|i| i.children().filter(move |b| b.tag_name().name() == tag))
                            .flat_map(|b| {
                                b.children().filter(|v| v.tag_name().name() == "variable")
                            })
                            .map(|v| {
                                let ty = child(v, "type").map(xml_type).unwrap_or_default();
                                (v.attribute("name").unwrap_or("").to_string(), ty)
                            })
                            .collect()
                    };
                    let result = iface.and_then(|i| child(i, "returnType")).map(xml_type);
                    self.pous.push(Pou {
                        name: n.attribute("name").unwrap_or("").to_string(),
                        kind,
                        lang,
                        file,
                        range: None,
                        pins: pins_json(kind, section("inputVars"), section("outputVars"), result),
                    });
                }
                "dataType" => self
                    .types
                    .push((n.attribute("name").unwrap_or("").to_string(), file)),
                "configuration" => {
                    let resources: Vec<Json> = n
                        .children()
                        .filter(|r| r.tag_name().name() == "resource")
                        .map(|r| {
                            let mut programs = Vec::new();
                            let tasks: Vec<Json> = r
                                .children()
                                .filter(|t| t.tag_name().name() == "task")
                                .map(|t| {
                                    let mut props = Map::new();
                                    for a in ["interval", "priority", "single"] {
                                        if let Some(v) = t.attribute(a) {
                                            props.insert(a.into(), json!(v));
                                        }
                                    }
                                    for i in t.children().filter(|i| i.tag_name().name() == "pouInstance") {
                                        programs.push(instance_json(i, t.attribute("name")));
                                    }
                                    json!({"name": t.attribute("name").unwrap_or(""), "props": props})
                                })
                                .collect();
                            for i in r.children().filter(|i| i.tag_name().name() == "pouInstance") {
                                programs.push(instance_json(i, None));
                            }
                            json!({"name": r.attribute("name").unwrap_or(""), "tasks": tasks, "programs": programs})
                        })
                        .collect();
                    self.configs.push(json!({
                        "name": n.attribute("name").unwrap_or(""),
                        "file": file,
                        "resources": resources,
                    }));
                }
                _ => {}
            }
        }
    }

    /// `GET /api/project`.
    pub fn info(&self) -> Json {
        let files: Vec<Json> = self
            .files
            .iter()
            .map(|f| json!({"name": f.name, "lang": f.lang}))
            .collect();
        let pous: Vec<Json> = self
            .pous
            .iter()
            .map(|p| {
                let text = &self.files[p.file].text;
                let mut j = json!({
                    "name": p.name,
                    "kind": p.kind,
                    "lang": p.lang,
                    "file": p.file,
                    "graphical": matches!(p.lang.as_str(), "LD" | "FBD" | "SFC") && p.range.is_none(),
                });
                if let Some(pins) = &p.pins {
                    j["pins"] = pins.clone();
                }
                if let Some((s, e)) = p.range {
                    j["from"] = json!(utf16(text, s));
                    j["to"] = json!(utf16(text, e));
                    j["line"] = json!(text[..s.min(text.len())].matches('\n').count() + 1);
                }
                j
            })
            .collect();
        let types: Vec<Json> = self
            .types
            .iter()
            .map(|(n, f)| json!({"name": n, "file": f}))
            .collect();
        let instances: Vec<Json> = self
            .instances
            .iter()
            .map(|(n, t)| json!({"name": n, "pou": t}))
            .collect();
        json!({
            "files": files,
            "pous": pous,
            "types": types,
            "configurations": self.configs,
            "instances": instances,
        })
    }

    /// `GET /api/files/{n}`.
    pub fn file(&self, n: &str) -> Result<Json, (u16, String)> {
        let f = n
            .parse::<usize>()
            .ok()
            .and_then(|i| self.files.get(i))
            .ok_or_else(|| (404, format!("no file `{n}`: GET /api/project lists them")))?;
        Ok(json!({"name": f.name, "lang": f.lang, "text": f.text}))
    }

    /// `GET /api/diagram/{pou}`.
    pub fn diagram(&self, name: &str) -> Result<Json, (u16, String)> {
        let pou = self
            .pous
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name) && p.range.is_none())
            .ok_or_else(|| (404, format!("no POU `{name}` in a PLCopen file")))?;
        let mut j = diagram_in(&self.files[pou.file].text, name)?;
        j["file"] = json!(pou.file);
        Ok(j)
    }
}

/// `POST /api/diagram/{pou}`: the diagram of POU `name` in the PLCopen text given
/// (an edited file, before it is saved or loaded).
pub fn diagram_of(text: &[u8], name: &str) -> Result<Json, (u16, String)> {
    let text = std::str::from_utf8(text).map_err(|_| (400, "the text is not UTF-8".to_string()))?;
    diagram_in(text, name).map_err(|(status, e)| (if status == 500 { 400 } else { status }, e))
}

/// The graphical body of POU `name` of a PLCopen text as JSON.
fn diagram_in(text: &str, name: &str) -> Result<Json, (u16, String)> {
    let doc = roxmltree::Document::parse(text).map_err(|e| (500, e.to_string()))?;
    let node = doc
        .descendants()
        .find(|n| {
            n.tag_name().name() == "pou"
                && n.attribute("name")
                    .is_some_and(|x| x.eq_ignore_ascii_case(name))
        })
        .ok_or_else(|| (404, format!("no POU `{name}`")))?;
    let body = child(node, "body")
        .and_then(|b| b.children().find(|c| c.is_element()))
        .ok_or_else(|| (404, format!("`{name}` has no body")))?;
    let lang = body.tag_name().name();
    if !matches!(lang, "LD" | "FBD" | "SFC") {
        return Err((404, format!("`{name}` is written in {lang}, not drawn")));
    }
    let elements: Vec<Json> = body
        .children()
        .filter(|c| c.is_element())
        .map(element_json)
        .collect();
    let kind = node.attribute("pouType").unwrap_or("program");
    Ok(json!({
        "pou": node.attribute("name").unwrap_or(name),
        "kind": kind,
        "lang": lang,
        "elements": elements,
    }))
}

/// A source file to build: its name and text.
pub type Source = (String, Vec<u8>);

impl Project {
    /// The project's files (name and text) with `text` in place of the file `name`.
    pub fn with_file(&self, name: &str, text: Vec<u8>) -> Result<Vec<Source>, (u16, String)> {
        let Some(i) = self.files.iter().position(|x| x.name == name) else {
            return Err((404, format!("no file `{name}` in the project")));
        };
        let mut text = Some(text);
        Ok(self
            .files
            .iter()
            .enumerate()
            .map(|(j, x)| {
                let t = match (i == j).then(|| text.take()).flatten() {
                    Some(t) => t,
                    None => x.text.as_bytes().to_vec(),
                };
                (x.name.clone(), t)
            })
            .collect())
    }

    /// The files' names as paths (what [`Project::new`] takes).
    pub fn paths(&self) -> Vec<std::path::PathBuf> {
        self.files.iter().map(|f| f.name.clone().into()).collect()
    }

    /// `POST /api/check?file=NAME|lang=L`: the diagnostics of `text`, built in place
    /// of the project's file NAME (the other files with it), or alone as language L.
    pub fn check(
        &self,
        loader: &Loader,
        query: &str,
        text: Vec<u8>,
    ) -> Result<Json, (u16, String)> {
        let mut file = None;
        let mut lang = None;
        for kv in query.split('&').filter(|kv| !kv.is_empty()) {
            match kv.split_once('=') {
                Some(("file", f)) => {
                    file = Some(super::http::percent_decode(f).unwrap_or_default())
                }
                Some(("lang", l @ ("st" | "il" | "stl" | "xml"))) => lang = Some(l.to_string()),
                _ => {
                    return Err((
                        400,
                        format!("`{kv}`: use file=NAME or lang=st, il, stl, xml"),
                    ))
                }
            }
        }
        let (texts, name) = match (file, lang) {
            (Some(f), None) => (self.with_file(&f, text)?, f),
            (None, Some(l)) => {
                let name = format!("program.{l}");
                (vec![(name.clone(), text)], name)
            }
            _ => return Err((400, "give file=NAME or lang=st, il, stl, xml".into())),
        };
        let mut opts = loader.opts.clone();
        opts.check_only = true;
        let build = crate::driver::build_sources_with_library(texts, loader.library.clone(), &opts)
            .map_err(|e| (400, e.0))?;
        let mut out = Vec::new();
        for d in &build.diagnostics {
            let mut j = json!({
                "severity": if d.severity == Severity::Error { "error" } else { "warning" },
                "code": d.code,
                "message": d.message,
                "label": d.label,
                "notes": d.notes,
            });
            if let Some(span) = d.span {
                let f = build.sources.get(span.file);
                let t = &f.text;
                let (s, e) = (span.start as usize, span.end as usize);
                let line = t[..s.min(t.len())].matches('\n').count() + 1;
                j["file"] = json!(f.name);
                j["here"] = json!(f.name == name);
                j["from"] = json!(utf16(t, s));
                j["to"] = json!(utf16(t, e.max(s)));
                j["line"] = json!(line);
            }
            out.push(j);
        }
        let errors = build.diagnostics.iter().filter(|d| d.is_error()).count();
        Ok(json!({"ok": errors == 0, "errors": errors, "diagnostics": out}))
    }
}

/// The targets the page builds for, and what it asks each for.
const BUILDS: &[(&str, &[&str])] = &[
    ("pic16f876a", &["hex", "asm"]),
    ("vmasm", &["xcp", "asm"]),
    ("c", &["c"]),
];

impl Project {
    /// `POST /api/build?target=T`: the project (its files as started, or the body in
    /// place of the file `file=NAME` when given) built for target T, with its settings
    /// `set=KEY=VALUE` (each percent-encoded, as `-s` gives them): the output files
    /// (contents in base64) and the target's resource report; the diagnostics if it
    /// does not build.
    pub fn build(
        &self,
        loader: &Loader,
        query: &str,
        body: Vec<u8>,
    ) -> Result<Json, (u16, String)> {
        let mut target = None;
        let mut file = None;
        let mut settings = Vec::new();
        for kv in query.split('&').filter(|kv| !kv.is_empty()) {
            match kv.split_once('=') {
                Some(("target", t)) => target = Some(t.to_string()),
                Some(("file", f)) => file = super::http::percent_decode(f),
                // A target setting, as `-s KEY=VALUE` gives it (`pin.%IX0.0=RA2`).
                Some(("set", s)) => match super::http::percent_decode(s)
                    .as_deref()
                    .and_then(|s| s.split_once('='))
                {
                    Some((k, v)) if !k.trim().is_empty() => {
                        settings.push((k.trim().to_string(), v.trim().to_string()))
                    }
                    _ => return Err((400, format!("`{kv}`: a setting is set=KEY=VALUE"))),
                },
                _ => {
                    return Err((
                        400,
                        format!("`{kv}`: use target=T, file=NAME and set=KEY=VALUE"),
                    ))
                }
            }
        }
        let names = BUILDS
            .iter()
            .map(|(t, _)| *t)
            .collect::<Vec<_>>()
            .join(", ");
        let Some(&(target, emits)) = BUILDS.iter().find(|(t, _)| Some(*t) == target.as_deref())
        else {
            return Err((400, format!("give target=T, one of {names}")));
        };
        let texts = match &file {
            Some(f) => self.with_file(f, body)?,
            None => self.with_file(&self.files[0].name, self.files[0].text.clone().into())?,
        };
        let mut opts = loader.opts.clone();
        opts.inline_c = crate::targets::find(target).is_some_and(|t| t.inline_c);
        let build = crate::driver::build_sources_with_library(texts, loader.library.clone(), &opts)
            .map_err(|e| (400, e.0))?;
        let report = |diags: &[plcc_ir::diag::Diagnostic]| {
            json!({
                "ok": false,
                "target": target,
                "errors": crate::render::render(&build.sources, diags),
            })
        };
        let Some(module) = build.module.as_ref() else {
            return Ok(report(&build.diagnostics));
        };
        let Some(backend) = crate::targets::backend(target) else {
            return Err((500, format!("no backend for `{target}`")));
        };
        let stem = std::path::Path::new(&self.files[0].name)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned());
        let mut files = Vec::new();
        let mut summary = None;
        for emit in emits {
            let opts = plcc_ir::backend::Options {
                emit: Some(emit.to_string()),
                settings: settings.clone(),
                sources: crate::driver::source_texts(&build.sources, module),
                output_stem: stem.clone(),
            };
            match backend.compile(module, &opts) {
                Ok(arts) => {
                    summary = summary.or(arts.summary);
                    for a in arts.files {
                        let name = if a.kind.contains('.') {
                            a.kind.clone()
                        } else {
                            format!("{}.{}", stem.as_deref().unwrap_or("program"), a.kind)
                        };
                        if files.iter().any(|f: &Json| f["name"] == name.as_str()) {
                            continue;
                        }
                        files.push(json!({"name": name, "size": a.bytes.len(), "base64": base64(&a.bytes)}));
                    }
                }
                Err(diags) => return Ok(report(&diags)),
            }
        }
        let warnings = build.diagnostics.iter().filter(|d| !d.is_error()).count();
        Ok(json!({
            "ok": true,
            "target": target,
            "summary": summary,
            "warnings": warnings,
            "files": files,
        }))
    }
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * i)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The first child element of `n` named `tag`.
/// The type a PLCopen `type` or `returnType` element holds: an elementary type's
/// name in upper case, a derived type's name as written.
fn xml_type(t: roxmltree::Node) -> String {
    match t.children().find(|c| c.is_element()) {
        Some(c) if c.tag_name().name() == "derived" => {
            c.attribute("name").unwrap_or("").to_string()
        }
        Some(c) => c.tag_name().name().to_ascii_uppercase(),
        None => String::new(),
    }
}

fn child<'a, 'i>(n: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    n.children().find(|c| c.tag_name().name() == tag)
}

/// A `pouInstance` as JSON.
fn instance_json(i: roxmltree::Node, task: Option<&str>) -> Json {
    let ty = i
        .attribute("typeName")
        .or_else(|| i.attribute("type"))
        .filter(|t| !t.is_empty())
        .or_else(|| i.attribute("name"))
        .unwrap_or("");
    json!({"name": i.attribute("name").unwrap_or(""), "task": task, "type": ty})
}

/// A number attribute.
fn num(n: roxmltree::Node, a: &str) -> f64 {
    n.attribute(a)
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(0.0)
}

/// The text of an element's child `tag` (`<variable>`, `<expression>`).
fn child_text(n: roxmltree::Node, tag: &str) -> Option<String> {
    child(n, tag).map(|c| c.text().unwrap_or("").trim().to_string())
}

/// The text of an SFC condition or action body: inline ST, or the reference's name.
fn inline_text(n: roxmltree::Node) -> Option<String> {
    if let Some(r) = child(n, "reference") {
        return r.attribute("name").map(str::to_string);
    }
    let inline = child(n, "inline")?;
    let text: String = inline
        .descendants()
        .filter(|d| d.is_text())
        .filter_map(|d| d.text())
        .collect();
    Some(text.trim().to_string())
}

/// A connection point: its absolute place, the connections of an input, the
/// name of the variable of a block it belongs to.
fn point_json(
    cp: roxmltree::Node,
    x: f64,
    y: f64,
    name: Option<&str>,
    negated: bool,
    edge: Option<&str>,
) -> Json {
    let rel = child(cp, "relPosition");
    let (rx, ry) = rel.map_or((0.0, 0.0), |r| (num(r, "x"), num(r, "y")));
    let conns: Vec<Json> = cp
        .children()
        .filter(|c| c.tag_name().name() == "connection")
        .map(|c| {
            let points: Vec<Json> = c
                .children()
                .filter(|p| p.tag_name().name() == "position")
                .map(|p| json!([num(p, "x"), num(p, "y")]))
                .collect();
            json!({
                "from": c.attribute("refLocalId").and_then(|v| v.parse::<u64>().ok()),
                "param": c.attribute("formalParameter").filter(|p| !p.is_empty()),
                "points": points,
            })
        })
        .collect();
    let mut j = json!({"x": x + rx, "y": y + ry, "name": name, "negated": negated});
    if let Some(e) = edge.filter(|e| *e != "none") {
        j["edge"] = json!(e);
    }
    if cp.tag_name().name() == "connectionPointIn" {
        j["conns"] = json!(conns);
    }
    j
}

/// An element of a graphical body as JSON.
fn element_json(n: roxmltree::Node) -> Json {
    let kind = n.tag_name().name();
    let (x, y) = child(n, "position").map_or((0.0, 0.0), |p| (num(p, "x"), num(p, "y")));
    let mut j = json!({
        "kind": kind,
        "id": n.attribute("localId").and_then(|v| v.parse::<u64>().ok()),
        "x": x,
        "y": y,
        "w": num(n, "width"),
        "h": num(n, "height"),
    });
    for a in [
        "negated",
        "edge",
        "storage",
        "typeName",
        "instanceName",
        "executionOrderId",
        "initialStep",
        "name",
        "label",
        "targetName",
        "qualifier",
    ] {
        if let Some(v) = n.attribute(a) {
            j[a] = json!(v);
        }
    }
    if let Some(t) = child_text(n, "variable").or_else(|| child_text(n, "expression")) {
        j["text"] = json!(t);
    }
    if let Some(c) = child(n, "condition") {
        j["condition"] = json!(inline_text(c));
    }
    let mut ins = Vec::new();
    let mut outs = Vec::new();
    // Connection points of the element itself, then of its block variables.
    for c in n.children().filter(|c| c.is_element()) {
        match c.tag_name().name() {
            "connectionPointIn" => ins.push(point_json(
                c,
                x,
                y,
                c.attribute("formalParameter"),
                false,
                None,
            )),
            "connectionPointOut" => outs.push(point_json(
                c,
                x,
                y,
                c.attribute("formalParameter"),
                false,
                None,
            )),
            "connectionPointOutAction" => {
                outs.push(point_json(c, x, y, Some("action"), false, None))
            }
            "condition" => {
                if let Some(cp) = child(c, "connectionPointIn") {
                    ins.push(point_json(cp, x, y, Some("condition"), false, None));
                }
            }
            g @ ("inputVariables" | "inOutVariables" | "outputVariables") => {
                for v in c.children().filter(|v| v.tag_name().name() == "variable") {
                    let name = v.attribute("formalParameter");
                    let neg = v.attribute("negated") == Some("true");
                    let edge = v.attribute("edge");
                    if g != "outputVariables" {
                        if let Some(cp) = child(v, "connectionPointIn") {
                            ins.push(point_json(cp, x, y, name, neg, edge));
                        }
                    }
                    if g != "inputVariables" {
                        if let Some(cp) = child(v, "connectionPointOut") {
                            outs.push(point_json(cp, x, y, name, neg, edge));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    j["ins"] = json!(ins);
    j["outs"] = json!(outs);
    if kind == "actionBlock" {
        let actions: Vec<Json> = n
            .children()
            .filter(|a| a.tag_name().name() == "action")
            .map(|a| {
                json!({
                    "qualifier": a.attribute("qualifier").unwrap_or("N"),
                    "duration": a.attribute("duration"),
                    "indicator": a.attribute("indicator"),
                    "text": inline_text(a),
                })
            })
            .collect();
        j["actions"] = json!(actions);
    }
    if kind == "comment" {
        j["text"] = json!(child(n, "content").map(|c| c
            .descendants()
            .filter(|d| d.is_text())
            .filter_map(|d| d.text())
            .collect::<String>()
            .trim()
            .to_string()));
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_and_its_assets_are_embedded() {
        let (ty, page) = asset("/").unwrap();
        assert!(ty.starts_with("text/html"));
        assert!(std::str::from_utf8(page)
            .unwrap()
            .contains("/assets/app.js"));
        assert_eq!(
            asset("/assets/app.css").unwrap().0,
            "text/css; charset=utf-8"
        );
        assert!(asset("/assets/nothing.js").is_none());
    }

    /// `web/dist/` is the bundle of the sources in `web/`: every source file has the
    /// FNV-1a 64 that `web/build.mjs` recorded in `web/dist/SOURCES.txt` when it
    /// built the bundle (and every file of `web/src/` is listed).
    #[test]
    fn the_bundle_is_built_from_the_sources() {
        let web = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("web");
        let fnv = |bytes: &[u8]| {
            let mut h: u64 = 0xcbf2_9ce4_8422_2325;
            for &b in bytes {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
            format!("{h:016x}")
        };
        let listed = std::fs::read_to_string(web.join("dist/SOURCES.txt")).unwrap();
        let mut names = Vec::new();
        for line in listed.lines().filter(|l| !l.starts_with('#')) {
            let (hash, name) = line.split_once("  ").expect("`hash  path`");
            let text = std::fs::read(web.join(name)).unwrap_or_else(|e| panic!("web/{name}: {e}"));
            assert_eq!(
                fnv(&text),
                hash,
                "web/{name} changed since web/dist/ was built: cd web && npm ci && npm run build"
            );
            names.push(name.to_string());
        }
        for f in std::fs::read_dir(web.join("src")).unwrap() {
            let name = format!("src/{}", f.unwrap().file_name().to_string_lossy());
            assert!(
                names.contains(&name),
                "web/{name} is not in the bundle: cd web && npm run build"
            );
        }
    }

    fn project(files: &[(&str, &str)]) -> (Project, Loader) {
        let texts: Vec<(String, Vec<u8>)> = files
            .iter()
            .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec()))
            .collect();
        let opts = crate::driver::BuildOptions::default();
        let build = crate::driver::build_sources(texts, &opts).unwrap();
        let module = build.module.clone().expect("the project builds");
        let names: Vec<std::path::PathBuf> = files.iter().map(|(n, _)| n.into()).collect();
        let loader = Loader {
            library: Vec::new(),
            opts,
            target: "interp",
            settings: Vec::new(),
        };
        (Project::new(&build, &names, &module), loader)
    }

    #[test]
    fn the_ladder_example_as_the_page_reads_it() {
        let xml = include_str!("../../examples/ladder_demo.xml");
        let (p, loader) = project(&[("ladder_demo.xml", xml)]);
        let info = p.info();
        assert_eq!(info["pous"][0]["name"], "ladder_demo");
        assert_eq!(info["pous"][0]["lang"], "LD");
        assert_eq!(info["pous"][0]["graphical"], true);
        assert!(
            info["pous"][0].get("pins").is_none(),
            "a PROGRAM has no pins"
        );
        assert_eq!(
            info["instances"],
            json!([{"name": "main", "pou": "ladder_demo"}])
        );
        let res = &info["configurations"][0]["resources"][0];
        assert_eq!(res["tasks"][0]["props"]["interval"], "T#20ms");
        assert_eq!(res["programs"][0]["task"], "main_task");
        let d = p.diagram("LADDER_DEMO").unwrap();
        assert_eq!(d["lang"], "LD");
        let elems = d["elements"].as_array().unwrap();
        let of = |k: &str| elems.iter().filter(|e| e["kind"] == k).count();
        assert_eq!((of("contact"), of("coil"), of("block")), (7, 3, 2));
        let stop = elems.iter().find(|e| e["text"] == "stop_pb").unwrap();
        assert_eq!(stop["negated"], "true");
        assert_eq!(stop["ins"][0]["conns"].as_array().unwrap().len(), 2);
        assert_eq!(stop["ins"][0]["x"], 140.0);
        let ctu = elems.iter().find(|e| e["typeName"] == "CTU").unwrap();
        let pins: Vec<&str> = ctu["ins"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["name"].as_str().unwrap())
            .collect();
        assert_eq!(pins, ["CU", "R", "PV"]);
        assert_eq!(ctu["outs"][1]["name"], "CV");
        assert_eq!(ctu["outs"][1]["y"], 360.0);
        assert!(p.diagram("nothing").is_err());
        // A check of the file edited: the diagnostic is in it, at the XML.
        let bad = xml.replacen(
            "<variable>stop_pb</variable>",
            "<variable>stop_btn</variable>",
            1,
        );
        let r = p
            .check(&loader, "file=ladder_demo.xml", bad.clone().into_bytes())
            .unwrap();
        assert_eq!(r["ok"], false);
        let d = &r["diagnostics"][0];
        assert_eq!(d["here"], true);
        let from = d["from"].as_u64().unwrap() as usize;
        assert_eq!(&bad[from..from + 8], "stop_btn");
        assert_eq!(
            p.check(&loader, "file=ladder_demo.xml", xml.into())
                .unwrap()["ok"],
            true
        );
        assert!(p.check(&loader, "file=other.xml", Vec::new()).is_err());
        assert!(p.check(&loader, "lang=c", Vec::new()).is_err());
    }

    #[test]
    fn pins_of_a_plcopen_function() {
        let xml = include_str!("../../tests/programs/plcopen/fbd_user_function.xml");
        let (p, _) = project(&[("f.xml", xml)]);
        let info = p.info();
        let scale = info["pous"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == "SCALE3")
            .expect("SCALE3");
        assert_eq!(
            scale["pins"],
            json!({"inputs": [["x", "INT"], ["k", "INT"]], "outputs": [], "result": "INT"})
        );
    }

    #[test]
    fn textual_pous_with_their_places() {
        let st = "FUNCTION_BLOCK fb\nVAR_INPUT x : INT; END_VAR\nEND_FUNCTION_BLOCK\nTYPE t : INT; END_TYPE\nPROGRAM p\nVAR f : fb; END_VAR\nf(x := 1);\nEND_PROGRAM\n";
        let (p, loader) = project(&[("a.st", st)]);
        let info = p.info();
        let pous = info["pous"].as_array().unwrap();
        assert_eq!(pous.len(), 2);
        assert_eq!(pous[0]["kind"], "functionBlock");
        assert_eq!(pous[1]["name"], "p");
        assert_eq!(pous[1]["line"], 5);
        assert_eq!(pous[1]["graphical"], false);
        // The pins the ladder editor places the FB with; a PROGRAM has none.
        assert_eq!(
            pous[0]["pins"],
            json!({"inputs": [["x", "INT"]], "outputs": [], "result": null})
        );
        assert!(pous[1].get("pins").is_none());
        assert_eq!(info["types"][0]["name"], "t");
        assert_eq!(info["instances"], json!([{"name": "p", "pou": "p"}]));
        assert_eq!(p.file("0").unwrap()["text"], st);
        assert!(p.file("1").is_err());
        let r = p
            .check(
                &loader,
                "lang=st",
                b"PROGRAM q\ny := 1;\nEND_PROGRAM".to_vec(),
            )
            .unwrap();
        assert_eq!(r["errors"], 1);
        assert_eq!(r["diagnostics"][0]["line"], 2);
    }

    #[test]
    fn base64_as_the_rfc_gives_it() {
        for (raw, enc) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), enc);
        }
    }

    #[test]
    fn the_example_builds_for_the_chip_the_vm_and_c() {
        let xml = include_str!("../../examples/ladder_demo.xml");
        let (p, loader) = project(&[("ladder_demo.xml", xml)]);
        let pic = p.build(&loader, "target=pic16f876a", Vec::new()).unwrap();
        assert_eq!(pic["ok"], true, "{pic}");
        let names: Vec<&str> = pic["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["ladder_demo.hex", "ladder_demo.asm"]);
        assert!(pic["summary"].as_str().unwrap().contains("flash"), "{pic}");
        let vm = p.build(&loader, "target=vmasm", Vec::new()).unwrap();
        let names: Vec<&str> = vm["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            names,
            ["ladder_demo.xcp", "ladder_demo.dcp", "ladder_demo.asm"]
        );
        let c = p.build(&loader, "target=c", Vec::new()).unwrap();
        assert!(
            c["files"]
                .as_array()
                .unwrap()
                .iter()
                .any(|f| f["name"] == "POUS.c"),
            "{c}"
        );
        let bad = xml.replacen(
            "<variable>stop_pb</variable>",
            "<variable>stop_btn</variable>",
            1,
        );
        let r = p
            .build(&loader, "target=c&file=ladder_demo.xml", bad.into_bytes())
            .unwrap();
        assert_eq!(r["ok"], false);
        assert!(r["errors"].as_str().unwrap().contains("stop_btn"));
        assert!(p.build(&loader, "target=host", Vec::new()).is_err());
        // Target settings: a pin of the chip moved (the assembly reads RA2), an
        // unknown setting reported, a malformed one refused.
        let asm = |r: &Json| {
            let f = r["files"]
                .as_array()
                .unwrap()
                .iter()
                .find(|f| f["name"] == "ladder_demo.asm");
            String::from_utf8(decode64(f.unwrap()["base64"].as_str().unwrap())).unwrap()
        };
        let moved = p
            .build(
                &loader,
                "target=pic16f876a&set=pin.%25IX0.0%3DRA2",
                Vec::new(),
            )
            .unwrap();
        assert_eq!(moved["ok"], true, "{moved}");
        assert_ne!(asm(&moved), asm(&pic));
        assert!(asm(&moved).contains("RA2") || asm(&moved).contains("PORTA, 2"));
        let unknown = p
            .build(&loader, "target=vmasm&set=bogus%3D1", Vec::new())
            .unwrap();
        assert_eq!(unknown["ok"], false);
        assert!(
            unknown["errors"].as_str().unwrap().contains("bogus"),
            "{unknown}"
        );
        assert!(p
            .build(&loader, "target=vmasm&set=mode", Vec::new())
            .is_err());
    }

    /// Standard base64 back to bytes (for the tests).
    fn decode64(s: &str) -> Vec<u8> {
        const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut bits = 0u32;
        let mut n = 0;
        let mut out = Vec::new();
        for c in s.bytes().filter(|&c| c != b'=') {
            bits = (bits << 6) | ABC.iter().position(|&x| x == c).unwrap() as u32;
            n += 6;
            if n >= 8 {
                n -= 8;
                out.push((bits >> n) as u8);
            }
        }
        out
    }

    #[test]
    fn offsets_count_utf16_units() {
        assert_eq!(utf16("aé€b", 0), 0);
        assert_eq!(utf16("aé€b", 3), 2);
        assert_eq!(utf16("aé€b", 6), 3);
        assert_eq!(utf16("a😀b", 5), 3);
        assert_eq!(utf16("ab", 9), 2);
    }
}
