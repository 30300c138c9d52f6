//! Data memory: the layout of aggregates with BOOLs packed eight to a byte, and the
//! map of the chip's general-purpose RAM that objects and frames are placed in.

use plcc_ir::module::{AggDef, Module};
use plcc_ir::vars::PathStep;
use plcc_ir::{AggId, MemType, Type};

/// Where a member sits inside its aggregate: a byte offset, and for a BOOL the bit.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Place {
    /// Byte offset from the start of the aggregate.
    pub offset: u16,
    /// Bit number (0–7) for an `i1`; 0 otherwise.
    pub bit: u8,
}

/// Size and member places of one aggregate.
#[derive(Clone, Debug, Default)]
pub struct AggInfo {
    /// Size in bytes.
    pub size: u32,
    /// Struct fields' places.
    pub fields: Vec<Place>,
    /// Bytes between array elements.
    pub stride: u32,
}

/// The PIC16 layout of every aggregate: no alignment; BOOL fields of a struct share
/// bytes, eight to a byte in declaration order (as PLC-UD does); BOOL array elements
/// take a byte each (bit 0), so a computed index needs no bit arithmetic.
#[derive(Clone, Debug)]
pub struct PicLayout {
    aggs: Vec<AggInfo>,
}

/// Bytes of a scalar in RAM (`i1` as a struct field takes a bit; elsewhere a byte).
pub fn scalar_bytes(t: Type) -> u32 {
    match t {
        Type::I1 | Type::I8 => 1,
        Type::I16 | Type::Ptr => 2,
        Type::I32 | Type::F32 => 4,
        Type::I64 | Type::F64 => 8,
    }
}

impl PicLayout {
    /// Lays out every aggregate of `module`.
    pub fn compute(module: &Module) -> PicLayout {
        let mut l = PicLayout {
            aggs: vec![AggInfo::default(); module.aggs.len()],
        };
        let mut done = vec![false; module.aggs.len()];
        for i in 0..module.aggs.len() {
            l.visit(module, AggId::new(i), &mut done);
        }
        l
    }

    fn visit(&mut self, module: &Module, id: AggId, done: &mut [bool]) {
        if done[id.index()] {
            return;
        }
        done[id.index()] = true; // the verifier rules out cycles
        let info = match module.agg(id) {
            AggDef::Struct(s) => {
                let mut off = 0u32;
                let mut bits: Option<(u32, u8)> = None; // byte being filled, next bit
                let mut fields = Vec::with_capacity(s.fields.len());
                for f in &s.fields {
                    match f.ty {
                        MemType::Scalar(Type::I1) => {
                            let (byte, bit) = match bits {
                                Some((b, n)) if n < 8 => (b, n),
                                _ => {
                                    off += 1;
                                    (off - 1, 0)
                                }
                            };
                            bits = Some((byte, bit + 1));
                            fields.push(Place {
                                offset: byte as u16,
                                bit,
                            });
                        }
                        t => {
                            fields.push(Place {
                                offset: off.min(u16::MAX as u32) as u16,
                                bit: 0,
                            });
                            off = off.saturating_add(self.size_of(module, t, done));
                        }
                    }
                }
                AggInfo {
                    size: off,
                    fields,
                    stride: 0,
                }
            }
            AggDef::Array(a) => {
                let stride = self.size_of(module, a.elem, done);
                AggInfo {
                    size: stride.saturating_mul(a.len),
                    fields: Vec::new(),
                    stride,
                }
            }
        };
        self.aggs[id.index()] = info;
    }

    fn size_of(&mut self, module: &Module, t: MemType, done: &mut [bool]) -> u32 {
        match t {
            MemType::Scalar(s) => scalar_bytes(s),
            MemType::Agg(a) => {
                self.visit(module, a, done);
                self.aggs[a.index()].size
            }
        }
    }

    /// Size in bytes of a memory type.
    pub fn size(&self, t: MemType) -> u32 {
        match t {
            MemType::Scalar(s) => scalar_bytes(s),
            MemType::Agg(a) => self.aggs[a.index()].size,
        }
    }

    /// An aggregate's layout.
    pub fn agg(&self, a: AggId) -> &AggInfo {
        &self.aggs[a.index()]
    }

    /// The place reached by following `steps` from the start of an object.
    pub fn place_of(&self, steps: &[PathStep]) -> Place {
        let mut p = Place::default();
        for s in steps {
            match *s {
                PathStep::Field(agg, f) => {
                    let fp = self.aggs[agg.index()].fields[f as usize];
                    p.offset += fp.offset;
                    p.bit = fp.bit;
                }
                PathStep::Elem(agg, i) => {
                    p.offset += (self.aggs[agg.index()].stride * i) as u16;
                }
            }
        }
        p
    }
}

/// The general-purpose RAM ranges of the PIC16F876A, bank by bank, without the 16
/// common bytes (0x70–0x7F), which the runtime and the hottest values use.
pub const BANK_RANGES: [(u16, u16); 4] =
    [(0x20, 0x70), (0xA0, 0xF0), (0x110, 0x170), (0x190, 0x1F0)];

/// The common RAM, reachable from every bank.
pub const COMMON: (u16, u16) = (0x70, 0x80);

/// Total general-purpose RAM of the chip in bytes.
pub const RAM_BYTES: u32 = 368;

