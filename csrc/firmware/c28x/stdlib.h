/* The C library's <stdlib.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here). A size, a seed or a status goes to the C library as the 32-bit
 * number it takes; rand() returns 0 to RAND_MAX, 32767, as TI's does (its sequence is the C
 * library's, not TI's); atof() and strtod() read a 32-bit double. */
#ifndef CRSLAB_C28X_STDLIB_H
#define CRSLAB_C28X_STDLIB_H
#include <stddef.h>

#define RAND_MAX 32767
#define EXIT_SUCCESS 0
#define EXIT_FAILURE 1

void *malloc(unsigned long size);
void *calloc(unsigned long count, unsigned long size);
void *realloc(void *p, unsigned long size);
void free(void *p);
_Noreturn void exit(long status);
_Noreturn void abort(void);
long labs(long x);
long atol(const char *text);
long strtol(const char *text, char **end, long base);
unsigned long strtoul(const char *text, char **end, long base);
double strtod(const char *text, char **end) __asm__("strtof");
char *getenv(const char *name);
int system(const char *command);
void qsort(void *items, unsigned long count, unsigned long size, int (*compare)(const void *, const void *));
void *bsearch(const void *key, const void *items, unsigned long count, unsigned long size,
              int (*compare)(const void *, const void *));
void srand(unsigned long seed);
long crs_c28x_rand(void) __asm__("rand");
static inline int rand(void) { return (int)(crs_c28x_rand() & RAND_MAX); }
static inline int abs(int x) { return x < 0 ? -x : x; }
static inline int atoi(const char *text) { return (int)atol(text); }
static inline double atof(const char *text) { return strtod(text, NULL); }

#endif
