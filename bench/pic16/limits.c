/* limits: signed compares, clamping, min/max of several DINT/INT/SINT values
 * (the logic of limits.st). Host: gcc limits.c -DNSCANS=N prints the variables after
 * N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

int32_t a = -100000;
int32_t b = 70000;
int16_t c = -300;
int16_t d = 250;
int8_t  e = -100;
int32_t lo, hi, span;
int16_t mn, mx, clamped;
int32_t lim;
uint8_t inrange;
int8_t  sgn, emax;
uint8_t crossings;

void scan(void)
{
    a += 45000;
    b -= 30000;
    c += 170;
    d -= 90;
    e += 45;
    if (a < b) {
        lo = a;
        hi = b;
    } else {
        lo = b;
        hi = a;
        crossings++;
    }
    span = hi - lo;
    mn = c < d ? c : d;
    mx = c > d ? c : d;
    clamped = c;
    if (clamped > 200)
        clamped = 200;
    else if (clamped < -200)
        clamped = -200;
    lim = a < -50000 ? -50000 : (a > 50000 ? 50000 : a);
    inrange = (a >= -50000) && (a <= 50000);
    if (c > d)
        sgn = 1;
    else if (c < d)
        sgn = -1;
    else
        sgn = 0;
    emax = e > -20 ? e : -20;
    if ((int32_t)c > a)
        crossings += 16;
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
    PI(a); PI(b); PI(c); PI(d); PI(e); PI(lo); PI(hi); PI(span); PI(mn); PI(mx);
    PI(clamped); PI(lim); PB(inrange); PI(sgn); PI(emax); PU(crossings);
    return 0;
}
#endif
