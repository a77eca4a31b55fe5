/* The board's hardware as the firmware sees it: the serial port's transmit ring and line behind
 * serial_printf, the GPIO registers, the clock. */
#define _POSIX_C_SOURCE 199309L

#include "board_io.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "firmware_port.h"
#include "generations.h"
#include "serial_line.h"

int64_t crs_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

int crs_board_check_generation(crs_board *board)
{
    const crs_generation *gen = crs_generation_of(board->config.generation);
    const char *problem = crs_generation_problem(gen);
    if (problem == NULL) {
        board->config.gen = gen; /* the row every serial_printf and host reply reads */
        return 0;
    }
    crs_fw_trap *t = &board->trap;
    t->kind = CRS_FW_TRAP_LOAD;
    t->phase = CRS_PHASE_LOADING;
    t->tick = board->tick;
    if (gen != NULL) {
        snprintf(t->text, sizeof t->text, "framework generation %s cannot run: %s", gen->name, problem);
        return CRS_RUN_TRAPPED;
    }
    int n = snprintf(t->text, sizeof t->text, "the board knows no framework generation %d (it knows",
                     (int)board->config.generation);
    for (int32_t i = 0; i < crs_generation_count() && n > 0 && (size_t)n < sizeof t->text; ++i) {
        const crs_generation *g = crs_generation_at(i);
        n += snprintf(t->text + n, sizeof t->text - (size_t)n, "%s %s (%d)", i == 0 ? "" : ",", g->name,
                      (int)g->id);
    }
    if (n > 0 && (size_t)n < sizeof t->text) snprintf(t->text + n, sizeof t->text - (size_t)n, ")");
    return CRS_RUN_TRAPPED;
}

void crs_board_lab_cost(crs_board *board, int64_t cost)
{
    board->lab_cost_total += cost;
    if (cost > board->lab_cost_max) {
        board->lab_cost_max = cost;
        board->lab_max_tick = board->tick;
    }
    if (cost > board->config.budget) {
        const int64_t kept = (int64_t)(sizeof board->first_over_tick / sizeof board->first_over_tick[0]);
        if (board->over_budget < kept) board->first_over_tick[board->over_budget] = board->tick;
        board->over_budget++;
    }
}

int32_t crs_board_serial_out(crs_board *board, const char *chars, uint32_t available, uint32_t formatted)
{
    if (board == NULL || board->shared == NULL || board->overflow_tick >= 0) return 0;
    const crs_generation *gen = board->config.gen; /* looked up when loaded */
    const uint32_t buffer = (uint32_t)gen->printf_buffer_chars;
    crs_shared *sh = board->shared;
    if (formatted >= buffer) {
        /* the characters and the terminating NUL overrun the board's buffer: memory is corrupt */
        board->overflow_tick = board->tick;
        board->overflow_chars = formatted;
        board->overflow_phase = sh->phase;
        return 0;
    }
    const uint32_t n = formatted <= available ? formatted : available;
    const uint32_t ring = (uint32_t)gen->tx_ring_chars;
    const uint32_t taken = crs_line_queue(&sh->line, ring, board->tick, chars, n);
    if (taken > 0 && sh->print_count < CRS_PRINT_CAPACITY) {
        /* a print mark: this call's tick and how many of its characters are on the line */
        sh->print_tick[sh->print_count] = board->tick;
        sh->print_chars[sh->print_count] = taken;
        sh->print_count++;
    }
    if (taken < n) {
        if (board->tx_first_drop_tick < 0) board->tx_first_drop_tick = board->tick;
        board->tx_dropped += (int64_t)(n - taken);
    }
    return (int32_t)taken;
}

enum { GPBDAT = 4, GPBSET = 5, GPBCLEAR = 6, GPBTOGGLE = 7 };

uint32_t crs_board_update_gpio(crs_board *board)
{
    uint32_t *r = board->fw.gpio;
    if (r == NULL) return board->leds;
    uint32_t dat = r[GPBDAT];
    dat ^= r[GPBTOGGLE];
    dat |= r[GPBSET];
    dat &= ~r[GPBCLEAR];
    r[GPBDAT] = dat;
    r[GPBTOGGLE] = 0;
    r[GPBSET] = 0;
    r[GPBCLEAR] = 0;
    return ((dat >> 2) & 1u) | (((dat >> 28) & 1u) << 1); /* GPIO34, GPIO60 */
}
