//! Random functions shaped like naive front-end output (locals in stack slots,
//! variables in structs reached through pointers and globals, every statement
//! reloading what it reads, IF/WHILE/RETURN with dead blocks after RETURN, CASE as a
//! `br_table`, calls that write memory, divisions that may fault), run by the
//! reference interpreter before and after each pass, after the whole driver, and
//! after what the targets without an indirect jump run then (value ranges, the jump
//! tables as compares). Results, fault flags and the final contents of memory must
//! agree, and the IR must verify after every pass.

use super::{back_edges, verify, PASSES};
use crate::builder::FuncBuilder;
use crate::entities::{AggId, DataId, FuncId, SlotId, Value};
use crate::function::{FuncKind, Function};
use crate::inst::{BinaryOp, BlockCall, ConvOp, FloatCC, IntCC, UnaryOp};
use crate::interp::Interp;
use crate::machine::Machine;
use crate::module::{
    AggDef, ArrayDef, DataDef, DataKind, Field, FieldRole, Module, StructDef, StructKind,
};
use crate::types::{ElemType, MemType, Type};

use crate::rng::Rng;

/// Field types of the struct `%S` (index = field number); the last field is `arr`.
const FIELDS: [(Type, ElemType); 7] = [
    (Type::I32, ElemType::DInt),
    (Type::I16, ElemType::Int),
    (Type::I8, ElemType::SInt),
    (Type::I1, ElemType::Bool),
    (Type::F32, ElemType::Real),
    (Type::I64, ElemType::LInt),
    (Type::I32, ElemType::DInt),
];
const ARR_FIELD: u32 = FIELDS.len() as u32;
/// `recs: [2 x %R]` with `%R = { x: i32, y: i16 }`: an array of structs, where a
/// variable index leaves only the field to tell two accesses apart.
const RECS_FIELD: u32 = ARR_FIELD + 1;
const RECS_LEN: u32 = 2;
const REC_FIELDS: [Type; 2] = [Type::I32, Type::I16];
const ARR_LEN: u32 = 4;
const TYPES: [Type; 6] = [
    Type::I1,
    Type::I8,
    Type::I16,
    Type::I32,
    Type::I64,
    Type::F32,
];

/// Where a variable lives.
#[derive(Copy, Clone)]
enum Base {
    /// Parameter `p` (the test passes @g).
    P,
    /// Parameter `q` (@h, or @g again: aliasing).
    Q,
    /// `global_addr @g`.
    G,
    /// A local `%S` in a stack slot (never promoted: an aggregate).
    L,
    /// A pointer variable (a `ptr` stack slot) pointing at one of the others.
    R,
}

const BASES: [Base; 5] = [Base::P, Base::Q, Base::G, Base::L, Base::R];

#[derive(Copy, Clone)]
enum Place {
    Slot(SlotId, Type),
    Field(Base, u32),
    Elem(Base, Option<u32>),
    /// `recs[index].field`
    Rec(Base, Option<u32>, u32),
}

struct Ctx {
    s: AggId,
    a: AggId,
    r: AggId,
    ra: AggId,
    g: DataId,
    bump: FuncId,
}

struct Gen<'a, 'f> {
    rng: &'a mut Rng,
    b: FuncBuilder<'f>,
    cx: &'a Ctx,
    slots: Vec<(SlotId, Type)>,
    /// The local struct (`Base::L`) and the pointer variable (`Base::R`).
    local: SlotId,
    ptr_var: SlotId,
    params: Vec<Value>,
    depth: u32,
    budget: u32,
    /// Whether RETURN may appear in the middle (off for the throughput measurement,
    /// where it would make most code dead).
    early_return: bool,
}

impl Gen<'_, '_> {
    fn place_type(&self, p: Place) -> Type {
        match p {
            Place::Slot(_, t) => t,
            Place::Field(_, f) => FIELDS[f as usize].0,
            Place::Elem(..) => Type::I32,
            Place::Rec(_, _, f) => REC_FIELDS[f as usize],
        }
    }

    fn base(&mut self, base: Base) -> Value {
        match base {
            Base::P => self.params[2],
            Base::Q => self.params[3],
            Base::G => self.b.global_addr(self.cx.g),
            Base::L => self.b.slot_addr(self.local),
            Base::R => {
                let a = self.b.slot_addr(self.ptr_var);
                self.b.load(Type::Ptr, a)
            }
        }
    }

