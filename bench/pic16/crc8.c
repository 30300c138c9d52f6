/* crc8: bitwise CRC-8 (polynomial 0x07, initial value 0) over 8 bytes of an array;
 * one byte changes every scan (the logic of crc8.st).
 * Host: gcc crc8.c -DNSCANS=N prints the variables after N scans (default 5). */
#include <stdint.h>

#ifndef NSCANS
#define NSCANS 5
#endif

#ifdef __SDCC
static __code uint16_t __at(0x2007) configword = 0x3F32;
#else
#include <stdio.h>
#endif

uint8_t data[8] = {0x31, 0x32, 0x33, 0x34, 0x35, 0x36, 0x37, 0x38};
uint8_t seq;
uint8_t crc;
uint8_t i;
uint8_t j;

void scan(void)
{
    data[seq & 7] ^= (uint8_t)(seq * 0x1D);
    seq++;
    crc = 0;
    for (i = 0; i <= 7; i++) {
        crc ^= data[i];
        for (j = 0; j <= 7; j++) {
            if (crc & 0x80)
                crc = (uint8_t)(crc << 1) ^ 0x07;
            else
                crc = (uint8_t)(crc << 1);
        }
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
#define PX(x) printf(#x " = 16#%X\n", (unsigned)(x))   /* BYTE, as plcc run prints it */
int main(void)
{
    int k;
    for (k = 0; k < NSCANS; k++)
        scan();
    for (k = 0; k < 8; k++)
        printf("data[%d] = 16#%X\n", k, data[k]);
    PU(seq); PX(crc); PU(i); PU(j);
    return 0;
}
#endif
