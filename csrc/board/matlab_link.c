/* SerialC: the course's MATLAB variable protocol (docs/framework.md section 8; the bytes in
 * docs/host-tools.md, "SerialC: a MATLAB message"), as the framework receives and answers it:
 * Gen A's matlab_serialRX and matlab_serialSWI, Gen B's RXCINT_recv_ready and the idle loop's
 * command code.
 *
 * A message is '*', a length byte L that counts the whole message, and L - 2 payload bytes, the
 * command first; no checksum and no timeout. Commands (addresses are 16-bit-word addresses, big
 * endian, low 22 bits used; values IEEE single):
 *   '2' read N floats from addr, addr + 2, ...: reply '*', (3 + N) & 0xFF, '3', N values little endian
 *   '3' write k (address, value) pairs, value little endian: no reply
 *   '1' (CRS_MATLAB_BIG_ENDIAN_WRITE: Gen A) the same with the value big endian
 *   '0' (CRS_MATLAB_ECHO: Gen A) echo: each address's 32 bits are sampled as its last byte arrives;
 *       reply '*', (3 + 8m) & 0xFF, '0', then each address and value, both big endian
 * A generation without them (Gen B) parses and samples '0' too but answers neither '0' nor '1'.
 * An unknown command is ignored. With CRS_MATLAB_LOCK (Gen A) every read also sets the
 * framework's matlabLock (a float in .my_vars) to 1. Which bits a generation has is its row's
 * `matlab` (generations.c). */
#include <stddef.h>
#include <stdint.h>

#include "c28x_memory.h"
#include "framework_facts.h"
#include "generations.h"
#include "host_reply.h"
#include "matlab_link.h"
#include "serial_line.h"

enum { ADDRESS_MASK = 0x3FFFFF, MAX_PAIRS = (CRS_MATLAB_MESSAGE_CHARS - 1) / 8 };

_Static_assert((int)CRS_MATLAB_BUFFER >= (int)CRS_MATLAB_MESSAGE_CHARS, "the receiver keeps UARTMessageArray");
_Static_assert((int)CRS_MATLAB_ECHO_BUFFER >= ((int)CRS_MATLAB_MESSAGE_CHARS - 1) / 4, "every echo address fits");

static uint32_t big_endian32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

static uint32_t little_endian32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void put_big_endian32(char *out, uint32_t v)
{
    for (int i = 0; i < 4; ++i) out[i] = (char)(v >> (24 - 8 * i));
}

/* '2': the floats at address, address + 2, ... read now, little endian after a 3-byte header. The
 * board sends the header, then each float, into the transmit ring, which keeps what fits (the
 * line drains far slower than the board queues, so once a float does not fit whole, nothing after
 * it does). */
static void read_floats(crs_board *board, int64_t now, const uint8_t *m, int32_t matlab)
{
    const uint32_t address = big_endian32(m + 1) & ADDRESS_MASK;
    const uint32_t floats = (uint32_t)m[5] << 8 | m[6];
    /* the framework variable in .my_vars (csrc/firmware/firmware.c) */
    if ((matlab & CRS_MATLAB_LOCK) && board->fw.matlab_lock != NULL) *board->fw.matlab_lock = 1.0f;
    crs_host_port *hp = &board->shared->host_ports[CRS_HOST_PORT_C];
    const char header[3] = {(char)CRS_MATLAB_START, (char)((3 + floats) & 0xFF), '3'};
    crs_host_reply(board, CRS_HOST_PORT_C, now, header, sizeof header);
    for (uint32_t i = 0; i < floats; ++i) {
        const uint32_t v = crs_mem_read32(&board->memory, (address + 2 * i) & ADDRESS_MASK);
        const char bytes[4] = {(char)v, (char)(v >> 8), (char)(v >> 16), (char)(v >> 24)};
        const int64_t dropped_before = hp->tx_dropped;
        crs_host_reply(board, CRS_HOST_PORT_C, now, bytes, sizeof bytes);
        if (hp->tx_dropped != dropped_before) { /* the ring is full: the rest is dropped too */
            hp->tx_dropped += 4 * (int64_t)(floats - i - 1);
            break;
        }
    }
}

