//! Compiling a whole IR module into a Cranelift module (the JIT's or an object's):
//! data layout, declarations, and the per-function translate-and-compile loop.

use crate::codes;
use crate::runtime::{func_symbol, MATH};
use crate::translate::{math_signature, signature, Addressing, Env, Translator};
use cranelift_codegen::ir::Signature;
use cranelift_codegen::isa::{self, TargetIsa};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_codegen::{print_errors, CodegenError, Context};
use cranelift_module::{FuncId as ClFuncId, Linkage, Module as ClModule, ModuleError};
use plcc_ir::diag::Diagnostic;
use plcc_ir::layout::{Layout, LayoutRules};
use plcc_ir::{InstData, Module};

/// Data objects beyond this total size are refused rather than allocated.
pub(crate) const MAX_DATA_BYTES: u64 = 1 << 30;

/// Where every data object lives in the one data block.
#[derive(Clone)]
pub(crate) struct DataLayout {
    pub layout: Layout,
    /// Offset of each data object.
    pub offsets: Vec<u64>,
    /// Total size in bytes.
    pub size: u64,
    /// Alignment of the block.
    pub align: u32,
}

impl DataLayout {
    /// Lays the data objects out one after the other, each at its alignment.
    pub fn compute(module: &Module) -> Result<DataLayout, Vec<Diagnostic>> {
        let layout = Layout::compute(module, LayoutRules::HOST);
        if let Some(name) = overflowing_agg(module, &layout) {
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_DATA_TOO_LARGE,
                format!(
                    "the type `{name}` takes 4 GiB or more, over the native backend's \
                     limit of {MAX_DATA_BYTES} bytes of data"
                ),
            )]);
        }
        let mut offsets = Vec::with_capacity(module.data.len());
        let mut off: u64 = 0;
        let mut align: u32 = 8;
        for d in &module.data {
            let a = layout.align_of(d.ty).max(1) as u64;
            off = off.div_ceil(a) * a;
            offsets.push(off);
            off += layout.size_of(d.ty) as u64;
            align = align.max(a as u32);
        }
        if off > MAX_DATA_BYTES {
            return Err(vec![Diagnostic::error_nowhere(
                codes::E_DATA_TOO_LARGE,
                format!(
                    "the program's data takes {off} bytes, more than the native backend's \
                     limit of {MAX_DATA_BYTES}"
                ),
            )]);
        }
        Ok(DataLayout {
            layout,
            offsets,
            size: off,
            align,
        })
    }
}

/// An aggregate too large for `Layout`'s 32-bit sizes, whose offsets are then wrong.
fn overflowing_agg(module: &Module, layout: &Layout) -> Option<String> {
    for (i, agg) in module.aggs.iter().enumerate() {
        let id = plcc_ir::AggId::new(i);
        let al = layout.agg(id);
        let too_big = match agg {
            plcc_ir::AggDef::Array(a) => al.stride as u64 * a.len as u64 >= u32::MAX as u64,
            plcc_ir::AggDef::Struct(s) => {
                let mut end = 0u64;
                let mut bad = false;
                for (f, field) in s.fields.iter().enumerate() {
                    let off = al.field_offsets[f] as u64;
                    bad |= off < end;
                    end = off + layout.size_of(field.ty) as u64;
                }
                bad || end > al.size as u64
            }
        };
        if too_big {
            return Some(agg.name().to_string());
        }
    }
    None
}

/// Backend settings that shape code generation.
#[derive(Clone, Debug)]
pub(crate) struct CodegenSettings {
    /// Cranelift's `opt_level`: `none`, `speed` or `speed_and_size`.
    pub opt_level: String,
    /// Cranelift's `regalloc_algorithm`: `backtracking` or `single_pass`.
    pub regalloc: String,
    /// Worker threads for compiling functions (0: choose).
    pub threads: usize,
    /// Add the watchdog checks ([`plcc_ir::passes::watchdog`]) to each function as
    /// it is translated, on the worker threads, rather than to the module before.
    pub watchdog: bool,
    /// The quick tier: the translator's own optimisations (ranges, fills, if
    /// conversion, loop rotation) are left out.
    pub quick: bool,
}

