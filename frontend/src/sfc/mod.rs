//! Sequential function charts (IEC 61131-3, 6.7) turned into Structured Text.
//!
//! A POU whose body is a chart ([`ast::Sfc`]) is written again as ST: its header and
//! declarations copied, a variable per step (`S.X`, `S.T`, of the standard library's
//! `__SFC_STEP`) and per action (its control: `A.Q`), and a body that makes one
//! evolution of the chart per call under the chosen [`Profile`] (`emit`). The text
//! is a source file of its own, "`FILE` (SFC as ST)", parsed like any ST file; its
//! [`SpanMap`] sends diagnostics about it back to the chart, exactly where it copies
//! the user's text (conditions, durations, action bodies), else to the element it was
//! made from. The structural checks (`check`) run on the chart first.
//!
//! Every later stage sees ordinary ST, so every target runs charts.

mod check;
mod control;
mod draw;
mod emit;
mod safety;
#[cfg(test)]
mod tests;

use crate::ast::{self, Item, Sfc, SourceUnit};
use crate::intern::Interner;
use crate::plcopen::map::SpanMap;
use crate::source::{SourceFile, SourceMap};
use plcc_ir::diag::{Diagnostic, FileId};

/// How a chart evolves: the standard's model or a tool's (docs/sfc.md).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Profile {
    /// IEC 61131-3: transitions on the states the previous scan left, one branch of a
    /// selective divergence (in evaluation order), then the actions of the active
    /// steps under the standard's ACTION_CONTROL (associations combined, a final
    /// execution when an action stops).
    #[default]
    Iec,
    /// matiec (OpenPLC, Beremiz): its algorithm step by step (the reference's §6.2):
    /// unprioritised branches all fire, the last association wins, no final
    /// execution.
    Matiec,
    /// CODESYS: the actions of the active steps first, then the transitions, whose
    /// effect the actions see in the next cycle; the standard's action control.
    Codesys,
}

impl Profile {
    /// The profile named `name` (`iec`, `matiec`, `codesys`).
    pub fn from_name(name: &str) -> Option<Profile> {
        match name.to_ascii_lowercase().as_str() {
            "iec" => Some(Profile::Iec),
            "matiec" => Some(Profile::Matiec),
            "codesys" => Some(Profile::Codesys),
            _ => None,
        }
    }

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Iec => "iec",
            Profile::Matiec => "matiec",
            Profile::Codesys => "codesys",
        }
    }
}

/// The ST written for the charts of one file, and its map back to the file.
#[derive(Debug, Clone)]
pub struct View {
    /// The file the charts are in.
    pub file: FileId,
    /// The generated ST.
    pub st: FileId,
    /// From the generated text to the file.
    pub map: SpanMap,
    /// The charts drawn as text (`--emit sfc-text`).
    pub drawing: String,
}

/// The name of the ST view of the charts of file `name`.
pub fn view_name(name: &str) -> String {
    format!("{name} (SFC as ST)")
}

/// Writes every chart of `units` as ST, parses it and puts the POUs it gives in place
/// of the charts. Returns the views (for [`remap_all`]). A chart with errors is
/// reported and left out (its POU keeps an empty body). The text of a file in
/// `il_files` (IL, and the ST views of PLCopen files), or with a transition written
/// in IL, is read by the IL front end, which tells IL bodies from ST ones.
pub fn expand(
    units: &mut [SourceUnit],
    sources: &mut SourceMap,
    interner: &mut Interner,
    profile: Profile,
    il_files: &[FileId],
    diags: &mut Vec<Diagnostic>,
) -> Vec<View> {
    let mut views = Vec::new();
    for unit in units.iter_mut() {
        let charts: Vec<usize> = unit
            .items
            .iter()
            .enumerate()
            .filter(|(_, i)| matches!(i, Item::Pou(p) if pou_has_chart(p)))
            .map(|(k, _)| k)
            .collect();
        if charts.is_empty() {
            continue;
        }
        let file = unit.file;
        let text = sources.get(file).text.clone();
        let mut out = crate::plcopen::map::Out::default();
        let mut made = Vec::new();
        let mut il = il_files.contains(&file);
        let mut drawing = String::new();
        for &k in &charts {
            let Item::Pou(pou) = &mut unit.items[k] else {
                continue;
            };
            // The body's chart first, then the actions'.
            let mut sfcs: Vec<(Option<usize>, Sfc)> = Vec::new();
            if let Some(c) = pou.sfc.take() {
                sfcs.push((None, c));
            }
            for (i, a) in pou.actions.iter_mut().enumerate() {
                if let Some(c) = a.sfc.take() {
                    sfcs.push((Some(i), c));
                }
            }
            for (action, chart) in &sfcs {
                if !drawing.is_empty() {
                    drawing.push('\n');
                }
                drawing.push_str(&draw::draw(pou, *action, chart, &text));
            }
            let refs: Vec<(Option<usize>, &Sfc)> = sfcs.iter().map(|(a, c)| (*a, c)).collect();
            let before = diags.iter().filter(|d| d.is_error()).count();
            let facts = check::check_pou(pou, &refs, &text, interner, profile, diags);
            if diags.iter().filter(|d| d.is_error()).count() > before {
                continue;
            }
            let facts = facts.expect("checked without errors");
            il |= sfcs.iter().any(|(_, c)| c.transitions.iter().any(|t| t.il));
            let charts: Vec<emit::Chart<'_>> = refs
                .iter()
                .zip(facts)
                .map(|(&(action, sfc), facts)| emit::Chart { sfc, action, facts })
                .collect();
            emit::pou(&mut out, pou, &charts, &text, profile);
            made.push(k);
        }
        if made.is_empty() {
            continue;
        }
        let name = view_name(&sources.get(file).name);
        let st = sources.add(SourceFile::new(name, out.text));
        let parsed = if il {
            crate::il::parse(st, &sources.get(st).text, interner, diags)
        } else {
            crate::st::parse(st, &sources.get(st).text, interner, diags)
        };
        // The generated file holds the charts' POUs in the order of `made`.
        let mut pous = parsed
            .items
            .into_iter()
            .filter(|i| matches!(i, Item::Pou(_)));
        for k in made {
            if let Some(p) = pous.next() {
                unit.items[k] = p;
            }
        }
        views.push(View {
            file,
            st,
            map: out.map,
            drawing,
        });
    }
    views
}

/// Sends the spans of `diags` that point into a chart's ST view back to the chart.
pub fn remap_all(views: &[View], diags: &mut [Diagnostic]) {
    for d in diags {
        for v in views {
            v.map.remap(d, v.st, v.file);
        }
    }
}

/// True if `unit` holds a chart (before [`expand`]).
pub fn has_chart(unit: &SourceUnit) -> bool {
    unit.items
        .iter()
        .any(|i| matches!(i, Item::Pou(p) if pou_has_chart(p)))
}

/// True if the body of `pou` or one of its actions is a chart.
fn pou_has_chart(pou: &ast::Pou) -> bool {
    pou.sfc.is_some() || pou.actions.iter().any(|a| a.sfc.is_some())
}
