/* The 1 kHz loop: encoders -> framework -> lab() -> printing -> safety -> motors -> physics. */
#include "sim.h"

#include <math.h>
#include <string.h>

#include "board.h"
#include "crs_arm.h"
#include "framework.h"

static const double CLAMP_UNITS = 5.0; /* the framework clamps every command to +-5 */

void crs_sim_init(crs_sim *sim)
{
    memset(sim, 0, sizeof *sim);
    sim->generation = 1;
    sim->startup_ticks = 4100;
    sim->budget_ns = 1000000;
    sim->time_lab = 1;
    sim->serial_line_limit = 2048;
    sim->nan_first_tick = -1;
    sim->long_line_tick = -1;
    sim->faults.rng_state = 0x9E3779B97F4A7C15ULL;
    sim->faults.glitch_tick = -1;
}

static void call_lab(crs_sim *sim)
{
    crs_shared *sh = sim->shared;
    sim->lab_calls++;
    if (!sim->time_lab) {
        sh->phase = CRS_PHASE_LAB;
        lab((float)sim->enc_rad[0], (float)sim->enc_rad[1], (float)sim->enc_rad[2], &sim->tau[0],
            &sim->tau[1], &sim->tau[2], sim->safety_flag);
        return;
    }
    const int64_t t0 = crs_now_ns();
    sh->phase_start_ns = t0;
    sh->phase = CRS_PHASE_LAB;
    lab((float)sim->enc_rad[0], (float)sim->enc_rad[1], (float)sim->enc_rad[2], &sim->tau[0],
        &sim->tau[1], &sim->tau[2], sim->safety_flag);
    const int64_t dt = crs_now_ns() - t0;
    sim->lab_ns_total += dt;
    if (dt > sim->lab_ns_max) {
        sim->lab_ns_max = dt;
        sim->lab_max_tick = sim->tick;
    }
    if (dt > sim->budget_ns) {
        if (sim->over_budget < 8) sim->first_over_tick[sim->over_budget] = sim->tick;
        sim->over_budget++;
    }
}

/* One tick of the framework; returns CRS_RUN_NAN_STRICT to stop, else 0. */
static int framework_tick(crs_sim *sim)
{
    double motor[3];
    const double dh[3] = {sim->qpos[0], sim->qpos[1], sim->qpos[2]};
    crs_dh_to_motor(dh, motor);
    crs_read_encoders(sim, motor, sim->enc_rad);

    const int outside = crs_outside_envelope(sim->enc_rad);
    if (!outside || !sim->has_hold) {
        memcpy(sim->hold_motor_rad, sim->enc_rad, sizeof motor);
        sim->has_hold = 1;
    }
    if (sim->tick < sim->startup_ticks || lab == NULL) {
        /* before the startup gate opens nothing reaches the motors and lab() is not called */
        memset(sim->applied, 0, sizeof sim->applied);
        return 0;
    }

    call_lab(sim);
    crs_board_after_lab(sim);
    sim->leds = crs_board_update_gpio();

    int stop = 0;
    double out[3];
    if (outside) {
        crs_hold_controller(sim, out); /* the lab's torques are discarded */
    } else {
        for (int j = 0; j < 3; ++j) out[j] = (double)sim->tau[j];
    }
    for (int j = 0; j < 3; ++j) {
        if (!isfinite(out[j])) {
            if (sim->nan_first_tick < 0) {
                sim->nan_first_tick = sim->tick;
                sim->nan_first_joint = j + 1;
            }
            sim->nan_count++;
            out[j] = 0.0; /* no torque on that joint this tick */
            if (sim->strict_nan) stop = CRS_RUN_NAN_STRICT;
        }
        out[j] = out[j] > CLAMP_UNITS ? CLAMP_UNITS : (out[j] < -CLAMP_UNITS ? -CLAMP_UNITS : out[j]);
        if (sim->estop_latched || sim->faults.dead_motor[j]) out[j] = 0.0;
        sim->applied[j] = out[j];
    }
    sim->safety_flag = outside;
    return stop;
}

static void log_tick(crs_sim *sim, int plots)
{
    crs_log *lg = &sim->log;
    const int64_t i = lg->count++;
    lg->tick[i] = sim->tick;
    for (int j = 0; j < 3; ++j) {
        lg->enc_rad[3 * i + j] = sim->enc_rad[j];
        lg->tau_lab[3 * i + j] = sim->tau[j];
        lg->tau_applied[3 * i + j] = sim->applied[j];
        lg->qpos_dh_rad[3 * i + j] = sim->qpos[j];
    }
    lg->plot[4 * i + 0] = plots ? Simulink_PlotVar1 : 0.0;
    lg->plot[4 * i + 1] = plots ? Simulink_PlotVar2 : 0.0;
    lg->plot[4 * i + 2] = plots ? Simulink_PlotVar3 : 0.0;
    lg->plot[4 * i + 3] = plots ? Simulink_PlotVar4 : 0.0;
    lg->safety[i] = sim->safety_flag;
    lg->leds[i] = sim->leds;
}

int crs_sim_run(crs_sim *sim, int64_t until_tick)
{
    crs_board_attach(sim);
    crs_shared *sh = sim->shared;
    /* which symbols the lab defines never changes: look once per chunk, not every tick */
    const int plots = (crs_lab_symbols() & CRS_LAB_HAS_PLOTVARS) != 0;
    while (sim->tick < until_tick) {
        sh->tick = sim->tick;
        const int stop = framework_tick(sim);
        for (int j = 0; j < 3; ++j) sim->ctrl[j] = sim->applied[j];
        crs_hand_step(sim);
        for (int j = 0; j < 3; ++j) sim->qfrc_applied[j] = sim->hand.force_nm[j];
        if (sim->log.capacity > 0) log_tick(sim, plots);

        sh->phase = CRS_PHASE_PHYSICS;
        sim->mj_step(sim->mj_model, sim->mj_data);
        memcpy(sim->prev_enc_rad, sim->enc_rad, sizeof sim->enc_rad);
        sim->tick++;
        sh->phase = CRS_PHASE_IDLE;
        sh->tick = sim->tick;

        if (stop) return stop;
        if (sh->serial_len > CRS_SERIAL_CAPACITY / 2 || sh->mark_count > CRS_MARK_CAPACITY / 2) {
            return CRS_RUN_SERIAL_FULL;
        }
        if (sim->log.capacity > 0 && sim->log.count >= sim->log.capacity) return CRS_RUN_LOG_FULL;
    }
    return CRS_RUN_DONE;
}
