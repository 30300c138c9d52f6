//! Operations the VM lacks, composed from the ones it has: the arithmetic right
//! shift, rotations by 0, sign extension, float rounding, and the conversions
//! between integers and floats. What the C VMs leave undefined (division by zero,
//! `MIN / -1` where it overflows, shifts by the width or more, float-to-integer
//! conversions out of range) the build has guarded in the IR before
//! (`passes::legalize`, told what the port defines by `Port::defines`), so those
//! operations are emitted plainly here.

use super::*;

impl Fx<'_, '_> {
    pub(super) fn unsupported(&self, what: &str, span: Option<Span>) -> Box<Diagnostic> {
        let msg = format!("{what} is not supported on the vmasm target");
        Box::new(match span {
            Some(s) => Diagnostic::error(crate::codes::E_UNSUPPORTED, msg, s),
            None => Diagnostic::error_nowhere(crate::codes::E_UNSUPPORTED, msg),
        })
    }

    pub(super) fn unary(&mut self, uop: UnaryOp, arg: Value, v: Value) -> Res<()> {
        let t = self.vty(arg);
        let d = self.home(v);
        let a = self.home(arg);
        let n = self.size(t);
        let lreal = t == Type::F64;
        let math = |base: u8| Opcode::new(op::group::MATH, base + lreal as u8);
        let opcode = match uop {
            UnaryOp::Ineg => {
                self.negate(d, a, t);
                return Ok(());
            }
            UnaryOp::Bnot => Opcode::new(op::group::NEG, 0x10 | logic_code(n, t == Type::I1)),
            UnaryOp::Iabs => return self.abs(d, a, t),
            UnaryOp::Fneg => Opcode::new(op::group::NEG, if lreal { 9 } else { 7 }),
            UnaryOp::Fabs => Opcode::new(op::group::MATH, 0x10 | float_ty(t) as u8),
            UnaryOp::Fsqrt => math(0x20),
            UnaryOp::Ln => math(0x22),
            UnaryOp::Log10 => math(0x24),
            UnaryOp::Exp => math(0x26),
            UnaryOp::Sin => math(0x28),
            UnaryOp::Cos => math(0x2A),
            UnaryOp::Tan => math(0x2C),
            UnaryOp::Asin => math(0x2E),
            UnaryOp::Acos => math(0x30),
            UnaryOp::Atan => math(0x32),
            UnaryOp::Fnearest | UnaryOp::Ftrunc | UnaryOp::Ffloor | UnaryOp::Fceil => {
                return self.round(uop, t, a, d);
            }
        };
        self.rrr(opcode, &[d, a]);
        Ok(())
    }

