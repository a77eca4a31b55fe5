/* The page's rows of a chunk in crslab serve, packed straight from the shared block's scope log
 * (crslab/sinks/page_stream.py writes the same bytes from the rows as numpy arrays: the page's
 * script reads both alike). The run host calls it once per chunk: it takes the place of copying
 * the log's columns, picking the rows, converting them and base64, some hundred microseconds of
 * Python a chunk. */
#ifndef CRSLAB_PAGE_ROWS_H
#define CRSLAB_PAGE_ROWS_H

#include <stdint.h>

#include "board.h"

/* Where a world row's columns the page shows start (world_facts.py's WORLD_COLUMNS, one value each). */
typedef struct {
    int32_t egg_force;
    int32_t scale_g;
    int32_t egg_broken;
} crs_page_world;

/* What crs_page_rows says besides its bytes. */
typedef struct {
    int64_t frame;        /* in: the 1/60 s frame of simulated time of the last frame sent (-1:
                             none); out: that of this chunk's last row */
    int64_t rows;         /* the scope rows written (0: none, and nothing was written) */
    double qpos_dh_rad[3]; /* the last row's DH angles (when rows > 0) */
    int32_t egg_broken;   /* the last row's egg is broken (a world with fixtures) */
} crs_page_state;

/* Write the chunk message's fields `, "frames": {...}, "scope": {...}` of the first `n` rows of
 * `log` (those of ticks divisible by `every`) into `out`: the frames are the rows that start a
 * 1/60 s frame of simulated time (after `state->frame`) and the last, each `tick, th1..3, theta1..3
 * motor, safety, motor board off` and with `world` (non-NULL: a world with fixtures) the egg's force,
 * the scale's grams and the egg broken, as little-endian float64; the scope rows are
 * Simulink_PlotVar1..4, theta1..3motor, tau1..3, tau1..3 applied and with `world` the scale's grams,
 * as little-endian float32; both base64. Returns the bytes written (0 when no row is of a tick
 * divisible by `every`), or -1 when `capacity` is too small. */
int64_t crs_page_rows(const crs_scope_log *log, int64_t n, int64_t every, const crs_page_world *world,
                      crs_page_state *state, char *out, int64_t capacity);
/* The capacity crs_page_rows needs at most for `n` rows. */
int64_t crs_page_rows_capacity(int64_t n);

#endif
