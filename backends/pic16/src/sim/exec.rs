//! What each decoded instruction does to the core: the run loop's `exec`, the plain
//! instructions, and the slow path of special registers.

use super::*;

impl Core {
    // ---- the instructions ----------------------------------------------------------

    /// Executes `op`, the instruction at `h.pc` (a fused op: both instructions, unless
    /// the cycle counter reaches `next` after the first).
    #[inline(always)]
    pub(super) fn exec(&mut self, h: &mut Hot, op: Op) -> Result<(), Exit> {
        use Kind as K;
        let at = h.pc;
        h.pc = (at + 1) & 0x1FFF;
        let k = op.b;
        // A fused pair: the first instruction, its cycle, and the second unless the
        // first skipped it or the run loop has to check first.
        macro_rules! pair {
            ($first:ident, $second:ident) => {{
                self.simple(h, K::$first, op.a, op.b);
                h.cycles += 1;
                if h.pc != (at + 1) & 0x1FFF || h.cycles >= self.next {
                    return Ok(());
                }
                h.pc = (h.pc + 1) & 0x1FFF;
                self.simple(h, K::$second, op.a2, op.b2);
            }};
        }
        match op.kind {
            K::AddwfW => self.simple(h, K::AddwfW, op.a, k),
            K::AddwfF => self.simple(h, K::AddwfF, op.a, k),
            K::AndwfW => self.simple(h, K::AndwfW, op.a, k),
            K::AndwfF => self.simple(h, K::AndwfF, op.a, k),
            K::Clrf => self.simple(h, K::Clrf, op.a, k),
            K::Clrw => self.simple(h, K::Clrw, op.a, k),
            K::ComfW => self.simple(h, K::ComfW, op.a, k),
            K::ComfF => self.simple(h, K::ComfF, op.a, k),
            K::DecfW => self.simple(h, K::DecfW, op.a, k),
            K::DecfF => self.simple(h, K::DecfF, op.a, k),
            K::DecfszW => self.simple(h, K::DecfszW, op.a, k),
            K::DecfszF => self.simple(h, K::DecfszF, op.a, k),
            K::IncfW => self.simple(h, K::IncfW, op.a, k),
            K::IncfF => self.simple(h, K::IncfF, op.a, k),
            K::IncfszW => self.simple(h, K::IncfszW, op.a, k),
            K::IncfszF => self.simple(h, K::IncfszF, op.a, k),
            K::IorwfW => self.simple(h, K::IorwfW, op.a, k),
            K::IorwfF => self.simple(h, K::IorwfF, op.a, k),
            K::MovfW => self.simple(h, K::MovfW, op.a, k),
            K::MovfF => self.simple(h, K::MovfF, op.a, k),
            K::Movwf => self.simple(h, K::Movwf, op.a, k),
            K::Nop => self.simple(h, K::Nop, op.a, k),
            K::RlfW => self.simple(h, K::RlfW, op.a, k),
            K::RlfF => self.simple(h, K::RlfF, op.a, k),
            K::RrfW => self.simple(h, K::RrfW, op.a, k),
            K::RrfF => self.simple(h, K::RrfF, op.a, k),
            K::SubwfW => self.simple(h, K::SubwfW, op.a, k),
            K::SubwfF => self.simple(h, K::SubwfF, op.a, k),
            K::SwapfW => self.simple(h, K::SwapfW, op.a, k),
            K::SwapfF => self.simple(h, K::SwapfF, op.a, k),
            K::XorwfW => self.simple(h, K::XorwfW, op.a, k),
            K::XorwfF => self.simple(h, K::XorwfF, op.a, k),
            K::Bcf => self.simple(h, K::Bcf, op.a, k),
            K::Bsf => self.simple(h, K::Bsf, op.a, k),
            K::Btfsc => self.simple(h, K::Btfsc, op.a, k),
            K::Btfss => self.simple(h, K::Btfss, op.a, k),
            K::BcfStatus => self.simple(h, K::BcfStatus, op.a, k),
            K::BsfStatus => self.simple(h, K::BsfStatus, op.a, k),
            K::BtfscStatus => self.simple(h, K::BtfscStatus, op.a, k),
            K::BtfssStatus => self.simple(h, K::BtfssStatus, op.a, k),
            K::BcfZ => self.simple(h, K::BcfZ, op.a, k),
            K::BsfZ => self.simple(h, K::BsfZ, op.a, k),
            K::BtfscZ => self.simple(h, K::BtfscZ, op.a, k),
            K::BtfssZ => self.simple(h, K::BtfssZ, op.a, k),
            K::MovfWIndf => self.simple(h, K::MovfWIndf, op.a, k),
            K::MovwfIndf => self.simple(h, K::MovwfIndf, op.a, k),
            K::Addlw => self.simple(h, K::Addlw, op.a, k),
            K::Andlw => self.simple(h, K::Andlw, op.a, k),
            K::Iorlw => self.simple(h, K::Iorlw, op.a, k),
            K::Xorlw => self.simple(h, K::Xorlw, op.a, k),
            K::Movlw => self.simple(h, K::Movlw, op.a, k),
            K::Sublw => self.simple(h, K::Sublw, op.a, k),
            K::Goto => self.simple(h, K::Goto, op.a, k),
            K::Clrwdt => self.simple(h, K::Clrwdt, op.a, k),
            K::Call => {
                if let Err(e) = self.push(h.pc as u16, at) {
                    h.pc = at;
                    return Err(Exit::Fault(e));
                }
                h.pc = usize::from(self.ram[PCLATH as usize] & 0x18) << 8 | usize::from(op.a);
                h.cycles += 1;
            }
            K::Return | K::Retlw | K::Retfie => {
                let name = match op.kind {
                    K::Return => "RETURN",
                    K::Retlw => "RETLW",
                    _ => "RETFIE",
                };
                match self.pop(name, at) {
                    Ok(ret) => h.pc = usize::from(ret),
                    Err(e) => {
                        h.pc = at;
                        return Err(Exit::Fault(e));
                    }
                }
                if op.kind == K::Retlw {
                    h.w = k;
                } else if op.kind == K::Retfie {
                    self.ram[INTCON as usize] |= 0x80;
                    self.irq_changed(h.cycles + 1);
                    self.next = 0;
                }
                h.cycles += 1;
            }
            K::Slow => {
                self.h = *h;
                self.exec_slow(op.a);
                *h = self.h;
            }
            K::Sleep => {
                h.pc = at;
                return Err(Exit::Fault(err_at("SLEEP executed", at)));
            }
            K::Invalid => {
                h.pc = at;
                return Err(Exit::Fault(invalid(op.a, at)));
            }
            K::Break => {
                h.pc = at;
                return Err(Exit::Break);
            }
            K::MovfWMovwf => pair!(MovfW, Movwf),
            K::MovwfMovfW => pair!(Movwf, MovfW),
            K::AddwfFMovfW => pair!(AddwfF, MovfW),
            K::RlfFRlfF => pair!(RlfF, RlfF),
            K::BcfStatusRlfF => pair!(BcfStatus, RlfF),
            K::MovwfGoto => pair!(Movwf, Goto),
            K::MovfWXorlw => pair!(MovfW, Xorlw),
            K::MovwfClrf => pair!(Movwf, Clrf),
            K::MovfWAddwfF => pair!(MovfW, AddwfF),
            K::ClrfMovfW => pair!(Clrf, MovfW),
            K::MovwfIncfF => pair!(Movwf, IncfF),
            K::MovfWBtfscStatus => pair!(MovfW, BtfscStatus),
            K::MovwfMovlw => pair!(Movwf, Movlw),
            K::ClrfClrf => pair!(Clrf, Clrf),
            K::IncfFMovfW => pair!(IncfF, MovfW),
            K::MovlwAddwfF => pair!(Movlw, AddwfF),
            K::MovfWSublw => pair!(MovfW, Sublw),
            K::MovfWBtfscZ => pair!(MovfW, BtfscZ),
            K::BcfBtfsc => pair!(Bcf, Btfsc),
            K::SublwBtfssStatus => pair!(Sublw, BtfssStatus),
            K::MovwfBcfStatus => pair!(Movwf, BcfStatus),
            K::SubwfFMovfW => pair!(SubwfF, MovfW),
            K::RlfFDecfszF => pair!(RlfF, DecfszF),
            K::RrfFBtfssStatus => pair!(RrfF, BtfssStatus),
            K::BcfStatusRrfF => pair!(BcfStatus, RrfF),
            K::MovfWBtfssStatus => pair!(MovfW, BtfssStatus),
            K::XorlwMovwf => pair!(Xorlw, Movwf),
            K::MovlwMovwf => pair!(Movlw, Movwf),
            K::MovfWSubwfF => pair!(MovfW, SubwfF),
            K::AndlwMovwf => pair!(Andlw, Movwf),
            K::MovfWAndlw => pair!(MovfW, Andlw),
            K::MovfWSubwfW => pair!(MovfW, SubwfW),
            K::RlfFBtfscStatus => pair!(RlfF, BtfscStatus),
            K::SubwfFBtfscStatus => pair!(SubwfF, BtfscStatus),
            K::MovfWBtfssZ => pair!(MovfW, BtfssZ),
            K::IncfFGoto => pair!(IncfF, Goto),
            K::MovwfBsf => pair!(Movwf, Bsf),
            K::MovwfBcf => pair!(Movwf, Bcf),
            K::MovfWIndfMovwf => pair!(MovfWIndf, Movwf),
            K::BcfStatusBtfsc => pair!(BcfStatus, Btfsc),
            K::IncfFBtfscZ => pair!(IncfF, BtfscZ),
            K::AddwfFGoto => pair!(AddwfF, Goto),
            K::AddwfWMovwf => pair!(AddwfW, Movwf),
            K::IncfFMovfWIndf => pair!(IncfF, MovfWIndf),
            K::BsfBtfss => pair!(Bsf, Btfss),
            K::MovlwAddwfW => pair!(Movlw, AddwfW),
            K::SubwfWBtfssZ => pair!(SubwfW, BtfssZ),
            K::RlfFMovlw => pair!(RlfF, Movlw),
            K::MovlwSubwfW => pair!(Movlw, SubwfW),
            K::BcfBtfssStatus => pair!(Bcf, BtfssStatus),
            K::SublwBtfssZ => pair!(Sublw, BtfssZ),
            K::BcfBtfssZ => pair!(Bcf, BtfssZ),
            K::BcfBtfss => pair!(Bcf, Btfss),
            K::MovlwBtfscStatus => pair!(Movlw, BtfscStatus),
            K::MovlwBtfssStatus => pair!(Movlw, BtfssStatus),
            K::DecfszFGoto => pair!(DecfszF, Goto),
            K::BtfssZGoto => pair!(BtfssZ, Goto),
            K::BtfscStatusGoto => pair!(BtfscStatus, Goto),
            K::BtfssStatusGoto => pair!(BtfssStatus, Goto),
            K::IncfszWAddwfF => pair!(IncfszW, AddwfF),
            K::IncfszWSubwfF => pair!(IncfszW, SubwfF),
            K::BtfssBcf => pair!(Btfss, Bcf),
            K::BtfssGoto => pair!(Btfss, Goto),
        }
        h.cycles += 1;
        Ok(())
    }