    /// Float rounding to an integral float: through TRUNC where the value has a
    /// fraction, keeping the sign of zero.
    pub(super) fn round(&mut self, uop: UnaryOp, t: Type, x: u32, d: u32) -> Res<()> {
        let ft = float_ty(t);
        let n = self.size(t);
        let it = if t == Type::F64 { Type::I64 } else { Type::I32 };
        let lend = self.new_label("R");
        let lcopy = self.new_label("R");
        let a = self.scratch(n)?;
        let c = self.scratch(1)?;
        self.rrr(Opcode::new(op::group::MATH, 0x10 | ft as u8), &[a, x]);
        let big = self.konst(
            t,
            fbits(
                t,
                if t == Type::F64 {
                    4503599627370496.0
                } else {
                    8388608.0
                },
            ),
        );
        self.rrr(op::cmp(op::group::LT, ft), &[c, a, big]);
        self.jz(c, lcopy);
        let ti = self.scratch(n)?;
        let lr = t == Type::F64;
        self.rrr(Opcode::new(op::group::MATH, 0x34 + lr as u8), &[ti, x]);
        if lr {
            self.lint_to_lreal(d, ti)?;
        } else {
            self.rrr(Opcode::new(op::group::CONV, 0x01), &[d, ti]);
        }
        let sign = self.konst(it, 1u64 << (bits_of(t) - 1));
        let s = self.scratch(n)?;
        let code = logic_code(n, false);
        self.rrr(Opcode::new(op::group::AND, 0x20 | code), &[s, x, sign]);
        self.rrr(Opcode::new(op::group::OR, 0x20 | code), &[d, d, s]);
        let one = self.konst(t, fbits(t, 1.0));
        match uop {
            UnaryOp::Ftrunc => {}
            UnaryOp::Ffloor => {
                self.rrr(op::cmp(op::group::GT, ft), &[c, d, x]);
                self.jz(c, lend);
                self.rrr(op::sub(ft), &[d, d, one]);
            }
            UnaryOp::Fceil => {
                self.rrr(op::cmp(op::group::LT, ft), &[c, d, x]);
                self.jz(c, lend);
                self.rrr(op::add(ft, 2), &[d, d, one]);
            }
            _ => {
                // Ties to even: the fraction decides, and at exactly one half the
                // parity of the truncated integer.
                let half = self.konst(t, fbits(t, 0.5));
                let mhalf = self.konst(t, fbits(t, -0.5));
                let fr = self.scratch(n)?;
                let odd = self.scratch(1)?;
                let one8 = self.konst(Type::I8, 1);
                let (lup, ldown, lneg) = (
                    self.new_label("R"),
                    self.new_label("R"),
                    self.new_label("R"),
                );
                self.rrr(op::sub(ft), &[fr, x, d]);
                self.rrr(Opcode::new(op::group::AND, 0x21), &[odd, ti, one8]);
                self.rrr(op::cmp(op::group::GT, ft), &[c, fr, half]);
                self.jnz(c, lup);
                self.rrr(op::cmp(op::group::LT, ft), &[c, fr, mhalf]);
                self.jnz(c, ldown);
                self.rrr(op::cmp(op::group::EQ, ft), &[c, fr, half]);
                self.jz(c, lneg);
                self.jnz(odd, lup);
                self.jmp(lend);
                self.label(lneg);
                self.rrr(op::cmp(op::group::EQ, ft), &[c, fr, mhalf]);
                self.jz(c, lend);
                self.jz(odd, lend);
                self.label(ldown);
                self.rrr(op::sub(ft), &[d, d, one]);
                self.jmp(lend);
                self.label(lup);
                self.rrr(op::add(ft, 2), &[d, d, one]);
            }
        }
        self.jmp(lend);
        self.label(lcopy);
        self.copy(d, x, n);
        self.label(lend);
        Ok(())
    }

    pub(super) fn binary(
        &mut self,
        bop: BinaryOp,
        av: Value,
        bv: Value,
        v: Value,
        span: Option<Span>,
    ) -> Res<()> {
        let t = self.vty(av);
        let d = self.home(v);
        let a = self.home(av);
        let b = self.home(bv);
        let n = self.size(t);
        let u = int_ty(t, false);
        let is_bool = t == Type::I1;
        let logic = |g: u8, xor: bool| {
            let code = logic_code(n, is_bool);
            let code = if xor && code >= 3 { code + 1 } else { code };
            Opcode::new(g, 0x20 | code)
        };
        let opcode = match bop {
            BinaryOp::Iadd => op::add(u, 2),
            BinaryOp::Isub => op::sub(u),
            BinaryOp::Imul => self.mul_op(t),
            BinaryOp::Band => logic(op::group::AND, false),
            BinaryOp::Bor => logic(op::group::OR, false),
            BinaryOp::Bxor => logic(op::group::XOR, true),
            BinaryOp::Fadd => op::add(float_ty(t), 2),
            BinaryOp::Fsub => op::sub(float_ty(t)),
            BinaryOp::Fmul => op::mul(float_ty(t), 2),
            BinaryOp::Fdiv => op::div(float_ty(t)),
            BinaryOp::Fpow => return self.power(t, d, a, b),
            BinaryOp::Fatan2 => return Err(self.unsupported("ATAN2", span)),
            BinaryOp::Sdiv | BinaryOp::Srem | BinaryOp::Udiv | BinaryOp::Urem => {
                return self.divide(bop, t, d, a, b);
            }
            BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr | BinaryOp::Rotl | BinaryOp::Rotr => {
                return self.shift(bop, t, d, a, b, bv);
            }
        };
        self.rrr(opcode, &[d, a, b]);
        Ok(())
    }

    /// Division and remainder, legalized: the divisor is not zero, and a signed
    /// division sees `MIN, -1` only at the widths the port defines it (SINT, and INT
    /// where C's `int` has 32 bits, are promoted; LINT is divided by magnitudes as
    /// LWORD, since the VM's LINT reads are not portable).
    pub(super) fn divide(&mut self, bop: BinaryOp, t: Type, d: u32, a: u32, b: u32) -> Res<()> {
        let signed = matches!(bop, BinaryOp::Sdiv | BinaryOp::Srem);
        let rem = matches!(bop, BinaryOp::Srem | BinaryOp::Urem);
        if signed && t == Type::I64 {
            return self.sdiv_lint(rem, d, a, b);
        }
        let ty = int_ty(t, signed);
        let opc = if rem { op::modulo(ty) } else { op::div(ty) };
        self.rrr(opc, &[d, a, b]);
        Ok(())
    }