impl Default for CodegenSettings {
    fn default() -> Self {
        CodegenSettings {
            opt_level: "speed".to_string(),
            regalloc: "backtracking".to_string(),
            threads: 0,
            watchdog: false,
            quick: false,
        }
    }
}

/// Cranelift flags for the JIT (`pic = false`) or for objects (`pic = true`).
pub(crate) fn flags(s: &CodegenSettings, pic: bool) -> Result<settings::Flags, Vec<Diagnostic>> {
    let mut b = settings::builder();
    let mut set = |k: &str, v: &str| {
        b.set(k, v).map_err(|e| {
            vec![Diagnostic::error_nowhere(
                codes::E_BAD_SETTING,
                format!("cannot set Cranelift's `{k}` to `{v}`: {e}"),
            )]
        })
    };
    set("opt_level", &s.opt_level)?;
    set("regalloc_algorithm", &s.regalloc)?;
    set("is_pic", if pic { "true" } else { "false" })?;
    // Cranelift's own verifier runs only when a function fails (for the message) and
    // in debug builds: it would cost a tenth of the compile time.
    set(
        "enable_verifier",
        if cfg!(debug_assertions) {
            "true"
        } else {
            "false"
        },
    )?;
    if !pic {
        // Nothing unwinds through JIT code (helpers never panic).
        set("unwind_info", "false")?;
    }
    Ok(settings::Flags::new(b))
}

/// The host's ISA for the JIT.
pub(crate) fn host_isa(s: &CodegenSettings) -> Result<isa::OwnedTargetIsa, Vec<Diagnostic>> {
    let builder = cranelift_native::builder().map_err(|e| {
        vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED_TARGET,
            format!("this host cannot run JIT code: {e}"),
        )]
    })?;
    builder.finish(flags(s, false)?).map_err(|e| {
        vec![Diagnostic::error_nowhere(
            codes::E_UNSUPPORTED_TARGET,
            format!("cannot configure Cranelift for this host: {e}"),
        )]
    })
}

/// Which [`MATH`] functions the module uses.
fn used_math(module: &Module) -> [bool; 22] {
    let mut used = [false; 22];
    for f in &module.funcs {
        for (_, inst) in f.inst_iter() {
            let (idx, arg) = match f.inst(inst) {
                InstData::Unary { op, arg } => (crate::runtime::math_unary_index(*op), *arg),
                InstData::Binary { op, args } => (crate::runtime::math_binary_index(*op), args[0]),
                _ => continue,
            };
            if let Some(i) = idx {
                let i = if f.value_type(arg) == plcc_ir::Type::F64 {
                    i + 1
                } else {
                    i
                };
                used[i] = true;
            }
        }
    }
    used
}

/// What compiling a module gives.
pub(crate) struct Compiled {
    /// The Cranelift id of every IR function.
    pub funcs: Vec<ClFuncId>,
    /// Bytes of machine code.
    pub code_size: u64,
}

fn module_error(code: &'static str, what: &str, e: ModuleError) -> Vec<Diagnostic> {
    vec![Diagnostic::error_nowhere(code, format!("{what}: {e}"))]
}

