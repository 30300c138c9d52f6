/* plc_scan: the logic of /work/shared/tools/samples/plc_scan.c minus PORTB, beside
 * plcc's plc_scan.st. Host: gcc plc_scan.c -DNSCANS=N prints the variables after N
 * scans (default 5) in the format of `plcc run`. */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

uint16_t scan_count = 0x00FE;  /* CTU-like 16-bit counter                        */
uint16_t ton_et;               /* TON elapsed "time" in scans, PT = 3            */
uint8_t  ton_q;
uint16_t sum_n;                /* 1 + 2 + ... + n_param                          */
uint8_t  n_param = 30;
uint16_t mul_a = 300, mul_b = 7;
uint16_t prod;                 /* 16x16 -> 16 multiply                           */
uint16_t quot, rem;            /* 16/16 divide and modulo                        */
int16_t  level = -40;          /* ramps by +25 a scan                            */
uint8_t  alarms;               /* bit0: level > 50, bit1: level < -20, bit2: TON */
uint32_t total;                /* 32-bit accumulator                             */

void scan(void)
{
    uint8_t i;

    scan_count++;
    if (ton_et < 3u)
        ton_et++;
    ton_q = (ton_et >= 3u);
    sum_n = 0;
    for (i = 1; i <= n_param; i++)
        sum_n += i;
    prod = mul_a * mul_b;
    mul_b++;
    quot = prod / 13u;
    rem  = prod % 13u;
    level += 25;
    alarms = 0;
    if (level > 50)
        alarms |= 1u;
    if (level < -20)
        alarms |= 2u;
    if (ton_q)
        alarms |= 4u;
    total += prod;
}

#ifdef __SDCC
void main(void)
{
    for (;;)
        scan();
}
#else
#define PU(x) printf(#x " = %u\n", (unsigned)(x))
#define PI(x) printf(#x " = %d\n", (int)(x))
#define PB(x) printf(#x " = %s\n", (x) ? "TRUE" : "FALSE")
int main(void)
{
    int k;
    for (k = 0; k < NSCANS; k++)
        scan();
    PU(scan_count); PU(ton_et); PB(ton_q); PU(sum_n); PU(n_param); PU(mul_a); PU(mul_b);
    PU(prod); PU(quot); PU(rem); PI(level); PU(alarms);
    printf("total = %lu\n", (unsigned long)total);
    return 0;
}
#endif