    /// Shifts and rotates. Shifts are legalized (their counts are below the
    /// width); the arithmetic right shift, which the VM lacks, goes through XOR with
    /// the sign mask. Rotations take any count: the IR's is modulo the width, and
    /// the C VMs compute a rotation by 0 as a shift by the width, so that is a copy.
    pub(super) fn shift(
        &mut self,
        bop: BinaryOp,
        t: Type,
        d: u32,
        a: u32,
        cnt: u32,
        cv: Value,
    ) -> Res<()> {
        let n = self.size(t);
        let w = bits_of(t) as u64;
        let code = logic_code(n, false);
        let u = int_ty(t, false);
        let kind = match bop {
            BinaryOp::Ishl => 0x00,
            BinaryOp::Ushr | BinaryOp::Sshr => 0x10,
            BinaryOp::Rotl => 0x20,
            _ => 0x30,
        };
        let opc = Opcode::new(op::group::SHIFT, kind | code);
        let mask = if n >= 8 {
            u64::MAX
        } else {
            (1u64 << (n * 8)) - 1
        };
        let k = self.iconst(cv).map(|k| k as u64 & mask);
        if matches!(bop, BinaryOp::Rotl | BinaryOp::Rotr) {
            match k {
                Some(k) if k % w == 0 => self.copy(d, a, n),
                Some(k) => {
                    let c16 = self.konst(Type::I16, k % w);
                    self.rrr(opc, &[d, a, c16]);
                }
                None => {
                    let m = self.scratch(n)?;
                    let wm1 = self.konst(t, w - 1);
                    self.rrr(Opcode::new(op::group::AND, 0x20 | code), &[m, cnt, wm1]);
                    let c16 = self.scratch(2)?;
                    self.resize(c16, 2, m, n);
                    let c = self.scratch(1)?;
                    let zero = self.konst(Type::I16, 0);
                    let (lrot, lend) = (self.new_label("S"), self.new_label("S"));
                    self.rrr(op::cmp(op::group::NE, Ty::Word), &[c, c16, zero]);
                    self.jnz(c, lrot);
                    self.copy(d, a, n);
                    self.jmp(lend);
                    self.label(lrot);
                    self.rrr(opc, &[d, a, c16]);
                    self.label(lend);
                }
            }
            return Ok(());
        }
        // The count as the VM's 16-bit operand (below the width: legalized).
        let c16 = match k {
            Some(k) => {
                debug_assert!(k < w, "a shift by {k} of {w} bits was not legalized");
                self.konst(Type::I16, k)
            }
            None => {
                let c16 = self.scratch(2)?;
                self.resize(c16, 2, cnt, n);
                c16
            }
        };
        if bop != BinaryOp::Sshr {
            self.rrr(opc, &[d, a, c16]);
            return Ok(());
        }
        // sshr: x XOR s, shifted logically, XOR s again (s = all sign bits).
        let s = self.scratch(n)?;
        let neg = self.scratch(1)?;
        let zero = self.konst(t, 0);
        let ones = self.konst(t, u64::MAX);
        self.is_negative(neg, a, t);
        self.rrr(op::sel(u), &[s, neg, zero, ones]);
        let x = self.scratch(n)?;
        let xor = Opcode::new(
            op::group::XOR,
            0x20 | if code >= 3 { code + 1 } else { code },
        );
        self.rrr(xor, &[x, a, s]);
        self.rrr(opc, &[x, x, c16]);
        self.rrr(xor, &[d, x, s]);
        Ok(())
    }

    /// Sign-extends `src` (type `from`) into `dst` (type `to`).
    pub(super) fn sext(&mut self, dst: u32, to: Type, src: u32, from: Type) {
        if from == Type::I16 && to == Type::I32 {
            self.rrr(Opcode::new(op::group::CONV, 0x0C), &[dst, src]);
            return;
        }
        let (dn, sn) = (self.size(to), self.size(from));
        self.resize(dst, dn, src, sn);
        let m = self.konst(to, 1u64 << (bits_of(from) - 1));
        let u = int_ty(to, false);
        let code = logic_code(dn, false);
        let xor = Opcode::new(
            op::group::XOR,
            0x20 | if code >= 3 { code + 1 } else { code },
        );
        self.rrr(xor, &[dst, dst, m]);
        self.rrr(op::sub(u), &[dst, dst, m]);
    }

