//! Answers `sizeof` with a target's layout.
//!
//! The front end cannot know how big a type is on the machine that will run the
//! code: one module serves the host, the CPDev VM (packed or 4-byte aligned, 16- or
//! 32-bit addresses) and the PIC16 (BOOL fields eight to a byte). So `SIZEOF` lowers
//! to [`InstData::SizeOf`], and a backend whose instruction selection wants constants
//! runs [`resolve`] with its own layout on the module it translates. Targets that
//! read the instruction directly (the interpreter, the JIT, C's `sizeof`) need not.

use crate::inst::InstData;
use crate::module::Module;
use crate::types::MemType;

/// Replaces every `sizeof.ty T` of `module` with the `iconst.ty` of `size_of(T)`
/// (wrapped to the type's width, as a store of it would be). Returns how many it
/// replaced.
pub fn resolve(module: &mut Module, size_of: impl Fn(MemType) -> u64) -> usize {
    let mut n = 0;
    for f in &mut module.funcs {
        for data in &mut f.insts {
            if let InstData::SizeOf { ty, of } = *data {
                *data = InstData::Iconst {
                    ty,
                    imm: ty.canon_int(size_of(of) as i64),
                };
                n += 1;
            }
        }
    }
    n
}

/// True if `module` has a `sizeof` to resolve.
pub fn any(module: &Module) -> bool {
    module
        .funcs
        .iter()
        .any(|f| f.insts.iter().any(|d| matches!(d, InstData::SizeOf { .. })))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{Layout, LayoutRules};
    use crate::text::parse_module;

    #[test]
    fn resolves_with_the_given_layout() {
        let src =
            "struct %pair struct {\n    var a: i1 BOOL\n    var b: i32 DINT\n    var p: ptr\n}\n\
                   func @f() -> i32 function {\n\
                   block0:\n    v0 = sizeof.i32 %pair\n    v1 = sizeof.i8 i64\n    \
                   v2 = sext.i32 v1\n    v3 = iadd v0, v2\n    return v3\n}\n";
        let m = parse_module(src).expect("parses");
        assert!(any(&m));
        let sizes = |rules: LayoutRules| {
            let mut m = m.clone();
            let layout = Layout::compute(&m, rules);
            assert_eq!(resolve(&mut m, |t| layout.size_of(t) as u64), 2);
            assert!(!any(&m));
            crate::verify::verify_module(&m).expect("still valid");
            m.funcs[0]
                .insts
                .iter()
                .filter_map(|d| match d {
                    InstData::Iconst { imm, .. } => Some(*imm),
                    _ => None,
                })
                .collect::<Vec<_>>()
        };
        // Natural alignment with 8-byte pointers: a at 0, b at 4, p at 8.
        assert_eq!(sizes(LayoutRules::HOST), vec![16, 8]);
        // Packed with 2-byte pointers (the VM's 16-bit mode).
        let packed = LayoutRules {
            ptr_bytes: 2,
            max_align: 1,
        };
        assert_eq!(sizes(packed), vec![7, 8]);
    }
}
