//! EXPT (`fpow`, C's `pow`) from what the VM has.
//!
//! Every public C VM computes its float EXPT (`0607` REAL, `0608` LREAL) as
//! `exp(log(x) * y)` in double: NaN for any negative base (even with an integral
//! exponent), NaN for `0 ** 0`, NaN for `1 ** inf`, and an LREAL result that is not
//! correctly rounded (`reference/cpdev-vm-opcodes.md` §2.1). The composition keeps
//! the VM's EXPT only where it is right:
//! - `y = 0` gives 1 and `|x| = 1` gives ±1, whatever the other operand; `y = 0.5`
//!   is SQRT (correctly rounded);
//! - a negative base with an integral exponent is `|x| ** y` with the sign of an odd
//!   exponent; with any other exponent it is NaN (`-inf` gives `inf ** y`);
//! - REAL: `EXPT(|x|, y)` in double, rounded once to REAL (the correctly rounded
//!   result but for double-rounding near ties, and exact whenever the exact result is
//!   a REAL);
//! - LREAL with an integral exponent: square-and-multiply in LREAL (of `1 / |x|` for a
//!   negative exponent), exact whenever every step is; any other exponent: `EXPT`.
//!
//! Integrality and parity are tested in float arithmetic (`(v + 2^52) - 2^52` rounds
//! `v` to an integer), so no conversion is needed.

use super::*;

impl Fx<'_, '_> {
    /// `c := v is an integer`, for `0 <= v < big` (2^52 or 2^23, where adding `big`
    /// rounds to an integer): `tmp := (v + big) - big` is `v` rounded to an integer.
    fn is_integral_below(&mut self, ft: Ty, c: u32, tmp: u32, v: u32, big: u32) {
        self.rrr(op::add(ft, 2), &[tmp, v, big]);
        self.rrr(op::sub(ft), &[tmp, tmp, big]);
        self.rrr(op::cmp(op::group::EQ, ft), &[c, tmp, v]);
    }

