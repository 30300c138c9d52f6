// Library crates never print (ARCHITECTURE.md, "Panics"): what they say is a Diagnostic.
#![cfg_attr(not(test), deny(clippy::print_stdout, clippy::print_stderr))]
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
pub mod frame;
pub mod helpers;
pub mod isa;
pub mod isel;
pub mod machine;
pub mod ram;
pub mod runtime;
pub mod sim;
pub mod softfloat;

use asm::{DataSymbol, Image, Item, Label, Program, Unit};
use frame::{FrameInfo, Ptr, Repr, Sym};
use helpers::{HelperSet, Workspace};
use isel::{Emitter, Placement};
use plcc_ir::backend::{Artifact, Artifacts, Backend, Options, Symbol, TargetFacts};
use plcc_ir::diag::{CodeInfo, Diagnostic};
use plcc_ir::inst::{BinaryOp, InstData, Intrinsic};
use plcc_ir::machine::Machine;
use plcc_ir::{ElemType, FuncId, MemType, Module, Type};
use ram::{PicLayout, RamMap};
use runtime::{PinBinding, Rt};
use rustc_hash::{FxHashMap, FxHashSet};

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
        explanation: "The PIC16's return stack has 8 levels and one is kept for the interrupt. \
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

fn setting_pins(options: &Options) -> Result<FxHashMap<String, runtime::Pin>, Vec<Diagnostic>> {
    let mut m = FxHashMap::default();
    for (k, v) in &options.settings {
        let bad = |msg: String| vec![Diagnostic::error_nowhere(codes::E_BAD_SETTING, msg)];
        let Some(loc) = k.strip_prefix("pin.") else {
            return Err(bad(format!(
                "unknown pic16f876a setting `{k}` (known: pin.LOCATION)"
            )));
        };
        if runtime::parse_bit_location(loc).is_none() {
            return Err(bad(format!(
                "`{loc}` is not a bit location such as %IX0.0 or %QX0.1"
            )));
        }
        let Some(pin) = runtime::Pin::parse(v) else {
            return Err(bad(format!(
                "`{v}` is not a pin (RA0-RA5, RB0-RB7, RC0-RC7)"
            )));
        };
        m.insert(loc.trim().to_ascii_uppercase(), pin);
    }
    Ok(m)
}

/// Assembler-safe name of a source path: `main.timer.Q` → `main_timer_Q`.
fn asm_name(path: &str, taken: &mut FxHashSet<String>) -> String {
    let mut s: String = path
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    while s.contains("__") {
        s = s.replace("__", "_");
    }
    let s = s.trim_end_matches('_').to_string();
    let s = if s.chars().next().is_some_and(|c| c.is_ascii_digit()) || s.is_empty() {
        format!("v_{s}")
    } else {
        s
    };
    let mut name = s.clone();
    let mut n = 1;
    while !taken.insert(name.to_ascii_lowercase()) {
        n += 1;
        name = format!("{s}_{n}");
    }
    name
}