/* '3' / '1': k = (L - 3) / 8 raw 32-bit stores (C division: a short message writes none). */
static void write_values(crs_board *board, const uint8_t *m, int32_t length_byte, int big_endian)
{
    int32_t pairs = (length_byte - 3) / 8;
    if (pairs > MAX_PAIRS) pairs = MAX_PAIRS; /* the board would read past UARTMessageArray */
    for (int32_t k = 0; k < pairs; ++k) {
        const uint8_t *p = m + 1 + 8 * k;
        const uint32_t value = big_endian ? big_endian32(p + 4) : little_endian32(p + 4);
        crs_mem_write32(&board->memory, big_endian32(p) & ADDRESS_MASK, value);
    }
}

/* '0': every sampled address and its value, both big endian. */
static void echo(crs_board *board, int64_t now)
{
    const crs_matlab_rx *rx = &board->matlab;
    char reply[3 + 8 * CRS_MATLAB_ECHO_BUFFER];
    reply[0] = (char)CRS_MATLAB_START;
    reply[1] = (char)((3 + 8 * rx->echo_count) & 0xFF);
    reply[2] = '0';
    uint32_t n = 3;
    for (uint32_t i = 0; i < rx->echo_count; ++i) {
        put_big_endian32(reply + n, rx->echo_address[i]);
        put_big_endian32(reply + n + 4, rx->echo_value[i]);
        n += 8;
    }
    crs_host_reply(board, CRS_HOST_PORT_C, now, reply, n);
}

static void dispatch(crs_board *board, int64_t now)
{
    const crs_matlab_rx *rx = &board->matlab;
    const int32_t matlab = board->config.gen->matlab; /* looked up when loaded */
    const uint8_t *m = rx->message; /* a 2-byte message finds the last one's payload still here */
    switch (m[0]) {
    case '2':
        read_floats(board, now, m, matlab);
        break;
    case '3':
        write_values(board, m, rx->length + 1, 0);
        break;
    case '1':
        if (matlab & CRS_MATLAB_BIG_ENDIAN_WRITE) write_values(board, m, rx->length + 1, 1);
        break;
    case '0':
        if (matlab & CRS_MATLAB_ECHO) echo(board, now);
        break;
    default: /* no such command: no reply */
        break;
    }
}

void crs_matlab_receive(crs_board *board, int64_t now, uint8_t byte)
{
    crs_matlab_rx *rx = &board->matlab;
    if (rx->wedged) return; /* the count can never match again: only a reset helps */
    if (!rx->receiving) {
        if (byte == CRS_MATLAB_START) {
            rx->receiving = 1;
            rx->count = 0;
            rx->echo_count = 0;
        }
        return;
    }
    if (rx->count == 0) { /* the length byte */
        rx->length = (int32_t)byte - 1;
        rx->count = 1;
        if (rx->length <= 0) {
            rx->wedged = 1;
            crs_host_port *hp = &board->shared->host_ports[CRS_HOST_PORT_C];
            hp->wedged = 1;
            hp->wedged_tick = crs_line_tick(now);
            return;
        }
    } else {
        const int32_t index = rx->count - 1;
        if (index < CRS_MATLAB_MESSAGE_CHARS) { /* past it the board overwrites other memory */
            rx->message[index] = byte;
            /* '0': an address is sampled as its fourth byte arrives */
            if (rx->message[0] == '0' && index >= 4 && index % 4 == 0
                && rx->echo_count < CRS_MATLAB_ECHO_BUFFER) {
                const uint32_t address = big_endian32(rx->message + index - 3);
                rx->echo_address[rx->echo_count] = address;
                rx->echo_value[rx->echo_count] = crs_mem_read32(&board->memory, address & ADDRESS_MASK);
                rx->echo_count++;
            }
        }
        rx->count++;
    }
    if (rx->count == rx->length) {
        rx->receiving = 0;
        dispatch(board, now);
    }
}
