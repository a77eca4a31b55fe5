/* The 1 kHz loop: encoders -> framework -> lab() -> printing -> safety -> motor board -> drive ->
 * physics. */
#include "board.h"

#include <math.h>
#include <string.h>

#include "board_io.h"
#include "crs_arm.h"
#include "drive.h"
#include "firmware_port.h"
#include "framework.h"
#include "framework_facts.h"
#include "friction.h"
#include "hand.h"
#include "host_ports.h"
#include "motor_board.h"
#include "push.h"
#include "serial_line.h"
#include "world.h"

void crs_board_defaults(crs_board *board)
{
    memset(board, 0, sizeof *board);
    board->config.startup_ticks = CRS_STARTUP_TICKS;
    board->config.budget = INT64_MAX;
    board->config.time_lab = 1;
    board->config.motor_board = CRS_MOTOR_BOARD_NONE;
    /* an ideal drive (every command delivered at once) until the plant parameters are set */
    for (int j = 0; j < 3; ++j) board->config.drive.stall_units[j] = HUGE_VAL;
    board->leds = CRS_LEDS_AT_START;
    board->nan_first_tick = -1;
    board->safety_first_tick = -1;
    board->tx_first_drop_tick = -1;
    board->overflow_tick = -1;
    board->faults.rng_state = 0x9E3779B97F4A7C15ULL;
    board->faults.glitch_tick = -1;
    crs_motor_board_init(&board->motor_board);
    crs_world_init(&board->world);
}

/* The framework's command for this tick once the startup gate is open: lab(), printing(), the
 * safety envelope (the hold controller's output outside it), NaN check, clamp, e-stop. Returns
 * a CRS_RUN_* code to stop the run, else 0. */
static int lab_tick(crs_board *board)
{
    int32_t print = 0;
    int code = crs_fw_call_lab(board, &print);
    if (code) return code;
    if (board->overflow_tick >= 0) return CRS_RUN_PRINTF_OVERFLOW;
    if (print) {
        board->print_triggers++;
        if (board->fw.symbols & CRS_LAB_HAS_PRINTING) {
            code = crs_fw_call_printing(board);
            if (code) return code;
            board->printing_runs++;
            if (board->overflow_tick >= 0) return CRS_RUN_PRINTF_OVERFLOW;
        }
    }
    board->leds = crs_board_update_gpio(board);
    for (int j = 0; j < 3; ++j) board->tau[j] = board->fw.tau[j];

    int stop = 0;
    const float clamp = (float)CRS_CLAMP_UNITS;
    const int outside = crs_outside_envelope(board->enc_rad);
    for (int j = 0; j < 3; ++j) {
        /* outside, the lab's torques are discarded */
        float out = outside ? board->hold.out[j] : board->tau[j];
        if (!isfinite(out)) {
            if (board->nan_first_tick < 0) {
                board->nan_first_tick = board->tick;
                board->nan_first_joint = j + 1;
            }
            board->nan_count++;
            out = 0.0f; /* no torque on that joint this tick */
            if (board->config.strict_nan) stop = CRS_RUN_NAN_STRICT;
        }
        out = out > clamp ? clamp : (out < -clamp ? -clamp : out);
        board->command[j] = board->estop_latched ? 0.0 : (double)out;
    }
    if (outside) {
        crs_hold_reanchor(&board->hold, board->enc_rad);
        board->safety_ticks++;
        if (!board->safety_flag) { /* the arm left the envelope: the hold's torques from now on */
            board->safety_trips++;
            if (board->safety_first_tick < 0) board->safety_first_tick = board->tick;
        }
    } else {
        crs_hold_follow(&board->hold, board->enc_rad);
    }
    board->safety_flag = outside;
    return stop;
}

/* One tick of the framework and the motor board; returns a CRS_RUN_* code to stop, else 0. */
static int framework_tick(crs_board *board)
{
    double motor[3];
    const double dh[3] = {board->plant.qpos[0], board->plant.qpos[1], board->plant.qpos[2]};
    crs_dh_to_motor(dh, motor);
    crs_read_encoders(board, motor, board->enc_rad);
    crs_hold_update(&board->hold, board->enc_rad);

    int stop = 0;
    if (board->tick >= board->config.startup_ticks && (board->fw.symbols & CRS_LAB_HAS_LAB)) {
        stop = lab_tick(board);
        if (stop == CRS_RUN_PRINTF_OVERFLOW || stop == CRS_RUN_TRAPPED) return stop;
    } else {
        /* before the startup gate opens lab() is not called and the commands are zero */
        memset(board->command, 0, sizeof board->command);
    }
    if (crs_motor_board_step(board->config.motor_board, &board->motor_board, board->tick, board->command)
        && stop == 0) {
        stop = CRS_RUN_EVENTS_FULL;
    }
    for (int j = 0; j < 3; ++j) {
        board->applied[j] = board->faults.dead_motor[j] ? 0.0 : board->motor_board.out_units[j];
    }
    return stop;
}

static double plot_var(const float *v) { return v != NULL ? (double)*v : 0.0; }

