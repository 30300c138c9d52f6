//! Compares (the flags and which one holds the answer), conversions and selects.

use super::*;

impl Emitter<'_> {
    /// Sets the flags for `a cond b` and says which flag holds the answer.
    pub(super) fn compare(&mut self, cond: IntCC, args: [Value; 2]) -> FlagCond {
        let t = self.ty(args[0]);
        if t == Type::I1 {
            let (a, b) = (self.bit(args[0]), self.bit(args[1]));
            let mut k = 0u8;
            for x in [a, b] {
                match x {
                    BitLoc::Lit(v) => k ^= v as u8,
                    BitLoc::Bit(_, _, n) => k ^= n as u8,
                }
            }
            self.i(Inst::Movlw(k));
            for x in [a, b] {
                if let BitLoc::Bit(r, bn, _) = x {
                    self.i(Inst::Btfsc(r, bn));
                    self.i(Inst::Xorlw(1));
                }
            }
            self.i(Inst::Andlw(1));
            return FlagCond {
                bit: reg::Z,
                when_set: cond == IntCC::Eq,
            };
        }
        let n = self.bytes(t);
        let (mut a, mut b) = (self.loc(args[0]), self.loc(args[1]));
        match cond {
            IntCC::Eq | IntCC::Ne => {
                if matches!(a, Loc::Lit(_)) {
                    std::mem::swap(&mut a, &mut b);
                }
                let join = self.new_label("eq");
                for i in 0..n {
                    let (x, y) = (Self::byte(a, i), Self::byte(b, i));
                    match y {
                        Src::Lit(0) => {
                            let r = self.reg_for(x, SCRATCH[0], None);
                            self.i(Inst::Movf(r, Dest::W));
                        }
                        Src::Lit(k) => {
                            self.load_w(x);
                            self.i(Inst::Xorlw(k));
                        }
                        _ => {
                            let yr = self.reg_for(y, SCRATCH[0], None);
                            self.load_w(x);
                            self.i(Inst::Xorwf(yr, Dest::W));
                        }
                    }
                    if i + 1 < n {
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.goto(join);
                    }
                }
                self.label(join);
                FlagCond {
                    bit: reg::Z,
                    when_set: cond == IntCC::Eq,
                }
            }
            _ => {
                // a < b or a >= b after swapping the others.
                let (cond, swap) = match cond {
                    IntCC::Sgt => (IntCC::Slt, true),
                    IntCC::Sle => (IntCC::Sge, true),
                    IntCC::Ugt => (IntCC::Ult, true),
                    IntCC::Ule => (IntCC::Uge, true),
                    c => (c, false),
                };
                if swap {
                    std::mem::swap(&mut a, &mut b);
                }
                let signed = matches!(cond, IntCC::Slt | IntCC::Sge);
                if signed && matches!(b, Loc::Lit(k) if k & mask(n) == 0) {
                    // The sign bit alone: C := it.
                    match Self::byte(a, n - 1) {
                        Src::Reg(r) => self.i(Inst::Rlf(r, Dest::W)),
                        s => {
                            let r = self.reg_for(s, SCRATCH[0], None);
                            self.i(Inst::Rlf(r, Dest::W));
                        }
                    }
                    return FlagCond {
                        bit: reg::C,
                        when_set: cond == IntCC::Slt,
                    };
                }
                let join = self.new_label("cmp");
                for i in (0..n).rev() {
                    let (mut x, mut y) = (Self::byte(a, i), Self::byte(b, i));
                    if signed && i == n - 1 && matches!((x, y), (Src::Lit(_), _) | (_, Src::Lit(_)))
                    {
                        // One side constant: flip the other's sign bit in W.
                        match (x, y) {
                            (_, Src::Lit(ky)) => {
                                let k = ky ^ 0x80;
                                self.load_w(x);
                                self.i(Inst::Xorlw(0x80));
                                if k == 0 {
                                    // x' >= 0 always; Z already says x' == 0.
                                    self.i(Inst::Bsf(reg::STATUS, reg::C));
                                } else {
                                    self.i(Inst::Addlw(k.wrapping_neg()));
                                }
                            }
                            (Src::Lit(kx), _) => {
                                self.load_w(y);
                                self.i(Inst::Xorlw(0x80));
                                self.i(Inst::Sublw(kx ^ 0x80));
                            }
                            _ => unreachable!(),
                        }
                        if i > 0 {
                            self.i(Inst::Btfss(reg::STATUS, reg::Z));
                            self.goto(join);
                        }
                        continue;
                    }
                    if signed && i == n - 1 {
                        // Flip the sign bits: signed order becomes unsigned order.
                        x = self.flip_sign(x, SCRATCH[0]);
                        y = self.flip_sign(y, SCRATCH[1]);
                    }
                    // W = x - y; C = x >= y; Z = x == y.
                    match (x, y) {
                        (_, Src::Lit(k)) => {
                            let xr = self.reg_for(x, SCRATCH[2], None);
                            self.i(Inst::Movlw(k));
                            self.i(Inst::Subwf(xr, Dest::W));
                        }
                        (Src::Lit(k), _) => {
                            self.load_w(y);
                            self.i(Inst::Sublw(k));
                        }
                        _ => {
                            let xr = self.reg_for(x, SCRATCH[2], None);
                            self.load_w(y);
                            self.i(Inst::Subwf(xr, Dest::W));
                        }
                    }
                    if i > 0 {
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.goto(join);
                    }
                }
                self.label(join);
                FlagCond {
                    bit: reg::C,
                    when_set: matches!(cond, IntCC::Sge | IntCC::Uge),
                }
            }
        }
    }

    pub(super) fn flip_sign(&mut self, s: Src, t: u16) -> Src {
        match s {
            Src::Lit(k) => Src::Lit(k ^ 0x80),
            _ => {
                self.load_w(s);
                self.i(Inst::Xorlw(0x80));
                self.i(Inst::Movwf(t));
                Src::Reg(t)
            }
        }
    }

    pub(super) fn flag_to_bit(&mut self, d: (u16, u8), fc: FlagCond) {
        self.i(Inst::Bcf(d.0, d.1));
        self.i(if fc.when_set {
            Inst::Btfsc(reg::STATUS, fc.bit)
        } else {
            Inst::Btfss(reg::STATUS, fc.bit)
        });
        self.i(Inst::Bsf(d.0, d.1));
    }

    // ---- conversions, select, memory -----------------------------------------------

    pub(super) fn convert(
        &mut self,
        inst: plcc_ir::Inst,
        op: ConvOp,
        ty: Type,
        a: Value,
        r: Value,
    ) {
        let from = self.ty(a);
        if ty.is_float() || from.is_float() {
            if op == ConvOp::Bitcast {
                if let Some(d) = self.home(r) {
                    let l = self.loc(a);
                    self.copy_bytes(d, l, self.bytes(ty));
                }
                return;
            }
            self.unsupported(inst, "REAL conversion");
            return;
        }
        if ty == Type::I1 {
            // itrunc to i1 keeps bit 0.
            if let Some(d) = self.home_bit(r) {
                match Self::byte(self.loc(a), 0) {
                    Src::Lit(k) => self.copy_bit(d, BitLoc::Lit(k & 1 != 0), false),
                    s => {
                        let reg = self.reg_for(s, SCRATCH[0], Some(d.0));
                        self.copy_bit(d, BitLoc::Bit(reg, 0, false), false);
                    }
                }
            }
            return;
        }
        let Some(d) = self.home(r) else { return };
        let n = self.bytes(ty);
        if from == Type::I1 {
            for i in 1..n {
                self.i(Inst::Clrf(d + i));
            }
            match self.bit(a) {
                BitLoc::Lit(b) => {
                    self.i(Inst::Movlw(b as u8));
                    self.i(Inst::Movwf(d));
                }
                BitLoc::Bit(x, bn, neg) => {
                    self.i(Inst::Movlw(neg as u8));
                    self.i(Inst::Btfsc(x, bn));
                    self.i(Inst::Movlw(!neg as u8));
                    self.i(Inst::Movwf(d));
                }
            }
            return;
        }
        let m = self.bytes(from);
        let la = self.loc(a);
        match op {
            // REAL bits as DWORD and back, once REAL is an integer (see `softfloat`).
            ConvOp::Itrunc | ConvOp::Bitcast => self.copy_bytes(d, la, n),
            ConvOp::Uext | ConvOp::Sext => {
                self.copy_bytes(d, la, m);
                if op == ConvOp::Sext {
                    self.fill(BinaryOp::Sshr, d + m, n - m, Src::Reg(d + m - 1));
                } else {
                    for i in m..n {
                        self.i(Inst::Clrf(d + i));
                    }
                }
            }
            ConvOp::PtrToInt | ConvOp::IntToPtr => {
                self.unsupported(inst, "pointer arithmetic (CODESYS pointers as numbers)")
            }
            _ => self.unsupported(inst, "this conversion"),
        }
    }

    pub(super) fn select(&mut self, c: Value, t: Value, e: Value, r: Value) {
        let cond = self.bit(c);
        let ty = self.ty(t);
        let emit_copy = |s: &mut Self, v: Value| {
            if ty == Type::I1 {
                if let Some(d) = s.home_bit(r) {
                    let b = s.bit(v);
                    s.copy_bit(d, b, false);
                }
            } else if let Some(d) = s.home(r) {
                let l = s.loc(v);
                s.copy_bytes(d, l, s.bytes(ty));
            }
        };
        match cond {
            BitLoc::Lit(true) => emit_copy(self, t),
            BitLoc::Lit(false) => emit_copy(self, e),
            c @ BitLoc::Bit(..) => {
                let else_l = self.new_label("sel");
                let end = self.new_label("sele");
                self.i(c.skip_if_true());
                self.goto(else_l);
                emit_copy(self, t);
                self.goto(end);
                self.label(else_l);
                emit_copy(self, e);
                self.label(end);
            }
        }
    }
}
