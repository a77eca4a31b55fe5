/* The host ports' lines: the host's bytes in, the board's replies out (host_ports.h). */
#include "host_ports.h"

#include <string.h>

#include "framework_facts.h"
#include "host_reply.h"
#include "matlab_link.h"
#include "serial_line.h"
#include "simulink_link.h"

/* Move what has left port's transmit line by line time `until` to out[]. */
static void send_until(crs_host_port *hp, int64_t until)
{
    char bytes[CRS_LINE_MAX_CHARS_PER_TICK];
    uint32_t n;
    while ((n = crs_line_take_until(&hp->tx, until, bytes, sizeof bytes)) > 0) {
        uint64_t len = hp->out_len;
        if (len > CRS_HOST_OUT_CAPACITY) len = CRS_HOST_OUT_CAPACITY;
        if (len + n > CRS_HOST_OUT_CAPACITY) {
            hp->out_dropped += n;
        } else {
            memcpy(hp->out + len, bytes, n);
            hp->out_len = len + n;
        }
    }
}

static void port_tick(crs_board *board, int port, int64_t tick)
{
    crs_host_port *hp = &board->shared->host_ports[port];
    uint32_t inbox = hp->inbox_len; /* the reader wrote it: clamp to the block */
    if (inbox > CRS_HOST_INBOX_CAPACITY) inbox = CRS_HOST_INBOX_CAPACITY;
    if (inbox == 0 && hp->rx.len == 0 && hp->tx.len == 0) return;
    if (inbox > 0) { /* onto the receive line from this tick on; what it cannot hold waits */
        const uint32_t taken = crs_line_queue(&hp->rx, CRS_LINE_QUEUE_CAPACITY, tick, hp->inbox, inbox);
        memmove(hp->inbox, hp->inbox + taken, inbox - taken);
        hp->inbox_len = inbox - taken;
    }
    /* each byte that arrives during this tick, when it arrives: what left the transmit line
     * before it first, so a reply it starts follows the line as it is then */
    const int64_t per_char = crs_line_units_per_char();
    const int64_t first_arrival = hp->rx.head_done;
    char bytes[CRS_LINE_MAX_CHARS_PER_TICK];
    const uint32_t n = crs_line_take(&hp->rx, tick, bytes);
    for (uint32_t i = 0; i < n; ++i) {
        const int64_t now = first_arrival + (int64_t)i * per_char;
        send_until(hp, now);
        if (port == CRS_HOST_PORT_B) {
            crs_simulink_receive(board, now, (uint8_t)bytes[i]);
        } else {
            crs_matlab_receive(board, now, (uint8_t)bytes[i]);
        }
    }
    send_until(hp, (tick + 1) * crs_line_units_per_tick());
}

void crs_host_ports_tick(crs_board *board, int64_t tick)
{
    port_tick(board, CRS_HOST_PORT_B, tick);
    port_tick(board, CRS_HOST_PORT_C, tick);
}

int crs_host_ports_full(const crs_shared *sh)
{
    for (int p = 0; p < CRS_HOST_PORTS; ++p) {
        if (sh->host_ports[p].out_len > CRS_HOST_OUT_CAPACITY / 2) return 1;
    }
    return 0;
}