/* The tick's row of the scope log, at row i of the shared block's (counted once the tick is done). */
static void log_tick(crs_board *board, int64_t i, int plots)
{
    crs_scope_log *lg = &board->shared->log;
    lg->tick[i] = board->tick;
    for (int j = 0; j < 3; ++j) {
        lg->enc_rad[3 * i + j] = board->enc_rad[j];
        lg->tau_lab[3 * i + j] = board->tau[j];
        lg->tau_applied[3 * i + j] = board->applied[j];
        lg->qpos_dh_rad[3 * i + j] = board->plant.qpos[j];
        lg->push_force[3 * i + j] = board->push.now_n[j];
    }
    double ee_in[3];
    crs_fk_dh(board->plant.qpos, ee_in);
    for (int k = 0; k < 3; ++k) lg->ee[3 * i + k] = CRS_M_PER_IN * ee_in[k];
    for (int k = 0; k < 4; ++k) lg->plot[4 * i + k] = plots ? plot_var(board->fw.plot[k]) : 0.0;
    lg->safety[i] = board->safety_flag;
    lg->leds[i] = board->leds;
    lg->motor_board_off[i] = board->motor_board.off;
}

static int run_ticks(crs_board *board, int64_t until_tick)
{
    crs_shared *sh = board->shared;
    /* what changes only between chunks (the lab's symbols never; the drive's lag and the hand's
     * move at scenario events, which end chunks): worked out once per chunk, not every tick */
    const crs_board_config *cfg = &board->config;
    const int plots = (board->fw.symbols & CRS_LAB_HAS_PLOTVARS) != 0;
    const double drive_follow = crs_drive_follow(&cfg->drive);
    crs_hand_path hand_path;
    crs_hand_plan(&board->hand, &hand_path);
    const int64_t log_every = cfg->log_every_ticks; /* 0: no log */
    while (board->tick < until_tick) {
        if (sh->stop) return CRS_RUN_STOPPED;
        /* the row of this tick, if it is logged: the rows so far are the reader's (the lab may
         * scribble on the shared block: an index out of range starts it again) */
        int64_t row = -1;
        if (log_every > 0 && board->tick % log_every == 0) {
            row = sh->log.count >= 0 && sh->log.count <= CRS_LOG_CAPACITY ? sh->log.count : 0;
            if (row == CRS_LOG_CAPACITY) return CRS_RUN_LOG_FULL;
        }
        sh->tick = board->tick;
        if (crs_fw_tick_begins(board)) return CRS_RUN_BREAK;
        const int stop = framework_tick(board);
        /* the board's memory is corrupt, or the firmware stopped: the tick goes no further */
        if (stop == CRS_RUN_PRINTF_OVERFLOW || stop == CRS_RUN_TRAPPED) return stop;
        /* motor speeds: motor 3 turns with the forearm's absolute angle, j2 + j3 */
        const double speed[3] = {board->plant.qvel[0], board->plant.qvel[1], board->plant.qvel[1] + board->plant.qvel[2]};
        crs_drive_step(&cfg->drive, &board->drive, drive_follow, board->applied, speed, board->faults.dead_motor,
                       board->plant.ctrl);
        crs_friction_add(&cfg->friction, speed, board->plant.ctrl);
        crs_hand_step_along(&cfg->hand, &board->hand, &hand_path, board->tick, board->plant.qpos, board->plant.qvel);
        for (int j = 0; j < 3; ++j) board->plant.qfrc_applied[j] = board->hand.force_nm[j];
        crs_push_apply(&board->push, board->tick, board->plant.qpos, board->plant.qfrc_applied);
        if (row >= 0) log_tick(board, row, plots);
        crs_line_send(sh, board->tick);
        crs_host_ports_tick(board, board->tick); /* after lab(): what the host sent, the replies */

        sh->phase = CRS_PHASE_PHYSICS;
        board->plant.step(board->plant.model, board->plant.data);
        if (board->world.enabled) {
            /* the contact forces of the step just taken, logged with the state it started from */
            crs_world_update(&board->world, board->tick);
            if (row >= 0) {
                memcpy(&sh->log.world[CRS_WORLD_ROW * row], board->world.state.row,
                       sizeof board->world.state.row);
            }
        }
        if (row >= 0) sh->log.count = row + 1; /* the tick's row is whole */
        board->tick++;
        sh->phase = CRS_PHASE_IDLE;
        sh->tick = board->tick;

        if (stop) return stop;
        if (sh->serial_len > CRS_SERIAL_CAPACITY / 2 || sh->mark_count > CRS_MARK_CAPACITY / 2
            || sh->print_count > CRS_PRINT_CAPACITY / 2 || crs_host_ports_full(sh)) {
            return CRS_RUN_SERIAL_FULL;
        }
        if (crs_fw_chunk_over(board)) return CRS_RUN_CUT;
    }
    return CRS_RUN_DONE;
}

int crs_board_run(crs_board *board, int64_t until_tick)
{
    crs_fw_chunk_begins(board);
    const int code = run_ticks(board, until_tick);
    crs_fw_chunk_ends(board);
    return code;
}
