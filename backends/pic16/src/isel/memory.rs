//! Loads and stores through known addresses or FSR/INDF.

use super::*;

impl Emitter<'_> {
    /// Points FSR (and IRP) at a dynamic pointer plus `add`.
    pub(super) fn point_fsr(&mut self, p: Loc, add: u16) {
        let lo = Self::byte(p, 0);
        self.load_w(lo);
        let k = add as u8;
        if k != 0 {
            self.i(Inst::Addlw(k));
        }
        self.i(Inst::Movwf(reg::FSR));
        match Self::byte(p, 1) {
            Src::Lit(h) => self.items.push(Item::Op(Op::Irp(h & 1 != 0))),
            Src::Reg(r) | Src::Add(r, _) => {
                self.i(Inst::Bcf(reg::STATUS, reg::IRP));
                self.skip_then(Inst::Btfsc(r, 0), Inst::Bsf(reg::STATUS, reg::IRP));
            }
        }
    }

    /// The address form of a pointer operand: a fixed address with its bit, or a
    /// pointer in RAM plus a constant offset with the bit if it is known.
    pub(super) fn addr_of(&self, p: Value) -> Result<(u16, u8), (Loc, u16, Option<u8>)> {
        match self.frame.repr[p.index()] {
            Repr::Ptr(Ptr::Known(s, o, b)) => {
                let v = self.p.ptr_value(s, o, b);
                Ok((v & 0x1FF, (v >> 9) as u8 & 7))
            }
            Repr::Ptr(Ptr::Derived(base, o, b)) => Err((self.loc(base), o, b)),
            _ => Err((self.loc(p), 0, None)),
        }
    }

    pub(super) fn bitmask_from(&mut self, p: Loc) {
        // W := 1 << bit, the bit number from the pointer's high byte.
        self.load_w(Self::byte(p, 1));
        let l = self
            .helpers
            .label(self.labels, crate::helpers::Helper::BitMask);
        self.items.push(Item::Op(Op::Call(l)));
    }

    pub(super) fn load(&mut self, ty: Type, addr: Value, r: Value) {
        match self.addr_of(addr) {
            Ok((a, bit)) => {
                if ty == Type::I1 {
                    if let Some(d) = self.home_bit(r) {
                        self.copy_bit(d, BitLoc::Bit(a, bit, false), false);
                    }
                } else if let Some(d) = self.home(r) {
                    self.copy_bytes(d, Loc::Mem(a), self.bytes(ty));
                }
            }
            Err((p, off, bit)) => {
                if ty == Type::I1 {
                    let Some(d) = self.home_bit(r) else { return };
                    match bit {
                        Some(b) => {
                            self.point_fsr(p, off);
                            self.copy_bit(d, BitLoc::Bit(reg::INDF, b, false), false);
                        }
                        None => {
                            self.bitmask_from(p);
                            self.i(Inst::Movwf(SCRATCH[3]));
                            self.point_fsr(p, off);
                            self.i(Inst::Movf(SCRATCH[3], Dest::W));
                            self.i(Inst::Andwf(reg::INDF, Dest::W));
                            self.i(Inst::Bcf(d.0, d.1));
                            self.i(Inst::Btfss(reg::STATUS, reg::Z));
                            self.i(Inst::Bsf(d.0, d.1));
                        }
                    }
                    return;
                }
                let Some(d) = self.home(r) else { return };
                self.point_fsr(p, off);
                let n = self.bytes(ty);
                for i in 0..n {
                    self.i(Inst::Movf(reg::INDF, Dest::W));
                    self.i(Inst::Movwf(d + i));
                    if i + 1 < n {
                        self.i(Inst::Incf(reg::FSR, Dest::F));
                    }
                }
            }
        }
    }

    pub(super) fn store(&mut self, v: Value, addr: Value) {
        let ty = self.ty(v);
        match self.addr_of(addr) {
            Ok((a, bit)) => {
                if ty == Type::I1 {
                    let s = self.bit(v);
                    self.copy_bit((a, bit), s, false);
                } else {
                    let l = self.loc(v);
                    self.copy_bytes(a, l, self.bytes(ty));
                }
            }
            Err((p, off, bit)) => {
                if ty == Type::I1 {
                    let s = self.bit(v);
                    match bit {
                        Some(b) => {
                            self.point_fsr(p, off);
                            self.copy_bit((reg::INDF, b), s, false);
                        }
                        None => {
                            self.bitmask_from(p);
                            self.i(Inst::Movwf(SCRATCH[3]));
                            self.point_fsr(p, off);
                            self.i(Inst::Movf(SCRATCH[3], Dest::W));
                            match s {
                                BitLoc::Lit(true) => self.i(Inst::Iorwf(reg::INDF, Dest::F)),
                                BitLoc::Lit(false) => {
                                    self.i(Inst::Xorlw(0xFF));
                                    self.i(Inst::Andwf(reg::INDF, Dest::F));
                                }
                                x @ BitLoc::Bit(..) => {
                                    let set = self.new_label("bs");
                                    let end = self.new_label("be");
                                    self.i(x.skip_if_false());
                                    self.goto(set);
                                    self.i(Inst::Xorlw(0xFF));
                                    self.i(Inst::Andwf(reg::INDF, Dest::F));
                                    self.goto(end);
                                    self.label(set);
                                    self.i(Inst::Iorwf(reg::INDF, Dest::F));
                                    self.label(end);
                                }
                            }
                        }
                    }
                    return;
                }
                let l = self.loc(v);
                self.point_fsr(p, off);
                let n = self.bytes(ty);
                for i in 0..n {
                    self.load_w(Self::byte(l, i));
                    self.i(Inst::Movwf(reg::INDF));
                    if i + 1 < n {
                        self.i(Inst::Incf(reg::FSR, Dest::F));
                    }
                }
            }
        }
    }
}
