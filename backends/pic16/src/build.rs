//! [`build`]: a verified module to the chip's program, one function per phase.
//!
//! 1. [`check`]: what the chip cannot run (unchecked pointers, C code, recursion).
//! 2. [`legalize`]: calls bound at run time as compare chains of direct calls, REAL
//!    as integers and calls of the soft-float routines, jump tables as binary
//!    searches of compares.
//! 3. [`CallOrder::of`]: the call graph from the roots, callers first, and the
//!    pointer parameters every caller agrees on.
//! 4. [`frames_of`]: each function's static frame, and the data it touches.
//! 5. [`place::place`]: RAM for the runtime, the workspace, the data, the frames.
//! 6. [`emit`]: labels, and each function's code by [`crate::isel`].
//! 7. [`bind_pins`]: the BOOL variables located at pins.
//! 8. [`runtime_units`]: the reset and interrupt vectors and the scan loop, which
//!    calls each program's init and body with its instance.
//! 9. [`select_banks`]: the bank selects the control flow needs ([`crate::banks`]).
//! 10. [`stack_depth`]: the deepest chain of calls against the 8-level stack.
//! 11. [`symbols`]: the variables for the listing and the runner; the header; the
//!     assembly ([`crate::asm`]).

mod place;

use crate::asm::{self, DataSymbol, Item, Label, Program, Unit};
use crate::frame::{self, FrameInfo, Ptr, Repr, Sym};
use crate::helpers::{self, HelperSet};
use crate::isel::{Emitter, Placement};
use crate::ram::{self, PicLayout};
use crate::runtime::{self, PinBinding};
use crate::{banks, codes, softfloat, Build};
use plcc_ir::backend::{Options, Symbol};
use plcc_ir::diag::Diagnostic;
use plcc_ir::inst::{BinaryOp, InstData, Intrinsic};
use plcc_ir::names::{identifier, Namer};
use plcc_ir::{DataId, FuncId, MemType, Module, Type};
use rustc_hash::{FxHashMap, FxHashSet};

/// Compiles a verified module for the chip.
pub fn build(module: &Module, options: &Options) -> Result<Build, Vec<Diagnostic>> {
    check(module)?;
    let pin_over = setting_pins(options)?;
    let legal = legalize(module)?;
    let module = &legal;
    let layout = PicLayout::compute(module);
    let calls = CallOrder::of(module);
    let frames = frames_of(module, &layout, &calls);
    let needs = RuntimeNeeds::of(module, &calls.order);
    let ram = place::place(module, &layout, &calls, &frames, &needs)?;
    let mut taken = taken_names();
    let mut code = emit(module, &layout, &calls, &frames, &ram, options, &mut taken)?;
    let pins = bind_pins(module, &layout, &ram.data, &pin_over);
    let mut all = runtime_units(module, &frames, &ram, &pins, &mut code);
    let bank_selects = select_banks(&mut all)?;
    code.program.units = all;
    let stack_depth = stack_depth(&calls, &code.helper_users, ram.rt.ticks)?;
    let vars = symbols(
        module,
        &layout,
        &ram,
        needs.widest_muldiv,
        &mut code.program,
        &mut taken,
    );
    let mut program = code.program;
    program.header = header(&pins);
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
    let scan_addr = image.label_addr[code.rl.scan.0 as usize];
    let scan_end_addr = image.label_addr[code.rl.scan_end.0 as usize];
    program.header.insert(
        1,
        format!(
            "flash {}/{} words, ram {}/{} bytes, stack {}/8, bank selects {}",
            image.used_words(),
            asm::FLASH_WORDS,
            ram.ram_used,
            ram::RAM_BYTES,
            stack_depth,
            bank_selects
        ),
    );
    Ok(Build {
        program,
        image,
        symbols: vars.symbols,
        bits: vars.bits,
        asm_names: vars.asm_names,
        pins,
        rt: ram.rt,
        ram_used: ram.ram_used,
        stack_depth,
        bank_selects,
        scan_addr,
        scan_end_addr,
        data: ram.data,
        layout,
    })
}

