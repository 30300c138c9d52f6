// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
//! plcc's PIC16F876A backend: the IR to MPASM assembly and Intel HEX for the chip of
//! the PLC-UD controller, and a simulator of the chip that runs the result.
//!
//! The path (see [`build`]): aggregates are laid out with BOOLs packed into bits
//! ([`ram`]); pointer parameters that every caller passes the same address become
//! constants ([`frame::param_consensus`]; where they differ, as for an FB used twice
//! or a PROGRAM type with several instances, the address is stored in the callee's
//! frame before the call, by the caller's code or by the scan loop); every other SSA
//! value gets a home in its function's static frame, overlaid by liveness, and frames
//! are overlaid through the call graph ([`frame`], [`build`]); [`isel`] emits code
//! with full data addresses; [`banks`] inserts the bank selects the control flow
//! needs; [`asm`] assembles words and prints the listing; [`sim`] runs the words.

#![warn(missing_docs)]

pub mod asm;
pub mod banks;
mod build;
pub mod frame;
pub mod helpers;
pub mod isa;
pub mod isel;
pub mod machine;
pub mod ram;
pub mod runtime;
pub mod sim;
pub mod softfloat;

use asm::{Image, Program};
use plcc_ir::backend::{Artifact, Artifacts, Backend, Options, Symbol, TargetFacts};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::machine::Machine;
use plcc_ir::{ElemType, Module};
use ram::PicLayout;
use runtime::{PinBinding, Rt};

/// Diagnostic codes of the PIC16 backend.
pub mod codes {
    /// An operation or type the chip cannot do (yet).
    pub const E_UNSUPPORTED: &str = "E9001";
    /// Program memory is full.
    pub const E_FLASH: &str = "E9002";
    /// RAM is full.
    pub const E_RAM: &str = "E9003";
    /// The hardware stack is too shallow for the call depth.
    pub const E_STACK: &str = "E9004";
    /// A backend setting is unknown or has a bad value.
    pub const E_BAD_SETTING: &str = "E9005";
    /// A bug of this backend (an internal rule was broken).
    pub const E_INTERNAL: &str = "E9006";
}

/// Every code the PIC16 backend reports, for `plcc explain`.
pub const CODES: &[CodeInfo] = &[
    CodeInfo {
        code: codes::E_UNSUPPORTED,
        title: "not supported on the PIC16F876A",
        explanation: "The program uses an operation that the pic16f876a target cannot \
compile: arithmetic, comparisons or conversions on LREAL (64-bit floating point; LREAL \
variables can still be held, copied and stored). REAL is supported in software: the four \
operations, comparisons, SQRT, TRUNC and rounding, the conversions to and from integers \
(all bit-exact with other targets) and the transcendental functions SIN, COS, TAN, ASIN, \
ACOS, ATAN, LN, LOG, EXP and EXPT (within 2 ulp). The message names the operation and \
points at it. Example: `y := x * 2.5;` on LREALs; declare them REAL.",
    },
    CodeInfo {
        code: codes::E_FLASH,
        title: "program memory full",
        explanation: "The generated code does not fit the chip's 8192 words of program memory \
(or, for now, the first 2048-word page: code that needs PCLATH paging is not generated yet). \
The message says how many words the program needs. Split the program, or move work out of \
large loops that are unrolled.\n\n    CASE step OF 0: ... 1199: ... END_CASE;   (* error: 1,200 branches take 16,455 words *)",
    },
    CodeInfo {
        code: codes::E_RAM,
        title: "data memory full",
        explanation: "The variables, the frames of the functions and the runtime need more than \
the chip's 368 bytes of RAM, or one object (an array, an FB instance, a program's \
variables) is larger than a RAM bank (80 or 96 bytes), which it must fit in. The message \
names what did not fit and by how much. Use smaller types (SINT, BOOL), fewer or smaller \
arrays, or split a program's variables into several programs.\n\n    VAR log : ARRAY[0..99] OF DINT; END_VAR   (* error: 400 bytes, more than the chip has *)\n    VAR log : ARRAY[0..15] OF INT; END_VAR    (* fits: 32 bytes *)",
    },
    CodeInfo {
        code: codes::E_STACK,
        title: "hardware stack too shallow",
        explanation: "The PIC16's return stack has 8 levels; a program that reads the clock (TIME, \
the timers) keeps one for the clock's interrupt. \
The deepest chain of calls (programs, function blocks, functions, runtime helpers for \
multiply and divide) needs more. The message gives the depth. Calls that the optimiser \
inlines do not count; flatten the deepest chain of FB or FUNCTION calls.\n\n    (* error: main calls fb1, fb1 calls fb2, ... fb8: nine levels with the multiply helper *)",
    },
    CodeInfo {
        code: codes::E_BAD_SETTING,
        title: "bad pic16f876a setting",
        explanation: "A `-s key=value` setting of the pic16f876a target is not understood. The \
target knows `pin.LOCATION=PIN`, which binds a located BOOL to a pin, for example \
`-s pin.%IX0.0=RA2` or `-s pin.%QX0.1=RB7`.",
    },
    CodeInfo {
        code: codes::E_INTERNAL,
        title: "internal error of the PIC16 backend",
        explanation: "The backend broke one of its own rules while generating code (for example \
a bank select between a skip and the instruction it skips). This is a bug in plcc; please \
report it with the program. No correct program shows it, so there is no example.",
    },
];

