//! The generator of the object-oriented part (see [`super`] for what it makes and
//! why every program it makes is valid and terminates).

use super::{Class, Iface, Method, Oo, OoStmt, Prop, Recv, Sig};
use crate::difftest::gen::{lit, Expr, Gen, Prog, Rng, Stmt, T};

/// The types of fields, method inputs and results (LREAL left out: the PIC16
/// would not hold the programs).
const TYPES: [T; 10] = [
    T::Int,
    T::Int,
    T::Dint,
    T::Sint,
    T::Uint,
    T::Bool,
    T::Bool,
    T::Real,
    T::Word,
    T::Lint,
];

/// The generator of an OO part.
struct Builder<'r> {
    rng: &'r mut Rng,
    oo: Oo,
    /// The next method number.
    next_method: usize,
    /// The next property number.
    next_prop: usize,
}

/// A declaration list of `n` names `prefix{i}` of random types with literal
/// initial values.
fn decl_list(rng: &mut Rng, prefix: &str, n: u64) -> Vec<(String, T, Expr)> {
    (0..n)
        .map(|i| {
            let t = *rng.pick(&TYPES);
            (format!("{prefix}{i}"), t, lit(rng, t))
        })
        .collect()
}

/// A program of no statements over the names `vars` (writable), for a [`Gen`]
/// working in a method's scope.
fn scope(vars: &[(String, T)]) -> Prog {
    let mut rng = Rng::new(1);
    let mut p = Gen::new(&mut rng).prog().clone();
    p.vars = vars
        .iter()
        .map(|(n, t)| (n.clone(), *t, Expr::Lit(*t, String::new())))
        .collect();
    p
}

impl<'r> Builder<'r> {
    fn sig(&mut self, result: bool) -> Sig {
        let num = self.next_method;
        self.next_method += 1;
        let n = self.rng.below(3);
        Sig {
            name: format!("M{num}"),
            num,
            inputs: (0..n)
                .map(|i| (format!("a{i}"), *self.rng.pick(&TYPES)))
                .collect(),
            result: (result || self.rng.chance(70)).then(|| *self.rng.pick(&TYPES)),
        }
    }

    /// A method with the signature `sig` whose body is made later.
    fn method(&mut self, sig: Sig, over: bool) -> Method {
        let n = self.rng.below(3);
        let locals = decl_list(self.rng, "l", n);
        let inst = if self.oo.codesys && self.rng.chance(50) {
            let n = 1 + self.rng.below(2);
            // Named by method, not class: an override's VAR_INSTs are named as
            // the overridden method's (each is a field of its own).
            decl_list(self.rng, &format!("n{}_", sig.num), n)
        } else {
            Vec::new()
        };
        Method {
            sig,
            public: true,
            over,
            is_abstract: false,
            is_final: false,
            locals,
            inst,
            body: Vec::new(),
        }
    }

    /// The interfaces: none, one, or two with the second extending the first.
    fn interfaces(&mut self) {
        let n = *self.rng.pick(&[0usize, 1, 1, 2, 2]);
        for i in 0..n {
            let methods = (0..1 + self.rng.below(2)).map(|_| self.sig(true)).collect();
            self.oo.ifaces.push(Iface {
                name: format!("IK{i}"),
                extends: (i > 0).then(|| i - 1),
                methods,
            });
        }
    }

