/* Numbers as text for result files: exactly printf's "%.17g", fast.
 *
 * Seventeen significant digits read back to the same double. printf produces them by
 * exact (multi-precision) arithmetic, about 250 ns a number; here |x| is scaled by a power
 * of ten in 80-bit extended precision (powl within an ulp, 1.1e-19, then one rounding: N
 * within 0.02 of exact) and rounded to a 17-digit integer N. Where the scaled value lies
 * within 0.05 of a rounding tie (a few numbers in a hundred) or extended precision is not
 * at hand, printf itself formats
 * the number, so the text is printf's in every case. Then %g's layout: fixed notation for
 * decimal exponents from -4 to 16, scientific otherwise, trailing zeros removed.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "text.h"

static int printf_17g(double x, char *out)
{
    return snprintf(out, 32, "%.17g", x);
}

#if LDBL_MANT_DIG >= 64
#define LOWEST (-16 - 308 - 1)                       /* 10^(16 - exponent) for every double */
#define HIGHEST (16 + 324 + 1)
static long double powers[HIGHEST - LOWEST + 1];      /* 10^k, each within an ulp (powl) */
static int have_powers;
#endif

int format_17g(double x, char *out)
{
#if LDBL_MANT_DIG >= 64
    if (!isfinite(x) || x == 0.0)
        return printf_17g(x, out);
    if (!have_powers) {
        for (int k = LOWEST; k <= HIGHEST; k++)
            powers[k - LOWEST] = powl(10.0L, k);
        have_powers = 1;
    }
    const long double ax = fabsl((long double)x);
    int binary;
    frexp(x, &binary);                               /* 2^(binary - 1) <= |x| < 2^binary */
    int exponent = (int)floor((binary - 1) * 0.30102999566398120);  /* decimal, or one less */
    long double scaled = ax * powers[16 - exponent - LOWEST];
    if (scaled >= 1e17L) {
        exponent++;
        scaled /= 10.0L;
    } else if (scaled < 1e16L) {
        exponent--;
        scaled *= 10.0L;
    }
    const long double whole = floorl(scaled), fraction = scaled - whole;
    if (fabsl(fraction - 0.5L) < 0.05L || scaled < 1e16L || scaled >= 1e17L)
        return printf_17g(x, out);                  /* near a tie: printf decides */
    uint64_t n = (uint64_t)whole + (fraction > 0.5L);
    if (n == 100000000000000000ULL) {                /* rounded up to the next decade */
        n /= 10;
        exponent++;
    }
    char digits[17];
    for (int k = 16; k >= 0; k--, n /= 10)
        digits[k] = (char)('0' + n % 10);
    int last = 16;                                   /* without trailing zeros */
    while (last > 0 && digits[last] == '0')
        last--;
    char *p = out;
    if (x < 0)
        *p++ = '-';
    if (exponent >= -4 && exponent < 17) {           /* fixed notation */
        if (exponent < 0) {
            memcpy(p, "0.", 2);
            p += 2;
            for (int k = 0; k < -exponent - 1; k++)
                *p++ = '0';
            memcpy(p, digits, last + 1);
            p += last + 1;
        } else {
            memcpy(p, digits, exponent + 1);
            p += exponent + 1;
            if (last > exponent) {
                *p++ = '.';
                memcpy(p, digits + exponent + 1, last - exponent);
                p += last - exponent;
            }
        }
    } else {                                         /* scientific, two exponent digits at least */
        *p++ = digits[0];
        if (last > 0) {
            *p++ = '.';
            memcpy(p, digits + 1, last);
            p += last;
        }
        const int e = abs(exponent);
        *p++ = 'e';
        *p++ = exponent < 0 ? '-' : '+';
        if (e >= 100)
            *p++ = (char)('0' + e / 100);
        *p++ = (char)('0' + e / 10 % 10);
        *p++ = (char)('0' + e % 10);
    }
    *p = '\0';
    return (int)(p - out);
#else
    return printf_17g(x, out);
#endif
}
