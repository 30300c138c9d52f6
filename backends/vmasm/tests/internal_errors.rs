//! The vmasm backend's internal errors (E9104) are diagnostics, never panics: here a
//! module that breaks an IR rule the backend relies on (a function without blocks,
//! which the IR verifier rejects, so the driver never hands it over).

use plcc_ir::backend::{Backend, Options};
use plcc_ir::text::parse_module;
use plcc_vmasm::VmasmBackend;

const NO_BLOCKS: &str = "struct %p program {
    var x: i16 INT
}

data @p: %p program

func @p(ptr) program {
}

func @p$init(ptr) init {
block0(v0: ptr):
    return
}

program \"p\" data @p body @p init @p$init
";

#[test]
fn a_function_without_blocks_is_e9104() {
    let m = parse_module(NO_BLOCKS).expect("parses");
    assert!(plcc_ir::verify::verify_module(&m).is_err());
    let b = VmasmBackend::new();
    let machine = b
        .machine(&m, &Options::default())
        .expect("the VM runs code");
    for r in [
        b.compile(&m, &Options::default()).map(|_| ()),
        machine.map(|_| ()),
    ] {
        let ds = r.expect_err("the module is refused");
        assert!(
            ds.iter()
                .any(|d| d.code == "E9104" && d.message.contains("function without blocks")),
            "{:?}",
            ds.iter().map(|d| (d.code, &d.message)).collect::<Vec<_>>()
        );
    }
}