    /// `d := x ** y` in float type `t`.
    pub(super) fn power(&mut self, t: Type, d: u32, x: u32, y: u32) -> Res<()> {
        let ft = float_ty(t);
        let n = self.size(t);
        let lreal = t == Type::F64;
        let bits = if lreal { Ty::Lword } else { Ty::Dword };
        let and = Opcode::new(op::group::AND, 0x20 | logic_code(n, false));
        let expt = Opcode::new(op::group::MATH, if lreal { 0x08 } else { 0x07 });
        let neg_op = Opcode::new(op::group::NEG, if lreal { 9 } else { 7 });
        let sign = 1u64 << (bits_of(t) - 1);
        let (c, neg, odd, int) = (
            self.scratch(1)?,
            self.scratch(1)?,
            self.scratch(1)?,
            self.scratch(1)?,
        );
        let r = self.scratch(n)?;
        let a = self.scratch(n)?;
        let ay = self.scratch(n)?;
        let w = self.scratch(n)?;
        let h = self.scratch(n)?;
        let one = self.konst(t, fbits(t, 1.0));
        let zero = self.konst(t, fbits(t, 0.0));
        let half = self.konst(t, fbits(t, 0.5));
        let inf = self.konst(t, fbits(t, f64::INFINITY));
        let big = self.konst(
            t,
            fbits(t, if lreal { 2f64.powi(52) } else { 2f64.powi(23) }),
        );
        let signk = self.konst(t, sign);
        let absmask = self.konst(t, sign.wrapping_sub(1));
        let zero8 = self.konst(Type::I1, 0);
        let l = |fx: &mut Self| fx.new_label("P");
        let (ldone, lsign, lpos, lgo) = (l(self), l(self), l(self), l(self));

        // y = 0: 1, whatever x (NaN included).
        self.rrr(op::cmp(op::group::EQ, ft), &[c, y, zero]);
        self.jz(c, lgo);
        self.copy(r, one, n);
        self.jmp(ldone);
        self.label(lgo);
        // a = |x| (the sign bit cleared: ABS keeps -0.0), neg = x's sign bit.
        self.rrr(and, &[a, x, absmask]);
        self.rrr(and, &[ay, y, absmask]);
        self.rrr(op::cmp(op::group::GE, bits), &[neg, x, signk]);
        // int = y is an integer (infinities too, NaN not); odd = it is an odd one.
        let (lint, lodd) = (l(self), l(self));
        self.rrr(op::cmp(op::group::GE, ft), &[int, ay, big]);
        self.jnz(int, lint);
        self.is_integral_below(ft, int, w, ay, big);
        self.label(lint);
        self.fill(odd, 0, 1);
        self.jz(int, lodd);
        self.rrr(op::mul(ft, 2), &[w, ay, half]);
        self.rrr(op::cmp(op::group::LT, ft), &[odd, w, big]);
        self.jz(odd, lodd);
        self.is_integral_below(ft, odd, h, w, big);
        self.rrr(op::cmp(op::group::EQ, Ty::Bool), &[odd, odd, zero8]);
        self.label(lodd);
        // A negative base: |x| ** y where y is integral or x is -inf, else NaN.
        self.jz(neg, lpos);
        self.jnz(int, lpos);
        self.rrr(op::cmp(op::group::EQ, ft), &[c, a, inf]);
        self.jnz(c, lpos);
        self.rrr(expt, &[r, x, y]);
        self.jmp(ldone);
        // r = a ** y.
        self.label(lpos);
        let lnot1 = l(self);
        self.rrr(op::cmp(op::group::EQ, ft), &[c, a, one]);
        self.jz(c, lnot1);
        self.copy(r, one, n);
        self.jmp(lsign);
        self.label(lnot1);
        // y = 0.5: SQRT, correctly rounded (x = -0 and -inf do not come here).
        let lnot_half = l(self);
        self.rrr(op::cmp(op::group::EQ, ft), &[c, y, half]);
        self.jz(c, lnot_half);
        self.rrr(Opcode::new(op::group::MATH, 0x20 | lreal as u8), &[r, a]);
        self.jmp(lsign);
        self.label(lnot_half);
        if lreal {
            let (lexpt, lloop, leven, lsq, lend) = (l(self), l(self), l(self), l(self), l(self));
            self.jz(int, lexpt);
            self.rrr(op::cmp(op::group::EQ, ft), &[c, ay, inf]);
            self.jnz(c, lexpt);
            // w = the base (1 / a for a negative exponent), r = 1, ay = the exponent's
            // magnitude, halved each round.
            self.copy(w, a, n);
            self.rrr(op::cmp(op::group::LT, ft), &[c, y, zero]);
            let lbase = l(self);
            self.jz(c, lbase);
            self.rrr(op::div(ft), &[w, one, a]);
            self.label(lbase);
            self.copy(r, one, n);
            self.label(lloop);
            self.rrr(op::cmp(op::group::EQ, ft), &[c, ay, zero]);
            self.jnz(c, lend);
            self.rrr(op::mul(ft, 2), &[h, ay, half]);
            self.rrr(op::cmp(op::group::GE, ft), &[c, h, big]);
            self.jnz(c, leven);
            self.is_integral_below(ft, c, ay, h, big);
            self.jnz(c, leven);
            // An odd exponent: r *= w, ay = (2h - 1) / 2.
            self.rrr(op::mul(ft, 2), &[r, r, w]);
            self.rrr(op::sub(ft), &[ay, h, half]);
            self.jmp(lsq);
            self.label(leven);
            self.copy(ay, h, n);
            self.label(lsq);
            self.rrr(op::mul(ft, 2), &[w, w, w]);
            self.jmp(lloop);
            self.label(lexpt);
            self.rrr(expt, &[r, a, y]);
            self.label(lend);
        } else {
            self.rrr(expt, &[r, a, y]);
        }
        // The sign of a negative base to an odd power.
        self.label(lsign);
        self.jz(neg, ldone);
        self.jz(odd, ldone);
        self.rrr(neg_op, &[r, r]);
        self.label(ldone);
        self.copy(d, r, n);
        Ok(())
    }
}
