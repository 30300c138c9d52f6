//! `POUS.h`: the program's types (one struct per PROGRAM, FUNCTION_BLOCK and STRUCT
//! type, upper-cased fields; one per array type with its elements in `table`, as
//! matiec's `_ARRAY_TYPE`), the `extern` declarations of its variables, the
//! prototypes of its functions, and the inline helpers the generated code calls
//! (`static inline`, prefixed `__plcc_`: `POUS.h` is included by several translation
//! units, so it defines no object and no other function).

use crate::names::{field_type, value_type, FuncForm, Names};
use plcc_ir::module::AggDef;
use plcc_ir::types::MemType;
use plcc_ir::{AggId, FuncId, Module, Type};
use std::fmt::Write;

/// The helpers: typed memory access through `memcpy` (so no access depends on
/// aliasing rules), float constants from their bits, the hints that fault paths are
/// unlikely, rounding to nearest even, the
/// runtime context (clock, fault flag, stop request) and the reading of the stop
/// request.
pub const HELPERS: &str = r#"#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <math.h>

/* Memory is read and written through memcpy: no access depends on the types of the
   objects involved, and compilers turn each into one load or store. */
#define __PLCC_ACCESS(name, type)                                              \
    static inline type __plcc_ld_##name(const unsigned char *p) {             \
        type v;                                                                \
        memcpy(&v, p, sizeof v);                                               \
        return v;                                                              \
    }                                                                          \
    static inline void __plcc_st_##name(unsigned char *p, type v) {           \
        memcpy(p, &v, sizeof v);                                               \
    }
__PLCC_ACCESS(u8, uint8_t)
__PLCC_ACCESS(u16, uint16_t)
__PLCC_ACCESS(u32, uint32_t)
__PLCC_ACCESS(u64, uint64_t)
__PLCC_ACCESS(f32, float)
__PLCC_ACCESS(f64, double)
__PLCC_ACCESS(ptr, unsigned char *)

static inline float __plcc_f32(uint32_t bits) {
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}
static inline double __plcc_f64(uint64_t bits) {
    double f;
    memcpy(&f, &bits, sizeof f);
    return f;
}
static inline uint32_t __plcc_bits_f32(float f) {
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    return bits;
}
static inline uint64_t __plcc_bits_f64(double f) {
    uint64_t bits;
    memcpy(&bits, &f, sizeof bits);
    return bits;
}

/* The fault paths (an index out of range, a division by zero) are unlikely. */
#if defined(__GNUC__)
#define __PLCC_LIKELY(c) __builtin_expect((c) != 0, 1)
#define __PLCC_UNLIKELY(c) __builtin_expect((c) != 0, 0)
#else
#define __PLCC_LIKELY(c) ((c) != 0)
#define __PLCC_UNLIKELY(c) ((c) != 0)
#endif

/* Rounding to the nearest integer, ties to even, in any rounding mode and without
   nearbyint (which avr-libc lacks): round (ties away from zero), and a tie goes to
   twice the rounded half, which is even. Every step is exact. */
static inline float __plcc_nearestf(float x) {
    float r = roundf(x);
    if (fabsf(r - x) == 0.5f) {
        r = 2.0f * roundf(0.5f * x);
    }
    return r;
}
static inline double __plcc_nearest(double x) {
    double r = round(x);
    if (fabs(r - x) == 0.5) {
        r = 2.0 * round(0.5 * x);
    }
    return r;
}

/* The runtime context: the clock sampled at the start of the scan, the fault flag
   (division by zero, index out of range) and the stop request of a watchdog. */
typedef struct {
    int32_t clock_ms;
    int64_t clock_ns;
    uint8_t fault;
    volatile uint8_t stop;
} __plcc_rt_t;
extern __plcc_rt_t __plcc_rt;

static inline uint8_t __plcc_stop_requested(void) {
#if defined(__GNUC__)
    return (uint8_t)(__atomic_load_n(&__plcc_rt.stop, __ATOMIC_RELAXED) != 0);
#else
    return (uint8_t)(__plcc_rt.stop != 0);
#endif
}
"#;

/// The C declaration of a function (without the `;`).
pub fn signature(module: &Module, names: &Names, f: FuncId) -> String {
    let func = module.func(f);
    let name = &names.funcs[f.index()];
    match names.forms[f.index()] {
        FuncForm::Body(a) => format!("void {name}({} *data__)", names.aggs[a.index()]),
        FuncForm::Init(a) => format!(
            "void {name}({} *data__, BOOL retain)",
            names.aggs[a.index()]
        ),
        FuncForm::Plain => {
            let ret = func.ret.map_or("void", value_type);
            let params: Vec<String> = func
                .params
                .iter()
                .enumerate()
                .map(|(k, t)| format!("{} p{k}", value_type(*t)))
                .collect();
            let params = if params.is_empty() {
                "void".to_string()
            } else {
                params.join(", ")
            };
            format!("{ret} {name}({params})")
        }
    }
}

