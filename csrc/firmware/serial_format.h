/* How serial_printf turns a format and its arguments into characters, in each of the two ways
 * the framework's generations do (docs/framework.md section 7; a generation's row names its
 * formatter, csrc/port/generations.c). Internal to the firmware; not read by cffi.
 *
 * Both take their arguments as a C28x would have passed them: `int` is 16 bits, `long` 32 bits,
 * and `float` and `double` are both 32-bit floats, so a float argument (promoted to double by
 * the host's varargs) is converted back to float before it is formatted.
 *
 * CRS_FORMATTER_SMALL (Gen A): the course's own small printf. Conversions %d %i (16-bit int),
 * %ld %li (32-bit long), %x and %b (hex and binary of 0xFFFF & an int; with l, of a 32-bit long),
 * %c, %s, %f and %%.
 * Flags '-' (left-justify), '+' (sign on non-negative %d and %f) and '0' (pad numbers with zeros
 * after the sign); a width; a precision for %f (default 5; %.0f prints no point). %f prints '-'
 * for a negative value and continues with its absolute value v: the integer part floor(v), then
 * for each decimal `v -= whole; v *= 10; whole = floor(v)` in 32-bit float arithmetic, printing
 * whole as the digit. So digits are truncated, never rounded, and float error can lose one more
 * count: 1.41f prints 1.40, 87.06f prints 87.05. The integer part converts like the C28x's
 * saturating float-to-long: NaN and infinity print garbage (NaN as 0.00000, infinity as
 * 2147483647.00000), never "nan". An unknown conversion character prints as itself and takes
 * no argument.
 *
 * CRS_FORMATTER_TI (Gen B): TI's run-time library vsprintf, which rounds like glibc; every C
 * conversion, with the C28x's argument sizes above.
 *
 * Each writes at most cap - 1 characters and a NUL into out (cap >= 1) and returns how many
 * characters the whole format produces, which may be more than were written. */
#ifndef CRSLAB_SERIAL_FORMAT_H
#define CRSLAB_SERIAL_FORMAT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

size_t crs_format_small(char *out, size_t cap, const char *fmt, va_list ap);
size_t crs_format_ti(char *out, size_t cap, const char *fmt, va_list ap);

typedef size_t (*crs_format_fn)(char *out, size_t cap, const char *fmt, va_list ap);
/* The formatter of kind `formatter` (CRS_FORMATTER_*, csrc/port/generations.h), or NULL. */
crs_format_fn crs_format_of(int32_t formatter);

#endif
