//! The IR's `fill p, v, n` (`passes::fill`): `n` elements of `v`'s type at `p` := `v`.
//!
//! - At a frame-relative address with a constant count, it is straight-line code:
//!   the first element (FPAT when every byte of a constant `v` is the same, up to 255
//!   bytes at once, else a copy of `v`), then MEMCPs that double the filled part (1,
//!   2, 4, … elements), each from the start of the array, until the count is reached.
//!   A fill of 10,000 BOOLs is one FPAT and six MEMCPs.
//! - Anywhere else, a loop that writes one element through the pointer (DPWRL) and
//!   steps it, `n` times.

use super::*;

impl Fx<'_, '_> {
    /// Lowers `fill p, v, n` (`args` = `[p, v, n]`).
    pub(super) fn fill_elems(&mut self, args: &[Value]) -> Res<()> {
        let [p, v, n] = args else {
            return Err(self.internal("fill takes 3 operands"));
        };
        let size = self.size(self.vty(*v));
        let count = self.iconst(*n);
        match (self.class_of(*p), count) {
            (PtrClass::Rel(off), Some(count)) => {
                let total = count.max(0) as u64 * size as u64;
                if total > u32::MAX as u64 {
                    return Err(self.internal("a fill larger than data memory"));
                }
                self.fill_static(off, *v, size, total as u32);
            }
            _ => self.fill_loop(*p, *v, *n, size)?,
        }
        Ok(())
    }

    /// The constant-count fill of `total` bytes at frame offset `off`.
    fn fill_static(&mut self, off: u32, v: Value, size: u32, total: u32) {
        if total == 0 {
            return;
        }
        let byte = plcc_ir::passes::fill::repeated_byte(self.f, v, size);
        let mut done = match byte {
            Some(b) => {
                // FPAT counts one byte, FPAT4A (the aligned mode's) a word.
                let most = if self.mode() == Mode::M32A {
                    0xFFFF
                } else {
                    0xFF
                };
                let first = total.min(most) / size * size;
                self.fill(off, b, first);
                first
            }
            None => {
                let h = self.home(v);
                self.copy(off, h, size);
                size
            }
        };
        while done < total {
            let k = done.min(total - done).min(0xFFFF / size * size);
            self.copy(off + done, off, k);
            done += k;
        }
    }

    /// The general fill: a loop of `n` element writes through a pointer.
    fn fill_loop(&mut self, p: Value, v: Value, n: Value, size: u32) -> Res<()> {
        let pb = self.mode().addr_bytes() as u32;
        let ptr = self.scratch(pb)?;
        let left = self.scratch(8)?;
        let cond = self.scratch(1)?;
        match self.class_of(p) {
            c @ (PtrClass::Rel(_) | PtrClass::Abs(_)) => self.materialize(ptr, c),
            PtrClass::Idx { base, index, .. } => {
                // DPTR + base + index * size; the index is in range, so its low bytes
                // are the whole of it.
                let pt = self.ptr_ty();
                self.materialize(ptr, PtrClass::Rel(base));
                let off = self.scratch(pb)?;
                let (src, low) = self.folded_index.get(&index).copied().unwrap_or((index, 0));
                let ih = self.home(src);
                let isz = self.size(self.vty(src));
                if low == 0 {
                    self.resize(off, pb, ih, isz);
                } else {
                    // A folded `sext(i) - low` (i an INT) is not computed: take it
                    // in INT, where it is 0..len.
                    let lo = self.konst(Type::I16, low as u64);
                    self.fill(off, 0, pb);
                    self.rrr(op::sub(Ty::Int), &[off, ih, lo]);
                }
                let k = self.konst(self.ptr_type(), size as u64);
                self.rrr(op::mul(pt, 2), &[off, off, k]);
                self.rrr(op::add(pt, 2), &[ptr, ptr, off]);
            }
            PtrClass::Dyn => {
                let h = self.home(p);
                self.copy(ptr, h, pb);
            }
        }
        let nh = self.home(n);
        self.copy(left, nh, 8);
        let src = self.home(v);
        let zero = self.konst(Type::I64, 0);
        let one = self.konst(Type::I64, 1);
        let step = self.konst(self.ptr_type(), size as u64);
        let top = self.new_label("fill");
        let end = self.new_label("fill_end");
        self.label(top);
        self.rrr(op::cmp(op::group::LE, Ty::Lint), &[cond, left, zero]);
        self.jnz(cond, end);
        self.dp_move(true, src, ptr, size);
        self.rrr(op::add(self.ptr_ty(), 2), &[ptr, ptr, step]);
        self.rrr(op::sub(Ty::Lint), &[left, left, one]);
        self.jmp(top);
        self.label(end);
        Ok(())
    }
}