    /// A chain of `depth` classes, the root implementing `implements`.
    fn chain(&mut self, depth: usize, implements: Vec<usize>) {
        let codesys = self.oo.codesys;
        let root_abstract = depth >= 2 && self.rng.chance(30);
        let mut finals: Vec<String> = Vec::new();
        let mut abstract_pending: Vec<String> = Vec::new();
        // The first levels may be CLASSes (a class extends only a class; a
        // FUNCTION_BLOCK may extend one).
        let class_levels = if self.rng.chance(25) {
            1 + self.rng.below(depth as u64) as usize
        } else {
            0
        };
        for level in 0..depth {
            let is_class = level < class_levels;
            let idx = self.oo.classes.len();
            let leaf = level + 1 == depth;
            let base = (level > 0).then(|| idx - 1);
            let mut methods = Vec::new();
            if level == 0 {
                let sigs: Vec<Sig> = implements
                    .iter()
                    .flat_map(|&i| self.oo.iface_methods(i))
                    .collect();
                for s in sigs {
                    if !methods.iter().any(|m: &Method| m.sig.name == s.name) {
                        methods.push(self.method(s, false));
                    }
                }
            } else {
                // Overrides: every abstract method, and some others.
                let inherited = self.oo.visible(idx - 1);
                for (m, _) in inherited {
                    let must = abstract_pending.contains(&m.sig.name);
                    if finals.contains(&m.sig.name) || !(must || self.rng.chance(50)) {
                        continue;
                    }
                    let mut nm = self.method(m.sig.clone(), true);
                    nm.public = m.public;
                    methods.push(nm);
                }
                abstract_pending.clear();
            }
            for _ in 0..1 + self.rng.below(2) {
                let s = self.sig(false);
                let mut m = self.method(s, false);
                m.public = self.rng.chance(75);
                methods.push(m);
            }
            if level == 0 && root_abstract {
                // One of its own methods is ABSTRACT, the next level implements it.
                let m = methods.last_mut().expect("an own method");
                m.is_abstract = true;
                m.locals.clear();
                m.inst.clear();
                abstract_pending.push(m.sig.name.clone());
            }
            for m in methods.iter_mut() {
                if !m.is_abstract && self.rng.chance(if leaf { 25 } else { 10 }) {
                    m.is_final = true;
                    finals.push(m.sig.name.clone());
                }
            }
            let mut props = Vec::new();
            if codesys && self.rng.chance(50) {
                let t = *self.rng.pick(&TYPES);
                props.push(Prop {
                    name: format!("P{}", self.next_prop),
                    t,
                    get: Vec::new(),
                    set: Vec::new(),
                });
                self.next_prop += 1;
            }
            let c = idx;
            let (ni, nq, ns) = (self.rng.below(3), 1 + self.rng.below(2), self.rng.below(2));
            // A class's methods write its VARs (an FB's write its outputs too).
            let (ni, nq, ns) = if is_class {
                (0, 0, 1 + ns)
            } else {
                (ni, nq, ns)
            };
            let base_is_class = level > 0 && level - 1 < class_levels;
            let class = Class {
                name: format!("K{c}"),
                base,
                implements: if level == 0 {
                    implements.clone()
                } else {
                    Vec::new()
                },
                is_abstract: level == 0 && root_abstract,
                is_final: leaf && depth > 1 && self.rng.chance(30),
                is_class,
                inputs: decl_list(self.rng, &format!("i{c}_"), ni),
                outputs: decl_list(self.rng, &format!("q{c}_"), nq),
                vars: decl_list(self.rng, &format!("s{c}_"), ns),
                methods,
                props,
                super_body: codesys && level > 0 && !base_is_class && self.rng.chance(60),
                body: Vec::new(),
            };
            self.oo.classes.push(class);
        }
    }

    /// Bodies of every method, property and FB.
    fn bodies(&mut self) {
        for c in 0..self.oo.classes.len() {
            let fields = self.oo.fields(c);
            let writable: Vec<(String, T)> = fields
                .iter()
                .filter(|f| !f.2)
                .map(|f| (f.0.clone(), f.1))
                .collect();
            let inputs: Vec<(String, T)> = fields
                .iter()
                .filter(|f| f.2)
                .map(|f| (f.0.clone(), f.1))
                .collect();
            let props = self.oo.props(c);
            for mi in 0..self.oo.classes[c].methods.len() {
                let m = self.oo.classes[c].methods[mi].clone();
                if m.is_abstract {
                    continue;
                }
                let mut w = writable.clone();
                w.extend(m.locals.iter().map(|(n, t, _)| (n.clone(), *t)));
                w.extend(m.inst.iter().map(|(n, t, _)| (n.clone(), *t)));
                if let Some(t) = m.sig.result {
                    w.push((m.sig.name.clone(), t));
                }
                let mut r = inputs.clone();
                r.extend(m.sig.inputs.iter().cloned());
                for p in &props {
                    r.push((format!("THIS^.{}", p.name), p.t));
                }
                let calls = self.callables(c, m.sig.num);
                let n = 1 + self.rng.below(4);
                let mut body = self.block(&w, &r, &calls, n, true);
                if let Some(t) = m.sig.result {
                    if self.rng.chance(70) {
                        let e = self.scoped_expr(&w, &r, &calls, t);
                        body.push(Stmt::Assign(m.sig.name.clone(), e));
                    }
                }
                self.oo.classes[c].methods[mi].body = body;
            }
            for pi in 0..self.oo.classes[c].props.len() {
                let p = self.oo.classes[c].props[pi].clone();
                let e = self.scoped_expr(&writable, &inputs, &[], p.t);
                let get = vec![Stmt::Assign(p.name.clone(), e)];
                let mut r = inputs.clone();
                r.push((p.name.clone(), p.t));
                let n = 1 + self.rng.below(2);
                let set = self.block(&writable, &r, &[], n, false);
                self.oo.classes[c].props[pi].get = get;
                self.oo.classes[c].props[pi].set = set;
            }
            // The FB body: any method may be called (nothing calls the body); no
            // loop, whose control variable a base's body might declare too.
            let calls = self.callables(c, 0);
            let n = self.rng.below(3);
            if self.oo.classes[c].is_class {
                continue;
            }
            let body = self.block(&writable, &inputs, &calls, n, false);
            self.oo.classes[c].body = body;
        }
    }

