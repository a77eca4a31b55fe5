/* The serial lines: ring + FIFO + shift register, drained at the baud rate. */
#include "serial_line.h"

#include "framework_facts.h"

int64_t crs_line_units_per_tick(void) { return CRS_SERIAL_BAUD; }

int64_t crs_line_units_per_char(void) { return (int64_t)CRS_TICKS_PER_S * CRS_SERIAL_BITS_PER_CHAR; }

int64_t crs_line_tick(int64_t t) { return (t - 1) / crs_line_units_per_tick(); }

uint32_t crs_line_queue(crs_serial_line *line, uint32_t ring_chars, int64_t tick, const char *data,
                        uint32_t n)
{
    return crs_line_queue_at(line, ring_chars, tick * crs_line_units_per_tick(), data, n);
}

uint32_t crs_line_queue_at(crs_serial_line *line, uint32_t ring_chars, int64_t start, const char *data,
                           uint32_t n)
{
    /* the FIFO and the shift register are full before the ring holds anything */
    const uint32_t outside_ring = CRS_SCI_TX_FIFO + CRS_SCI_TX_SHIFT;
    const uint32_t in_ring = line->len > outside_ring ? line->len - outside_ring : 0;
    uint32_t take = in_ring < ring_chars ? ring_chars - in_ring : 0;
    if (take > n) take = n;
    if (take > CRS_LINE_QUEUE_CAPACITY - line->len) take = CRS_LINE_QUEUE_CAPACITY - line->len;
    if (take == 0) return 0;
    if (line->len == 0) {
        line->first = 0;
        line->head_done = start + crs_line_units_per_char();
    }
    for (uint32_t i = 0; i < take; ++i) {
        line->queue[(line->first + line->len + i) % CRS_LINE_QUEUE_CAPACITY] = data[i];
    }
    line->len += take;
    return take;
}

uint32_t crs_line_take(crs_serial_line *line, int64_t tick, char *dst)
{
    return crs_line_take_until(line, (tick + 1) * crs_line_units_per_tick(), dst, CRS_LINE_MAX_CHARS_PER_TICK);
}

uint32_t crs_line_take_until(crs_serial_line *line, int64_t until, char *dst, uint32_t room)
{
    if (line->len == 0 || line->head_done > until) return 0;
    const int64_t per_char = crs_line_units_per_char();
    int64_t count = (until - line->head_done) / per_char + 1;
    if (count > line->len) count = line->len;
    if (count > room) count = room;
    const uint32_t m = (uint32_t)count;
    for (uint32_t i = 0; i < m; ++i) dst[i] = line->queue[(line->first + i) % CRS_LINE_QUEUE_CAPACITY];
    line->first = (line->first + m) % CRS_LINE_QUEUE_CAPACITY;
    line->len -= m;
    line->head_done += (int64_t)m * per_char;
    return m;
}

void crs_line_send(crs_shared *sh, int64_t tick)
{
    char sent[CRS_LINE_MAX_CHARS_PER_TICK];
    const uint32_t m = crs_line_take(&sh->line, tick, sent);
    if (m == 0) return;
    if (sh->serial_len + m > CRS_SERIAL_CAPACITY || sh->mark_count >= CRS_MARK_CAPACITY) {
        sh->serial_dropped += m;
        return;
    }
    sh->mark_tick[sh->mark_count] = tick;
    sh->mark_offset[sh->mark_count] = sh->serial_len;
    sh->mark_count++;
    for (uint32_t i = 0; i < m; ++i) sh->serial[sh->serial_len + i] = sent[i];
    sh->serial_len += m;
}
