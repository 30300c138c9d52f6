//! What `plcc run` prints: every variable in IEC literal form, the same on every
//! target; unsigned 64-bit values of 2^63 and above are not negative numbers.

use std::path::Path;
use std::process::Command;

#[test]
fn run_prints_unsigned_64_bit_values_unsigned_on_every_target() {
    let prog =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/programs/st/regress/ulint_printing.st");
    for target in ["host", "interp", "vmasm", "pic16f876a"] {
        let out = Command::new(env!("CARGO_BIN_EXE_plcc"))
            .args([
                "run",
                prog.to_str().unwrap(),
                "--target",
                target,
                "--scans",
                "1",
            ])
            .output()
            .expect("plcc runs");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{target}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        for line in [
            "u = 18446744073709551615",
            "w = 16#8000000000000001",
            "h = 9223372036854775808",
            "ud = 4294967295",
        ] {
            assert!(
                text.lines().any(|l| l == line),
                "{target}: no line `{line}` in:\n{text}"
            );
        }
    }
}
