//! RETAIN and PERSISTENT variables: which they are, and the `--retain FILE` that
//! keeps their values from one run of `plcc serve` to the next.
//!
//! The variables are those of the `VAR RETAIN` (`PERSISTENT`) blocks of the
//! PROGRAMs (in every instance) and the `VAR_GLOBAL RETAIN` blocks, at top level or
//! in a configuration or resource, each with everything inside it (an FB instance's
//! variables, a struct's fields, an array's elements). The file is JSON,
//! `{"plcc_retain": 1, "values": {"plant.count": 5, ...}}`, written whole to a
//! temporary file and renamed over the old one.

use super::http::{from_json, to_json};
use super::scan::{Value, Var};
use crate::driver::Build;
use plcc_frontend::ast::{Item, PouKind, VarBlock, VarKind};
use plcc_ir::machine::{read_string, write_string, Machine};
use plcc_ir::{AggDef, MemType, Module};
use serde_json::{json, Map, Value as Json};
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// The version of the file format.
const FORMAT: u64 = 1;

/// The names declared in RETAIN blocks: per PROGRAM type (upper case), and the
/// globals'.
fn retain_names(build: &Build) -> (HashMap<String, Vec<String>>, Vec<String>) {
    let mut programs: HashMap<String, Vec<String>> = HashMap::new();
    let mut globals = Vec::new();
    let names = |blocks: &[VarBlock], kinds: &[VarKind]| -> Vec<String> {
        blocks
            .iter()
            .filter(|b| b.retain && kinds.contains(&b.kind))
            .flat_map(|b| b.decls.iter().flat_map(|d| d.names.iter()))
            .map(|n| {
                build
                    .sources
                    .get(n.span.file)
                    .slice(n.span)
                    .to_ascii_uppercase()
            })
            .collect()
    };
    let own = [VarKind::Var, VarKind::Input, VarKind::Output, VarKind::Stat];
    for unit in &build.syntax {
        for item in &unit.items {
            match item {
                Item::Pou(p) => {
                    // VAR_GLOBAL in a POU declares globals (the front end also holds
                    // top-level global blocks this way).
                    globals.extend(names(&p.var_blocks, &[VarKind::Global]));
                    if p.kind != PouKind::Program {
                        continue;
                    }
                    // The front end gathers the VAR_GLOBAL blocks (top level, and a
                    // configuration's and its resources') into a PROGRAM of its own
                    // (`plcc_frontend::GLOBALS_POU`), named nowhere in the source (an
                    // empty span), whose VAR blocks are the globals.
                    if p.name.span.start == p.name.span.end {
                        globals.extend(names(&p.var_blocks, &own));
                        continue;
                    }
                    let name = build
                        .sources
                        .get(p.name.span.file)
                        .slice(p.name.span)
                        .to_ascii_uppercase();
                    programs
                        .entry(name)
                        .or_default()
                        .extend(names(&p.var_blocks, &own));
                }
                Item::Globals(b) => {
                    globals.extend(names(std::slice::from_ref(b), &[VarKind::Global]))
                }
                Item::Configuration(c) => {
                    globals.extend(names(&c.var_blocks, &[VarKind::Global]));
                    for r in &c.resources {
                        globals.extend(names(&r.var_blocks, &[VarKind::Global]));
                    }
                }
                _ => {}
            }
        }
    }
    (programs, globals)
}

