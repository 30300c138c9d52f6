//! The interface that makes a backend pluggable.

use crate::diag::Diagnostic;
use crate::machine::Machine;
use crate::module::Module;
use crate::types::ElemType;

/// What a target is like, as far as front ends and the driver care.
#[derive(Clone, Debug)]
pub struct TargetFacts {
    /// The target's name on the command line.
    pub name: &'static str,
    /// Width of a data address in bits.
    pub pointer_bits: u32,
    /// Byte order of multi-byte values in memory.
    pub little_endian: bool,
    /// The elementary types it can hold; any other is a compile error naming the type
    /// and the target.
    pub elem_types: &'static [ElemType],
    /// Where promoting instance variables to SSA values pays on it (the driver
    /// optimises for it: [`crate::passes::optimize_program_for`]).
    pub promotion: crate::passes::promote::Promotion,
}

/// Options the driver passes to a backend.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// What to produce when the backend has several outputs (`asm`, `hex`, `obj`, …);
    /// `None` for its default.
    pub emit: Option<String>,
    /// Target-specific settings (`key=value` from the command line).
    pub settings: Vec<(String, String)>,
    /// The text of each source file of the module (indexed like `Module::files`),
    /// where known, for listings that show source lines.
    pub sources: Vec<Option<String>>,
    /// The main output file's name without its extension, for outputs that refer to
    /// each other (a description naming its code image); `None` when unknown.
    pub output_stem: Option<String>,
}

/// One output file of a compilation.
#[derive(Clone, Debug)]
pub struct Artifact {
    /// What it is, as an extension: `asm`, `hex`, `xcp`, `dcp`, `o`, `h`.
    pub kind: String,
    /// Its contents.
    pub bytes: Vec<u8>,
}

/// Where a variable ended up on the target.
#[derive(Clone, Debug)]
pub struct Symbol {
    /// The source path (`main.count`).
    pub path: String,
    /// Its address in the target's data memory.
    pub address: u64,
    /// Its size in bytes.
    pub size: u32,
    /// Its IEC type.
    pub elem: ElemType,
}

/// Everything a compilation produces.
#[derive(Clone, Debug, Default)]
pub struct Artifacts {
    /// Output files, the main one first.
    pub files: Vec<Artifact>,
    /// The variables' addresses.
    pub symbols: Vec<Symbol>,
    /// A one-line summary for the user (for example memory usage).
    pub summary: Option<String>,
}

/// A code generator for one target.
pub trait Backend {
    /// What the target can hold.
    fn facts(&self) -> TargetFacts;

    /// Translates a verified module. Errors are diagnostics with codes and, where
    /// possible, source spans.
    fn compile(&self, module: &Module, options: &Options) -> Result<Artifacts, Vec<Diagnostic>>;

    /// A machine that runs the module, if this target can run code here (a JIT, a
    /// simulator, a VM).
    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>>;
}

/// Errors with `code` for the `inline_c` instructions of `module` (C code kept from
/// pragmas for the `c` target), for a backend that cannot run C (`target` names it in
/// the message). One error per instruction, at its span.
pub fn reject_inline_c(
    module: &Module,
    target: &str,
    code: &'static str,
) -> Result<(), Vec<Diagnostic>> {
    let mut errs = Vec::new();
    for f in &module.funcs {
        for (_, i) in f.inst_iter() {
            if matches!(f.inst(i), crate::inst::InstData::InlineC { .. }) {
                let msg = format!(
                    "C code in a pragma cannot run on {target}: only the `c` target copies it into its output"
                );
                errs.push(match f.spans.get(i.index()).copied().flatten() {
                    Some(s) => Diagnostic::error(code, msg, s),
                    None => Diagnostic::error_nowhere(code, format!("{msg} (in `{}`)", f.name)),
                });
            }
        }
    }
    if errs.is_empty() {
        Ok(())
    } else {
        Err(errs)
    }
}