    pub(super) fn convert(&mut self, cop: ConvOp, to: Type, arg: Value, v: Value) -> Res<()> {
        let from = self.vty(arg);
        let d = self.home(v);
        let a = self.home(arg);
        let (dn, sn) = (self.size(to), self.size(from));
        let conv = |f: u8| Opcode::new(op::group::CONV, f);
        match cop {
            ConvOp::Sext => self.sext(d, to, a, from),
            ConvOp::Uext => self.resize(d, dn, a, sn),
            ConvOp::Itrunc if to == Type::I1 => {
                let one = self.konst(Type::I8, 1);
                self.rrr(Opcode::new(op::group::AND, 0x21), &[d, a, one]);
            }
            ConvOp::Itrunc | ConvOp::Bitcast => self.copy(d, a, dn),
            // Rejected before (`Isel::inst`).
            ConvOp::PtrToInt | ConvOp::IntToPtr => {
                return Err(self.unsupported("pointer arithmetic", None))
            }
            ConvOp::Fpromote => self.rrr(conv(0x0D), &[d, a]),
            ConvOp::Fdemote => self.rrr(conv(0x0E), &[d, a]),
            ConvOp::SiToF | ConvOp::UiToF => {
                let signed = cop == ConvOp::SiToF;
                let wide = self.int_to_f64_or_direct(d, to, a, from, signed)?;
                if let Some(t) = wide {
                    // Only LINT_TO_LREAL takes 64 bits: a REAL result rounds twice.
                    self.rrr(conv(0x0E), &[d, t]);
                }
            }
            ConvOp::FToSi | ConvOp::FToUi => {
                self.float_to_int(d, to, a, from, cop == ConvOp::FToSi)?
            }
        }
        Ok(())
    }

    /// Integer to float. Writes `d` directly, or returns a scratch LREAL that still
    /// has to be narrowed to REAL.
    fn int_to_f64_or_direct(
        &mut self,
        d: u32,
        to: Type,
        a: u32,
        from: Type,
        signed: bool,
    ) -> Res<Option<u32>> {
        let conv = |f: u8| Opcode::new(op::group::CONV, f);
        let sn = self.size(from);
        if to == Type::F32 {
            match (from, signed) {
                (Type::I16, true) => {
                    self.rrr(conv(0x00), &[d, a]);
                    return Ok(None);
                }
                (Type::I8, true) => {
                    let t = self.scratch(2)?;
                    self.sext(t, Type::I16, a, from);
                    self.rrr(conv(0x00), &[d, t]);
                    return Ok(None);
                }
                (Type::I32, true) => {
                    self.rrr(conv(0x01), &[d, a]);
                    return Ok(None);
                }
                (Type::I32, false) => {
                    self.rrr(conv(0x10), &[d, a]);
                    return Ok(None);
                }
                (Type::I8 | Type::I16, false) => {
                    let t = self.scratch(4)?;
                    self.resize(t, 4, a, sn);
                    self.rrr(conv(0x01), &[d, t]);
                    return Ok(None);
                }
                _ => {}
            }
        }
        let target = if to == Type::F32 { self.scratch(8)? } else { d };
        let l = if from == Type::I64 && to == Type::F32 {
            self.sticky_low_bits(a, signed)?
        } else if from == Type::I64 {
            a
        } else {
            let t = self.scratch(8)?;
            if signed {
                self.sext(t, Type::I64, a, from);
            } else {
                self.resize(t, 8, a, sn);
            }
            t
        };
        if signed || from != Type::I64 {
            self.lint_to_lreal(target, l)?;
        } else {
            // ULINT: halve (keeping the low bit for rounding) when the top bit is set.
            let c = self.scratch(1)?;
            let (lbig, lend) = (self.new_label("U"), self.new_label("U"));
            self.is_negative(c, l, Type::I64);
            self.jnz(c, lbig);
            self.lint_to_lreal(target, l)?;
            self.jmp(lend);
            self.label(lbig);
            let h = self.scratch(8)?;
            let b = self.scratch(8)?;
            let one16 = self.konst(Type::I16, 1);
            let one = self.konst(Type::I64, 1);
            self.rrr(Opcode::new(op::group::SHIFT, 0x14), &[h, l, one16]);
            self.rrr(Opcode::new(op::group::AND, 0x24), &[b, l, one]);
            self.rrr(Opcode::new(op::group::OR, 0x24), &[h, h, b]);
            self.lint_to_lreal(target, h)?;
            self.rrr(op::add(Ty::Lreal, 2), &[target, target, target]);
            self.label(lend);
        }
        Ok(if to == Type::F32 { Some(target) } else { None })
    }

