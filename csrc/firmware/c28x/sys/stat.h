/* The C library's <sys/stat.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here), laid out as the C library's (wasm32). The board refuses to
 * look anything up. */
#ifndef CRSLAB_C28X_SYS_STAT_H
#define CRSLAB_C28X_SYS_STAT_H
#include <time.h>
struct stat {
    unsigned long long st_dev, st_ino;
    unsigned long st_nlink, st_mode, st_uid, st_gid, crs_pad0, crs_pad1;
    unsigned long long st_rdev;
    long long st_size;
    long st_blksize, crs_pad2;
    long long st_blocks;
    struct timespec st_atim, st_mtim, st_ctim;
    long long crs_reserved[3];
};
#define S_IFMT 0xf000
#define S_IFSOCK 0xc000
#define S_IFREG 0x8000
#define S_IFDIR 0x4000
#define S_ISSOCK(m) (((m) & S_IFMT) == S_IFSOCK)
#define S_ISREG(m) (((m) & S_IFMT) == S_IFREG)
#define S_ISDIR(m) (((m) & S_IFMT) == S_IFDIR)
int stat(const char *path, struct stat *info);
int fstat(long fd, struct stat *info);
#endif
