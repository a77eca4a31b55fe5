/* The two serial_printf formatters of the framework's generations (see serial_format.h for the rules). */
#include "serial_format.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "framework_facts.h"
#include "generations.h"

enum { MAX_FIELD = 4096 }; /* widths and precisions beyond this are clamped (never on a board) */

/* Output that counts every character and keeps what fits. */
typedef struct {
    char *out;
    size_t cap, n;
} text_out;

static void put(text_out *t, char c)
{
    if (t->n + 1 < t->cap) t->out[t->n] = c;
    t->n++;
}

static void put_repeat(text_out *t, char c, int count)
{
    for (int i = 0; i < count; ++i) put(t, c);
}

static size_t finish(text_out *t)
{
    t->out[t->n < t->cap ? t->n : t->cap - 1] = '\0';
    return t->n;
}

/* A width or precision written in digits at *p (no digit: 0), clamped to MAX_FIELD; *p is left
 * past the digits. */
static int field_number(const char **p)
{
    int value = 0;
    for (; **p >= '0' && **p <= '9'; ++*p) {
        if (value < MAX_FIELD) value = 10 * value + (**p - '0');
    }
    return value < MAX_FIELD ? value : MAX_FIELD;
}

/* ---- CRS_FORMATTER_SMALL (Gen A): the course's small printf ------------------------------- */

/* The C28x's float-to-long conversion saturates; NaN gives 0 (no undefined behaviour here). */
static int32_t f32_to_i32_saturating(float x)
{
    if (x != x) return 0;
    if (x >= 2147483648.0f) return INT32_MAX;
    if (x <= -2147483648.0f) return INT32_MIN;
    return (int32_t)x;
}

/* Digits of an unsigned value in base 2, 10 or 16 (lowercase), most significant first. */
static int unsigned_digits(uint32_t value, unsigned base, char digits[40])
{
    char rev[40];
    int n = 0;
    do {
        const unsigned d = (unsigned)(value % base);
        rev[n++] = (char)(d < 10 ? '0' + d : 'a' + d - 10);
        value /= base;
    } while (value != 0);
    for (int i = 0; i < n; ++i) digits[i] = rev[n - 1 - i];
    return n;
}

typedef struct {
    int left, plus, zero, width, precision, is_long; /* precision -1: not given */
} small_spec;

/* One field: the sign (0 for none) and the body, padded to the width. */
static void put_field(text_out *t, const small_spec *s, char sign, const char *body, int body_len,
                      int numeric)
{
    const int len = body_len + (sign ? 1 : 0);
    const int pad = s->width > len ? s->width - len : 0;
    if (s->left) {
        if (sign) put(t, sign);
        for (int i = 0; i < body_len; ++i) put(t, body[i]);
        put_repeat(t, ' ', pad);
    } else if (s->zero && numeric) {
        if (sign) put(t, sign);
        put_repeat(t, '0', pad);
        for (int i = 0; i < body_len; ++i) put(t, body[i]);
    } else {
        put_repeat(t, ' ', pad);
        if (sign) put(t, sign);
        for (int i = 0; i < body_len; ++i) put(t, body[i]);
    }
}

/* %f: the integer part, then each decimal by the float digit loop (truncating). */
static void put_small_float(text_out *t, const small_spec *s, float v)
{
    char body[MAX_FIELD + 48];
    char sign = s->plus ? '+' : 0;
    if (v < 0.0f) {
        sign = '-';
        v = -v;
    }
    float whole = floorf(v);
    int n = unsigned_digits((uint32_t)f32_to_i32_saturating(whole), 10, body);
    const int precision = s->precision < 0 ? CRS_SMALL_PRINTF_PRECISION : s->precision;
    if (precision > 0) body[n++] = '.';
    for (int i = 0; i < precision; ++i) {
        v -= whole;
        v *= 10.0f;
        whole = floorf(v);
        body[n++] = (char)(('0' + (uint32_t)f32_to_i32_saturating(whole)) & 0xFFu);
    }
    put_field(t, s, sign, body, n, 1);
}

size_t crs_format_small(char *out, size_t cap, const char *fmt, va_list ap)
{
    text_out t = {out, cap, 0};
    for (const char *p = fmt; *p; ++p) {
        if (*p != '%') {
            put(&t, *p);
            continue;
        }
        small_spec s = {0, 0, 0, 0, -1, 0};
        for (++p;; ++p) {
            if (*p == '-') {
                s.left = 1;
            } else if (*p == '+') {
                s.plus = 1;
            } else if (*p == '0') {
                s.zero = 1;
            } else {
                break;
            }
        }
        s.width = field_number(&p);
        if (*p == '.') {
            ++p;
            s.precision = field_number(&p);
        }
        if (*p == 'l') {
            s.is_long = 1;
            ++p;
        }
        char body[40];
        switch (*p) {
        case '\0':
            return finish(&t); /* a lone '%' at the end */
        case 'd':
        case 'i': {
            const int32_t v = s.is_long ? (int32_t)va_arg(ap, long) : (int16_t)va_arg(ap, int);
            const uint32_t mag = v < 0 ? 0u - (uint32_t)v : (uint32_t)v;
            const int n = unsigned_digits(mag, 10, body);
            put_field(&t, &s, v < 0 ? '-' : (s.plus ? '+' : 0), body, n, 1);
            break;
        }
        case 'x':
        case 'b': {
            const uint32_t v = s.is_long ? (uint32_t)va_arg(ap, long) : 0xFFFFu & (uint32_t)va_arg(ap, int);
            const int n = unsigned_digits(v, *p == 'x' ? 16 : 2, body);
            put_field(&t, &s, 0, body, n, 1);
            break;
        }
        case 'c':
            body[0] = (char)va_arg(ap, int);
            put_field(&t, &s, 0, body, 1, 0);
            break;
        case 's': {
            const char *str = va_arg(ap, const char *);
            if (str == NULL) str = "";
            const size_t len = strlen(str);
            put_field(&t, &s, 0, str, len < (1u << 24) ? (int)len : (1 << 24), 0);
            break;
        }
        case 'f':
            put_small_float(&t, &s, (float)va_arg(ap, double));
            break;
        default: /* '%%', and any conversion the small printf does not know: the character itself */
            put(&t, *p);
            break;
        }
    }
    return finish(&t);
}

