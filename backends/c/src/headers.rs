//! plcc's own headers with the names matiec's generated code takes from a runtime
//! (`iec_types.h`, `iec_types_all.h`, `accessor.h`, `iec_std_lib.h`), for building
//! the C outside a runtime (tests, the C machine, small targets). Written for plcc
//! from the interface facts of `reference/matiec-c-abi.md` §3: the names, macro
//! signatures and layouts; nothing is copied from matiec or OpenPLC.
//!
//! Only what the generated code and a runtime's glue need is here: the elementary
//! types, the `__IEC_<T>_t`/`_p` wrappers (OpenPLC's `_p`, with the forced value) and
//! their flags, the accessors of variables and located variables, the prototypes of
//! the globals' accessors, and the runtime's `__CURRENT_TIME` and `__DEBUG`.

/// `iec_types.h`: the `IEC_<T>` types.
pub const IEC_TYPES_H: &str = r#"/* iec_types.h: the IEC 61131-3 elementary types (plcc's own header). */
#ifndef IEC_TYPES_H
#define IEC_TYPES_H

#include <stdint.h>

typedef uint8_t IEC_BOOL;
typedef int8_t IEC_SINT;
typedef int16_t IEC_INT;
typedef int32_t IEC_DINT;
typedef int64_t IEC_LINT;
typedef uint8_t IEC_USINT;
typedef uint16_t IEC_UINT;
typedef uint32_t IEC_UDINT;
typedef uint64_t IEC_ULINT;
typedef uint8_t IEC_BYTE;
typedef uint16_t IEC_WORD;
typedef uint32_t IEC_DWORD;
typedef uint64_t IEC_LWORD;
typedef float IEC_REAL;
typedef double IEC_LREAL;

/* A duration or an instant: seconds and nanoseconds. */
typedef struct {
    long tv_sec;
    long tv_nsec;
} IEC_TIMESPEC;

typedef IEC_TIMESPEC IEC_TIME;
typedef IEC_TIMESPEC IEC_DATE;
typedef IEC_TIMESPEC IEC_DT;
typedef IEC_TIMESPEC IEC_TOD;

#ifndef STR_MAX_LEN
#define STR_MAX_LEN 126
#endif
#ifndef STR_LEN_TYPE
#define STR_LEN_TYPE uint8_t
#endif
typedef STR_LEN_TYPE __strlen_t;
typedef struct {
    __strlen_t len;
    uint8_t body[STR_MAX_LEN];
} IEC_STRING;

#endif
"#;

/// `iec_types_all.h`: the bare type names, the variable wrappers and their flags.
pub const IEC_TYPES_ALL_H: &str = r#"/* iec_types_all.h: IEC type names and variable wrappers (plcc's own header). */
#ifndef IEC_TYPES_ALL_H
#define IEC_TYPES_ALL_H

#include "iec_types.h"

#ifndef TRUE
#define TRUE 1
#define FALSE 0
#endif

#define __IEC_DEBUG_FLAG 0x01
#define __IEC_FORCE_FLAG 0x02
#define __IEC_RETAIN_FLAG 0x04
#define __IEC_OUTPUT_FLAG 0x08

/* For each type: the bare name, a variable (value and flags) and a located or
   external variable (where the value is, flags, and the value it is forced to). */
#define __PLCC_DECLARE_IEC_TYPE(type)        \
    typedef IEC_##type type;                 \
    typedef struct {                         \
        IEC_##type value;                    \
        IEC_BYTE flags;                      \
    } __IEC_##type##_t;                      \
    typedef struct {                         \
        IEC_##type *value;                   \
        IEC_BYTE flags;                      \
        IEC_##type fvalue;                   \
    } __IEC_##type##_p;

__PLCC_DECLARE_IEC_TYPE(BOOL)
__PLCC_DECLARE_IEC_TYPE(SINT)
__PLCC_DECLARE_IEC_TYPE(INT)
__PLCC_DECLARE_IEC_TYPE(DINT)
__PLCC_DECLARE_IEC_TYPE(LINT)
__PLCC_DECLARE_IEC_TYPE(USINT)
__PLCC_DECLARE_IEC_TYPE(UINT)
__PLCC_DECLARE_IEC_TYPE(UDINT)
__PLCC_DECLARE_IEC_TYPE(ULINT)
__PLCC_DECLARE_IEC_TYPE(BYTE)
__PLCC_DECLARE_IEC_TYPE(WORD)
__PLCC_DECLARE_IEC_TYPE(DWORD)
__PLCC_DECLARE_IEC_TYPE(LWORD)
__PLCC_DECLARE_IEC_TYPE(REAL)
__PLCC_DECLARE_IEC_TYPE(LREAL)
__PLCC_DECLARE_IEC_TYPE(TIME)
__PLCC_DECLARE_IEC_TYPE(DATE)
__PLCC_DECLARE_IEC_TYPE(DT)
__PLCC_DECLARE_IEC_TYPE(TOD)
__PLCC_DECLARE_IEC_TYPE(STRING)

#endif
"#;

/// `accessor.h`: declaring, initialising, reading and writing variables.
pub const ACCESSOR_H: &str = r#"/* accessor.h: variable accessors (plcc's own header). */
#ifndef ACCESSOR_H
#define ACCESSOR_H

#define __DECLARE_VAR(type, name) __IEC_##type##_t name;
#define __INIT_VAR(name, initial, retained) \
    name.value = initial;                   \
    name.flags = (retained) ? __IEC_RETAIN_FLAG : 0;
#define __GET_VAR(name, ...) name.value __VA_ARGS__
#define __SET_VAR(prefix, name, suffix, new_value)            \
    if (!(prefix name.flags & __IEC_FORCE_FLAG)) {            \
        prefix name.value suffix = new_value;                 \
    }

/* The accessor of a global another file defines (`<Config>.h` declares them). */
#define __DECLARE_GLOBAL_PROTOTYPE(type, name) extern type *__GET_GLOBAL_##name(void);

/* A located variable: the runtime's storage, unless a debugger forced it. */
#define __GET_LOCATED(name, ...)                                          \
    ((name.flags & __IEC_FORCE_FLAG) ? name.fvalue __VA_ARGS__            \
                                     : (*(name.value))__VA_ARGS__)
#define __SET_LOCATED(prefix, name, suffix, new_value)        \
    if (!(prefix name.flags & __IEC_FORCE_FLAG)) {            \
        *(prefix name.value) suffix = new_value;              \
    }

#endif
"#;

/// `iec_std_lib.h`: what the runtime provides the generated code.
pub const IEC_STD_LIB_H: &str = r#"/* iec_std_lib.h: what the runtime gives the program (plcc's own header). */
#ifndef IEC_STD_LIB_H
#define IEC_STD_LIB_H

#include "iec_types_all.h"

/* The runtime's clock and debug switch (the runtime defines them). */
extern TIME __CURRENT_TIME;
extern BOOL __DEBUG;

#define __BOOL_LITERAL(value) ((BOOL)(value))

#endif
"#;

/// Every header, by file name.
pub fn all() -> [(&'static str, &'static str); 4] {
    [
        ("iec_types.h", IEC_TYPES_H),
        ("iec_types_all.h", IEC_TYPES_ALL_H),
        ("accessor.h", ACCESSOR_H),
        ("iec_std_lib.h", IEC_STD_LIB_H),
    ]
}