/// The PIC16F876A backend.
#[derive(Clone, Debug, Default)]
pub struct Pic16Backend;

impl Pic16Backend {
    /// The backend.
    pub fn new() -> Pic16Backend {
        Pic16Backend
    }
}

/// Elementary types the chip holds (everything but strings).
const ELEM_TYPES: &[ElemType] = &ElemType::ALL;

impl Backend for Pic16Backend {
    fn facts(&self) -> TargetFacts {
        TargetFacts {
            name: "pic16f876a",
            pointer_bits: 16,
            little_endian: true,
            elem_types: ELEM_TYPES,
            // Values live in RAM here too, but the code sizes of docs/pic16.md were
            // tuned with promotion everywhere; not measured otherwise yet.
            promotion: plcc_ir::passes::promote::Promotion::Everywhere,
        }
    }

    /// MPASM assembly (`asm`, the default) or Intel HEX (`--emit hex`).
    fn compile(&self, module: &Module, options: &Options) -> Result<Artifacts, Vec<Diagnostic>> {
        let b = build(module, options)?;
        let file = match options.emit.as_deref() {
            None | Some("asm") => Artifact {
                kind: "asm".into(),
                bytes: b.program.mpasm().into_bytes(),
            },
            Some("hex") => Artifact {
                kind: "hex".into(),
                bytes: asm::intel_hex(&b.image).into_bytes(),
            },
            Some(other) => {
                return Err(vec![Diagnostic::error_nowhere(
                    codes::E_BAD_SETTING,
                    format!("pic16f876a cannot emit `{other}` (it emits asm or hex)"),
                )])
            }
        };
        Ok(Artifacts {
            files: vec![file],
            symbols: b.symbols.clone(),
            summary: Some(b.summary()),
        })
    }

    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
        Some(
            build(module, options)
                .map(|b| Box::new(machine::PicMachine::new(module, b)) as Box<dyn Machine>),
        )
    }
}

