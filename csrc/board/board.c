/* The board's hardware as the firmware sees it: the serial port's transmit ring and line behind
 * serial_printf, the GPIO registers, the clock. */
#define _POSIX_C_SOURCE 199309L

#include "board.h"

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

int crs_board_check_generation(crs_sim *sim)
{
    const crs_generation *gen = crs_generation_of(sim->generation);
    const char *problem = crs_generation_problem(gen);
    if (problem == NULL) {
        sim->gen = gen; /* the row every serial_printf and host reply reads */
        return 0;
    }
    crs_fw_trap *t = &sim->trap;
    t->kind = CRS_FW_TRAP_LOAD;
    t->phase = CRS_PHASE_LOADING;
    t->tick = sim->tick;
    if (gen != NULL) {
        snprintf(t->text, sizeof t->text, "framework generation %s cannot run: %s", gen->name, problem);
        return CRS_RUN_TRAPPED;
    }
    int n = snprintf(t->text, sizeof t->text, "the board knows no framework generation %d (it knows",
                     (int)sim->generation);
    for (int32_t i = 0; i < crs_generation_count() && n > 0 && (size_t)n < sizeof t->text; ++i) {
        const crs_generation *g = crs_generation_at(i);
        n += snprintf(t->text + n, sizeof t->text - (size_t)n, "%s %s (%d)", i == 0 ? "" : ",", g->name,
                      (int)g->id);
    }
    if (n > 0 && (size_t)n < sizeof t->text) snprintf(t->text + n, sizeof t->text - (size_t)n, ")");
    return CRS_RUN_TRAPPED;
}

void crs_board_lab_cost(crs_sim *sim, int64_t cost)
{
    sim->lab_cost_total += cost;
    if (cost > sim->lab_cost_max) {
        sim->lab_cost_max = cost;
        sim->lab_max_tick = sim->tick;
    }
    if (cost > sim->budget) {
        const int64_t kept = (int64_t)(sizeof sim->first_over_tick / sizeof sim->first_over_tick[0]);
        if (sim->over_budget < kept) sim->first_over_tick[sim->over_budget] = sim->tick;
        sim->over_budget++;
    }
}

int32_t crs_board_serial_out(crs_sim *sim, const char *chars, uint32_t available, uint32_t formatted)
{
    if (sim == NULL || sim->shared == NULL || sim->overflow_tick >= 0) return 0;
    const crs_generation *gen = sim->gen; /* looked up when loaded */
    const uint32_t buffer = (uint32_t)gen->printf_buffer_chars;
    crs_shared *sh = sim->shared;
    if (formatted >= buffer) {
        /* the characters and the terminating NUL overrun the board's buffer: memory is corrupt */
        sim->overflow_tick = sim->tick;
        sim->overflow_chars = formatted;
        sim->overflow_phase = sh->phase;
        return 0;
    }
    const uint32_t n = formatted <= available ? formatted : available;
    const uint32_t ring = (uint32_t)gen->tx_ring_chars;
    const uint32_t taken = crs_line_queue(&sh->line, ring, sim->tick, chars, n);
    if (taken > 0 && sh->print_count < CRS_PRINT_CAPACITY) {
        /* a print mark: this call's tick and how many of its characters are on the line */
        sh->print_tick[sh->print_count] = sim->tick;
        sh->print_chars[sh->print_count] = taken;
        sh->print_count++;
    }
    if (taken < n) {
        if (sim->tx_first_drop_tick < 0) sim->tx_first_drop_tick = sim->tick;
        sim->tx_dropped += (int64_t)(n - taken);
    }
    return (int32_t)taken;
}

enum { GPBDAT = 4, GPBSET = 5, GPBCLEAR = 6, GPBTOGGLE = 7 };

uint32_t crs_board_update_gpio(crs_sim *sim)
{
    uint32_t *r = sim->fw.gpio;
    if (r == NULL) return sim->leds;
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