    /// The address of a place, recomputed at every access as a naive front end does.
    fn addr(&mut self, p: Place) -> Value {
        match p {
            Place::Slot(s, _) => self.b.slot_addr(s),
            Place::Field(base, f) => {
                let bv = self.base(base);
                self.b.field_addr(bv, self.cx.s, f)
            }
            Place::Elem(base, idx) => {
                let bv = self.base(base);
                let arr = self.b.field_addr(bv, self.cx.s, ARR_FIELD);
                let i = match idx {
                    Some(k) => self.b.iconst(Type::I32, k as i64),
                    None => {
                        // Any value, reduced into range the way a checked index is.
                        let x = self.expr(Type::I32);
                        let n = self.b.iconst(Type::I32, ARR_LEN as i64);
                        self.b.binary(BinaryOp::Urem, x, n)
                    }
                };
                self.b.elem_addr(arr, self.cx.a, i)
            }
            Place::Rec(base, idx, f) => {
                let bv = self.base(base);
                let recs = self.b.field_addr(bv, self.cx.s, RECS_FIELD);
                let i = match idx {
                    Some(k) => self.b.iconst(Type::I32, k as i64),
                    None => {
                        let x = self.expr(Type::I32);
                        let n = self.b.iconst(Type::I32, RECS_LEN as i64);
                        self.b.binary(BinaryOp::Urem, x, n)
                    }
                };
                let rec = self.b.elem_addr(recs, self.cx.ra, i);
                self.b.field_addr(rec, self.cx.r, f)
            }
        }
    }

    fn random_place(&mut self, ty: Option<Type>) -> Option<Place> {
        for _ in 0..20 {
            let p = match self.rng.below(5) {
                4 => Place::Rec(
                    *self.rng.pick(&BASES),
                    if self.rng.chance(40) {
                        Some(self.rng.below(RECS_LEN as u64) as u32)
                    } else {
                        None
                    },
                    self.rng.below(REC_FIELDS.len() as u64) as u32,
                ),
                0 if !self.slots.is_empty() => {
                    let (s, t) = *self.rng.pick(&self.slots);
                    Place::Slot(s, t)
                }
                1 => Place::Elem(
                    *self.rng.pick(&BASES),
                    if self.rng.chance(60) {
                        Some(self.rng.below(ARR_LEN as u64) as u32)
                    } else {
                        None
                    },
                ),
                _ => Place::Field(
                    *self.rng.pick(&BASES),
                    self.rng.below(FIELDS.len() as u64) as u32,
                ),
            };
            if ty.is_none_or(|t| t == self.place_type(p)) {
                return Some(p);
            }
        }
        None
    }

    fn konst(&mut self, ty: Type) -> Value {
        if ty == Type::F32 {
            let x = *self
                .rng
                .pick(&[0.0f32, -0.0, 1.0, -1.5, 2.5, 0.1, 1e30, -7.0, 3.5, 65536.0]);
            return self.b.f32const(x);
        }
        let w = ty.bits();
        let x = match self.rng.below(8) {
            0 => 0,
            1 => 1,
            2 => -1,
            3 => 1i64 << (w - 1).min(62),
            4 => w as i64,
            5 => self.rng.below(10) as i64,
            6 => 1 << self.rng.below(w as u64),
            _ => self.rng.next_u64() as i64,
        };
        self.b.iconst(ty, x)
    }

    fn expr(&mut self, ty: Type) -> Value {
        self.depth += 1;
        let v = self.expr_inner(ty);
        self.depth -= 1;
        v
    }

    fn expr_inner(&mut self, ty: Type) -> Value {
        let leaf = self.depth > 3 || self.budget == 0 || self.rng.chance(30);
        self.budget = self.budget.saturating_sub(1);
        if leaf {
            return match self.rng.below(3) {
                0 => self.konst(ty),
                1 => match self.random_place(Some(ty)) {
                    Some(p) => {
                        let a = self.addr(p);
                        self.b.load(ty, a)
                    }
                    None => self.konst(ty),
                },
                _ => {
                    let x = self.params[self.rng.below(2) as usize];
                    self.of_i32(x, ty)
                }
            };
        }
        match ty {
            Type::I1 => match self.rng.below(6) {
                0 | 1 => {
                    let t = *self.rng.pick(&TYPES[1..5]);
                    let (x, y) = (self.expr(t), self.expr(t));
                    let cc = *self.rng.pick(&IntCC::ALL);
                    self.b.icmp(cc, x, y)
                }
                2 => {
                    let (x, y) = (self.expr(Type::F32), self.expr(Type::F32));
                    let cc = *self.rng.pick(&FloatCC::ALL);
                    self.b.fcmp(cc, x, y)
                }
                3 => {
                    let x = self.expr(Type::I1);
                    self.b.unary(UnaryOp::Bnot, x)
                }
                4 => {
                    let (x, y) = (self.expr(Type::I1), self.expr(Type::I1));
                    let op = *self
                        .rng
                        .pick(&[BinaryOp::Band, BinaryOp::Bor, BinaryOp::Bxor]);
                    self.b.binary(op, x, y)
                }
                _ => self.select(ty),
            },
            Type::F32 => match self.rng.below(5) {
                0 | 1 => {
                    let (x, y) = (self.expr(ty), self.expr(ty));
                    let op = *self.rng.pick(&[
                        BinaryOp::Fadd,
                        BinaryOp::Fsub,
                        BinaryOp::Fmul,
                        BinaryOp::Fdiv,
                    ]);
                    self.b.binary(op, x, y)
                }
                2 => {
                    let x = self.expr(ty);
                    let op = *self.rng.pick(&[
                        UnaryOp::Fneg,
                        UnaryOp::Fabs,
                        UnaryOp::Fsqrt,
                        UnaryOp::Fnearest,
                        UnaryOp::Ftrunc,
                        UnaryOp::Ffloor,
                        UnaryOp::Fceil,
                    ]);
                    self.b.unary(op, x)
                }
                3 => {
                    let x = self.expr(Type::I32);
                    let op = *self.rng.pick(&[ConvOp::SiToF, ConvOp::UiToF]);
                    self.b.convert(op, ty, x)
                }
                _ => self.select(ty),
            },
            _ => match self.rng.below(8) {
                0..=2 => {
                    let (x, y) = (self.expr(ty), self.expr(ty));
                    let op = *self.rng.pick(&BinaryOp::ALL[..15]);
                    self.b.binary(op, x, y)
                }
                3 => {
                    // Operations with one constant operand exercise the identities.
                    let x = self.expr(ty);
                    let k = self.konst(ty);
                    let op = *self.rng.pick(&BinaryOp::ALL[..15]);
                    if self.rng.chance(50) {
                        self.b.binary(op, x, k)
                    } else {
                        self.b.binary(op, k, x)
                    }
                }
                4 => {
                    let x = self.expr(ty);
                    let op = *self
                        .rng
                        .pick(&[UnaryOp::Ineg, UnaryOp::Bnot, UnaryOp::Iabs]);
                    self.b.unary(op, x)
                }
                5 => {
                    let from = *self.rng.pick(&TYPES);
                    let x = self.expr(from);
                    self.convert(x, from, ty)
                }
                6 if ty == Type::I32 && self.rng.chance(30) => {
                    let base = *self.rng.pick(&BASES);
                    let p = self.base(base);
                    self.b.call(self.cx.bump, Some(Type::I32), vec![p]).unwrap()
                }
                _ => self.select(ty),
            },
        }
    }

