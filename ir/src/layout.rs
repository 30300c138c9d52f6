//! Byte layout of aggregates for byte-addressed targets.
//!
//! The IR leaves offsets to backends. Hosts (the JIT, the interpreter) and the CPDev VM
//! use this computation with their own rules; a target with other needs (bit-packed
//! BOOLs on the PIC16) computes its own.

use crate::entities::AggId;
use crate::module::{AggDef, Module};
use crate::types::{MemType, Type};
use crate::vars::PathStep;

/// How scalars are sized and aligned.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct LayoutRules {
    /// Bytes of a `ptr`.
    pub ptr_bytes: u32,
    /// Align every scalar to its size, up to this many bytes (1 packs everything).
    pub max_align: u32,
}

impl LayoutRules {
    /// Natural alignment with 8-byte pointers: what the JIT and the interpreter use.
    pub const HOST: LayoutRules = LayoutRules {
        ptr_bytes: 8,
        max_align: 8,
    };

    /// Size in bytes of a scalar (a BOOL takes a byte).
    pub fn scalar_size(&self, ty: Type) -> u32 {
        match ty {
            Type::I1 | Type::I8 => 1,
            Type::I16 => 2,
            Type::I32 | Type::F32 => 4,
            Type::I64 | Type::F64 => 8,
            Type::Ptr => self.ptr_bytes,
        }
    }

    /// Alignment of a scalar.
    pub fn scalar_align(&self, ty: Type) -> u32 {
        self.scalar_size(ty).min(self.max_align).max(1)
    }
}

/// Size, alignment and member offsets of one aggregate.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AggLayout {
    /// Total size in bytes (a multiple of `align`), the tail included.
    pub size: u32,
    /// Where the members end: a struct's tail (see [`Layout::compute_with_tails`])
    /// starts here.
    pub fields_end: u32,
    /// Alignment in bytes.
    pub align: u32,
    /// Byte offset of each field (structs only).
    pub field_offsets: Vec<u32>,
    /// Distance between elements (arrays only).
    pub stride: u32,
}

/// The layout of every aggregate of a module under some rules.
#[derive(Clone, Debug)]
pub struct Layout {
    /// The rules it was computed with.
    pub rules: LayoutRules,
    aggs: Vec<AggLayout>,
}

fn align_up(x: u64, a: u32) -> u64 {
    let a = a.max(1) as u64;
    x.div_ceil(a) * a
}

impl Layout {
    /// Lays out every aggregate of `module`. Aggregates may refer to each other in any
    /// order; a cycle (a struct containing itself) is a front-end bug and panics.
    pub fn compute(module: &Module, rules: LayoutRules) -> Layout {
        Layout::compute_with_tails(module, rules, &[])
    }

    /// Like [`Layout::compute`], with `tails[a]` more bytes at the end of every
    /// instance of struct `a`, after its members (the CPDev VM keeps the temporaries
    /// of the code that runs on an instance there).
    pub fn compute_with_tails(module: &Module, rules: LayoutRules, tails: &[u32]) -> Layout {
        let mut layout = Layout {
            rules,
            aggs: vec![AggLayout::default(); module.aggs.len()],
        };
        let mut state = vec![0u8; module.aggs.len()]; // 0 todo, 1 in progress, 2 done
        for i in 0..module.aggs.len() {
            layout.visit(module, AggId::new(i), tails, &mut state);
        }
        layout
    }

    fn visit(&mut self, module: &Module, id: AggId, tails: &[u32], state: &mut [u8]) {
        match state[id.index()] {
            2 => return,
            1 => panic!("aggregate {} contains itself", module.agg(id).name()),
            _ => {}
        }
        state[id.index()] = 1;
        let member = |l: &mut Layout, t: MemType, state: &mut [u8]| -> (u32, u32) {
            match t {
                MemType::Scalar(s) => (l.rules.scalar_size(s), l.rules.scalar_align(s)),
                MemType::Agg(a) => {
                    l.visit(module, a, tails, state);
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
                    let (size, a) = member(self, f.ty, state);
                    off = align_up(off, a);
                    offsets.push(off as u32);
                    off += size as u64;
                    align = align.max(a);
                }
                let fields_end = align_up(off, align);
                let tail = tails.get(id.index()).copied().unwrap_or(0) as u64;
                AggLayout {
                    size: align_up(fields_end + tail, align).min(u32::MAX as u64) as u32,
                    fields_end: fields_end as u32,
                    align,
                    field_offsets: offsets,
                    stride: 0,
                }
            }
            AggDef::Array(a) => {
                let (size, al) = member(self, a.elem, state);
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

    /// Size in bytes of a scalar under these rules.
    pub fn scalar_size(&self, ty: Type) -> u32 {
        self.rules.scalar_size(ty)
    }

    /// Size in bytes of a memory type.
    pub fn size_of(&self, t: MemType) -> u32 {
        match t {
            MemType::Scalar(s) => self.rules.scalar_size(s),
            MemType::Agg(a) => self.aggs[a.index()].size,
        }
    }

    /// Alignment of a memory type.
    pub fn align_of(&self, t: MemType) -> u32 {
        match t {
            MemType::Scalar(s) => self.rules.scalar_align(s),
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
