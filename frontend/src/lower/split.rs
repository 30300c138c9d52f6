//! Lowering the POU bodies on two threads.
//!
//! Bodies are lowered in POU order, and each one may add to the build's shared
//! tables: array and reference types, IR aggregates, helper functions, standard
//! functions first used, interned names. The split keeps the result exactly what
//! lowering in order gives, by speculating and checking:
//!
//! - The used POUs are cut in two halves of about equal cost (source size, and a
//!   fixed part per POU: [`POU_COST_BYTES`]). The calling
//!   thread lowers the first half in its own [`Lowerer`]; a copy of the lowerer made
//!   just before ([`Lowerer::fork`]) lowers the second half on another thread.
//! - The copy stops at the first POU that adds to a shared table ([`Footprint`]) or
//!   uses a block name nothing declares. Every lookup the POUs before it made found
//!   what was there before the split, which lowering in order would have found too,
//!   so their bodies are the ones lowering in order makes. Their functions, their
//!   storage, their diagnostics (after the first half's), their calls and their
//!   temporaries' types are moved over.
//! - The calling thread then lowers the POU the copy stopped at, and splits what is
//!   left again (each round lowers at least one POU, so it ends).
//!
//! Lazily computed facts about other POUs (folded constants) that the copy computed
//! are not moved; the calling thread computes them again when it needs them, and a
//! diagnostic reported twice that way is removed with the other duplicates at the
//! end of [`Lowerer::run`].
//!
//! Invariant: every table a body can add to is counted in [`Footprint`]. A test
//! lowers every program of the repository and of `../shared` both ways, split as
//! often as it can be, and compares modules and diagnostics.

use super::{CallNode, Lowerer, PouIr};
use crate::intern::Interner;
use crate::types::PouId;
use plcc_ir::diag::{Diagnostic, Span};
use plcc_ir::{FuncId, FuncKind, Function};

/// When the bodies are lowered on two threads ([`super::LowerOptions::parallel_bodies`]).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum ParallelBodies {
    /// When the used POUs' source is large enough to pay for the copy and the
    /// machine has two cores.
    #[default]
    Auto,
    /// Never: one thread, in order.
    Never,
    /// Whenever there are two POUs or more left, on any machine (for tests that
    /// compare the two ways).
    Always,
}

/// Below this many bytes of used POUs' source, the bodies are lowered on one thread.
const MIN_SOURCE_BYTES: usize = 256 * 1024;

/// What lowering a POU costs besides its source, in bytes of source that cost as
/// much: its functions, their entry and exit, an instance's init function. Measured
/// on gen_synth 2000 (its first half by size holds every FUNCTION): with 0 the first
/// half finished 4-8 ms after the second; from 400 to 1,000 within about 2 ms.
const POU_COST_BYTES: usize = 600;

/// The sizes of every table lowering a body can add to. Two equal footprints, one
/// taken before and one after some bodies were lowered, mean those bodies added
/// nothing shared.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Footprint(Vec<usize>);

/// What the copy made of the second half: its first `done` POUs.
struct Second {
    /// How many POUs of the half were lowered without adding anything shared.
    done: usize,
    /// The lowered functions (bodies and init functions), unless bodies are dropped.
    funcs: Vec<(FuncId, Function)>,
    /// The POUs' IR records (where their variables live).
    ir: Vec<(PouId, PouIr)>,
    diags: Vec<Diagnostic>,
    calls: Vec<(CallNode, CallNode, Span)>,
    temp_types: crate::print::TempTypes,
}