/// The retained variables among `vars` (the API's, by canonical path), sorted by
/// path.
pub fn retained(build: &Build, module: &Module, vars: &HashMap<String, Var>) -> Vec<Var> {
    let (programs, globals) = retain_names(build);
    let mut roots: Vec<String> = Vec::new();
    for e in &module.programs {
        let MemType::Agg(agg) = module.data[e.data.index()].ty else {
            continue;
        };
        let AggDef::Struct(s) = module.agg(agg) else {
            continue;
        };
        for n in programs
            .get(&s.name.to_ascii_uppercase())
            .into_iter()
            .flatten()
        {
            roots.push(format!("{}.{n}", e.name).to_ascii_uppercase());
        }
    }
    for g in &globals {
        roots.push(format!("{}.{g}", plcc_frontend::GLOBALS_DATA).to_ascii_uppercase());
    }
    let roots: HashSet<String> = roots.into_iter().collect();
    let mut out: Vec<Var> = vars
        .values()
        .filter(|v| {
            let up = v.path().to_ascii_uppercase();
            // The variable itself, or something inside it.
            let mut cut = up.len();
            loop {
                if roots.contains(&up[..cut]) {
                    return true;
                }
                match up[..cut].rfind(['.', '[']) {
                    Some(i) => cut = i,
                    None => return false,
                }
            }
        })
        .cloned()
        .collect();
    out.sort_by(|a, b| a.path().cmp(b.path()));
    out
}

/// The values of `vars` on `m`, by path.
pub fn snapshot(m: &dyn Machine, vars: &[Var]) -> Result<Map<String, Json>, String> {
    let mut values = Map::new();
    for v in vars {
        let (value, wide) = match v {
            Var::Scalar { path, .. } => (
                Value::Scalar(m.read(path).map_err(|e| format!("reading {path}: {e}"))?),
                false,
            ),
            Var::Str(s) => (
                Value::Str(read_string(m, s).map_err(|e| format!("reading {}: {e}", s.path))?),
                s.wide,
            ),
        };
        values.insert(v.path().to_string(), to_json(&value, wide));
    }
    Ok(values)
}

/// Writes the saved `values` into `m`: each of `vars` that has one. The messages
/// of the values that could not be taken (a variable no longer retained, or of
/// another type now).
pub fn restore(m: &mut dyn Machine, vars: &[Var], values: &Map<String, Json>) -> Vec<String> {
    let mut skipped = Vec::new();
    let by_path: HashMap<&str, &Var> = vars.iter().map(|v| (v.path(), v)).collect();
    for (path, j) in values {
        let Some(var) = by_path.get(path.as_str()) else {
            skipped.push(format!(
                "`{path}` is not a retained variable of this program"
            ));
            continue;
        };
        let written = match from_json(var, j) {
            Ok(Value::Scalar(p)) => m.write(path, p).map_err(|e| e.to_string()),
            Ok(Value::Str(chars)) => match var {
                Var::Str(s) => write_string(m, s, &chars).map_err(|e| e.to_string()),
                Var::Scalar { .. } => Err("not a string".into()),
            },
            Ok(Value::Many(_)) => Err("not one value".into()),
            Err(e) => Err(e),
        };
        if let Err(e) = written {
            skipped.push(format!("`{path}`: {e}"));
        }
    }
    skipped
}

/// Reads a retain file: its values; none if there is no file yet. `Err((status,
/// message))`: 2 when it cannot be read, 1 when it is not a retain file.
pub fn load(path: &Path) -> Result<Map<String, Json>, (u8, String)> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Map::new()),
        Err(e) => return Err((2, format!("cannot read {}: {e}", path.display()))),
    };
    let bad = |why: String| Err((1, format!("{}: {why}", path.display())));
    let j: Json = match serde_json::from_str(&text) {
        Ok(j) => j,
        Err(e) => return bad(format!("not a retain file: {e}")),
    };
    match (&j["plcc_retain"], &j["values"]) {
        (Json::Number(n), Json::Object(values)) if n.as_u64() == Some(FORMAT) => {
            Ok(values.clone())
        }
        _ => bad(format!(
            "not a retain file of format {FORMAT} ({{\"plcc_retain\": {FORMAT}, \"values\": {{...}}}})"
        )),
    }
}

/// Writes a retain file atomically.
pub fn save(path: &Path, values: Map<String, Json>) -> Result<(), String> {
    let text = serde_json::to_string_pretty(&json!({"plcc_retain": FORMAT, "values": values}))
        .map_err(|e| e.to_string())?;
    crate::output::write_atomic(path, format!("{text}\n").as_bytes())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}
