//! Byte layout of aggregates in the VM's data memory.
//!
//! Fields are laid out as `ir::layout` does (packed in the 16- and 32-bit modes,
//! aligned to at most 4 bytes in the aligned mode), with one difference: an FB or
//! PROGRAM instance ends with the *temporary area* of the functions that run on it.
//! Those functions address their SSA values relative to DPTR, which points at the
//! instance while they run (the CPDev compiler keeps `?IF?CTL` and friends in the
//! instance the same way), so every instance carries its own temporaries.

use plcc_ir::entities::AggId;
use plcc_ir::module::{AggDef, Module};
use plcc_ir::types::{MemType, Type};
use plcc_ir::vars::PathStep;

/// Size, alignment and member offsets of one aggregate.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AggLayout {
    /// Total size in bytes, temporary area included.
    pub size: u32,
    /// Where the temporary area starts (the end of the fields).
    pub fields_end: u32,
    /// Alignment in bytes.
    pub align: u32,
    /// Byte offset of each field (structs only).
    pub field_offsets: Vec<u32>,
    /// Distance between elements (arrays only).
    pub stride: u32,
}

/// The layout of every aggregate of a module.
#[derive(Clone, Debug)]
pub struct VmLayout {
    /// Bytes of a `ptr`.
    pub ptr_bytes: u32,
    /// The largest alignment of a scalar.
    pub max_align: u32,
    aggs: Vec<AggLayout>,
}

fn align_up(x: u64, a: u32) -> u64 {
    let a = a.max(1) as u64;
    x.div_ceil(a) * a
}

impl VmLayout {
    /// Lays out every aggregate; `temps[a]` is the size of the temporary area that
    /// instances of struct `a` carry.
    pub fn compute(module: &Module, ptr_bytes: u32, max_align: u32, temps: &[u32]) -> VmLayout {
        let mut l = VmLayout {
            ptr_bytes,
            max_align,
            aggs: vec![AggLayout::default(); module.aggs.len()],
        };
        let mut state = vec![0u8; module.aggs.len()];
        for i in 0..module.aggs.len() {
            l.visit(module, AggId::new(i), temps, &mut state);
        }
        l
    }

    /// Size in bytes of a scalar.
    pub fn scalar_size(&self, ty: Type) -> u32 {
        match ty {
            Type::I1 | Type::I8 => 1,
            Type::I16 => 2,
            Type::I32 | Type::F32 => 4,
            Type::I64 | Type::F64 => 8,
            Type::Ptr => self.ptr_bytes,
        }
    }

    fn scalar_align(&self, ty: Type) -> u32 {
        self.scalar_size(ty).min(self.max_align).max(1)
    }

    fn visit(&mut self, module: &Module, id: AggId, temps: &[u32], state: &mut [u8]) {
        match state[id.index()] {
            2 => return,
            // A struct containing itself is rejected by the verifier; lay it out empty
            // rather than loop.
            1 => return,
            _ => {}
        }
        state[id.index()] = 1;
        let mut member = |l: &mut VmLayout, t: MemType| -> (u32, u32) {
            match t {
                MemType::Scalar(s) => (l.scalar_size(s), l.scalar_align(s)),
                MemType::Agg(a) => {
                    l.visit(module, a, temps, state);
                    (l.aggs[a.index()].size, l.aggs[a.index()].align)
                }
            }
        };
        let result = match module.agg(id) {
            AggDef::Struct(s) => {
                let mut off: u64 = 0;
                let mut align = 1;
                let mut offsets = Vec::with_capacity(s.fields.len());
                for f in &s.fields {
                    let (size, a) = member(self, f.ty);
                    off = align_up(off, a);
                    offsets.push(off as u32);
                    off += size as u64;
                    align = align.max(a);
                }
                let fields_end = align_up(off, align);
                let extra = temps.get(id.index()).copied().unwrap_or(0) as u64;
                AggLayout {
                    size: align_up(fields_end + extra, align).min(u32::MAX as u64) as u32,
                    fields_end: fields_end as u32,
                    align,
                    field_offsets: offsets,
                    stride: 0,
                }
            }
            AggDef::Array(a) => {
                let (size, al) = member(self, a.elem);
                let stride = align_up(size as u64, al) as u32;
                let size = (stride as u64 * a.len as u64).min(u32::MAX as u64) as u32;
                AggLayout {
                    size,
                    fields_end: size,
                    align: al,
                    field_offsets: Vec::new(),
                    stride,
                }
            }
        };
        self.aggs[id.index()] = result;
        state[id.index()] = 2;
    }

    /// The layout of an aggregate.
    pub fn agg(&self, id: AggId) -> &AggLayout {
        &self.aggs[id.index()]
    }

    /// Size in bytes of a memory type.
    pub fn size_of(&self, t: MemType) -> u32 {
        match t {
            MemType::Scalar(s) => self.scalar_size(s),
            MemType::Agg(a) => self.aggs[a.index()].size,
        }
    }

    /// Alignment of a memory type.
    pub fn align_of(&self, t: MemType) -> u32 {
        match t {
            MemType::Scalar(s) => self.scalar_align(s),
            MemType::Agg(a) => self.aggs[a.index()].align,
        }
    }

    /// Byte offset of a field.
    pub fn field_offset(&self, agg: AggId, field: u32) -> u32 {
        self.aggs[agg.index()].field_offsets[field as usize]
    }

    /// Byte distance between consecutive elements of an array.
    pub fn stride(&self, agg: AggId) -> u32 {
        self.aggs[agg.index()].stride
    }

    /// Byte offset reached by following `steps` from the start of an object.
    pub fn offset_of(&self, steps: &[PathStep]) -> u64 {
        steps
            .iter()
            .map(|s| match *s {
                PathStep::Field(agg, f) => self.field_offset(agg, f) as u64,
                PathStep::Elem(agg, i) => self.stride(agg) as u64 * i as u64,
            })
            .sum()
    }
}
