/* sum_array: a FOR loop over an array of 16 INTs (sum, max, count of negatives);
 * one element changes every scan (the logic of sum_array.st).
 * Host: gcc sum_array.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

int16_t arr[16] = {12, -7, 300, 45, -1000, 8, 0, 77, -3, 2500, 19, -64, 5, 640, -250, 31};
int16_t k;
int16_t i;
int16_t sum;
int16_t maxv;
int16_t neg;

void scan(void)
{
    arr[k] = arr[k] * 3 - 7;
    k = (k + 5) % 16;
    sum = 0;
    maxv = -30000;
    neg = 0;
    for (i = 0; i <= 15; i++) {
        sum += arr[i];
        if (arr[i] > maxv)
            maxv = arr[i];
        if (arr[i] < 0)
            neg++;
    }
}

#ifdef __SDCC
void main(void)
{
    for (;;)
        scan();
}
#else
#define PI(x) printf(#x " = %d\n", (int)(x))
int main(void)
{
    int n;
    for (n = 0; n < NSCANS; n++)
        scan();
    for (n = 0; n < 16; n++)
        printf("arr[%d] = %d\n", n, arr[n]);
    PI(k); PI(i); PI(sum); PI(maxv); PI(neg);
    return 0;
}
#endif