    /// For a 64-bit integer going to REAL through LREAL: where it has more than 53
    /// significant bits, replaces its low 12 bits by one marker bit, so that the
    /// LREAL is exact and the one rounding to REAL is the correct one.
    pub(super) fn sticky_low_bits(&mut self, a: u32, signed: bool) -> Res<u32> {
        let x = self.scratch(8)?;
        self.copy(x, a, 8);
        let c = self.scratch(1)?;
        let (lbig, lend) = (self.new_label("K"), self.new_label("K"));
        let hi = self.konst(Type::I64, 1u64 << 53);
        if signed {
            self.cmp_lint(op::group::GE, c, x, hi)?;
            self.jnz(c, lbig);
            let lo = self.konst(Type::I64, (-(1i64 << 53)) as u64);
            self.cmp_lint(op::group::LE, c, x, lo)?;
            self.jnz(c, lbig);
        } else {
            self.rrr(op::cmp(op::group::GE, Ty::Lword), &[c, x, hi]);
            self.jnz(c, lbig);
        }
        self.jmp(lend);
        self.label(lbig);
        let low = self.scratch(8)?;
        let m = self.konst(Type::I64, 0xFFF);
        let keep = self.konst(Type::I64, !0xFFFu64);
        let zero = self.konst(Type::I64, 0);
        let marker = self.konst(Type::I64, 0x800);
        self.rrr(Opcode::new(op::group::AND, 0x24), &[low, x, m]);
        self.rrr(Opcode::new(op::group::AND, 0x24), &[x, x, keep]);
        self.rrr(op::cmp(op::group::NE, Ty::Lword), &[c, low, zero]);
        self.jz(c, lend);
        self.rrr(Opcode::new(op::group::OR, 0x24), &[x, x, marker]);
        self.label(lend);
        Ok(x)
    }

    /// Float to integer, toward zero, of an operand legalized into the range whose
    /// truncation fits `to` (saturation and NaN are selected around the conversion
    /// in the IR). The VM truncates REAL to DINT and LREAL to LINT; UDINT from REAL
    /// has a conversion of its own, and ULINT at or above 2^63 is truncated less
    /// 2^63 and has its top bit put back.
    pub(super) fn float_to_int(
        &mut self,
        d: u32,
        to: Type,
        x: u32,
        from: Type,
        signed: bool,
    ) -> Res<()> {
        let dn = self.size(to);
        let w = bits_of(to);
        let trunc_real = Opcode::new(op::group::MATH, 0x34);
        let trunc_lreal = Opcode::new(op::group::MATH, 0x35);
        if from == Type::F32 && w <= 32 && (signed || w < 32) {
            let t = self.scratch(4)?;
            self.rrr(trunc_real, &[t, x]);
            self.copy(d, t, dn);
            return Ok(());
        }
        if from == Type::F32 && w == 32 {
            self.rrr(Opcode::new(op::group::CONV, 0x11), &[d, x]);
            return Ok(());
        }
        let xl = if from == Type::F32 {
            let xl = self.scratch(8)?;
            self.rrr(Opcode::new(op::group::CONV, 0x0D), &[xl, x]);
            xl
        } else {
            x
        };
        let t = self.scratch(8)?;
        if !signed && w == 64 {
            // At or above 2^63: subtract it, truncate, and put the top bit back.
            let c = self.scratch(1)?;
            let (lsmall, ldone) = (self.new_label("F"), self.new_label("F"));
            let two63 = self.konst(Type::F64, fbits(Type::F64, 9223372036854775808.0));
            self.rrr(op::cmp(op::group::LT, Ty::Lreal), &[c, xl, two63]);
            self.jnz(c, lsmall);
            let y = self.scratch(8)?;
            self.rrr(op::sub(Ty::Lreal), &[y, xl, two63]);
            self.rrr(trunc_lreal, &[t, y]);
            let top = self.konst(Type::I64, 1u64 << 63);
            self.rrr(op::add(Ty::Lword, 2), &[t, t, top]);
            self.jmp(ldone);
            self.label(lsmall);
            self.rrr(trunc_lreal, &[t, xl]);
            self.label(ldone);
        } else {
            self.rrr(trunc_lreal, &[t, xl]);
        }
        self.copy(d, t, dn);
        Ok(())
    }
}
