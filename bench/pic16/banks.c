/* banks: the logic of /work/shared/tools/samples/banks.c, for SDCC (-mpic14 -p16f876a)
 * beside plcc's banks.st. On the host (gcc banks.c -DNSCANS=N) it prints the variables
 * after N scans (default 5) in the format of `plcc run`. */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

uint8_t  scan_cnt;
uint16_t cnt16 = 0x00FE;
uint16_t sum16, acc16, prod16, diff16;
uint8_t  mul_a, mul_b;
uint8_t  arr[4];

void scan(void)
{
    uint8_t i;
    scan_cnt++;
    cnt16++;
    sum16 = 0;
    for (i = 30; i != 0; i--)
        sum16 += i;
    acc16 += 0x1234;
    mul_a = 200;
    mul_b = 150;
    prod16 = (uint16_t)mul_a * mul_b;
    diff16 = prod16 - sum16;
    for (i = 0; i < 4; i++)
        arr[i] = 0xA1 + i;
}

#ifdef __SDCC
void main(void)
{
    for (;;)
        scan();
}
#else
int main(void)
{
    int k;
    for (k = 0; k < NSCANS; k++)
        scan();
    printf("scan_cnt = %u\ncnt16 = %u\nsum16 = %u\nacc16 = %u\nprod16 = %u\ndiff16 = %u\n"
           "mul_a = %u\nmul_b = %u\n", scan_cnt, cnt16, sum16, acc16, prod16, diff16,
           mul_a, mul_b);
    for (k = 0; k < 4; k++)
        printf("arr[%d] = %u\n", k, arr[k]);
    return 0;
}
#endif
