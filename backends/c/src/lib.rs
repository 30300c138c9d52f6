// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
//! plcc's C backend: the IR as C source against matiec's ABI (the files `iec2c`
//! writes, with its names and layouts), and the `c` target's [`Machine`], which builds
//! that C with the system's compiler into a shared library and runs it in this
//! process.
//!
//! The C is C99 and C++11 at once and has no undefined behaviour: integers are
//! computed in unsigned types (signed wrap-around by the modulo rules), memory is read
//! and written through `memcpy` (no aliasing assumptions), and the divisions, shifts
//! and float-to-integer conversions C leaves undefined are guarded by the IR's
//! [`legalize`](plcc_ir::passes::legalize) pass, told that C defines none of them.
//!
//! - [`names`]: the C names of aggregates, data objects, globals and functions
//!   (matiec's, after the configuration's and resources' names).
//! - [`repr`]: how each variable is held: `__IEC_<T>_t` wrappers, `__IEC_<T>_p` for
//!   located ones, plain.
//! - [`located`]: located variables, checked, and the lines of `LOCATED_VARIABLES.h`.
//! - [`headers`]: plcc's own clean-room `iec_types.h`, `iec_types_all.h`,
//!   `accessor.h` and `iec_std_lib.h`.
//! - [`decls`]: `POUS.h`: struct types, prototypes, the preparation of storage and
//!   the inline helpers.
//! - [`body`]: one IR function as a C function (SSA values as locals, blocks as
//!   labels, block parameters assigned on the edges, variables through the
//!   runtime's accessors).
//! - [`variables`]: the debuggers' list, `VARIABLES.csv`.
//! - [`files`]: the file set (`POUS.c`, `POUS.h`, `LOCATED_VARIABLES.h`,
//!   `VARIABLES.csv`, `<Config>.c`, `<Config>.h`, one `<Res>.c` per resource).
//! - [`cc`]: finding and running the C compiler.
//! - [`harness`]: the extra translation unit of the machine's library (entry points
//!   and the layout tables the machine reads variables with).
//! - [`machine`]: the `c` target's [`Machine`].
//!
//! [`Machine`]: plcc_ir::machine::Machine

#![warn(missing_docs)]

pub mod body;
pub mod cc;
pub mod decls;
pub mod files;
pub mod harness;
pub mod headers;
pub mod located;
pub mod machine;
pub mod names;
pub mod repr;
pub mod variables;

pub use machine::CMachine;

use plcc_ir::backend::{Artifact, Artifacts, Backend, Options, TargetFacts};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::machine::Machine;
use plcc_ir::{ElemType, Module};

/// Diagnostic codes of the C backend.
pub mod codes {
    /// A backend setting or `--emit` value is unknown or has a bad value.
    pub const E_BAD_SETTING: &str = "E9201";
    /// No C compiler was found to build the machine's library.
    pub const E_NO_COMPILER: &str = "E9202";
    /// The C compiler rejected the generated C (a bug of this backend).
    pub const E_CC_FAILED: &str = "E9203";
    /// The built library could not be loaded.
    pub const E_LOAD: &str = "E9204";
    /// The program has unchecked pointers, which the C machine does not run.
    pub const E_UNCHECKED_POINTERS: &str = "E9205";
    /// The IR breaks a rule the backend relies on (a bug of the front end or a pass).
    pub const E_MALFORMED_IR: &str = "E9206";
    /// A located variable the runtime cannot bind (a bad address, a size that does
    /// not hold the type, an aggregate).
    pub const E_LOCATION: &str = "E9207";
    /// Two variables of different types at one address.
    pub const E_LOCATION_TYPES: &str = "E9208";
}

