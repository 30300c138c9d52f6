//! Lowering one POU body: the function's prologue and epilogue, where each variable
//! lives, and the context shared by statements and expressions.

use super::consts::ConstVal;
use super::usertypes::{EnumLookup, TagDefault};
use super::{Lowerer, Storage};
use crate::ast::{self, PouKind, VarKind};
use crate::codes;
use crate::types::{PouId, StructId, TagId, Ty};
use plcc_ir::diag::Span;
use plcc_ir::{Block, FuncBuilder, FuncId, Function, MemType, SlotId, Type, Value};

/// Why a place may not be written.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum Access {
    /// Any access.
    ReadWrite,
    /// The POU's own VAR_INPUT.
    OwnInput,
    /// An output of another instance.
    OtherOutput,
    /// A CONSTANT kept in memory (a string, array or STRUCT).
    Constant,
    /// An internal variable (VAR) of another instance, or something inside one,
    /// which the CODESYS dialect lets outside code read but not write.
    Internal,
}

/// A variable, element or member in memory.
#[derive(Copy, Clone, Debug)]
pub(super) struct Place {
    /// Its address.
    pub addr: Value,
    /// Its type.
    pub ty: Ty,
    /// Whether it may be written.
    pub access: Access,
    /// `x.3`: a single bit of the word at `addr` (the place's type is BOOL then, and
    /// `word` is the word's type).
    pub bit: Option<(u8, Ty)>,
    /// For array elements: an `i1` that is false when an index was out of bounds.
    /// Then `addr` is a safe stand-in, reads give 0 and writes are dropped.
    pub guard: Option<Value>,
    /// The derived type it was declared with (a subrange's bounds are checked on
    /// constants assigned to it).
    pub tag: Option<TagId>,
}

impl Place {
    pub(super) fn new(addr: Value, ty: Ty) -> Place {
        Place {
            addr,
            ty,
            access: Access::ReadWrite,
            bit: None,
            guard: None,
            tag: None,
        }
    }
}

/// How many later uses of an undeclared name its error marks.
const MORE_UNDECLARED_USES: usize = 3;

/// What a name stands for in an expression.
pub(super) enum Named {
    /// A variable in memory.
    Place(Place),
    /// A constant.
    Const(ConstVal, Ty),
    /// Something already reported.
    Error,
}

/// Jump targets of the innermost loops.
#[derive(Copy, Clone, Debug)]
pub(super) struct LoopTargets {
    /// Where EXIT goes.
    pub exit: Block,
    /// Where CONTINUE goes.
    pub cont: Block,
}

/// The state of lowering one function body.
pub(super) struct BodyCx<'a, 's> {
    pub l: &'a mut Lowerer<'s>,
    pub b: FuncBuilder<'a>,
    pub pou: PouId,
    /// What the recursion check counts this body's calls from: the POU, or the
    /// ACTION being lowered.
    pub caller: super::CallNode,
    /// The instance pointer (PROGRAM and FB bodies and init functions, METHODs).
    pub self_ptr: Option<Value>,
    /// The class of the instance `self_ptr` points to, whose struct addresses its
    /// fields: the POU (FB and PROGRAM bodies), the owner (METHODs), or a class
    /// derived from the POU (its body run on a derived instance, `SUPER^()`).
    pub this_class: Option<PouId>,
    /// Innermost loop last.
    pub loops: Vec<LoopTargets>,
    /// FOR control variables whose value is known to stay within `[lo, hi]` in the
    /// body being lowered (constant bounds, never written in the body): array indexes
    /// by them need no bounds check.
    pub known_ranges: Vec<(crate::intern::Symbol, i128, i128)>,
    /// Compiler temporaries (`Let` statements) by name: slot and type. A later `Let`
    /// of the same name replaces the earlier one.
    pub temps: rustc_hash::FxHashMap<crate::intern::Symbol, (SlotId, Ty)>,
    /// Compiler temporaries that hold the "value" of a call of a FUNCTION without a
    /// result (IL: such a call leaves the current result undefined): the FUNCTION.
    /// Reading one is E0405 at the call (reported once: the flag).
    pub void_temps: rustc_hash::FxHashMap<crate::intern::Symbol, (PouId, bool)>,
    /// The labels of the body (IL, ladder): the blocks they start, where they are.
    pub labels: rustc_hash::FxHashMap<crate::intern::Symbol, (Block, Span)>,
    /// A FUNCTION's epilogue (copies outputs, returns the result).
    pub ret_block: Option<Block>,
    /// A FUNCTION's result variable.
    pub result_slot: Option<SlotId>,
    /// Where a FUNCTION returning a STRUCT or an array writes its result (the
    /// caller's address).
    pub result_ptr: Option<Value>,
    /// Lowering initial values: only constants may be named.
    pub in_init: bool,
    /// Parameter values of the function (FUNCTION inputs and pointers).
    pub params: Vec<Value>,
    /// Names this body uses without a declaration: the index of the error reported
    /// at the first use, which later uses are added to instead of repeating it.
    pub undeclared: rustc_hash::FxHashMap<crate::intern::Symbol, usize>,
    /// Set by a standard function that failed when the value is TRUE (an invalid
    /// BCD): its call's ENO is then FALSE (`en_eno.rs`).
    pub eno_error: Option<Value>,
}

