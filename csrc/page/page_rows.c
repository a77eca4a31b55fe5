/* See page_rows.h. */
#include "page_rows.h"

#include <stdio.h>
#include <string.h>

enum { FRAME_HZ = 60, FRAME_COLUMNS = 9, WORLD_FRAME_COLUMNS = 3, SCOPE_COLUMNS = 13 };

static const char BASE64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/* Standard base64 with padding (Python's base64.b64encode) of `n` bytes at `in` into `out`;
 * returns the characters written. */
static int64_t base64(const unsigned char *in, int64_t n, char *out) {
    char *o = out;
    int64_t i = 0;
    for (; i + 2 < n; i += 3) {
        uint32_t v = (uint32_t)in[i] << 16 | (uint32_t)in[i + 1] << 8 | in[i + 2];
        *o++ = BASE64[v >> 18];
        *o++ = BASE64[(v >> 12) & 63];
        *o++ = BASE64[(v >> 6) & 63];
        *o++ = BASE64[v & 63];
    }
    if (i < n) {
        uint32_t v = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0);
        *o++ = BASE64[v >> 18];
        *o++ = BASE64[(v >> 12) & 63];
        *o++ = i + 1 < n ? BASE64[(v >> 6) & 63] : '=';
        *o++ = '=';
    }
    return o - out;
}

/* The `n` bytes of the value at `v`, little-endian (the page's DataView reads them so). */
static unsigned char *put_le(unsigned char *p, const void *v, int n) {
    const unsigned char *b = (const unsigned char *)v;
    for (int k = 0; k < n; k++) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
        p[k] = b[n - 1 - k];
#else
        p[k] = b[k];
#endif
    }
    return p + n;
}

static unsigned char *put_f8(unsigned char *p, double v) { return put_le(p, &v, 8); }

static unsigned char *put_f4(unsigned char *p, float v) { return put_le(p, &v, 4); }

static int64_t frame_of(int64_t tick) {
    /* numpy's floor division, for any tick */
    int64_t t = tick * FRAME_HZ, q = t / 1000;
    return (t % 1000 != 0 && t < 0) ? q - 1 : q;
}

int64_t crs_page_rows_capacity(int64_t n) {
    int64_t row_bytes = 8 * (FRAME_COLUMNS + WORLD_FRAME_COLUMNS) + 4 * (SCOPE_COLUMNS + 1);
    return 256 + 2 * (n * row_bytes * 4 / 3 + 4);
}

int64_t crs_page_rows(const crs_scope_log *log, int64_t n, int64_t every, const crs_page_world *world,
                      crs_page_state *state, char *out, int64_t capacity) {
    state->rows = 0;
    if (n < 0) n = 0;
    if (n > CRS_LOG_CAPACITY) n = CRS_LOG_CAPACITY;
    if (capacity < crs_page_rows_capacity(n)) return -1;
    /* the rows of ticks divisible by `every`, in order (all of them when the board logged only those) */
    int64_t kept = 0, first = -1, last = -1;
    for (int64_t i = 0; i < n; i++) {
        if (every <= 0 || log->tick[i] % every == 0) {
            if (first < 0) first = i;
            last = i;
            kept++;
        }
    }
    if (!kept) return 0;
    /* the packed bytes go at the end of `out`, the text at its start: the text never reaches them */
    const int64_t frame_columns = FRAME_COLUMNS + (world ? WORLD_FRAME_COLUMNS : 0);
    const int64_t scope_columns = SCOPE_COLUMNS + (world ? 1 : 0);
    unsigned char *raw = (unsigned char *)out + capacity - kept * (8 * frame_columns + 4 * scope_columns);
    unsigned char *frames = raw, *p = raw;
    int64_t frame_rows = 0, prev = state->frame;
    for (int64_t i = first; i <= last; i++) {
        if (every > 0 && log->tick[i] % every != 0) continue;
        int64_t frame = frame_of(log->tick[i]);
        int keep = frame != prev || i == last;
        prev = frame;
        if (!keep) continue;
        p = put_f8(p, (double)log->tick[i]);
        for (int k = 0; k < 3; k++) p = put_f8(p, log->qpos_dh_rad[3 * i + k]);
        for (int k = 0; k < 3; k++) p = put_f8(p, log->enc_rad[3 * i + k]);
        p = put_f8(p, (double)log->safety[i]);
        p = put_f8(p, (double)log->motor_board_off[i]);
        if (world) {
            const double *row = &log->world[CRS_WORLD_ROW * i];
            p = put_f8(p, row[world->egg_force]);
            p = put_f8(p, row[world->scale_g]);
            p = put_f8(p, row[world->egg_broken]);
        }
        frame_rows++;
    }
    state->frame = prev;
    unsigned char *scope = p;
    for (int64_t i = first; i <= last; i++) {
        if (every > 0 && log->tick[i] % every != 0) continue;
        for (int k = 0; k < 4; k++) p = put_f4(p, (float)log->plot[4 * i + k]);
        for (int k = 0; k < 3; k++) p = put_f4(p, (float)log->enc_rad[3 * i + k]);
        for (int k = 0; k < 3; k++) p = put_f4(p, (float)log->tau_lab[3 * i + k]);
        for (int k = 0; k < 3; k++) p = put_f4(p, (float)log->tau_applied[3 * i + k]);
        if (world) p = put_f4(p, (float)log->world[CRS_WORLD_ROW * i + world->scale_g]);
    }
    char *o = out;
    o += sprintf(o, ", \"frames\": {\"columns\": %d, \"rows\": %lld, \"data\": \"", (int)frame_columns,
                 (long long)frame_rows);
    o += base64(frames, scope - frames, o);
    o += sprintf(o, "\"}, \"scope\": {\"tick0\": %lld, \"every\": %lld, \"rows\": %lld, \"columns\": %d, \"data\": \"",
                 (long long)log->tick[first], (long long)every, (long long)kept, (int)scope_columns);
    o += base64(scope, p - scope, o);
    *o++ = '"';
    *o++ = '}';
    for (int k = 0; k < 3; k++) state->qpos_dh_rad[k] = log->qpos_dh_rad[3 * last + k];
    state->egg_broken = world ? log->world[CRS_WORLD_ROW * last + world->egg_broken] > 0 : 0;
    state->rows = kept;
    return o - out;
}