    /// The calls a method numbered `num` of class `c` may make: `THIS^.Mk` for
    /// k > num, `SUPER^.Mk` (of the base, not abstract there) for k >= num.
    fn callables(&self, c: usize, num: usize) -> Vec<(String, Sig)> {
        let mut out: Vec<(String, Sig)> = self
            .oo
            .visible(c)
            .into_iter()
            .filter(|(m, _)| m.sig.num > num)
            .map(|(m, _)| ("THIS^".to_string(), m.sig))
            .collect();
        if let Some(b) = self.oo.classes[c].base {
            out.extend(
                self.oo
                    .visible(b)
                    .into_iter()
                    .filter(|(m, _)| m.sig.num >= num && !m.is_abstract)
                    .map(|(m, _)| ("SUPER^".to_string(), m.sig)),
            );
        }
        out
    }

    /// An expression of type `t` in a method's scope (`w` writable and `r`
    /// read-only names, `calls` the methods it may call).
    fn scoped_expr(
        &mut self,
        w: &[(String, T)],
        r: &[(String, T)],
        calls: &[(String, Sig)],
        t: T,
    ) -> Expr {
        // Sometimes a call of a method with a result of type `t`.
        let fitting: Vec<&(String, Sig)> =
            calls.iter().filter(|(_, s)| s.result == Some(t)).collect();
        if !fitting.is_empty() && self.rng.chance(35) {
            let (recv, s) = (*self.rng.pick(&fitting)).clone();
            let args = s
                .inputs
                .iter()
                .map(|(_, at)| self.scoped_expr(w, r, &[], *at))
                .collect();
            return Expr::Call(t, format!("{recv}.{}", s.name), args);
        }
        let prog = scope(w);
        let mut g = Gen::over(self.rng, prog);
        g.local = true;
        g.extra = r.to_vec();
        g.expr(t)
    }

    /// `n` statements in a method's scope.
    fn block(
        &mut self,
        w: &[(String, T)],
        r: &[(String, T)],
        calls: &[(String, Sig)],
        n: u64,
        loops: bool,
    ) -> Vec<Stmt> {
        let depth = if loops { 0 } else { 2 };
        (0..n).map(|_| self.mstmt(w, r, calls, depth)).collect()
    }

    /// A statement of a method's scope; at `depth` 2 no compound statement.
    fn mstmt(
        &mut self,
        w: &[(String, T)],
        r: &[(String, T)],
        calls: &[(String, Sig)],
        depth: u32,
    ) -> Stmt {
        let k = self.rng.below(100);
        match k {
            0..=14 if !calls.is_empty() => {
                let (recv, s) = self.rng.pick(calls).clone();
                let args = s
                    .inputs
                    .iter()
                    .map(|(_, at)| self.scoped_expr(w, r, &[], *at))
                    .collect();
                let target = match s.result {
                    Some(t) => {
                        let ok: Vec<&(String, T)> = w.iter().filter(|x| x.1 == t).collect();
                        (!ok.is_empty() && self.rng.chance(60))
                            .then(|| self.rng.pick(&ok).0.clone())
                    }
                    None => None,
                };
                Stmt::Oo(Box::new(OoStmt::Call {
                    target,
                    recv: Recv::Plain(recv),
                    method: s.name.clone(),
                    args,
                    named: Vec::new(),
                }))
            }
            15..=29 if depth < 2 => {
                let c = self.scoped_expr(w, r, calls, T::Bool);
                let a = (0..1 + self.rng.below(2))
                    .map(|_| self.mstmt(w, r, calls, depth + 1))
                    .collect();
                let e = (0..self.rng.below(2))
                    .map(|_| self.mstmt(w, r, calls, depth + 1))
                    .collect();
                Stmt::If(c, a, e)
            }
            30..=37 if depth < 2 => {
                let lo = self.rng.below(3) as i64;
                let body = (0..1 + self.rng.below(2))
                    .map(|_| self.mstmt(w, r, calls, depth + 1))
                    .collect();
                Stmt::For(lo, lo + self.rng.below(3) as i64, 1, body)
            }
            _ => {
                let (n, t) = self.rng.pick(w).clone();
                let e = self.scoped_expr(w, r, calls, t);
                Stmt::Assign(n, e)
            }
        }
    }

