/* A run's settings and a scenario's events applied to the board (board_config.h). */
#include "board_config.h"

#include <string.h>

#include "framework_facts.h"
#include "motor_board.h"

void crs_board_init(crs_board *board, int32_t generation, crs_shared *shared)
{
    crs_board_defaults(board);
    board->config.generation = generation;
    board->shared = shared;
}

void crs_board_configure(crs_board *board, const crs_board_settings *s)
{
    crs_board_config c = board->config; /* the generation, its row and the cost unit stay */
    c.strict_nan = s->strict_nan != 0;
    c.startup_ticks = s->startup_ticks;
    /* the budget in the firmware's cost unit: instructions, or (native) ns at one instruction per
     * cycle of the F28335 (CRS_CPU_CYCLES_PER_TICK per ms) */
    c.budget = c.cost_unit == CRS_COST_INSTRUCTIONS ? s->budget_instructions
                                                    : s->budget_instructions * 1000000 / CRS_CPU_CYCLES_PER_TICK;
    c.time_lab = s->time_lab != 0;
    c.log_every_ticks = s->log_every_ticks > 0 ? s->log_every_ticks : 0;
    c.motor_board = s->motor_board;
    for (int j = 0; j < 3; ++j) {
        c.rest_motor_rad[j] = s->rest_motor_rad[j];
        /* the drive works in the commands' units: the plant's N.m over the motor gain */
        c.drive.stall_units[j] = s->stall_nm[j] / s->motor_gain_nm_per_unit;
        c.drive.backemf_units_s_per_rad[j] = s->backemf_nm_s_per_rad[j] / s->motor_gain_nm_per_unit;
    }
    c.drive.lag_s = s->drive_lag_s;
    c.friction = s->friction;
    c.hand = (crs_hand_config){s->hand_kp_nm_per_rad, s->hand_ki_nm_per_rad_s, s->hand_kd_nm_s_per_rad,
                               s->hand_max_nm};
    c.debug.break_when = s->break_when != 0;
    c.debug.trap_fp = s->trap_fp != 0;
    board->config = c;
    /* the encoders' noise until a scenario's fault changes it */
    for (int j = 0; j < 3; ++j) board->faults.noise_counts[j] = s->encoder_noise_counts;
}

void crs_board_attach_plant(crs_board *board, const crs_board_plant *p)
{
    board->plant = *p;
}

uint32_t crs_board_take_motor_board_events(crs_board *board)
{
    const uint32_t n = board->motor_board.event_count;
    board->motor_board.event_count = 0;
    return n;
}

void crs_board_attach_memory(crs_board *board, crs_mem_var *vars, uint32_t count)
{
    board->memory.vars = vars;
    board->memory.count = count;
}

void crs_board_attach_world(crs_board *board, const crs_world_config *config)
{
    crs_world_attach(&board->world, config);
}

void crs_board_counters(const crs_board *board, int64_t *out)
{
    out[CRS_COUNTER_LAB_CALLS] = board->lab_calls;
    out[CRS_COUNTER_LAB_COST_TOTAL] = board->lab_cost_total;
    out[CRS_COUNTER_LAB_COST_MAX] = board->lab_cost_max;
    out[CRS_COUNTER_LAB_MAX_TICK] = board->lab_max_tick;
    out[CRS_COUNTER_OVER_BUDGET] = board->over_budget;
    out[CRS_COUNTER_COST_UNIT] = board->config.cost_unit;
    out[CRS_COUNTER_BUDGET] = board->config.budget;
    out[CRS_COUNTER_NAN_FIRST_TICK] = board->nan_first_tick;
    out[CRS_COUNTER_NAN_FIRST_JOINT] = board->nan_first_joint;
    out[CRS_COUNTER_NAN_COUNT] = board->nan_count;
    out[CRS_COUNTER_PRINTING_RUNS] = board->printing_runs;
    out[CRS_COUNTER_PRINT_TRIGGERS] = board->print_triggers;
    out[CRS_COUNTER_SAFETY_FLAG] = board->safety_flag;
    out[CRS_COUNTER_SAFETY_TRIPS] = board->safety_trips;
    out[CRS_COUNTER_SAFETY_FIRST_TICK] = board->safety_first_tick;
    out[CRS_COUNTER_SAFETY_TICKS] = board->safety_ticks;
    out[CRS_COUNTER_LEDS] = board->leds;
    out[CRS_COUNTER_ESTOP_LATCHED] = board->estop_latched;
    out[CRS_COUNTER_TX_DROPPED] = board->tx_dropped;
    out[CRS_COUNTER_TX_FIRST_DROP_TICK] = board->tx_first_drop_tick;
    out[CRS_COUNTER_OVERFLOW_TICK] = board->overflow_tick;
    out[CRS_COUNTER_OVERFLOW_CHARS] = board->overflow_chars;
    out[CRS_COUNTER_OVERFLOW_PHASE] = board->overflow_phase;
    out[CRS_COUNTER_CONSOLE_BYTES] = board->console_bytes;
    out[CRS_COUNTER_TICK] = board->tick;
    out[CRS_COUNTER_MOTOR_BOARD_CUTOUTS] = board->motor_board.cutouts;
}

static void set_joints(int32_t flags[3], int32_t joints, int32_t on)
{
    for (int j = 0; j < 3; ++j) {
        if (joints & (1 << j)) flags[j] = on != 0;
    }
}

int crs_board_apply_event(crs_board *board, const crs_board_event *e)
{
    crs_faults *f = &board->faults;
    switch (e->kind) {
    case CRS_EVENT_HAND_MOVE:
        board->hand.active = 1;
        board->hand.start_tick = board->tick;
        board->hand.duration_ticks = e->duration_ticks;
        for (int j = 0; j < 3; ++j) {
            board->hand.start_dh_rad[j] = board->plant.qpos[j];
            board->hand.target_dh_rad[j] = e->values[j];
        }
        return 0;
    case CRS_EVENT_HAND_RELEASE:
        board->hand.active = 0;
        memset(board->hand.integral_rad_s, 0, sizeof board->hand.integral_rad_s);
        return 0;
    case CRS_EVENT_PUSH:
        /* the board works out each tick's force from the tick number (csrc/plant/push.c) */
        board->push.active = e->on != 0;
        board->push.start_tick = e->tick;
        board->push.half_period_ticks = e->half_period_ticks;
        for (int k = 0; k < 3; ++k) board->push.force_n[k] = e->values[k];
        return 0;
    case CRS_EVENT_ENCODER_NOISE:
        if (e->rng_state != 0) f->rng_state = e->rng_state;
        for (int j = 0; j < 3; ++j) {
            if (e->joints & (1 << j)) f->noise_counts[j] = e->values[j];
        }
        return 0;
    case CRS_EVENT_ENCODER_GLITCH:
        if (f->glitch_tick != board->tick) { /* a new glitch; two at one tick add up */
            f->glitch_tick = board->tick;
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
        board->estop_latched = 1;
        return 0;
    case CRS_EVENT_FRICTION:
        board->config.friction = e->friction;
        return 0;
    case CRS_EVENT_SIMULINK_INPUT:
        if (e->input >= 1 && e->input <= 7 && board->fw.simulink_input[e->input - 1] != NULL) {
            *board->fw.simulink_input[e->input - 1] = (int32_t)e->value;
        }
        return 0;
    default:
        return -1;
    }
}
