/* Numbers as text for result files: exactly printf's "%.17g", fast.
 *
 * Seventeen significant digits read back to the same double. printf produces them by
 * exact (multi-precision) arithmetic; here |x| is scaled by a power of ten in 80-bit
 * extended precision and rounded to a 17-digit integer N. The powers 10^0 to 10^27 are
 * exact in extended precision, so the scaled value has one rounding, within 0.006 of
 * exact below 10^17 (the decimal exponents -11 to 16, most numbers of a result file);
 * other powers come from powl within an ulp, 1.1e-19, so within 0.02. Where the scaled
 * value lies within twice that of a rounding tie, or extended precision is not at hand,
 * printf itself formats the number, so the text is printf's in every case. Then %g's
 * layout: fixed notation for decimal exponents from -4 to 16, scientific otherwise,
 * trailing zeros removed.
 */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
    if (x == 0.0) {                                   /* "0" or "-0", as printf */
        const int negative = signbit(x) != 0;
        memcpy(out, "-0", 3);
        if (!negative)
            memmove(out, out + 1, 2);
        return 1 + negative;
    }
#if LDBL_MANT_DIG >= 64
    if (!isfinite(x))
        return printf_17g(x, out);
    if (!have_powers) {
        for (int k = LOWEST; k <= HIGHEST; k++)
            powers[k - LOWEST] = powl(10.0L, k);
        long double exact = 1.0L;
        for (int k = 0; k <= 27; k++, exact *= 10.0L)   /* exact products: 5^27 < 2^64 */
            powers[k - LOWEST] = exact;
        have_powers = 1;
    }
    const long double ax = fabsl((long double)x);
    int binary;
    frexp(x, &binary);                               /* 2^(binary - 1) <= |x| < 2^binary */
    int exponent = (int)floor((binary - 1) * 0.30102999566398120);  /* decimal, or one less */
    long double scaled = ax * powers[16 - exponent - LOWEST];
    if (scaled >= 1e17L || scaled < 1e16L) {        /* one decade off: scale afresh */
        exponent += scaled >= 1e17L ? 1 : -1;
        scaled = ax * powers[16 - exponent - LOWEST];
    }
    const int exact_power = 16 - exponent >= 0 && 16 - exponent <= 27;
    const long long nearest = llrintl(scaled);      /* no change of the x87 rounding mode */
    const long double off = fabsl(scaled - (long double)nearest);   /* at most 0.5 */
    if (0.5L - off < (exact_power ? 0.012L : 0.05L) || scaled < 1e16L || scaled >= 1e17L)
        return printf_17g(x, out);                  /* near a tie: printf decides */
    uint64_t n = (uint64_t)nearest;
    if (n == 100000000000000000ULL) {                /* rounded up to the next decade */
        n /= 10;
        exponent++;
    }
    static const char pairs[] = "00010203040506070809101112131415161718192021222324"
                                "25262728293031323334353637383940414243444546474849"
                                "50515253545556575859606162636465666768697071727374"
                                "75767778798081828384858687888990919293949596979899";
    char digits[17];
    for (int k = 15; k >= 1; k -= 2, n /= 100)      /* two digits a division */
        memcpy(digits + k, pairs + 2 * (n % 100), 2);
    digits[0] = (char)('0' + n);
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

/* Write all of `size` bytes to the file descriptor `fd`; 0, or -1 with errno set. */
static int write_all(int fd, const char *text, size_t size)
{
    while (size > 0) {
        const ssize_t done = write(fd, text, size);
        if (done < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        text += done;
        size -= (size_t)done;
    }
    return 0;
}

/* Rows are formatted into a buffer of CSV_BUFFER bytes and written as it fills: the memory
 * stays the same whatever the rows, and no large allocation costs the kernel page faults
 * (a thread formatting half of the rows gained nothing in a fresh process: the second
 * processor's wake-up took as long). */
#define CSV_BUFFER 65536
int fm_csv_write(int fd, const char *const *columns, const ptrdiff_t *strides, int n_columns,
                 ptrdiff_t rows)
{
    char *text = malloc(CSV_BUFFER);
    size_t used = 0;
    if (!text)
        return ENOMEM;
    for (ptrdiff_t r = 0; r < rows && n_columns > 0; r++)
        for (int k = 0; k < n_columns; k++) {
            if (used > CSV_BUFFER - 32) {        /* a number takes 25 bytes at most */
                if (write_all(fd, text, used)) {
                    free(text);
                    return errno;
                }
                used = 0;
            }
            used += (size_t)format_17g(*(const double *)(columns[k] + r * strides[k]),
                                       text + used);
            text[used++] = k + 1 < n_columns ? ',' : '\n';
        }
    const int error = write_all(fd, text, used) ? errno : 0;
    free(text);
    return error;
}
