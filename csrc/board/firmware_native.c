/* The native firmware's port (firmware_port.h): the firmware (csrc/firmware) linked into the same
 * shared object as the board. crslab debug (gdb), --sanitize (ASan and UBSan) and --native run it.
 * lab() is called directly and its cost is the time it took on the monotonic clock; the crslab
 * process watches the worker from outside,
 * and the run sandbox (crslab/sandbox) keeps the process from reaching anything. */
#define _POSIX_C_SOURCE 199309L

#include "firmware_native.h"

#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "board_io.h"
#include "debug.h"
#include "firmware.h"
#include "firmware_port.h"

static crs_board *this_board; /* the one board of this process: serial_printf's way to it */

static void *at(uintptr_t address) { return (void *)address; }

/* What the firmware's serial_printf sends (firmware.h: the board's function it calls). */
static int32_t serial_send(int32_t port, const char *chars, uint32_t formatted)
{
    (void)port;
    return crs_board_serial_out(this_board, chars, formatted, formatted);
}

int crs_fw_native_attach(crs_board *board)
{
    this_board = board;
    crs_board_serial_send = serial_send;
    memset(&board->trap, 0, sizeof board->trap);
    if (crs_board_check_generation(board) != 0) return CRS_RUN_TRAPPED;
    const crs_fw_table *t = crs_fw_start(board->config.generation);
    if (t == NULL) { /* the firmware is linked with the same generations.c: never */
        board->trap.kind = CRS_FW_TRAP_LOAD;
        board->trap.phase = CRS_PHASE_LOADING;
        snprintf(board->trap.text, sizeof board->trap.text, "the firmware cannot run framework generation %d",
                 (int)board->config.generation);
        return CRS_RUN_TRAPPED;
    }
    crs_fw_view *v = &board->fw;
    v->tau = at(t->tau);
    v->offset_enc2 = at(t->offset_enc2);
    v->offset_enc3 = at(t->offset_enc3);
    for (int i = 0; i < CRS_FW_PLOTS; ++i) v->plot[i] = at(t->plot[i]);
    v->gpio = at(t->gpio);
    for (int i = 0; i < CRS_FW_SIMULINK_INPUTS; ++i) v->simulink_input[i] = at(t->simulink_input[i]);
    v->matlab_lock = at(t->matlab_lock);
    v->symbols = t->symbols;
    board->config.cost_unit = CRS_COST_NS;
    return 0;
}

int crs_fw_call_lab(crs_board *board, int32_t *print)
{
    crs_shared *sh = board->shared;
    const float th1 = (float)board->enc_rad[0], th2 = (float)board->enc_rad[1], th3 = (float)board->enc_rad[2];
    board->lab_calls++;
    if (!board->config.time_lab) {
        sh->phase = CRS_PHASE_LAB;
        *print = crs_fw_lab(th1, th2, th3, board->safety_flag);
        return 0;
    }
    if (board->config.debug.trap_fp) crs_debug_fp_traps(1); /* crslab debug --debug-on-crash --strict */
    /* the monotonic clock (vDSO, no system call): a thread CPU-time clock costs two system
     * calls per tick, a sixth of the worker's time */
    const int64_t start_ns = crs_now_ns();
    sh->phase = CRS_PHASE_LAB;
    *print = crs_fw_lab(th1, th2, th3, board->safety_flag);
    crs_board_lab_cost(board, crs_now_ns() - start_ns);
    if (board->config.debug.trap_fp) crs_debug_fp_traps(0);
    return 0;
}

int crs_fw_tick_begins(crs_board *board) { return crs_debug_tick_begins(board); }

void crs_fw_chunk_begins(crs_board *board) { (void)board; /* the crslab process watches a native worker */ }

void crs_fw_chunk_ends(crs_board *board) { (void)board; }

int crs_fw_chunk_over(crs_board *board) { (void)board; return 0; /* a native worker holds one board */ }

int crs_fw_call_printing(crs_board *board)
{
    board->shared->phase = CRS_PHASE_PRINTING;
    crs_fw_printing();
    return 0;
}