/// Compiles a verified module for the chip.
pub fn build(module: &Module, options: &Options) -> Result<Build, Vec<Diagnostic>> {
    if module.unchecked_pointers {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED,
            "unchecked pointers (CODESYS pointer arithmetic, a pointer given the address of another type, or the address of a temporary kept) are not supported on pic16f876a: run the program on interp",
        )]);
    }
    plcc_ir::backend::reject_inline_c(module, "pic16f876a", codes::E_UNSUPPORTED)?;
    // The verifier rejects recursion; a module that skipped it must not get frames
    // overlaid as if the calls nested a bounded number of times.
    if let Some(cycle) = plcc_ir::analysis::find_recursion(module) {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_STACK,
            format!(
                "recursion ({}, directly or through a table) needs an unbounded stack; the chip's has 8 levels",
                plcc_ir::analysis::describe_cycle(module, &cycle)
            ),
        )]);
    }
    let pin_over = setting_pins(options)?;
    // Calls bound at run time become compare chains of direct calls (CALL takes an
    // immediate address), so the call graph, the stack depth and the frame overlays
    // see every entry; REAL becomes integers and calls of the soft-float routines.
    let mut legal = module.clone();
    plcc_ir::passes::dispatch::run(&mut legal);
    softfloat::legalize(&mut legal)?;
    let module = &legal;
    let layout = PicLayout::compute(module);
    let nf = module.funcs.len();

    // Call graph from the roots (`plcc_ir::analysis`): callers before callees.
    let callees: Vec<Vec<FuncId>> = (0..nf)
        .map(|f| {
            plcc_ir::analysis::callees(module, f)
                .into_iter()
                .map(FuncId::new)
                .collect()
        })
        .collect();
    let mut roots: Vec<FuncId> = Vec::new();
    roots.extend(module.init_globals);
    for p in &module.programs {
        roots.push(p.init);
        roots.push(p.body);
    }
    let order = plcc_ir::analysis::callers_first_from(module, &roots);

    // Pointers every caller agrees on.
    let mut root_params: FxHashMap<FuncId, Vec<Option<Ptr>>> = FxHashMap::default();
    let merge_root = |f: FuncId, p: Option<Ptr>, m: &mut FxHashMap<FuncId, Vec<Option<Ptr>>>| {
        let e = m.entry(f).or_insert_with(|| vec![p]);
        if e[0] != p {
            e[0] = None;
        }
    };
    for p in &module.programs {
        let ptr = Some(Ptr::Known(Sym::Data(p.data), 0, 0));
        merge_root(p.body, ptr, &mut root_params);
        merge_root(p.init, ptr, &mut root_params);
    }
    let consensus = frame::param_consensus(&module.funcs, &order, &root_params);

    // Frames.
    let mut frames: Vec<FrameInfo> = vec![FrameInfo::default(); nf];
    // The data objects each function reads and writes directly, with a count.
    let mut touches: Vec<FxHashMap<plcc_ir::DataId, u32>> = vec![FxHashMap::default(); nf];
    for &fid in &order {
        let f = &module.funcs[fid.index()];
        let mut ptrs = frame::pointer_facts(f, fid, &consensus[fid.index()]);
        frame::derive_pointers(f, &layout, &mut ptrs);
        for (_, i) in f.inst_iter() {
            if let InstData::Load { addr, .. } | InstData::Store { addr, .. } = f.inst(i) {
                if let Some(Ptr::Known(Sym::Data(d), _, _)) = ptrs.get(addr) {
                    *touches[fid.index()].entry(*d).or_default() += 1;
                }
            }
        }
        let slot_sizes: Vec<u32> = f.slots.iter().map(|s| layout.size(s.ty)).collect();
        frames[fid.index()] = frame::build_frame(f, &ptrs, &slot_sizes);
    }

    // What the runtime needs.
    let mut uses_ns = false;
    let mut widest_muldiv = 0u16;
    for &fid in &order {
        let f = &module.funcs[fid.index()];
        for (_, i) in f.inst_iter() {
            match f.inst(i) {
                InstData::Intrinsic {
                    op: Intrinsic::ClockNs,
                    ..
                } => uses_ns = true,
                InstData::Binary {
                    op:
                        BinaryOp::Imul
                        | BinaryOp::Sdiv
                        | BinaryOp::Udiv
                        | BinaryOp::Srem
                        | BinaryOp::Urem,
                    args,
                } => {
                    let t = f.value_type(args[0]);
                    if t.is_int() && t != Type::I1 {
                        widest_muldiv = widest_muldiv.max(ram::scalar_bytes(t) as u16);
                    }
                }
                _ => {}
            }
        }
    }

    // RAM: runtime block, helpers' workspace, data objects, then frames.
    let mut map = RamMap::new();
    let ram_err = |what: String| vec![Diagnostic::error_nowhere(codes::E_RAM, what)];
    // clock (4), sampled clock (4), flags (1), interrupt context (3), ns clocks (16).
    let rt_size: u16 = if uses_ns { 28 } else { 12 };
    let rt_at = map
        .find(rt_size, &[], Some(0))
        .ok_or_else(|| ram_err("no RAM for the runtime".into()))?;
    map.take(rt_at, rt_size);
    let rt = Rt {
        clk_ms: rt_at,
        now_ms: rt_at + 4,
        flags: rt_at + 8,
        isr_save: rt_at + 9,
        clk_ns: uses_ns.then_some(rt_at + 12),
        now_ns: if uses_ns { rt_at + 20 } else { rt_at },
    };
    let ws = if widest_muldiv > 0 {
        let size = helpers::workspace_bytes(widest_muldiv);
        let at = map.find(size, &[], None).ok_or_else(|| {
            ram_err(format!(
                "no room for the {size} bytes of the multiply/divide workspace"
            ))
        })?;
        map.take(at, size);
        Workspace {
            a: at,
            b: at + widest_muldiv,
            r: at + 2 * widest_muldiv,
            cnt: at + 3 * widest_muldiv,
        }
    } else {
        Workspace::default()
    };
    let data = place_data(module, &layout, &consensus, &order, &mut map)?;
    // Ancestors of every function (all functions that can be active while it runs).
    let mut ancestors: Vec<FxHashSet<FuncId>> = vec![FxHashSet::default(); nf];
    for &f in &order {
        for &g in &callees[f.index()] {
            let mut add: FxHashSet<FuncId> = ancestors[f.index()].clone();
            add.insert(f);
            ancestors[g.index()].extend(add);
        }
    }
    let mut frame_base = vec![0u16; nf];
    let mut placed: Vec<Option<(u16, u16)>> = vec![None; nf];
    let mut frame_bytes: FxHashSet<u16> = FxHashSet::default();
    for &f in &order {
        let size = frames[f.index()].size;
        if size == 0 {
            continue;
        }
        let avoid: Vec<(u16, u16)> = ancestors[f.index()]
            .iter()
            .filter_map(|a| placed[a.index()])
            .collect();
        // Beside the variables the function uses most, so that working on both
        // needs no bank switch.
        let mut per_bank = [0u32; 4];
        for (d, n) in &touches[f.index()] {
            per_bank[((data.addr(*d, 0) >> 7) & 3) as usize] += n;
        }
        let prefer = (0..4u8).max_by_key(|&b| (per_bank[b as usize], std::cmp::Reverse(b)));
        // A hot function (a program body, or one with a loop) whose frame fits goes
        // to common RAM, where it needs no bank selects at all.
        let hot = module.programs.iter().any(|p| p.body == f) || has_loop(&module.funcs[f.index()]);
        let common = hot.then(|| find_common(size, &avoid)).flatten();
        let Some(at) = common.or_else(|| map.find(size, &avoid, prefer)) else {
            let fname = &module.funcs[f.index()].name;
            // The deepest chain of frames down to this one (they all coexist).
            let mut chain = vec![0u32; nf];
            for &g in &order {
                let own = frames[g.index()].size as u32;
                let up = (0..nf)
                    .filter(|&c| callees[c].contains(&g))
                    .map(|c| chain[c])
                    .max()
                    .unwrap_or(0);
                chain[g.index()] = up + own;
            }
            let chain = chain[f.index()];
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_RAM,
                format!(
                    "`{fname}` needs {size} bytes for its temporaries and locals, but no bank has that much free beside the variables ({} bytes) and the frames of the functions that call it (the deepest chain down to it needs {} bytes); the chip has {} bytes",
                    map.used_bytes(),
                    chain,
                    ram::RAM_BYTES
                ),
            )]);
        };
        frame_base[f.index()] = at;
        placed[f.index()] = Some((at, at + size));
        frame_bytes.extend((at..at + size).filter(|a| !(0x70..0x80).contains(a)));
    }
    let ram_used = map.used_bytes() + frame_bytes.len() as u32 + 16;

    // Labels and code.
    let mut program = Program {
        config: 0x3F32,
        ..Default::default()
    };
    let mut taken: FxHashSet<String> = asm::reserved_names()
        .map(|s| s.to_ascii_lowercase())
        .collect();
    for (n, ..) in runtime::common_symbols() {
        taken.insert(n.to_string());
    }
    for n in [
        "plc_flags",
        "plc_isr_save",
        "plc_clock_ms",
        "plc_now_ms",
        "plc_clock_ns",
        "plc_now_ns",
        "plc_ws",
    ] {
        taken.insert(n.to_string());
    }
    let rl = runtime::labels(&mut program.labels);
    let mut func_label = vec![Label(u32::MAX); nf];
    for &f in &order {
        let name = asm_name(&format!("f_{}", module.funcs[f.index()].name), &mut taken);
        program.labels.push(name);
        func_label[f.index()] = Label(program.labels.len() as u32 - 1);
    }
    let placement = Placement {
        module,
        layout: &layout,
        data: data.clone(),
        frame_base: frame_base.clone(),
        frames: &frames,
        func_label: func_label.clone(),
        rt,
        ws,
    };
    let sources: Vec<Option<String>> = options.sources.clone();
    let mut helper_set = HelperSet::default();
    let mut units: Vec<Unit> = Vec::new();
    let mut diags = Vec::new();
    let mut helper_users: FxHashSet<FuncId> = FxHashSet::default();
    for &f in &order {
        let prefix = program.labels[func_label[f.index()].0 as usize].clone();
        let before = helper_set.clone();
        let em = Emitter::new(
            &placement,
            f,
            &mut program.labels,
            &mut helper_set,
            prefix.clone(),
            &sources,
        );
        let (items, d) = em.run(func_label[f.index()]);
        if format!("{before:?}") != format!("{helper_set:?}")
            || uses_helper(&items, &program.labels)
        {
            helper_users.insert(f);
        }
        diags.extend(d);
        let frame = placed[f.index()].map(|(s, e)| (s, e, format!("{prefix}_fr")));
        units.push(Unit {
            name: format!(
                "{} `{}`",
                module.funcs[f.index()].kind.name(),
                module.funcs[f.index()].name
            ),
            org: None,
            items,
            frame,
        });
    }
    if diags.iter().any(|d| d.is_error()) {
        return Err(diags);
    }
    // Pins.
    let mut pins = Vec::new();
    let bind = |path: String, addr: u16, bit: u8, loc: &str, pins: &mut Vec<PinBinding>| {
        let key = loc.trim().to_ascii_uppercase();
        let pin = pin_over
            .get(&key)
            .copied()
            .or_else(|| runtime::default_pin(&key));
        if let (Some(pin), Some((input, _, _))) = (pin, runtime::parse_bit_location(&key)) {
            pins.push(PinBinding {
                path,
                addr,
                bit,
                pin,
                input,
            });
        }
    };
    for (i, d) in module.data.iter().enumerate() {
        match d.ty {
            MemType::Scalar(Type::I1) => {
                if let Some(loc) = &d.location {
                    bind(
                        d.name.clone(),
                        data.addr(plcc_ir::DataId::new(i), 0),
                        0,
                        loc,
                        &mut pins,
                    );
                }
            }
            MemType::Agg(a) => {
                if let plcc_ir::module::AggDef::Struct(s) = module.agg(a) {
                    for (fi, fld) in s.fields.iter().enumerate() {
                        if let (Some(loc), MemType::Scalar(Type::I1)) = (&fld.location, fld.ty) {
                            let p = layout.agg(a).fields[fi];
                            bind(
                                format!("{}.{}", d.name, fld.name),
                                data.addr(plcc_ir::DataId::new(i), p.offset),
                                p.bit,
                                loc,
                                &mut pins,
                            );
                        }
                    }
                }
            }
            _ => {}
        }
    }
    // The runtime calls every program's init and body with the address of its
    // instance. A callee that does not know that address already (several instances
    // share it, or a configuration's wrapper calls it too) reads it from its frame:
    // store it there before each call, as a call in the code would.
    let entry_call = |f: FuncId, d: plcc_ir::DataId| runtime::EntryCall {
        label: func_label[f.index()],
        stores: instance_arg_stores(
            &module.funcs[f.index()],
            &frames[f.index()],
            frame_base[f.index()],
            data.addr(d, 0),
        ),
    };
    let mut inits = Vec::new();
    inits.extend(module.init_globals.map(|f| runtime::EntryCall {
        label: func_label[f.index()],
        stores: Vec::new(),
    }));
    let mut bodies = Vec::new();
    for p in &module.programs {
        inits.push(entry_call(p.init, p.data));
        bodies.push(entry_call(p.body, p.data));
    }
    let plan = runtime::RuntimePlan {
        rt,
        inits,
        bodies,
        pins: &pins,
    };
    let mut all = vec![
        runtime::reset_unit(&rl),
        runtime::isr_unit(&rt, &mut program.labels),
        runtime::main_unit(&plan, &rl),
    ];
    all.extend(units);
    for mut u in helper_set.units(ws) {
        helpers::resolve_local(&mut u, &mut program.labels);
        all.push(u);
    }
    // Bank selects. Round one, callees first and entries unknown: the bank each unit
    // returns with and the banks known at every call. Round two: each unit starts
    // with what all its callers agree on. (Round one's facts hold in round two, as
    // knowing more at an entry only ever adds to what is known.)
    let entry_label = |u: &Unit| {
        u.items.iter().find_map(|it| match it {
            Item::Label(l) => Some(*l),
            _ => None,
        })
    };
    let mut exits: FxHashMap<Label, banks::State> = FxHashMap::default();
    let mut entries: FxHashMap<Label, Option<banks::State>> = FxHashMap::default();
    for u in all.iter().rev() {
        let mut probe = u.clone();
        let st = banks::insert_selects(&mut probe, banks::State::UNKNOWN, &|l| {
            exits.get(&l).copied()
        })
        .map_err(|e| vec![Diagnostic::error_nowhere(codes::E_INTERNAL, e)])?;
        if let (Some(l), Some(x)) = (entry_label(u), st.exit) {
            exits.insert(l, x);
        }
        for (callee, state) in st.calls {
            let e = entries.entry(callee).or_insert(None);
            *e = banks::State::meet(*e, Some(state));
        }
    }
    let mut bank_selects = 0;
    for (i, u) in all.iter_mut().enumerate() {
        // The vectors and the scan loop are entered by reset, interrupt or jump.
        let entry = match entry_label(u) {
            Some(l) if i > 2 => entries
                .get(&l)
                .copied()
                .flatten()
                .unwrap_or(banks::State::UNKNOWN),
            _ => banks::State::UNKNOWN,
        };
        let st = banks::insert_selects(u, entry, &|l| exits.get(&l).copied())
            .map_err(|e| vec![Diagnostic::error_nowhere(codes::E_INTERNAL, e)])?;
        bank_selects += st.selects;
    }
    program.units = all;

    // Stack depth: the scan loop's calls, plus one level for the interrupt.
    let mut depth: Vec<u32> = vec![0; nf];
    for &f in order.iter().rev() {
        let mut d = 1;
        for &g in &callees[f.index()] {
            d = d.max(1 + depth[g.index()]);
        }
        if helper_users.contains(&f) {
            d = d.max(2);
        }
        depth[f.index()] = d;
    }
    let stack_depth = roots.iter().map(|r| depth[r.index()]).max().unwrap_or(0) + 1;
    if stack_depth > 8 {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_STACK,
            format!(
                "the deepest chain of calls needs {stack_depth} levels of the 8-level hardware stack (the interrupt included): {} too many",
                stack_depth - 8
            ),
        )]);
    }

    // Symbols for the listing and the runner.
    let mut symbols = Vec::new();
    let mut bits = Vec::new();
    let mut asm_names = Vec::new();
    for (n, a, size, c) in runtime::common_symbols() {
        program.symbols.push(DataSymbol {
            name: n.into(),
            addr: a,
            size,
            bit: None,
            comment: c.into(),
        });
    }
    for (n, a, s, c) in [
        ("plc_clock_ms", rt.clk_ms, 4, "running clock, ms"),
        (
            "plc_now_ms",
            rt.now_ms,
            4,
            "clock sampled at scan start, ms",
        ),
        ("plc_flags", rt.flags, 1, "bit 0: fault"),
        (
            "plc_isr_save",
            rt.isr_save,
            3,
            "interrupt: saved STATUS, PCLATH, FSR",
        ),
    ] {
        program.symbols.push(DataSymbol {
            name: n.into(),
            addr: a,
            size: s,
            bit: None,
            comment: c.into(),
        });
    }
    if let Some(ns) = rt.clk_ns {
        for (n, a, c) in [
            ("plc_clock_ns", ns, "running clock, ns"),
            ("plc_now_ns", rt.now_ns, "clock sampled at scan start, ns"),
        ] {
            program.symbols.push(DataSymbol {
                name: n.into(),
                addr: a,
                size: 8,
                bit: None,
                comment: c.into(),
            });
        }
    }
    if widest_muldiv > 0 {
        program.symbols.push(DataSymbol {
            name: "plc_ws".into(),
            addr: ws.a,
            size: helpers::workspace_bytes(widest_muldiv),
            bit: None,
            comment: "multiply/divide workspace".into(),
        });
    }
    for i in 0..module.data.len() {
        for v in plcc_ir::vars::variables(module, plcc_ir::DataId::new(i)) {
            let place = layout.place_of(&v.steps);
            let addr = data.addr(plcc_ir::DataId::new(i), place.offset);
            let is_bool = v.ty == Type::I1;
            symbols.push(Symbol {
                path: v.path.clone(),
                address: addr as u64,
                size: ram::scalar_bytes(v.ty),
                elem: v.elem,
            });
            bits.push(is_bool.then_some(place.bit));
            let name = asm_name(&v.path, &mut taken);
            asm_names.push(name.clone());
            program.symbols.push(DataSymbol {
                name,
                addr,
                size: ram::scalar_bytes(v.ty) as u16,
                bit: is_bool.then_some(place.bit),
                comment: if is_bool {
                    format!("{} : {} (bit {})", v.path, v.elem.name(), place.bit)
                } else {
                    format!("{} : {}", v.path, v.elem.name())
                },
            });
        }
    }
    for u in &program.units {
        if let Some((s, _, n)) = &u.frame {
            program.symbols.push(DataSymbol {
                name: n.clone(),
                addr: *s,
                size: 0,
                bit: None,
                comment: format!("frame of {}", u.name),
            });
        }
    }
    program.header = vec![
        "PIC16F876A assembly generated by plcc".into(),
        "assemble with: gpasm FILE.asm (MPASM syntax)".into(),
        "pins: %IX0.0-7 = RB0-7, %IX1.0-5 = RA0-5, %QX0.0-7 = RC0-7 (unless overridden)".into(),
    ];
    for p in &pins {
        program.header.push(format!(
            "  {} {} {}",
            p.path,
            if p.input { "<-" } else { "->" },
            p.pin.name()
        ));
    }
    program
        .paginate()
        .map_err(|e| vec![Diagnostic::error_nowhere(codes::E_FLASH, e)])?;
    let image = program.assemble().map_err(|e| {
        let code = if e.contains("program memory") {
            codes::E_FLASH
        } else {
            codes::E_INTERNAL
        };
        vec![Diagnostic::error_nowhere(code, e)]
    })?;
    let scan_addr = image.label_addr[rl.scan.0 as usize];
    let scan_end_addr = image.label_addr[rl.scan_end.0 as usize];
    program.header.insert(
        1,
        format!(
            "flash {}/{} words, ram {}/{} bytes, stack {}/8, bank selects {}",
            image.used_words(),
            asm::FLASH_WORDS,
            ram_used,
            ram::RAM_BYTES,
            stack_depth,
            bank_selects
        ),
    );
    Ok(Build {
        program,
        image,
        symbols,
        bits,
        asm_names,
        pins,
        rt,
        ram_used,
        stack_depth,
        bank_selects,
        scan_addr,
        scan_end_addr,
        data,
        layout,
    })
}

