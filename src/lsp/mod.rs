//! `plcc lsp`: a language server over standard input and output.
//!
//! Messages are read by a thread of their own (Content-Length framing, a message of
//! at most [`MAX_MESSAGE`] bytes) and handled one at a time on the main thread: no
//! async runtime. A document's project is its folder: every source file in it (not
//! in its subfolders), with the open documents' unsaved texts instead of the disk's.
//! Each change marks the folder to build again; the build runs when no message is
//! waiting, so a burst of edits is built once. Diagnostics go to the file they are
//! about; the syntax trees answer outlines, hovers, definitions, references and
//! completion ([`index`]).

pub mod doc;
pub mod index;
pub mod outline;
pub mod text;
pub mod tokens;
pub mod xml;

use crate::driver::{self, Build, BuildOptions};
use index::{Decl, Index};
use lsp_server::{ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::*;
use plcc_frontend::Lang;
use plcc_ir::diag::{FileId, Severity, Span};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::io::{BufRead, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use text::Lines;

/// The largest message body accepted (a larger Content-Length ends the server with
/// status 1 rather than allocating it).
pub const MAX_MESSAGE: usize = 64 << 20;
/// The longest header line accepted.
const MAX_HEADER_LINE: u64 = 4096;
/// A folder's files built together: at most this many (in name order).
pub const MAX_FILES: usize = 500;
/// A file on disk larger than this is left out of its folder's build.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Runs the server on standard input and output until `exit` or the end of the
/// input; the exit status is 0 after `shutdown` then `exit`, else 1.
pub fn run() -> u8 {
    let (tx, rx) = mpsc::channel();
    // The reader ends with the input; it is not joined (it may sit in a read).
    let spawned = std::thread::Builder::new()
        .name("lsp-reader".into())
        .spawn(move || read_loop(&mut std::io::stdin().lock(), &tx));
    if let Err(e) = spawned {
        eprintln!("plcc lsp: cannot start the reader thread: {e}");
        return 1;
    }
    Server::default().run(&rx)
}

/// A source file of a folder: its path, its URI, and whether it starts with a BOM.
type FileOnDisk = (PathBuf, Url, bool);

/// What the reader thread hands the main loop.
enum Incoming {
    /// A well-formed message.
    Msg(Message),
    /// The input ended between messages.
    Eof,
    /// The stream cannot be read on (bad framing, an I/O error).
    Broken(String),
}

fn read_loop(input: &mut impl BufRead, tx: &mpsc::Sender<Incoming>) {
    loop {
        let incoming = match read_frame(input) {
            Ok(None) => Incoming::Eof,
            Err(e) => Incoming::Broken(e),
            Ok(Some(body)) => match serde_json::from_slice::<Message>(&body) {
                Ok(m) => Incoming::Msg(m),
                Err(e) => {
                    // JSON-RPC: an error response with a null id, and go on.
                    let code = if serde_json::from_slice::<serde_json::Value>(&body).is_ok() {
                        ErrorCode::InvalidRequest
                    } else {
                        ErrorCode::ParseError
                    };
                    write_json(&serde_json::json!({
                        "jsonrpc": "2.0",
                        "id": null,
                        "error": {"code": code as i32, "message": format!("not a JSON-RPC message: {e}")},
                    }));
                    continue;
                }
            },
        };
        let last = !matches!(incoming, Incoming::Msg(_));
        if tx.send(incoming).is_err() || last {
            return;
        }
    }
}

/// One message body: `None` at the end of the input before any header.
fn read_frame(input: &mut impl BufRead) -> Result<Option<Vec<u8>>, String> {
    let mut length = None;
    let mut first = true;
    let mut line = Vec::new();
    loop {
        line.clear();
        let n = input
            .by_ref()
            .take(MAX_HEADER_LINE)
            .read_until(b'\n', &mut line)
            .map_err(|e| format!("reading a header: {e}"))?;
        if n == 0 {
            return if first {
                Ok(None)
            } else {
                Err("the input ended inside a header".into())
            };
        }
        first = false;
        let Some(l) = line.strip_suffix(b"\n") else {
            return Err("a header line too long or not ended".into());
        };
        let l = l.strip_suffix(b"\r").unwrap_or(l);
        if l.is_empty() {
            break;
        }
        let l = std::str::from_utf8(l).map_err(|_| "a header that is not text".to_string())?;
        let (name, value) = l
            .split_once(':')
            .ok_or_else(|| format!("a malformed header `{l}`"))?;
        if name.trim().eq_ignore_ascii_case("Content-Length") {
            let v = value.trim();
            length = Some(
                v.parse::<usize>()
                    .map_err(|_| format!("a bad Content-Length `{v}`"))?,
            );
        }
    }
    let length = length.ok_or("a message without Content-Length")?;
    if length > MAX_MESSAGE {
        return Err(format!(
            "a message of {length} bytes (at most {MAX_MESSAGE})"
        ));
    }
    let mut body = vec![0; length];
    input
        .read_exact(&mut body)
        .map_err(|e| format!("reading a message body: {e}"))?;
    Ok(Some(body))
}

/// Writes one framed message to standard output (errors are left to the reader:
/// a client that closed its end closes our input too).
fn write_json(v: &impl serde::Serialize) {
    let Ok(body) = serde_json::to_string(v) else {
        return;
    };
    let mut out = std::io::stdout().lock();
    let _ = write!(out, "Content-Length: {}\r\n\r\n{body}", body.len());
    let _ = out.flush();
}

fn send(msg: Message) {
    if let Ok(serde_json::Value::Object(mut m)) = serde_json::to_value(&msg) {
        m.insert("jsonrpc".into(), "2.0".into());
        write_json(&m);
    }
}

fn notify<N: lsp_types::notification::Notification>(params: N::Params) {
    send(Message::Notification(Notification::new(
        N::METHOD.to_string(),
        params,
    )));
}

/// An open document.
struct Doc {
    uri: Url,
    text: String,
}

/// A folder's last build and what was published from it.
#[derive(Default)]
struct Group {
    analysis: Option<Analysis>,
    /// The files whose last published diagnostics were not empty.
    published: BTreeSet<Url>,
}

/// One file of a folder's build.
struct FileEntry {
    id: FileId,
    path: PathBuf,
    uri: Url,
    /// The text began with a byte order mark, which decoding dropped.
    bom: bool,
}

/// A folder's build, with the index of its syntax trees.
struct Analysis {
    build: Build,
    files: Vec<FileEntry>,
    index: Index,
}

impl Analysis {
    fn file(&self, path: &Path) -> Option<&FileEntry> {
        self.files.iter().find(|f| f.path == path)
    }

    fn file_of(&self, id: FileId) -> Option<&FileEntry> {
        self.files.iter().find(|f| f.id == id)
    }

    fn lines(&self, f: &FileEntry) -> Lines<'_> {
        Lines::new(self.build.sources.get(f.id), f.bom)
    }

    /// The place of a span in a file of the folder: a span of a PLCopen file's view
    /// in the XML where it is copied verbatim from there, else nowhere.
    fn location(&self, span: Span) -> Option<Location> {
        self.file_location(xml::exact(&self.build.ladder, &self.build.sources, span)?)
    }

    /// As [`Analysis::location`], but a span of a view not copied verbatim is at the
    /// XML element it comes from (for a definition).
    fn location_or_element(&self, span: Span) -> Option<Location> {
        self.file_location(xml::place(&self.build.ladder, &self.build.sources, span)?)
    }

    fn file_location(&self, span: Span) -> Option<Location> {
        let f = self.file_of(span.file)?;
        Some(Location::new(f.uri.clone(), self.lines(f).range(span)))
    }

    /// The file and offset a name at `offset` of the folder's file `f` is resolved
    /// at: in the view for a PLCopen file, where the XML is copied verbatim there.
    fn resolve_place(&self, f: &FileEntry, offset: u32) -> (FileId, u32) {
        xml::to_view(&self.build.ladder, f.id, offset).unwrap_or((f.id, offset))
    }
}

#[derive(Default)]
struct Server {
    opts: BuildOptions,
    initialized: bool,
    shut_down: bool,
    docs: HashMap<PathBuf, Doc>,
    groups: HashMap<PathBuf, Group>,
    dirty: BTreeSet<PathBuf>,
}

/// A request's failure: the JSON-RPC error code and message.
type Failure = (ErrorCode, String);

impl Server {
    fn run(&mut self, rx: &mpsc::Receiver<Incoming>) -> u8 {
        loop {
            let incoming = match rx.try_recv() {
                Ok(m) => m,
                Err(mpsc::TryRecvError::Empty) => {
                    self.flush();
                    match rx.recv() {
                        Ok(m) => m,
                        Err(_) => return 1,
                    }
                }
                Err(mpsc::TryRecvError::Disconnected) => return 1,
            };
            match incoming {
                Incoming::Msg(Message::Request(req)) => self.request(req),
                Incoming::Msg(Message::Notification(n)) => {
                    if let Some(status) = self.notification(n) {
                        return status;
                    }
                }
                Incoming::Msg(Message::Response(_)) => {}
                Incoming::Eof => return 1,
                Incoming::Broken(why) => {
                    eprintln!("plcc lsp: {why}");
                    return 1;
                }
            }
        }
    }

    fn request(&mut self, req: Request) {
        let id = req.id.clone();
        let result = if !self.initialized && req.method != request::Initialize::METHOD {
            Err((
                ErrorCode::ServerNotInitialized,
                "the server is not initialized".to_string(),
            ))
        } else if self.shut_down {
            Err((
                ErrorCode::InvalidRequest,
                "the server is shut down".to_string(),
            ))
        } else {
            self.answer(req)
        };
        let resp = match result {
            Ok(v) => Response::new_ok(id, v),
            Err((code, msg)) => Response::new_err(id, code as i32, msg),
        };
        send(Message::Response(resp));
    }

    fn answer(&mut self, req: Request) -> Result<serde_json::Value, Failure> {
        fn params<P: serde::de::DeserializeOwned>(req: Request) -> Result<P, Failure> {
            serde_json::from_value(req.params)
                .map_err(|e| (ErrorCode::InvalidParams, format!("bad params: {e}")))
        }
        fn ok<T: serde::Serialize>(v: T) -> Result<serde_json::Value, Failure> {
            serde_json::to_value(v).map_err(|e| (ErrorCode::InternalError, e.to_string()))
        }
        match req.method.as_str() {
            request::Initialize::METHOD => {
                if self.initialized {
                    return Err((ErrorCode::InvalidRequest, "initialized twice".into()));
                }
                let p: InitializeParams = params(req)?;
                ok(self.initialize(p))
            }
            request::Shutdown::METHOD => {
                self.shut_down = true;
                ok(())
            }
            request::DocumentSymbolRequest::METHOD => {
                let p: DocumentSymbolParams = params(req)?;
                ok(self.document_symbols(&p.text_document.uri))
            }
            request::HoverRequest::METHOD => {
                let p: HoverParams = params(req)?;
                ok(self.hover(&p.text_document_position_params))
            }
            request::GotoDefinition::METHOD => {
                let p: GotoDefinitionParams = params(req)?;
                ok(self
                    .definition(&p.text_document_position_params)
                    .map(GotoDefinitionResponse::Scalar))
            }
            request::References::METHOD => {
                let p: ReferenceParams = params(req)?;
                ok(self.references(&p))
            }
            request::Completion::METHOD => {
                let p: CompletionParams = params(req)?;
                ok(self
                    .completion(&p.text_document_position)
                    .map(CompletionResponse::Array))
            }
            request::Rename::METHOD => {
                let p: RenameParams = params(req)?;
                let edit = self.rename(&p.text_document_position, &p.new_name)?;
                ok(edit)
            }
            request::SemanticTokensFullRequest::METHOD => {
                let p: SemanticTokensParams = params(req)?;
                ok(self.semantic_tokens(&p.text_document.uri))
            }
            request::Formatting::METHOD => {
                let p: DocumentFormattingParams = params(req)?;
                let edits = self.format(&p.text_document.uri)?;
                ok(edits)
            }
            m => Err((
                ErrorCode::MethodNotFound,
                format!("method `{m}` is not supported"),
            )),
        }
    }

    fn initialize(&mut self, p: InitializeParams) -> InitializeResult {
        let dialect = p
            .initialization_options
            .as_ref()
            .and_then(|o| o.get("dialect"))
            .and_then(|d| d.as_str())
            .map(str::to_ascii_lowercase);
        match dialect.as_deref() {
            Some("codesys") => {
                self.opts.codesys = true;
                self.opts.dialect_given = true;
            }
            Some("iec") => self.opts.dialect_given = true,
            Some(other) => log(&format!(
                "unknown dialect `{other}` (use iec or codesys); the files decide"
            )),
            None => {}
        }
        self.opts.check_only = true;
        self.initialized = true;
        InitializeResult {
            capabilities: ServerCapabilities {
                text_document_sync: Some(TextDocumentSyncCapability::Options(
                    TextDocumentSyncOptions {
                        open_close: Some(true),
                        change: Some(TextDocumentSyncKind::FULL),
                        save: Some(TextDocumentSyncSaveOptions::SaveOptions(SaveOptions {
                            include_text: Some(true),
                        })),
                        ..Default::default()
                    },
                )),
                document_symbol_provider: Some(OneOf::Left(true)),
                hover_provider: Some(HoverProviderCapability::Simple(true)),
                definition_provider: Some(OneOf::Left(true)),
                references_provider: Some(OneOf::Left(true)),
                completion_provider: Some(CompletionOptions {
                    trigger_characters: Some(vec![".".into()]),
                    ..Default::default()
                }),
                rename_provider: Some(OneOf::Left(true)),
                document_formatting_provider: Some(OneOf::Left(true)),
                semantic_tokens_provider: Some(
                    SemanticTokensServerCapabilities::SemanticTokensOptions(
                        SemanticTokensOptions {
                            legend: tokens::legend(),
                            full: Some(SemanticTokensFullOptions::Bool(true)),
                            ..Default::default()
                        },
                    ),
                ),
                ..Default::default()
            },
            server_info: Some(ServerInfo {
                name: "plcc".into(),
                version: Some(env!("CARGO_PKG_VERSION").into()),
            }),
        }
    }

    /// Handles a notification; `Some(status)` ends the server.
    fn notification(&mut self, n: Notification) -> Option<u8> {
        if n.method == notification::Exit::METHOD {
            return Some(if self.shut_down { 0 } else { 1 });
        }
        if !self.initialized || self.shut_down {
            return None;
        }
        fn params<P: serde::de::DeserializeOwned>(n: Notification) -> Option<P> {
            serde_json::from_value(n.params)
                .map_err(|e| log(&format!("bad params of a notification: {e}")))
                .ok()
        }
        match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                let p: DidOpenTextDocumentParams = params(n)?;
                let d = p.text_document;
                self.set_text(d.uri, d.text);
            }
            notification::DidChangeTextDocument::METHOD => {
                let p: DidChangeTextDocumentParams = params(n)?;
                let path = p.text_document.uri.to_file_path().ok()?;
                let doc = self.docs.get_mut(&path)?;
                for change in p.content_changes {
                    apply_change(&mut doc.text, change);
                }
                self.mark(&path);
            }
            notification::DidSaveTextDocument::METHOD => {
                let p: DidSaveTextDocumentParams = params(n)?;
                match p.text {
                    Some(text) => self.set_text(p.text_document.uri, text),
                    None => self.mark(&p.text_document.uri.to_file_path().ok()?),
                }
            }
            notification::DidCloseTextDocument::METHOD => {
                let p: DidCloseTextDocumentParams = params(n)?;
                let path = p.text_document.uri.to_file_path().ok()?;
                self.docs.remove(&path);
                let dir = folder(&path);
                if self.docs.keys().any(|p| folder(p) == dir) {
                    self.mark(&path);
                } else if let Some(g) = self.groups.remove(&dir) {
                    // Nothing of the folder is open: its diagnostics go with it.
                    self.dirty.remove(&dir);
                    for uri in g.published {
                        publish(uri, Vec::new());
                    }
                }
            }
            _ => {}
        }
        None
    }

    fn set_text(&mut self, uri: Url, text: String) {
        let Ok(path) = uri.to_file_path() else {
            log(&format!("{uri}: only file: documents are checked"));
            return;
        };
        self.docs.insert(path.clone(), Doc { uri, text });
        self.mark(&path);
    }

    fn mark(&mut self, path: &Path) {
        self.dirty.insert(folder(path));
    }

    /// Builds every folder marked since the last build and publishes its diagnostics.
    fn flush(&mut self) {
        for dir in std::mem::take(&mut self.dirty) {
            self.build(&dir);
        }
    }

    /// The analysis of the folder of `uri`, built first if it is not current.
    fn analysis(&mut self, uri: &Url) -> Option<(&Analysis, PathBuf)> {
        let path = uri.to_file_path().ok()?;
        let dir = folder(&path);
        if self.dirty.contains(&dir) || !self.groups.contains_key(&dir) {
            self.dirty.remove(&dir);
            self.build(&dir);
        }
        let a = self.groups.get(&dir)?.analysis.as_ref()?;
        Some((a, path))
    }

    fn build(&mut self, dir: &Path) {
        let (texts, entries) = self.folder_sources(dir);
        let opts = self.opts.clone();
        let built = std::panic::catch_unwind(move || {
            driver::build_sources_with_library(texts, Vec::new(), &opts)
        });
        let build = match built {
            Ok(Ok(b)) => b,
            Ok(Err(e)) => {
                log(&format!("{}: {e}", dir.display()));
                return;
            }
            Err(_) => {
                log(&format!(
                    "{}: internal error ({}): the compiler panicked; please report it with these files",
                    dir.display(),
                    driver::E_INTERNAL
                ));
                return;
            }
        };
        let mut files = Vec::new();
        let mut langs = Vec::new();
        for (k, (path, uri, bom)) in entries.into_iter().enumerate() {
            let id = FileId(k as u32);
            if build.sources.get(id).name != path.display().to_string() {
                continue;
            }
            if let Some(lang) = Lang::from_path(&build.sources.get(id).name) {
                langs.push((id, lang));
            }
            files.push(FileEntry { id, path, uri, bom });
        }
        // The views of the PLCopen files are parsed as the front end parses them.
        langs.extend(build.ladder.iter().map(|v| (v.il, Lang::Il)));
        let index = Index::new(&build.sources, &langs);
        let analysis = Analysis {
            build,
            files,
            index,
        };
        let fallback = self
            .docs
            .iter()
            .filter(|(p, _)| folder(p) == dir)
            .map(|(_, d)| d.uri.clone())
            .min();
        let diagnostics = lsp_diagnostics(&analysis, fallback.as_ref());
        let group = self.groups.entry(dir.to_path_buf()).or_default();
        let mut targets: BTreeSet<Url> = std::mem::take(&mut group.published);
        targets.extend(diagnostics.keys().cloned());
        targets.extend(
            self.docs
                .iter()
                .filter(|(p, _)| folder(p) == dir)
                .map(|(_, d)| d.uri.clone()),
        );
        for uri in targets {
            let list = diagnostics.get(&uri).cloned().unwrap_or_default();
            if !list.is_empty() {
                group.published.insert(uri.clone());
            }
            publish(uri, list);
        }
        group.analysis = Some(analysis);
    }

    /// The source files of a folder, open documents' texts first: (name, bytes) for
    /// the build, and (path, URI, BOM) of each in the same order.
    fn folder_sources(&self, dir: &Path) -> (Vec<(String, Vec<u8>)>, Vec<FileOnDisk>) {
        let mut paths: BTreeSet<PathBuf> = self
            .docs
            .keys()
            .filter(|p| folder(p) == dir && is_source(p))
            .cloned()
            .collect();
        if let Ok(entries) = std::fs::read_dir(dir) {
            for e in entries.flatten() {
                let p = e.path();
                let small = e
                    .metadata()
                    .is_ok_and(|m| m.is_file() && m.len() <= MAX_FILE_BYTES);
                if small && is_source(&p) {
                    paths.insert(p);
                }
            }
        }
        let mut texts = Vec::new();
        let mut entries = Vec::new();
        for path in paths {
            if texts.len() == MAX_FILES {
                log(&format!(
                    "{}: only the first {MAX_FILES} source files are built together",
                    dir.display()
                ));
                break;
            }
            let (bytes, uri) = match self.docs.get(&path) {
                Some(d) => (d.text.clone().into_bytes(), d.uri.clone()),
                None => {
                    let Ok(bytes) = std::fs::read(&path) else {
                        continue;
                    };
                    // An XML file that is not PLCopen's is not a source.
                    let xml = Lang::from_path(&path.display().to_string()) == Some(Lang::Ld);
                    if xml && !contains(&bytes, b"plcopen.org") {
                        continue;
                    }
                    let Ok(uri) = Url::from_file_path(&path) else {
                        continue;
                    };
                    (bytes, uri)
                }
            };
            let bom = bytes.starts_with(b"\xEF\xBB\xBF");
            texts.push((path.display().to_string(), bytes));
            entries.push((path, uri, bom));
        }
        (texts, entries)
    }

    fn document_symbols(&mut self, uri: &Url) -> Option<DocumentSymbolResponse> {
        let (a, path) = self.analysis(uri)?;
        let f = a.file(&path)?;
        // A PLCopen file's outline is its view's.
        let view = a.build.ladder.iter().find(|v| v.xml == f.id);
        let unit = a.index.unit(view.map_or(f.id, |v| v.il))?;
        let outline = outline::Outline {
            sources: &a.build.sources,
            lines: a.lines(f),
            views: &a.build.ladder,
        };
        Some(DocumentSymbolResponse::Nested(outline.items(&unit.items)))
    }

    /// The declaration under a position, with the span of the name there (in the
    /// view, for a name in a PLCopen file).
    fn resolve(&mut self, at: &TextDocumentPositionParams) -> Option<(&Analysis, Span, Decl<'_>)> {
        let (a, path) = self.analysis(&at.text_document.uri)?;
        let f = a.file(&path)?;
        let (file, offset) = a.resolve_place(f, a.lines(f).offset(at.position));
        let (span, decl) = a.index.resolve_at(file, offset)?;
        Some((a, span, decl))
    }

    /// The declaration under the position (its type, declaration and doc comment)
    /// and the explanation of each diagnostic whose range holds it.
    fn hover(&mut self, at: &TextDocumentPositionParams) -> Option<Hover> {
        let (a, path) = self.analysis(&at.text_document.uri)?;
        let f = a.file(&path)?;
        let lines = a.lines(f);
        let offset = lines.offset(at.position);
        let mut parts = Vec::new();
        let mut range = None;
        // In a PLCopen file, the name in its view; the range where the XML has it.
        let (file, at) = a.resolve_place(f, offset);
        let sources = &a.build.sources;
        let shown = |s: Span| xml::exact(&a.build.ladder, sources, s).map(|s| lines.range(s));
        let raw_xml = file == f.id && Lang::from_path(&sources.get(f.id).name) == Some(Lang::Ld);
        if let Some((span, decl)) = a.index.resolve_at(file, at) {
            parts.push(outline::hover_text(sources, &decl));
            range = shown(span);
        } else if let Some((span, text)) =
            outline::builtin_hover(sources, file, at).filter(|_| !raw_xml)
        {
            parts.push(text);
            range = shown(span);
        }
        let mut codes = BTreeSet::new();
        for d in &a.build.diagnostics {
            let Some(s) = d.span.filter(|s| s.file == f.id) else {
                continue;
            };
            if s.start <= offset && offset <= s.end && codes.insert(d.code) {
                if let Some(info) = crate::commands::code_info(d.code) {
                    parts.push(format!(
                        "**{}** {}\n\n{}",
                        info.code, info.title, info.explanation
                    ));
                    range.get_or_insert_with(|| lines.range(s));
                }
            }
        }
        if parts.is_empty() {
            return None;
        }
        Some(Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value: parts.join("\n\n---\n\n"),
            }),
            range,
        })
    }

    /// Every use of the declaration under the position renamed, the declaration's
    /// own name included, in the folder's text files and PLCopen XML files alike.
    /// Refused when the name is no identifier, when the declaration is not in the
    /// folder's files (the standard library's), when a use in a PLCopen project is
    /// not written verbatim in its XML (or the project does not convert and holds
    /// the name), and when the renamed folder would build with an error the folder
    /// had not (a name taken, say).
    fn rename(
        &mut self,
        at: &TextDocumentPositionParams,
        new_name: &str,
    ) -> Result<Option<WorkspaceEdit>, Failure> {
        let refuse = |why: String| Err((ErrorCode::RequestFailed, why));
        if !plcc_frontend::st::lexer::is_identifier(new_name) || new_name.contains("__") {
            return refuse(format!(
                "`{new_name}` is not a name (letters, digits and single underscores, not a keyword, not starting with a digit)"
            ));
        }
        let opts = self.opts.clone();
        let Some((a, _, decl)) = self.resolve(at) else {
            return Ok(None);
        };
        let old = a
            .build
            .sources
            .get(decl.name().span.file)
            .slice(decl.name().span)
            .to_string();
        let declared = decl.name().span.file;
        if a.file_of(declared).is_none() && xml::view_of(&a.build.ladder, declared).is_none() {
            return refuse(format!(
                "`{old}` is declared in the standard library, not in the folder: it cannot be renamed"
            ));
        }
        let sources = &a.build.sources;
        let xml_files = a
            .files
            .iter()
            .filter(|f| Lang::from_path(&sources.get(f.id).name) == Some(Lang::Ld))
            .map(|f| f.id);
        if let Some(name) = xml::unconverted_use(&a.build.ladder, sources, xml_files, &old) {
            return refuse(format!(
                "the PLCopen project {name} does not convert (it has errors), and it may use `{old}`: rename there by hand, or mend it first"
            ));
        }
        let spans =
            match xml::rename_spans(&a.build.ladder, sources, &a.index.references(&decl), &old) {
                Ok(s) => s,
                Err(why) => return refuse(why),
            };
        // The folder's texts with the spans replaced (from the back of each file).
        let mut texts: Vec<(String, String)> = a
            .files
            .iter()
            .map(|f| {
                let src = a.build.sources.get(f.id);
                (src.name.clone(), src.text.to_string())
            })
            .collect();
        let mut sorted = spans.clone();
        sorted.sort_by_key(|s| std::cmp::Reverse((s.file, s.start)));
        for s in &sorted {
            let Some(k) = a.files.iter().position(|f| f.id == s.file) else {
                return refuse(format!("a use of `{old}` is outside the folder's files"));
            };
            texts[k]
                .1
                .replace_range(s.start as usize..s.end as usize, new_name);
        }
        let errors =
            |diags: &[plcc_ir::diag::Diagnostic]| diags.iter().filter(|d| d.is_error()).count();
        let before = errors(&a.build.diagnostics);
        let texts = texts
            .into_iter()
            .map(|(n, t)| (n, t.into_bytes()))
            .collect();
        match driver::build_sources_with_library(texts, Vec::new(), &opts) {
            Ok(b) if errors(&b.diagnostics) > before => {
                let d = b
                    .diagnostics
                    .iter()
                    .find(|d| d.is_error())
                    .expect("an error");
                let place = d
                    .span
                    .map(|s| format!(" ({})", b.sources.describe(s)))
                    .unwrap_or_default();
                return refuse(format!(
                    "renaming `{old}` to `{new_name}` would give {}: {}{place}",
                    d.code, d.message
                ));
            }
            Ok(_) => {}
            Err(e) => return refuse(format!("the renamed folder does not build: {e}")),
        }
        let mut changes: HashMap<Url, Vec<TextEdit>> = HashMap::new();
        for s in spans {
            if let Some(l) = a.location(s) {
                changes
                    .entry(l.uri)
                    .or_default()
                    .push(TextEdit::new(l.range, new_name.to_string()));
            }
        }
        Ok(Some(WorkspaceEdit::new(changes)))
    }

    /// The semantic tokens of a Structured Text, Instruction List or STL document
    /// ([`tokens`]); none for PLCopen XML.
    fn semantic_tokens(&mut self, uri: &Url) -> Option<SemanticTokensResult> {
        let (a, path) = self.analysis(uri)?;
        let f = a.file(&path)?;
        let src = a.build.sources.get(f.id);
        let lines = a.lines(f);
        let data = match Lang::from_path(&src.name) {
            Some(Lang::St | Lang::Cst) => tokens::tokens(&a.index, f.id, &src.text, &lines, false),
            Some(Lang::Il) => tokens::tokens(&a.index, f.id, &src.text, &lines, true),
            Some(Lang::Stl) => tokens::stl_tokens(&a.index, f.id, &src.text, &lines),
            _ => return None,
        };
        Some(SemanticTokensResult::Tokens(SemanticTokens {
            result_id: None,
            data,
        }))
    }

    /// `plcc fmt` on a Structured Text document: one edit replacing the whole text,
    /// none when it is formatted; an error when it does not parse or is no ST.
    fn format(&mut self, uri: &Url) -> Result<Vec<TextEdit>, Failure> {
        let failed = |why: String| (ErrorCode::RequestFailed, why);
        let path = uri
            .to_file_path()
            .map_err(|()| failed(format!("{uri}: only file: documents are formatted")))?;
        let name = path.display().to_string();
        let format = match Lang::from_path(&name) {
            Some(Lang::St | Lang::Cst) => plcc_frontend::fmt::format_st,
            Some(Lang::Il) => plcc_frontend::fmt::format_il,
            Some(Lang::Stl) => plcc_frontend::fmt::format_stl,
            _ => return Err(failed(format!("{name}: PLCopen XML is not formatted"))),
        };
        let text = match self.docs.get(&path) {
            Some(d) => d.text.clone(),
            None => std::fs::read_to_string(&path).map_err(|e| failed(format!("{name}: {e}")))?,
        };
        let formatted = format(&text).map_err(|e| failed(format!("{name}: not formatted: {e}")))?;
        if formatted == text {
            return Ok(Vec::new());
        }
        Ok(vec![TextEdit::new(
            Range::new(Position::new(0, 0), text::end_of(&text)),
            formatted,
        )])
    }

    fn definition(&mut self, at: &TextDocumentPositionParams) -> Option<Location> {
        let (a, _, decl) = self.resolve(at)?;
        a.location_or_element(decl.name().span)
    }

    /// Every use of the declaration under the position (and the declaration if
    /// asked), in the folder's text files and, where the name is written verbatim,
    /// in its PLCopen XML files; each place once.
    fn references(&mut self, p: &ReferenceParams) -> Option<Vec<Location>> {
        let with_decl = p.context.include_declaration;
        let (a, _, decl) = self.resolve(&p.text_document_position)?;
        let own = a.location(decl.name().span);
        let mut seen = BTreeSet::new();
        Some(
            a.index
                .references(&decl)
                .into_iter()
                .filter_map(|s| a.location(s))
                .filter(|l| with_decl || Some(l) != own.as_ref())
                .filter(|l| {
                    let r = l.range;
                    seen.insert((
                        l.uri.clone(),
                        (r.start.line, r.start.character, r.end.line, r.end.character),
                    ))
                })
                .collect(),
        )
    }

    fn completion(&mut self, at: &TextDocumentPositionParams) -> Option<Vec<CompletionItem>> {
        let (a, path) = self.analysis(&at.text_document.uri)?;
        let f = a.file(&path)?;
        let offset = a.lines(f).offset(at.position);
        let sources = &a.build.sources;
        let mut seen = BTreeSet::new();
        let mut items = Vec::new();
        for d in a.index.visible_at(f.id, offset) {
            let label = sources
                .get(d.name().span.file)
                .slice(d.name().span)
                .to_string();
            // Names with `__` are the standard library's helpers, which no user can write.
            if label.is_empty() || label.contains("__") || !seen.insert(label.to_ascii_uppercase())
            {
                continue;
            }
            let (kind, detail) = completion_kind(sources, &d);
            items.push(CompletionItem {
                label,
                kind: Some(kind),
                detail,
                ..Default::default()
            });
        }
        for (name, signature) in plcc_frontend::lower::STANDARD_FUNCTIONS {
            if seen.insert(name.to_string()) {
                items.push(CompletionItem {
                    label: name.to_string(),
                    kind: Some(CompletionItemKind::FUNCTION),
                    detail: Some(signature.to_string()),
                    ..Default::default()
                });
            }
        }
        Some(items)
    }
}