/// What the chip cannot run: unchecked pointers, C code, recursion.
fn check(module: &Module) -> Result<(), Vec<Diagnostic>> {
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
    Ok(())
}

/// The module as the chip can run it: calls bound at run time become compare chains
/// of direct calls (CALL takes an immediate address), so the call graph, the stack
/// depth and the frame overlays see every entry; REAL becomes integers and calls of
/// the soft-float routines; SIZEOF is the size in the chip's layout; the compares
/// value ranges decide are constants; jump tables are binary searches of compares.
fn legalize(module: &Module) -> Result<Module, Vec<Diagnostic>> {
    let mut legal = module.clone();
    let layout = PicLayout::compute(module);
    plcc_ir::passes::sizes::resolve(&mut legal, |t| layout.size(t) as u64);
    // Compares that value ranges decide (bounds checks a loop makes redundant) go.
    plcc_ir::passes::ranges::run_module(&mut legal);
    plcc_ir::passes::dispatch::run(&mut legal);
    softfloat::legalize(&mut legal)?;
    // Small jump tables (the soft-float routines' included) become binary searches
    // of compares; the others, computed GOTOs (`isel::flow::br_table`).
    for f in &mut legal.funcs {
        plcc_ir::passes::br_table::run_below(f, plcc_ir::passes::br_table::PIC16_MIN_TABLE);
    }
    Ok(legal)
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

/// The call graph from the roots (`plcc_ir::analysis`) and what it tells.
pub(super) struct CallOrder {
    /// The functions each function calls.
    pub callees: Vec<Vec<FuncId>>,
    /// What the runtime calls: the globals' initialiser, each program's init and body.
    pub roots: Vec<FuncId>,
    /// The functions reached from the roots, callers before callees.
    pub order: Vec<FuncId>,
    /// For each function, the pointer each parameter holds at every call, if the
    /// callers agree on one.
    pub consensus: Vec<Vec<Option<Ptr>>>,
}

impl CallOrder {
    fn of(module: &Module) -> CallOrder {
        let callees: Vec<Vec<FuncId>> = (0..module.funcs.len())
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
        // Pointers every caller agrees on: the runtime passes each program's instance.
        let mut root_params: FxHashMap<FuncId, Vec<Option<Ptr>>> = FxHashMap::default();
        let mut merge_root = |f: FuncId, p: Option<Ptr>| {
            let e = root_params.entry(f).or_insert_with(|| vec![p]);
            if e[0] != p {
                e[0] = None;
            }
        };
        for p in &module.programs {
            let ptr = Some(Ptr::Known(Sym::Data(p.data), 0, 0));
            merge_root(p.body, ptr);
            merge_root(p.init, ptr);
        }
        let consensus = frame::param_consensus(&module.funcs, &order, &root_params);
        CallOrder {
            callees,
            roots,
            order,
            consensus,
        }
    }
}

/// The functions' frames and the data they touch.
pub(super) struct Frames {
    /// Each function's frame.
    pub info: Vec<FrameInfo>,
    /// The data objects each function reads and writes directly, with a count.
    pub touches: Vec<FxHashMap<DataId, u32>>,
}

/// Builds the frame of every function reached from the roots.
fn frames_of(module: &Module, layout: &PicLayout, calls: &CallOrder) -> Frames {
    let nf = module.funcs.len();
    let mut info: Vec<FrameInfo> = vec![FrameInfo::default(); nf];
    let mut touches: Vec<FxHashMap<DataId, u32>> = vec![FxHashMap::default(); nf];
    for &fid in &calls.order {
        let f = &module.funcs[fid.index()];
        let mut ptrs = frame::pointer_facts(f, fid, &calls.consensus[fid.index()]);
        frame::derive_pointers(f, layout, &mut ptrs);
        for (_, i) in f.inst_iter() {
            if let InstData::Load { addr, .. } | InstData::Store { addr, .. } = f.inst(i) {
                if let Some(Ptr::Known(Sym::Data(d), _, _)) = ptrs.get(addr) {
                    *touches[fid.index()].entry(*d).or_default() += 1;
                }
            }
        }
        let slot_sizes: Vec<u32> = f.slots.iter().map(|s| layout.size(s.ty)).collect();
        info[fid.index()] = frame::build_frame(f, &ptrs, &slot_sizes);
    }
    Frames { info, touches }
}

/// What the runtime must provide for the code.
pub(super) struct RuntimeNeeds {
    /// The millisecond clock is read.
    pub uses_ms: bool,
    /// The nanosecond clock is read.
    pub uses_ns: bool,
    /// The widest integer multiplied or divided, in bytes (0: none).
    pub widest_muldiv: u16,
}

impl RuntimeNeeds {
    fn of(module: &Module, order: &[FuncId]) -> RuntimeNeeds {
        let mut needs = RuntimeNeeds {
            uses_ms: false,
            uses_ns: false,
            widest_muldiv: 0,
        };
        for &fid in order {
            let f = &module.funcs[fid.index()];
            for (_, i) in f.inst_iter() {
                match f.inst(i) {
                    InstData::Intrinsic {
                        op: Intrinsic::ClockNs,
                        ..
                    } => needs.uses_ns = true,
                    InstData::Intrinsic {
                        op: Intrinsic::ClockMs,
                        ..
                    } => needs.uses_ms = true,
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
                            needs.widest_muldiv =
                                needs.widest_muldiv.max(ram::scalar_bytes(t) as u16);
                        }
                    }
                    _ => {}
                }
            }
        }
        needs
    }
}

