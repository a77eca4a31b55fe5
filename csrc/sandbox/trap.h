/* The sandboxed worker's SIGSYS handler (see trap.c). Read by cffi (ABI mode) together with
 * csrc/board/board.h: plain declarations only. */
#ifndef CRSLAB_TRAP_H
#define CRSLAB_TRAP_H

#include <stdint.h>

#include "board.h"

enum {
    CRS_TRAP_SYSCALLS = 1024, /* path_arg[] covers system calls 0 .. 1023 */
    CRS_TRAP_EXIT = 121       /* the worker's exit status after a refused call */
};

/* Install the SIGSYS handler (on its own stack). A refused call is recorded in
 * shared->refusal; path_arg[nr] says which argument of call nr is a path to copy into the
 * record (-1: none). While loading is on, an open of exactly lab_path for reading is answered
 * with a fresh duplicate of lab_fd. report_fd >= 0 is a sanitizer's report file: once it is
 * not empty (the sanitizer is reporting), opens for reading are carried out (Landlock decides
 * what they may read) instead of refused. Returns 0, or -errno. */
int crs_trap_arm(crs_shared *shared, const char *lab_path, int32_t lab_fd, const int8_t *path_arg,
                 int32_t report_fd);
/* Turn the answer to opens of lab_path on (1) while the loader maps it, and off (0) after. */
void crs_trap_loading(int32_t on);

#endif
