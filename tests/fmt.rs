//! `plcc fmt` (docs/editors.md): every ST, IL and STL file of `tests/programs` and
//! `../shared/corpus` (OSCAT included) formats idempotently, and a file that compiles
//! compiles after formatting to the same optimised IR; snapshots of small layouts;
//! the command's exit statuses and file handling.

use plcc::driver::{build_sources, BuildOptions};
use plcc_frontend::fmt::{format_il, format_st, format_stl, FmtError};
use plcc_frontend::Lang;
use plcc_ir::text::{print_module, PrintOptions};
use std::path::{Path, PathBuf};

#[path = "common/skip.rs"]
mod skip;

#[path = "common/sources.rs"]
mod sources;
use sources::{corpus_files, is_codesys, lang_of, read_text, source_files};

#[path = "common/rng.rs"]
#[allow(dead_code)]
mod rng;

fn format(text: &str, lang: Lang) -> Result<String, FmtError> {
    match lang {
        Lang::Il => format_il(text),
        Lang::Stl => format_stl(text),
        _ => format_st(text),
    }
}

/// The optimised IR of one file as text, or its errors' codes.
fn ir_of(name: &str, text: &str, lang: Lang, codesys: bool) -> Result<String, Vec<String>> {
    let opts = BuildOptions {
        codesys,
        lang: Some(lang),
        ..Default::default()
    };
    let build = build_sources(vec![(name.to_string(), text.as_bytes().to_vec())], &opts)
        .map_err(|e| vec![e.0])?;
    match build.module {
        Some(m) => Ok(print_module(&m, &PrintOptions::default())),
        None => Err(build
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| d.code.to_string())
            .collect()),
    }
}

/// `text` with every line's indentation removed and its keywords in lower case.
fn messed_up(text: &str) -> String {
    let mut interner = plcc_frontend::intern::Interner::new();
    let lexed = plcc_frontend::st::lexer::lex(
        plcc_ir::diag::FileId(0),
        text,
        &mut interner,
        &mut Vec::new(),
    );
    let mut lower = text.to_string();
    for t in &lexed.tokens {
        if t.kind.is_keyword() {
            let r = t.start as usize..t.end as usize;
            let l = lower[r.clone()].to_ascii_lowercase();
            lower.replace_range(r, &l);
        }
    }
    lower
        .lines()
        .map(str::trim_start)
        .collect::<Vec<_>>()
        .join("\n")
}

/// How one file fared.
#[derive(Default)]
struct Tally {
    same_ir: usize,
    not_compiling: Vec<String>,
    not_parsing: Vec<String>,
    failures: Vec<String>,
}

fn check_file(path: &Path, codesys: bool, t: &mut Tally) {
    let lang = lang_of(path).expect("an ST, IL or STL file");
    let text = read_text(path);
    let name = path.display().to_string();
    let once = match format(&text, lang) {
        Ok(s) => s,
        Err(FmtError::Syntax(_)) => {
            t.not_parsing.push(name);
            return;
        }
        Err(e) => {
            t.failures.push(format!("{name}: {e}"));
            return;
        }
    };
    match format(&once, lang) {
        Ok(twice) if twice == once => {}
        Ok(twice) => {
            let line = once
                .lines()
                .zip(twice.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(0);
            t.failures.push(format!(
                "{name}: not idempotent at line {}:\n  {:?}\n  {:?}",
                line + 1,
                once.lines().nth(line).unwrap_or(""),
                twice.lines().nth(line).unwrap_or("")
            ));
            return;
        }
        Err(e) => {
            t.failures
                .push(format!("{name}: the formatted text fails: {e}"));
            return;
        }
    }
    // The same file with its keywords in lower case and no indentation at all formats
    // idempotently too, to the same meaning.
    let messy = messed_up(&text);
    let messy_once = match format(&messy, lang) {
        Ok(s) if format(&s, lang).ok().as_deref() == Some(s.as_str()) => s,
        _ => {
            t.failures
                .push(format!("{name}: not idempotent without indentation"));
            return;
        }
    };
    let original = ir_of(&name, &text, lang, codesys);
    if ir_of(&name, &messy_once, lang, codesys) != original {
        t.failures.push(format!(
            "{name}: without indentation, it formats to another meaning"
        ));
    }
    match (original, ir_of(&name, &once, lang, codesys)) {
        (Ok(a), Ok(b)) if a == b => t.same_ir += 1,
        (Ok(_), Ok(_)) => t.failures.push(format!("{name}: the IR differs")),
        (Err(a), Err(b)) if a == b => t.not_compiling.push(format!("{name} ({})", a.join(" "))),
        (a, b) => t.failures.push(format!(
            "{name}: compiles {} before, {} after formatting",
            if a.is_ok() { "ok" } else { "with errors" },
            if b.is_ok() { "ok" } else { "with errors" },
        )),
    }
}

#[test]
fn corpus_formats_idempotently_to_the_same_ir() {
    let (files, ours) = corpus_files(false, "formatting");
    let mut t = Tally::default();
    for f in &files {
        check_file(f, is_codesys(f), &mut t);
    }
    println!(
        "{} files ({} of tests/programs): {} formatted idempotently to the same IR, \
         {} formatted idempotently with the same errors (they do not compile today), \
         {} refused (they do not parse)",
        files.len(),
        ours,
        t.same_ir,
        t.not_compiling.len(),
        t.not_parsing.len()
    );
    for n in &t.not_parsing {
        println!("  does not parse: {n}");
    }
    for n in &t.not_compiling {
        println!("  does not compile: {n}");
    }
    assert!(t.failures.is_empty(), "{}", t.failures.join("\n"));
    assert!(t.same_ir >= ours / 2, "too few files compiled");
}

fn formatted(text: &str) -> String {
    formatted_as(text, Lang::St)
}

/// `text` formatted as `lang`, checked to format to itself again.
fn formatted_as(text: &str, lang: Lang) -> String {
    let out = format(text, lang).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        format(&out, lang).ok().as_deref(),
        Some(out.as_str()),
        "not idempotent"
    );
    out
}