/// Declares and defines every function of `module` in `cl`.
pub(crate) fn compile_functions<M: ClModule>(
    cl: &mut M,
    module: &Module,
    data: &DataLayout,
    addressing: Addressing,
    linkage: Linkage,
    settings: &CodegenSettings,
    isa: &isa::OwnedTargetIsa,
) -> Result<Compiled, Vec<Diagnostic>> {
    // Backends get verified modules, but this one checks again: Cranelift may panic
    // on ill-typed input (release builds do not run its verifier), and a library
    // caller's bug should be a diagnostic. It costs about 1% of a build.
    verify(module)?;
    plcc_ir::backend::reject_inline_c(module, "the host target", codes::E_UNSUPPORTED_TARGET)?;
    let call_conv = isa.default_call_conv();
    let frontend = isa.frontend_config();

    // Math helpers: imported by their C names, declared only when used so that objects
    // reference nothing they do not need.
    let used = used_math(module);
    let mut math = Vec::with_capacity(MATH.len());
    for (i, m) in MATH.iter().enumerate() {
        let sig = math_signature(m, call_conv);
        let id = if used[i] {
            cl.declare_function(m.name, Linkage::Import, &sig)
                .map_err(|e| module_error(codes::E_EMIT, "cannot declare a helper", e))?
        } else {
            // Never referenced; any id will do.
            ClFuncId::from_u32(0)
        };
        math.push(id);
    }

    let mut sigs: Vec<Signature> = Vec::with_capacity(module.funcs.len());
    let mut funcs = Vec::with_capacity(module.funcs.len());
    for f in &module.funcs {
        let sig = signature(f, call_conv);
        let id = cl
            .declare_function(&func_symbol(&f.name), linkage, &sig)
            .map_err(|e| {
                module_error(
                    codes::E_EMIT,
                    &format!("cannot declare function `{}`", f.name),
                    e,
                )
            })?;
        sigs.push(sig);
        funcs.push(id);
    }

    let env = Env {
        module,
        layout: &data.layout,
        data_offsets: &data.offsets,
        addressing,
        funcs: &funcs,
        sigs: &sigs,
        math: &math,
        call_conv,
        watchdog: settings.watchdog,
        quick: settings.quick,
    };

    let threads = match settings.threads {
        0 => std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
            .min(4),
        n => n,
    };
    let code_size = if threads > 1 && module.funcs.len() >= 64 {
        compile_parallel(cl, &env, frontend, threads, isa)?
    } else {
        compile_serial(cl, &env, frontend)?
    };
    Ok(Compiled { funcs, code_size })
}

fn compile_serial<M: ClModule>(
    cl: &mut M,
    env: &Env,
    frontend: isa::TargetFrontendConfig,
) -> Result<u64, Vec<Diagnostic>> {
    let mut ctx = Context::new();
    let mut tr = Translator::default();
    let mut code_size = 0u64;
    for (i, f) in env.module.funcs.iter().enumerate() {
        ctx.clear();
        tr.translate(env, plcc_ir::FuncId::new(i), &mut ctx.func, frontend)
            .map_err(|m| malformed(&f.name, m))?;
        if let Err(e) = cl.define_function(env.funcs[i], &mut ctx) {
            return Err(define_error(cl.isa(), &f.name, &mut ctx, e));
        }
        if let Some(c) = ctx.compiled_code() {
            code_size += c.code_info().total_size as u64;
        }
    }
    Ok(code_size)
}

/// One compiled function, ready for `define_function_bytes`.
struct Done {
    index: usize,
    align: u64,
    bytes: Vec<u8>,
    relocs: Vec<cranelift_module::ModuleReloc>,
}

/// Translates and compiles on worker threads (each with its own contexts); the
/// calling thread defines the results in the module as they come.
fn compile_parallel<M: ClModule>(
    cl: &mut M,
    env: &Env,
    frontend: isa::TargetFrontendConfig,
    threads: usize,
    isa: &isa::OwnedTargetIsa,
) -> Result<u64, Vec<Diagnostic>> {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let n = env.module.funcs.len();
    // Largest functions first, so that no big one is left to run alone at the end.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(env.module.funcs[i].live_inst_count()));
    let order = &order;
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let min_align = isa.function_alignment().minimum as u64;
    let sym_align = isa.symbol_alignment();
    let (tx, rx) = std::sync::mpsc::channel::<Result<Done, Vec<Diagnostic>>>();
    std::thread::scope(|s| -> Result<u64, Vec<Diagnostic>> {
        for _ in 0..threads {
            let tx = tx.clone();
            let (next, stop, isa) = (&next, &stop, &**isa);
            s.spawn(move || {
                let mut ctx = Context::new();
                let mut tr = Translator::default();
                loop {
                    if stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= n {
                        break;
                    }
                    let i = order[k];
                    let r = compile_one(env, isa, frontend, &mut ctx, &mut tr, i);
                    let failed = r.is_err();
                    if tx.send(r).is_err() || failed {
                        break;
                    }
                }
            });
        }
        drop(tx);
        // Functions are defined in module order, whatever order they finish in, so
        // that objects come out the same every time.
        let mut code_size = 0u64;
        let mut result = Ok(());
        let mut pending: Vec<Option<Done>> = (0..n).map(|_| None).collect();
        let mut cursor = 0;
        for r in rx {
            match r {
                Ok(d) if result.is_ok() => {
                    let i = d.index;
                    pending[i] = Some(d);
                    while let Some(d) = pending.get_mut(cursor).and_then(Option::take) {
                        cursor += 1;
                        code_size += d.bytes.len() as u64;
                        let align = d.align.max(min_align).max(sym_align);
                        if let Err(e) =
                            cl.define_function_bytes(env.funcs[d.index], align, &d.bytes, &d.relocs)
                        {
                            stop.store(true, Ordering::Relaxed);
                            result = Err(module_error(
                                codes::E_EMIT,
                                &format!(
                                    "cannot place the code of `{}`",
                                    env.module.funcs[d.index].name
                                ),
                                e,
                            ));
                            break;
                        }
                    }
                }
                Ok(_) => {}
                Err(e) => {
                    stop.store(true, Ordering::Relaxed);
                    if result.is_ok() {
                        result = Err(e);
                    }
                }
            }
        }
        result.map(|()| code_size)
    })
}