/// Every code the C backend reports, for `plcc explain`.
pub const CODES: &[CodeInfo] = &[
    CodeInfo {
        code: codes::E_BAD_SETTING,
        title: "bad C backend setting",
        explanation: "A `key=value` setting or an `--emit` value given to the C backend is \
unknown or invalid. The backend knows `sanitize` (`none` or `undefined`: the machine \
builds its library with the undefined-behaviour sanitizer; default `none`), `opt` (the C compiler's \
optimisation level, 0 to 3; default 1) and `cc` (the compiler to run; default: `$CC`, \
else `cc`, `gcc` or `clang`, the first found), and `--emit` `c` (the file set, the \
default) or `headers` (plcc's own headers). Example: `-s sanitize=thread` fails; write \
`-s sanitize=undefined`.",
    },
    CodeInfo {
        code: codes::E_NO_COMPILER,
        title: "no C compiler",
        explanation: "`plcc run` and `plcc test` on the `c` target build the generated C \
into a shared library with the system's C compiler, and none was found: neither `$CC` nor \
`cc`, `gcc` or `clang` runs. Install one (`apt-get install gcc`), or name it with \
`-s cc=PATH`. Example: `plcc test prog.st --scenario prog.expect --target c -s \
cc=/no/such/cc` fails. Compiling to C files (`plcc --target c`) needs no compiler.",
    },
    CodeInfo {
        code: codes::E_CC_FAILED,
        title: "the C compiler rejected the generated C",
        explanation: "The C machine's library did not build: the C compiler reported \
errors (or, since the build uses `-Wall -Wextra -Werror`, warnings) in the C plcc \
wrote. The note holds the compiler's output. This is a bug of plcc's C backend, not of \
the program: please report it with the source that triggers it. Other targets run the \
program meanwhile. No correct program shows it, so there is no example.",
    },
    CodeInfo {
        code: codes::E_LOAD,
        title: "cannot load the built library",
        explanation: "The shared library the C compiler built could not be loaded into \
plcc's process (the system's loader refused it, or a symbol plcc needs is missing), or \
its temporary directory could not be made. The message says which; check the space and \
permissions of the temporary directory (`$TMPDIR`). It comes from the system, not from a \
program, so there is no example.",
    },
    CodeInfo {
        code: codes::E_UNCHECKED_POINTERS,
        title: "unchecked pointers on the C machine",
        explanation: "The program uses CODESYS pointers as numbers (`pt := pt + 1`), gives a \
pointer the address of another type, or keeps the address of a temporary, so a pointer \
may hold any address. The C machine runs the program's code in plcc's own process, where \
a wrong address would corrupt plcc instead of raising the fault flag, so `plcc run`/`test` \
on `c` refuse such a program (it still compiles to C files). Example: `pt := ADR(buf); \
pt := pt + 1; x := pt^;` in `--dialect codesys`. Run it with `--target interp`.",
    },
    CodeInfo {
        code: codes::E_MALFORMED_IR,
        title: "malformed IR reached the C backend",
        explanation: "The IR module breaks a rule the C backend relies on (a program body \
or init without the `(ptr)` signature, `init_globals` with parameters, a program naming a \
missing function or data object). This is a bug of plcc's front end or of an IR pass, not \
of the program: please report it with the source that triggers it. No correct program \
shows it, so there is no example.",
    },
    CodeInfo {
        code: codes::E_LOCATION,
        title: "a located variable the runtime cannot bind",
        explanation: "In the C the runtime owns the storage of every located variable \
(`AT %IX0.0`): `LOCATED_VARIABLES.h` lists each address with its elementary type, the \
runtime defines the storage, and the program reaches it through a pointer. So the \
address must be one the runtime binds: `%` then `I`, `Q` or `M`, a size letter `X` \
(a BOOL), `B` (8 bits), `W` (16), `D` (32: DINT, REAL, TIME...) or `L` (64), and \
numbers separated by dots; an address without a size letter (`%I0.1`) is taken as `X` \
for a BOOL. The variable must be elementary: a STRUCT, array or string has no \
location in the runtime's I/O tables. Example: `x AT %IX0.0 : INT;` fails (a bit \
cannot hold an INT); write `x AT %IW0 : INT;`.",
    },
    CodeInfo {
        code: codes::E_LOCATION_TYPES,
        title: "one address, two types",
        explanation: "Two located variables share an address but not a type. The \
runtime defines one storage per address, of one type (`LOCATED_VARIABLES.h` has one line \
per address), so both variables must have the same elementary type. Example: \
`a AT %MW2 : INT;` in one PROGRAM and `b AT %MW2 : WORD;` in another fail; declare \
both INT (or both WORD) and convert where needed.",
    },
];

