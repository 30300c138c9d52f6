//! Typed indices of the things an IR module and its functions contain.

use std::fmt;

macro_rules! entity {
    ($(#[$m:meta])* $name:ident, $prefix:literal) => {
        $(#[$m])*
        #[derive(Copy, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);

        impl $name {
            /// The index as a `usize`, for indexing vectors.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The entity with the given index.
            #[inline]
            pub fn new(index: usize) -> Self {
                $name(index as u32)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($prefix, "{}"), self.0)
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Display::fmt(self, f)
            }
        }
    };
}

entity!(
    /// An SSA value of a function (`v3`).
    Value,
    "v"
);
entity!(
    /// An instruction of a function.
    Inst,
    "inst"
);
entity!(
    /// A basic block of a function (`block2`).
    Block,
    "block"
);
entity!(
    /// A stack slot of a function: memory that lives for one call (`ss0`).
    SlotId,
    "ss"
);
entity!(
    /// An aggregate (struct or array) type of a module.
    AggId,
    "agg"
);
entity!(
    /// A data object of a module: a program instance, a global, a constant table.
    DataId,
    "data"
);
entity!(
    /// A function of a module.
    FuncId,
    "func"
);
entity!(
    /// A function table of a module: the callees of a call bound at run time (`t0`).
    TableId,
    "t"
);
