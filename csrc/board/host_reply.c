/* The board's replies on the host ports: queued into a port's transmit ring (host_reply.h). */
#include "host_reply.h"

#include "generations.h"
#include "serial_line.h"

/* The transmit ring of a host port in this generation. */
static uint32_t tx_ring(const crs_board *board, int port)
{
    const crs_generation *gen = board->config.gen; /* looked up when loaded */
    return (uint32_t)(port == CRS_HOST_PORT_B ? gen->scib_tx_ring_chars : gen->scic_tx_ring_chars);
}

void crs_host_reply(crs_board *board, int port, int64_t now, const char *data, uint32_t n)
{
    crs_host_port *hp = &board->shared->host_ports[port];
    const uint32_t taken = crs_line_queue_at(&hp->tx, tx_ring(board, port), now, data, n);
    if (taken < n) {
        if (hp->tx_dropped == 0) hp->tx_first_drop_tick = crs_line_tick(now);
        hp->tx_dropped += (int64_t)(n - taken);
    }
}