    fn select(&mut self, ty: Type) -> Value {
        let c = self.expr(Type::I1);
        let x = self.expr(ty);
        let y = if self.rng.chance(20) {
            x
        } else {
            self.expr(ty)
        };
        self.b.select(c, x, y)
    }

    fn of_i32(&mut self, x: Value, ty: Type) -> Value {
        self.convert(x, Type::I32, ty)
    }

    fn convert(&mut self, x: Value, from: Type, to: Type) -> Value {
        if from == to {
            return x;
        }
        if from.is_float() {
            let op = *self.rng.pick(&[ConvOp::FToSi, ConvOp::FToUi]);
            if to == Type::I1 {
                let z = self.b.f32const(0.0);
                return self.b.fcmp(FloatCC::Ne, x, z);
            }
            return self.b.convert(op, to, x);
        }
        if to.is_float() {
            let x = if from == Type::I1 {
                self.b.convert(ConvOp::Uext, Type::I32, x)
            } else {
                x
            };
            let op = *self.rng.pick(&[ConvOp::SiToF, ConvOp::UiToF]);
            return self.b.convert(op, to, x);
        }
        if to.bits() < from.bits() {
            if to == Type::I1 {
                let z = self.b.iconst(from, 0);
                return self.b.icmp(IntCC::Ne, x, z);
            }
            self.b.convert(ConvOp::Itrunc, to, x)
        } else {
            let op = if from == Type::I1 || self.rng.chance(50) {
                ConvOp::Uext
            } else {
                ConvOp::Sext
            };
            self.b.convert(op, to, x)
        }
    }

