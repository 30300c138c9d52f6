//! A whole build: calling conventions, the layout fixpoint, data placement, the task
//! code, assembly and the variables' addresses.
//!
//! Instances carry their functions' temporaries, and a function's call area is as
//! large as its callees' frames, so sizes depend on code and code on sizes (offsets
//! of fields after an instance grow with its temporaries). The build generates all
//! code with the sizes of the previous round until nothing changes; the dependencies
//! are acyclic (no recursion, no struct containing itself), so this ends after at most
//! as many rounds as the deepest nesting.

use crate::code::{Arg, Image, Item, Program, Unit, VInst};
use crate::codes;
use crate::isa::{op, Mode};
use crate::isel::{self, Conv, Cx};
use plcc_ir::backend::{Options, Symbol};
use plcc_ir::diag::Diagnostic;
use plcc_ir::entities::{AggId, DataId, FuncId};
use plcc_ir::function::FuncKind;
use plcc_ir::inst::InstData;
use plcc_ir::layout::Layout as VmLayout;
use plcc_ir::module::{AggDef, StructKind};
use plcc_ir::types::{MemType, Type};
use plcc_ir::Module;
use rustc_hash::FxHashMap;

use crate::port::Port;

/// Settings of the vmasm target (`-s key=value`).
#[derive(Clone, Debug)]
pub struct Settings {
    /// The addressing mode (`mode=16|32|32a`).
    pub mode: Mode,
    /// The task cycle written to the DCP, in ms (`cycle=…`; else the common tick
    /// of the programs' tasks, the GCD of their intervals, else 100 ms).
    pub cycle_ms: Option<u32>,
    /// The VM port the code is for (`port=full|esp32|avr|6502|sdcc`): what it lacks is
    /// a compile error, and its C `int` width picks the UB-free instruction forms.
    pub port: Port,
}

impl Settings {
    /// Reads the settings of `options`.
    pub fn from_options(options: &Options) -> Result<Settings, Box<Diagnostic>> {
        let mut s = Settings {
            mode: Mode::M16,
            cycle_ms: None,
            port: Port::Full,
        };
        for (k, v) in &options.settings {
            match k.to_ascii_lowercase().as_str() {
                "mode" => {
                    s.mode = Mode::parse(v).ok_or_else(|| {
                        Box::new(Diagnostic::error_nowhere(
                            codes::E_BAD_SETTING,
                            format!("vmasm: unknown mode `{v}` (modes: 16, 32, 32a)"),
                        ))
                    })?
                }
                "cycle" => {
                    s.cycle_ms = Some(v.parse().ok().filter(|&c| c > 0).ok_or_else(|| {
                        Box::new(Diagnostic::error_nowhere(
                            codes::E_BAD_SETTING,
                            format!("vmasm: `cycle` must be a positive number of ms, not `{v}`"),
                        ))
                    })?)
                }
                "port" => {
                    s.port = Port::parse(v).ok_or_else(|| {
                        Box::new(Diagnostic::error_nowhere(
                            codes::E_BAD_SETTING,
                            format!(
                                "vmasm: unknown port `{v}` (ports: full, esp32, avr, 6502, sdcc)"
                            ),
                        ))
                    })?
                }
                _ => {
                    return Err(Box::new(Diagnostic::error_nowhere(
                        codes::E_BAD_SETTING,
                        format!("vmasm: unknown setting `{k}` (settings: mode, cycle, port)"),
                    )))
                }
            }
        }
        Ok(s)
    }
}

/// A program instance the task runs.
#[derive(Clone, Debug)]
pub struct TaskProgram {
    /// Its name.
    pub name: String,
    /// Absolute address of its instance.
    pub addr: u32,
    /// Its data object.
    pub data: DataId,
}

/// Everything a build produces.
#[derive(Clone, Debug)]
pub struct Build {
    /// The settings it was made with.
    pub settings: Settings,
    /// The assembled code and listing.
    pub image: Image,
    /// Bytes of data memory the program needs.
    pub data_size: u32,
    /// Absolute address of every data object.
    pub data_addrs: Vec<u32>,
    /// The layout of aggregates.
    pub layout: VmLayout,
    /// Where the task body starts (the scan loop's top, `TSKLOOP`).
    pub loop_addr: u32,
    /// The programs, in the order the task runs them.
    pub programs: Vec<TaskProgram>,
    /// Every variable and its address.
    pub symbols: Vec<Symbol>,
    /// Absolute address of the fault word ([`FAULT_NAME`]): a WORD that cold start
    /// sets to 0 and a runtime fault (division by zero, an index out of range, a NULL
    /// dereference) to 1; nothing in the VM acts on it.
    pub fault_addr: u32,
}