impl<'s> Lowerer<'s> {
    /// Lowers the body (and, for instances, the init function) of one POU.
    pub(super) fn lower_pou(&mut self, id: PouId) {
        let kind = self.pou(id).kind;
        let body_id = match self.ir[id.0 as usize].body {
            Some(b) => b,
            None => return,
        };
        // A derived FB without a body of its own runs its base's; in CODESYS its
        // body, even empty, replaces the base's (which `SUPER^()` runs).
        let src = match self.pou(id).base {
            Some(_) if self.pou_ast(id).body.stmts.is_empty() && !self.codesys => {
                self.body_owner(id).unwrap_or(id)
            }
            _ => id,
        };
        self.with_function(body_id, |l, func| {
            let mut cx = BodyCx::new(l, func, src, false);
            cx.this_class = Some(id)
                .filter(|_| kind != PouKind::Function)
                .or(cx.this_class);
            let stmts = &cx.l.pou_ast(src).body.stmts;
            cx.lower_body(stmts);
        });
        if kind != PouKind::Function {
            let init_id = self.ir[id.0 as usize].init.expect("init function");
            self.with_function(init_id, |l, func| {
                let mut cx = BodyCx::new(l, func, id, true);
                cx.init_instance_fields();
                cx.b.ret(None);
            });
        }
    }

    /// Takes a function out of the module while `f` builds it (so the builder and the
    /// lowerer can both be borrowed), then puts it back, its tables cut to size; under
    /// [`LowerOptions::check_only`](super::LowerOptions::check_only) it drops it.
    pub(super) fn with_function(
        &mut self,
        fid: FuncId,
        f: impl FnOnce(&mut Lowerer<'s>, &mut Function),
    ) {
        let shell = {
            let cur = &self.module.funcs[fid.index()];
            let mut s = Function::new(cur.name.clone(), cur.kind, cur.params.clone(), cur.ret);
            s.span = cur.span;
            s
        };
        let current = std::mem::replace(&mut self.module.funcs[fid.index()], shell);
        // Built in the scratch function (taken: building one body may start
        // another), then copied out without room to spare; under `check_only`
        // nothing is copied and the next body reuses the memory.
        let mut func = match self.scratch.take() {
            Some(mut scratch) => {
                scratch.refill_from(current);
                scratch
            }
            None => current,
        };
        f(self, &mut func);
        if !self.drop_bodies {
            self.module.funcs[fid.index()] = func.take_exact();
        }
        self.scratch = Some(func);
    }
}

impl<'a, 's> BodyCx<'a, 's> {
    pub(super) fn new(
        l: &'a mut Lowerer<'s>,
        func: &'a mut Function,
        pou: PouId,
        in_init: bool,
    ) -> Self {
        let b = FuncBuilder::new(func);
        let params = b.params();
        let kind = l.pou(pou).kind;
        let owner = l.pou(pou).owner;
        let self_ptr = (kind != PouKind::Function || owner.is_some()).then(|| params[0]);
        let this_class = owner.or((kind != PouKind::Function).then_some(pou));
        BodyCx {
            l,
            b,
            pou,
            caller: super::CallNode::Pou(pou),
            self_ptr,
            this_class,
            loops: Vec::new(),
            known_ranges: Vec::new(),
            temps: Default::default(),
            void_temps: Default::default(),
            labels: Default::default(),
            ret_block: None,
            result_slot: None,
            result_ptr: None,
            in_init,
            params,
            undeclared: Default::default(),
            eno_error: None,
        }
    }

    /// Lowers a body (of the POU, or of one of its actions): prologue, statements,
    /// epilogue.
    pub(super) fn lower_body(&mut self, stmts: &'s [ast::Stmt]) {
        self.prologue();
        self.collect_labels(stmts);
        self.stmts(stmts);
        self.epilogue();
    }

    pub(super) fn kind(&self) -> PouKind {
        self.l.pou(self.pou).kind
    }

    pub(super) fn set_span(&mut self, span: Span) {
        self.b.set_span(Some(span));
    }

    /// Allocates slots for FUNCTION variables and VAR_TEMPs and gives them their
    /// initial values (they start afresh at every call).
    fn prologue(&mut self) {
        let pou = self.pou;
        let kind = self.kind();
        let n = self.l.pou(pou).vars.len();
        if kind == PouKind::Function {
            let ret = self.l.pou(pou).ret;
            let ret_tag = self.l.pou(pou).ret_tag;
            if let Some(p) = self.l.ir[pou.0 as usize].result_param {
                let addr = self.params[p as usize];
                self.result_ptr = Some(addr);
                self.init_var(addr, ret, ret_tag, None);
            } else if let Some(t) = ret.ir() {
                let name = self.l.pou(pou).display.clone();
                let slot = self.b.slot(name, MemType::Scalar(t));
                self.result_slot = Some(slot);
                let addr = self.b.slot_addr(slot);
                if ret_tag.is_some() || matches!(ret, Ty::Enum(..)) {
                    self.init_var(addr, ret, ret_tag, None);
                } else {
                    let zero = self.zero(ret);
                    self.b.store(zero, addr);
                }
            }
            let rb = self.b.create_block();
            self.ret_block = Some(rb);
        }
        for vi in 0..n {
            let v = self.l.pou(pou).vars[vi].clone();
            if v.constant {
                if self.l.ir[pou.0 as usize].storage[vi].is_none() {
                    self.l.fold_constant(pou, vi);
                }
                continue;
            }
            let local = match kind {
                PouKind::Function => !matches!(
                    v.section,
                    VarKind::InOut | VarKind::External | VarKind::Inst
                ),
                _ => v.section == VarKind::Temp,
            };
            if !local {
                continue;
            }
            let Some((mt, _)) = self.l.mem_type(v.ty) else {
                continue;
            };
            let slot = self.b.slot(v.display.clone(), mt);
            self.l.ir[pou.0 as usize].storage[vi] = Some(Storage::Slot(slot));
            self.set_span(v.name.span);
            let addr = self.b.slot_addr(slot);
            if kind == PouKind::Function && v.section == VarKind::Input {
                let p = self.l.ir[pou.0 as usize].param_of[vi].expect("input parameter");
                let pv = self.params[p as usize];
                if v.ty.is_aggregate() {
                    // Copied on entry, so the callee never changes the caller's value.
                    self.copy_value(addr, pv, v.ty);
                } else {
                    self.b.store(pv, addr);
                }
            } else {
                let init = self.decl_init(vi);
                self.init_var(addr, v.ty, v.tag, init);
            }
        }
    }