fn completion_kind(
    sources: &plcc_frontend::source::SourceMap,
    d: &Decl<'_>,
) -> (CompletionItemKind, Option<String>) {
    let text = |s: Span| sources.get(s.file).slice(s).to_string();
    match *d {
        Decl::Var { decl, block, .. } => (
            CompletionItemKind::VARIABLE,
            Some(format!(
                "{} : {}",
                outline::block_keyword(block),
                text(decl.ty.span())
            )),
        ),
        Decl::Pou(p) => (
            match p.kind {
                plcc_frontend::ast::PouKind::Function => CompletionItemKind::FUNCTION,
                plcc_frontend::ast::PouKind::FunctionBlock => CompletionItemKind::CLASS,
                plcc_frontend::ast::PouKind::Program => CompletionItemKind::MODULE,
            },
            None,
        ),
        Decl::Method(..) => (CompletionItemKind::METHOD, None),
        Decl::Property(..) => (CompletionItemKind::PROPERTY, None),
        Decl::Action(_) => (CompletionItemKind::FUNCTION, Some("ACTION".into())),
        Decl::Type(_) => (CompletionItemKind::STRUCT, Some("TYPE".into())),
        Decl::Interface(_) => (CompletionItemKind::INTERFACE, None),
        _ => (CompletionItemKind::TEXT, None),
    }
}

