/* runtime.c: a runtime in the way of OpenPLC v3's (written for plcc's tests, from
   the interface of docs/c.md and the reference: nothing of OpenPLC's own code). It
   owns the located variables (their storage and the pointers the program binds to,
   defined from LOCATED_VARIABLES.h as a glue generator does), binds them into its
   I/O tables, and runs the scan loop: config_run__(tick++), then the virtual time
   advances by common_ticktime__. It runs plant.st's C and checks what a PLC user
   would see. Built as C99 and as C++ (gnu++11), as OpenPLC builds it. */
#include <stdio.h>
#include <string.h>
#include "iec_std_lib.h"
#include "POUS.h" /* as a debugger's file does: the program's types and variables */

TIME __CURRENT_TIME;
BOOL __DEBUG;
extern unsigned long long common_ticktime__;
extern unsigned long greatest_tick_count__;
/* Declared as OpenPLC's ladder.h does: no extern "C" (in C++ they are mangled). */
void config_init__(void);
void config_run__(unsigned long tick);

/* The I/O tables: pointers into the located storage, NULL where nothing is. */
#define SLOTS 1024
IEC_BOOL *bool_input[SLOTS][8], *bool_output[SLOTS][8];
IEC_BYTE *byte_input[SLOTS], *byte_output[SLOTS];
IEC_UINT *int_input[SLOTS], *int_output[SLOTS], *int_memory[SLOTS];
IEC_UDINT *dint_input[SLOTS], *dint_output[SLOTS], *dint_memory[SLOTS];
IEC_ULINT *lint_input[SLOTS], *lint_output[SLOTS], *lint_memory[SLOTS];

/* The storage, then the pointers to it. */
#define __LOCATED_VAR(type, name, ...) type __##name;
#include "LOCATED_VARIABLES.h"
#undef __LOCATED_VAR
#define __LOCATED_VAR(type, name, ...) type *name = &__##name;
#include "LOCATED_VARIABLES.h"
#undef __LOCATED_VAR

