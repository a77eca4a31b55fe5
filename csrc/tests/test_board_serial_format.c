/* C-level tests of the two generations' serial_printf formatters (csrc/firmware/serial_format.c);
 * built with -Werror and under ASan/UBSan by tests/test_c_core.py. Exit status 0 when every
 * check passes.
 *
 * Every expected string is worked by hand from the rules in docs/framework.md section 7 (Gen A) or is
 * what C's printf gives for the float value (Gen B). For Gen A's %f the float digit loop is
 * spelled out in the comments: v is the float, "whole" the integer part, then per digit
 * v = (v - whole) * 10 in float and the digit is floor(v). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "serial_format.h"

#include "checks.h"

static void check_format(int gen_b, const char *want, const char *fmt, ...)
{
    char out[512];
    va_list ap;
    va_start(ap, fmt);
    const size_t n = gen_b ? crs_format_ti(out, sizeof out, fmt, ap) : crs_format_small(out, sizeof out, fmt, ap);
    va_end(ap);
    if (strcmp(out, want) != 0 || n != strlen(want)) {
        printf("FAIL gen %c \"%s\": got \"%s\" (%zu chars), want \"%s\"\n", gen_b ? 'B' : 'A', fmt, out, n,
               want);
        ++failures;
    }
}

#define GEN_A(want, ...) check_format(0, want, __VA_ARGS__)
#define GEN_B(want, ...) check_format(1, want, __VA_ARGS__)

static void gen_a_floats_truncate_digit_by_digit(void)
{
    /* 1.41f = 1.40999996662: whole 1; 0.40999997 * 10 = 4.0999997 -> 4; 0.0999997 * 10 -> 0 */
    GEN_A("1.40", "%.2f", 1.41f);
    /* 87.06f = 87.0599975586: 0.0599976 * 10 = 0.599976 -> 0; 5.99976 -> 5 (the lost count) */
    GEN_A("87.05", "%.2f", 87.06f);
    /* negative: '-', then the absolute value 1.98999989033: 9.8999989 -> 9, then 8.999989 -> 8 */
    GEN_A("-1.98", "%.2f", -1.99f);
    GEN_A("29.81", "%.2f", 29.82f); /* 29.8199996948 */
    /* a bare %f prints 5 decimals: 1.40999996662 -> 1.40999 */
    GEN_A("1.40999", "%f", 1.41f);
    GEN_A("87.05999", "%f", 87.06f);
    GEN_A("123.45600", "%f", 123.456f); /* 123.456001282 */
    /* %.0f: the integer part, no point (2.5 does not round to 2 or 3: it truncates) */
    GEN_A("2", "%.0f", 2.5f);
    GEN_A("-1", "%.0f", -1.99f);
    GEN_A("-0", "%.0f", -0.004f); /* negative: the sign, then 0 */
    /* width pads on the left with blanks, '-' on the right, '0' with zeros after the sign */
    GEN_A("  1.40", "%6.2f", 1.41f);
    GEN_A(" -1.98", "%6.2f", -1.99f);
    GEN_A("29.819  |", "%-8.3f|", 29.82f);
    GEN_A("0123.45", "%07.2f", 123.456f);
    GEN_A("-001.98", "%07.2f", -1.99f);
    GEN_A("-000.00", "%07.2f", -0.004f);
    /* '+' on a non-negative value */
    GEN_A("+0.1", "%+.1f", 0.1f);
    GEN_A("+87.0", "%+.1f", 87.06f);
    GEN_A("-1.9", "%+.1f", -1.99f);
    /* a double argument is taken as the float the board would have passed */
    GEN_A("1.40", "%.2f", 1.41);
    /* NaN and infinity are garbage on the board; here the saturating conversion's */
    GEN_A("0.00", "%.2f", (double)NAN);
    GEN_A("2147483647.00", "%.2f", (double)INFINITY);
    GEN_A("-2147483647.00", "%.2f", -(double)INFINITY);
}

static void gen_a_integers_are_16_bit(void)
{
    GEN_A("42 -42", "%d %i", 42, -42);
    GEN_A("-32768 32767", "%d %d", -32768, 32767);
    /* an int holding 70000 (or a long passed to %d) shows its low 16 bits: 70000 - 65536 */
    GEN_A("4464", "%d", 70000);
    GEN_A("-5536", "%d", 60000); /* 60000 - 65536 */
    GEN_A("100000 -2147483648", "%ld %ld", 100000L, -2147483647L - 1);
    GEN_A("   42|42   |-0042|+7", "%5d|%-5d|%05d|%+d", 42, 42, -42, 7);
    /* %x and %b print 0xFFFF & value: negative ints as 16-bit two's complement */
    GEN_A("ff ffff 8000", "%x %x %x", 255, -1, -32768);
    GEN_A("101 1111111111111110", "%b %b", 5, -2);
    GEN_A("00ff", "%04x", 255);
    GEN_A("ffffffff 10000", "%lx %lx", -1L, 65536L);
}