/// Every diagnostic of a build as LSP diagnostics, by the file they are about.
/// Those about no file of the folder (none should be) go to `fallback` at its start,
/// with the place they name.
fn lsp_diagnostics(a: &Analysis, fallback: Option<&Url>) -> BTreeMap<Url, Vec<Diagnostic>> {
    let mut out: BTreeMap<Url, Vec<Diagnostic>> = BTreeMap::new();
    for d in &a.build.diagnostics {
        let mut message = d.message.clone();
        if !d.label.is_empty() && d.label != d.message {
            message.push('\n');
            message.push_str(&d.label);
        }
        for note in &d.notes {
            message.push_str("\nnote: ");
            message.push_str(note);
        }
        let place = d.span.and_then(|s| Some((a.file_of(s.file)?, s)));
        let (uri, range) = match place {
            Some((f, s)) => (f.uri.clone(), a.lines(f).range(s)),
            None => {
                let Some(uri) = fallback else { continue };
                if let Some(s) = d.span {
                    message = format!("{}: {message}", a.build.sources.describe(s));
                }
                (uri.clone(), Range::default())
            }
        };
        let related: Vec<_> = d
            .secondary
            .iter()
            .filter_map(|(s, label)| {
                Some(DiagnosticRelatedInformation {
                    location: a.location(*s)?,
                    message: label.clone(),
                })
            })
            .collect();
        out.entry(uri).or_default().push(Diagnostic {
            range,
            severity: Some(match d.severity {
                Severity::Error => DiagnosticSeverity::ERROR,
                Severity::Warning => DiagnosticSeverity::WARNING,
            }),
            code: Some(NumberOrString::String(d.code.to_string())),
            source: Some("plcc".into()),
            message,
            related_information: (!related.is_empty()).then_some(related),
            ..Default::default()
        });
    }
    out
}

