//! `POUS.h`: the program's types (one struct per PROGRAM, FUNCTION_BLOCK and STRUCT
//! type, upper-cased fields; one per array type with its elements in `table`, as
//! matiec's `_ARRAY_TYPE`), the `extern` declarations of its variables, the
//! prototypes of its functions, and the inline helpers the generated code calls
//! (`static inline`, prefixed `__plcc_`: `POUS.h` is included by several translation
//! units, so it defines no object and no other function).

use crate::names::{field_type, value_type, FuncForm, Names};
use crate::repr::Repr;
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

/* A value of plcc's C type as the IEC type of a variable (the same bits; the sizes
   are checked here, whichever runtime's headers define the IEC types). */
#define __PLCC_TO_IEC(T, U)                                                    \
    typedef char __plcc_size_of_##T[sizeof(IEC_##T) == sizeof(U) ? 1 : -1];   \
    static inline IEC_##T __plcc_to_##T(U v) {                                 \
        IEC_##T r;                                                             \
        memcpy(&r, &v, sizeof r);                                              \
        return r;                                                              \
    }
__PLCC_TO_IEC(BOOL, uint8_t)
__PLCC_TO_IEC(SINT, uint8_t)
__PLCC_TO_IEC(INT, uint16_t)
__PLCC_TO_IEC(DINT, uint32_t)
__PLCC_TO_IEC(LINT, uint64_t)
__PLCC_TO_IEC(USINT, uint8_t)
__PLCC_TO_IEC(UINT, uint16_t)
__PLCC_TO_IEC(UDINT, uint32_t)
__PLCC_TO_IEC(ULINT, uint64_t)
__PLCC_TO_IEC(BYTE, uint8_t)
__PLCC_TO_IEC(WORD, uint16_t)
__PLCC_TO_IEC(DWORD, uint32_t)
__PLCC_TO_IEC(LWORD, uint64_t)
__PLCC_TO_IEC(REAL, float)
__PLCC_TO_IEC(LREAL, double)

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

/// The declaration of a variable or field `name` held as `repr` (`__IEC_INT_t CNT`,
/// `__IEC_BOOL_p START`, `struct TON T1`).
pub fn member_decl(
    names: &Names,
    repr: Repr,
    ty: MemType,
    elem: Option<plcc_ir::ElemType>,
    name: &str,
) -> String {
    let ty = match (repr, ty) {
        (Repr::Var(t), _) => format!("__IEC_{t}_t"),
        (Repr::Located(i), _) => format!("__IEC_{}_p", names.repr.located[i].ty),
        (Repr::AggVar, MemType::Agg(b)) => format!("struct __IEC_{}_t", names.aggs[b.index()]),
        (_, MemType::Scalar(t)) => field_type(t, elem).to_string(),
        (_, MemType::Agg(b)) => format!("struct {}", names.aggs[b.index()]),
    };
    declare(&ty, name)
}

/// A declaration of `name` with C type `ty` (`unsigned char *` binds to the name).
pub fn declare(ty: &str, name: &str) -> String {
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
                    let repr = names.repr.fields[a.index()][k];
                    let field = &names.fields[a.index()][k];
                    let _ = writeln!(s, "    {};", member_decl(names, repr, f.ty, f.elem, field));
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
        if names.repr.wrapped[a.index()] {
            let _ = writeln!(
                s,
                "typedef struct __IEC_{name}_t {{\n    {name} value;\n    IEC_BYTE flags;\n}} __IEC_{name}_t;\n"
            );
        }
    }
    s
}

/// The statements that prepare the variable or field `lvalue` held as `repr`: its
/// flags cleared, a located one bound to the runtime's pointer, a member aggregate
/// prepared.
pub fn prep_member(names: &Names, repr: Repr, ty: MemType, lvalue: &str) -> String {
    let member = match ty {
        MemType::Agg(b) if names.repr.prep[b.index()] => Some(&names.aggs[b.index()]),
        _ => None,
    };
    let mut s = String::new();
    match repr {
        Repr::Plain => {
            if let Some(b) = member {
                let _ = writeln!(s, "    __plcc_prep_{b}(&{lvalue});");
            }
        }
        Repr::Var(_) => {
            let _ = writeln!(s, "    {lvalue}.flags = 0;");
        }
        Repr::AggVar => {
            let _ = writeln!(s, "    {lvalue}.flags = 0;");
            if let Some(b) = member {
                let _ = writeln!(s, "    __plcc_prep_{b}(&{lvalue}.value);");
            }
        }
        Repr::Located(i) => {
            let _ = writeln!(
                s,
                "    {lvalue}.value = {};\n    {lvalue}.flags = 0;",
                names.repr.located[i].name()
            );
        }
    }
    s
}

/// The preparation of each aggregate's storage that needs it, `static inline void
/// __plcc_prep_NAME(NAME *p)`: the flags of its variables cleared, its located
/// variables bound to the runtime's pointers, its members prepared. Storage is
/// prepared before its initial values are written (the program instances and
/// globals at `config_init__`, a function's locals when it starts).
pub fn preps(module: &Module, names: &Names) -> String {
    let mut s = String::new();
    for a in agg_order(module) {
        let k = a.index();
        if !names.repr.prep[k] {
            continue;
        }
        let name = &names.aggs[k];
        let _ = writeln!(s, "static inline void __plcc_prep_{name}({name} *p) {{");
        match module.agg(a) {
            AggDef::Struct(st) => {
                for (f, field) in st.fields.iter().enumerate() {
                    let member = format!("p->{}", names.fields[k][f]);
                    s.push_str(&prep_member(
                        names,
                        names.repr.fields[k][f],
                        field.ty,
                        &member,
                    ));
                }
            }
            AggDef::Array(ar) => {
                if let MemType::Agg(b) = ar.elem {
                    let _ = writeln!(
                        s,
                        "    size_t i;\n    for (i = 0; i < {}u; i++) {{\n        __plcc_prep_{}(&p->table[i]);\n    }}",
                        ar.len,
                        names.aggs[b.index()]
                    );
                }
            }
        }
        s.push_str("}\n\n");
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
    if !names.repr.located.is_empty() {
        s.push_str("/* The runtime's located variables (LOCATED_VARIABLES.h). */\n");
        for l in &names.repr.located {
            let _ = writeln!(s, "extern {} *{};", l.ty, l.name());
        }
        s.push('\n');
    }
    s.push_str(&preps(module, names));
    for (k, d) in module.data.iter().enumerate() {
        if !names.is_globals(plcc_ir::DataId::new(k)) {
            let _ = writeln!(
                s,
                "extern {};",
                declare(&mem_type(names, d.ty), &names.data[k])
            );
        }
    }
    if let Some(MemType::Agg(g)) = names.globals_data.map(|d| module.data[d.index()].ty) {
        if let AggDef::Struct(st) = module.agg(g) {
            for (k, f) in st.fields.iter().enumerate() {
                let repr = names.repr.fields[g.index()][k];
                let _ = writeln!(
                    s,
                    "extern {};",
                    member_decl(names, repr, f.ty, f.elem, &names.globals[k])
                );
            }
        }
    }
    s.push('\n');
    for k in 0..module.funcs.len() {
        let _ = writeln!(s, "{};", signature(module, names, FuncId::new(k)));
    }
    s.push_str("\n#endif\n");
    s
}