/// Everything a build produces.
#[derive(Clone, Debug)]
pub struct Build {
    /// The code.
    pub program: Program,
    /// The assembled words.
    pub image: Image,
    /// Program variables and their addresses.
    pub symbols: Vec<Symbol>,
    /// The bit of every BOOL variable symbol, by symbol index.
    pub bits: Vec<Option<u8>>,
    /// The listing's name of every variable symbol (`main_count`), by symbol index.
    pub asm_names: Vec<String>,
    /// Bound pins.
    pub pins: Vec<PinBinding>,
    /// Runtime addresses.
    pub rt: Rt,
    /// RAM bytes used (common RAM included).
    pub ram_used: u32,
    /// Deepest use of the hardware stack (interrupt included).
    pub stack_depth: u32,
    /// Bank select instructions inserted.
    pub bank_selects: u32,
    /// Address of the top of the scan loop.
    pub scan_addr: u16,
    /// Address of `plc_scan_end`.
    pub scan_end_addr: u16,
    /// Where each data object is.
    pub data: ram::DataMap,
    /// The layout of aggregates.
    pub layout: PicLayout,
}

impl Build {
    /// `flash N/8192 words, ram N/368 bytes, stack N/8`
    pub fn summary(&self) -> String {
        format!(
            "flash {}/{} words, ram {}/{} bytes, stack {}/8",
            self.image.used_words(),
            asm::FLASH_WORDS,
            self.ram_used,
            ram::RAM_BYTES,
            self.stack_depth
        )
    }
}

pub use build::build;

#[cfg(test)]
mod tests {
    use super::*;

    /// Three instances of one PROGRAM type: `a` and `b` run the shared body straight
    /// from the scan loop, `c` through a wrapper (a configuration's task body) that
    /// runs it twice. The body's instance pointer is no constant, so the runtime must
    /// store each instance's address before calling the shared init and body (it
    /// did not, and the body ran on the 0xA5A5 of uninitialised RAM).
    const SHARED_BODY: &str = r#"
struct %p program {
    var n: i16 INT
    var acc: i16 INT
}

data @a: %p program
data @b: %p program
data @c: %p program

func @p(ptr) program {
block0(v0: ptr):
    v1 = field_addr v0, %p.n
    v2 = load.i16 v1
    v3 = iconst.i16 1
    v4 = iadd v2, v3
    store v4, v1
    v5 = field_addr v0, %p.acc
    v6 = load.i16 v5
    v7 = iadd v6, v4
    store v7, v5
    return
}

func @p$init(ptr) init {
block0(v0: ptr):
    v1 = field_addr v0, %p.n
    v2 = iconst.i16 0
    store v2, v1
    v3 = field_addr v0, %p.acc
    store v2, v3
    return
}

func @c$scan(ptr) program {
block0(v0: ptr):
    call @p(v0)
    call @p(v0)
    return
}

program "a" data @a body @p init @p$init
program "b" data @b body @p init @p$init
program "c" data @c body @c$scan init @p$init
"#;

    #[test]
    fn instances_sharing_a_body_get_their_own_address() {
        let module = plcc_ir::text::parse_module(SHARED_BODY).expect("parses");
        plcc_ir::verify::verify_module(&module).expect("verifies");
        let build = build(&module, &Options::default()).expect("builds");
        let asm = build.program.mpasm();
        // The scan loop passes each instance to the shared body (the wrapper of `c`
        // passes its own, as any call does).
        let scan = &asm[asm.find("\nplc_scan\n").expect("scan loop")..];
        let scan = &scan[..scan.find("plc_scan_end").expect("scan end")];
        assert_eq!(scan.matches("movwf\tf_p_fr\n").count(), 2, "{scan}");
        let mut m = machine::PicMachine::new(&module, build);
        m.cold_start().unwrap();
        for _ in 0..3 {
            m.scan().unwrap();
        }
        let read = |m: &machine::PicMachine, p: &str| m.read(p).unwrap().as_i64();
        assert_eq!(read(&m, "a.n"), 3);
        assert_eq!(read(&m, "a.acc"), 6);
        assert_eq!(read(&m, "b.n"), 3);
        assert_eq!(read(&m, "b.acc"), 6);
        assert_eq!(read(&m, "c.n"), 6);
        assert_eq!(read(&m, "c.acc"), 21);
    }
}
