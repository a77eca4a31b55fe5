/* crslab's C28x arithmetic check (see math.h here): the stdlib functions a lab may call. */
#ifndef CRSLAB_C28X_CHECK_STDLIB_H
#define CRSLAB_C28X_CHECK_STDLIB_H
#include <stddef.h>
#define RAND_MAX 32767
int abs(int x);
long labs(long x);
int rand(void);
void srand(unsigned seed);
int atoi(const char *text);
long atol(const char *text);
double atof(const char *text);
double strtod(const char *text, char **end);
long strtol(const char *text, char **end, int base);
void *malloc(size_t size);
void *calloc(size_t count, size_t size);
void free(void *p);
void exit(int status);
void abort(void);
#endif
