//! Directly represented variables used in statements without a declaration (IEC
//! 61131-3, 6.5.5: `%QX0.1 := %IX0.0;`, `%MW4 := %MW4 + 1;`).
//!
//! Every address a body uses becomes a name before lowering: the variable declared
//! `AT` that address, when the POU or a global list declares one (so that both
//! reach the same storage), else an implicit global `__AT_<address>` (`__AT_QX0_1`)
//! declared `AT` it, of the type its size gives: X BOOL, B BYTE, W WORD, D DWORD,
//! L LWORD. An address without a size (`%I0.1`) or a wildcard (`%I*`) is E0205.

use crate::ast::{
    ExprKind, Ident, Item, Pou, SourceUnit, Stmt, TypeSpec, VarBlock, VarDecl, VarKind,
};
use crate::codes;
use crate::intern::{Interner, Symbol};
use crate::source::SourceMap;
use plcc_ir::diag::{Diagnostic, Span};
use std::collections::BTreeMap;

/// `%QX0.1` as a key: upper case, no spaces.
fn key(a: &str) -> String {
    a.chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_uppercase()
}

/// The names located variables are declared with in `blocks`, by address.
fn located(blocks: &[VarBlock]) -> impl Iterator<Item = (String, Symbol)> + '_ {
    blocks.iter().flat_map(|b| &b.decls).filter_map(|d| {
        let (loc, _) = d.location.as_ref()?;
        (d.names.len() == 1).then(|| (key(loc), d.names[0].sym))
    })
}

/// The bodies of a POU: its own and its actions'.
fn bodies(p: &mut Pou) -> impl Iterator<Item = &mut Vec<Stmt>> {
    std::iter::once(&mut p.body.stmts).chain(p.actions.iter_mut().map(|a| &mut a.body.stmts))
}

/// Gives every direct address in a statement its variable (see the module's text);
/// the implicit globals go into a block of `units`' first unit. The bodies of a unit
/// whose source has no `%` (which every direct address starts with, in ST, IL and
/// PLCopen XML alike) are not walked.
pub fn resolve(
    units: &mut [SourceUnit],
    sources: &SourceMap,
    interner: &mut Interner,
    diags: &mut Vec<Diagnostic>,
) {
    // Located globals, by address.
    let mut globals: BTreeMap<String, Symbol> = BTreeMap::new();
    for unit in units.iter() {
        for item in &unit.items {
            let blocks: &[VarBlock] = match item {
                Item::Globals(b) => std::slice::from_ref(b),
                Item::Configuration(c) => &c.var_blocks,
                _ => continue,
            };
            globals.extend(located(blocks));
            if let Item::Configuration(c) = item {
                for r in &c.resources {
                    globals.extend(located(&r.var_blocks));
                }
            }
        }
    }
    // The implicit ones made, by address: (name, type, first use).
    let mut implicit: BTreeMap<String, (Symbol, &'static str, Span)> = BTreeMap::new();
    for unit in units.iter_mut() {
        if !sources.get(unit.file).text.contains('%') {
            continue;
        }
        for item in &mut unit.items {
            let Item::Pou(p) = item else { continue };
            let own: BTreeMap<String, Symbol> = located(&p.var_blocks).collect();
            for stmts in bodies(p) {
                crate::visit::each_expr_mut(stmts, &mut |e| {
                    let ExprKind::DirectAddress(a) = &e.kind else {
                        return;
                    };
                    let k = key(a);
                    let sym = match own.get(&k).or_else(|| globals.get(&k)) {
                        Some(&s) => s,
                        None => {
                            let size = k.chars().nth(2);
                            let ty = match size {
                                Some('X') => "BOOL",
                                Some('B') => "BYTE",
                                Some('W') => "WORD",
                                Some('D') => "DWORD",
                                Some('L') => "LWORD",
                                _ => {
                                    diags.push(
                                        Diagnostic::error(
                                            codes::E_BAD_DECLARATION,
                                            format!("`{a}` has no size: a direct address used in a statement needs one (`%IX0.1`, `%IW2`)"),
                                            e.span,
                                        )
                                        .with_label("X, B, W, D or L after I, Q or M"),
                                    );
                                    return;
                                }
                            };
                            let name = format!("__AT_{}", k[1..].replace('.', "_"));
                            implicit
                                .entry(k.clone())
                                .or_insert_with(|| (interner.intern(&name), ty, e.span))
                                .0
                        }
                    };
                    e.kind = ExprKind::Name(Ident { sym, span: e.span });
                });
            }
        }
    }
    if implicit.is_empty() {
        return;
    }
    let decls: Vec<VarDecl> = implicit
        .into_iter()
        .map(|(k, (sym, ty, at))| VarDecl {
            names: vec![Ident { sym, span: at }],
            location: Some((k.into_boxed_str(), at)),
            ty: TypeSpec::Named(Ident {
                sym: interner.intern(ty),
                span: at,
            }),
            init: None,
            edge: None,
            span: at,
        })
        .collect();
    let at = decls[0].span;
    let Some(first) = units.first_mut() else {
        return;
    };
    first.items.push(Item::Globals(VarBlock {
        kind: VarKind::Global,
        constant: false,
        retain: false,
        list: None,
        decls,
        span: at,
    }));
}