    fn stmts(&mut self, n: u32, loops: u32) {
        for _ in 0..n {
            self.budget = 12;
            match self.rng.below(13) {
                0..=5 => {
                    if let Some(p) = self.random_place(None) {
                        let ty = self.place_type(p);
                        let v = self.expr(ty);
                        let a = self.addr(p);
                        self.b.store(v, a);
                    }
                }
                6 | 7 if self.depth_ok() => {
                    let c = self.expr(Type::I1);
                    let (t, e, j) = (
                        self.b.create_block(),
                        self.b.create_block(),
                        self.b.create_block(),
                    );
                    self.b.brif(c, t, vec![], e, vec![]);
                    self.b.switch_to(t);
                    self.nested(|g| g.stmts(2, loops));
                    self.b.jump(j, vec![]);
                    self.b.switch_to(e);
                    if self.rng.chance(50) {
                        self.nested(|g| g.stmts(2, loops));
                    }
                    self.b.jump(j, vec![]);
                    self.b.switch_to(j);
                }
                8 if loops > 0 && self.depth_ok() && self.rng.chance(50) => {
                    self.stepped_loop(loops);
                }
                8 if loops > 0 && self.depth_ok() => {
                    // cnt := k; WHILE cnt > 0 DO ...; cnt := cnt - 1; END_WHILE
                    let cnt = self.b.slot("cnt", MemType::Scalar(Type::I16));
                    let k = self.b.iconst(Type::I16, 1 + self.rng.below(3) as i64);
                    let a = self.b.slot_addr(cnt);
                    self.b.store(k, a);
                    let (h, body, exit) = (
                        self.b.create_block(),
                        self.b.create_block(),
                        self.b.create_block(),
                    );
                    self.b.jump(h, vec![]);
                    self.b.switch_to(h);
                    let a = self.b.slot_addr(cnt);
                    let c = self.b.load(Type::I16, a);
                    let z = self.b.iconst(Type::I16, 0);
                    let go = self.b.icmp(IntCC::Sgt, c, z);
                    self.b.brif(go, body, vec![], exit, vec![]);
                    self.b.switch_to(body);
                    self.nested(|g| g.stmts(2, loops - 1));
                    let a = self.b.slot_addr(cnt);
                    let c = self.b.load(Type::I16, a);
                    let one = self.b.iconst(Type::I16, 1);
                    let d = self.b.binary(BinaryOp::Isub, c, one);
                    let a = self.b.slot_addr(cnt);
                    self.b.store(d, a);
                    self.b.jump(h, vec![]);
                    self.b.switch_to(exit);
                }
                12 if self.depth_ok() => self.switch(loops),
                9 if self.early_return && self.rng.chance(30) => {
                    // RETURN in the middle: the rest goes to a dead block.
                    let v = self.expr(Type::I32);
                    self.b.ret(Some(v));
                }
                11 if self.rng.chance(40) => {
                    // R := ADR(somewhere else)
                    let base = *self.rng.pick(&[Base::P, Base::Q, Base::G, Base::L]);
                    let p = self.base(base);
                    let a = self.b.slot_addr(self.ptr_var);
                    self.b.store(p, a);
                }
                10 => {
                    let base = *self.rng.pick(&BASES);
                    let p = self.base(base);
                    self.b.call(self.cx.bump, Some(Type::I32), vec![p]);
                }
                _ => {
                    let v = self.expr(Type::I32);
                    let p = self
                        .random_place(Some(Type::I32))
                        .unwrap_or(Place::Field(Base::P, 0));
                    let a = self.addr(p);
                    self.b.store(v, a);
                }
            }
        }
    }

    /// A CASE as a jump table: `br_table` on an expression less a small constant (now
    /// and then a constant: it folds), whose entries go to 1–3 arms or to the ELSE
    /// part; the first arm takes an `i32` argument, which differs between entries, and
    /// stores it.
    /// `cnt := start; WHILE cnt < k DO ...; n := n + 1; IF n > 3 THEN EXIT;
    /// END_IF; cnt := cnt + step; END_WHILE` with `start` and `step` random
    /// expressions: the loops the watchdog pass copies without checks (bounded by
    /// `n`, whatever the step).
    fn stepped_loop(&mut self, loops: u32) {
        let ty = Type::I16;
        let (cnt, step, n) = (
            self.b.slot("cnt", MemType::Scalar(ty)),
            self.b.slot("step", MemType::Scalar(ty)),
            self.b.slot("n", MemType::Scalar(ty)),
        );
        for (slot, v) in [
            (cnt, self.expr(ty)),
            (step, self.expr(ty)),
            (n, self.b.iconst(ty, 0)),
        ] {
            let a = self.b.slot_addr(slot);
            self.b.store(v, a);
        }
        let (h, body, latch, exit) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        self.b.jump(h, vec![]);
        self.b.switch_to(h);
        let a = self.b.slot_addr(cnt);
        let c = self.b.load(ty, a);
        let k = self.b.iconst(ty, 1 + self.rng.below(4) as i64);
        let go = self.b.icmp(IntCC::Slt, c, k);
        self.b.brif(go, body, vec![], exit, vec![]);
        self.b.switch_to(body);
        self.nested(|g| g.stmts(2, loops - 1));
        let a = self.b.slot_addr(n);
        let t = self.b.load(ty, a);
        let one = self.b.iconst(ty, 1);
        let t = self.b.binary(BinaryOp::Iadd, t, one);
        self.b.store(t, a);
        let three = self.b.iconst(ty, 3);
        let stop = self.b.icmp(IntCC::Sgt, t, three);
        self.b.brif(stop, exit, vec![], latch, vec![]);
        self.b.switch_to(latch);
        let a = self.b.slot_addr(cnt);
        let c = self.b.load(ty, a);
        let s = self.b.slot_addr(step);
        let s = self.b.load(ty, s);
        let next = self.b.binary(BinaryOp::Iadd, c, s);
        self.b.store(next, a);
        self.b.jump(h, vec![]);
        self.b.switch_to(exit);
    }