fn compile_one(
    env: &Env,
    isa: &dyn TargetIsa,
    frontend: isa::TargetFrontendConfig,
    ctx: &mut Context,
    tr: &mut Translator,
    i: usize,
) -> Result<Done, Vec<Diagnostic>> {
    let f = &env.module.funcs[i];
    ctx.clear();
    tr.translate(env, plcc_ir::FuncId::new(i), &mut ctx.func, frontend)
        .map_err(|m| malformed(&f.name, m))?;
    let mut cp = Default::default();
    let (align, bytes) = match ctx.compile(isa, &mut cp) {
        Ok(c) => (c.buffer.alignment as u64, c.code_buffer().to_vec()),
        Err(e) => {
            let inner = e.inner;
            return Err(codegen_error(isa, &f.name, ctx, inner));
        }
    };
    let code = ctx.compiled_code().expect("just compiled");
    let relocs = code
        .buffer
        .relocs()
        .iter()
        .map(|r| cranelift_module::ModuleReloc::from_mach_reloc(r, &ctx.func, env.funcs[i]))
        .collect();
    Ok(Done {
        index: i,
        align,
        bytes,
        relocs,
    })
}

fn malformed(name: &str, m: String) -> Vec<Diagnostic> {
    vec![Diagnostic::error_nowhere(
        codes::E_MALFORMED_IR,
        format!("the native backend cannot translate function `{name}`: {m}"),
    )]
}

fn define_error(
    isa: &dyn TargetIsa,
    name: &str,
    ctx: &mut Context,
    e: ModuleError,
) -> Vec<Diagnostic> {
    match e {
        ModuleError::Compilation(c) => codegen_error(isa, name, ctx, c),
        e => module_error(
            codes::E_EMIT,
            &format!("cannot place the code of `{name}`"),
            e,
        ),
    }
}

fn codegen_error(
    isa: &dyn TargetIsa,
    name: &str,
    ctx: &mut Context,
    e: CodegenError,
) -> Vec<Diagnostic> {
    // Re-run the verifier for a readable account of what is wrong.
    let detail = match ctx.verify(isa) {
        Err(errors) => print_errors::pretty_verifier_error(&ctx.func, None, errors),
        Ok(()) => print_errors::pretty_error(&ctx.func, e),
    };
    vec![Diagnostic::error_nowhere(
        codes::E_CODEGEN,
        format!("Cranelift cannot compile function `{name}`"),
    )
    .with_note(detail)]
}