    /// The AST initial value of variable `vi` of this POU.
    pub(super) fn decl_init(&self, vi: usize) -> Option<&'s ast::Init> {
        let v = &self.l.pou(self.pou).vars[vi];
        let ast = self.l.pou_ast(self.pou);
        ast.var_blocks[v.decl.0 as usize].decls[v.decl.1 as usize]
            .init
            .as_ref()
    }

    /// Ends the body: FUNCTIONs copy their outputs and return their result.
    fn epilogue(&mut self) {
        let pou = self.pou;
        match self.ret_block {
            Some(rb) => {
                if !self.b.is_terminated() {
                    self.b.jump(rb, vec![]);
                }
                self.b.switch_to(rb);
                let n = self.l.pou(pou).vars.len();
                for vi in 0..n {
                    let v = &self.l.pou(pou).vars[vi];
                    if v.section != VarKind::Output {
                        continue;
                    }
                    let ty = v.ty;
                    let Some(Storage::Slot(slot)) = self.l.ir[pou.0 as usize].storage[vi] else {
                        continue;
                    };
                    let p = self.l.ir[pou.0 as usize].param_of[vi].expect("output parameter");
                    let out_ptr = self.params[p as usize];
                    if ty.is_aggregate() {
                        let addr = self.b.slot_addr(slot);
                        self.copy_value(out_ptr, addr, ty);
                        continue;
                    }
                    let Some(irt) = ty.ir() else { continue };
                    let addr = self.b.slot_addr(slot);
                    let val = self.b.load(irt, addr);
                    self.b.store(val, out_ptr);
                }
                let result = self.result_slot.map(|s| {
                    let t = self.l.pou(pou).ret.ir().expect("result type");
                    let addr = self.b.slot_addr(s);
                    self.b.load(t, addr)
                });
                self.b.ret(result);
            }
            None => {
                if !self.b.is_terminated() {
                    self.b.ret(None);
                }
            }
        }
    }

    /// Cold-start values of the instance's fields (the body of `T$init`).
    fn init_instance_fields(&mut self) {
        let pou = self.pou;
        let agg = self.l.ir[pou.0 as usize].agg.expect("instance struct");
        let this = self.self_ptr.expect("instance pointer");
        if let Some(&id) = self.l.classes.class_id.get(&pou) {
            let v = self.b.iconst(super::dispatch::CLASS_ID, id as i64);
            let a = self.b.field_addr(this, agg, 0);
            self.b.store(v, a);
        }
        // The fields of the bases too, farthest first, each with its initial value as
        // its class declares it (not by calling the base's init function: on a VM
        // whose instances hold their functions' frames, that frame would lie over
        // this instance's own fields).
        let mut lineage = self.l.lineage(pou);
        lineage.reverse();
        for c in lineage {
            self.pou = c;
            let n = self.l.pou(c).vars.len();
            for vi in 0..n {
                let Some(Storage::Field(fi)) = self.l.ir[c.0 as usize].storage[vi] else {
                    continue;
                };
                let v = self.l.pou(c).vars[vi].clone();
                self.set_span(v.name.span);
                let addr = self.b.field_addr(this, agg, fi);
                if v.section == VarKind::InOut {
                    if let Some(init) = self.decl_init(vi) {
                        self.l.error(
                            codes::E_BAD_DECLARATION,
                            "a VAR_IN_OUT cannot have an initial value",
                            init.span(),
                        );
                    }
                    continue;
                }
                let init = self.decl_init(vi);
                self.init_var(addr, v.ty, v.tag, init);
            }
            // The VAR_INST variables of its methods.
            for m in self.l.own_methods(c) {
                for vi in 0..self.l.pou(m).vars.len() {
                    let Some(Storage::Field(fi)) = self.l.ir[m.0 as usize].storage[vi] else {
                        continue;
                    };
                    let v = self.l.pou(m).vars[vi].clone();
                    let addr = self.b.field_addr(this, agg, fi);
                    self.pou = m;
                    let init = self.decl_init(vi);
                    self.init_var(addr, v.ty, v.tag, init);
                    self.pou = c;
                }
            }
        }
        self.pou = pou;
    }

