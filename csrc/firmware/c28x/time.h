/* The C library's <time.h> as a lab sees it in crslab's WebAssembly firmware (compiled with the
 * C28x's widths: see math.h here). The board has no clock a lab may read: it refuses each. */
#ifndef CRSLAB_C28X_TIME_H
#define CRSLAB_C28X_TIME_H
#include <stddef.h>
typedef long long time_t;
typedef long clock_t;
struct timespec {
    time_t tv_sec;
    long tv_nsec;
    long crs_pad; /* the C library's layout (wasm32) */
};
#define CLOCKS_PER_SEC 1000000L
#define CLOCK_REALTIME 0
#define CLOCK_MONOTONIC 1
time_t time(time_t *now);
clock_t clock(void);
int clock_gettime(long clock, struct timespec *now);
#endif