/// The `c` target: C files against matiec's ABI; its machine builds them with the
/// system's C compiler and runs them here.
///
/// Settings: `sanitize` (`none`, `undefined`; the machine's build only),
/// `opt` (0 to 3, default 1), `cc` (the compiler; default `$CC`, else the first of
/// `cc`, `gcc`, `clang` that runs).
#[derive(Clone, Debug, Default)]
pub struct CBackend;

impl CBackend {
    /// The backend.
    pub fn new() -> CBackend {
        CBackend
    }
}

/// The settings of the backend, parsed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// The sanitizer the machine's library is built with: `none` or `undefined`.
    pub sanitize: String,
    /// The optimisation level (0 to 3).
    pub opt: u8,
    /// The compiler, if named.
    pub cc: Option<String>,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            sanitize: "none".into(),
            opt: 1,
            cc: None,
        }
    }
}

impl Settings {
    /// Reads `key=value` settings.
    pub fn parse(options: &Options) -> Result<Settings, Vec<Diagnostic>> {
        let bad = |m: String| vec![Diagnostic::error_nowhere(codes::E_BAD_SETTING, m)];
        let mut s = Settings::default();
        for (k, v) in &options.settings {
            match k.as_str() {
                "sanitize" => match v.as_str() {
                    "none" | "undefined" => s.sanitize = v.clone(),
                    _ => {
                        return Err(bad(format!(
                            "`sanitize` is `none` or `undefined`, not `{v}` (the address sanitizer cannot be loaded into a running process; see docs/c.md)"
                        )))
                    }
                },
                "opt" => match v.parse::<u8>() {
                    Ok(n) if n <= 3 => s.opt = n,
                    _ => return Err(bad(format!("`opt` is 0, 1, 2 or 3, not `{v}`"))),
                },
                "cc" => s.cc = Some(v.clone()),
                _ => {
                    return Err(bad(format!(
                        "the C backend has no setting `{k}` (it has `sanitize`, `opt` and `cc`)"
                    )))
                }
            }
        }
        Ok(s)
    }
}

impl Backend for CBackend {
    fn facts(&self) -> TargetFacts {
        TargetFacts {
            name: "c",
            pointer_bits: 64,
            little_endian: cfg!(target_endian = "little"),
            elem_types: &ElemType::ALL,
            promotion: plcc_ir::passes::promote::Promotion::Everywhere,
        }
    }

    /// The file set (`--emit c`, the default; each artifact's `kind` is its file
    /// name), or plcc's headers (`--emit headers`).
    fn compile(&self, module: &Module, options: &Options) -> Result<Artifacts, Vec<Diagnostic>> {
        Settings::parse(options)?;
        let files = match options.emit.as_deref() {
            None | Some("c") => files::generate(module)?.into_named(),
            Some("headers") => headers::all()
                .iter()
                .map(|(n, t)| (n.to_string(), t.to_string()))
                .collect(),
            Some(e) => {
                return Err(vec![Diagnostic::error_nowhere(
                    codes::E_BAD_SETTING,
                    format!("the C backend emits `c` or `headers`, not `{e}`"),
                )])
            }
        };
        Ok(Artifacts {
            files: files
                .into_iter()
                .map(|(kind, text)| Artifact {
                    kind,
                    bytes: text.into_bytes(),
                })
                .collect(),
            symbols: Vec::new(),
            summary: None,
        })
    }

    /// The C machine: the module built into a shared library and loaded here.
    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
        Some(
            Settings::parse(options)
                .and_then(|s| CMachine::new(module, &s))
                .map(|m| Box::new(m) as Box<dyn Machine>),
        )
    }
}

/// True if a C compiler is found here (so the `c` target can run programs).
pub fn can_run() -> bool {
    cc::find(None).is_ok()
}