/// The names the listing reserves: the assembler's, and the runtime's symbols.
fn taken_names() -> Namer {
    let mut taken = Namer::new(true);
    taken.reserve(asm::reserved_names());
    taken.reserve(runtime::common_symbols().into_iter().map(|(n, ..)| n));
    taken.reserve([
        "plc_flags",
        "plc_isr_save",
        "plc_clock_ms",
        "plc_now_ms",
        "plc_clock_ns",
        "plc_now_ns",
        "plc_ws",
    ]);
    taken
}

/// The code of the functions, before the runtime and the bank selects.
struct Code {
    /// The program being built: its labels (the functions' units are in `units`).
    program: Program,
    /// The runtime's labels.
    rl: runtime::RuntimeLabels,
    /// Each function's entry label.
    func_label: Vec<Label>,
    /// Each function's unit, in `order`.
    units: Vec<Unit>,
    /// The helper routines the code calls.
    helper_set: HelperSet,
    /// The functions that call a helper (one more stack level).
    helper_users: FxHashSet<FuncId>,
}

/// Labels every function and emits its code.
fn emit(
    module: &Module,
    layout: &PicLayout,
    calls: &CallOrder,
    frames: &Frames,
    ram: &place::RamPlan,
    options: &Options,
    taken: &mut Namer,
) -> Result<Code, Vec<Diagnostic>> {
    let nf = module.funcs.len();
    let mut program = Program {
        config: 0x3F32,
        ..Default::default()
    };
    let rl = runtime::labels(&mut program.labels);
    let mut func_label = vec![Label(u32::MAX); nf];
    for &f in &calls.order {
        let name = asm_name(&format!("f_{}", module.funcs[f.index()].name), taken);
        program.labels.push(name);
        func_label[f.index()] = Label(program.labels.len() as u32 - 1);
    }
    let placement = Placement {
        module,
        layout,
        data: ram.data.clone(),
        frame_base: ram.frame_base.clone(),
        frames: &frames.info,
        func_label: func_label.clone(),
        rt: ram.rt,
        ws: ram.ws,
    };
    let sources: Vec<Option<String>> = options.sources.clone();
    let mut helper_set = HelperSet::default();
    let mut units: Vec<Unit> = Vec::new();
    let mut diags = Vec::new();
    let mut helper_users: FxHashSet<FuncId> = FxHashSet::default();
    for &f in &calls.order {
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
        let frame = ram.placed[f.index()].map(|(s, e)| (s, e, format!("{prefix}_fr")));
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
    Ok(Code {
        program,
        rl,
        func_label,
        units,
        helper_set,
        helper_users,
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

/// The BOOL variables (and BOOL fields) located at a bit of `%IX`/`%QX` that has a
/// pin, by default or by a `pin.` setting.
fn bind_pins(
    module: &Module,
    layout: &PicLayout,
    data: &ram::DataMap,
    pin_over: &FxHashMap<String, runtime::Pin>,
) -> Vec<PinBinding> {
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
                        data.addr(DataId::new(i), 0),
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
                                data.addr(DataId::new(i), p.offset),
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
    pins
}

/// Every unit of the program: the reset vector, the interrupt routine and the scan
/// loop (which calls each program's init and body with the address of its
/// instance), the functions' units, and the helper routines they call.
fn runtime_units(
    module: &Module,
    frames: &Frames,
    ram: &place::RamPlan,
    pins: &[PinBinding],
    code: &mut Code,
) -> Vec<Unit> {
    // A callee that does not know its instance's address already (several
    // instances share it, or a configuration's wrapper calls it too) reads it from
    // its frame: store it there before each call, as a call in the code would.
    let func_label = &code.func_label;
    let entry_call = |f: FuncId, d: DataId| runtime::EntryCall {
        label: func_label[f.index()],
        stores: instance_arg_stores(
            &module.funcs[f.index()],
            &frames.info[f.index()],
            ram.frame_base[f.index()],
            ram.data.addr(d, 0),
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
        rt: ram.rt,
        inits,
        bodies,
        pins,
    };
    let labels = &mut code.program.labels;
    let mut all = vec![runtime::reset_unit(&code.rl)];
    if ram.rt.ticks {
        all.push(runtime::isr_unit(&ram.rt, labels));
    }
    all.push(runtime::main_unit(&plan, &code.rl));
    all.append(&mut code.units);
    for mut u in code.helper_set.units(ram.ws) {
        helpers::resolve_local(&mut u, labels);
        all.push(u);
    }
    all
}

/// Inserts the bank selects and returns how many. Round one, callees first and
/// entries unknown: the bank each unit returns with and the banks known at every
/// call. Round two: each unit starts with what all its callers agree on. (Round
/// one's facts hold in round two, as knowing more at an entry only ever adds to what
/// is known.)
fn select_banks(all: &mut [Unit]) -> Result<u32, Vec<Diagnostic>> {
    let entry_label = |u: &Unit| {
        u.items.iter().find_map(|it| match it {
            Item::Label(l) => Some(*l),
            _ => None,
        })
    };
    let internal = |e: String| vec![Diagnostic::error_nowhere(codes::E_INTERNAL, e)];
    let mut exits: FxHashMap<Label, banks::State> = FxHashMap::default();
    let mut entries: FxHashMap<Label, Option<banks::State>> = FxHashMap::default();
    for u in all.iter().rev() {
        let mut probe = u.clone();
        let st = banks::insert_selects(&mut probe, banks::State::UNKNOWN, &|l| {
            exits.get(&l).copied()
        })
        .map_err(internal)?;
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
        let st = banks::insert_selects(u, entry, &|l| exits.get(&l).copied()).map_err(internal)?;
        bank_selects += st.selects;
    }
    Ok(bank_selects)
}

/// The deepest use of the hardware stack: the scan loop's calls, plus one level for
/// the clock's interrupt when there is one; an error past the chip's 8 levels.
fn stack_depth(
    calls: &CallOrder,
    helper_users: &FxHashSet<FuncId>,
    interrupt: bool,
) -> Result<u32, Vec<Diagnostic>> {
    let mut depth: Vec<u32> = vec![0; calls.callees.len()];
    for &f in calls.order.iter().rev() {
        let mut d = 1;
        for &g in &calls.callees[f.index()] {
            d = d.max(1 + depth[g.index()]);
        }
        if helper_users.contains(&f) {
            d = d.max(2);
        }
        depth[f.index()] = d;
    }
    let stack_depth = calls
        .roots
        .iter()
        .map(|r| depth[r.index()])
        .max()
        .unwrap_or(0)
        + u32::from(interrupt);
    if stack_depth > 8 {
        let with = if interrupt {
            " (the clock's interrupt included)"
        } else {
            ""
        };
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_STACK,
            format!(
                "the deepest chain of calls needs {stack_depth} levels of the 8-level hardware stack{with}: {} too many",
                stack_depth - 8
            ),
        )]);
    }
    Ok(stack_depth)
}

/// The program's variables as the runner and the listing see them.
struct Vars {
    symbols: Vec<Symbol>,
    bits: Vec<Option<u8>>,
    asm_names: Vec<String>,
}

/// The symbols of the listing (the runtime's, every variable's, every frame's) and
/// the variables for the runner.
fn symbols(
    module: &Module,
    layout: &PicLayout,
    ram: &place::RamPlan,
    widest_muldiv: u16,
    program: &mut Program,
    taken: &mut Namer,
) -> Vars {
    let rt = ram.rt;
    let mut vars = Vars {
        symbols: Vec::new(),
        bits: Vec::new(),
        asm_names: Vec::new(),
    };
    let mut sym = |name: String, addr: u16, size: u16, comment: String| {
        program.symbols.push(DataSymbol {
            name,
            addr,
            size,
            bit: None,
            comment,
        })
    };
    for (n, a, size, c) in runtime::common_symbols() {
        sym(n.into(), a, size, c.into());
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
        sym(n.into(), a, s, c.into());
    }
    if let Some(ns) = rt.clk_ns {
        for (n, a, c) in [
            ("plc_clock_ns", ns, "running clock, ns"),
            ("plc_now_ns", rt.now_ns, "clock sampled at scan start, ns"),
        ] {
            sym(n.into(), a, 8, c.into());
        }
    }
    if widest_muldiv > 0 {
        let size = helpers::workspace_bytes(widest_muldiv);
        sym(
            "plc_ws".into(),
            ram.ws.a,
            size,
            "multiply/divide workspace".into(),
        );
    }
    for i in 0..module.data.len() {
        for v in plcc_ir::vars::variables(module, DataId::new(i)) {
            let place = layout.place_of(&v.steps);
            let addr = ram.data.addr(DataId::new(i), place.offset);
            let is_bool = v.ty == Type::I1;
            vars.symbols.push(Symbol {
                path: v.path.clone(),
                address: addr as u64,
                size: ram::scalar_bytes(v.ty),
                elem: v.elem,
            });
            vars.bits.push(is_bool.then_some(place.bit));
            let name = asm_name(&v.path, taken);
            vars.asm_names.push(name.clone());
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
    let frames: Vec<DataSymbol> = program
        .units
        .iter()
        .filter_map(|u| {
            let (s, _, n) = u.frame.as_ref()?;
            Some(DataSymbol {
                name: n.clone(),
                addr: *s,
                size: 0,
                bit: None,
                comment: format!("frame of {}", u.name),
            })
        })
        .collect();
    program.symbols.extend(frames);
    vars
}

/// The listing's header (the summary line is inserted once the code is assembled).
fn header(pins: &[PinBinding]) -> Vec<String> {
    let mut header = vec![
        "PIC16F876A assembly generated by plcc".into(),
        "assemble with: gpasm FILE.asm (MPASM syntax)".into(),
        "pins: %IX0.0-7 = RB0-7, %IX1.0-5 = RA0-5, %QX0.0-7 = RC0-7 (unless overridden)".into(),
    ];
    for p in pins {
        header.push(format!(
            "  {} {} {}",
            p.path,
            if p.input { "<-" } else { "->" },
            p.pin.name()
        ));
    }
    header
}

/// Assembler-safe name of a source path: `main.timer.Q` → `main_timer_Q`.
fn asm_name(path: &str, taken: &mut Namer) -> String {
    let mut s = identifier(path);
    while s.contains("__") {
        s = s.replace("__", "_");
    }
    let s = s.trim_end_matches('_').to_string();
    let s = if s.chars().next().is_some_and(|c| c.is_ascii_digit()) || s.is_empty() {
        format!("v_{s}")
    } else {
        s
    };
    taken.unique(&s)
}
