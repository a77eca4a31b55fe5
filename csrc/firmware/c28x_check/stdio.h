/* crslab's C28x arithmetic check (see math.h here): the stdio functions a lab may call. */
#ifndef CRSLAB_C28X_CHECK_STDIO_H
#define CRSLAB_C28X_CHECK_STDIO_H
#include <stdarg.h>
#include <stddef.h>
typedef struct crs_check_file FILE;
int printf(const char *fmt, ...);
int sprintf(char *out, const char *fmt, ...);
int snprintf(char *out, size_t size, const char *fmt, ...);
int vsprintf(char *out, const char *fmt, va_list ap);
int vsnprintf(char *out, size_t size, const char *fmt, va_list ap);
int puts(const char *text);
int putchar(int c);
int sscanf(const char *text, const char *fmt, ...);
#endif