/// The C type of a memory type, for declarations.
pub fn mem_type(names: &Names, t: MemType) -> String {
    match t {
        MemType::Scalar(s) => value_type(s).to_string(),
        MemType::Agg(a) => names.aggs[a.index()].clone(),
    }
}

/// A declaration of `name` with C type `ty` (`unsigned char *` binds to the name).
fn declare(ty: &str, name: &str) -> String {
    if ty.ends_with('*') {
        format!("{ty}{name}")
    } else {
        format!("{ty} {name}")
    }
}

/// The aggregates in an order where each comes after those it holds by value.
fn agg_order(module: &Module) -> Vec<AggId> {
    fn visit(module: &Module, a: AggId, done: &mut [bool], out: &mut Vec<AggId>) {
        if done[a.index()] {
            return;
        }
        done[a.index()] = true;
        let members: Vec<MemType> = match module.agg(a) {
            AggDef::Struct(s) => s.fields.iter().map(|f| f.ty).collect(),
            AggDef::Array(x) => vec![x.elem],
        };
        for m in members {
            if let MemType::Agg(b) = m {
                visit(module, b, done, out);
            }
        }
        out.push(a);
    }
    let mut done = vec![false; module.aggs.len()];
    let mut out = Vec::new();
    for i in 0..module.aggs.len() {
        visit(module, AggId::new(i), &mut done, &mut out);
    }
    out
}

/// The type declarations of every aggregate.
pub fn types(module: &Module, names: &Names) -> String {
    let mut s = String::new();
    for a in agg_order(module) {
        let name = &names.aggs[a.index()];
        match module.agg(a) {
            AggDef::Struct(st) => {
                let _ = writeln!(s, "/* {} {} */", st.kind.name(), st.name);
                // Tagged, so that a field may be declared `struct T T;` (C++ forbids
                // a member that changes the meaning of a type name used before it).
                let _ = writeln!(s, "typedef struct {name} {{");
                for (k, f) in st.fields.iter().enumerate() {
                    let ty = match f.ty {
                        MemType::Scalar(t) => field_type(t, f.elem).to_string(),
                        MemType::Agg(b) => format!("struct {}", names.aggs[b.index()]),
                    };
                    let _ = writeln!(s, "    {};", declare(&ty, &names.fields[a.index()][k]));
                }
                if st.fields.is_empty() {
                    // C has no empty structs (C++ gives them a byte): one byte in both.
                    s.push_str("    uint8_t __plcc_empty;\n");
                }
                let _ = writeln!(s, "}} {name};\n");
            }
            AggDef::Array(ar) => {
                let ty = match ar.elem {
                    MemType::Scalar(t) => field_type(t, ar.elem_type).to_string(),
                    MemType::Agg(b) => format!("struct {}", names.aggs[b.index()]),
                };
                // C has no arrays of no element; such an array is never indexed.
                let len = ar.len.max(1);
                let _ = writeln!(
                    s,
                    "/* array {} [{} .. {}] */\ntypedef struct {name} {{\n    {}[{len}];\n}} {name};\n",
                    ar.name,
                    ar.lower,
                    ar.lower + ar.len as i64 - 1,
                    declare(&ty, "table")
                );
            }
        }
    }
    s
}

/// True if the module has an LREAL anywhere: a value, a variable, a field, an
/// array's elements.
fn uses_f64(module: &Module) -> bool {
    let f64 = |t: &MemType| *t == MemType::Scalar(Type::F64);
    module
        .funcs
        .iter()
        .any(|f| f.values.iter().any(|v| v.ty == Type::F64))
        || module.data.iter().any(|d| f64(&d.ty))
        || module.aggs.iter().any(|a| match a {
            AggDef::Struct(s) => s.fields.iter().any(|x| f64(&x.ty)),
            AggDef::Array(x) => f64(&x.elem),
        })
}

/// `POUS.h`.
pub fn pous_h(module: &Module, names: &Names) -> String {
    let mut s = String::new();
    s.push_str("/* POUS.h: the program's types, variables and functions (written by plcc). */\n");
    s.push_str("#ifndef __POUS_H\n#define __POUS_H\n\n");
    s.push_str("#include \"accessor.h\"\n#include \"iec_std_lib.h\"\n\n");
    s.push_str(HELPERS);
    if uses_f64(module) {
        // LREAL must be a 64-bit double (avr-gcc's has 32 bits: the program would
        // compute in the wrong precision, and its LREAL constants would lose bits).
        s.push_str(
            "\n/* LREAL is a 64-bit IEEE double: a compiler whose double is narrower stops here. */\n\
             typedef char __plcc_lreal_needs_a_64_bit_double[sizeof(double) == 8 ? 1 : -1];\n",
        );
    }
    s.push('\n');
    s.push_str(&types(module, names));
    for (k, d) in module.data.iter().enumerate() {
        let _ = writeln!(
            s,
            "extern {};",
            declare(&mem_type(names, d.ty), &names.data[k])
        );
    }
    s.push('\n');
    for k in 0..module.funcs.len() {
        let _ = writeln!(s, "{};", signature(module, names, FuncId::new(k)));
    }
    s.push_str("\n#endif\n");
    s
}
