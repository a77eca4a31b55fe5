/* The C library's <ctype.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here): a character goes to the C library as the 32-bit int it takes. */
#ifndef CRSLAB_C28X_CTYPE_H
#define CRSLAB_C28X_CTYPE_H
int isalnum(long c);
int isalpha(long c);
int isdigit(long c);
int isspace(long c);
int isupper(long c);
int islower(long c);
int isprint(long c);
int ispunct(long c);
int isxdigit(long c);
int toupper(long c);
int tolower(long c);
#endif
