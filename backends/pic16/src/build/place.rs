//! Where everything goes in the chip's RAM: the runtime's block, the multiply and
//! divide workspace, the data objects (whole in one bank, or split between their
//! fields), and the functions' frames (overlaid through the call graph, beside the
//! data they use, in common RAM for hot functions).

use super::{CallOrder, Frames, RuntimeNeeds};
use crate::codes;
use crate::frame::{self, Ptr, Sym};
use crate::helpers::{self, Workspace};
use crate::ram::{self, PicLayout, RamMap};
use crate::runtime::{self, Rt};
use plcc_ir::diag::Diagnostic;
use plcc_ir::inst::InstData;
use plcc_ir::{FuncId, MemType, Module};
use rustc_hash::{FxHashMap, FxHashSet};

/// Where the runtime, the workspace, the data and the frames are.
pub(super) struct RamPlan {
    /// The runtime's block.
    pub rt: Rt,
    /// The multiply/divide workspace (empty if no code multiplies or divides).
    pub ws: Workspace,
    /// Where each data object is.
    pub data: ram::DataMap,
    /// The first byte of each function's frame.
    pub frame_base: Vec<u16>,
    /// Each function's frame as a range, if it has one.
    pub placed: Vec<Option<(u16, u16)>>,
    /// RAM bytes used, common RAM included.
    pub ram_used: u32,
}

fn ram_err(what: String) -> Vec<Diagnostic> {
    vec![Diagnostic::error_nowhere(codes::E_RAM, what)]
}

/// Places the runtime's block, the workspace, the data objects, then the frames.
pub(super) fn place(
    module: &Module,
    layout: &PicLayout,
    calls: &CallOrder,
    frames: &Frames,
    needs: &RuntimeNeeds,
) -> Result<RamPlan, Vec<Diagnostic>> {
    let mut map = RamMap::new();
    // clock (4), sampled clock (4), flags (1), interrupt context (3), ns clocks (16).
    let rt_size: u16 = if needs.uses_ns { 28 } else { 12 };
    let rt_at = map
        .find(rt_size, &[], Some(0))
        .ok_or_else(|| ram_err("no RAM for the runtime".into()))?;
    map.take(rt_at, rt_size);
    let rt = Rt {
        clk_ms: rt_at,
        now_ms: rt_at + 4,
        flags: rt_at + 8,
        isr_save: rt_at + 9,
        clk_ns: needs.uses_ns.then_some(rt_at + 12),
        now_ns: if needs.uses_ns { rt_at + 20 } else { rt_at },
        ticks: needs.uses_ms || needs.uses_ns,
    };
    let widest = needs.widest_muldiv;
    let ws = if widest > 0 {
        let size = helpers::workspace_bytes(widest);
        let at = map.find(size, &[], None).ok_or_else(|| {
            ram_err(format!(
                "no room for the {size} bytes of the multiply/divide workspace"
            ))
        })?;
        map.take(at, size);
        Workspace {
            a: at,
            b: at + widest,
            r: at + 2 * widest,
            cnt: at + 3 * widest,
        }
    } else {
        Workspace::default()
    };
    let data = place_data(module, layout, &calls.consensus, &calls.order, &mut map)?;
    let (frame_base, placed, frame_bytes) = place_frames(module, calls, frames, &data, &mut map)?;
    let ram_used = map.used_bytes() + frame_bytes + 16;
    Ok(RamPlan {
        rt,
        ws,
        data,
        frame_base,
        placed,
        ram_used,
    })
}

/// Places every frame away from the frames of the functions that can be active
/// while it runs (its ancestors in the call graph). Returns each frame's base, its
/// range, and the bytes frames take outside common RAM.
#[allow(clippy::type_complexity)]
fn place_frames(
    module: &Module,
    calls: &CallOrder,
    frames: &Frames,
    data: &ram::DataMap,
    map: &mut RamMap,
) -> Result<(Vec<u16>, Vec<Option<(u16, u16)>>, u32), Vec<Diagnostic>> {
    let nf = module.funcs.len();
    let (order, callees) = (&calls.order, &calls.callees);
    // Ancestors of every function (all functions that can be active while it runs).
    let mut ancestors: Vec<FxHashSet<FuncId>> = vec![FxHashSet::default(); nf];
    for &f in order {
        for &g in &callees[f.index()] {
            let mut add: FxHashSet<FuncId> = ancestors[f.index()].clone();
            add.insert(f);
            ancestors[g.index()].extend(add);
        }
    }
    let mut frame_base = vec![0u16; nf];
    let mut placed: Vec<Option<(u16, u16)>> = vec![None; nf];
    let mut frame_bytes: FxHashSet<u16> = FxHashSet::default();
    for &f in order {
        let size = frames.info[f.index()].size;
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
        for (d, n) in &frames.touches[f.index()] {
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
            for &g in order {
                let own = frames.info[g.index()].size as u32;
                let up = (0..nf)
                    .filter(|&c| callees[c].contains(&g))
                    .map(|c| chain[c])
                    .max()
                    .unwrap_or(0);
                chain[g.index()] = up + own;
            }
            let chain = chain[f.index()];
            return Err(ram_err(format!(
                "`{fname}` needs {size} bytes for its temporaries and locals, but no bank has that much free beside the variables ({} bytes) and the frames of the functions that call it (the deepest chain down to it needs {} bytes); the chip has {} bytes",
                map.used_bytes(),
                chain,
                ram::RAM_BYTES
            )));
        };
        frame_base[f.index()] = at;
        placed[f.index()] = Some((at, at + size));
        frame_bytes.extend((at..at + size).filter(|a| !(0x70..0x80).contains(a)));
    }
    Ok((frame_base, placed, frame_bytes.len() as u32))
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
