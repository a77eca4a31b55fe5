/* SerialB: the course's Simulink link (docs/framework.md section 8; the bytes in docs/host-tools.md,
 * "SerialB: the Simulink packets"), as Gen A's simulink_serialRX and Gen B's RXBINT_recv_ready
 * handle it (the same logic).
 *
 * Every 5 ms the model sends 16 bytes: FF 7F, then seven int16 values, little endian. The board
 * answers at once on the 7F, before the data bytes arrive, with Simulink_PlotVar1..4 as
 * int32(10000 * value), little endian, no header; then stores the seven values into
 * SIMU_Var1..7_fromSIMU_16bit. Sync: outside a packet, a byte taken while the flag is 1 clears it
 * if it is FF; while it is 0, the next byte sets it back to 1 and starts a packet if it is 7F (so
 * right after reset the very first byte is tested for 7F alone). Data bytes are never inspected. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "framework_facts.h"
#include "host_reply.h"
#include "simulink_link.h"

_Static_assert((int)CRS_SIMULINK_BUFFER >= 2 * (int)CRS_SIMULINK_INPUTS, "the receiver keeps a packet's data");

int32_t crs_simulink_scaled(float value)
{
    const float scaled = (float)CRS_SIMULINK_SCALE * value; /* single precision, as on the DSP */
    if (isnan(scaled)) return 0;
    if (scaled >= 2147483648.0f) return INT32_MAX;
    if (scaled <= -2147483648.0f) return INT32_MIN;
    return (int32_t)scaled; /* truncates toward zero */
}

static float plot_var(const float *v) { return v != NULL ? *v : 0.0f; }

static void reply(crs_board *board, int64_t now)
{
    char out[4 * CRS_SIMULINK_PLOTS];
    for (int i = 0; i < CRS_SIMULINK_PLOTS; ++i) {
        const uint32_t v = (uint32_t)crs_simulink_scaled(plot_var(board->fw.plot[i]));
        for (int b = 0; b < 4; ++b) out[4 * i + b] = (char)(v >> (8 * b));
    }
    crs_host_reply(board, CRS_HOST_PORT_B, now, out, sizeof out);
}

static void store(crs_board *board, const crs_simulink_rx *rx)
{
    for (int i = 0; i < CRS_SIMULINK_INPUTS; ++i) {
        /* the C28x's int is 16 bits */
        int32_t *input = board->fw.simulink_input[i];
        if (input != NULL) *input = (int16_t)(uint16_t)(rx->data[2 * i] | rx->data[2 * i + 1] << 8);
    }
}

void crs_simulink_receive(crs_board *board, int64_t now, uint8_t byte)
{
    crs_simulink_rx *rx = &board->simulink;
    if (rx->receiving) {
        rx->data[rx->count++] = byte;
        if (rx->count == 2 * CRS_SIMULINK_INPUTS) {
            store(board, rx);
            rx->receiving = 0;
        }
        return;
    }
    if (rx->check_first) {
        if (byte == CRS_SIMULINK_SYNC_1) rx->check_first = 0;
        return;
    }
    rx->check_first = 1;
    if (byte == CRS_SIMULINK_SYNC_2) {
        rx->receiving = 1;
        rx->count = 0;
        reply(board, now);
    }
}