    /// `main`'s parts: instances, interface variables and arrays, references.
    fn main_parts(&mut self) {
        let classes = self.oo.classes.len();
        for c in 0..classes {
            if self.oo.classes[c].is_abstract {
                continue;
            }
            let n = if self.rng.chance(25) { 2 } else { 1 };
            for _ in 0..n {
                let name = format!("o{}", self.oo.insts.len());
                self.oo.insts.push((name, c));
            }
        }
        for i in 0..self.oo.ifaces.len() {
            if self.rng.chance(70) {
                self.oo.itf_vars.push((format!("ov{i}"), i));
            }
            if self.rng.chance(70) {
                let len = 2 + self.rng.below(3) as usize;
                self.oo.arrays.push((format!("oa{i}"), i, len));
            }
        }
        for c in 0..classes {
            // A reference to each root whose chain has another class.
            let root = self.oo.classes[c].base.is_none();
            let derived = self.oo.classes.iter().any(|k| k.base == Some(c));
            if root && derived {
                let name = format!("orf{}", self.oo.refs.len());
                self.oo.refs.push((name, c));
            }
        }
    }

    /// Instances that are an `i`.
    fn implementers(&self, i: usize) -> Vec<String> {
        self.oo
            .insts
            .iter()
            .filter(|(_, c)| self.oo.is_a(*c, i))
            .map(|(n, _)| n.clone())
            .collect()
    }

    /// Instances whose class is `root` or derives from it.
    fn derived_from(&self, root: usize) -> Vec<String> {
        self.oo
            .insts
            .iter()
            .filter(|(_, c)| self.oo.chain(*c).contains(&root))
            .map(|(n, _)| n.clone())
            .collect()
    }

    /// A variable of `main` for a result of type `t`: one of `main`'s, or a new
    /// one of the OO part.
    fn result_var(&mut self, p: &Prog, t: T) -> String {
        let mine: Vec<String> = p
            .vars
            .iter()
            .filter(|v| v.1 == t)
            .map(|v| v.0.clone())
            .collect();
        if !mine.is_empty() && self.rng.chance(60) {
            return self.rng.pick(&mine).clone();
        }
        if let Some((n, _)) = self.oo.results.iter().find(|r| r.1 == t) {
            return n.clone();
        }
        let n = format!("ot{}", self.oo.results.len());
        self.oo.results.push((n.clone(), t));
        n
    }

    /// What `main` may read of the instances: their outputs and properties.
    fn readables(&self) -> Vec<(String, T)> {
        let mut out = Vec::new();
        for (n, c) in &self.oo.insts {
            // Outputs (`q..`); internal variables (`s..`) where CODESYS lets
            // outside code read them.
            for (f, t, _) in self.oo.fields(*c) {
                if f.starts_with('q') || (self.oo.codesys && f.starts_with('s')) {
                    out.push((format!("{n}.{f}"), t));
                }
            }
            for p in self.oo.props(*c) {
                out.push((format!("{n}.{}", p.name), p.t));
            }
        }
        out
    }

    /// An expression of `main`'s scope, which may read the instances' outputs and
    /// properties and call their methods.
    fn main_expr(&mut self, p: &Prog, t: T) -> Expr {
        if self.rng.chance(20) {
            let cands: Vec<(String, Sig)> = self
                .oo
                .insts
                .iter()
                .flat_map(|(n, c)| {
                    self.public_methods(*c)
                        .into_iter()
                        .filter(|s| s.result == Some(t))
                        .map(move |s| (n.clone(), s))
                })
                .collect();
            if !cands.is_empty() {
                let (inst, s) = self.rng.pick(&cands).clone();
                let args = s
                    .inputs
                    .iter()
                    .map(|(_, at)| {
                        let mut g = Gen::over(self.rng, p.clone());
                        g.expr(*at)
                    })
                    .collect();
                return Expr::Call(t, format!("{inst}.{}", s.name), args);
            }
        }
        let extra = self.readables();
        let mut g = Gen::over(self.rng, p.clone());
        g.extra = extra;
        g.expr(t)
    }

