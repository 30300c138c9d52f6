//! The native backend's internal-error paths: IR that breaks the verifier's rules
//! (E8003), a function Cranelift refuses (E8004), code that cannot be placed (E8005),
//! and data too large for the host (E8006) are diagnostics, never panics.

use plcc_ir::backend::{Backend, Options};
use plcc_ir::text::parse_module;
use plcc_native::NativeBackend;

/// A counter program in the IR's text form; `add_ty` is the type of the constant
/// added (`i16` makes it valid).
fn counter(add_ty: &str) -> String {
    format!(
        "struct %p program {{
    var x: i16 INT
}}

data @p: %p program

func @p(ptr) program {{
block0(v0: ptr):
    v1 = field_addr v0, %p.x
    v2 = load.i16 v1
    v3 = iconst.{add_ty} 1
    v4 = iadd v2, v3
    store v4, v1
    return
}}

func @p$init(ptr) init {{
block0(v0: ptr):
    return
}}

program \"p\" data @p body @p init @p$init
"
    )
}

fn codes(r: Result<impl Sized, Vec<plcc_ir::diag::Diagnostic>>) -> Vec<String> {
    match r {
        Ok(_) => vec![],
        Err(ds) => ds
            .iter()
            .map(|d| format!("{} {}", d.code, d.message))
            .collect(),
    }
}

#[test]
fn valid_ir_compiles() {
    let m = parse_module(&counter("i16")).expect("parses");
    plcc_ir::verify::verify_module(&m).expect("valid");
    let b = NativeBackend::new();
    assert!(b.compile(&m, &Options::default()).is_ok());
    assert!(b.machine(&m, &Options::default()).unwrap().is_ok());
}

#[test]
fn malformed_ir_is_e8003_for_objects_and_the_jit() {
    // An i16 plus an i32: the verifier's type rule is broken.
    let m = parse_module(&counter("i32")).expect("parses");
    assert!(plcc_ir::verify::verify_module(&m).is_err());
    let b = NativeBackend::new();
    for got in [
        codes(b.compile(&m, &Options::default())),
        codes(
            b.machine(&m, &Options::default())
                .expect("the host runs code"),
        ),
    ] {
        assert!(!got.is_empty(), "malformed IR was accepted");
        assert!(
            got.iter()
                .all(|d| d.starts_with("E8003 the native backend was given malformed IR")),
            "{got:?}"
        );
    }
}

#[test]
fn data_over_the_limit_is_e8006() {
    // 2^28 LREALs: 2 GiB, over the 1 GiB the native backend allows.
    let text = "struct %p program {
    var a: %big
}
array %big = [268435456 x f64 LREAL] lower 0

data @p: %p program

func @p(ptr) program {
block0(v0: ptr):
    return
}

func @p$init(ptr) init {
block0(v0: ptr):
    return
}

program \"p\" data @p body @p init @p$init
";
    let m = parse_module(text).expect("parses");
    plcc_ir::verify::verify_module(&m).expect("valid");
    let b = NativeBackend::new();
    for got in [
        codes(b.compile(&m, &Options::default())),
        codes(
            b.machine(&m, &Options::default())
                .expect("the host runs code"),
        ),
    ] {
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(got[0].starts_with("E8006 "), "{got:?}");
        assert!(got[0].contains("1073741824"), "{got:?}");
    }
}