fn uses_helper(items: &[Item], labels: &[String]) -> bool {
    items.iter().any(
        |it| matches!(it, Item::Op(asm::Op::Call(l)) if labels[l.0 as usize].starts_with("plc_")),
    )
}

/// The bytes to store before calling `f` (a program's init or body) with the
/// instance at `addr`: none when the callee knows the address (its parameter is a
/// constant), else the address into the parameter's home in the callee's frame at
/// `base`.
fn instance_arg_stores(
    f: &plcc_ir::function::Function,
    frame: &FrameInfo,
    base: u16,
    addr: u16,
) -> Vec<(u16, u8)> {
    let Some(entry) = f.entry() else {
        return Vec::new();
    };
    let Some(&p) = f.block(entry).params.first() else {
        return Vec::new();
    };
    match frame.repr[p.index()] {
        Repr::Bytes(o) => {
            let at = base + o;
            vec![(at, addr as u8), (at + 1, (addr >> 8) as u8)]
        }
        Repr::Ptr(Ptr::Known(..)) | Repr::Unused => Vec::new(),
        r => unreachable!("an instance pointer held as {r:?}"),
    }
}

/// Places every data object: whole in one bank when it fits, else (a program's or a
/// global struct's variables) split between its fields, which is only done when no
/// code reaches the object through a computed pointer.
fn place_data(
    module: &Module,
    layout: &PicLayout,
    consensus: &[Vec<Option<Ptr>>],
    order: &[FuncId],
    map: &mut RamMap,
) -> Result<ram::DataMap, Vec<Diagnostic>> {
    let ram_err = |what: String| vec![Diagnostic::error_nowhere(codes::E_RAM, what)];
    let full = |map: &RamMap, d: &plcc_ir::module::DataDef, size: u32| {
        ram_err(format!(
            "`{}` needs {size} bytes but the largest free block left is {} bytes ({} of {} bytes used)",
            d.name,
            map.largest_free(),
            map.used_bytes() + 16,
            ram::RAM_BYTES
        ))
    };
    let total: u32 = module.data.iter().map(|d| layout.size(d.ty)).sum();
    let free = ram::RAM_BYTES - 16 - map.used_bytes();
    if total > free {
        return Err(ram_err(format!(
            "the variables need {total} bytes of RAM but {free} are left beside the runtime ({} of the chip's {} bytes): {} too many",
            16 + map.used_bytes(),
            ram::RAM_BYTES,
            total - free
        )));
    }
    let escapes = escaping_objects(module, layout, consensus, order);
    let mut pieces = vec![Vec::new(); module.data.len()];
    for (i, d) in module.data.iter().enumerate() {
        let size = layout.size(d.ty);
        if size <= 96 {
            let s = size as u16;
            let at = map
                .find(s.max(1), &[], Some(0))
                .ok_or_else(|| full(map, d, size))?;
            map.take(at, s.max(1));
            pieces[i] = vec![(0, s.max(1), at)];
            continue;
        }
        let MemType::Agg(agg) = d.ty else {
            unreachable!("scalars are small")
        };
        let splittable = matches!(module.agg(agg), plcc_ir::module::AggDef::Struct(_))
            && !escapes.contains(&plcc_ir::DataId::new(i));
        let ranges = ram::field_ranges(layout, module, agg);
        if !splittable || ranges.iter().any(|(a, b)| b - a > 96) {
            return Err(ram_err(format!(
                "`{}` needs {size} bytes in one piece{}; a RAM bank holds at most 96 bytes",
                d.name,
                if splittable {
                    " (one of its members is larger than a bank)"
                } else {
                    " (it is an array, or code reaches it through a pointer)"
                }
            )));
        }
        // Runs of whole fields, each in the first bank with room.
        let mut bank = Some(0u8);
        for (a, b) in ranges {
            let at = map
                .find(b - a, &[], bank)
                .ok_or_else(|| full(map, d, size))?;
            map.take(at, b - a);
            bank = Some(((at >> 7) & 3) as u8);
            match pieces[i].last_mut() {
                Some((s0, e, pa)) if *e == a && *pa + (a - *s0) == at => *e = b,
                _ => pieces[i].push((a, b, at)),
            }
        }
    }
    Ok(ram::DataMap { pieces })
}

