//! Relocatable objects for a target triple, with their C header.

use crate::codegen::{self, CodegenSettings, DataLayout};
use crate::codes;
use crate::runtime::{data_symbol, DATA_SYMBOL, RT_SIZE, RT_SYMBOL};
use crate::translate::Addressing;
use cranelift_codegen::isa;
use cranelift_module::{default_libcall_names, DataDescription, Linkage, Module as _};
use cranelift_object::{ObjectBuilder, ObjectModule};
use plcc_ir::backend::{Artifact, Artifacts, Symbol};
use plcc_ir::diag::Diagnostic;
use plcc_ir::value::host_size;
use plcc_ir::{DataId, Module};
use std::str::FromStr;
use target_lexicon::{PointerWidth, Triple};

fn target_error(msg: String) -> Vec<Diagnostic> {
    vec![Diagnostic::error_nowhere(codes::E_UNSUPPORTED_TARGET, msg)]
}

/// Parses a triple and checks that Cranelift can generate code for it with plcc's
/// layout (64-bit pointers).
pub(crate) fn target_isa(
    triple: Option<&str>,
    settings: &CodegenSettings,
) -> Result<isa::OwnedTargetIsa, Vec<Diagnostic>> {
    let triple = match triple {
        None => Triple::host(),
        Some(t) => Triple::from_str(t)
            .map_err(|e| target_error(format!("`{t}` is not a target triple: {e}")))?,
    };
    if triple.pointer_width() != Ok(PointerWidth::U64) {
        return Err(target_error(format!(
            "the native backend generates code for 64-bit targets only, not `{triple}`"
        )));
    }
    let builder = isa::lookup(triple.clone()).map_err(|e| {
        target_error(format!(
            "Cranelift cannot generate code for `{triple}`: {e}"
        ))
    })?;
    builder
        .finish(codegen::flags(settings, true)?)
        .map_err(|e| target_error(format!("cannot configure Cranelift for `{triple}`: {e}")))
}

/// Compiles `module` into an object file and its C header.
pub(crate) fn compile(
    module: &Module,
    triple: Option<&str>,
    settings: &CodegenSettings,
) -> Result<Artifacts, Vec<Diagnostic>> {
    let isa = target_isa(triple, settings)?;
    let triple_name = isa.triple().to_string();
    let dl = DataLayout::compute(module)?;
    let emit_err = |what: &str, e: &dyn std::fmt::Display| {
        vec![Diagnostic::error_nowhere(
            codes::E_EMIT,
            format!("cannot write the object file: {what}: {e}"),
        )]
    };
    let builder = ObjectBuilder::new(isa.clone(), "plcc", default_libcall_names())
        .map_err(|e| emit_err("setup", &e))?;
    let mut cl = ObjectModule::new(builder);

    // One zero-initialised block for all data (the init functions fill it), and the
    // runtime context.
    let data_id = cl
        .declare_data(DATA_SYMBOL, Linkage::Export, true, false)
        .map_err(|e| emit_err(DATA_SYMBOL, &e))?;
    let mut desc = DataDescription::new();
    desc.define_zeroinit((dl.size as usize).max(1));
    desc.set_align(dl.align as u64);
    cl.define_data(data_id, &desc)
        .map_err(|e| emit_err(DATA_SYMBOL, &e))?;
    let rt_id = cl
        .declare_data(RT_SYMBOL, Linkage::Export, true, false)
        .map_err(|e| emit_err(RT_SYMBOL, &e))?;
    let mut desc = DataDescription::new();
    desc.define_zeroinit(RT_SIZE);
    desc.set_align(8);
    cl.define_data(rt_id, &desc)
        .map_err(|e| emit_err(RT_SYMBOL, &e))?;

    let addressing = Addressing::Symbols {
        data: data_id,
        rt: rt_id,
    };
    let compiled = codegen::compile_functions(
        &mut cl,
        module,
        &dl,
        addressing,
        Linkage::Export,
        settings,
        &isa,
    )?;

    let mut product = cl.finish();
    // A symbol for every data object, inside the data block.
    let block = product.object.symbol(product.data_symbol(data_id));
    let (block_value, block_section) = (block.value, block.section);
    for (i, d) in module.data.iter().enumerate() {
        product.object.add_symbol(object::write::Symbol {
            name: data_symbol(&d.name).into_bytes(),
            value: block_value + dl.offsets[i],
            size: dl.layout.size_of(d.ty) as u64,
            kind: object::SymbolKind::Data,
            scope: object::SymbolScope::Dynamic,
            weak: false,
            section: block_section,
            flags: object::SymbolFlags::None,
        });
    }
    let bytes = product.emit().map_err(|e| emit_err("emit", &e))?;
    let header = crate::header::generate(module, &dl, &triple_name);

    let mut symbols = Vec::new();
    for i in 0..module.data.len() {
        let id = DataId::new(i);
        for v in plcc_ir::vars::variables(module, id) {
            symbols.push(Symbol {
                address: dl.offsets[i] + dl.layout.offset_of(&v.steps),
                size: host_size(v.ty),
                elem: v.elem,
                path: v.path,
            });
        }
    }
    Ok(Artifacts {
        files: vec![
            Artifact {
                kind: "o".to_string(),
                bytes,
            },
            Artifact {
                kind: "h".to_string(),
                bytes: header.into_bytes(),
            },
        ],
        symbols,
        summary: Some(format!(
            "{triple_name}: {} functions, {} bytes of code, {} bytes of data \
             (symbol addresses are offsets in `{DATA_SYMBOL}`)",
            module.funcs.len(),
            compiled.code_size,
            dl.size
        )),
    })
}
