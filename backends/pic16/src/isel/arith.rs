//! Arithmetic: negation, addition and subtraction with the carry idioms, the bit operations, multiply and divide through the helpers, shifts.

use super::*;

impl Emitter<'_> {
    pub(super) fn unary(&mut self, inst: plcc_ir::Inst, op: UnaryOp, a: Value, r: Value) {
        let t = self.ty(a);
        if t == Type::I1 {
            if matches!(self.frame.repr[r.index()], Repr::NotOf(_)) {
                return;
            }
            if let (UnaryOp::Bnot, Some(d)) = (op, self.home_bit(r)) {
                let s = self.bit(a);
                self.copy_bit(d, s, true);
            }
            return;
        }
        if !op.is_int_op() {
            self.unsupported(inst, "REAL arithmetic");
            return;
        }
        let Some(d) = self.home(r) else { return };
        let n = self.bytes(t);
        let la = self.loc(a);
        match op {
            UnaryOp::Bnot => {
                for i in 0..n {
                    match Self::byte(la, i) {
                        Src::Reg(x) => self.i(Inst::Comf(x, Dest::W)),
                        s => {
                            self.load_w(s);
                            self.i(Inst::Xorlw(0xFF));
                        }
                    }
                    self.i(Inst::Movwf(d + i));
                }
            }
            UnaryOp::Ineg => {
                self.copy_bytes(d, la, n);
                self.negate_in_place(d, n);
            }
            UnaryOp::Iabs => {
                self.copy_bytes(d, la, n);
                let done = self.new_label("abs");
                self.i(Inst::Btfss(d + n - 1, 7));
                self.goto(done);
                self.negate_in_place(d, n);
                self.label(done);
            }
            _ => unreachable!(),
        }
    }

    pub(super) fn negate_in_place(&mut self, d: u16, n: u16) {
        for i in 0..n {
            self.i(Inst::Comf(d + i, Dest::F));
        }
        self.increment_in_place(d, n);
    }

    pub(super) fn increment_in_place(&mut self, d: u16, n: u16) {
        if n == 1 {
            self.i(Inst::Incf(d, Dest::F));
            return;
        }
        if n == 2 {
            self.i(Inst::Incf(d, Dest::F));
            self.i(Inst::Btfsc(reg::STATUS, reg::Z));
            self.i(Inst::Incf(d + 1, Dest::F));
            return;
        }
        self.carry_chain(d, 0, n);
    }

    /// Adds one to bytes `from..n` of `d` as one number, stopping at the first byte
    /// that does not wrap to zero.
    pub(super) fn carry_chain(&mut self, d: u16, from: u16, n: u16) {
        let done = self.new_label("inc");
        for i in from..n {
            if i + 1 == n {
                self.i(Inst::Incf(d + i, Dest::F));
            } else {
                self.i(Inst::Incfsz(d + i, Dest::F));
                self.goto(done);
            }
        }
        self.label(done);
    }

    /// `d += s` over `n` bytes, the carry chained.
    pub(super) fn add_in_place(&mut self, d: u16, s: Loc, n: u16) {
        if let Loc::Lit(k) = s {
            let k = k & mask(n);
            if k == 0 {
                return;
            }
            if k == 1 {
                self.increment_in_place(d, n);
                return;
            }
            if k < 256 && n > 1 {
                // Only the low byte adds; the carry ripples up.
                self.i(Inst::Movlw(k as u8));
                self.i(Inst::Addwf(d, Dest::F));
                if n == 2 {
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incf(d + 1, Dest::F));
                    return;
                }
                let no_carry = self.new_label("cy");
                self.i(Inst::Btfss(reg::STATUS, reg::C));
                self.goto(no_carry);
                self.carry_chain(d, 1, n);
                self.label(no_carry);
                return;
            }
        }
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                self.i(Inst::Addwf(d, Dest::F));
                continue;
            }
            match src {
                Src::Lit(0) if i + 1 == n => {
                    // The carry out of the top byte is not needed.
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incf(d + i, Dest::F));
                }
                Src::Lit(k) => {
                    if k == 0xFF {
                        self.i(Inst::Movlw(0xFF));
                        self.i(Inst::Btfss(reg::STATUS, reg::C));
                        self.i(Inst::Addwf(d + i, Dest::F));
                    } else {
                        self.i(Inst::Movlw(k));
                        self.i(Inst::Btfsc(reg::STATUS, reg::C));
                        self.i(Inst::Movlw(k + 1));
                        self.i(Inst::Addwf(d + i, Dest::F));
                    }
                }
                _ => {
                    let r = self.reg_for(src, SCRATCH[0], Some(d + i));
                    self.i(Inst::Movf(r, Dest::W));
                    self.i(Inst::Btfsc(reg::STATUS, reg::C));
                    self.i(Inst::Incfsz(r, Dest::W));
                    self.i(Inst::Addwf(d + i, Dest::F));
                }
            }
        }
    }

    /// `d -= s` over `n` bytes, the borrow chained (C = 1: no borrow).
    pub(super) fn sub_in_place(&mut self, d: u16, s: Loc, n: u16) {
        if let Loc::Lit(k) = s {
            self.add_in_place(d, Loc::Lit(k.wrapping_neg()), n);
            return;
        }
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                self.i(Inst::Subwf(d, Dest::F));
                continue;
            }
            let r = self.reg_for(src, SCRATCH[0], Some(d + i));
            self.i(Inst::Movf(r, Dest::W));
            self.i(Inst::Btfss(reg::STATUS, reg::C));
            self.i(Inst::Incfsz(r, Dest::W));
            self.i(Inst::Subwf(d + i, Dest::F));
        }
    }

    pub(super) fn binary(&mut self, inst: plcc_ir::Inst, op: BinaryOp, args: [Value; 2], r: Value) {
        let t = self.ty(args[0]);
        if !op.is_int_op() {
            self.unsupported(inst, "REAL arithmetic");
            return;
        }
        if t == Type::I1 {
            self.binary_bits(op, args, r);
            return;
        }
        let n = self.bytes(t);
        let (a, b) = (self.loc(args[0]), self.loc(args[1]));
        let Some(d) = self.home(r) else {
            // A division whose result is unused still raises the fault on zero.
            if op.can_fault() {
                if let Loc::Lit(0) = b {
                    self.i(Inst::Bsf(self.p.rt.flags, crate::runtime::FAULT_BIT));
                } else if !matches!(b, Loc::Lit(_)) {
                    let ok = self.new_label("nz");
                    self.test_zero(b, n);
                    self.i(Inst::Btfss(reg::STATUS, reg::Z));
                    self.goto(ok);
                    self.i(Inst::Bsf(self.p.rt.flags, crate::runtime::FAULT_BIT));
                    self.label(ok);
                }
            }
            return;
        };
        match op {
            BinaryOp::Iadd => {
                // The second operand may be the destination itself (`v := k * w + v`,
                // with v used in place): adding into it leaves it unread by the copy.
                let (x, y) = if matches!(a, Loc::Lit(_)) || b == Loc::Mem(d) {
                    (b, a)
                } else {
                    (a, b)
                };
                self.copy_bytes(d, x, n);
                self.add_in_place(d, y, n);
            }
            BinaryOp::Isub => {
                self.copy_bytes(d, a, n);
                self.sub_in_place(d, b, n);
            }
            BinaryOp::Band | BinaryOp::Bor | BinaryOp::Bxor => {
                for i in 0..n {
                    let (x, y) = (Self::byte(a, i), Self::byte(b, i));
                    let (x, y) = if matches!(x, Src::Lit(_)) {
                        (y, x)
                    } else {
                        (x, y)
                    };
                    match (op, y) {
                        (BinaryOp::Band, Src::Lit(0)) => {
                            self.i(Inst::Clrf(d + i));
                            continue;
                        }
                        (BinaryOp::Band, Src::Lit(0xFF))
                        | (BinaryOp::Bor, Src::Lit(0))
                        | (BinaryOp::Bxor, Src::Lit(0)) => {
                            self.load_w(x);
                        }
                        (_, Src::Lit(k)) => {
                            self.load_w(x);
                            self.i(match op {
                                BinaryOp::Band => Inst::Andlw(k),
                                BinaryOp::Bor => Inst::Iorlw(k),
                                _ => Inst::Xorlw(k),
                            });
                        }
                        _ => {
                            let yr = self.reg_for(y, SCRATCH[0], None);
                            self.load_w(x);
                            self.i(match op {
                                BinaryOp::Band => Inst::Andwf(yr, Dest::W),
                                BinaryOp::Bor => Inst::Iorwf(yr, Dest::W),
                                _ => Inst::Xorwf(yr, Dest::W),
                            });
                        }
                    }
                    self.i(Inst::Movwf(d + i));
                }
            }
            BinaryOp::Imul => {
                if let Loc::Lit(k) = b {
                    let k = k & mask(n);
                    if k.is_power_of_two() {
                        self.shift_const(BinaryOp::Ishl, d, a, n, k.trailing_zeros());
                        return;
                    }
                }
                if let Loc::Lit(k) = a {
                    let k = k & mask(n);
                    if k.is_power_of_two() {
                        self.shift_const(BinaryOp::Ishl, d, b, n, k.trailing_zeros());
                        return;
                    }
                }
                self.helpers.mul = self.helpers.mul.max(n);
                let ws = self.p.ws;
                self.copy_bytes(ws.a, a, n);
                self.copy_bytes(ws.b, b, n);
                let l = self
                    .helpers
                    .label(self.labels, crate::helpers::Helper::Mul(n));
                self.items.push(Item::Op(Op::Call(l)));
                self.copy_bytes(d, Loc::Mem(ws.r), n);
            }
            BinaryOp::Udiv | BinaryOp::Urem | BinaryOp::Sdiv | BinaryOp::Srem => {
                self.divide(op, d, a, b, n)
            }
            BinaryOp::Ishl | BinaryOp::Ushr | BinaryOp::Sshr | BinaryOp::Rotl | BinaryOp::Rotr => {
                let bits = 8 * n as u32;
                match b {
                    Loc::Lit(k) => {
                        let nb = self.bytes(self.ty(args[1]));
                        let k = k & mask(nb);
                        let c = if matches!(op, BinaryOp::Rotl | BinaryOp::Rotr) {
                            (k % bits as u64) as u32
                        } else {
                            k.min(bits as u64) as u32
                        };
                        self.shift_const(op, d, a, n, c);
                    }
                    _ => {
                        let nb = self.bytes(self.ty(args[1]));
                        self.shift_var(op, d, a, b, n, nb);
                    }
                }
            }
            _ => unreachable!(),
        }
    }

    pub(super) fn binary_bits(&mut self, op: BinaryOp, args: [Value; 2], r: Value) {
        let Some(d) = self.home_bit(r) else { return };
        let (a, b) = (self.bit(args[0]), self.bit(args[1]));
        let (a, b) = if matches!(a, BitLoc::Lit(_)) {
            (b, a)
        } else {
            (a, b)
        };
        match (op, b) {
            (BinaryOp::Band, BitLoc::Lit(false)) => self.i(Inst::Bcf(d.0, d.1)),
            (BinaryOp::Bor, BitLoc::Lit(true)) => self.i(Inst::Bsf(d.0, d.1)),
            (BinaryOp::Band, BitLoc::Lit(true))
            | (BinaryOp::Bor, BitLoc::Lit(false))
            | (BinaryOp::Bxor, BitLoc::Lit(false)) => self.copy_bit(d, a, false),
            (BinaryOp::Bxor, BitLoc::Lit(true)) => self.copy_bit(d, a, true),
            (_, b @ BitLoc::Bit(..)) => {
                let BitLoc::Bit(ab, an, aneg) = a else {
                    unreachable!()
                };
                let BitLoc::Bit(bb, bn, bneg) = b else {
                    unreachable!()
                };
                let is_d = |x: (u16, u8), n: bool| x == d && !n;
                let touches_d = (ab, an) == d || (bb, bn) == d;
                match op {
                    BinaryOp::Band if is_d((ab, an), aneg) => {
                        self.skip_then(b.skip_if_true(), Inst::Bcf(d.0, d.1))
                    }
                    BinaryOp::Band if is_d((bb, bn), bneg) => {
                        self.skip_then(a.skip_if_true(), Inst::Bcf(d.0, d.1))
                    }
                    BinaryOp::Bor if is_d((ab, an), aneg) => {
                        self.skip_then(b.skip_if_false(), Inst::Bsf(d.0, d.1))
                    }
                    BinaryOp::Bor if is_d((bb, bn), bneg) => {
                        self.skip_then(a.skip_if_false(), Inst::Bsf(d.0, d.1))
                    }
                    BinaryOp::Band if !touches_d => {
                        self.i(Inst::Bsf(d.0, d.1));
                        self.skip_then(a.skip_if_true(), Inst::Bcf(d.0, d.1));
                        self.skip_then(b.skip_if_true(), Inst::Bcf(d.0, d.1));
                    }
                    BinaryOp::Bor if !touches_d => {
                        self.i(Inst::Bcf(d.0, d.1));
                        self.skip_then(a.skip_if_false(), Inst::Bsf(d.0, d.1));
                        self.skip_then(b.skip_if_false(), Inst::Bsf(d.0, d.1));
                    }
                    _ => {
                        // Through W: W = the result (0 or 1), then Z.
                        match op {
                            BinaryOp::Band => {
                                self.i(Inst::Movlw(0));
                                self.i(a.skip_if_false());
                                self.i(Inst::Movlw(1));
                                self.i(b.skip_if_true());
                                self.i(Inst::Movlw(0));
                            }
                            BinaryOp::Bor => {
                                self.i(Inst::Movlw(0));
                                self.i(a.skip_if_false());
                                self.i(Inst::Movlw(1));
                                self.i(b.skip_if_false());
                                self.i(Inst::Movlw(1));
                            }
                            _ => {
                                self.i(Inst::Movlw((aneg != bneg) as u8));
                                self.i(Inst::Btfsc(ab, an));
                                self.i(Inst::Xorlw(1));
                                self.i(Inst::Btfsc(bb, bn));
                                self.i(Inst::Xorlw(1));
                            }
                        }
                        self.i(Inst::Andlw(1));
                        self.i(Inst::Bcf(d.0, d.1));
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.i(Inst::Bsf(d.0, d.1));
                    }
                }
            }
            _ => unreachable!(),
        }
    }

    pub(super) fn test_zero(&mut self, s: Loc, n: u16) {
        for i in 0..n {
            let src = Self::byte(s, i);
            if i == 0 {
                self.load_w(src);
                if !matches!(src, Src::Reg(_)) {
                    self.i(Inst::Iorlw(0));
                }
            } else {
                let r = self.reg_for(src, SCRATCH[0], None);
                self.i(Inst::Iorwf(r, Dest::W));
            }
        }
    }

    pub(super) fn divide(&mut self, op: BinaryOp, d: u16, a: Loc, b: Loc, n: u16) {
        let flags = self.p.rt.flags;
        let signed = matches!(op, BinaryOp::Sdiv | BinaryOp::Srem);
        let want_rem = matches!(op, BinaryOp::Urem | BinaryOp::Srem);
        if let Loc::Lit(k) = b {
            let k = k & mask(n);
            if k == 0 {
                self.i(Inst::Bsf(flags, crate::runtime::FAULT_BIT));
                for i in 0..n {
                    self.i(Inst::Clrf(d + i));
                }
                return;
            }
            if !signed && k.is_power_of_two() {
                if want_rem {
                    self.binary_const_and(d, a, n, k - 1);
                } else {
                    self.shift_const(BinaryOp::Ushr, d, a, n, k.trailing_zeros());
                }
                return;
            }
            let positive = k < 1u64 << (8 * n as u32 - 1);
            if signed && want_rem && positive && k.is_power_of_two() {
                // The remainder takes the dividend's sign: mask |a|, then restore it.
                self.copy_bytes(d, a, n);
                let pos = self.new_label("pos");
                let done = self.new_label("rem");
                self.i(Inst::Btfss(d + n - 1, 7));
                self.goto(pos);
                self.negate_in_place(d, n);
                self.binary_const_and(d, Loc::Mem(d), n, k - 1);
                self.negate_in_place(d, n);
                self.goto(done);
                self.label(pos);
                self.binary_const_and(d, Loc::Mem(d), n, k - 1);
                self.label(done);
                return;
            }
            if signed && !want_rem && positive && k.is_power_of_two() {
                // Toward zero: a negative dividend is biased by k - 1 before the
                // arithmetic shift.
                self.copy_bytes(d, a, n);
                if k > 1 {
                    let pos = self.new_label("pos");
                    self.i(Inst::Btfss(d + n - 1, 7));
                    self.goto(pos);
                    self.add_in_place(d, Loc::Lit(k - 1), n);
                    self.label(pos);
                    self.shift_const(BinaryOp::Sshr, d, Loc::Mem(d), n, k.trailing_zeros());
                }
                return;
            }
        }
        let done = self.new_label("div");
        if !matches!(b, Loc::Lit(_)) {
            let ok = self.new_label("nz");
            self.test_zero(b, n);
            self.i(Inst::Btfss(reg::STATUS, reg::Z));
            self.goto(ok);
            self.i(Inst::Bsf(flags, crate::runtime::FAULT_BIT));
            for i in 0..n {
                self.i(Inst::Clrf(d + i));
            }
            self.goto(done);
            self.label(ok);
        }
        let ws = self.p.ws;
        self.helpers.div = self.helpers.div.max(n);
        self.copy_bytes(ws.a, a, n);
        self.copy_bytes(ws.b, b, n);
        let sign = SCRATCH[5];
        if signed {
            // sign bit 0: result negative; |a|, |b| into the workspace.
            self.i(Inst::Clrf(sign));
            let pa = self.new_label("pa");
            self.i(Inst::Btfss(ws.a + n - 1, 7));
            self.goto(pa);
            self.negate_in_place(ws.a, n);
            self.i(Inst::Incf(sign, Dest::F));
            self.label(pa);
            let pb = self.new_label("pb");
            self.i(Inst::Btfss(ws.b + n - 1, 7));
            self.goto(pb);
            self.negate_in_place(ws.b, n);
            if !want_rem {
                self.i(Inst::Incf(sign, Dest::F));
            }
            self.label(pb);
        }
        let l = self
            .helpers
            .label(self.labels, crate::helpers::Helper::Div(n));
        self.items.push(Item::Op(Op::Call(l)));
        let res = if want_rem { ws.r } else { ws.a };
        self.copy_bytes(d, Loc::Mem(res), n);
        if signed {
            let pos = self.new_label("pos");
            self.i(Inst::Btfss(sign, 0));
            self.goto(pos);
            self.negate_in_place(d, n);
            self.label(pos);
        }
        self.label(done);
    }

    pub(super) fn binary_const_and(&mut self, d: u16, a: Loc, n: u16, k: u64) {
        for i in 0..n {
            let kb = (k >> (8 * i)) as u8;
            if kb == 0 {
                self.i(Inst::Clrf(d + i));
            } else {
                self.load_w(Self::byte(a, i));
                if kb != 0xFF {
                    self.i(Inst::Andlw(kb));
                }
                self.i(Inst::Movwf(d + i));
            }
        }
    }

    /// One-bit shift or rotate of `d` in place.
    pub(super) fn shift1(&mut self, op: BinaryOp, d: u16, n: u16) {
        let top = d + n - 1;
        match op {
            BinaryOp::Ishl => {
                self.i(Inst::Bcf(reg::STATUS, reg::C));
                for i in 0..n {
                    self.i(Inst::Rlf(d + i, Dest::F));
                }
            }
            BinaryOp::Rotl => {
                self.i(Inst::Rlf(top, Dest::W));
                for i in 0..n {
                    self.i(Inst::Rlf(d + i, Dest::F));
                }
            }
            BinaryOp::Ushr => {
                self.i(Inst::Bcf(reg::STATUS, reg::C));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            BinaryOp::Sshr => {
                self.i(Inst::Rlf(top, Dest::W));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            BinaryOp::Rotr => {
                self.i(Inst::Rrf(d, Dest::W));
                for i in (0..n).rev() {
                    self.i(Inst::Rrf(d + i, Dest::F));
                }
            }
            _ => unreachable!(),
        }
    }

    pub(super) fn fill(&mut self, op: BinaryOp, d: u16, n: u16, sign_from: Src) {
        if op == BinaryOp::Sshr {
            let t = self.reg_for(sign_from, SCRATCH[1], None);
            self.i(Inst::Movlw(0));
            self.i(Inst::Btfsc(t, 7));
            self.i(Inst::Movlw(0xFF));
            for i in 0..n {
                self.i(Inst::Movwf(d + i));
            }
        } else {
            for i in 0..n {
                self.i(Inst::Clrf(d + i));
            }
        }
    }

    pub(super) fn shift_const(&mut self, op: BinaryOp, d: u16, a: Loc, n: u16, c: u32) {
        let bits = 8 * n as u32;
        let top = Self::byte(a, n - 1);
        if c >= bits {
            self.fill(op, d, n, top);
            return;
        }
        let (q, r) = ((c / 8) as u16, c % 8);
        // Whole bytes first, straight from the operand.
        match op {
            BinaryOp::Ishl => {
                for i in (0..n).rev() {
                    if i >= q {
                        let s = Self::byte(a, i - q);
                        self.copy_src(d + i, s);
                    } else {
                        self.i(Inst::Clrf(d + i));
                    }
                }
            }
            BinaryOp::Ushr | BinaryOp::Sshr => {
                for i in 0..n {
                    if i + q < n {
                        let s = Self::byte(a, i + q);
                        self.copy_src(d + i, s);
                    }
                }
                if q > 0 {
                    self.fill(op, d + n - q, q, top);
                }
            }
            BinaryOp::Rotl | BinaryOp::Rotr => {
                for i in 0..n {
                    let from = if op == BinaryOp::Rotl {
                        (i + n - q) % n
                    } else {
                        (i + q) % n
                    };
                    let s = Self::byte(a, from);
                    self.copy_src(d + i, s);
                }
            }
            _ => unreachable!(),
        }
        for _ in 0..r {
            self.shift1(op, d, n);
        }
    }

    pub(super) fn copy_src(&mut self, d: u16, s: Src) {
        match s {
            Src::Lit(0) => self.i(Inst::Clrf(d)),
            Src::Reg(r) if r == d => {}
            _ => {
                self.load_w(s);
                self.i(Inst::Movwf(d));
            }
        }
    }

    pub(super) fn shift_var(&mut self, op: BinaryOp, d: u16, a: Loc, c: Loc, n: u16, nc: u16) {
        let bits = 8 * n as u8;
        let cnt = SCRATCH[2];
        let done = self.new_label("sh");
        let lp = self.new_label("shl");
        self.copy_bytes(d, a, n);
        self.load_w(Self::byte(c, 0));
        self.i(Inst::Movwf(cnt));
        if matches!(op, BinaryOp::Rotl | BinaryOp::Rotr) {
            self.i(Inst::Movlw(bits - 1));
            self.i(Inst::Andwf(cnt, Dest::F));
        } else {
            let big = self.new_label("big");
            for i in 1..nc {
                let r = self.reg_for(Self::byte(c, i), SCRATCH[0], None);
                self.i(Inst::Movf(r, Dest::W));
                self.i(Inst::Btfss(reg::STATUS, reg::Z));
                self.goto(big);
            }
            self.i(Inst::Movlw(bits));
            self.i(Inst::Subwf(cnt, Dest::W));
            let small = self.new_label("small");
            self.i(Inst::Btfss(reg::STATUS, reg::C));
            self.goto(small);
            self.label(big);
            self.fill(op, d, n, Src::Reg(d + n - 1));
            self.goto(done);
            self.label(small);
        }
        self.i(Inst::Movf(cnt, Dest::F));
        self.i(Inst::Btfsc(reg::STATUS, reg::Z));
        self.goto(done);
        self.label(lp);
        self.shift1(op, d, n);
        self.i(Inst::Decfsz(cnt, Dest::F));
        self.goto(lp);
        self.label(done);
    }
}