impl<'s> Lowerer<'s> {
    /// Lowers the body of every used POU, on two threads when `how` and the build's
    /// size say so (see the module doc).
    pub(super) fn lower_bodies(&mut self, how: ParallelBodies) {
        let used: Vec<PouId> = (0..self.pous.len())
            .filter(|&i| self.used[i])
            .map(|i| PouId(i as u32))
            .collect();
        // Each POU's cost: its source size and a fixed part (measured once for every
        // round).
        let all_sizes: Vec<usize> = used
            .iter()
            .map(|&p| {
                let s = self.pou_ast(p).span;
                (s.end - s.start) as usize + POU_COST_BYTES
            })
            .collect();
        let mut from = 0;
        loop {
            let rest = &used[from..];
            let sizes = &all_sizes[from..];
            let total: usize = sizes.iter().sum();
            let split = match how {
                ParallelBodies::Never => false,
                ParallelBodies::Always => rest.len() >= 2,
                ParallelBodies::Auto => {
                    total >= MIN_SOURCE_BYTES && plcc_ir::parallel::threads() >= 2
                }
            };
            if !split {
                for &p in rest {
                    self.lower_pou(p);
                }
                return;
            }
            // The first half: the POUs before the middle of the source.
            let mut acc = 0;
            let mid = sizes
                .iter()
                .position(|&s| {
                    acc += s;
                    acc * 2 >= total
                })
                .map_or(rest.len() / 2, |i| i + 1)
                .clamp(1, rest.len() - 1);
            let (first, second) = rest.split_at(mid);
            let before = self.footprint();
            let mut interner = self.interner.clone();
            let fork = self.fork(&mut interner);
            let done = std::thread::scope(|scope| {
                let worker = scope.spawn(|| fork.lower_half(second, &before));
                for &p in first {
                    self.lower_pou(p);
                }
                worker.join()
            });
            // A copy that failed (a panic) did nothing; lowering here reports it.
            let done = done.map_or(0, |s| self.take_second(s));
            #[cfg(test)]
            if done == second.len() {
                tests::KEPT.with(|n| n.set(n.get() + 1));
            } else {
                tests::REDONE.with(|n| n.set(n.get() + 1));
            }
            if done == second.len() {
                return;
            }
            // The POU that added something shared is lowered here, after the ones
            // before it; the rest is split again.
            self.lower_pou(second[done]);
            from += mid + done + 1;
        }
    }

