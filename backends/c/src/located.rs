//! Located variables (`AT %IX0.0`) as the runtime's: each distinct address is one
//! `__LOCATED_VAR(T,__IX0_0,I,X,0,0)` line of `LOCATED_VARIABLES.h`; the runtime
//! defines its storage (`____IX0_0`) and a pointer to it (`__IX0_0`), and the program
//! reaches it through an `__IEC_<T>_p` field bound to that pointer.
//!
//! Addresses are checked here: the direction is `I`, `Q` or `M`; the size letter is
//! `X`, `B`, `W`, `D` or `L` and must hold the variable's type (the runtime reaches
//! the storage through `IEC_BOOL *`, `IEC_BYTE *`, `IEC_UINT *`, `IEC_UDINT *` or
//! `IEC_ULINT *`); an address without a size letter (`%I0.1`, matiec's `S`) is
//! normalised to `X` for a BOOL and refused otherwise; `T` is the elementary type
//! of the variable's representation (never a derived type's name, which the
//! runtime's glue would not know). Partly specified addresses (`%I*`) have no storage
//! of their own until a `VAR_CONFIG` gives one, which plcc does not read: such a
//! variable is an ordinary one.

use crate::codes;
use plcc_ir::diag::Diagnostic;
use plcc_ir::Type;

/// A fully specified address.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Address {
    /// `I`, `Q` or `M`.
    pub dir: char,
    /// `X`, `B`, `W`, `D` or `L` (normalised: never `S`).
    pub size: char,
    /// The parts of the address, decimal as written (`0`, `0` for `%IX0.0`).
    pub parts: Vec<String>,
}

impl Address {
    /// The runtime's name of the pointer: `__` and the address without `%`, with
    /// `_` for `.` (`__IX0_0`).
    pub fn name(&self) -> String {
        format!("__{}{}{}", self.dir, self.size, self.parts.join("_"))
    }
}

/// What an `AT` clause gives.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// A fully specified address.
    Full(Address),
    /// `%I*`, `%Q*`, `%M*`: not bound to storage.
    Partial,
}

/// One line of `LOCATED_VARIABLES.h`: a distinct address and its elementary type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Located {
    /// The address.
    pub addr: Address,
    /// The elementary type's name (`BOOL`, `INT`, ...).
    pub ty: &'static str,
}

impl Located {
    /// The pointer's name (`__IX0_0`).
    pub fn name(&self) -> String {
        self.addr.name()
    }

    /// The line, without its line feed:
    /// `__LOCATED_VAR(BOOL,__IX0_0,I,X,0,0)`.
    pub fn line(&self) -> String {
        format!(
            "__LOCATED_VAR({},{},{},{},{})",
            self.ty,
            self.name(),
            self.addr.dir,
            self.addr.size,
            self.addr.parts.join(",")
        )
    }
}

/// Reads an address as written (`%IX0.0`, `%qw1`, `%I0.1`, `%Q*`).
pub fn parse(text: &str) -> Result<Location, String> {
    let bad = || {
        Err(format!(
            "`{text}` is not a direct address the runtime can bind (`%` then I, Q or M, a size X, B, W, D or L, and numbers separated by `.`)"
        ))
    };
    let Some(rest) = text.trim().strip_prefix('%') else {
        return bad();
    };
    let mut chars = rest.chars();
    let dir = match chars.next().map(|c| c.to_ascii_uppercase()) {
        Some(c @ ('I' | 'Q' | 'M')) => c,
        _ => return bad(),
    };
    let rest = chars.as_str();
    if rest == "*" {
        return Ok(Location::Partial);
    }
    let (size, digits) = match rest.chars().next().map(|c| c.to_ascii_uppercase()) {
        Some(c @ ('X' | 'B' | 'W' | 'D' | 'L')) => (c, &rest[1..]),
        Some(c) if c.is_ascii_digit() => ('S', rest),
        _ => return bad(),
    };
    if digits == "*" {
        return Ok(Location::Partial);
    }
    let parts: Vec<String> = digits.split('.').map(str::to_string).collect();
    if parts
        .iter()
        .any(|p| p.is_empty() || !p.bytes().all(|b| b.is_ascii_digit()))
    {
        return bad();
    }
    Ok(Location::Full(Address { dir, size, parts }))
}

/// Checks that `addr` holds a value of IR type `ty` and normalises a missing size
/// (`S`) to `X` for a BOOL. `what` names the variable in the message.
pub fn check(mut addr: Address, ty: Type, what: &str) -> Result<Address, Vec<Diagnostic>> {
    let width = match ty {
        Type::I1 => 'X',
        Type::I8 => 'B',
        Type::I16 => 'W',
        Type::I32 | Type::F32 => 'D',
        Type::I64 | Type::F64 => 'L',
        Type::Ptr => '?',
    };
    if addr.size == 'S' && width == 'X' {
        addr.size = 'X';
    }
    if addr.size != width {
        let holds = match width {
            'X' => "a BOOL needs a bit address such as `%IX0.0`".to_string(),
            '?' => "a pointer has no address".to_string(),
            w => format!("its type needs the size letter `{w}`"),
        };
        let size = if addr.size == 'S' {
            "no size letter".to_string()
        } else {
            format!("size `{}`", addr.size)
        };
        return Err(vec![Diagnostic::error_nowhere(
            codes::E_LOCATION,
            format!("{what} is located at an address of {size}, which does not hold it: {holds}"),
        )]);
    }
    Ok(addr)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn full(t: &str) -> Address {
        match parse(t).unwrap() {
            Location::Full(a) => a,
            Location::Partial => panic!("{t} is partial"),
        }
    }

    #[test]
    fn addresses_and_their_names() {
        assert_eq!(full("%IX0.0").name(), "__IX0_0");
        assert_eq!(full("%qx2.3").name(), "__QX2_3");
        assert_eq!(full("%MW2").name(), "__MW2");
        assert_eq!(full("%IX100.2.1").name(), "__IX100_2_1");
        assert_eq!(parse("%Q*").unwrap(), Location::Partial);
        assert_eq!(parse("%IX*").unwrap(), Location::Partial);
        for bad in ["IX0.0", "%KX0.0", "%IY0", "%IX", "%IX0..1", "%IXa"] {
            assert!(parse(bad).is_err(), "{bad}");
        }
        let l = Located {
            addr: full("%IX0.0"),
            ty: "BOOL",
        };
        assert_eq!(l.line(), "__LOCATED_VAR(BOOL,__IX0_0,I,X,0,0)");
    }

    #[test]
    fn sizes_hold_their_types() {
        assert_eq!(check(full("%I0.1"), Type::I1, "x").unwrap().size, 'X');
        assert_eq!(
            check(full("%I0.1"), Type::I1, "x").unwrap().name(),
            "__IX0_1"
        );
        assert!(check(full("%I0"), Type::I16, "x").is_err());
        assert!(check(full("%IX0.0"), Type::I16, "x").is_err());
        assert!(check(full("%MD0"), Type::F32, "x").is_ok());
        assert!(check(full("%ML1"), Type::F64, "x").is_ok());
        assert!(check(full("%MW1"), Type::I32, "x").is_err());
        assert!(check(full("%MB1"), Type::I8, "x").is_ok());
    }
}