#[test]
fn lower_case_keywords_and_alignment() {
    insta::assert_snapshot!(formatted(
        "function_block counter
var_input
   up:bool; reset : BOOL;
  limit:int:=100;
end_var
var_output count : int; at_limit:BOOL; END_VAR
var
  r_trig_up , other_edge : R_TRIG;
    buffer: array[0..9] of int := [10(0)];
end_var
r_trig_up(clk:=up);
if reset then count:=0;
elsif r_trig_up.q and count<limit then
count:=count+1;
end_if;
at_limit:=count>=limit;
end_function_block
"
    ));
}

#[test]
fn case_and_nested_ifs() {
    insta::assert_snapshot!(formatted(
        "PROGRAM main
VAR state : INT; x, y : INT; END_VAR
CASE state OF
0: x := 1;
(* before a label *)
1, 2:
IF x > 0 THEN
IF y > 0 THEN
y := y - 1;
ELSE
x := -x;
END_IF;
END_IF;
3..5, 7:
state := 0;
// before ELSE
ELSE
state := state + 1;
END_CASE;
WHILE x < 10 DO x := x + 1; END_WHILE;
REPEAT
y := y + 1;
UNTIL y > 3
END_REPEAT;
FOR x := 1 TO 10 BY 2 DO
y := y * 2;
END_FOR;
END_PROGRAM
"
    ));
}

#[test]
fn comments_in_odd_places() {
    insta::assert_snapshot!(formatted(
        "(* file header *)
// line comment before the POU
PROGRAM main (* after the name *)
VAR
  {attribute 'hide'}
  x : INT;            (* trailing, aligned *)
  longer_name : BOOL; (* with this one *)
  z : INT;   // alone
  /* C-style */ y : REAL := 1.0E3;
END_VAR
  x := (* inside *) x + 16#FF;   (* kept at its column *)



  IF x > 0 THEN
  (* a comment
     over two lines *)
     y := y * 2.0;
  // before END_IF: stays in the block
  END_IF;
  x := fn(a := 1,
  b := 2);
END_PROGRAM
"
    ));
}

#[test]
fn literals_kept_as_spelt() {
    let text = "PROGRAM p\nVAR s : STRING := 'a$N'; t : TIME := t#1s; END_VAR\n\
                x := 16#ff + 2#1010 + 8#17 + 1_000 + 1.0e3 + INT#-5;\nEND_PROGRAM\n";
    let out = formatted(text);
    for lit in [
        "'a$N'", "t#1s", "16#ff", "2#1010", "8#17", "1_000", "1.0e3", "INT#-5",
    ] {
        assert!(out.contains(lit), "{lit} re-spelt:\n{out}");
    }
}