    /// A copy of this lowerer for lowering bodies on another thread: the same tables,
    /// its own interner (a copy of this one's), and no diagnostics, calls or
    /// temporaries' types yet (those it makes are appended to this lowerer's).
    fn fork<'w>(&self, interner: &'w mut Interner) -> Lowerer<'w>
    where
        's: 'w,
    {
        Lowerer {
            sources: self.sources,
            interner,
            units: self.units,
            pous: self.pous.clone(),
            pou_by_name: self.pou_by_name.clone(),
            types: self.types.clone(),
            user: self.user.clone(),
            diags: Vec::new(),
            module: self.module.clone(),
            ir: self.ir.clone(),
            array_aggs: self.array_aggs.clone(),
            prototypes: self.prototypes.clone(),
            actions: self.actions.clone(),
            action_bodies: self.action_bodies.clone(),
            string_aggs: self.string_aggs.clone(),
            helpers: self.helpers.clone(),
            calls: Vec::new(),
            used: self.used.clone(),
            pending: self.pending.clone(),
            unsupported_names: self.unsupported_names.clone(),
            unknown_uses: Vec::new(),
            globals_pou: self.globals_pou,
            globals_data: self.globals_data,
            cpdev_files: self.cpdev_files.clone(),
            codesys: self.codesys,
            inline_c: self.inline_c,
            drop_bodies: self.drop_bodies,
            run_programs: self.run_programs.clone(),
            library: self.library.clone(),
            program_data: self.program_data.clone(),
            ref_depth: self.ref_depth,
            classes: self.classes.clone(),
            temp_types: Default::default(),
            scratch: None,
            builtins: self.builtins.clone(),
        }
    }

    /// Lowers `pous` in this (forked) lowerer, in order, until one adds to a table
    /// of `before` or uses a block name nothing declares (whose reports are merged
    /// by their diagnostics' places, which the copy does not share), and hands over
    /// what the POUs before that one made.
    fn lower_half(mut self, pous: &[PouId], before: &Footprint) -> Second {
        let mut done = 0;
        let (mut diags, mut calls) = (0, 0);
        let mut temp_types = crate::print::TempTypes::default();
        for &p in pous {
            self.lower_pou(p);
            if self.footprint() != *before || !self.unknown_uses.is_empty() {
                break;
            }
            done += 1;
            (diags, calls) = (self.diags.len(), self.calls.len());
            // Compiler temporaries are IL's; a later POU may give a name another type.
            if !self.temp_types.is_empty() {
                temp_types.clone_from(&self.temp_types);
            }
        }
        self.diags.truncate(diags);
        self.calls.truncate(calls);
        let mut funcs = Vec::new();
        let mut ir = Vec::with_capacity(done);
        for &p in &pous[..done] {
            let rec = std::mem::take(&mut self.ir[p.0 as usize]);
            if !self.drop_bodies {
                for f in [rec.body, rec.init].into_iter().flatten() {
                    let gone = Function::new("", FuncKind::Init, Vec::new(), None);
                    funcs.push((
                        f,
                        std::mem::replace(&mut self.module.funcs[f.index()], gone),
                    ));
                }
            }
            ir.push((p, rec));
        }
        Second {
            done,
            funcs,
            ir,
            diags: self.diags,
            calls: self.calls,
            temp_types,
        }
    }

    /// Moves the second half's work into this lowerer, after the first half's;
    /// returns how many of its POUs it lowered.
    fn take_second(&mut self, s: Second) -> usize {
        for (f, func) in s.funcs {
            self.module.funcs[f.index()] = func;
        }
        for (p, rec) in s.ir {
            self.ir[p.0 as usize] = rec;
        }
        self.diags.extend(s.diags);
        self.calls.extend(s.calls);
        self.temp_types.extend(s.temp_types);
        s.done
    }

    /// The sizes of the tables bodies can add to (see [`Footprint`]).
    fn footprint(&self) -> Footprint {
        let (arrays, refs) = self.types.counts();
        let c = &self.classes;
        let m = &self.module;
        Footprint(vec![
            self.interner.len(),
            arrays,
            refs,
            self.user.named.len(),
            self.user.by_name.len(),
            self.user.structs.len(),
            self.user.enums.len(),
            self.user.tags.len(),
            self.user.enum_values.len(),
            m.aggs.len(),
            m.data.len(),
            m.funcs.len(),
            m.tables.len(),
            m.programs.len(),
            self.pous.len(),
            self.pou_by_name.len(),
            self.ir.len(),
            self.array_aggs.len(),
            self.string_aggs.len(),
            self.helpers.len(),
            self.prototypes.len(),
            self.actions.len(),
            self.action_bodies.len(),
            self.pending.len(),
            self.unsupported_names.len(),
            self.program_data.len(),
            c.ifaces.len(),
            c.iface_by_name.len(),
            c.methods.len(),
            c.props.len(),
            c.implements.len(),
            c.class_id.len(),
            c.dispatchers.len(),
            c.body_copies.len(),
            c.pending_copies.len(),
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::ParallelBodies;
    use crate::lower::{LowerOptions, PrintAs};
    use crate::source::{SourceFile, SourceMap};
    use crate::test_files::{files_under, repo_root, shared};
    use crate::{compile, Lang};
    use std::cell::Cell;

    thread_local! {
        /// Splits made on this thread whose second half was kept.
        pub(super) static KEPT: Cell<usize> = const { Cell::new(0) };
        /// Splits made on this thread whose second half was lowered again in order.
        pub(super) static REDONE: Cell<usize> = const { Cell::new(0) };
    }

    fn count(c: &'static std::thread::LocalKey<Cell<usize>>) -> usize {
        c.with(Cell::get)
    }

    /// What a build of one file gives: the module, the diagnostics, the build
    /// printed as ST (which shows the compiler temporaries' types).
    fn build(name: &str, text: &str, lang: Lang, how: ParallelBodies, check: bool) -> String {
        let mut sources = SourceMap::new();
        let file = sources.add(SourceFile::new(name, text));
        let opts = LowerOptions {
            parallel_bodies: how,
            check_only: check,
            print: if check { PrintAs::Nothing } else { PrintAs::St },
            ..Default::default()
        };
        let c = compile(&mut sources, &[(file, lang)], &opts);
        format!("{:?}\n{:?}\n{:?}", c.module, c.diagnostics, c.printed)
    }

    /// Builds every file both ways (and both ways under `check_only`); returns how
    /// many files were compared.
    fn compare(dirs: Vec<std::path::PathBuf>) -> usize {
        let files = files_under(dirs, |p| {
            Lang::from_path(&p.display().to_string()).is_some()
        });
        for (name, text) in &files {
            let lang = Lang::from_path(name).expect("kept by its extension");
            for check in [false, true] {
                let in_order = build(name, text, lang, ParallelBodies::Never, check);
                let split = build(name, text, lang, ParallelBodies::Always, check);
                assert!(
                    in_order == split,
                    "{name} (check_only {check}): the split differs"
                );
            }
        }
        files.len()
    }

    /// A PROGRAM and two FUNCTION_BLOCKs, the last one (the second half: the first
    /// two are longer) with variables `decls` and body `second`.
    fn second_adds(decls: &str, second: &str) -> String {
        let long = "x := x + 1;\n".repeat(40);
        format!(
            "PROGRAM main\nVAR a : A; b : B; END_VAR\na(); b();\nEND_PROGRAM\n\
             FUNCTION_BLOCK A\nVAR x : INT; END_VAR\n{long}END_FUNCTION_BLOCK\n\
             FUNCTION_BLOCK B\n{decls}\n{second}\nEND_FUNCTION_BLOCK\n"
        )
    }

    #[test]
    fn a_second_half_that_adds_something_shared_is_lowered_again_in_order() {
        let cases = [
            // A string type's IR array.
            ("VAR_TEMP s : STRING[77]; END_VAR", "s := 'x';"),
            // A standard string function, lowered after the POUs.
            (
                "VAR s : STRING; t : STRING; END_VAR",
                "t := CONCAT(s, 'y'); t := INSERT(t, s, 2);",
            ),
            // An array type's IR array.
            ("VAR_TEMP v : ARRAY[0..6] OF LREAL; END_VAR", "v[2] := 1.5;"),
            // A FUNCTION nothing declares (the reports of one name are merged).
            ("VAR r : INT; END_VAR", "r := Nowhere(1);"),
        ];
        for (k, (decls, body)) in cases.into_iter().enumerate() {
            let text = second_adds(decls, body);
            for check in [false, true] {
                let redone = count(&REDONE);
                let in_order = build("t.st", &text, Lang::St, ParallelBodies::Never, check);
                let split = build("t.st", &text, Lang::St, ParallelBodies::Always, check);
                assert!(in_order == split, "{text}: the split differs");
                assert!(
                    count(&REDONE) > redone,
                    "case {k} (check_only {check}): kept"
                );
            }
        }
    }

    #[test]
    fn bodies_lowered_on_two_threads_give_the_build_lowered_in_order() {
        let root = repo_root();
        let n = compare(vec![root.join("examples"), root.join("tests")]);
        assert!(n > 500, "{n} files");
        let (kept, redone) = (count(&KEPT), count(&REDONE));
        eprintln!("repository: {n} files, splits kept {kept}, lowered again {redone}");
        // Most files add nothing shared in their second half; some do.
        assert!(
            kept > 300 && redone > 20,
            "kept {kept}, lowered again {redone}"
        );
        match shared() {
            Some(shared) => {
                let n = compare(vec![shared]);
                let kept = count(&KEPT) - kept;
                let redone = count(&REDONE) - redone;
                eprintln!("../shared: {n} files, splits kept {kept}, lowered again {redone}");
                assert!(n > 300, "{n} files");
            }
            None => eprintln!("NOTICE: ../shared is absent: its programs were not lowered split"),
        }
    }
}
