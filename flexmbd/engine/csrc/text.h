/* Numbers as text for result files (text.c). */
#ifndef FLEXMBD_TEXT_H
#define FLEXMBD_TEXT_H

#include <stddef.h>

/* x as printf's "%.17g" would write it, into out (32 bytes at least); the length. */
int format_17g(double x, char *out);

/* The rows of `n_columns` float64 columns of `rows` entries each (column k's entry r at
 * columns[k] + r * strides[k] bytes) as CSV lines on the file descriptor fd, each number as
 * format_17g writes it; 0, or the errno of the write that failed. Needs no Python: the
 * binding calls it without the interpreter's lock. */
int fm_csv_write(int fd, const char *const *columns, const ptrdiff_t *strides, int n_columns,
                 ptrdiff_t rows);

#endif