fn publish(uri: Url, diagnostics: Vec<Diagnostic>) {
    notify::<notification::PublishDiagnostics>(PublishDiagnosticsParams {
        uri,
        diagnostics,
        version: None,
    });
}

fn log(message: &str) {
    notify::<notification::LogMessage>(LogMessageParams {
        typ: MessageType::WARNING,
        message: format!("plcc: {message}"),
    });
}

/// Applies one change: the whole text, or a range of it replaced.
fn apply_change(text: &mut String, change: TextDocumentContentChangeEvent) {
    let Some(range) = change.range else {
        *text = change.text;
        return;
    };
    let file = plcc_frontend::source::SourceFile::new("", text.as_str());
    let lines = Lines::new(&file, false);
    let start = lines.offset(range.start) as usize;
    let end = (lines.offset(range.end) as usize).max(start);
    text.replace_range(start..end, &change.text);
}

/// The folder whose files a document is built with.
fn folder(path: &Path) -> PathBuf {
    path.parent().map(Path::to_path_buf).unwrap_or_default()
}

fn is_source(path: &Path) -> bool {
    Lang::from_path(&path.display().to_string()).is_some()
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_read_and_bad_ones_refused() {
        let mut ok: &[u8] = b"Content-Length: 2\r\nContent-Type: x\r\n\r\n{}";
        assert_eq!(read_frame(&mut ok), Ok(Some(b"{}".to_vec())));
        assert_eq!(read_frame(&mut ok), Ok(None));
        let mut huge: &[u8] = b"Content-Length: 99999999999999\r\n\r\n";
        assert!(read_frame(&mut huge).unwrap_err().contains("at most"));
        let mut none: &[u8] = b"Content-Type: x\r\n\r\n{}";
        assert!(read_frame(&mut none).is_err());
        let mut cut: &[u8] = b"Content-Length: 10\r\n\r\n{}";
        assert!(read_frame(&mut cut).is_err());
        let mut garbage: &[u8] = b"hello\n";
        assert!(read_frame(&mut garbage).is_err());
    }

    #[test]
    fn ranged_changes_are_applied_in_utf16() {
        let mut t = "é𝄞x := 1;\nb".to_string();
        apply_change(
            &mut t,
            TextDocumentContentChangeEvent {
                range: Some(Range::new(Position::new(0, 3), Position::new(0, 4))),
                range_length: None,
                text: "y".into(),
            },
        );
        assert_eq!(t, "é𝄞y := 1;\nb");
    }
}
