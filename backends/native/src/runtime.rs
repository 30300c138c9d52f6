//! What compiled code needs from its surroundings: the runtime context (clock and fault
//! flag) and the C library's math functions.

use cranelift_codegen::ir::types;

/// The runtime context compiled code reads the clock from and raises the fault flag in.
///
/// The JIT owns one; an object file defines one as the symbol [`RT_SYMBOL`], and the C
/// header declares it with the same layout.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Runtime {
    /// The PLC clock in milliseconds (TIME), what `clock_ms` returns.
    pub clock_ms: i32,
    _pad0: i32,
    /// The same instant in nanoseconds (LTIME), what `clock_ns` returns.
    pub clock_ns: i64,
    /// Nonzero once a runtime fault (division by zero, `raise_fault`) happened.
    pub fault: u8,
    /// Nonzero asks the running scan to stop: what `stop_requested` reads. The JIT's
    /// watchdog thread sets it; a host runtime may too.
    pub stop: u8,
    _pad1: [u8; 6],
}

/// Byte offset of [`Runtime::clock_ms`].
pub const RT_CLOCK_MS: i32 = 0;
/// Byte offset of [`Runtime::clock_ns`].
pub const RT_CLOCK_NS: i32 = 8;
/// Byte offset of [`Runtime::fault`].
pub const RT_FAULT: i32 = 16;
/// Byte offset of [`Runtime::stop`].
pub const RT_STOP: i32 = 17;
/// Size of [`Runtime`] in bytes.
pub const RT_SIZE: usize = 24;
/// The runtime context's symbol in object files.
pub const RT_SYMBOL: &str = "plcc_rt";
/// The symbol of the one block that holds every data object in object files.
pub const DATA_SYMBOL: &str = "plcc_data";

const _: () = assert!(std::mem::size_of::<Runtime>() == RT_SIZE);
const _: () = assert!(std::mem::offset_of!(Runtime, clock_ns) == RT_CLOCK_NS as usize);
const _: () = assert!(std::mem::offset_of!(Runtime, fault) == RT_FAULT as usize);
const _: () = assert!(std::mem::offset_of!(Runtime, stop) == RT_STOP as usize);

/// A math function of the C library the IR's float operations call.
#[derive(Copy, Clone, Debug)]
pub(crate) struct MathFn {
    /// The C name (`sinf`, `atan2`), used as the import symbol in objects and the JIT.
    pub name: &'static str,
    /// `F32` or `F64`.
    pub ty: types::Type,
    /// One or two operands.
    pub arity: u8,
    /// The Rust implementation the JIT links to.
    pub addr: fn() -> *const u8,
}

// The Rust float methods call the same C library functions as the interpreter does
// (it uses these very methods), so results agree bit for bit. They never panic, which
// matters: unwinding through JIT frames would abort.
macro_rules! unary {
    ($name:ident, $t:ty, $m:ident) => {
        extern "C" fn $name(x: $t) -> $t {
            x.$m()
        }
    };
}
unary!(h_sinf, f32, sin);
unary!(h_sin, f64, sin);
unary!(h_cosf, f32, cos);
unary!(h_cos, f64, cos);
unary!(h_tanf, f32, tan);
unary!(h_tan, f64, tan);
unary!(h_asinf, f32, asin);
unary!(h_asin, f64, asin);
unary!(h_acosf, f32, acos);
unary!(h_acos, f64, acos);
unary!(h_atanf, f32, atan);
unary!(h_atan, f64, atan);
unary!(h_logf, f32, ln);
unary!(h_log, f64, ln);
unary!(h_log10f, f32, log10);
unary!(h_log10, f64, log10);
unary!(h_expf, f32, exp);
unary!(h_exp, f64, exp);
extern "C" fn h_powf(x: f32, y: f32) -> f32 {
    x.powf(y)
}
extern "C" fn h_pow(x: f64, y: f64) -> f64 {
    x.powf(y)
}
extern "C" fn h_atan2f(y: f32, x: f32) -> f32 {
    y.atan2(x)
}
extern "C" fn h_atan2(y: f64, x: f64) -> f64 {
    y.atan2(x)
}

