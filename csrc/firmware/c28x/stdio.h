/* The C library's <stdio.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here). Every function is the C library's own: a count or a character
 * goes to it as the 32-bit number it takes, and a variadic call's int and double arguments are
 * widened on the way as C does on wasm32 (crslab/lab/c28x_ir.py), so printf reads what it is given.
 * The console (stdout, stderr) is the board's; no file can be opened (the board refuses). */
#ifndef CRSLAB_C28X_STDIO_H
#define CRSLAB_C28X_STDIO_H
#include <stdarg.h>
#include <stddef.h>

typedef struct crs_c28x_file FILE;
extern FILE *const stdin;
extern FILE *const stdout;
extern FILE *const stderr;
#define EOF (-1)
#define BUFSIZ 1024

int printf(const char *fmt, ...);
int fprintf(FILE *to, const char *fmt, ...);
int sprintf(char *out, const char *fmt, ...);
int snprintf(char *out, unsigned long size, const char *fmt, ...);
int sscanf(const char *text, const char *fmt, ...);
int puts(const char *text);
int fputs(const char *text, FILE *to);
int putchar(long c);
int fputc(long c, FILE *to);
int fflush(FILE *f);
FILE *fopen(const char *path, const char *mode);
int fclose(FILE *f);
char *fgets(char *out, long size, FILE *from);
int fgetc(FILE *from);
unsigned long fread(void *out, unsigned long size, unsigned long count, FILE *from);
unsigned long fwrite(const void *from, unsigned long size, unsigned long count, FILE *to);
int remove(const char *path);
int rename(const char *from, const char *to);
void perror(const char *text);

#endif