    /// The public methods of class `c` (none abstract: `c` is instantiated).
    fn public_methods(&self, c: usize) -> Vec<Sig> {
        self.oo
            .visible(c)
            .into_iter()
            .filter(|(m, _)| m.public && !m.is_abstract)
            .map(|(m, _)| m.sig)
            .collect()
    }

    fn args(&mut self, p: &Prog, s: &Sig) -> (Vec<Expr>, Vec<String>) {
        let args = s
            .inputs
            .iter()
            .map(|(_, t)| self.main_expr(p, *t))
            .collect();
        let named = if self.rng.chance(30) {
            s.inputs.iter().map(|(n, _)| n.clone()).collect()
        } else {
            Vec::new()
        };
        (args, named)
    }

    /// A call of a method of `sigs` on `recv`, its result (if any) into a
    /// variable of `main`.
    fn call(&mut self, p: &Prog, recv: Recv, sigs: &[Sig]) -> Option<OoStmt> {
        if sigs.is_empty() {
            return None;
        }
        let s = self.rng.pick(sigs).clone();
        let (args, named) = self.args(p, &s);
        let target = match s.result {
            Some(t) if self.rng.chance(85) => Some(self.result_var(p, t)),
            _ => None,
        };
        Some(OoStmt::Call {
            target,
            recv,
            method: s.name,
            args,
            named,
        })
    }

    /// A statement of `main` on the OO part.
    fn main_stmt(&mut self, p: &Prog) -> Option<OoStmt> {
        let reads = self.readables();
        if !reads.is_empty() && self.rng.chance(15) {
            // An output or a property read into a variable of `main` (there are
            // none when every instance is of a CLASS, outside CODESYS).
            let (name, t) = self.rng.pick(&reads).clone();
            let target = self.result_var(p, t);
            let e = match t {
                T::Bool | T::Word => Expr::Bin(
                    t,
                    "XOR",
                    Box::new(Expr::Var(t, name)),
                    Box::new(self.main_expr(p, t)),
                ),
                _ => Expr::Bin(
                    t,
                    "+",
                    Box::new(Expr::Var(t, name)),
                    Box::new(self.main_expr(p, t)),
                ),
            };
            return Some(OoStmt::Assign { target, value: e });
        }
        self.main_oo_stmt(p)
    }

    fn main_oo_stmt(&mut self, p: &Prog) -> Option<OoStmt> {
        let k = self.rng.below(100);
        match k {
            0..=24 => {
                let (inst, c) = self.rng.pick(&self.oo.insts).clone();
                let sigs = self.public_methods(c);
                self.call(p, Recv::Plain(inst), &sigs)
            }
            25..=39 if !self.oo.itf_vars.is_empty() => {
                let (v, i) = self.rng.pick(&self.oo.itf_vars).clone();
                let sigs = self.oo.iface_methods(i);
                self.call(p, Recv::Itf(v), &sigs)
            }
            40..=49 if !self.oo.arrays.is_empty() => {
                let (a, i, len) = self.rng.pick(&self.oo.arrays).clone();
                let sigs = self.oo.iface_methods(i);
                let s = self.rng.pick(&sigs).clone();
                if self.rng.chance(60) {
                    let t = s.result.expect("interface methods have results");
                    let (args, _) = self.args(p, &s);
                    let target = self.result_var(p, t);
                    Some(OoStmt::Each {
                        array: a,
                        len,
                        method: s.name,
                        args,
                        target,
                        t,
                    })
                } else {
                    let idx = self.main_expr(p, T::Int);
                    self.call(p, Recv::Elem(a, len, idx), &[s])
                }
            }
            50..=59 if !self.oo.refs.is_empty() => {
                let (r, c) = self.rng.pick(&self.oo.refs).clone();
                let sigs: Vec<Sig> = self
                    .oo
                    .visible(c)
                    .into_iter()
                    .filter(|(m, _)| m.public)
                    .map(|(m, _)| m.sig)
                    .collect();
                self.call(p, Recv::Deref(r), &sigs)
            }
            60..=74 => self.bind(),
            75..=84 => {
                // A CLASS's instances are not invoked.
                let fbs: Vec<(String, usize)> = (self.oo.insts.iter())
                    .filter(|(_, c)| !self.oo.classes[*c].is_class)
                    .cloned()
                    .collect();
                if fbs.is_empty() {
                    return None;
                }
                let (inst, c) = self.rng.pick(&fbs).clone();
                let ins: Vec<(String, T)> = self
                    .oo
                    .fields(c)
                    .into_iter()
                    .filter(|f| f.2)
                    .map(|f| (f.0, f.1))
                    .collect();
                let mut args = Vec::new();
                for (n, t) in ins {
                    if self.rng.chance(60) {
                        args.push((n, self.main_expr(p, t)));
                    }
                }
                Some(OoStmt::Invoke { inst, args })
            }
            _ => {
                let (inst, c) = self.rng.pick(&self.oo.insts).clone();
                let mut members: Vec<(String, T)> = self
                    .oo
                    .fields(c)
                    .into_iter()
                    .filter(|f| f.2)
                    .map(|f| (f.0, f.1))
                    .collect();
                members.extend(self.oo.props(c).into_iter().map(|p| (p.name, p.t)));
                if members.is_empty() {
                    return None;
                }
                let (member, t) = self.rng.pick(&members).clone();
                let value = self.main_expr(p, t);
                Some(OoStmt::SetMember {
                    inst,
                    member,
                    value,
                })
            }
        }
    }