/// The Cranelift IR of every function, as text (for debugging and inspection).
pub(crate) fn clif_text(module: &Module) -> Result<String, Vec<Diagnostic>> {
    let settings = CodegenSettings::default();
    let isa = host_isa(&settings)?;
    let data = DataLayout::compute(module)?;
    let call_conv = isa.default_call_conv();
    let sigs: Vec<Signature> = module
        .funcs
        .iter()
        .map(|f| signature(f, call_conv))
        .collect();
    let funcs: Vec<ClFuncId> = (0..module.funcs.len() as u32)
        .map(ClFuncId::from_u32)
        .collect();
    let math: Vec<ClFuncId> = (0..MATH.len() as u32).map(ClFuncId::from_u32).collect();
    let env = Env {
        module,
        layout: &data.layout,
        data_offsets: &data.offsets,
        addressing: Addressing::Absolute {
            data: 0x1000,
            rt: 0x100,
        },
        funcs: &funcs,
        sigs: &sigs,
        math: &math,
        call_conv,
        watchdog: false,
        quick: false,
    };
    let mut tr = Translator::default();
    let mut out = String::new();
    for (i, f) in module.funcs.iter().enumerate() {
        let mut func = cranelift_codegen::ir::Function::new();
        tr.translate(
            &env,
            plcc_ir::FuncId::new(i),
            &mut func,
            isa.frontend_config(),
        )
        .map_err(|m| malformed(&f.name, m))?;
        out.push_str(&format!("; {}\n{}\n", f.name, func.display()));
    }
    Ok(out)
}

/// Runs the IR verifier; its findings become [`codes::E_MALFORMED_IR`] diagnostics.
pub(crate) fn verify(module: &Module) -> Result<(), Vec<Diagnostic>> {
    plcc_ir::verify::verify_module(module).map_err(|errs| {
        errs.iter()
            .map(|e| {
                Diagnostic::error_nowhere(
                    codes::E_MALFORMED_IR,
                    format!("the native backend was given malformed IR: {e}"),
                )
            })
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cranelift_codegen::ir::{types, AbiParam, InstBuilder};
    use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
    use cranelift_object::{ObjectBuilder, ObjectModule};

    /// The host's ISA with Cranelift's verifier on, so that a bad function fails
    /// with an error rather than a panic.
    fn verifying_isa() -> isa::OwnedTargetIsa {
        let mut flags = settings::builder();
        flags.set("enable_verifier", "true").unwrap();
        cranelift_native::builder()
            .unwrap()
            .finish(settings::Flags::new(flags))
            .unwrap()
    }

    /// A function of one block that returns; `promise_i32` makes its signature
    /// promise an i32 it never returns.
    fn function(isa: &dyn TargetIsa, ctx: &mut Context, promise_i32: bool) {
        if promise_i32 {
            ctx.func.signature.returns.push(AbiParam::new(types::I32));
        }
        let mut fctx = FunctionBuilderContext::new();
        let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
        let block = b.create_block();
        b.switch_to_block(block);
        b.seal_block(block);
        b.ins().return_(&[]);
        b.finalize(isa.frontend_config());
    }

    #[test]
    fn a_function_cranelift_refuses_is_e8004_with_its_account() {
        let isa = verifying_isa();
        let mut ctx = Context::new();
        function(&*isa, &mut ctx, true);
        let e = ctx
            .compile(&*isa, &mut Default::default())
            .expect_err("the function returns too few values")
            .inner;
        let d = codegen_error(&*isa, "bad", &mut ctx, e);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, "E8004");
        assert_eq!(d[0].message, "Cranelift cannot compile function `bad`");
        assert!(d[0].notes[0].contains("return"), "{:?}", d[0].notes);
    }

    #[test]
    fn code_that_cannot_be_placed_is_e8005() {
        let isa = verifying_isa();
        let mut ctx = Context::new();
        function(&*isa, &mut ctx, false);
        let builder =
            ObjectBuilder::new(isa, "t", cranelift_module::default_libcall_names()).unwrap();
        let mut obj = ObjectModule::new(builder);
        let id = obj
            .declare_function("f", Linkage::Export, &ctx.func.signature)
            .unwrap();
        obj.define_function(id, &mut ctx).unwrap();
        // A second body for the same symbol.
        let e = obj
            .define_function(id, &mut ctx)
            .expect_err("defined twice");
        let isa = obj.isa();
        let d = define_error(isa, "f", &mut ctx, e);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, "E8005");
        assert!(
            d[0].message.starts_with("cannot place the code of `f`: "),
            "{}",
            d[0].message
        );
    }
}