/// A first-fit allocator over the banked RAM: every block lies inside one bank, so
/// an object can be walked with FSR and every multi-byte value needs one bank select.
#[derive(Clone, Debug)]
pub struct RamMap {
    /// Used byte ranges per bank, sorted.
    used: [Vec<(u16, u16)>; 4],
}

impl Default for RamMap {
    fn default() -> Self {
        RamMap::new()
    }
}

impl RamMap {
    /// An empty map.
    pub fn new() -> RamMap {
        RamMap {
            used: Default::default(),
        }
    }

    /// Finds room for `size` bytes avoiding `avoid` (extra ranges that must not be
    /// overlapped, e.g. frames of functions on the same call path), preferring `bank`.
    pub fn find(&self, size: u16, avoid: &[(u16, u16)], prefer: Option<u8>) -> Option<u16> {
        let order: Vec<usize> = match prefer {
            Some(b) => std::iter::once(b as usize)
                .chain((0..4).filter(|&x| x != b as usize))
                .collect(),
            None => (0..4).collect(),
        };
        for b in order {
            let (lo, hi) = BANK_RANGES[b];
            let mut busy: Vec<(u16, u16)> = self.used[b].clone();
            busy.extend(avoid.iter().copied().filter(|&(s, e)| s < hi && e > lo));
            busy.sort();
            let mut at = lo;
            for (s, e) in busy {
                if s >= at + size {
                    break;
                }
                at = at.max(e);
            }
            if at + size <= hi {
                return Some(at);
            }
        }
        None
    }

    /// Marks `[at, at+size)` used.
    pub fn take(&mut self, at: u16, size: u16) {
        if size == 0 {
            return;
        }
        let b = BANK_RANGES
            .iter()
            .position(|&(lo, hi)| at >= lo && at < hi)
            .expect("address inside a bank");
        self.used[b].push((at, at + size));
        self.used[b].sort();
    }

    /// Bytes used so far.
    pub fn used_bytes(&self) -> u32 {
        self.used
            .iter()
            .flatten()
            .map(|&(s, e)| (e - s) as u32)
            .sum()
    }

    /// The largest block that could still be found (for error messages).
    pub fn largest_free(&self) -> u16 {
        (0..4)
            .map(|b| {
                let (lo, hi) = BANK_RANGES[b];
                let mut at = lo;
                let mut best = 0;
                for &(s, e) in &self.used[b] {
                    best = best.max(s.saturating_sub(at));
                    at = at.max(e);
                }
                best.max(hi.saturating_sub(at))
            })
            .max()
            .unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_stay_inside_a_bank() {
        let mut m = RamMap::new();
        // Banks 0 and 1 have 80 bytes besides common RAM, banks 2 and 3 have 96.
        let a = m.find(70, &[], None).unwrap();
        m.take(a, 70);
        assert_eq!(a, 0x20);
        let b = m.find(20, &[], None).unwrap();
        assert_eq!(b, 0xA0, "10 bytes are left in bank 0, not 20");
        m.take(b, 20);
        let c = m.find(6, &[], Some(0)).unwrap();
        assert_eq!(c, 0x20 + 70);
        assert_eq!(m.find(90, &[], None), Some(0x110));
        assert_eq!(m.find(97, &[], None), None);
        // Bank 2 blocked: the first other bank with room.
        assert_eq!(m.find(4, &[(0x110, 0x16E)], Some(2)), Some(0x20 + 70));
    }
}

/// Where every data object ended up. A program's variables that do not fit in one
/// bank are split between fields, so each piece is a run of whole fields in one bank;
/// an object is only split when no code reaches it through a computed pointer.
#[derive(Clone, Debug, Default)]
pub struct DataMap {
    /// Per object: `(start offset, end offset, address of the start)` pieces, sorted.
    pub pieces: Vec<Vec<(u16, u16, u16)>>,
}

impl DataMap {
    /// The address of byte `off` of object `d`.
    pub fn addr(&self, d: plcc_ir::DataId, off: u16) -> u16 {
        let ps = &self.pieces[d.index()];
        for &(s, e, a) in ps {
            if off >= s && off < e {
                return a + (off - s);
            }
        }
        // Past the end (a zero-sized object): relative to the first piece.
        ps.first()
            .map(|&(s, _, a)| a + off.saturating_sub(s))
            .unwrap_or(0)
    }

    /// True if object `d` is in several pieces.
    pub fn is_split(&self, d: plcc_ir::DataId) -> bool {
        self.pieces[d.index()].len() > 1
    }
}

/// The byte ranges of a struct's fields (BOOLs sharing a byte merge), in order.
pub fn field_ranges(layout: &PicLayout, module: &Module, agg: AggId) -> Vec<(u16, u16)> {
    let AggDef::Struct(s) = module.agg(agg) else {
        return vec![(0, layout.agg(agg).size as u16)];
    };
    let info = layout.agg(agg);
    let mut r: Vec<(u16, u16)> = s
        .fields
        .iter()
        .zip(&info.fields)
        .map(|(f, p)| {
            let size = match f.ty {
                MemType::Scalar(Type::I1) => 1,
                t => layout.size(t) as u16,
            };
            (p.offset, p.offset + size)
        })
        .filter(|(a, b)| b > a)
        .collect();
    r.sort();
    let mut out: Vec<(u16, u16)> = Vec::new();
    for (a, b) in r {
        match out.last_mut() {
            Some(last) if a < last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}