#[test]
fn instruction_list_bodies() {
    let text = "function_block fb\nvar_input a, b : bool; n : int; end_var\n\
                var_output q : bool; end_var\nvar t : ton; end_var\n  ld a\nandn b\n   \
                st q (* the output *)\n ld n\n gt 5\njmpc big\n\n\n and( a\n or b\n )\nst q\n\
                big: cal t(in := a,\npt := t#1s)\n  ret\nend_function_block\n";
    insta::assert_snapshot!(formatted_as(text, Lang::Il));
}

#[test]
fn stl_blocks_and_one_statement_branches() {
    let text = "(* a sequencer *)\nprogram seq;\nvar\nstate : USINT;\nn, total : INT := 5;\nend_var;\n\
                begin\nif state = 0 then\nbegin\nif n > 0 then\nn := n - 1;\nstate := 1;\nend\n\
                else if state = 1 then state := 2\nelse\nstate := 0;\nwhile n < 10 do\nn := n + 1;\n\
                for n := 1 to 3 do begin total := total + n; end;\nrepeat\nn := n - 1;\nuntil n = 0;\n\
                total := total +\nn * 2;   (* kept *)\nend.\n";
    insta::assert_snapshot!(formatted_as(text, Lang::Stl));
}

/// A scratch directory of this test's own.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("fmt_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch directory");
    d
}