macro_rules! math {
    ($name:literal, $t:ident, $n:literal, $f:ident, $ft:ty) => {
        MathFn {
            name: $name,
            ty: types::$t,
            arity: $n,
            addr: || $f as $ft as *const u8,
        }
    };
}

type F1 = extern "C" fn(f32) -> f32;
type D1 = extern "C" fn(f64) -> f64;
type F2 = extern "C" fn(f32, f32) -> f32;
type D2 = extern "C" fn(f64, f64) -> f64;

/// Every math function, f32 version at even indexes and f64 at odd ones.
pub(crate) const MATH: [MathFn; 22] = [
    math!("sinf", F32, 1, h_sinf, F1),
    math!("sin", F64, 1, h_sin, D1),
    math!("cosf", F32, 1, h_cosf, F1),
    math!("cos", F64, 1, h_cos, D1),
    math!("tanf", F32, 1, h_tanf, F1),
    math!("tan", F64, 1, h_tan, D1),
    math!("asinf", F32, 1, h_asinf, F1),
    math!("asin", F64, 1, h_asin, D1),
    math!("acosf", F32, 1, h_acosf, F1),
    math!("acos", F64, 1, h_acos, D1),
    math!("atanf", F32, 1, h_atanf, F1),
    math!("atan", F64, 1, h_atan, D1),
    math!("logf", F32, 1, h_logf, F1),
    math!("log", F64, 1, h_log, D1),
    math!("log10f", F32, 1, h_log10f, F1),
    math!("log10", F64, 1, h_log10, D1),
    math!("expf", F32, 1, h_expf, F1),
    math!("exp", F64, 1, h_exp, D1),
    math!("powf", F32, 2, h_powf, F2),
    math!("pow", F64, 2, h_pow, D2),
    math!("atan2f", F32, 2, h_atan2f, F2),
    math!("atan2", F64, 2, h_atan2, D2),
];

/// Index into [`MATH`] of the f32 version of a unary IR operation (add 1 for f64).
pub(crate) fn math_unary_index(op: plcc_ir::UnaryOp) -> Option<usize> {
    use plcc_ir::UnaryOp::*;
    Some(match op {
        Sin => 0,
        Cos => 2,
        Tan => 4,
        Asin => 6,
        Acos => 8,
        Atan => 10,
        Ln => 12,
        Log10 => 14,
        Exp => 16,
        _ => return None,
    })
}

/// Index into [`MATH`] of the f32 version of a binary IR operation (add 1 for f64).
pub(crate) fn math_binary_index(op: plcc_ir::BinaryOp) -> Option<usize> {
    match op {
        plcc_ir::BinaryOp::Fpow => Some(18),
        plcc_ir::BinaryOp::Fatan2 => Some(20),
        _ => None,
    }
}

/// Turns any name into a C identifier with a prefix, reversibly: ASCII letters and
/// digits stay, `_` becomes `__`, every other byte `_xx` (hex). So distinct IR names
/// always give distinct symbols (`main$init` is `main_24init`).
pub fn mangle(prefix: &str, name: &str) -> String {
    use std::fmt::Write;
    let mut s = String::with_capacity(prefix.len() + name.len() + 4);
    s.push_str(prefix);
    for b in name.bytes() {
        match b {
            b'a'..=b'z' | b'A'..=b'Z' | b'0'..=b'9' => s.push(b as char),
            b'_' => s.push_str("__"),
            _ => {
                let _ = write!(s, "_{b:02x}");
            }
        }
    }
    s
}

/// The symbol of an IR function in the JIT and in objects.
pub fn func_symbol(name: &str) -> String {
    mangle("plcc_f_", name)
}

/// The symbol of a data object in objects.
pub fn data_symbol(name: &str) -> String {
    mangle("plcc_d_", name)
}
