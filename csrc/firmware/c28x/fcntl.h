/* The C library's <fcntl.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here): the flags are the C library's (WASI's), 32-bit numbers. The board
 * refuses to open anything. */
#ifndef CRSLAB_C28X_FCNTL_H
#define CRSLAB_C28X_FCNTL_H
#define O_APPEND 0x0001L
#define O_CREAT (0x0001L << 12)
#define O_EXCL (0x0004L << 12)
#define O_TRUNC (0x0008L << 12)
#define O_RDONLY 0x04000000L
#define O_WRONLY 0x10000000L
#define O_RDWR (O_RDONLY | O_WRONLY)
int open(const char *path, long flags, ...);
#endif
