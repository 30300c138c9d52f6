/* motor_logic: start/stop latches, interlocks and edge detection on 16 BOOLs
 * (the logic of motor_logic.st). BOOL = uint8_t holding 0 or 1.
 * Host: gcc motor_logic.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

uint8_t pat = 3;
uint8_t edges;
uint8_t start1, stop1, start2, stop2, estop;
uint8_t run1, run2;
uint8_t start1_prev, stop2_prev, start1_re, stop2_fe;
uint8_t fault, ready, busy, alarm;
uint8_t lamp = 1;

void scan(void)
{
    pat = pat * 5 + 1;
    start1 = (pat & 0x01) != 0;
    stop1 = (pat & 0x06) == 0x06;
    start2 = (pat & 0x10) != 0;
    stop2 = (pat & 0x20) != 0;
    estop = (pat & 0xC0) == 0xC0;
    start1_re = start1 && !start1_prev;
    start1_prev = start1;
    stop2_fe = !stop2 && stop2_prev;
    stop2_prev = stop2;
    if (estop && (run1 || run2))
        fault = 1;
    if (stop2_fe && !estop)
        fault = 0;
    ready = !estop && !fault;
    run1 = (start1_re || run1) && !stop1 && ready;
    run2 = (start2 || run2) && !stop2 && ready && !run1;
    busy = run1 ^ run2;
    alarm = fault || (estop && !lamp);
    lamp = busy || (alarm && start2) || (!lamp && stop1);
    if (start1_re)
        edges++;
    if (stop2_fe)
        edges += 16;
}

#ifdef __SDCC
void main(void)
{
    for (;;)
        scan();
}
#else
#define PU(x) printf(#x " = %u\n", (unsigned)(x))
#define PB(x) printf(#x " = %s\n", (x) ? "TRUE" : "FALSE")
int main(void)
{
    int k;
    for (k = 0; k < NSCANS; k++)
        scan();
    PU(pat); PU(edges);
    PB(start1); PB(stop1); PB(start2); PB(stop2); PB(estop); PB(run1); PB(run2);
    PB(start1_prev); PB(stop2_prev); PB(start1_re); PB(stop2_fe);
    PB(fault); PB(ready); PB(busy); PB(alarm); PB(lamp);
    return 0;
}
#endif
