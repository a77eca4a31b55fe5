/* The 1 kHz loop: encoders -> framework -> lab() -> printing -> safety -> motor board -> drive ->
 * physics. */
#include "sim.h"

#include <math.h>
#include <string.h>

#include "board.h"
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

void crs_sim_init(crs_sim *sim)
{
    memset(sim, 0, sizeof *sim);
    sim->startup_ticks = CRS_STARTUP_TICKS;
    sim->budget = INT64_MAX;
    sim->time_lab = 1;
    sim->log_every_ticks = 1;
    sim->leds = CRS_LEDS_AT_START;
    sim->nan_first_tick = -1;
    sim->tx_first_drop_tick = -1;
    sim->overflow_tick = -1;
    sim->faults.rng_state = 0x9E3779B97F4A7C15ULL;
    sim->faults.glitch_tick = -1;
    crs_motor_board_init(&sim->motor_board, CRS_MOTOR_BOARD_NONE);
    crs_world_init(&sim->world);
    /* an ideal drive (every command delivered at once) until the plant parameters are set */
    for (int j = 0; j < 3; ++j) sim->drive.stall_units[j] = HUGE_VAL;
}

/* The framework's command for this tick once the startup gate is open: lab(), printing(), the
 * safety envelope (the hold controller's output outside it), NaN check, clamp, e-stop. Returns
 * a CRS_RUN_* code to stop the run, else 0. */
static int lab_tick(crs_sim *sim)
{
    int32_t print = 0;
    int code = crs_fw_call_lab(sim, &print);
    if (code) return code;
    if (sim->overflow_tick >= 0) return CRS_RUN_PRINTF_OVERFLOW;
    if (print) {
        sim->print_triggers++;
        if (sim->fw.symbols & CRS_LAB_HAS_PRINTING) {
            code = crs_fw_call_printing(sim);
            if (code) return code;
            sim->printing_runs++;
            if (sim->overflow_tick >= 0) return CRS_RUN_PRINTF_OVERFLOW;
        }
    }
    sim->leds = crs_board_update_gpio(sim);
    for (int j = 0; j < 3; ++j) sim->tau[j] = sim->fw.tau[j];

    int stop = 0;
    const float clamp = (float)CRS_CLAMP_UNITS;
    const int outside = crs_outside_envelope(sim->enc_rad);
    for (int j = 0; j < 3; ++j) {
        /* outside, the lab's torques are discarded */
        float out = outside ? sim->hold.out[j] : sim->tau[j];
        if (!isfinite(out)) {
            if (sim->nan_first_tick < 0) {
                sim->nan_first_tick = sim->tick;
                sim->nan_first_joint = j + 1;
            }
            sim->nan_count++;
            out = 0.0f; /* no torque on that joint this tick */
            if (sim->strict_nan) stop = CRS_RUN_NAN_STRICT;
        }
        out = out > clamp ? clamp : (out < -clamp ? -clamp : out);
        sim->command[j] = sim->estop_latched ? 0.0 : (double)out;
    }
    if (outside) {
        crs_hold_reanchor(&sim->hold, sim->enc_rad);
    } else {
        crs_hold_follow(&sim->hold, sim->enc_rad);
    }
    sim->safety_flag = outside;
    return stop;
}

/* One tick of the framework and the motor board; returns a CRS_RUN_* code to stop, else 0. */
static int framework_tick(crs_sim *sim)
{
    double motor[3];
    const double dh[3] = {sim->plant.qpos[0], sim->plant.qpos[1], sim->plant.qpos[2]};
    crs_dh_to_motor(dh, motor);
    crs_read_encoders(sim, motor, sim->enc_rad);
    crs_hold_update(&sim->hold, sim->enc_rad);

    int stop = 0;
    if (sim->tick >= sim->startup_ticks && (sim->fw.symbols & CRS_LAB_HAS_LAB)) {
        stop = lab_tick(sim);
        if (stop == CRS_RUN_PRINTF_OVERFLOW || stop == CRS_RUN_TRAPPED) return stop;
    } else {
        /* before the startup gate opens lab() is not called and the commands are zero */
        memset(sim->command, 0, sizeof sim->command);
    }
    if (crs_motor_board_step(&sim->motor_board, sim->tick, sim->command) && stop == 0) {
        stop = CRS_RUN_EVENTS_FULL;
    }
    for (int j = 0; j < 3; ++j) {
        sim->applied[j] = sim->faults.dead_motor[j] ? 0.0 : sim->motor_board.out_units[j];
    }
    return stop;
}

static double plot_var(const float *v) { return v != NULL ? (double)*v : 0.0; }

