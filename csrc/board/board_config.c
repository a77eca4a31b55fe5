/* A run's settings and a scenario's events applied to the board (board_config.h). */
#include "board_config.h"

#include <string.h>

#include "framework_facts.h"
#include "motor_board.h"

void crs_board_init(crs_sim *sim, int32_t generation, crs_shared *shared)
{
    crs_sim_init(sim);
    sim->generation = generation;
    sim->shared = shared;
}

void crs_board_configure(crs_sim *sim, const crs_board_config *c)
{
    sim->strict_nan = c->strict_nan != 0;
    sim->startup_ticks = c->startup_ticks;
    /* the budget in the firmware's cost unit: instructions, or (native) ns at one instruction per
     * cycle of the F28335 (CRS_CPU_CYCLES_PER_TICK per ms) */
    sim->budget = sim->cost_unit == CRS_COST_INSTRUCTIONS
                      ? c->budget_instructions
                      : c->budget_instructions * 1000000 / CRS_CPU_CYCLES_PER_TICK;
    sim->time_lab = c->time_lab != 0;
    sim->log_every_ticks = c->log_every_ticks > 1 ? c->log_every_ticks : 1;
    sim->motor_board.model = c->motor_board;
    for (int j = 0; j < 3; ++j) {
        sim->rest_motor_rad[j] = c->rest_motor_rad[j];
        sim->faults.noise_counts[j] = c->encoder_noise_counts;
        /* the drive works in the commands' units: the plant's N.m over the motor gain */
        sim->drive.stall_units[j] = c->stall_nm[j] / c->motor_gain_nm_per_unit;
        sim->drive.backemf_units_s_per_rad[j] = c->backemf_nm_s_per_rad[j] / c->motor_gain_nm_per_unit;
    }
    sim->drive.lag_s = c->drive_lag_s;
    sim->friction = c->friction;
    sim->hand.kp_nm_per_rad = c->hand_kp_nm_per_rad;
    sim->hand.ki_nm_per_rad_s = c->hand_ki_nm_per_rad_s;
    sim->hand.kd_nm_s_per_rad = c->hand_kd_nm_s_per_rad;
    sim->hand.max_nm = c->hand_max_nm;
    sim->debug.break_when = c->break_when != 0;
    sim->debug.trap_fp = c->trap_fp != 0;
}

void crs_board_attach_plant(crs_sim *sim, const crs_board_plant *p)
{
    sim->plant = *p;
}

void crs_board_attach_log(crs_sim *sim, const crs_log *log)
{
    sim->log = *log;
    sim->log.count = 0;
}

int64_t crs_board_take_log(crs_sim *sim)
{
    const int64_t n = sim->log.count;
    sim->log.count = 0;
    return n;
}

uint32_t crs_board_take_motor_board_events(crs_sim *sim)
{
    const uint32_t n = sim->motor_board.event_count;
    sim->motor_board.event_count = 0;
    return n;
}

void crs_board_attach_memory(crs_sim *sim, crs_mem_var *vars, uint32_t count)
{
    sim->memory.vars = vars;
    sim->memory.count = count;
}

void crs_board_attach_world(crs_sim *sim, const crs_world *world)
{
    crs_world *w = &sim->world;
    w->enabled = world->enabled;
    w->peg_tip_adr = world->peg_tip_adr;
    memcpy(w->sensor_adr, world->sensor_adr, sizeof w->sensor_adr);
    w->sensordata = world->sensordata;
    w->breaking_force_n = world->breaking_force_n;
    w->gravity_m_s2 = world->gravity_m_s2;
    memcpy(w->groove_xy_m, world->groove_xy_m, sizeof w->groove_xy_m);
    w->egg_contype = world->egg_contype;
    w->egg_conaffinity = world->egg_conaffinity;
    w->egg_size_m = world->egg_size_m;
    w->egg_pos_m = world->egg_pos_m;
}