/// The name the DCP gives the fault word, for the runtime or HMI that wants to show it.
pub const FAULT_NAME: &str = "PLCC_FAULT";

/// The struct a function with an instance runs on, if it has one.
fn instance_agg(module: &Module, id: FuncId) -> Option<AggId> {
    let f = module.func(id);
    if !matches!(
        f.kind,
        FuncKind::FbBody | FuncKind::ProgramBody | FuncKind::Init
    ) || f.params.first() != Some(&Type::Ptr)
    {
        return None;
    }
    for p in &module.programs {
        if p.body == id || p.init == id {
            if let MemType::Agg(a) = module.data[p.data.index()].ty {
                return Some(a);
            }
        }
    }
    // The FB's own struct, named as its body (`@K1`, `@K1$init` for `%K1`, and
    // `@K2$SUPER.K0` for K0's body run by CODESYS's `SUPER^()` on a K2).
    let own = f.name.split('$').next().unwrap_or(&f.name);
    if let Some(k) = module.aggs.iter().position(|a| {
        matches!(a, AggDef::Struct(s) if s.name == own
            && matches!(s.kind, StructKind::FunctionBlock | StructKind::Program))
    }) {
        return Some(AggId::new(k));
    }
    // Else the struct with the most fields addressed on the instance: a derived FB's
    // struct begins with its bases' fields, so its body may address the instance
    // through a base's struct too (an inlined base method), and the frame must come
    // after the derived fields, not the base's.
    let entry = f.entry()?;
    let this = *f.block(entry).params.first()?;
    let fields = |a: AggId| match module.agg(a) {
        AggDef::Struct(s) => s.fields.len(),
        AggDef::Array(_) => 0,
    };
    f.inst_iter()
        .filter_map(|(_, i)| match f.inst(i) {
            InstData::FieldAddr { base, agg, .. } if *base == this => Some(*agg),
            _ => None,
        })
        .max_by_key(|a| fields(*a))
}

fn label_name(module: &Module, id: FuncId) -> String {
    let f = module.func(id);
    let what = if f.kind == FuncKind::Init {
        "INIT"
    } else {
        "CODE"
    };
    format!("?plcc.{}?{what}", f.name)
}

/// The deepest nesting of calls the C VMs' return stack holds: the builds with a
/// 128-entry stack stop on the 129th call, and those with 256 entries let the 8-bit
/// stack pointer wrap (`reference/cpdev-vm-opcodes.md` §0).
pub const MAX_CALL_DEPTH: usize = 128;

/// Rejects a program whose calls nest deeper than [`MAX_CALL_DEPTH`] (counting the
/// task's call of a program body): the longest path of the call graph.
fn check_call_depth(module: &Module) -> Result<(), Vec<Diagnostic>> {
    let depth = plcc_ir::analysis::call_depths(module);
    for p in &module.programs {
        for f in [p.init, p.body] {
            let d = depth[f.index()] + 1;
            if d > MAX_CALL_DEPTH {
                return Err(vec![Diagnostic::error_nowhere(
                    codes::E_MEMORY,
                    format!(
                        "vmasm: the calls of `{}` nest {d} deep; the CPDev VMs' return stack holds {MAX_CALL_DEPTH}",
                        module.func(f).name
                    ),
                )]);
            }
        }
    }
    Ok(())
}

