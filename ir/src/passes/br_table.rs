//! `br_table` as compares, for the targets whose machines have no indirect jump.
//!
//! The CPDev VM's jumps take immediate addresses only, so the `vmasm` backend runs
//! this pass before its instruction selection; so does the PIC16 backend (after
//! linking the soft-float routines, which may have tables of their own). Each
//! `br_table` becomes a balanced binary search over the runs of equal destinations
//! of its table, the indexes past the table being one more run (the default's): at
//! every step `icmp ult arg, start` (the index read unsigned, as `br_table` reads it)
//! splits the runs in two halves, until one run is left, whose destination (with its
//! block arguments) the last branch takes. A table of `n` runs costs at most
//! `ceil(log2(n))` compares on any path, where the compare chain a front end would
//! write costs one per label.
//!
//! The PIC16 jumps through tables of [`PIC16_MIN_TABLE`] entries or more in constant
//! time (a computed `GOTO`: `MOVWF PCL` into a table of `GOTO`s) and expands only the
//! smaller ones ([`run_below`]), where the search is shorter than the table's setup.

use crate::diag::Span;
use crate::entities::{Block, Value};
use crate::function::Function;
use crate::inst::{BlockCall, InstData, IntCC};
use crate::module::Module;
use crate::types::Type;

/// Expands every `br_table` of every function of `module`; true if there was one.
pub fn run_module(module: &mut Module) -> bool {
    module
        .funcs
        .iter_mut()
        .fold(false, |changed, f| run(f) | changed)
}

/// The smallest table the PIC16 backend jumps through rather than searches.
pub const PIC16_MIN_TABLE: usize = 4;

/// Expands every `br_table` of `func` into compares and `brif`s; true if there was
/// one. The new blocks follow the block of their `br_table` in the layout.
pub fn run(func: &mut Function) -> bool {
    run_below(func, usize::MAX)
}

/// [`run`] for the tables of fewer than `len` entries only.
pub fn run_below(func: &mut Function, len: usize) -> bool {
    let old = std::mem::take(&mut func.layout);
    let mut layout = Vec::with_capacity(old.len());
    let mut changed = false;
    for b in old {
        layout.push(b);
        let Some(t) = func.blocks[b.index()].insts.last().copied() else {
            continue;
        };
        let InstData::BrTable {
            arg,
            default,
            table,
        } = func.inst(t).clone()
        else {
            continue;
        };
        if table.len() >= len {
            continue;
        }
        func.blocks[b.index()].insts.pop();
        let ty = func.value_type(arg);
        let runs = runs(ty, &default, &table);
        let span = func.spans.get(t.index()).copied().flatten();
        let mut e = Expander {
            func,
            arg,
            ty,
            span,
            blocks: &mut layout,
        };
        match runs.as_slice() {
            [(_, only)] => {
                let dest = (*only).clone();
                e.push(b, InstData::Jump { dest }, None);
            }
            _ => e.split(b, &runs),
        }
        changed = true;
    }
    func.layout = layout;
    changed
}

/// The runs of equal destinations: `(first index, destination)` in the order of the
/// indexes, each run reaching to the next one's first index, the last to the largest
/// value of `ty` read unsigned. Entries no index of `ty` reaches are left out.
fn runs<'t>(ty: Type, default: &'t BlockCall, table: &'t [BlockCall]) -> Vec<(u64, &'t BlockCall)> {
    let max = ty.zext_bits(-1);
    let mut runs: Vec<(u64, &BlockCall)> = Vec::new();
    for (k, d) in table.iter().enumerate() {
        let k = k as u64;
        if k > max {
            return runs;
        }
        if runs.last().is_none_or(|&(_, last)| last != d) {
            runs.push((k, d));
        }
    }
    // Every index from the table's length on takes the default.
    let past = table.len() as u64;
    if past <= max && runs.last().is_none_or(|&(_, last)| last != default) {
        runs.push((table.len() as u64, default));
    }
    runs
}

struct Expander<'f, 'l> {
    func: &'f mut Function,
    arg: Value,
    ty: Type,
    span: Option<Span>,
    blocks: &'l mut Vec<Block>,
}

impl Expander<'_, '_> {
    fn push(&mut self, b: Block, data: InstData, ty: Option<Type>) -> Option<Value> {
        let i = self.func.create_inst(data, ty, self.span);
        self.func.blocks[b.index()].insts.push(i);
        self.func.result(i)
    }

    /// Ends block `b` with the search among `runs` (at least two).
    fn split(&mut self, b: Block, runs: &[(u64, &BlockCall)]) {
        let mid = runs.len() / 2;
        let imm = self.ty.canon_int(runs[mid].0 as i64);
        let k = self.push(b, InstData::Iconst { ty: self.ty, imm }, Some(self.ty));
        let k = k.expect("a constant has a result");
        let below = self.push(
            b,
            InstData::Icmp {
                cond: IntCC::Ult,
                args: [self.arg, k],
            },
            Some(Type::I1),
        );
        let below = below.expect("a compare has a result");
        let then_dest = Box::new(self.target(&runs[..mid]));
        let else_dest = Box::new(self.target(&runs[mid..]));
        self.push(
            b,
            InstData::Brif {
                cond: below,
                then_dest,
                else_dest,
            },
            None,
        );
    }

    /// Where the search among `runs` (at least one) goes on: the destination of a
    /// single run, else a new block searching them.
    fn target(&mut self, runs: &[(u64, &BlockCall)]) -> BlockCall {
        if let [(_, only)] = runs {
            return (*only).clone();
        }
        let nb = self.func.create_block();
        self.blocks.push(nb);
        self.split(nb, runs);
        BlockCall::new(nb, Vec::new())
    }
}