    /// Executes an instruction that cannot fail (`kind` a constant where inlined): its
    /// operands `a`, `k` (see [`Op`]); `h.pc` already points past it.
    #[inline(always)]
    pub(super) fn simple(&mut self, h: &mut Hot, kind: Kind, target: u16, k: u8) {
        use Kind as K;
        let a = usize::from(target) & (RAM_SIZE - 1);
        match kind {
            K::AddwfW => h.w = h.add(self.ram[a], h.w),
            K::AddwfF => self.ram[a] = h.add(self.ram[a], h.w),
            K::AndwfW => {
                h.w &= self.ram[a];
                h.zv = h.w;
            }
            K::AndwfF => {
                let r = self.ram[a] & h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::Clrf => {
                self.ram[a] = 0;
                h.zv = 0;
            }
            K::Clrw => {
                h.w = 0;
                h.zv = 0;
            }
            K::ComfW => {
                h.w = !self.ram[a];
                h.zv = h.w;
            }
            K::ComfF => {
                let r = !self.ram[a];
                self.ram[a] = r;
                h.zv = r;
            }
            K::DecfW => {
                h.w = self.ram[a].wrapping_sub(1);
                h.zv = h.w;
            }
            K::DecfF => {
                let r = self.ram[a].wrapping_sub(1);
                self.ram[a] = r;
                h.zv = r;
            }
            K::DecfszW => {
                h.w = self.ram[a].wrapping_sub(1);
                if h.w == 0 {
                    skip(h);
                }
            }
            K::DecfszF => {
                let r = self.ram[a].wrapping_sub(1);
                self.ram[a] = r;
                if r == 0 {
                    skip(h);
                }
            }
            K::IncfW => {
                h.w = self.ram[a].wrapping_add(1);
                h.zv = h.w;
            }
            K::IncfF => {
                let r = self.ram[a].wrapping_add(1);
                self.ram[a] = r;
                h.zv = r;
            }
            K::IncfszW => {
                h.w = self.ram[a].wrapping_add(1);
                if h.w == 0 {
                    skip(h);
                }
            }
            K::IncfszF => {
                let r = self.ram[a].wrapping_add(1);
                self.ram[a] = r;
                if r == 0 {
                    skip(h);
                }
            }
            K::IorwfW => {
                h.w |= self.ram[a];
                h.zv = h.w;
            }
            K::IorwfF => {
                let r = self.ram[a] | h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::MovfW => {
                h.w = self.ram[a];
                h.zv = h.w;
            }
            K::MovfF => h.zv = self.ram[a],
            K::Movwf => self.ram[a] = h.w,
            K::Nop => {}
            K::RlfW => {
                let v = self.ram[a];
                h.w = v << 1 | (h.st & C);
                h.set_c(v >> 7);
            }
            K::RlfF => {
                let v = self.ram[a];
                self.ram[a] = v << 1 | (h.st & C);
                h.set_c(v >> 7);
            }
            K::RrfW => {
                let v = self.ram[a];
                h.w = v >> 1 | (h.st & C) << 7;
                h.set_c(v & 1);
            }
            K::RrfF => {
                let v = self.ram[a];
                self.ram[a] = v >> 1 | (h.st & C) << 7;
                h.set_c(v & 1);
            }
            K::SubwfW => h.w = h.sub(self.ram[a], h.w),
            K::SubwfF => self.ram[a] = h.sub(self.ram[a], h.w),
            K::SwapfW => h.w = self.ram[a].rotate_left(4),
            K::SwapfF => self.ram[a] = self.ram[a].rotate_left(4),
            K::XorwfW => {
                h.w ^= self.ram[a];
                h.zv = h.w;
            }
            K::XorwfF => {
                let r = self.ram[a] ^ h.w;
                self.ram[a] = r;
                h.zv = r;
            }
            K::Bcf => self.ram[a] &= !k,
            K::Bsf => self.ram[a] |= k,
            K::Btfsc => {
                if self.ram[a] & k == 0 {
                    skip(h);
                }
            }
            K::Btfss => {
                if self.ram[a] & k != 0 {
                    skip(h);
                }
            }
            K::BcfStatus => h.set_st(h.st & !k),
            K::BsfStatus => h.set_st(h.st | k),
            K::BtfscStatus => {
                if h.st & k == 0 {
                    skip(h);
                }
            }
            K::BtfssStatus => {
                if h.st & k != 0 {
                    skip(h);
                }
            }
            K::BcfZ => h.zv = 1,
            K::BsfZ => h.zv = 0,
            K::BtfscZ => {
                if h.zv != 0 {
                    skip(h);
                }
            }
            K::BtfssZ => {
                if h.zv == 0 {
                    skip(h);
                }
            }
            K::MovfWIndf => {
                h.w = self.rd_indf(h);
                h.zv = h.w;
            }
            K::MovwfIndf => self.wr_indf(h, h.w, false),
            K::Addlw => h.w = h.add(k, h.w),
            K::Andlw => {
                h.w &= k;
                h.zv = h.w;
            }
            K::Iorlw => {
                h.w |= k;
                h.zv = h.w;
            }
            K::Xorlw => {
                h.w ^= k;
                h.zv = h.w;
            }
            K::Movlw => h.w = k,
            K::Sublw => h.w = h.sub(k, h.w),
            K::Goto => {
                h.pc = usize::from(self.ram[PCLATH as usize] & 0x18) << 8 | usize::from(target);
                h.cycles += 1;
            }
            K::Clrwdt => h.st |= 0x18,
            _ => unreachable!("{kind:?} is no simple instruction"),
        }
    }

    /// Executes a byte- or bit-oriented instruction `word` on any file address (the
    /// instruction's cycle is counted by the caller, `h.pc` already points past it).
    #[inline(never)]
    pub(super) fn exec_slow(&mut self, word: u16) {
        let mut h = self.h;
        self.exec_file_op(&mut h, word);
        self.h = h;
    }

    pub(super) fn exec_file_op(&mut self, h: &mut Hot, word: u16) {
        use Inst::*;
        let Some(i) = Inst::decode(word) else {
            unreachable!("slow op 0x{word:04X} is no instruction");
        };
        match i {
            Addwf(f, d)
            | Andwf(f, d)
            | Comf(f, d)
            | Decf(f, d)
            | Incf(f, d)
            | Iorwf(f, d)
            | Movf(f, d)
            | Rlf(f, d)
            | Rrf(f, d)
            | Subwf(f, d)
            | Xorwf(f, d) => {
                // The flags first: a write to STATUS keeps them (and takes its other
                // bits from the result), so the order does not matter.
                let a = h.addr(f);
                let v = self.rd(h, a);
                let r = match i {
                    Addwf(..) => h.add(v, h.w),
                    Subwf(..) => h.sub(v, h.w),
                    Rlf(..) => {
                        let r = v << 1 | (h.st & C);
                        h.set_c(v >> 7);
                        r
                    }
                    Rrf(..) => {
                        let r = v >> 1 | (h.st & C) << 7;
                        h.set_c(v & 1);
                        r
                    }
                    _ => {
                        let r = match i {
                            Andwf(..) => v & h.w,
                            Comf(..) => !v,
                            Decf(..) => v.wrapping_sub(1),
                            Incf(..) => v.wrapping_add(1),
                            Iorwf(..) => v | h.w,
                            Xorwf(..) => v ^ h.w,
                            _ => v,
                        };
                        h.zv = r;
                        r
                    }
                };
                if d == Dest::W {
                    h.w = r;
                } else {
                    self.wr(h, a, r, true);
                }
            }
            Decfsz(f, d) | Incfsz(f, d) | Swapf(f, d) => {
                let a = h.addr(f);
                let v = self.rd(h, a);
                let r = match i {
                    Decfsz(..) => v.wrapping_sub(1),
                    Incfsz(..) => v.wrapping_add(1),
                    _ => v.rotate_left(4),
                };
                if d == Dest::W {
                    h.w = r;
                } else {
                    self.wr(h, a, r, false);
                }
                if r == 0 && !matches!(i, Swapf(..)) {
                    skip(h);
                }
            }
            Clrf(f) => {
                self.wr(h, h.addr(f), 0, true);
                h.zv = 0;
            }
            Movwf(f) => self.wr(h, h.addr(f), h.w, false),
            Bcf(f, b) | Bsf(f, b) => {
                let a = h.addr(f);
                let m = 1u8 << (b & 7);
                let v = self.rd(h, a);
                let r = if matches!(i, Bcf(..)) { v & !m } else { v | m };
                self.wr(h, a, r, false);
            }
            Btfsc(f, b) | Btfss(f, b) => {
                let set = self.rd(h, h.addr(f)) & 1 << (b & 7) != 0;
                if set == matches!(i, Btfss(..)) {
                    skip(h);
                }
            }
            _ => unreachable!("slow op 0x{word:04X} is no file operation"),
        }
    }
}

/// Skips the next instruction: one extra cycle.
#[inline(always)]
fn skip(h: &mut Hot) {
    h.pc = (h.pc + 1) & 0x1FFF;
    h.cycles += 1;
}
