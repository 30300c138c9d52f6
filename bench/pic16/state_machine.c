/* state_machine: a switch over a state variable, 6 states, with counters
 * (the logic of state_machine.st).
 * Host: gcc state_machine.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

uint8_t  state;
uint16_t timer;
uint16_t ticks;
int16_t  level;
int16_t  temp = 20;
uint8_t  fills;
uint8_t  mixes;
uint16_t batches;
uint8_t  errors;

void scan(void)
{
    ticks++;
    timer++;
    switch (state) {
    case 0: /* idle */
        if (timer >= 1) {
            state = 1;
            timer = 0;
        }
        break;
    case 1: /* fill */
        level += 13;
        if (level >= 13) {
            fills++;
            state = 2;
            timer = 0;
        }
        break;
    case 2: /* heat */
        temp += 15;
        if (temp >= 35 || timer > 4) {
            state = 3;
            timer = 0;
        }
        break;
    case 3: /* mix */
        mixes++;
        level -= 4;
        state = 4;
        timer = 0;
        break;
    case 4: /* drain */
        level -= 9;
        if (level <= 0) {
            level = 0;
            state = 5;
            timer = 0;
        }
        break;
    case 5: /* done */
        batches++;
        temp -= 15;
        state = 0;
        timer = 0;
        break;
    default:
        errors++;
        state = 0;
        break;
    }
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
    PU(state); PU(timer); PU(ticks); PI(level); PI(temp); PU(fills); PU(mixes);
    PU(batches); PU(errors);
    return 0;
}
#endif