    fn switch(&mut self, loops: u32) {
        let ty = *self.rng.pick(&[Type::I8, Type::I16, Type::I32]);
        let sel = if self.rng.chance(20) {
            self.b.iconst(ty, self.rng.range(-2, 9) as i64)
        } else {
            let x = self.expr(ty);
            let k = self.b.iconst(ty, self.rng.range(-3, 3) as i64);
            self.b.binary(BinaryOp::Isub, x, k)
        };
        let args = [self.expr(Type::I32), self.konst(Type::I32)];
        let arms: Vec<_> = (0..1 + self.rng.below(3))
            .map(|_| self.b.create_block())
            .collect();
        let param = self.b.block_param(arms[0], Type::I32);
        let (e, j) = (self.b.create_block(), self.b.create_block());
        let dest = |g: &mut Self| {
            let k = g.rng.index(arms.len() + 1);
            match k {
                0 => BlockCall::new(arms[0], vec![*g.rng.pick(&args)]),
                k if k < arms.len() => BlockCall::new(arms[k], vec![]),
                _ => BlockCall::new(e, vec![]),
            }
        };
        let table = (0..1 + self.rng.below(8)).map(|_| dest(self)).collect();
        let default = if self.rng.chance(70) {
            BlockCall::new(e, vec![])
        } else {
            dest(self)
        };
        self.b.br_table(sel, default, table);
        for (k, &arm) in arms.iter().enumerate() {
            self.b.switch_to(arm);
            if k == 0 {
                if let Some(p) = self.random_place(Some(Type::I32)) {
                    let a = self.addr(p);
                    self.b.store(param, a);
                }
            }
            self.nested(|g| g.stmts(1, loops));
            self.b.jump(j, vec![]);
        }
        self.b.switch_to(e);
        if self.rng.chance(50) {
            self.nested(|g| g.stmts(1, loops));
        }
        self.b.jump(j, vec![]);
        self.b.switch_to(j);
    }

    fn depth_ok(&self) -> bool {
        self.depth < 3
    }

    fn nested(&mut self, f: impl FnOnce(&mut Self)) {
        self.depth += 1;
        f(self);
        self.depth -= 1;
    }
}

/// The fixed part of every module: `%S`, `@g`, `@h`, `@bump(ptr) -> i32` (increments
/// field 0 and returns its old value) and `@init(ptr, i32, i32)` (fills a struct).
fn skeleton() -> (Module, Ctx, FuncId) {
    let mut m = Module::new();
    let a = m.add_agg(AggDef::Array(ArrayDef {
        name: "A".into(),
        elem: MemType::Scalar(Type::I32),
        elem_type: Some(ElemType::DInt),
        len: ARR_LEN,
        lower: 0,
    }));
    let mut fields: Vec<Field> = FIELDS
        .iter()
        .enumerate()
        .map(|(k, &(t, e))| Field {
            name: format!("f{k}"),
            ty: MemType::Scalar(t),
            elem: Some(e),
            role: FieldRole::Var,
            location: None,
        })
        .collect();
    fields.push(Field {
        name: "arr".into(),
        ty: MemType::Agg(a),
        elem: None,
        role: FieldRole::Var,
        location: None,
    });
    let r = m.add_agg(AggDef::Struct(StructDef {
        name: "R".into(),
        kind: StructKind::Struct,
        fields: vec![
            Field {
                name: "x".into(),
                ty: MemType::Scalar(Type::I32),
                elem: Some(ElemType::DInt),
                role: FieldRole::Var,
                location: None,
            },
            Field {
                name: "y".into(),
                ty: MemType::Scalar(Type::I16),
                elem: Some(ElemType::Int),
                role: FieldRole::Var,
                location: None,
            },
        ],
    }));
    let ra = m.add_agg(AggDef::Array(ArrayDef {
        name: "RA".into(),
        elem: MemType::Agg(r),
        elem_type: None,
        len: RECS_LEN,
        lower: 0,
    }));
    fields.push(Field {
        name: "recs".into(),
        ty: MemType::Agg(ra),
        elem: None,
        role: FieldRole::Var,
        location: None,
    });
    let s = m.add_agg(AggDef::Struct(StructDef {
        name: "S".into(),
        kind: StructKind::Struct,
        fields,
    }));
    let data = |name: &str| DataDef {
        name: name.into(),
        ty: MemType::Agg(s),
        elem: None,
        kind: DataKind::Global,
        location: None,
    };
    let g = m.add_data(data("g"));
    m.add_data(data("h"));

    let mut f = Function::new("bump", FuncKind::Function, vec![Type::Ptr], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let p = b.params()[0];
        let a0 = b.field_addr(p, s, 0);
        let x = b.load(Type::I32, a0);
        let one = b.iconst(Type::I32, 1);
        let y = b.binary(BinaryOp::Iadd, x, one);
        b.store(y, a0);
        b.ret(Some(x));
    }
    let bump = m.add_func(f);

    let mut f = Function::new(
        "init",
        FuncKind::Function,
        vec![Type::Ptr, Type::I32, Type::I32],
        None,
    );
    {
        let mut b = FuncBuilder::new(&mut f);
        let ps = b.params();
        let (p, x, y) = (ps[0], ps[1], ps[2]);
        let vals = [
            x,
            b.convert(ConvOp::Itrunc, Type::I16, y),
            {
                let t = b.binary(BinaryOp::Bxor, x, y);
                b.convert(ConvOp::Itrunc, Type::I8, t)
            },
            b.icmp(IntCC::Slt, x, y),
            b.convert(ConvOp::SiToF, Type::F32, y),
            {
                let t = b.convert(ConvOp::Sext, Type::I64, x);
                let u = b.convert(ConvOp::Sext, Type::I64, y);
                b.binary(BinaryOp::Imul, t, u)
            },
            y,
        ];
        for (k, v) in vals.into_iter().enumerate() {
            let a = b.field_addr(p, s, k as u32);
            b.store(v, a);
        }
        let arr = b.field_addr(p, s, ARR_FIELD);
        for k in 0..ARR_LEN {
            let i = b.iconst(Type::I32, k as i64);
            let e = b.elem_addr(arr, a, i);
            let kk = b.iconst(Type::I32, k as i64 * 7 - 5);
            let v = b.binary(BinaryOp::Imul, x, kk);
            b.store(v, e);
        }
        let recs = b.field_addr(p, s, RECS_FIELD);
        for k in 0..RECS_LEN {
            let i = b.iconst(Type::I32, k as i64);
            let rec = b.elem_addr(recs, ra, i);
            let fx = b.field_addr(rec, r, 0);
            let kk = b.iconst(Type::I32, k as i64 + 3);
            let v = b.binary(BinaryOp::Iadd, y, kk);
            b.store(v, fx);
            let fy = b.field_addr(rec, r, 1);
            let v = b.convert(ConvOp::Itrunc, Type::I16, x);
            b.store(v, fy);
        }
        b.ret(None);
    }
    let init = m.add_func(f);
    (
        m,
        Ctx {
            s,
            a,
            r,
            ra,
            g,
            bump,
        },
        init,
    )
}

