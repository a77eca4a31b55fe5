/* The C library's <string.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here): a count or a character goes to the C library as the 32-bit
 * number it takes. A char is 8 bits here, 16 on the C28x. */
#ifndef CRSLAB_C28X_STRING_H
#define CRSLAB_C28X_STRING_H
#include <stddef.h>

void *memcpy(void *to, const void *from, unsigned long n);
void *memmove(void *to, const void *from, unsigned long n);
void *memset(void *to, long c, unsigned long n);
int memcmp(const void *a, const void *b, unsigned long n);
void *memchr(const void *s, long c, unsigned long n);
unsigned long strlen(const char *s);
char *strcpy(char *to, const char *from);
char *strncpy(char *to, const char *from, unsigned long n);
char *strcat(char *to, const char *from);
char *strncat(char *to, const char *from, unsigned long n);
int strcmp(const char *a, const char *b);
int strncmp(const char *a, const char *b, unsigned long n);
char *strchr(const char *s, long c);
char *strrchr(const char *s, long c);
char *strstr(const char *s, const char *part);
char *strtok(char *s, const char *separators);
char *strerror(long number);

#endif
