//! What can run compiled code: the interface every runnable target implements.
//!
//! `plcc run`, `plcc test` and the differential tests talk only to this trait, so a new
//! target is tested by the same suite the day it can run.

use crate::value::PlcValue;
use std::fmt;

/// A failure while running a program (not a PLC fault: those set the fault flag).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MachineError(pub String);

impl fmt::Display for MachineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MachineError {}

impl From<crate::vars::PathError> for MachineError {
    fn from(e: crate::vars::PathError) -> Self {
        MachineError(e.0)
    }
}

/// A PLC that runs one compiled module scan by scan.
///
/// Variables are named by source path (`main.timer.Q`; case-insensitive). The clock is
/// simulated: the runner sets it before each scan and every read of the clock within
/// that scan sees the same value.
pub trait Machine {
    /// The target's name (`host`, `interp`, …).
    fn target(&self) -> &str;

    /// Cold start: every variable gets its declared initial value, the fault flag is
    /// cleared, and the clock is 0.
    fn cold_start(&mut self) -> Result<(), MachineError>;

    /// Sets the PLC clock (microseconds since cold start) the next scan samples.
    fn set_clock_us(&mut self, us: i64);

    /// Runs one scan: every program body once, in order.
    fn scan(&mut self) -> Result<(), MachineError>;

    /// The module whose variables the machine holds (its types and data objects at
    /// least; the functions may be left out): variable paths resolve against it.
    fn vars_module(&self) -> &crate::Module;

    /// The STRING or WSTRING variable at `path` (read and written with
    /// [`read_string`] and [`write_string`]).
    fn string_var(&self, path: &str) -> Result<crate::vars::StrRef, MachineError> {
        Ok(crate::vars::resolve_string(self.vars_module(), path)?)
    }

    /// Reads a variable.
    fn read(&self, path: &str) -> Result<PlcValue, MachineError>;

    /// Writes a variable (the value's type must be the variable's).
    fn write(&mut self, path: &str, value: PlcValue) -> Result<(), MachineError>;

    /// True once a runtime fault (division by zero, index out of range) has happened
    /// since the flag was last cleared.
    fn fault(&self) -> bool;

    /// Clears the fault flag.
    fn clear_fault(&mut self);

    /// Arms a watchdog: a scan that runs longer than `limit` is stopped and `scan`
    /// returns an error (the module must contain `stop_requested` checks, see
    /// `passes::watchdog`). `None` disarms it. Machines without one ignore this.
    fn set_watchdog(&mut self, limit: Option<std::time::Duration>) {
        let _ = limit;
    }
}

/// The text of a STRING or WSTRING variable on `m`: its characters up to the first
/// NUL (at most the capacity), read one by one as `path[i]`.
pub fn read_string(
    m: &(impl Machine + ?Sized),
    s: &crate::vars::StrRef,
) -> Result<Vec<u16>, MachineError> {
    let mut chars = Vec::new();
    for i in 0..s.cap {
        let c = m.read(&format!("{}[{i}]", s.path))?;
        if c.bits == 0 {
            break;
        }
        chars.push(c.bits as u16);
    }
    Ok(chars)
}

/// Writes `chars` into a STRING or WSTRING variable on `m`, followed by the NUL;
/// more characters than its capacity is an error (nothing is written then).
pub fn write_string(
    m: &mut (impl Machine + ?Sized),
    s: &crate::vars::StrRef,
    chars: &[u16],
) -> Result<(), MachineError> {
    if chars.len() > s.cap as usize {
        return Err(MachineError(format!(
            "`{}` holds at most {} characters; the value has {}",
            s.path,
            s.cap,
            chars.len()
        )));
    }
    let elem = if s.wide {
        crate::types::ElemType::WChar
    } else {
        crate::types::ElemType::Char
    };
    for (i, &c) in chars.iter().chain(&[0]).enumerate() {
        m.write(
            &format!("{}[{i}]", s.path),
            PlcValue::from_bits(elem, c as u64),
        )?;
    }
    Ok(())
}
