/* Doubles as decimal text and back, exactly as the C library does it, faster for the
 * values of a run's scale: the particle CSV files (written at start and end, read by the
 * file scene) hold hundreds of thousands of them, and glibc's printf and strtod spend
 * thousands of instructions on each (multi-precision arithmetic). Both do the common case
 * in exact 128-bit integer arithmetic, the formatter its small values (below about 1e-6)
 * in a wider integer, and leave every other case to the library. */
#ifndef SPAM_DECIMAL_H
#define SPAM_DECIMAL_H

/* "%.17g" of x into buf (at least 32 bytes), byte for byte as snprintf writes it; returns
 * the length (format_g17.c). */
int SpamFormatG17(double x, char *buf);
/* strtod(s, end) in the C locale, bit for bit (parse_double.c). */
double SpamParseDouble(const char *s, char **end);
#endif