    /// The zero value of a scalar type.
    pub(super) fn zero(&mut self, ty: Ty) -> Value {
        match ty.ir() {
            Some(t) if t.is_float() => self.b.fconst(t, 0.0),
            Some(t) => self.b.iconst(t, 0),
            None => self.b.iconst(Type::I32, 0),
        }
    }

    /// Stores the initial value of a variable of type `ty` at `addr`: the declared
    /// one, else its derived type's (`tag`), else the type's default.
    pub(super) fn init_var(
        &mut self,
        addr: Value,
        ty: Ty,
        tag: Option<TagId>,
        init: Option<&'s ast::Init>,
    ) {
        let saved = self.in_init;
        self.in_init = true;
        let tag_default = tag.map(|t| self.l.user.tags[t.0 as usize].default);
        let init = init.or(match tag_default {
            Some(TagDefault::Init(i)) => Some(i),
            _ => None,
        });
        match ty {
            Ty::Elem(_) | Ty::Enum(..) => {
                let v = match init {
                    Some(ast::Init::Expr(e)) => {
                        self.check_range(tag, e);
                        self.emit_as(e, ty)
                    }
                    Some(other) => {
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            format!(
                                "a {} is initialised with a single value",
                                self.l.ty_name(ty)
                            ),
                            other.span(),
                        );
                        self.zero(ty)
                    }
                    None => self.default_value(ty, tag),
                };
                self.b.store(v, addr);
            }
            Ty::Fb(p) => {
                let init_fn = self.l.ir[p.0 as usize].init;
                if let Some(f) = init_fn {
                    self.b.call(f, None, vec![addr]);
                }
                match init {
                    None => {}
                    Some(ast::Init::Struct { fields, .. }) => {
                        for (name, fi) in fields {
                            if let Some(place) = self.member_place(addr, p, *name, true) {
                                self.init_var(place.addr, place.ty, place.tag, Some(fi));
                            }
                        }
                    }
                    Some(other) => {
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            "a function block instance is initialised with `(name := value, ...)`",
                            other.span(),
                        );
                    }
                }
            }
            Ty::Array(a) => self.init_array(addr, a, init),
            Ty::Struct(s) => self.init_struct(addr, s, init),
            Ty::Str(s) => {
                let whole = self.kind() != PouKind::Function;
                self.init_string(addr, s, init, whole);
            }
            Ty::Ref(_) => {
                let v = match init {
                    Some(ast::Init::Expr(e)) => self.emit_ref(e, ty),
                    Some(other) => {
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            "a reference is initialised with a single value (REF(x) or NULL)",
                            other.span(),
                        );
                        self.zero(ty)
                    }
                    None => self.zero(ty),
                };
                self.b.store(v, addr);
            }
            _ => {}
        }
        self.in_init = saved;
    }

    /// The initial value of a scalar declared without one: its derived type's (a
    /// subrange's lower bound), an enumeration's first (or declared) value, else 0.
    pub(super) fn default_value(&mut self, ty: Ty, tag: Option<TagId>) -> Value {
        let from_tag = tag.and_then(|t| match self.l.user.tags[t.0 as usize].default {
            TagDefault::Value(v) => Some(v),
            TagDefault::Init(_) => None,
        });
        let v = match (from_tag, ty) {
            (Some(v), _) => v,
            (None, Ty::Enum(e, _)) => self.l.user.enums[e.0 as usize].default,
            _ => return self.zero(ty),
        };
        match ty.ir() {
            Some(t) if !t.is_float() => self.b.iconst(t, v as i64),
            _ => self.zero(ty),
        }
    }

    /// Reports a constant `e` outside the range of the subrange `tag`.
    pub(super) fn check_range(&mut self, tag: Option<TagId>, e: &ast::Expr) {
        let Some(t) = tag else { return };
        let Some((lo, hi)) = self.l.user.tags[t.0 as usize].range else {
            return;
        };
        if let Some((ConstVal::Int(v), _)) = self.l.const_eval(e, self.pou) {
            if v < lo || v > hi {
                let name = self.l.user.tags[t.0 as usize].name.clone();
                self.l.error(
                    codes::E_LITERAL_RANGE,
                    format!("{v} is out of the range of {name} ({lo}..{hi})"),
                    e.span,
                );
            }
        }
    }

    /// A STRUCT's fields get the values its initialiser names, the others the ones
    /// the STRUCT declares (or their type's default).
    fn init_struct(&mut self, addr: Value, s: StructId, init: Option<&'s ast::Init>) {
        let sname = self.l.user.structs[s.0 as usize].display.clone();
        let given: &'s [(ast::Ident, ast::Init)] = match init {
            None => &[],
            Some(ast::Init::Struct { fields, .. }) => fields,
            Some(other) => {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    format!("a STRUCT {sname} is initialised with `(field := value, ...)`"),
                    other.span(),
                );
                &[]
            }
        };
        for (k, (name, _)) in given.iter().enumerate() {
            if given[..k].iter().any(|(n, _)| n.sym == name.sym) {
                let n = self.l.text(name.span).to_string();
                self.l.error(
                    codes::E_BAD_DECLARATION,
                    format!("the field `{n}` is initialised twice"),
                    name.span,
                );
            } else if self.l.struct_field(s, name.sym).is_none() {
                let n = self.l.text(name.span).to_string();
                self.l.error(
                    codes::E_NO_MEMBER,
                    format!("STRUCT {sname} has no field `{n}`"),
                    name.span,
                );
            }
        }
        let agg = self.l.struct_agg(s);
        let fields = self.l.user.structs[s.0 as usize].fields.clone();
        for (fi, f) in fields.iter().enumerate() {
            let Some(ir_fi) = self.l.user.structs[s.0 as usize].ir_fields[fi] else {
                continue;
            };
            let explicit = given
                .iter()
                .find(|(n, _)| n.sym == f.name.sym)
                .map(|(_, i)| i);
            let fa = self.b.field_addr(addr, agg, ir_fi);
            self.init_var(fa, f.ty, f.tag, explicit.or(f.init));
        }
    }

    /// Element-wise initialisation of an array: a loop gives every element the
    /// element type's default, then the explicit values are stored.
    fn init_array(&mut self, addr: Value, a: crate::types::ArrayId, init: Option<&'s ast::Init>) {
        let at = self.l.types.get(a).clone();
        let explicit: Vec<Option<&'s ast::Init>> = match init {
            None => Vec::new(),
            Some(ast::Init::Array { elems, .. }) => {
                let mut flat = Vec::new();
                self.flatten_array_init(elems, &at, 0, &mut flat);
                if flat.len() as u64 > at.total() {
                    self.l.error(
                        codes::E_TYPE_MISMATCH,
                        format!(
                            "{} initial values for an array of {} elements",
                            flat.len(),
                            at.total()
                        ),
                        init.expect("array initialiser").span(),
                    );
                    flat.truncate(at.total() as usize);
                }
                flat
            }
            Some(other) => {
                self.l.error(
                    codes::E_TYPE_MISMATCH,
                    "an array is initialised with `[value, value, n(value), ...]`",
                    other.span(),
                );
                Vec::new()
            }
        };
        // Default every element (one loop over the flattened array).
        if (explicit.len() as u64) < at.total() || explicit.iter().any(|e| e.is_none()) {
            self.array_default_loop(addr, a, 0, &at);
        }
        for (k, init) in explicit.iter().enumerate() {
            let Some(init) = init else { continue };
            let idx = self.flat_to_indices(&at, k as u64);
            let mut p = addr;
            for (d, i) in idx.iter().enumerate() {
                let agg = self.l.array_agg(a, d as u32);
                let iv = self.b.iconst(Type::I32, *i as i64);
                p = self.b.elem_addr(p, agg, iv);
            }
            self.init_var(p, at.elem, at.elem_tag, Some(init));
        }
    }

    /// Appends the values of an array initialiser in row-major order (`None` for a
    /// default value). Values are listed flat (`[1, 2, 3, 4]` for `ARRAY[1..2, 1..2]`)
    /// or nested per dimension (`[[1, 2], [3, 4]]`, also for ARRAY OF ARRAY, which is
    /// one array with more dimensions): a nested list at dimension `dim` fills one
    /// slice of the remaining dimensions, padded with default values.
    fn flatten_array_init(
        &mut self,
        elems: &'s [ast::ArrayInitElem],
        at: &crate::types::ArrayTy,
        dim: usize,
        out: &mut Vec<Option<&'s ast::Init>>,
    ) {
        let cap = at.total() + 1;
        for el in elems {
            let count = match &el.repeat {
                None => 1,
                Some(r) => match self.l.const_eval(r, self.pou) {
                    Some((ConstVal::Int(n), _)) if n >= 0 => n as u64,
                    _ => {
                        self.l.error(
                            codes::E_NOT_CONSTANT,
                            "a repetition count must be a non-negative integer constant",
                            r.span,
                        );
                        0
                    }
                },
            };
            match &el.value {
                Some(ast::Init::Array { elems: inner, span }) if dim + 1 < at.dims.len() => {
                    let slice: u64 = (dim + 1..at.dims.len()).map(|d| at.len(d)).product();
                    let mut one = Vec::new();
                    self.flatten_array_init(inner, at, dim + 1, &mut one);
                    if one.len() as u64 > slice {
                        self.l.error(
                            codes::E_TYPE_MISMATCH,
                            format!(
                                "{} initial values for a slice of {slice} elements",
                                one.len()
                            ),
                            *span,
                        );
                        one.truncate(slice as usize);
                    }
                    one.resize(slice as usize, None);
                    for _ in 0..count.min(cap) {
                        if out.len() as u64 >= cap {
                            break;
                        }
                        out.extend(one.iter().copied());
                    }
                }
                v => {
                    for _ in 0..count.min(cap) {
                        out.push(v.as_ref());
                    }
                }
            }
        }
    }

    fn flat_to_indices(&self, at: &crate::types::ArrayTy, mut k: u64) -> Vec<u64> {
        let mut idx = vec![0u64; at.dims.len()];
        for d in (0..at.dims.len()).rev() {
            let len = at.len(d);
            idx[d] = k % len;
            k /= len;
        }
        idx
    }

    /// `for i in 0..len: init(elem i)`, nested per dimension.
    fn array_default_loop(
        &mut self,
        addr: Value,
        a: crate::types::ArrayId,
        dim: u32,
        at: &crate::types::ArrayTy,
    ) {
        let agg = self.l.array_agg(a, dim);
        let len = at.len(dim as usize) as i64;
        self.counted_loop(Type::I32, len, |cx, i| {
            let p = cx.b.elem_addr(addr, agg, i);
            if (dim as usize) + 1 < at.dims.len() {
                cx.array_default_loop(p, a, dim + 1, at);
            } else {
                cx.init_var(p, at.elem, at.elem_tag, None);
            }
        });
    }

    /// Emits `for i := 0 TO len - 1 DO body(i)` with `i` of type `ty`.
    pub(super) fn counted_loop(&mut self, ty: Type, len: i64, body: impl FnOnce(&mut Self, Value)) {
        let header = self.b.create_block();
        let body_block = self.b.create_block();
        let exit = self.b.create_block();
        let i = self.b.block_param(header, ty);
        let zero = self.b.iconst(ty, 0);
        self.b.jump(header, vec![zero]);
        self.b.switch_to(header);
        let lenv = self.b.iconst(ty, len);
        let more = self.b.icmp(plcc_ir::IntCC::Slt, i, lenv);
        self.b.brif(more, body_block, vec![], exit, vec![]);
        self.b.switch_to(body_block);
        body(self, i);
        let one = self.b.iconst(ty, 1);
        let next = self.b.binary(plcc_ir::BinaryOp::Iadd, i, one);
        self.b.jump(header, vec![next]);
        self.b.switch_to(exit);
    }

    /// Gives every label of the body (at any depth) a block; reports duplicates.
    fn collect_labels(&mut self, stmts: &'s [ast::Stmt]) {
        let mut labels = Vec::new();
        crate::visit::each_stmt(stmts, &mut |s| {
            if let ast::StmtKind::Label(id) = &s.kind {
                labels.push(*id);
            }
        });
        for id in labels {
            if let Some(&(_, first)) = self.labels.get(&id.sym) {
                let n = self.l.text(id.span).to_string();
                self.l.diags.push(
                    plcc_ir::diag::Diagnostic::error(
                        codes::E_DUPLICATE_LABEL,
                        format!("label `{n}` is defined twice in this body"),
                        id.span,
                    )
                    .with_secondary(first, "first defined here"),
                );
                continue;
            }
            let b = self.b.create_block();
            self.labels.insert(id.sym, (b, id.span));
        }
    }

    /// Resolves a plain name: a compiler temporary, a variable of this POU, the
    /// FUNCTION's result, a constant, a global, an enumeration value (of `want`'s
    /// enumeration if several have the name).
    pub(super) fn resolve_name(&mut self, id: ast::Ident, report: bool, want: Option<Ty>) -> Named {
        let pou = self.pou;
        if let Some(&(p, reported)) = self.void_temps.get(&id.sym) {
            // Once per temporary: every read of it is the same mistake.
            if report && !reported {
                self.void_temps.insert(id.sym, (p, true));
                let n = self.l.pou(p).display.clone();
                self.l.error(
                    codes::E_NO_RESULT,
                    format!("FUNCTION `{n}` has no result type, so it gives no value"),
                    id.span,
                );
            }
            return Named::Error;
        }
        if let Some(&(slot, ty)) = self.temps.get(&id.sym) {
            if ty == Ty::Error {
                return Named::Error;
            }
            let addr = self.b.slot_addr(slot);
            return Named::Place(Place::new(addr, ty));
        }
        if let Some(vi) = self.l.pou(pou).var(id.sym) {
            let vi = vi as usize;
            let v = &self.l.pou(pou).vars[vi];
            let (ty, section) = (v.ty, v.section);
            if section == VarKind::External {
                // Checked against the global already (`check_externals`), which made
                // a broken one's type an error.
                if ty == Ty::Error {
                    return Named::Error;
                }
                return self.resolve_global(id, report).unwrap_or(Named::Error);
            }
            let storage = self.l.ir[pou.0 as usize].storage[vi];
            if let Some(Storage::Const(c)) = storage {
                let val = self.l.ir[pou.0 as usize].consts[c as usize];
                return Named::Const(val, ty);
            }
            if v.constant {
                return Named::Error;
            }
            if self.in_init {
                if report {
                    self.l.error(
                        codes::E_NOT_CONSTANT,
                        "an initial value can only use literals and constants",
                        id.span,
                    );
                }
                return Named::Error;
            }
            // A FUNCTION's inputs are its own copies (writing them is ordinary Pascal
            // and STL style); an instance's inputs belong to its caller.
            let access = if v.read_only {
                Access::Constant
            } else if section == VarKind::Input && self.kind() != PouKind::Function {
                Access::OwnInput
            } else {
                Access::ReadWrite
            };
            let addr = match storage {
                Some(Storage::Slot(s)) => self.b.slot_addr(s),
                Some(Storage::Field(f)) => {
                    let class = self.this_class.unwrap_or(pou);
                    let agg = self.l.ir[class.0 as usize].agg.expect("instance struct");
                    let this = self.self_ptr.expect("instance pointer");
                    let fa = self.b.field_addr(this, agg, f);
                    if section == VarKind::InOut {
                        self.b.load(Type::Ptr, fa)
                    } else {
                        fa
                    }
                }
                None if section == VarKind::InOut && self.kind() == PouKind::Function => {
                    let p = self.l.ir[pou.0 as usize].param_of[vi].expect("in-out parameter");
                    self.params[p as usize]
                }
                _ => return Named::Error,
            };
            let tag = v.tag;
            return Named::Place(Place {
                addr,
                ty,
                access,
                bit: None,
                guard: None,
                tag,
            });
        }
        // A variable of the class (inherited, or the FB's seen from a METHOD).
        if let Some(named) = self.class_member_var(id) {
            return named;
        }
        // The FUNCTION's own name is its result variable.
        if self.kind() == PouKind::Function && id.sym == self.l.pou(pou).name.sym && !self.in_init {
            let ty = self.l.pou(pou).ret;
            let tag = self.l.pou(pou).ret_tag;
            let addr = match (self.result_slot, self.result_ptr) {
                (Some(slot), _) => Some(self.b.slot_addr(slot)),
                (None, Some(p)) => Some(p),
                _ => None,
            };
            if let Some(addr) = addr {
                let mut place = Place::new(addr, ty);
                place.tag = tag;
                return Named::Place(place);
            }
        }
        if let Some(named) = self.resolve_global(id, report) {
            return named;
        }
        match self.l.enum_named(id.sym, want) {
            EnumLookup::One(e, base, v) => {
                return Named::Const(ConstVal::Int(v), Ty::Enum(e, base));
            }
            EnumLookup::Ambiguous(ids) => {
                if report {
                    let n = self.l.text(id.span).to_string();
                    let qualified: Vec<String> = ids
                        .iter()
                        .map(|e| format!("`{}#{n}`", self.l.user.enums[e.0 as usize].display))
                        .collect();
                    self.l.diags.push(
                        plcc_ir::diag::Diagnostic::error(
                            codes::E_AMBIGUOUS,
                            format!("`{n}` is a value of several enumerations"),
                            id.span,
                        )
                        .with_note(format!("say which: {}", qualified.join(" or "))),
                    );
                }
                return Named::Error;
            }
            EnumLookup::None => {}
        }
        if self.l.is_unsupported_name(id.sym) {
            // Declared by something already reported as not supported (an
            // enumeration value, a user type): no second error.
            return Named::Error;
        }
        if report && self.l.sym_name(id.sym) == "NULL" {
            self.l.error(
                codes::E_NOT_A_PLACE,
                "NULL is a value, not a variable",
                id.span,
            );
            return Named::Error;
        }
        if report {
            if let Some(&i) = self.undeclared.get(&id.sym) {
                // One error per name and body: the first use, with a few more
                // marked, rather than one error per use.
                let d = &mut self.l.diags[i];
                if d.secondary.len() < MORE_UNDECLARED_USES {
                    d.secondary.push((id.span, "also used here".into()));
                }
                return Named::Error;
            }
            let upper = self.l.sym_name(id.sym).to_string();
            if upper == "SUPER" || upper == "THIS" {
                let msg = match self.lexical_class() {
                    Some(c) => format!(
                        "`SUPER^` names the base of the function block, and `{}` extends none",
                        self.l.pou(c).display
                    ),
                    None => format!(
                        "`{upper}^` is the instance a FUNCTION_BLOCK's body or METHOD runs on: there is none here"
                    ),
                };
                self.l.error(codes::E_OO_DECLARATION, msg, id.span);
                return Named::Error;
            }
            self.undeclared.insert(id.sym, self.l.diags.len());
            let name = self.l.text(id.span).to_string();
            let mut note = None;
            let msg = if self.l.is_global_list(id.sym) && !self.l.pou(pou).std {
                format!("`{name}` is a global variable list, not a variable: name one of its variables, `{name}.x`")
            } else if let Some(&p) = self.l.pou_by_name.get(&id.sym) {
                match self.l.pou(p).kind {
                    PouKind::Function => {
                        format!("`{name}` is a FUNCTION: call it with `{name}(...)`")
                    }
                    PouKind::FunctionBlock => {
                        format!("`{name}` is a FUNCTION_BLOCK type: declare an instance of it")
                    }
                    PouKind::Program => {
                        note = Some(if self.l.codesys {
                            format!("its variables are read as `{name}.x`")
                        } else {
                            format!("CODESYS reads a PROGRAM's variables from other POUs as `{name}.x`: `--dialect codesys` accepts that")
                        });
                        format!("`{name}` is a PROGRAM, not a variable")
                    }
                }
            } else {
                format!("`{name}` is not declared")
            };
            let mut d = plcc_ir::diag::Diagnostic::error(codes::E_UNDECLARED, msg, id.span);
            if let Some(n) = note {
                d = d.with_note(n);
            }
            self.l.diags.push(d);
        }
        Named::Error
    }

    /// A global variable or constant (VAR_GLOBAL), if there is one by this name.
    pub(super) fn resolve_global(&mut self, id: ast::Ident, report: bool) -> Option<Named> {
        // The standard library does not see the user's globals.
        let g = self
            .l
            .globals_pou
            .filter(|&g| g != self.pou && !self.l.pou(self.pou).std)?;
        let vi = self.l.pou(g).var(id.sym)? as usize;
        let v = &self.l.pou(g).vars[vi];
        let ty = v.ty;
        match self.l.ir[g.0 as usize].storage[vi] {
            Some(Storage::Const(c)) => {
                Some(Named::Const(self.l.ir[g.0 as usize].consts[c as usize], ty))
            }
            _ if v.constant => Some(Named::Error),
            _ if self.in_init => {
                if report {
                    self.l.error(
                        codes::E_NOT_CONSTANT,
                        "an initial value can only use literals and constants",
                        id.span,
                    );
                }
                Some(Named::Error)
            }
            Some(Storage::Field(fi)) => {
                let tag = v.tag;
                let agg = self.l.ir[g.0 as usize].agg?;
                let data = self.l.globals_data?;
                let base = self.b.global_addr(data);
                let addr = self.b.field_addr(base, agg, fi);
                let mut place = Place::new(addr, ty);
                place.tag = tag;
                Some(Named::Place(place))
            }
            _ => Some(Named::Error),
        }
    }

    /// The place of member `name` of the FB instance at `base`. `init` allows the
    /// internal variables (initialisers may set any member); otherwise only inputs and
    /// outputs are visible from outside.
    pub(super) fn member_place(
        &mut self,
        base: Value,
        fb: PouId,
        name: ast::Ident,
        init: bool,
    ) -> Option<Place> {
        let agg_of = fb;
        let Some((fb, vi)) = self.l.class_var(fb, name.sym) else {
            let n = self.l.text(name.span).to_string();
            let fbn = self.l.pou(fb).display.clone();
            let msg = if self.l.is_class(fb) {
                format!("function block `{fbn}` has no variable, method or property named `{n}`")
            } else {
                format!("function block `{fbn}` has no input or output named `{n}`")
            };
            self.l.error(codes::E_NO_MEMBER, msg, name.span);
            return None;
        };
        let v = self.l.pou(fb).vars[vi].clone();
        // `VAR PUBLIC` is visible from outside; `VAR PRIVATE`/`PROTECTED` only from
        // the class (and those derived from it).
        let declared = self.l.var_access(fb, vi);
        if !init && !self.var_accessible(fb, vi, name.span) {
            return None;
        }
        let public = matches!(
            declared,
            Some((
                crate::ast::AccessSpec::Public | crate::ast::AccessSpec::Internal,
                _
            ))
        ) || declared.is_some() && self.lexical_class().is_some();
        let visible = matches!(v.section, VarKind::Input | VarKind::Output | VarKind::InOut)
            || init
            || public;
        let storage = self.l.ir[fb.0 as usize].storage[vi];
        if let Some(Storage::Const(_)) | None = storage {
            if !visible || storage.is_none() {
                let n = self.l.text(name.span).to_string();
                self.l.error(
                    codes::E_NO_MEMBER,
                    format!(
                        "`{n}` is not an input or output of `{}`",
                        self.l.pou(fb).display
                    ),
                    name.span,
                );
                return None;
            }
        }
        // CODESYS lets outside code read the internal variables of an instance (of an
        // FB or a PROGRAM), not write them; CPDev's dialect lets it do both.
        let cpdev = self.l.cpdev_files.contains(&name.span.file);
        let outside_read = !visible && v.section == VarKind::Var && self.l.codesys && !cpdev;
        if outside_read {
            // Read only: `Access::Internal` below.
        } else if !visible && v.section == VarKind::Var && cpdev {
            let n = self.l.text(name.span).to_string();
            let fbn = self.l.pou(fb).display.clone();
            self.l.diags.push(plcc_ir::diag::Diagnostic::warning(
                codes::W_CPDEV_INTERNAL,
                format!(
                    "`{n}` is internal to `{fbn}`; the CPDev dialect lets it be used from outside"
                ),
                name.span,
            ));
        } else if !visible {
            let n = self.l.text(name.span).to_string();
            let mut d = plcc_ir::diag::Diagnostic::error(
                codes::E_NO_MEMBER,
                format!(
                    "`{n}` is internal to `{}`: only its inputs and outputs can be used from outside",
                    self.l.pou(fb).display
                ),
                name.span,
            );
            if v.section == VarKind::Var {
                d = d.with_note(
                    "CODESYS lets code outside an instance read its internal variables \
                     (not write them): `--dialect codesys` accepts such reads",
                );
            }
            self.l.diags.push(d);
            return None;
        }
        if v.section == VarKind::InOut {
            // The reference is bound by a call and means nothing outside one (before
            // the first call it points nowhere), so it is not a member one can use.
            let n = self.l.text(name.span).to_string();
            self.l.error(
                codes::E_NO_MEMBER,
                format!(
                    "`{n}` is a VAR_IN_OUT of `{}`: it refers to a variable only during a call, so it cannot be used from outside",
                    self.l.pou(fb).display
                ),
                name.span,
            );
            return None;
        }
        let Some(Storage::Field(fi)) = storage else {
            return None;
        };
        // An inherited variable is at the same field of the derived struct.
        let agg = self.l.ir[agg_of.0 as usize].agg?;
        let addr = self.b.field_addr(base, agg, fi);
        let access = if v.section == VarKind::Output && !init {
            Access::OtherOutput
        } else if outside_read && !init {
            Access::Internal
        } else {
            Access::ReadWrite
        };
        Some(Place {
            addr,
            ty: v.ty,
            access,
            bit: None,
            guard: None,
            tag: v.tag,
        })
    }
}
