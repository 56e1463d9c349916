/* Numbers as text for result files (text.c). */
#ifndef FLEXMBD_TEXT_H
#define FLEXMBD_TEXT_H

/* x as printf's "%.17g" would write it, into out (32 bytes at least); the length. */
int format_17g(double x, char *out);

#endif