/// Adds a random `@t(a: i32, b: i32, p: ptr, q: ptr) -> i32`.
fn random_function(m: &mut Module, cx: &Ctx, rng: &mut Rng) -> FuncId {
    let mut f = Function::new(
        "t",
        FuncKind::Function,
        vec![Type::I32, Type::I32, Type::Ptr, Type::Ptr],
        Some(Type::I32),
    );
    {
        let mut b = FuncBuilder::new(&mut f);
        let params = b.params();
        let local = b.slot("local", MemType::Agg(cx.s));
        let ptr_var = b.slot("ptr", MemType::Scalar(Type::Ptr));
        let mut g = Gen {
            rng,
            b,
            cx,
            slots: Vec::new(),
            local,
            ptr_var,
            params,
            depth: 0,
            budget: 12,
            early_return: true,
        };
        // The local struct gets every field written, the pointer variable a target.
        for (k, &(ty, _)) in FIELDS.iter().enumerate() {
            let v = g.konst(ty);
            let base = g.b.slot_addr(local);
            let a = g.b.field_addr(base, cx.s, k as u32);
            g.b.store(v, a);
        }
        for k in 0..ARR_LEN {
            let v = g.konst(Type::I32);
            let base = g.b.slot_addr(local);
            let arr = g.b.field_addr(base, cx.s, ARR_FIELD);
            let i = g.b.iconst(Type::I32, k as i64);
            let a = g.b.elem_addr(arr, cx.a, i);
            g.b.store(v, a);
        }
        for k in 0..RECS_LEN {
            for (fi, &ty) in REC_FIELDS.iter().enumerate() {
                let v = g.konst(ty);
                let base = g.b.slot_addr(local);
                let recs = g.b.field_addr(base, cx.s, RECS_FIELD);
                let i = g.b.iconst(Type::I32, k as i64);
                let rec = g.b.elem_addr(recs, cx.ra, i);
                let a = g.b.field_addr(rec, cx.r, fi as u32);
                g.b.store(v, a);
            }
        }
        let target = *g.rng.pick(&[Base::P, Base::Q, Base::G, Base::L]);
        let p = g.base(target);
        let a = g.b.slot_addr(ptr_var);
        g.b.store(p, a);
        // Locals, initialised as front ends do (sometimes from the inputs).
        for k in 0..g.rng.below(5) + 1 {
            let ty = *g.rng.pick(&TYPES);
            let s = g.b.slot(format!("l{k}"), MemType::Scalar(ty));
            g.slots.push((s, ty));
            let v = if g.rng.chance(50) {
                g.konst(ty)
            } else {
                let x = g.params[0];
                g.of_i32(x, ty)
            };
            let a = g.b.slot_addr(s);
            g.b.store(v, a);
        }
        let n = if g.rng.chance(15) {
            10 + g.rng.below(20) as u32
        } else {
            3 + g.rng.below(6) as u32
        };
        g.stmts(n, 2);
        g.budget = 12;
        let v = g.expr(Type::I32);
        g.b.ret(Some(v));
    }
    m.add_func(f)
}