    /// Binding an interface variable, an array element or a reference.
    fn bind(&mut self) -> Option<OoStmt> {
        let mut kinds = Vec::new();
        if !self.oo.itf_vars.is_empty() {
            kinds.push(0);
        }
        if !self.oo.arrays.is_empty() {
            kinds.push(1);
        }
        if !self.oo.refs.is_empty() {
            kinds.push(2);
        }
        if kinds.is_empty() {
            return None;
        }
        let null = self.rng.chance(10);
        let (place, cands) = match *self.rng.pick(&kinds) {
            0 => {
                let (v, i) = self.rng.pick(&self.oo.itf_vars).clone();
                (Recv::Itf(v), self.implementers(i))
            }
            1 => {
                let (a, i, len) = self.rng.pick(&self.oo.arrays).clone();
                let idx = Expr::Lit(T::Int, self.rng.below(len as u64).to_string());
                (Recv::Elem(a, len, idx), self.implementers(i))
            }
            _ => {
                let (r, c) = self.rng.pick(&self.oo.refs).clone();
                (Recv::Deref(r), self.derived_from(c))
            }
        };
        if cands.is_empty() {
            return None;
        }
        let value = (!null).then(|| self.rng.pick(&cands).clone());
        Some(OoStmt::Bind { place, value })
    }
}

/// Adds an OO part to `p`, with its statements in `p`'s body. Programs with a
/// CONFIGURATION lose it (their several instances of `main` would not fit the
/// PIC16 with the instances of the OO part).
pub fn add(p: &mut Prog, rng: &mut Rng) {
    let codesys = rng.chance(40);
    let mut b = Builder {
        rng,
        oo: Oo {
            codesys,
            ..Oo::default()
        },
        next_method: 0,
        next_prop: 0,
    };
    b.interfaces();
    let nif = b.oo.ifaces.len();
    // One chain, or two implementing the interfaces (several implementers).
    let chains = if nif > 0 && b.rng.chance(60) { 2 } else { 1 };
    for k in 0..chains {
        let depth = *b.rng.pick(&[1usize, 2, 2, 3, 3]);
        let implements = match (nif, k) {
            (0, _) => Vec::new(),
            (_, 0) => vec![nif - 1],
            _ => vec![0],
        };
        b.chain(depth, implements);
    }
    b.bodies();
    b.main_parts();
    p.config = None;
    // Bindings first (most calls through interfaces then find an instance), then
    // statements anywhere in the body.
    let mut first = Vec::new();
    for _ in 0..1 + b.rng.below(3) {
        if let Some(s) = b.bind() {
            first.push(Stmt::Oo(Box::new(s)));
        }
    }
    for _ in 0..3 + b.rng.below(6) {
        if let Some(s) = b.main_stmt(p) {
            let at = b.rng.below(p.body.len() as u64 + 1) as usize;
            p.body.insert(at, Stmt::Oo(Box::new(s)));
        }
    }
    for (i, s) in first.into_iter().enumerate() {
        p.body.insert(i, s);
    }
    p.oo = Some(b.oo);
}
