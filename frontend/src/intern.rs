//! Case-insensitive interning of identifiers.
//!
//! IEC 61131-3 names ignore case, so the key is the upper-cased spelling; comparing two
//! names is comparing two integers, and the parser allocates nothing for a name it has
//! seen before.

use rustc_hash::FxHashMap;

/// An interned, upper-cased identifier.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Symbol(pub u32);

/// The table of interned names of one build.
#[derive(Clone, Debug, Default)]
pub struct Interner {
    map: FxHashMap<Box<str>, Symbol>,
    names: Vec<Box<str>>,
    scratch: String,
}

impl Interner {
    /// An empty table.
    pub fn new() -> Interner {
        Interner::default()
    }

    /// The symbol of `name`, upper-casing ASCII letters first.
    pub fn intern(&mut self, name: &str) -> Symbol {
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.clear();
        scratch.push_str(name);
        scratch.make_ascii_uppercase();
        let sym = self.intern_upper(&scratch);
        self.scratch = scratch;
        sym
    }

    /// The symbol of a name that is already upper case.
    pub fn intern_upper(&mut self, upper: &str) -> Symbol {
        if let Some(&sym) = self.map.get(upper) {
            return sym;
        }
        let sym = Symbol(self.names.len() as u32);
        let boxed: Box<str> = upper.into();
        self.names.push(boxed.clone());
        self.map.insert(boxed, sym);
        sym
    }

    /// The symbol of `name` if it was interned before (never adds).
    pub fn lookup(&self, name: &str) -> Option<Symbol> {
        let upper = name.to_ascii_uppercase();
        self.map.get(upper.as_str()).copied()
    }

    /// The number of names interned.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// True if no name is interned.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Forgets the names interned after the first `len`.
    pub(crate) fn truncate(&mut self, len: usize) {
        for name in self.names.drain(len.min(self.names.len())..) {
            self.map.remove(&name);
        }
    }

    /// The names interned after the first `from`, in order.
    pub(crate) fn names_from(&self, from: usize) -> &[Box<str>] {
        &self.names[from.min(self.names.len())..]
    }

    /// The upper-cased name of a symbol.
    pub fn name(&self, sym: Symbol) -> &str {
        &self.names[sym.0 as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_ignore_case() {
        let mut i = Interner::new();
        let a = i.intern("Motor_On");
        let b = i.intern("MOTOR_ON");
        let c = i.intern("motor_off");
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(i.name(a), "MOTOR_ON");
        assert_eq!(i.lookup("motor_on"), Some(a));
        assert_eq!(i.lookup("pump"), None);
    }
}