/// Everything observable after one call: result, fault flag, both structs.
type Outcome = (Result<Option<u64>, String>, bool, Vec<u64>);

fn run_one(
    it: &mut Interp,
    m: &Module,
    init: FuncId,
    t: FuncId,
    x: i32,
    y: i32,
    alias: bool,
) -> Outcome {
    let g = it.data_addr(DataId::new(0)).unwrap();
    let h = it.data_addr(DataId::new(1)).unwrap();
    it.call(init, &[g, x as u64, y as u64]).expect("init runs");
    it.call(init, &[h, y as u64, x.wrapping_mul(3) as u64])
        .expect("init runs");
    it.clear_fault();
    let q = if alias { g } else { h };
    let r = it.call(t, &[x as u64, y as u64, g, q]).map_err(|e| e.0);
    let mut mem = Vec::new();
    for root in [DataId::new(0), DataId::new(1)] {
        for v in crate::vars::variables(m, root) {
            mem.push(it.read(&v.path).expect("readable").bits);
        }
    }
    (r, it.fault(), mem)
}

const INPUTS: [(i32, i32); 8] = [
    (0, 0),
    (1, 2),
    (-1, 7),
    (100, -3),
    (i32::MIN, -1),
    (i32::MAX, 4),
    (12345, 0),
    (-77, 65536),
];

fn outcomes(m: &Module, init: FuncId, t: FuncId) -> Vec<Outcome> {
    let mut it = Interp::new(m).expect("module runs");
    it.set_step_limit(Some(1_000_000));
    let mut out = Vec::new();
    for &(x, y) in &INPUTS {
        for alias in [false, true] {
            out.push(run_one(&mut it, m, init, t, x, y, alias));
        }
    }
    out
}

fn check_same(
    seed: u64,
    what: &str,
    m0: &Module,
    before: &[Outcome],
    m: &Module,
    init: FuncId,
    t: FuncId,
) {
    let after = outcomes(m, init, t);
    for (k, (a, b)) in before.iter().zip(&after).enumerate() {
        if a != b {
            panic!(
                "seed {seed}: {what} changed the behaviour for input {k}:\nbefore {a:?}\nafter  {b:?}\n{}\n--- after:\n{}",
                crate::text::print_function(m0, &m0.funcs[t.index()], &Default::default()),
                crate::text::print_function(m, &m.funcs[t.index()], &Default::default()),
            );
        }
    }
}

#[test]
fn random_functions_keep_their_meaning() {
    let seeds: u64 = if cfg!(debug_assertions) { 500 } else { 10000 };
    let (mut tables, mut copied, mut compacted) = (0, 0, 0);
    for seed in 1..=seeds {
        let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let (mut m, cx, init) = skeleton();
        let t = random_function(&mut m, &cx, &mut rng);
        verify(&m, &m.funcs[t.index()], &format!("seed {seed}: generated"));
        let before = outcomes(&m, init, t);
        if before.iter().any(|o| o.0.is_err()) {
            panic!(
                "seed {seed}: the generated function fails: {:?}",
                before[0].0
            );
        }

        // Each pass alone, in driver order, on the accumulated result.
        let mut cur = m.clone();
        for round in 0..2 {
            for (name, pass) in PASSES {
                for k in 0..cur.funcs.len() {
                    let mut f = cur.funcs[k].clone();
                    pass(&mut f);
                    cur.funcs[k] = f;
                    verify(
                        &cur,
                        &cur.funcs[k],
                        &format!("seed {seed}: after {name} (round {round})"),
                    );
                }
                check_same(seed, name, &m, &before, &cur, init, t);
            }
        }

        // The driver, and the compaction that ends `optimize_program`.
        let mut opt = m.clone();
        crate::passes::optimize_module(&mut opt);
        for f in &opt.funcs {
            verify(&opt, f, &format!("seed {seed}: after optimize_module"));
        }
        check_same(seed, "optimize_module", &m, &before, &opt, init, t);
        let live = opt.funcs[t.index()].live_inst_count();
        compacted += opt.funcs[t.index()].compact();
        for f in &opt.funcs {
            verify(&opt, f, &format!("seed {seed}: after compact"));
        }
        assert_eq!(opt.funcs[t.index()].insts.len(), live, "seed {seed}");
        check_same(seed, "compact", &m, &before, &opt, init, t);
        // The shape passes the JIT runs after the driver (if-conversion, then loop
        // rotation), on the optimised code as it is and with the watchdog's checks
        // on back edges that the runner adds.
        for watchdog in [false, true] {
            let mut shaped = opt.clone();
            for k in 0..shaped.funcs.len() {
                let mut f = shaped.funcs[k].clone();
                if watchdog {
                    let loops = back_edges(&f);
                    crate::passes::watchdog::run_function(&mut f);
                    copied += u64::from(back_edges(&f) > loops);
                }
                crate::passes::if_convert::run(&mut f);
                crate::passes::rotate::run(&mut f);
                shaped.funcs[k] = f;
                let what = format!("seed {seed}: after if_convert and rotate ({watchdog})");
                verify(&shaped, &shaped.funcs[k], &what);
            }
            check_same(seed, "if_convert + rotate", &m, &before, &shaped, init, t);
        }
        // Optimising again finds nothing to do.
        let mut again = opt.clone();
        for f in &mut again.funcs {
            assert!(
                !crate::passes::optimize_function(f),
                "seed {seed}: a second optimisation changed {}",
                f.name
            );
        }

        // What the targets without an indirect jump run after it: value ranges, then
        // the jump tables as compares.
        let mut low = opt;
        crate::passes::ranges::run_module(&mut low);
        let has_table = low.funcs.iter().any(|f| {
            f.inst_iter()
                .any(|(_, i)| matches!(f.inst(i), crate::inst::InstData::BrTable { .. }))
        });
        tables += has_table as u64;
        crate::passes::br_table::run_module(&mut low);
        for f in &low.funcs {
            verify(&low, f, &format!("seed {seed}: after ranges and br_table"));
        }
        check_same(seed, "ranges and br_table", &m, &before, &low, init, t);
    }
    // The optimiser leaves dead instructions for `compact` to drop.
    assert!(
        compacted as u64 >= seeds,
        "{compacted} dropped in {seeds} functions"
    );
    // Some loops run as the watchdog pass's copies without checks, and their tests.
    assert!(
        copied * 10 >= seeds,
        "only {copied} of {seeds} functions have a loop copied"
    );
    // The jump tables the generator makes mostly survive the optimiser.
    assert!(
        tables * 5 >= seeds,
        "only {tables} of {seeds} optimised functions have a br_table"
    );
}

