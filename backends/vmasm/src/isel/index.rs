//! Array indexes: the INT an A?RD/A?WR access reads (in place, or copied for CEAC to
//! subtract a lower bound), where those reads happen, and the `sext(i) - low` indexes
//! folded into CEAC.

use super::*;

impl Fx<'_, '_> {
    /// The zero-based INT index for an A?RD/A?WR access.
    ///
    /// The IR's index is in range (`elem_addr`'s contract: the front end's checks come
    /// before it), so an index of 2 bytes or more is read in place: its low two bytes
    /// (the VM is little-endian) are the INT. Only a folded `sext(i) - low` with a
    /// non-zero `low` is copied, for CEAC to subtract `low` (CPDev's own shape; CEAC's
    /// bound check then never fails).
    pub(super) fn lac(&mut self, index: Value, len: u32) -> Res<u32> {
        let (src, low) = self.folded_index.get(&index).copied().unwrap_or((index, 0));
        let ih = self.home(src);
        let isz = self.size(self.vty(src));
        if low == 0 && isz >= 2 {
            return Ok(ih);
        }
        let s = self.scratch(2)?;
        self.resize(s, 2, ih, isz);
        if low == 0 {
            return Ok(s);
        }
        let low = self.konst(Type::I16, low as u64);
        let span = self.konst(Type::I16, len.saturating_sub(1) as u64);
        self.rrr(op::CEAC, &[s, low, span]);
        Ok(s)
    }

    /// Records where array accesses at run-time indexes read their index (see
    /// [`UseKind::Late`]): the in-place and coalescing decisions must see those reads.
    pub(super) fn record_late_uses(&mut self) {
        let f = self.f;
        for (k, (_, i)) in f.inst_iter().enumerate() {
            let addr = match f.inst(i) {
                InstData::Load { addr, .. } | InstData::Store { addr, .. } => *addr,
                InstData::Intrinsic {
                    op: Intrinsic::Fill,
                    args,
                } => args[0],
                _ => continue,
            };
            {
                if let PtrClass::Idx { index, .. } = self.class_of(addr) {
                    let src = self.folded_index.get(&index).map_or(index, |&(y, _)| y);
                    self.late_use.insert(i, src);
                    self.uses[src.index()].push((k, UseKind::Late));
                }
            }
        }
    }

    /// Finds the array indexes of the form `sext(i) - low` or `sext(i)` with `i` an
    /// INT: the copied index is then `i` and CEAC subtracts `low` (the CPDev shape), and
    /// the widening and subtraction are not computed when nothing else uses them.
    pub(super) fn fold_indexes(&mut self) {
        let f = self.f;
        let def_of = |v: Value| match f.value_def(v) {
            ValueDef::Result(i) => Some(f.inst(i).clone()),
            _ => None,
        };
        let mut idx_values = Vec::new();
        for (_, i) in f.inst_iter() {
            if let (InstData::ElemAddr { .. }, Some(v)) = (f.inst(i), f.result(i)) {
                if let PtrClass::Idx { index, len, .. } = self.class_of(v) {
                    idx_values.push((index, len));
                }
            }
        }
        for (index, len) in idx_values {
            if self.folded_index.contains_key(&index) {
                continue;
            }
            let (x, low) = match def_of(index) {
                Some(InstData::Binary {
                    op: BinaryOp::Isub,
                    args,
                }) => match self.iconst(args[1]) {
                    Some(l) => (args[0], l),
                    None => continue,
                },
                _ => (index, 0),
            };
            let Some(InstData::Convert {
                op: ConvOp::Sext,
                arg: y,
                ..
            }) = def_of(x)
            else {
                continue;
            };
            let hi = low + len as i64 - 1;
            if self.vty(y) != Type::I16 || low < i16::MIN as i64 || hi > i16::MAX as i64 {
                continue;
            }
            self.folded_index.insert(index, (y, low));
        }
        // A folded index (and its widening) is computed only if something else uses it.
        let folded: Vec<Value> = self.folded_index.keys().copied().collect();
        for index in folded {
            let only_arrays = self.uses[index.index()].iter().all(|&(k, _)| {
                let i = f.inst_iter().nth(k).map(|(_, i)| i);
                i.and_then(|i| f.result(i))
                    .is_some_and(|r| matches!(self.class[r.index()], Some(PtrClass::Idx { .. })))
            });
            if !only_arrays {
                continue;
            }
            self.skip[index.index()] = true;
            if let Some(InstData::Binary {
                op: BinaryOp::Isub,
                args,
            }) = def_of(index)
            {
                if self.uses[args[0].index()].len() == 1 {
                    self.skip[args[0].index()] = true;
                }
            }
        }
    }
}