void crs_board_counters(const crs_sim *sim, int64_t *out)
{
    out[CRS_COUNTER_LAB_CALLS] = sim->lab_calls;
    out[CRS_COUNTER_LAB_COST_TOTAL] = sim->lab_cost_total;
    out[CRS_COUNTER_LAB_COST_MAX] = sim->lab_cost_max;
    out[CRS_COUNTER_LAB_MAX_TICK] = sim->lab_max_tick;
    out[CRS_COUNTER_OVER_BUDGET] = sim->over_budget;
    out[CRS_COUNTER_COST_UNIT] = sim->cost_unit;
    out[CRS_COUNTER_BUDGET] = sim->budget;
    out[CRS_COUNTER_NAN_FIRST_TICK] = sim->nan_first_tick;
    out[CRS_COUNTER_NAN_FIRST_JOINT] = sim->nan_first_joint;
    out[CRS_COUNTER_NAN_COUNT] = sim->nan_count;
    out[CRS_COUNTER_PRINTING_RUNS] = sim->printing_runs;
    out[CRS_COUNTER_PRINT_TRIGGERS] = sim->print_triggers;
    out[CRS_COUNTER_SAFETY_FLAG] = sim->safety_flag;
    out[CRS_COUNTER_LEDS] = sim->leds;
    out[CRS_COUNTER_ESTOP_LATCHED] = sim->estop_latched;
    out[CRS_COUNTER_TX_DROPPED] = sim->tx_dropped;
    out[CRS_COUNTER_TX_FIRST_DROP_TICK] = sim->tx_first_drop_tick;
    out[CRS_COUNTER_OVERFLOW_TICK] = sim->overflow_tick;
    out[CRS_COUNTER_OVERFLOW_CHARS] = sim->overflow_chars;
    out[CRS_COUNTER_OVERFLOW_PHASE] = sim->overflow_phase;
    out[CRS_COUNTER_CONSOLE_BYTES] = sim->console_bytes;
    out[CRS_COUNTER_TICK] = sim->tick;
    out[CRS_COUNTER_MOTOR_BOARD_CUTOUTS] = sim->motor_board.cutouts;
}

static void set_joints(int32_t flags[3], int32_t joints, int32_t on)
{
    for (int j = 0; j < 3; ++j) {
        if (joints & (1 << j)) flags[j] = on != 0;
    }
}

int crs_board_apply_event(crs_sim *sim, const crs_board_event *e)
{
    crs_faults *f = &sim->faults;
    switch (e->kind) {
    case CRS_EVENT_HAND_MOVE:
        sim->hand.active = 1;
        sim->hand.start_tick = sim->tick;
        sim->hand.duration_ticks = e->duration_ticks;
        for (int j = 0; j < 3; ++j) {
            sim->hand.start_dh_rad[j] = sim->plant.qpos[j];
            sim->hand.target_dh_rad[j] = e->values[j];
        }
        return 0;
    case CRS_EVENT_HAND_RELEASE:
        sim->hand.active = 0;
        memset(sim->hand.integral_rad_s, 0, sizeof sim->hand.integral_rad_s);
        return 0;
    case CRS_EVENT_PUSH:
        /* the board works out each tick's force from the tick number (csrc/plant/push.c) */
        sim->push.active = e->on != 0;
        sim->push.start_tick = e->tick;
        sim->push.half_period_ticks = e->half_period_ticks;
        for (int k = 0; k < 3; ++k) sim->push.force_n[k] = e->values[k];
        return 0;
    case CRS_EVENT_ENCODER_NOISE:
        if (e->rng_state != 0) f->rng_state = e->rng_state;
        for (int j = 0; j < 3; ++j) {
            if (e->joints & (1 << j)) f->noise_counts[j] = e->values[j];
        }
        return 0;
    case CRS_EVENT_ENCODER_GLITCH:
        if (f->glitch_tick != sim->tick) { /* a new glitch; two at one tick add up */
            f->glitch_tick = sim->tick;
            memset(f->glitch_counts, 0, sizeof f->glitch_counts);
        }
        for (int j = 0; j < 3; ++j) f->glitch_counts[j] += (int32_t)e->values[j];
        return 0;
    case CRS_EVENT_STUCK_ENCODER:
        set_joints(f->stuck_encoder, e->joints, e->on);
        return 0;
    case CRS_EVENT_DEAD_MOTOR:
        set_joints(f->dead_motor, e->joints, e->on);
        return 0;
    case CRS_EVENT_WRIST_ESTOP:
        sim->estop_latched = 1;
        return 0;
    case CRS_EVENT_FRICTION:
        sim->friction = e->friction;
        return 0;
    case CRS_EVENT_SIMULINK_INPUT:
        if (e->input >= 1 && e->input <= 7 && sim->fw.simulink_input[e->input - 1] != NULL) {
            *sim->fw.simulink_input[e->input - 1] = (int32_t)e->value;
        }
        return 0;
    default:
        return -1;
    }
}
