//! Is the chart safe? The token game played out: from the initial steps, every
//! transition whose steps are all active may fire (conditions are not looked at),
//! taking the token from the steps before it to the steps after it. A firing that
//! puts a token on a step that already has one (that is not one it takes from) makes
//! the chart unsafe: a simultaneous divergence closed by a selective convergence, or
//! a loop that lets a branch lap another. A transition that is never enabled waits
//! for steps that are never active together.

use super::check::Facts;
use crate::ast::Sfc;
use std::collections::{HashSet, VecDeque};

/// The markings looked at, at most: a bigger state space is not explored further
/// (the check then says nothing).
const LIMIT: usize = 20_000;

/// What the token game found.
#[derive(Debug, Default)]
pub(super) struct Safety {
    /// A transition whose firing puts a second token on a step: (transition, step).
    pub unsafe_at: Option<(usize, usize)>,
    /// Transitions never enabled.
    pub dead: Vec<usize>,
}

/// Plays the token game of `chart` (steps at most 128; `None` for larger charts or
/// when the state space exceeds [`LIMIT`]).
pub(super) fn check(chart: &Sfc, facts: &Facts) -> Option<Safety> {
    let n = chart.steps.len();
    if n > 128 {
        return None;
    }
    let bits = |list: &[usize]| list.iter().fold(0u128, |m, &k| m | 1 << k);
    let from: Vec<u128> = facts.from.iter().map(|f| bits(f)).collect();
    let to: Vec<u128> = facts.to.iter().map(|t| bits(t)).collect();
    let start = chart
        .steps
        .iter()
        .enumerate()
        .filter(|(_, s)| s.initial)
        .fold(0u128, |m, (k, _)| m | 1 << k);
    let mut seen = HashSet::from([start]);
    let mut work = VecDeque::from([start]);
    let mut enabled = vec![false; from.len()];
    let mut out = Safety::default();
    while let Some(m) = work.pop_front() {
        for t in 0..from.len() {
            if from[t] == 0 || m & from[t] != from[t] {
                continue;
            }
            enabled[t] = true;
            let rest = m & !from[t];
            let clash = rest & to[t];
            if clash != 0 && out.unsafe_at.is_none() {
                out.unsafe_at = Some((t, clash.trailing_zeros() as usize));
            }
            let next = rest | to[t];
            if seen.insert(next) {
                if seen.len() > LIMIT {
                    return None;
                }
                work.push_back(next);
            }
        }
    }
    out.dead = (0..from.len()).filter(|&t| !enabled[t]).collect();
    Some(out)
}