/* ---- CRS_FORMATTER_TI (Gen B): TI's rounding vsprintf, with the C28x's argument sizes ------ */

/* Append one conversion, formatted by the host's snprintf, to t. */
static void put_host(text_out *t, const char *spec, ...)
{
    va_list ap;
    va_start(ap, spec);
    const size_t at = t->n < t->cap ? t->n : t->cap - 1;
    const int k = vsnprintf(t->out + at, t->cap - at, spec, ap);
    va_end(ap);
    if (k > 0) t->n += (size_t)k;
}

size_t crs_format_ti(char *out, size_t cap, const char *fmt, va_list ap)
{
    text_out t = {out, cap, 0};
    for (const char *p = fmt; *p; ++p) {
        if (*p != '%') {
            put(&t, *p);
            continue;
        }
        /* rebuild the conversion with explicit numbers, then add the host's length modifier */
        char spec[64];
        size_t k = 0;
        spec[k++] = '%';
        for (++p; *p && strchr("-+ #0", *p); ++p) {
            if (k < 8) spec[k++] = *p;
        }
        int has_width = 0, width = 0, precision = -1;
        if (*p == '*') {
            has_width = 1;
            width = va_arg(ap, int);
            ++p;
        } else {
            const char *digits = p;
            width = field_number(&p);
            has_width = p != digits;
        }
        if (*p == '.') {
            if (*++p == '*') {
                precision = va_arg(ap, int);
                ++p;
            } else {
                precision = field_number(&p);
            }
        }
        /* a '*' width or precision: clamped as the digits are */
        if (width < -MAX_FIELD) width = -MAX_FIELD;
        if (width > MAX_FIELD) width = MAX_FIELD;
        if (precision > MAX_FIELD) precision = MAX_FIELD;
        if (width < 0) { /* a negative '*' width means '-' */
            spec[k++] = '-';
            width = -width;
        }
        if (has_width) k += (size_t)snprintf(spec + k, sizeof spec - k, "%d", width);
        if (precision >= 0) k += (size_t)snprintf(spec + k, sizeof spec - k, ".%d", precision);
        int longs = 0, is_long_double = 0;
        for (; *p && strchr("hlLqjzt", *p); ++p) {
            if (*p == 'l' || *p == 'q' || *p == 'j') longs++;
            if (*p == 'L') is_long_double = 1;
        }
        const char conv = *p;
        if (conv == '\0') return finish(&t);
        char full[80];
        switch (conv) {
        case 'd':
        case 'i':
            if (longs >= 2) {
                snprintf(full, sizeof full, "%.*slld", (int)k, spec);
                put_host(&t, full, (long long)va_arg(ap, long long));
            } else {
                const long v = longs ? (long)(int32_t)va_arg(ap, long) : (long)(int16_t)va_arg(ap, int);
                snprintf(full, sizeof full, "%.*sld", (int)k, spec);
                put_host(&t, full, v);
            }
            break;
        case 'o':
        case 'u':
        case 'x':
        case 'X':
            if (longs >= 2) {
                snprintf(full, sizeof full, "%.*sll%c", (int)k, spec, conv);
                put_host(&t, full, (unsigned long long)va_arg(ap, unsigned long long));
            } else {
                const unsigned long v = longs ? (unsigned long)(uint32_t)va_arg(ap, unsigned long)
                                              : (unsigned long)(uint16_t)va_arg(ap, unsigned int);
                snprintf(full, sizeof full, "%.*sl%c", (int)k, spec, conv);
                put_host(&t, full, v);
            }
            break;
        case 'c':
            snprintf(full, sizeof full, "%.*sc", (int)k, spec);
            put_host(&t, full, va_arg(ap, int));
            break;
        case 's': {
            const char *str = va_arg(ap, const char *);
            snprintf(full, sizeof full, "%.*ss", (int)k, spec);
            put_host(&t, full, str != NULL ? str : "");
            break;
        }
        case 'p':
            snprintf(full, sizeof full, "%.*sp", (int)k, spec);
            put_host(&t, full, va_arg(ap, void *));
            break;
        case 'f':
        case 'F':
        case 'e':
        case 'E':
        case 'g':
        case 'G':
        case 'a':
        case 'A':
            if (is_long_double) {
                snprintf(full, sizeof full, "%.*sL%c", (int)k, spec, conv);
                put_host(&t, full, va_arg(ap, long double));
            } else {
                snprintf(full, sizeof full, "%.*s%c", (int)k, spec, conv);
                put_host(&t, full, (double)(float)va_arg(ap, double));
            }
            break;
        case 'n':
            (void)va_arg(ap, void *); /* writes nothing: a host int is not the board's */
            break;
        case '%':
            put(&t, '%');
            break;
        default: /* not a conversion: print it as written */
            for (size_t i = 0; i < k; ++i) put(&t, spec[i]);
            put(&t, conv);
            break;
        }
    }
    return finish(&t);
}

crs_format_fn crs_format_of(int32_t formatter)
{
    switch (formatter) {
    case CRS_FORMATTER_SMALL:
        return crs_format_small;
    case CRS_FORMATTER_TI:
        return crs_format_ti;
    default:
        return NULL;
    }
}