/// Compiles a verified module.
pub fn build(module: &Module, options: &Options) -> Result<Build, Vec<Diagnostic>> {
    if module.unchecked_pointers {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED,
            "unchecked pointers (CODESYS pointer arithmetic, a pointer given the address of another type, or the address of a temporary kept) are not supported on the vmasm target: run the program on interp",
        )]);
    }
    plcc_ir::backend::reject_inline_c(module, "the vmasm target", codes::E_UNSUPPORTED)?;
    if let Some(p) = module
        .programs
        .iter()
        .find(|p| p.interval_us.is_some_and(|us| us % 1000 != 0))
    {
        let us = p.interval_us.unwrap_or_default();
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED,
            format!(
                "the task of `{}` runs every {}.{:03} ms, but the CPDev VM's clock counts whole milliseconds: give the task a whole number of milliseconds, or run the program on host, interp or pic16f876a",
                p.name,
                us / 1000,
                us % 1000
            ),
        )]);
    }
    let settings = Settings::from_options(options).map_err(|d| vec![*d])?;
    // Frames are static: the verifier rejects recursion, and a module that skipped
    // it is refused here rather than given frames that overwrite each other.
    if let Some(cycle) = plcc_ir::analysis::find_recursion(module) {
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED,
            format!(
                "recursion ({}, directly or through a table) is not supported on the vmasm target: every frame is static",
                plcc_ir::analysis::describe_cycle(module, &cycle)
            ),
        )]);
    }
    check_call_depth(module)?;
    // The guards of what the port's C leaves undefined (division by zero, MIN / -1
    // where it overflows, shifts by the width, float-to-integer conversions out of
    // range) are the IR's legalization; the instruction selector emits those
    // operations plainly.
    let mut legal = module.clone();
    // The VM's jumps take immediate addresses only: jump tables (dense CASEs) become
    // binary searches of compares.
    plcc_ir::passes::br_table::run_module(&mut legal);
    // Compares that value ranges decide (bounds checks a loop makes redundant) go
    // first, as in the other targets.
    plcc_ir::passes::ranges::run_module(&mut legal);
    // Loops that only set an array's elements to one value become `fill`s (FPAT and
    // MEMCPs, `isel/fill.rs`); the pass's cleanup folds the count, most often to a
    // constant.
    for k in 0..legal.funcs.len() {
        let placeholder = plcc_ir::function::Function::new("", FuncKind::Function, vec![], None);
        let mut f = std::mem::replace(&mut legal.funcs[k], placeholder);
        plcc_ir::passes::fill::run(&mut f, &legal);
        legal.funcs[k] = f;
    }
    plcc_ir::passes::legalize::run(&mut legal, &settings.port.defines());
    let module = &legal;
    let has_sizeof = plcc_ir::passes::sizes::any(module);
    let mode = settings.mode;
    let ptr_bytes = mode.addr_bytes() as u32;
    let max_align = if mode == Mode::M32A { 4 } else { 1 };
    let nf = module.funcs.len();
    let selfs: Vec<Option<AggId>> = (0..nf)
        .map(|i| instance_agg(module, FuncId::new(i)))
        .collect();
    let mut frame_sizes = vec![0u32; nf];
    let mut round = 0;
    loop {
        round += 1;
        // Temporaries of every instance: its functions' frames one after another.
        let mut temps = vec![0u32; module.aggs.len()];
        for (i, s) in selfs.iter().enumerate() {
            if let Some(a) = s {
                temps[a.index()] += frame_sizes[i];
            }
        }
        let rules = plcc_ir::layout::LayoutRules {
            ptr_bytes,
            max_align,
        };
        let layout = VmLayout::compute_with_tails(&legal, rules, &temps);
        // SIZEOF is the size in this round's layout (an instance's temporaries
        // included); the rounds end when the layout no longer changes.
        let sized;
        let module = if has_sizeof {
            let mut m = legal.clone();
            plcc_ir::passes::sizes::resolve(&mut m, |t| layout.size_of(t) as u64);
            sized = m;
            &sized
        } else {
            &legal
        };
        let mut used = vec![0u32; module.aggs.len()];
        let convs: Vec<Conv> = selfs
            .iter()
            .enumerate()
            .map(|(i, s)| match s {
                Some(a) => {
                    let base = layout.agg(*a).fields_end + used[a.index()];
                    used[a.index()] += frame_sizes[i];
                    Conv::Instance {
                        agg: *a,
                        temp_base: base,
                    }
                }
                None => Conv::Area,
            })
            .collect();
        let mut data_addrs = Vec::with_capacity(module.data.len());
        // Address 0 is the null pointer: when the program has one, no data starts there.
        let uses_null = module.funcs.iter().any(|f| {
            f.inst_iter()
                .any(|(_, i)| matches!(f.inst(i), InstData::Iconst { ty: Type::Ptr, .. }))
        });
        let mut at: u64 = if uses_null { 8 } else { 0 };
        for d in &module.data {
            let a = layout.align_of(d.ty) as u64;
            at = at.div_ceil(a) * a;
            data_addrs.push(at as u32);
            at += layout.size_of(d.ty) as u64;
        }
        // The fault word after the data objects.
        at = at.div_ceil(2) * 2;
        let fault_addr = at as u32;
        at += 2;
        let constants_once = constants_once(module, &convs);
        let mut prog = Program::default();
        let entry_labels: Vec<_> = (0..nf)
            .map(|i| prog.label(label_name(module, FuncId::new(i))))
            .collect();
        let cx = Cx {
            module,
            layout: &layout,
            mode,
            convs: &convs,
            frame_sizes: &frame_sizes,
            data_addrs: &data_addrs,
            entry_labels: &entry_labels,
            sources: &options.sources,
            fault_addr,
            port: settings.port,
            constants_once: &constants_once,
        };
        let mut units = Vec::with_capacity(nf);
        let mut pools = Vec::new();
        let mut new_sizes = vec![0u32; nf];
        let mut errors = Vec::new();
        for (i, size) in new_sizes.iter_mut().enumerate() {
            match isel::gen_function(&cx, &mut prog, FuncId::new(i)) {
                Ok(fc) => {
                    *size = fc.frame_size;
                    units.push(fc.unit);
                    if let Some((label, unit)) = fc.constants {
                        pools.push((FuncId::new(i), label));
                        units.push(unit);
                    }
                }
                Err(d) => errors.push(*d),
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        if new_sizes != frame_sizes {
            if round > 64 {
                return Err(vec![Diagnostic::error_nowhere(
                    codes::E_INTERNAL,
                    "vmasm: frame sizes do not settle",
                )]);
            }
            frame_sizes = new_sizes;
            continue;
        }
        // The area the task's own calls use (functions without an instance).
        let mut top_area_size = 0;
        let top_calls: Vec<FuncId> = module
            .init_globals
            .into_iter()
            .chain(module.programs.iter().flat_map(|p| [p.init, p.body]))
            .collect();
        for g in &top_calls {
            if convs[g.index()] == Conv::Area {
                top_area_size = top_area_size.max(frame_sizes[g.index()]);
            }
        }
        let top_area = at.div_ceil(max_align as u64) * max_align as u64;
        let data_size = top_area + top_area_size as u64;
        if data_size > mode.max_addr() + 1 {
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_MEMORY,
                format!(
                    "vmasm: the program needs {data_size} bytes of data memory; {}-bit addresses reach {}",
                    if mode == Mode::M16 { 16 } else { 32 },
                    mode.max_addr() + 1
                ),
            )]);
        }
        let top_area = top_area as u32;
        let programs: Vec<TaskProgram> = module
            .programs
            .iter()
            .map(|p| TaskProgram {
                name: p.name.clone(),
                addr: data_addrs[p.data.index()],
                data: p.data,
            })
            .collect();
        let mut task = Unit::default();
        let tskstr = prog.label("?plcc.TASK?TSKSTR");
        let tskloop = prog.label("?plcc.TASK?TSKLOOP");
        task.items.push(Item::Label(tskstr));
        // Cold start clears the fault word (the task runs with DPTR at 0).
        task.items.push(Item::Inst(VInst {
            opcode: mode.mcd(),
            args: vec![Arg::Abs(fault_addr), Arg::Bytes(vec![0, 0])],
        }));
        let call = |task: &mut Unit, g: FuncId, inst: Option<u32>| {
            let label = entry_labels[g.index()];
            match (convs[g.index()], inst) {
                (Conv::Instance { .. }, Some(a)) => task.items.push(Item::Inst(VInst {
                    opcode: op::CALB,
                    args: vec![Arg::Abs(a), Arg::Label(label)],
                })),
                (_, inst) => {
                    if let Some(a) = inst {
                        // The instance's address is the callee's first parameter.
                        let (params, _, _) =
                            isel::signature(&layout, module.func(g), Conv::Area, mode);
                        let p = params[0].unwrap_or(0);
                        let opcode = mode.mcd();
                        task.items.push(Item::Inst(VInst {
                            opcode,
                            args: vec![
                                Arg::Abs(top_area + p),
                                Arg::Bytes(a.to_le_bytes()[..mode.addr_bytes()].to_vec()),
                            ],
                        }));
                    }
                    task.items.push(Item::Inst(VInst {
                        opcode: op::CALF,
                        args: vec![Arg::Abs(top_area), Arg::Label(label)],
                    }));
                }
            }
        };
        if let Some(g) = module.init_globals {
            call(&mut task, g, None);
        }
        for p in &module.programs {
            call(&mut task, p.init, Some(data_addrs[p.data.index()]));
        }
        // The constant pools of the PROGRAM bodies that load them once: only the body
        // writes its frame in the instance, and it never writes its constants.
        for p in &module.programs {
            if let Some(&(_, label)) = pools.iter().find(|(g, _)| *g == p.body) {
                task.items.push(Item::Inst(VInst {
                    opcode: op::CALB,
                    args: vec![Arg::Abs(data_addrs[p.data.index()]), Arg::Label(label)],
                }));
            }
        }
        task.items.push(Item::Label(tskloop));
        for p in &module.programs {
            call(&mut task, p.body, Some(data_addrs[p.data.index()]));
        }
        task.items.push(Item::Inst(VInst {
            opcode: op::TRML,
            args: vec![Arg::Label(tskloop)],
        }));
        let mut names = FxHashMap::default();
        for (d, &a) in module.data.iter().zip(&data_addrs) {
            names.entry(a).or_insert_with(|| d.name.clone());
        }
        names.insert(fault_addr, FAULT_NAME.to_string());
        names
            .entry(top_area)
            .or_insert_with(|| "?TASK?AREA".to_string());
        task.abs_names = names.clone();
        for u in &mut units {
            u.abs_names = names.clone();
        }
        prog.units.push(task);
        prog.units.append(&mut units);
        let image = prog.assemble(mode).map_err(|m| {
            vec![Diagnostic::error_nowhere(
                codes::E_MEMORY,
                format!("vmasm: {m}"),
            )]
        })?;
        let loop_addr = image.label_addrs[tskloop.0 as usize];
        let mut symbols = Vec::new();
        for (i, &base) in data_addrs.iter().enumerate() {
            for v in plcc_ir::vars::variables(module, DataId::new(i)) {
                symbols.push(Symbol {
                    path: v.path.clone(),
                    address: base as u64 + layout.offset_of(&v.steps),
                    size: layout.scalar_size(v.ty),
                    elem: v.elem,
                });
            }
        }
        return Ok(Build {
            settings,
            image,
            data_size: data_size as u32,
            data_addrs,
            layout,
            loop_addr,
            programs,
            symbols,
            fault_addr,
        });
    }
}

