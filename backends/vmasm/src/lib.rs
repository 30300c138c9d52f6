// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(
    not(test),
    deny(clippy::print_stdout, clippy::print_stderr, clippy::unwrap_used)
)]
//! plcc's CPDev VM backend: the IR to VMASM (the mnemonic listing of the CPDev
//! compiler), the XCP code image and the DCP project description, and a VM in Rust
//! that runs XCP images as CPDev's C VM does.
//!
//! The path ([`build::build`]): every function gets a calling convention
//! ([`isel::Conv`]: on an instance, or on a call area); instances carry their
//! functions' temporaries (`plcc_ir::layout`, with tails); [`isel`] selects VM instructions with symbolic
//! labels ([`code`]); the task code calls the initialisers and then, every cycle, the
//! program bodies up to TRML; [`code::Program::assemble`] gives the XCP bytes and the
//! listing; [`dcp`] writes the description. [`vm`] runs images; [`machine`] is the
//! `Machine` of target `vmasm`.

#![warn(missing_docs)]

pub mod asm;
pub mod build;
pub mod code;
pub mod dcp;
pub mod dcp_read;
pub mod disasm;
pub mod isa;
pub mod isel;
pub mod machine;
pub mod port;
pub mod vm;

use plcc_ir::backend::{Artifact, Artifacts, Backend, Options, TargetFacts};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::machine::Machine;
use plcc_ir::{ElemType, Module};

/// Diagnostic codes of the vmasm backend.
pub mod codes {
    /// An operation the VM target cannot do.
    pub const E_UNSUPPORTED: &str = "E9101";
    /// The program does not fit the addressing mode's code or data memory.
    pub const E_MEMORY: &str = "E9102";
    /// A backend setting is unknown or has a bad value.
    pub const E_BAD_SETTING: &str = "E9103";
    /// A bug of this backend.
    pub const E_INTERNAL: &str = "E9104";
    /// The program needs a part of the VM that the chosen port lacks.
    pub const E_PORT: &str = "E9105";
}

/// Every code the vmasm backend reports, for `plcc explain`.
pub const CODES: &[CodeInfo] = &[
    CodeInfo {
        code: codes::E_UNSUPPORTED,
        title: "not supported on the CPDev VM",
        explanation: "The program uses an operation that the vmasm target cannot compile \
to the CPDev virtual machine's instructions. The message names it and points at it. \
Example: ATAN2 of the IR text form has no VM instruction and no composition yet.",
    },
    CodeInfo {
        code: codes::E_MEMORY,
        title: "code or data memory of the VM exceeded",
        explanation: "The code or the data (variables, instances with their temporaries, \
call areas) does not fit the addresses of the chosen mode: 64 KiB each with 16-bit \
addressing (the default). Use `-s mode=32` for 32-bit addressing, or make the program \
smaller.\n\n    VAR big : ARRAY[0..39999] OF INT; END_VAR   (* error in mode 16: 80,000 bytes *)\n    plcc --target vmasm -s mode=32 prog.st     (* fix: 32-bit addresses *)",
    },
    CodeInfo {
        code: codes::E_BAD_SETTING,
        title: "bad vmasm setting",
        explanation: "A `-s key=value` setting of the vmasm target is unknown or has a bad \
value. Settings: `mode=16|32|32a` (addressing: 16-bit, 32-bit, 32-bit with 4-byte \
alignment), `cycle=MS` (the task cycle written to the DCP) and `port=full|esp32|avr|6502|sdcc` \
(the CPDev VM port the code is for).\n\n    plcc --target vmasm -s mode=64 prog.st   (* error: no such mode *)\n    plcc --target vmasm -s mode=32 prog.st   (* fix *)",
    },
    CodeInfo {
        code: codes::E_PORT,
        title: "not available on the chosen CPDev VM port",
        explanation: "The CPDev VM is built differently for each machine (`vm_cfg.h`): the \
ESP32 and AVR builds have no LINT, ULINT, LWORD, LREAL or STRING; the 6502 and sdcc builds \
have no REAL, no math instructions, no pointers and no 64-bit integers either. A port's VM \
stops on an instruction it lacks, so plcc refuses to compile one for the port chosen with \
`-s port=NAME` (the default, `full`, is the Windows, BeagleBone AI, iOS and Due build, which \
has everything). The message names the missing part and points at the source that needs \
it.\n\n    VAR x : LREAL; END_VAR  x := x * 2.0;\n    plcc --target vmasm -s port=esp32 prog.st   (* error: LREAL arithmetic *)\n    plcc --target vmasm -s port=full prog.st    (* fix: a port with LREAL, or use REAL *)",
    },
    CodeInfo {
        code: codes::E_INTERNAL,
        title: "internal error of the vmasm backend",
        explanation: "A rule inside the vmasm backend was broken. This is a bug of plcc; \
please report it with the program. No correct program shows it, so there is no example.",
    },
];

/// The elementary types the VM holds: all of them (REAL and LREAL natively).
pub const ELEM_TYPES: &[ElemType] = &ElemType::ALL;

/// The `vmasm` target.
#[derive(Default)]
pub struct VmasmBackend;

impl VmasmBackend {
    /// The backend.
    pub fn new() -> VmasmBackend {
        VmasmBackend
    }
}

impl Backend for VmasmBackend {
    fn facts(&self) -> TargetFacts {
        TargetFacts {
            name: "vmasm",
            pointer_bits: 16,
            little_endian: true,
            elem_types: ELEM_TYPES,
            // Every value is a memory cell of the VM: promotion pays in loops only.
            promotion: plcc_ir::passes::promote::Promotion::InLoops,
        }
    }

    /// The XCP image with its DCP description (the default), or the VMASM listing
    /// (`--emit asm`).
    fn compile(&self, module: &Module, options: &Options) -> Result<Artifacts, Vec<Diagnostic>> {
        let b = build::build(module, options)?;
        let files = match options.emit.as_deref() {
            None | Some("xcp") => vec![
                Artifact {
                    kind: "xcp".into(),
                    bytes: b.image.code.clone(),
                },
                Artifact {
                    kind: "dcp".into(),
                    bytes: dcp::write(module, &b, options).into_bytes(),
                },
            ],
            Some("asm") => vec![Artifact {
                kind: "asm".into(),
                bytes: b.image.listing.clone().into_bytes(),
            }],
            Some(other) => {
                return Err(vec![Diagnostic::error_nowhere(
                    codes::E_BAD_SETTING,
                    format!("vmasm cannot emit `{other}` (it emits xcp, with its dcp, or asm)"),
                )])
            }
        };
        let summary = format!(
            "vmasm ({}-bit{}): code {} bytes, data {} bytes",
            if b.settings.mode == isa::Mode::M16 {
                16
            } else {
                32
            },
            if b.settings.mode == isa::Mode::M32A {
                ", aligned"
            } else {
                ""
            },
            b.image.code.len(),
            b.data_size
        );
        Ok(Artifacts {
            files,
            symbols: b.symbols.clone(),
            summary: Some(summary),
        })
    }

    fn machine(
        &self,
        module: &Module,
        options: &Options,
    ) -> Option<Result<Box<dyn Machine>, Vec<Diagnostic>>> {
        Some(build::build(module, options).and_then(|b| {
            machine::VmMachine::new(module, b)
                .map(|m| Box::new(m) as Box<dyn Machine>)
                .map_err(|e| vec![Diagnostic::error_nowhere(codes::E_INTERNAL, e)])
        }))
    }
}