/// Data objects whose address may reach code as a computed pointer: passed to a
/// function whose parameter is not the same known address at every call, stored,
/// or passed between blocks.
fn escaping_objects(
    module: &Module,
    layout: &PicLayout,
    consensus: &[Vec<Option<Ptr>>],
    order: &[FuncId],
) -> FxHashSet<plcc_ir::DataId> {
    let mut out = FxHashSet::default();
    for p in &module.programs {
        if consensus[p.body.index()]
            .first()
            .copied()
            .flatten()
            .is_none()
            || consensus[p.init.index()]
                .first()
                .copied()
                .flatten()
                .is_none()
        {
            out.insert(p.data);
        }
    }
    for &fid in order {
        let f = &module.funcs[fid.index()];
        let mut ptrs = frame::pointer_facts(f, fid, &consensus[fid.index()]);
        frame::derive_pointers(f, layout, &mut ptrs);
        // A pointer to one member stays inside that member, which is never split;
        // only the address of the whole object matters.
        let data_of = |v: plcc_ir::Value| match (ptrs.get(&v), f.value_def(v)) {
            (Some(Ptr::Known(Sym::Data(d), 0, _)), plcc_ir::function::ValueDef::Result(i))
                if matches!(f.inst(i), InstData::GlobalAddr { .. }) =>
            {
                Some(*d)
            }
            (Some(Ptr::Known(Sym::Data(d), 0, _)), plcc_ir::function::ValueDef::Param(..)) => {
                Some(*d)
            }
            _ => None,
        };
        for (_, inst) in f.inst_iter() {
            match f.inst(inst) {
                InstData::Call { func, args } => {
                    for (k, a) in args.iter().enumerate() {
                        if let Some(d) = data_of(*a) {
                            if consensus[func.index()].get(k).copied().flatten().is_none() {
                                out.insert(d);
                            }
                        }
                    }
                }
                InstData::Store { value, .. } => {
                    if let Some(d) = data_of(*value) {
                        out.insert(d);
                    }
                }
                InstData::Jump { dest } => {
                    for a in &dest.args {
                        out.extend(data_of(*a));
                    }
                }
                InstData::Brif {
                    then_dest,
                    else_dest,
                    ..
                } => {
                    for a in then_dest.args.iter().chain(&else_dest.args) {
                        out.extend(data_of(*a));
                    }
                }
                InstData::Select {
                    if_true, if_false, ..
                } => {
                    out.extend(data_of(*if_true));
                    out.extend(data_of(*if_false));
                }
                InstData::Return { value: Some(v) } => out.extend(data_of(*v)),
                _ => {}
            }
        }
    }
    out
}

/// A place for `size` bytes in the free part of common RAM, away from `avoid`.
fn find_common(size: u16, avoid: &[(u16, u16)]) -> Option<u16> {
    let (lo, hi) = runtime::COMMON_FREE;
    (lo..=hi.saturating_sub(size)).find(|&at| avoid.iter().all(|&(s, e)| at + size <= s || at >= e))
}

/// True if the function has a back edge in its layout (a loop).
fn has_loop(f: &plcc_ir::function::Function) -> bool {
    let pos: FxHashMap<plcc_ir::Block, usize> =
        f.layout.iter().enumerate().map(|(i, b)| (*b, i)).collect();
    f.layout.iter().enumerate().any(|(i, &b)| {
        f.successors(b)
            .iter()
            .any(|s| pos.get(s).is_some_and(|&j| j <= i))
    })
}

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