static int failures;
#define EXPECT(c)                                                  \
    do {                                                           \
        if (!(c)) {                                                \
            printf("FAIL line %d: %s\n", __LINE__, #c);            \
            failures++;                                            \
        }                                                          \
    } while (0)

/* The binders of each direction and size: the pointer's name must be the one its
   address parts give. */
static void name_is(const char *name, const char *dir_size, int a, int b, int bit) {
    char want[64];
    if (bit) {
        snprintf(want, sizeof want, "__%s%d_%d", dir_size, a, b);
    } else {
        snprintf(want, sizeof want, "__%s%d", dir_size, a);
    }
    if (strcmp(want, name) != 0) {
        printf("FAIL: %s is named %s\n", want, name);
        failures++;
    }
}
#define BITS(ds, table)                                                   \
    void bind_##ds(void *p, const char *name, int a, int b) {             \
        name_is(name, #ds, a, b, 1);                                      \
        table[a][b] = (IEC_BOOL *)p;                                      \
    }
#define WORDS(ds, table, T)                                               \
    void bind_##ds(void *p, const char *name, int a) {                    \
        name_is(name, #ds, a, 0, 0);                                      \
        table[a] = (T *)p;                                                \
    }
void bind_IX(void *p, const char *name, int a, int b);
void bind_QX(void *p, const char *name, int a, int b);
void bind_IW(void *p, const char *name, int a);
void bind_QW(void *p, const char *name, int a);
void bind_MW(void *p, const char *name, int a);
void bind_MD(void *p, const char *name, int a);
void bind_ML(void *p, const char *name, int a);
BITS(IX, bool_input)
BITS(QX, bool_output)
WORDS(IW, int_input, IEC_UINT)
WORDS(QW, int_output, IEC_UINT)
WORDS(MW, int_memory, IEC_UINT)
WORDS(MD, dint_memory, IEC_UDINT)
WORDS(ML, lint_memory, IEC_ULINT)

static void glue(void) {
#define __LOCATED_VAR(type, name, dir, size, ...) bind_##dir##size((void *)name, #name, __VA_ARGS__);
#include "LOCATED_VARIABLES.h"
#undef __LOCATED_VAR
}

/* OpenPLC's virtual time: exactly one tick per scan. */
static void advance_time(void) {
    __CURRENT_TIME.tv_sec += (long)(common_ticktime__ / 1000000000ULL);
    __CURRENT_TIME.tv_nsec += (long)(common_ticktime__ % 1000000000ULL);
    if (__CURRENT_TIME.tv_nsec >= 1000000000L) {
        __CURRENT_TIME.tv_nsec -= 1000000000L;
        __CURRENT_TIME.tv_sec++;
    }
}

/* What the debugger reaches (the names VARIABLES.csv gives it). */
extern __IEC_INT_t CONFIG0__G1;
extern __IEC_INT_p CONFIG0__GQ;
extern __IEC_DINT_t RES0__RG;
extern INT *__GET_GLOBAL_G1(void);
extern IEC_BYTE __IS_GLOBAL_G1_FORCED(void);

int main(void) {
    unsigned long tick = 0;
    int scan, done_at = -1;
    config_init__();
    glue();
    EXPECT(common_ticktime__ == 10000000ULL);
    EXPECT(greatest_tick_count__ == 4294967290UL);
    /* Initial values reach the runtime's storage at config_init__. */
    EXPECT(*int_output[7] == 42);
    EXPECT(CONFIG0__G1.value == 5 && RES0__RG.value == 3);

    for (scan = 0; scan < 20; scan++) {
        *bool_input[0][0] = (IEC_BOOL)(scan == 0); /* start, pressed once */
        *bool_input[0][1] = 0;                     /* stop */
        *int_input[0] = 1234;
        config_run__(tick++);
        if (done_at < 0 && *bool_output[0][1]) {
            done_at = scan;
        }
        advance_time();
    }
    EXPECT(*bool_output[0][0] == 1);       /* lamp: run latched */
    EXPECT(*int_output[1] == 1235);        /* aout */
    EXPECT(*int_memory[2] == 1235);        /* mem */
    EXPECT(*dint_memory[0] == 10);         /* task0 (20 ms) at ticks 0, 2, ..., 18 */
    EXPECT(*lint_memory[1] == 20);
    EXPECT(CONFIG0__G1.value == 9);        /* task1 (50 ms) at ticks 0, 5, 10, 15 */
    EXPECT(*__GET_GLOBAL_G1() == 9);
    EXPECT(RES0__RG.value == 48);
    EXPECT(*int_output[7] == 9);           /* gq := g1, through the located global */
    EXPECT(*CONFIG0__GQ.value == 9);
    /* The TON counts virtual time: started at 0 ms, done at the scan at 100 ms. */
    EXPECT(done_at == 10);
    EXPECT(__CURRENT_TIME.tv_sec == 0 && __CURRENT_TIME.tv_nsec == 200000000L);

    /* Forcing, as a debugger does it. An input: the program reads the forced value
       (stop forced TRUE although the input is FALSE: run falls). An output: the
       program's writes are skipped (lamp forced to what it is). A variable: its
       value stays. */
    {
        RES0__INSTANCE0.STOP.fvalue = 1;
        RES0__INSTANCE0.STOP.flags |= __IEC_FORCE_FLAG;
        RES0__INSTANCE0.DONE.flags |= __IEC_FORCE_FLAG;
        RES0__INSTANCE0.CNT.value = 1000;
        RES0__INSTANCE0.CNT.flags |= __IEC_FORCE_FLAG;
        CONFIG0__G1.value = 100;
        CONFIG0__G1.flags |= __IEC_FORCE_FLAG;
        EXPECT(__IS_GLOBAL_G1_FORCED());
        for (scan = 0; scan < 10; scan++) {
            config_run__(tick++);
            advance_time();
        }
        EXPECT(*bool_input[0][1] == 0);
        EXPECT(RES0__INSTANCE0.RUN.value == 0);
        EXPECT(*bool_output[0][0] == 0);   /* lamp follows run */
        EXPECT(*bool_output[0][1] == 1);   /* done is forced: the TON's Q fell, done did not */
        EXPECT(RES0__INSTANCE0.T1.Q.value == 0);
        EXPECT(RES0__INSTANCE0.CNT.value == 1000);
        EXPECT(CONFIG0__G1.value == 100);
    }
    printf(failures ? "FAILED (%d)\n" : "OK\n", failures);
    return failures != 0;
}
