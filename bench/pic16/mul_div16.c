/* mul_div16: 16-bit multiplies, divides and MODs (signed and unsigned) of values that
 * change every scan (the logic of mul_div16.st).
 * Host: gcc mul_div16.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

int16_t  a = 100;
int16_t  b = -37;
uint16_t c = 50000;
uint16_t d = 7;
int16_t  p1, q1, r1, r1n;
uint16_t p2, q2, r2, mix;

void scan(void)
{
    a += 37;
    b += 5;
    c -= 1111;
    d += 3;
    p1 = a * b;
    q1 = (int16_t)(a * 7) / b;
    r1 = a % b;
    r1n = -a % 9;
    p2 = (uint16_t)(c % 1000u) * d;
    q2 = c / d;
    r2 = c % d;
    mix = (uint16_t)(p2 / 3u + q2 * 2u) % 10007u;
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
int main(void)
{
    int k;
    for (k = 0; k < NSCANS; k++)
        scan();
    PI(a); PI(b); PU(c); PU(d); PI(p1); PI(q1); PI(r1); PI(r1n); PU(p2); PU(q2); PU(r2); PU(mix);
    return 0;
}
#endif