static void log_tick(crs_sim *sim, int plots)
{
    crs_log *lg = &sim->log;
    const int64_t i = lg->count++;
    lg->tick[i] = sim->tick;
    for (int j = 0; j < 3; ++j) {
        lg->enc_rad[3 * i + j] = sim->enc_rad[j];
        lg->tau_lab[3 * i + j] = sim->tau[j];
        lg->tau_applied[3 * i + j] = sim->applied[j];
        lg->qpos_dh_rad[3 * i + j] = sim->plant.qpos[j];
        lg->push_force[3 * i + j] = sim->push.now_n[j];
    }
    double ee_in[3];
    crs_fk_dh(sim->plant.qpos, ee_in);
    for (int k = 0; k < 3; ++k) lg->ee[3 * i + k] = CRS_M_PER_IN * ee_in[k];
    for (int k = 0; k < 4; ++k) lg->plot[4 * i + k] = plots ? plot_var(sim->fw.plot[k]) : 0.0;
    lg->safety[i] = sim->safety_flag;
    lg->leds[i] = sim->leds;
    lg->motor_board_off[i] = sim->motor_board.off;
}

static int run_ticks(crs_sim *sim, int64_t until_tick)
{
    crs_shared *sh = sim->shared;
    /* what changes only between chunks (the lab's symbols never; the drive's lag and the hand's
     * move at scenario events, which end chunks): worked out once per chunk, not every tick */
    const int plots = (sim->fw.symbols & CRS_LAB_HAS_PLOTVARS) != 0;
    const double drive_follow = crs_drive_follow(&sim->drive);
    crs_hand_path hand_path;
    crs_hand_plan(&sim->hand, &hand_path);
    const int64_t log_every = sim->log.capacity > 0 ? sim->log_every_ticks : 0; /* 0: no log */
    while (sim->tick < until_tick) {
        sh->tick = sim->tick;
        if (crs_fw_tick_begins(sim)) return CRS_RUN_BREAK;
        const int stop = framework_tick(sim);
        /* the board's memory is corrupt, or the firmware stopped: the tick goes no further */
        if (stop == CRS_RUN_PRINTF_OVERFLOW || stop == CRS_RUN_TRAPPED) return stop;
        /* motor speeds: motor 3 turns with the forearm's absolute angle, j2 + j3 */
        const double speed[3] = {sim->plant.qvel[0], sim->plant.qvel[1], sim->plant.qvel[1] + sim->plant.qvel[2]};
        crs_drive_step(&sim->drive, drive_follow, sim->applied, speed, sim->faults.dead_motor, sim->plant.ctrl);
        crs_friction_add(&sim->friction, speed, sim->plant.ctrl);
        crs_hand_step_along(sim, &hand_path);
        for (int j = 0; j < 3; ++j) sim->plant.qfrc_applied[j] = sim->hand.force_nm[j];
        crs_push_apply(&sim->push, sim->tick, sim->plant.qpos, sim->plant.qfrc_applied);
        const int logged = log_every == 1 || (log_every > 1 && sim->tick % log_every == 0);
        if (logged) log_tick(sim, plots);
        crs_line_send(sh, sim->tick);
        crs_host_ports_tick(sim, sim->tick); /* after lab(): what the host sent, the replies */

        sh->phase = CRS_PHASE_PHYSICS;
        sim->plant.step(sim->plant.model, sim->plant.data);
        if (sim->world.enabled) {
            /* the contact forces of the step just taken, logged with the state it started from */
            crs_world_update(&sim->world, sim->tick);
            if (logged && sim->log.world != NULL) {
                memcpy(&sim->log.world[CRS_WORLD_ROW * (sim->log.count - 1)], sim->world.row,
                       sizeof sim->world.row);
            }
        }
        sim->tick++;
        sh->phase = CRS_PHASE_IDLE;
        sh->tick = sim->tick;

        if (stop) return stop;
        if (sh->serial_len > CRS_SERIAL_CAPACITY / 2 || sh->mark_count > CRS_MARK_CAPACITY / 2
            || sh->print_count > CRS_PRINT_CAPACITY / 2 || crs_host_ports_full(sh)) {
            return CRS_RUN_SERIAL_FULL;
        }
        if (sim->log.capacity > 0 && sim->log.count >= sim->log.capacity) return CRS_RUN_LOG_FULL;
    }
    return CRS_RUN_DONE;
}

int crs_sim_run(crs_sim *sim, int64_t until_tick)
{
    crs_fw_chunk_begins(sim);
    const int code = run_ticks(sim, until_tick);
    crs_fw_chunk_ends(sim);
    return code;
}