#[test]
fn fuzz_stats() {
    let mut total = (0, 0, 0, 0);
    let mut shaped = (0, 0);
    let mut copied = 0;
    for seed in 1..=300u64 {
        let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let (mut m, cx, init) = skeleton();
        let t = random_function(&mut m, &cx, &mut rng);
        let before = outcomes(&m, init, t);
        let mut opt = m.clone();
        crate::passes::optimize_module(&mut opt);
        total.0 += m.funcs[t.index()].live_inst_count();
        total.1 += opt.funcs[t.index()].live_inst_count();
        total.2 += before.iter().filter(|o| o.1).count();
        total.3 += m.funcs[t.index()].layout.len();
        let mut f = opt.funcs[t.index()].clone();
        let mut checked = f.clone();
        crate::passes::watchdog::run_function(&mut checked);
        copied += usize::from(back_edges(&checked) > back_edges(&f));
        shaped.0 += usize::from(crate::passes::if_convert::run(&mut f));
        shaped.1 += usize::from(crate::passes::rotate::run(&mut f));
        if seed == 7 {
            println!(
                "{}",
                crate::text::print_function(&m, &m.funcs[t.index()], &Default::default())
            );
            println!(
                "{}",
                crate::text::print_function(&opt, &opt.funcs[t.index()], &Default::default())
            );
            println!("{:?}", before);
        }
    }
    println!(
        "insts before {} after {} faults {} blocks {}",
        total.0, total.1, total.2, total.3
    );
    println!(
        "functions if-converted {} rotated {}, with a loop the watchdog copied {copied}",
        shaped.0, shaped.1
    );
}

#[test]
fn fuzz_debug_seed() {
    let Ok(seed) = std::env::var("FUZZ_SEED") else {
        return;
    };
    let seed: u64 = seed.parse().unwrap();
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let (mut m, cx, _init) = skeleton();
    let t = random_function(&mut m, &cx, &mut rng);
    // FUZZ_SHAPE=1: print the optimised function with watchdog checks and
    // if-conversion, then after loop rotation (the JIT's shape passes).
    if std::env::var("FUZZ_SHAPE").is_ok() {
        let mut opt = m.clone();
        crate::passes::optimize_module(&mut opt);
        let mut f = opt.funcs[t.index()].clone();
        crate::passes::watchdog::run_function(&mut f);
        crate::passes::if_convert::run(&mut f);
        println!(
            "{}",
            crate::text::print_function(&opt, &f, &Default::default())
        );
        crate::passes::rotate::run(&mut f);
        println!(
            "{}",
            crate::text::print_function(&opt, &f, &Default::default())
        );
        return;
    }
    let mut cur = m.clone();
    for round in 0..2 {
        for (name, pass) in PASSES {
            let before =
                crate::text::print_function(&cur, &cur.funcs[t.index()], &Default::default());
            let mut f = cur.funcs[t.index()].clone();
            pass(&mut f);
            cur.funcs[t.index()] = f;
            if crate::verify::verify_function(&cur, &cur.funcs[t.index()]).is_err() {
                println!("before {name} round {round}:\n{before}");
                println!(
                    "after:\n{}",
                    crate::text::print_function(&cur, &cur.funcs[t.index()], &Default::default())
                );
                panic!();
            }
        }
    }
}
