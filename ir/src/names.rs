//! Names for the tools a backend writes for: identifiers made of IEC and IR names,
//! and a [`Namer`] that keeps them unique.
//!
//! The PIC16 listing (`main_count` for `main.count`, MPASM symbols compared without
//! case) and the C backend (`MAIN`, `CONFIG0__G1`, as matiec names them) both name
//! things this way. The native backend's symbols are another job: a reversible
//! encoding, so that distinct IR names can never meet (`plcc_native::runtime::mangle`).

use std::collections::HashSet;

/// `name` with every character other than an ASCII letter, digit or `_` turned
/// into `_` (`main.timer.Q` → `main_timer_Q`).
pub fn identifier(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The names given so far, and the next free one for a wanted name.
#[derive(Clone, Debug, Default)]
pub struct Namer {
    taken: HashSet<String>,
    fold_case: bool,
}

impl Namer {
    /// No name taken; with `fold_case`, names that differ only in case are the same
    /// (as MPASM's symbols are).
    pub fn new(fold_case: bool) -> Namer {
        Namer {
            taken: HashSet::new(),
            fold_case,
        }
    }

    /// Marks `names` as taken (a language's keywords, a runtime's symbols).
    pub fn reserve<'a>(&mut self, names: impl IntoIterator<Item = &'a str>) {
        for n in names {
            let k = self.key(n);
            self.taken.insert(k);
        }
    }

    /// `want` if it is free, else the first free of `want_2`, `want_3`, …; the name
    /// returned is taken from then on.
    pub fn unique(&mut self, want: &str) -> String {
        if self.taken.insert(self.key(want)) {
            return want.to_string();
        }
        (2..)
            .map(|k| format!("{want}_{k}"))
            .find(|n| self.taken.insert(self.key(n)))
            .expect("a free name")
    }

    fn key(&self, name: &str) -> String {
        if self.fold_case {
            name.to_ascii_lowercase()
        } else {
            name.to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_and_unique_names() {
        assert_eq!(identifier("main.timer.Q"), "main_timer_Q");
        assert_eq!(identifier("u$scan"), "u_scan");
        let mut n = Namer::new(true);
        n.reserve(["movlw"]);
        assert_eq!(n.unique("MOVLW"), "MOVLW_2");
        assert_eq!(n.unique("a"), "a");
        assert_eq!(n.unique("A"), "A_2");
        assert_eq!(n.unique("a"), "a_3");
        let mut c = Namer::new(false);
        assert_eq!(c.unique("A"), "A");
        assert_eq!(c.unique("a"), "a");
        assert_eq!(c.unique("A"), "A_2");
    }
}
