/* The C library's <unistd.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here): a descriptor or a count goes to the C library as the 32-bit
 * number it takes. The board has no file, pipe or process a lab may reach: it refuses each. */
#ifndef CRSLAB_C28X_UNISTD_H
#define CRSLAB_C28X_UNISTD_H
#include <stddef.h>
long read(long fd, void *out, unsigned long n);
long write(long fd, const void *from, unsigned long n);
int close(long fd);
long lseek(long fd, long long offset, long whence);
int unlink(const char *path);
int access(const char *path, long mode);
int usleep(unsigned long microseconds);
unsigned int sleep(unsigned long seconds);
extern char **environ;
#endif
