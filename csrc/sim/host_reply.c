/* The board's replies on the host ports: queued into a port's transmit ring (host_reply.h). */
#include "host_reply.h"

#include "framework_facts.h"
#include "serial_line.h"

/* The transmit ring of a host port in this generation. */
static uint32_t tx_ring(const crs_sim *sim, int port)
{
    if (sim->generation == CRS_GEN_B) {
        return port == CRS_HOST_PORT_B ? CRS_GEN_B_SCIB_TX_RING : CRS_GEN_B_SCIC_TX_RING;
    }
    return port == CRS_HOST_PORT_B ? CRS_GEN_A_SCIB_TX_RING : CRS_GEN_A_SCIC_TX_RING;
}

void crs_host_reply(crs_sim *sim, int port, int64_t now, const char *data, uint32_t n)
{
    crs_host_port *hp = &sim->shared->host_ports[port];
    const uint32_t taken = crs_line_queue_at(&hp->tx, tx_ring(sim, port), now, data, n);
    if (taken < n) {
        if (hp->tx_dropped == 0) hp->tx_first_drop_tick = crs_line_tick(now);
        hp->tx_dropped += (int64_t)(n - taken);
    }
}