fn plcc(args: &[&str], stdin: Option<&str>) -> (i32, String, String) {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_plcc"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("plcc runs");
    let mut input = child.stdin.take().expect("stdin");
    // plcc may end before reading its input (a usage error): then the pipe is
    // closed, and what matters is its status and messages.
    match input.write_all(stdin.unwrap_or("").as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => panic!("stdin: {e}"),
        _ => {}
    }
    drop(input);
    let out = child.wait_with_output().expect("plcc ends");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const UNFORMATTED: &str = "program p\nvar x : int; end_var\nx := x+1;\nend_program\n";
const FORMATTED: &str = "PROGRAM p\nVAR x : int; END_VAR\n    x := x + 1;\nEND_PROGRAM\n";

#[test]
fn cli_prints_checks_and_writes() {
    let d = scratch("cli");
    let messy = d.join("messy.st");
    let tidy = d.join("tidy.st");
    std::fs::write(&messy, UNFORMATTED).unwrap();
    std::fs::write(&tidy, FORMATTED).unwrap();
    let (m, t) = (messy.to_str().unwrap(), tidy.to_str().unwrap());

    // Printed on standard output; the file is not touched.
    let (code, out, _) = plcc(&["fmt", m], None);
    assert_eq!((code, out.as_str()), (0, FORMATTED));
    assert_eq!(std::fs::read_to_string(&messy).unwrap(), UNFORMATTED);

    // Standard input, with `-` or no file.
    assert_eq!(plcc(&["fmt"], Some(UNFORMATTED)).1, FORMATTED);
    assert_eq!(plcc(&["fmt", "-"], Some(UNFORMATTED)).1, FORMATTED);

    // --check: 1 and the name of the file that would change, 0 when none would.
    let (code, out, _) = plcc(&["fmt", "--check", m, t], None);
    assert_eq!(code, 1);
    assert_eq!(out.lines().collect::<Vec<_>>(), [m]);
    assert_eq!(plcc(&["fmt", "--check", t], None).0, 0);
    assert_eq!(std::fs::read_to_string(&messy).unwrap(), UNFORMATTED);

    // --write rewrites the file, which then passes --check; no temporary file is left.
    assert_eq!(plcc(&["fmt", "--write", m], None).0, 0);
    assert_eq!(std::fs::read_to_string(&messy).unwrap(), FORMATTED);
    assert_eq!(plcc(&["fmt", "--check", m], None).0, 0);
    let names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn cli_refuses_broken_and_unreadable_files() {
    let d = scratch("broken");
    let broken = d.join("broken.st");
    let text = "program p\nvar x : int; end_var\nx := (x + ;\nend_program\n";
    std::fs::write(&broken, text).unwrap();
    let b = broken.to_str().unwrap();
    for mode in ["--write", "--check"] {
        let (code, out, err) = plcc(&["fmt", mode, b], None);
        assert_eq!(code, 1, "{mode}");
        assert!(out.is_empty(), "{out}");
        assert!(err.contains("broken.st:3:"), "{err}");
        assert_eq!(std::fs::read_to_string(&broken).unwrap(), text);
    }
    // Missing files and usage errors: 2.
    let missing = d.join("missing.st");
    assert_eq!(plcc(&["fmt", missing.to_str().unwrap()], None).0, 2);
    assert_eq!(plcc(&["fmt", "--check", "--write", b], None).0, 2);
    assert_eq!(plcc(&["fmt", "--write"], Some(UNFORMATTED)).0, 2);
    // PLCopen XML is not formatted: a usage error, the file untouched.
    let xml = d.join("p.xml");
    std::fs::write(&xml, "<project/>\n").unwrap();
    let (code, _, err) = plcc(&["fmt", "--write", xml.to_str().unwrap()], None);
    assert_eq!(code, 2);
    assert!(err.contains("not PLCopen XML"), "{err}");
    assert_eq!(std::fs::read_to_string(&xml).unwrap(), "<project/>\n");
}

#[test]
fn cli_formats_instruction_list_by_extension_or_lang() {
    let d = scratch("il");
    let il = d.join("f.il");
    let messy =
        "function incr : int\nvar_input a:int; end_var\nld a\n add 1\nst incr\nend_function\n";
    let tidy = "FUNCTION incr : int\nVAR_INPUT a : int; END_VAR\n    LD a\n    ADD 1\n    ST incr\nEND_FUNCTION\n";
    std::fs::write(&il, messy).unwrap();
    assert_eq!(
        plcc(&["fmt", il.to_str().unwrap()], None),
        (0, tidy.into(), String::new())
    );
    assert_eq!(plcc(&["fmt", "--lang", "il"], Some(messy)).1, tidy);
    // Read as ST, the same text does not parse.
    assert_eq!(plcc(&["fmt"], Some(messy)).0, 1);
}

/// `text` with, between random tokens, comments of every kind and line breaks.
fn sprinkled(text: &str, rng: &mut rng::Rng) -> String {
    let mut interner = plcc_frontend::intern::Interner::new();
    let lexed = plcc_frontend::st::lexer::lex(
        plcc_ir::diag::FileId(0),
        text,
        &mut interner,
        &mut Vec::new(),
    );
    let mut out = String::with_capacity(text.len() * 2);
    let mut pos = 0;
    for t in &lexed.tokens {
        let start = t.start as usize;
        out.push_str(&text[pos..start]);
        if rng.below(6) == 0 {
            out.push_str(match rng.below(7) {
                0 => " (* c *) ",
                1 => "// line\n",
                2 => "\n",
                3 => " /* c\n  two lines */ ",
                4 => "{attribute 'x'}",
                5 => "\n\n\n",
                _ => "\t(* (* nested *) *)\n",
            });
        }
        out.push_str(&text[start..t.end as usize]);
        pos = t.end as usize;
    }
    out.push_str(&text[pos..]);
    out
}

#[test]
fn comments_and_line_breaks_anywhere() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    source_files(&root.join("tests/programs"), false, &mut files);
    // Line breaks end IL instructions: ST only.
    files.retain(|f| lang_of(f) == Some(Lang::St));
    let mut rng = rng::Rng(0x5eed_f0f0);
    let mut failures = Vec::new();
    let mut checked = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).expect("UTF-8");
        let name = f.display().to_string();
        let codesys = is_codesys(f);
        if ir_of(&name, &text, Lang::St, codesys).is_err() {
            continue;
        }
        let messy = sprinkled(&text, &mut rng);
        // Line breaks matter in IL (a chart's transitions may be written in it).
        let Ok(original) = ir_of(&name, &messy, Lang::St, codesys) else {
            continue;
        };
        let once = match format_st(&messy) {
            Ok(s) => s,
            // A comment or line break may end a line comment's line early or fall
            // inside a pragma-sensitive place the parser rejects: not the formatter's.
            Err(FmtError::Syntax(_)) => continue,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        checked += 1;
        if format_st(&once).ok().as_deref() != Some(once.as_str()) {
            failures.push(format!("{name}: not idempotent"));
        } else if ir_of(&name, &once, Lang::St, codesys) != Ok(original) {
            failures.push(format!("{name}: another meaning"));
        }
    }
    println!("{checked} files with comments and line breaks sprinkled");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked > 250, "only {checked} files checked");
}
