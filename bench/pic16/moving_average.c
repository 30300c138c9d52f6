/* moving_average: a ring buffer of 8 INTs, their sum divided by 8 (signed: the average
 * of negative samples rounds toward zero) - the logic of moving_average.st.
 * Host: gcc moving_average.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

int16_t buf[8] = {-40, -35, 12, -7, 90, -120, 3, -66};
uint8_t idx;
int16_t sample = -95;
int16_t sum;
int16_t avg;
uint8_t i;

void scan(void)
{
    sample += 23;
    buf[idx] = sample;
    idx = (idx + 1) & 7;
    sum = 0;
    for (i = 0; i <= 7; i++)
        sum += buf[i];
    avg = sum / 8;
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
    for (k = 0; k < 8; k++)
        printf("buf[%d] = %d\n", k, buf[k]);
    PU(idx); PI(sample); PI(sum); PI(avg); PU(i);
    return 0;
}
#endif
