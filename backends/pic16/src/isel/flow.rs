//! Calls, the copies on the edges of the control flow graph, jumps and branches.

use super::*;

impl Emitter<'_> {
    pub(super) fn call(&mut self, func: FuncId, args: &[Value], res: Option<Value>) {
        let callee = &self.p.module.funcs[func.index()];
        let cframe = &self.p.frames[func.index()];
        let cbase = self.p.frame_base[func.index()];
        if let Some(entry) = callee.entry() {
            let params = callee.block(entry).params.clone();
            for (p, &a) in params.iter().zip(args) {
                match cframe.repr[p.index()] {
                    Repr::Bytes(o) => {
                        let l = self.loc(a);
                        let n = self.bytes(callee.value_type(*p));
                        self.copy_bytes(cbase + o, l, n);
                    }
                    Repr::Bit(o, b) => {
                        let s = self.bit(a);
                        self.copy_bit((cbase + o, b), s, false);
                    }
                    _ => {}
                }
            }
        }
        let l = self.p.func_label[func.index()];
        self.items.push(Item::Op(Op::Call(l)));
        if let Some(r) = res {
            let ret = cbase + cframe.ret_offset;
            let t = self.ty(r);
            if t == Type::I1 {
                if let Some(d) = self.home_bit(r) {
                    self.copy_bit(d, BitLoc::Bit(ret, 0, false), false);
                }
            } else if let Some(d) = self.home(r) {
                self.copy_bytes(d, Loc::Mem(ret), self.bytes(t));
            }
        }
    }

    // ---- control flow --------------------------------------------------------------

    /// Copies branch arguments into the destination's parameters (as one parallel
    /// copy: through the frame's copy area when a destination overlaps a source).
    pub(super) fn edge_copies(&mut self, dest: &BlockCall) {
        let params = self.f.block(dest.block).params.clone();
        let mut moves: Vec<(Value, Value)> = Vec::new();
        for (p, a) in params.iter().zip(&dest.args) {
            if p != a && !matches!(self.frame.repr[p.index()], Repr::Unused) {
                moves.push((*p, *a));
            }
        }
        if moves.is_empty() {
            return;
        }
        let range = |s: &Self, mut v: Value| -> Option<(u32, u32)> {
            while let Repr::NotOf(x) = s.frame.repr[v.index()] {
                v = x;
            }
            // In bits, so BOOLs sharing a byte are told apart.
            let bytes = |a: u16, n: u16| Some((a as u32 * 8, (a + n) as u32 * 8));
            match s.frame.repr[v.index()] {
                Repr::Bytes(o) => bytes(s.base + o, s.bytes(s.ty(v))),
                Repr::Bit(o, b) => {
                    let at = (s.base + o) as u32 * 8 + b as u32;
                    Some((at, at + 1))
                }
                Repr::Ptr(Ptr::Derived(b, _, _)) => match s.frame.repr[b.index()] {
                    Repr::Bytes(o) => bytes(s.base + o, 2),
                    _ => None,
                },
                _ => None,
            }
        };
        let clash = |s: &Self, dst: Value, src: Value| match (range(s, dst), range(s, src)) {
            (Some((ps, pe)), Some((as_, ae))) => ps < ae && as_ < pe,
            _ => false,
        };
        // Sequentialise: a move may go once no other pending move still reads the
        // place it writes; a cycle (a swap) goes through the copy area.
        while !moves.is_empty() {
            let ready = (0..moves.len()).find(|&i| {
                moves
                    .iter()
                    .enumerate()
                    .all(|(j, &(_, a))| j == i || !clash(self, moves[i].0, a))
            });
            match ready {
                Some(i) => {
                    let (p, a) = moves.remove(i);
                    self.move_value(p, a);
                }
                None => break,
            }
        }
        if moves.is_empty() {
            return;
        }
        // Two phases through the copy area.
        let mut at = self.base + self.frame.copy_offset;
        let mut staged = Vec::new();
        for &(p, a) in &moves {
            let t = self.ty(p);
            if t == Type::I1 {
                let s = self.bit(a);
                self.i(Inst::Clrf(at));
                self.copy_bit((at, 0), s, false);
                staged.push((p, at));
                at += 1;
            } else {
                let n = self.bytes(t);
                let l = self.loc(a);
                self.copy_bytes(at, l, n);
                staged.push((p, at));
                at += n;
            }
        }
        for (p, from) in staged {
            let t = self.ty(p);
            if t == Type::I1 {
                if let Some(d) = self.home_bit(p) {
                    self.copy_bit(d, BitLoc::Bit(from, 0, false), false);
                }
            } else if let Some(d) = self.home(p) {
                self.copy_bytes(d, Loc::Mem(from), self.bytes(t));
            }
        }
    }

    pub(super) fn move_value(&mut self, dst: Value, src: Value) {
        let t = self.ty(dst);
        if t == Type::I1 {
            if let Some(d) = self.home_bit(dst) {
                let s = self.bit(src);
                self.copy_bit(d, s, false);
            }
        } else if let Some(d) = self.home(dst) {
            let l = self.loc(src);
            self.copy_bytes(d, l, self.bytes(t));
        }
    }

    pub(super) fn jump(&mut self, dest: &BlockCall, next: Option<Block>) {
        self.edge_copies(dest);
        if Some(dest.block) != next {
            let l = self.block_label(dest.block);
            self.goto(l);
        }
    }

    pub(super) fn has_moves(&self, d: &BlockCall) -> bool {
        let params = &self.f.block(d.block).params;
        params
            .iter()
            .zip(&d.args)
            .any(|(p, a)| p != a && !matches!(self.frame.repr[p.index()], Repr::Unused))
    }

    pub(super) fn brif(&mut self, cond: Value, t: &BlockCall, e: &BlockCall, next: Option<Block>) {
        // The test: a skip instruction that skips the next one when the condition is
        // true.
        let skip_if_true = match self.frame.repr[cond.index()] {
            Repr::Flags => {
                let (icmp_cond, args) = match self.f.inst(match self.f.value_def(cond) {
                    plcc_ir::function::ValueDef::Result(i) => i,
                    _ => unreachable!(),
                }) {
                    InstData::Icmp { cond, args } => (*cond, *args),
                    _ => unreachable!(),
                };
                let fc = self.compare(icmp_cond, args);
                if fc.when_set {
                    Inst::Btfss(reg::STATUS, fc.bit)
                } else {
                    Inst::Btfsc(reg::STATUS, fc.bit)
                }
            }
            _ => match self.bit(cond) {
                BitLoc::Lit(true) => return self.jump(t, next),
                BitLoc::Lit(false) => return self.jump(e, next),
                c @ BitLoc::Bit(..) => c.skip_if_true(),
            },
        };
        let (tm, em) = (self.has_moves(t), self.has_moves(e));
        if !em && !tm && Some(e.block) == next && Some(t.block) != next {
            // The false side follows: test the other way and jump only when true.
            let skip_if_false = match skip_if_true {
                Inst::Btfss(f, b) => Inst::Btfsc(f, b),
                Inst::Btfsc(f, b) => Inst::Btfss(f, b),
                other => unreachable!("a bit test, not {other:?}"),
            };
            self.i(skip_if_false);
            let l = self.block_label(t.block);
            self.goto(l);
            return;
        }
        let else_target = if em {
            self.new_label("else")
        } else {
            self.block_label(e.block)
        };
        // False falls into `goto else`; true skips it.
        self.i(skip_if_true);
        self.goto(else_target);
        self.jump(t, if em { None } else { next });
        if em {
            self.label(else_target);
            self.jump(e, next);
        }
    }

    /// `br_table arg, default, [table]` as a computed GOTO: the index (read unsigned)
    /// is checked against the table's length, then `PCLATH:W := table + index` and
    /// `MOVWF PCL` land on the index's `GOTO` in a table that follows. `PCLATH<4:3>`
    /// keeps the unit's page (the table lies in the unit, which no page boundary
    /// crosses); its low bits only matter to writes of PCL. An entry whose edge copies
    /// values jumps to a stub that copies them first.
    pub(super) fn br_table(
        &mut self,
        arg: Value,
        default: &BlockCall,
        table: &[BlockCall],
        next: Option<Block>,
    ) {
        let n = self.bytes(self.ty(arg));
        let loc = self.loc(arg);
        if let Loc::Lit(k) = loc {
            let k = (k & mask(n)) as usize;
            return self.jump(table.get(k).unwrap_or(default), next);
        }
        let mut stubs: Vec<(Label, &BlockCall)> = Vec::new();
        let target = |this: &mut Self, d: &'_ BlockCall| {
            if this.has_moves(d) {
                let l = this.new_label("edge");
                (l, true)
            } else {
                (this.block_label(d.block), false)
            }
        };
        let (dflt, stub) = target(self, default);
        if stub {
            stubs.push((dflt, default));
        }
        'table: {
            // An index with a byte above the first set is past the table.
            for i in (1..n).rev() {
                match Self::byte(loc, i) {
                    Src::Lit(0) => {}
                    Src::Lit(_) => {
                        self.goto(dflt);
                        break 'table;
                    }
                    s => {
                        self.load_w(s);
                        self.i(Inst::Btfss(reg::STATUS, reg::Z));
                        self.goto(dflt);
                    }
                }
            }
            let lo = self.reg_for(Self::byte(loc, 0), SCRATCH[0], None);
            if table.len() < 256 {
                // W := lo - len: no borrow (C set) when the index is past the table.
                self.i(Inst::Movlw(table.len() as u8));
                self.i(Inst::Subwf(lo, Dest::W));
                self.i(Inst::Btfsc(reg::STATUS, reg::C));
                self.goto(dflt);
            }
            let tab = self.new_label("table");
            self.items.push(Item::Op(Op::MovlwAddr(tab, true)));
            self.i(Inst::Movwf(reg::PCLATH));
            self.items.push(Item::Op(Op::MovlwAddr(tab, false)));
            self.i(Inst::Addwf(lo, Dest::W));
            self.i(Inst::Btfsc(reg::STATUS, reg::C));
            self.i(Inst::Incf(reg::PCLATH, Dest::F));
            self.i(Inst::Movwf(reg::PCL));
            self.label(tab);
            for d in table {
                let (l, stub) = target(self, d);
                if stub {
                    stubs.push((l, d));
                }
                self.items.push(Item::Op(Op::TableGoto(l)));
            }
        }
        for (l, d) in stubs {
            self.label(l);
            self.jump(d, None);
        }
    }
}