/// The functions whose constant pool the task loads once at cold start: the bodies of
/// the task's PROGRAMs (with their instance as frame) that no call and no function
/// table reaches, so that they only ever run on the instances the task loads.
fn constants_once(module: &Module, convs: &[Conv]) -> Vec<bool> {
    let mut once = vec![false; module.funcs.len()];
    for p in &module.programs {
        once[p.body.index()] = matches!(convs[p.body.index()], Conv::Instance { .. });
    }
    for f in &module.funcs {
        for (_, i) in f.inst_iter() {
            if let InstData::Call { func, .. } = f.inst(i) {
                once[func.index()] = false;
            }
        }
    }
    for t in &module.tables {
        for g in t.entries.iter().flatten() {
            once[g.index()] = false;
        }
    }
    once
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of `n` functions, each calling the next, under a program body.
    fn chain(n: usize) -> Module {
        let mut t = String::from(
            "struct %main program {\n    var r: i16 INT\n}\n\ndata @main: %main program\n\n",
        );
        for k in 0..n {
            let body = if k + 1 < n {
                format!("    v1 = call @f{}(v0)\n    return v1\n", k + 1)
            } else {
                "    return v0\n".to_string()
            };
            t.push_str(&format!(
                "func @f{k}(i16) -> i16 function {{\nblock0(v0: i16):\n{body}}}\n\n"
            ));
        }
        t.push_str("func @main(ptr) program {\nblock0(v0: ptr):\n    v1 = field_addr v0, %main.r\n    v2 = load.i16 v1\n    v3 = call @f0(v2)\n    store v3, v1\n    return\n}\n\n");
        t.push_str("func @main$init(ptr) init {\nblock0(v0: ptr):\n    v1 = field_addr v0, %main.r\n    v2 = iconst.i16 0\n    store v2, v1\n    return\n}\n\n");
        t.push_str("program \"main\" data @main body @main init @main$init\n");
        plcc_ir::text::parse_module(&t).expect("the IR parses")
    }

    /// Calls may nest 128 deep (the task's call of the body counts): the C VMs'
    /// return stack holds no more.
    #[test]
    fn calls_nest_at_most_128_deep() {
        assert!(check_call_depth(&chain(127)).is_ok());
        let e = check_call_depth(&chain(128)).unwrap_err();
        assert_eq!(e[0].code, codes::E_MEMORY);
        assert!(e[0].message.contains("nest 129 deep"), "{}", e[0].message);
    }
}