static void gen_a_text_and_unknown_conversions(void)
{
    GEN_A("A|  abc|abc  |%", "%c|%5s|%-5s|%%", 'A', "abc", "abc");
    /* a conversion the small printf does not know prints its character and takes no argument:
     * the 5 meant for %u goes to the %d after it */
    GEN_A("u 5", "%u %d", 5);
    GEN_A("e", "%e");
    GEN_A("end", "end%"); /* a lone % at the end prints nothing */
}

static void gen_b_rounds_with_the_boards_argument_sizes(void)
{
    GEN_B("1.41 87.06 -1.99 29.82", "%.2f %.2f %.2f %.2f", 1.41f, 87.06f, -1.99f, 29.82f);
    GEN_B("87.059998", "%f", 87.06f); /* six decimals of the float 87.0599975586 */
    GEN_B("2 -2", "%.0f %.0f", 2.5f, -1.99f); /* C rounds half to even */
    GEN_B("0123.46|+0.1", "%07.2f|%+.1f", 123.456f, 0.1f);
    GEN_B("1.41", "%.2f", 1.41); /* a double is a 32-bit float on the C28x */
    GEN_B("4464 ffff 65535", "%d %x %u", 70000, -1, -1); /* 16-bit int */
    GEN_B("100000 4294967295", "%ld %lu", 100000L, -1L); /* 32-bit long */
    GEN_B("1.234568e+04", "%e", 12345.678f);
    GEN_B("   42|42   |", "%*d|%-*d|", 5, 42, 5, 42);
    GEN_B("abc % x", "%s %% %c", "abc", 'x');
}

static size_t format_into(int gen_b, char *out, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const size_t n = gen_b ? crs_format_ti(out, cap, fmt, ap) : crs_format_small(out, cap, fmt, ap);
    va_end(ap);
    return n;
}

static void output_is_counted_beyond_the_buffer(void)
{
    for (int gen_b = 0; gen_b < 2; ++gen_b) {
        char out[8];
        const size_t n = format_into(gen_b, out, sizeof out, "%s %d", "0123456789", 42);
        if (n != 13 || strcmp(out, "0123456") != 0) {
            printf("FAIL gen %c: 13 characters into 8 bytes gave %zu, \"%s\"\n", gen_b ? 'B' : 'A', n, out);
            ++failures;
        }
    }
}

static void expect_count(int gen_b, size_t want, const char *fmt, ...)
{
    char out[8];
    va_list ap;
    va_start(ap, fmt);
    const size_t n = gen_b ? crs_format_ti(out, sizeof out, fmt, ap) : crs_format_small(out, sizeof out, fmt, ap);
    va_end(ap);
    if (n != want) {
        printf("FAIL gen %c \"%s\": %zu characters, want %zu\n", gen_b ? 'B' : 'A', fmt, n, want);
        ++failures;
    }
}

/* A width or precision beyond 4096 (MAX_FIELD) is taken as 4096, written in digits or (Gen B) as
 * a '*' argument: "%99999d" is 4096 characters wide; "%.99999f" of 1.0 is "1." and 4096 zeros. */
static void widths_and_precisions_beyond_4096_are_4096(void)
{
    for (int gen_b = 0; gen_b < 2; ++gen_b) {
        expect_count(gen_b, 4096, "%99999d", 7);
        expect_count(gen_b, 4096, "%-99999d", 7);
        expect_count(gen_b, 4098, "%.99999f", 1.0);
        expect_count(gen_b, 4098 + 4096 + 1, "%.99999f|%4096d", 1.0, 7);
    }
    expect_count(1, 4096, "%*d", 99999, 7);
    expect_count(1, 4096, "%*d", -99999, 7);
    expect_count(1, 4098, "%.*f", 99999, 1.0);
    GEN_A("2|  42", "%.f|%4d", 2.5f, 42); /* a point without digits: precision 0 */
    GEN_B("2|  42", "%.f|%4d", 2.5f, 42);
}

int main(void)
{
    gen_a_floats_truncate_digit_by_digit();
    gen_a_integers_are_16_bit();
    gen_a_text_and_unknown_conversions();
    gen_b_rounds_with_the_boards_argument_sizes();
    output_is_counted_beyond_the_buffer();
    widths_and_precisions_beyond_4096_are_4096();
    return checks_report();
}
