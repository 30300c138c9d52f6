//! Instruction forms that are defined on every CPDev VM port.
//!
//! The C VMs compute in C, so an instruction that overflows a signed type is undefined
//! behaviour, and which instructions overflow depends on the port's C `int`
//! (`reference/cpdev-vm-opcodes.md` §3). The shipped builds with byte-wise data
//! access also misread a LINT whose bit 31 is set and whose high half is not all ones
//! (§3.8), so no LINT-typed instruction is emitted at all: 64-bit signed operations
//! are done on LWORD.
//! - multiplication: SINT for 8 bits (promoted products stay below 2^15), INT or
//!   WORD for 16 bits by the port's `int` (WORD is promoted to a signed `int` where
//!   that has 32 bits, INT overflows where it has 16), DWORD and LWORD above;
//! - negation is `0 - x` in the unsigned type, absolute value a select of it;
//! - signed 64-bit comparisons are LWORD comparisons of the operands with their sign
//!   bits flipped; signed 64-bit division and remainder divide the magnitudes as LWORD;
//! - LINT to LREAL converts three pieces that the LINT read cannot get wrong.

use super::*;

impl Fx<'_, '_> {
    /// The multiplication of two values of type `t`, free of undefined behaviour on
    /// the port.
    pub(super) fn mul_op(&self, t: Type) -> Opcode {
        let ty = match t {
            Type::I8 | Type::I1 => Ty::Sint,
            Type::I16 if self.cx.port.int16() => Ty::Word,
            Type::I16 => Ty::Int,
            t => int_ty(t, false),
        };
        op::mul(ty, 2)
    }

    /// `c := a < 0` for a signed integer of type `t`.
    pub(super) fn is_negative(&mut self, c: u32, a: u32, t: Type) {
        if t == Type::I64 {
            let top = self.konst(Type::I64, 1 << 63);
            self.rrr(op::cmp(op::group::GE, Ty::Lword), &[c, a, top]);
        } else {
            let zero = self.konst(t, 0);
            self.rrr(op::cmp(op::group::LT, int_ty(t, true)), &[c, a, zero]);
        }
    }

    /// `d := 0 - a`, wrapping.
    pub(super) fn negate(&mut self, d: u32, a: u32, t: Type) {
        let zero = self.konst(t, 0);
        self.rrr(op::sub(int_ty(t, false)), &[d, zero, a]);
    }

    /// `d := |a|`, the most negative value giving itself. `d` is written last.
    pub(super) fn abs(&mut self, d: u32, a: u32, t: Type) -> Res<()> {
        let n = self.size(t);
        let c = self.scratch(1)?;
        let m = self.scratch(n)?;
        self.is_negative(c, a, t);
        self.negate(m, a, t);
        self.rrr(op::sel(int_ty(t, false)), &[d, c, a, m]);
        Ok(())
    }

    /// A signed comparison of 64-bit integers (`g` one of GT…LT), as LWORD after
    /// flipping the sign bits. `d` is written last.
    pub(super) fn cmp_lint(&mut self, g: u8, d: u32, a: u32, b: u32) -> Res<()> {
        let top = self.konst(Type::I64, 1 << 63);
        let xa = self.scratch(8)?;
        let xb = self.scratch(8)?;
        let xor = Opcode::new(op::group::XOR, 0x25);
        self.rrr(xor, &[xa, a, top]);
        self.rrr(xor, &[xb, b, top]);
        self.rrr(op::cmp(g, Ty::Lword), &[d, xa, xb]);
        Ok(())
    }

    /// Signed 64-bit division or remainder of `a` by a `b` known not to be 0: the
    /// magnitudes divided as LWORD, the sign put back (`MIN / -1` wraps to MIN).
    pub(super) fn sdiv_lint(&mut self, rem: bool, d: u32, a: u32, b: u32) -> Res<()> {
        let (na, nb) = (self.scratch(1)?, self.scratch(1)?);
        let (ua, ub) = (self.scratch(8)?, self.scratch(8)?);
        self.abs_parts(na, ua, a)?;
        self.abs_parts(nb, ub, b)?;
        let q = ua;
        let opc = if rem {
            op::modulo(Ty::Lword)
        } else {
            op::div(Ty::Lword)
        };
        self.rrr(opc, &[q, ua, ub]);
        // The sign: the dividend's for a remainder, else the XOR of both signs.
        let s = na;
        if !rem {
            self.rrr(Opcode::new(op::group::XOR, 0x20), &[s, na, nb]);
        }
        let m = ub;
        self.negate(m, q, Type::I64);
        self.rrr(op::sel(Ty::Lword), &[d, s, q, m]);
        Ok(())
    }

    /// `neg := a < 0; mag := |a|` as an LWORD.
    fn abs_parts(&mut self, neg: u32, mag: u32, a: u32) -> Res<()> {
        let m = self.scratch(8)?;
        self.is_negative(neg, a, Type::I64);
        self.negate(m, a, Type::I64);
        self.rrr(op::sel(Ty::Lword), &[mag, neg, a, m]);
        Ok(())
    }

    /// `dst := LINT_TO_LREAL(src)`, correctly rounded for every LINT: the high half
    /// (its low 32 bits cleared, so bit 31 is clear) and two 16-bit pieces of the low
    /// half each convert exactly; their sum rounds once. `dst` must not be `src`.
    pub(super) fn lint_to_lreal(&mut self, dst: u32, src: u32) -> Res<()> {
        let conv = Opcode::new(op::group::CONV, 0x0F);
        let and = Opcode::new(op::group::AND, 0x24);
        let t = self.scratch(8)?;
        let f = self.scratch(8)?;
        let hi = self.konst(Type::I64, 0xFFFF_FFFF_0000_0000);
        let lo16 = self.konst(Type::I64, 0xFFFF);
        let sixteen = self.konst(Type::I16, 16);
        let k65536 = self.konst(Type::F64, 65536f64.to_bits());
        self.rrr(and, &[t, src, hi]);
        self.rrr(conv, &[dst, t]);
        self.rrr(Opcode::new(op::group::SHIFT, 0x14), &[t, src, sixteen]);
        self.rrr(and, &[t, t, lo16]);
        self.rrr(conv, &[f, t]);
        self.rrr(op::mul(Ty::Lreal, 2), &[f, f, k65536]);
        self.rrr(and, &[t, src, lo16]);
        self.rrr(conv, &[t, t]);
        self.rrr(op::add(Ty::Lreal, 2), &[f, f, t]);
        self.rrr(op::add(Ty::Lreal, 2), &[dst, dst, f]);
        Ok(())
    }
}
