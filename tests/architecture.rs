//! The dependency rule of ARCHITECTURE.md, checked on every Cargo.toml of the
//! workspace: `ir` depends on no crate of ours; the front end and every backend on
//! `plcc-ir` only (in their dependencies, dev-dependencies and build-dependencies
//! alike); only the root package sees everything. Every crate directory under
//! `backends/` is a workspace member (so none escapes the check).
//!
//! Also a house rule of the tests: every insta snapshot file belongs to a test that
//! still names it (a deleted or renamed test leaves no stale `.snap` behind).

use std::path::Path;

/// The crates of ours (`plcc-*`) a manifest names in its dependency sections.
fn our_dependencies(manifest: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_deps = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            let section = line.trim_matches(|c| c == '[' || c == ']');
            in_deps = section.ends_with("dependencies");
            continue;
        }
        if !in_deps {
            continue;
        }
        let name = line
            .split(['=', '.', ' '])
            .next()
            .unwrap_or("")
            .trim_matches('"');
        if name.starts_with("plcc") {
            out.push(name.to_string());
        }
    }
    out
}

/// The workspace members the root manifest lists.
fn members(root: &str) -> Vec<String> {
    let line = root
        .lines()
        .find(|l| l.trim_start().starts_with("members"))
        .expect("a members list");
    line.split('"')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

#[test]
fn every_crate_depends_only_on_what_the_architecture_allows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read =
        |p: &Path| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let members = members(&read(&root.join("Cargo.toml")));
    assert!(members.contains(&"ir".to_string()) && members.contains(&"frontend".to_string()));
    let mut checked = 0;
    for m in &members {
        let deps = our_dependencies(&read(&root.join(m).join("Cargo.toml")));
        let allowed: &[&str] = if m == "ir" { &[] } else { &["plcc-ir"] };
        for d in &deps {
            assert!(
                allowed.contains(&d.as_str()),
                "{m}/Cargo.toml depends on {d}: ARCHITECTURE.md allows {m} {}",
                if allowed.is_empty() {
                    "no crate of ours".to_string()
                } else {
                    allowed.join(", ")
                }
            );
        }
        if m != "ir" {
            assert!(
                deps.iter().any(|d| d == "plcc-ir"),
                "{m} does not use plcc-ir: is it one of ours?"
            );
        }
        checked += 1;
    }
    for e in std::fs::read_dir(root.join("backends")).expect("backends/") {
        let dir = e.expect("an entry").path();
        if dir.join("Cargo.toml").is_file() {
            let rel = format!("backends/{}", dir.file_name().unwrap().to_string_lossy());
            assert!(members.contains(&rel), "{rel} is not a workspace member");
        }
    }
    assert!(checked >= 6, "only {checked} crates checked");
}

#[test]
fn the_check_sees_a_forbidden_dependency() {
    let manifest = "[package]\nname = \"x\"\n[dependencies]\nplcc-ir.workspace = true\nplcc-frontend = { path = \"../frontend\" }\n[dev-dependencies]\n\"plcc-c\" = \"*\"\nserde = \"1\"\n";
    assert_eq!(
        our_dependencies(manifest),
        ["plcc-ir", "plcc-frontend", "plcc-c"]
    );
    assert_eq!(
        members("[workspace]\nmembers = [\"ir\", \"backends/c\"]\n"),
        ["ir", "backends/c"]
    );
}

/// The source file a snapshot's module path points at (`fmt` → `tests/fmt.rs`,
/// `plcc_frontend__st__tests` → `frontend/src/st/tests.rs`), if there is one.
fn snapshot_source(root: &Path, module: &[&str]) -> Option<std::path::PathBuf> {
    let (base, rest) = match *module.first()? {
        "plcc_frontend" => (root.join("frontend/src"), &module[1..]),
        "plcc_ir" => (root.join("ir/src"), &module[1..]),
        "plcc" => (root.join("src"), &module[1..]),
        _ => (root.join("tests"), module),
    };
    let rel = rest.join("/");
    [
        base.join(format!("{rel}.rs")),
        base.join(rel).join("mod.rs"),
    ]
    .into_iter()
    .find(|p| p.is_file())
}

/// The snapshot file names under `dir`'s `snapshots/` directories, recursively.
fn snapshot_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() && !p.ends_with("target") && !p.ends_with("node_modules") {
            snapshot_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "snap") {
            out.push(p);
        }
    }
}

#[test]
fn every_snapshot_belongs_to_a_test_that_names_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for d in ["tests", "frontend", "ir", "backends", "src"] {
        snapshot_files(&root.join(d), &mut files);
    }
    assert!(files.len() > 100, "only {} snapshots found", files.len());
    let mut stale = Vec::new();
    for f in &files {
        let stem = f
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("a UTF-8 name");
        let parts: Vec<&str> = stem.split("__").collect();
        let (module, name) = parts.split_at(parts.len() - 1);
        // The second and later snapshots of one test are `name-2`, `name-3`...
        let name = name[0]
            .rsplit_once('-')
            .filter(|(_, n)| n.chars().all(|c| c.is_ascii_digit()))
            .map_or(name[0], |(n, _)| n);
        let named = snapshot_source(root, module)
            .and_then(|src| std::fs::read_to_string(src).ok())
            .is_some_and(|text| text.contains(name));
        if !named {
            stale.push(f.strip_prefix(root).unwrap_or(f).display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "snapshot files no test names (delete them, or bring the test back): {stale:?}"
    );
}
