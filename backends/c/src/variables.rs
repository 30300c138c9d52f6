//! `VARIABLES.csv`: the list a runtime's debugger is generated from (matiec's
//! format): the program instances, then every variable with its class, its path (the
//! C names, dotted: a consumer turns `CONFIG0.RES0.INSTANCE0.T1.Q` into
//! `RES0__INSTANCE0.T1.Q` and `CONFIG0.G1` into `CONFIG0__G1`), its elementary type
//! and its declared type, and the common tick in ns.
//!
//! Rows: the configuration's globals, the resources' globals, then each program
//! instance (an `FB` row) followed by its variables in declaration order, FB
//! instances expanded in place. Classes: `IN`, `OUT`, `MEM` for variables located at
//! `%I`, `%Q`, `%M`; `FB` for program and FB instances; `VAR` for the others. STRUCT
//! and array variables (and strings, which are arrays in plcc) have no row, as in
//! matiec's list; neither have `VAR_IN_OUT` and reference variables (addresses).

use crate::names::{ident, Names};
use crate::repr::Repr;
use plcc_ir::module::{AggDef, StructDef};
use plcc_ir::types::MemType;
use plcc_ir::{AggId, Module};
use std::fmt::Write;

struct Rows {
    text: String,
    n: usize,
}

impl Rows {
    fn row(&mut self, class: &str, path: &str, base: &str, declared: &str) {
        let _ = writeln!(
            self.text,
            "{};{class};{path};{path};{base};{declared};0;",
            self.n
        );
        self.n += 1;
    }

    /// The rows of the fields of struct `agg` under `path`.
    fn fields(&mut self, module: &Module, names: &Names, agg: AggId, path: &str) {
        let AggDef::Struct(s) = module.agg(agg) else {
            return;
        };
        for k in 0..s.fields.len() {
            let p = format!("{path}.{}", names.fields[agg.index()][k]);
            self.member(module, names, s, names.repr.fields[agg.index()][k], k, &p);
        }
    }

    fn member(
        &mut self,
        module: &Module,
        names: &Names,
        s: &StructDef,
        repr: Repr,
        k: usize,
        path: &str,
    ) {
        let f = &s.fields[k];
        let declared = |base: &str| f.elem.map_or(base.to_string(), |e| e.name().to_string());
        match (repr, f.ty) {
            (Repr::Var(t), _) => self.row("VAR", path, t, &declared(t)),
            (Repr::Located(i), _) => {
                let l = &names.repr.located[i];
                let class = match l.addr.dir {
                    'I' => "IN",
                    'Q' => "OUT",
                    _ => "MEM",
                };
                self.row(class, path, l.ty, &declared(l.ty));
            }
            (Repr::Plain, MemType::Agg(b)) if crate::repr::wraps(module, b) => {
                // The block's IEC name (plcc's own TON is PLCC_TON in C).
                self.row("FB", path, &ident(module.agg(b).name()), "");
                self.fields(module, names, b, path);
            }
            _ => {}
        }
    }
}

/// `VARIABLES.csv` of `module`, whose common tick is `tick_ns`.
pub fn csv(module: &Module, names: &Names, tick_ns: u64) -> String {
    let config = &names.config_c;
    let res_of = |p: usize| &names.resources[names.program_resource[p]].c;
    let mut s = String::from("// Programs\n");
    for (k, p) in module.programs.iter().enumerate() {
        let ty = match module.data[p.data.index()].ty {
            MemType::Agg(a) => names.aggs[a.index()].clone(),
            MemType::Scalar(_) => continue,
        };
        let inst = instance(names, p.data.index(), res_of(k));
        let _ = writeln!(s, "{k};{config}.{}.{inst};{ty};", res_of(k));
    }
    s.push_str("\n// Variables\n");
    let mut rows = Rows {
        text: String::new(),
        n: 0,
    };
    if let Some(MemType::Agg(g)) = names.globals_data.map(|d| module.data[d.index()].ty) {
        if let AggDef::Struct(st) = module.agg(g) {
            // The configuration's, then each resource's.
            for scope in std::iter::once(None).chain((0..names.resources.len()).map(Some)) {
                for k in 0..st.fields.len() {
                    if names.global_scope[k] != scope {
                        continue;
                    }
                    let var = &names.globals[k];
                    let short = var.split_once("__").map_or(var.as_str(), |(_, n)| n);
                    let path = match scope {
                        None => format!("{config}.{short}"),
                        Some(r) => format!("{config}.{}.{short}", names.resources[r].c),
                    };
                    let repr = names.repr.fields[g.index()][k];
                    rows.member(module, names, st, repr, k, &path);
                }
            }
        }
    }
    for (k, p) in module.programs.iter().enumerate() {
        let MemType::Agg(a) = module.data[p.data.index()].ty else {
            continue;
        };
        let inst = instance(names, p.data.index(), res_of(k));
        let path = format!("{config}.{}.{inst}", res_of(k));
        rows.row("FB", &path, &names.aggs[a.index()], "");
        rows.fields(module, names, a, &path);
    }
    s.push_str(&rows.text);
    let _ = write!(s, "\n// Ticktime\n{tick_ns}\n");
    s
}

/// The instance's name in a path: its C variable without the resource's prefix.
fn instance<'n>(names: &'n Names, data: usize, res: &str) -> &'n str {
    let var = &names.data[data];
    var.strip_prefix(res)
        .and_then(|v| v.strip_prefix("__"))
        .unwrap_or(var)
}
