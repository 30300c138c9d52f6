//! The VS Code extension in `editors/vscode` (docs/editors.md): its manifest names
//! files that exist and grammars whose scope names match, its bundled client starts
//! `plcc lsp`, and its grammars tokenize ST and IL as `test/cases.json` says, checked
//! with node by the committed test bundle (vscode-textmate with Oniguruma, as VS Code
//! tokenizes). VS Code itself is not here: the client is not run.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "common/skip.rs"]
mod skip;

fn ext() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("editors/vscode")
}

fn json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_manifest_names_what_is_there() {
    let m = json(&ext().join("package.json"));
    let c = &m["contributes"];
    let languages: Vec<&str> = c["languages"]
        .as_array()
        .expect("languages")
        .iter()
        .map(|l| l["id"].as_str().expect("an id"))
        .collect();
    assert_eq!(languages, ["iec-st", "iec-il", "plcud-stl"]);
    for l in c["languages"].as_array().unwrap() {
        let conf = l["configuration"].as_str().expect("a configuration");
        json(&ext().join(conf));
    }
    for g in c["grammars"].as_array().expect("grammars") {
        assert!(languages.contains(&g["language"].as_str().unwrap()), "{g}");
        let grammar = json(&ext().join(g["path"].as_str().unwrap()));
        assert_eq!(grammar["scopeName"], g["scopeName"], "{g}");
    }
    assert_eq!(
        c["configuration"]["properties"]["plcc.path"]["default"],
        "plcc"
    );
    let main = ext().join(m["main"].as_str().expect("main"));
    let client = std::fs::read_to_string(&main).expect("the bundled client (node build.mjs)");
    for part in [
        "\"lsp\"",
        "plcc.path",
        "iec-st",
        "iec-il",
        "plcud-stl",
        "**/*.xml",
    ] {
        assert!(
            client.contains(part) || client.contains(&part.replace("plcc.path", "\"path\"")),
            "{} does not have {part}",
            main.display()
        );
    }
}

#[test]
fn the_grammars_tokenize_st_and_il() {
    if Command::new("node").arg("--version").output().is_err() {
        skip::notice("node not found; the grammars of editors/vscode are not tokenized");
        return;
    }
    let o = Command::new("node")
        .arg("test/dist/grammar-test.js")
        .current_dir(ext())
        .output()
        .expect("node runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("checks in 2 cases passed"), "{out}");
}
