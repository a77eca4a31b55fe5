/* A run's settings and a scenario's events, handed to the board whole: the worker fills one struct
 * and makes one call (crs_board_configure, crs_board_apply_event, ...); nothing outside the board
 * writes crs_board's fields. The settings are in the units a user gives them (N.m, instructions);
 * the board's configuration (crs_board_config, board.h) is in its own. Read by cffi (after
 * board.h). */
#ifndef CRSLAB_BOARD_CONFIG_H
#define CRSLAB_BOARD_CONFIG_H

#include <stdint.h>

#include "board.h"

/* Everything of a run that decides what the board does (crslab/worker/config.py: RunConfig). */
typedef struct {
    int32_t strict_nan;                /* 1: a NaN/Inf torque stops the run */
    int32_t motor_board;               /* CRS_MOTOR_BOARD_* */
    int64_t startup_ticks;             /* lab() first runs at this tick */
    int64_t budget_instructions;       /* lab()'s budget per call; a native firmware's time is
                                          compared at one instruction per F28335 cycle */
    double rest_motor_rad[3];          /* the true resting pose the encoders were zeroed at */
    double encoder_noise_counts;       /* encoder noise on every joint, standard deviation, counts */
    double motor_gain_nm_per_unit;     /* N.m per command unit (the drive works in command units) */
    double stall_nm[3];                /* the drive's torque at standstill, at most, N.m */
    double backemf_nm_s_per_rad[3];    /* what each rad/s of motor speed takes off it, N.m s/rad */
    double drive_lag_s;                /* first-order lag of the delivered torque; 0: none */
    crs_friction friction;             /* the sliding friction beyond the static band */
    double hand_kp_nm_per_rad, hand_ki_nm_per_rad_s, hand_kd_nm_s_per_rad, hand_max_nm; /* the hand */
    int32_t break_when;                /* crslab debug --break-when (a native firmware) */
    int32_t trap_fp;                   /* crslab debug: a NaN or Inf in lab() raises SIGFPE */
    int32_t time_lab;                  /* 1: count each lab() call's cost (0: measuring only) */
    int32_t log_every_ticks;           /* the scope log (crs_shared.log) keeps the ticks divisible
                                          by this (1: every tick; 5: what Simulink samples, crslab
                                          serve's page); 0: no scope log */
} crs_board_settings;

/* A scenario's event (crslab/scenario), applied before the tick it is at. */
enum {
    CRS_EVENT_HAND_MOVE = 1,       /* from where the arm is to values[] (DH rad) over duration_ticks */
    CRS_EVENT_HAND_RELEASE = 2,    /* the hand lets go */
    CRS_EVENT_PUSH = 3,            /* on: values[] N at the end effector (square wave: half_period_ticks);
                                      off: the push ends */
    CRS_EVENT_ENCODER_NOISE = 4,   /* values[] counts on the joints of `joints`; rng_state: a new seed */
    CRS_EVENT_ENCODER_GLITCH = 5,  /* values[] counts added this tick (two at one tick add up) */
    CRS_EVENT_STUCK_ENCODER = 6,   /* the encoders of `joints` freeze (on) or read again (off) */
    CRS_EVENT_DEAD_MOTOR = 7,      /* the amplifiers of `joints` output nothing (on) or again (off) */
    CRS_EVENT_WRIST_ESTOP = 8,     /* every output latched to zero */
    CRS_EVENT_FRICTION = 9,        /* the sliding friction becomes `friction` */
    CRS_EVENT_SIMULINK_INPUT = 10  /* Simulink's input `input` (1..7) becomes `value` */
};
typedef struct {
    int32_t kind;                  /* CRS_EVENT_* */
    int32_t joints;                /* bit j-1: joint j */
    int32_t on;                    /* push, stuck, dead: 1 starts, 0 ends */
    int32_t input;                 /* Simulink's input 1..7 */
    int64_t tick;                  /* the event's own tick (a push's square wave counts from it) */
    int64_t duration_ticks;        /* hand move */
    int64_t half_period_ticks;     /* push: 0 constant */
    uint64_t rng_state;            /* encoder noise: the new seed; 0 keeps the generator's state */
    int64_t value;                 /* Simulink's input value */
    double values[3];
    crs_friction friction;
} crs_board_event;

/* The board's counters, in the order crs_board_counters writes them (the names, lower case, are
 * crs_board's fields; cost_unit and budget its configuration's, motor_board_cutouts the motor
 * board's). */
typedef enum {
    CRS_COUNTER_LAB_CALLS = 0,
    CRS_COUNTER_LAB_COST_TOTAL = 1,
    CRS_COUNTER_LAB_COST_MAX = 2,
    CRS_COUNTER_LAB_MAX_TICK = 3,
    CRS_COUNTER_OVER_BUDGET = 4,
    CRS_COUNTER_COST_UNIT = 5,
    CRS_COUNTER_BUDGET = 6,
    CRS_COUNTER_NAN_FIRST_TICK = 7,
    CRS_COUNTER_NAN_FIRST_JOINT = 8,
    CRS_COUNTER_NAN_COUNT = 9,
    CRS_COUNTER_PRINTING_RUNS = 10,
    CRS_COUNTER_PRINT_TRIGGERS = 11,
    CRS_COUNTER_SAFETY_FLAG = 12,
    CRS_COUNTER_SAFETY_TRIPS = 13,
    CRS_COUNTER_SAFETY_FIRST_TICK = 14,
    CRS_COUNTER_SAFETY_TICKS = 15,
    CRS_COUNTER_LEDS = 16,
    CRS_COUNTER_ESTOP_LATCHED = 17,
    CRS_COUNTER_TX_DROPPED = 18,
    CRS_COUNTER_TX_FIRST_DROP_TICK = 19,
    CRS_COUNTER_OVERFLOW_TICK = 20,
    CRS_COUNTER_OVERFLOW_CHARS = 21,
    CRS_COUNTER_OVERFLOW_PHASE = 22,
    CRS_COUNTER_CONSOLE_BYTES = 23,
    CRS_COUNTER_TICK = 24,
    CRS_COUNTER_MOTOR_BOARD_CUTOUTS = 25,
    CRS_COUNTERS = 26
} crs_counter;

/* A new board of framework generation `generation` writing into `shared` (crs_board_defaults, then
 * those two). */
void crs_board_init(crs_board *board, int32_t generation, crs_shared *shared);
/* Give the board a run's settings (after its firmware is loaded: the budget is converted into
 * its cost unit): board->config, in one assignment. */
void crs_board_configure(crs_board *board, const crs_board_settings *settings);
/* Step `plant` (its model, its data and their arrays). */
void crs_board_attach_plant(crs_board *board, const crs_board_plant *plant);
/* The motor board's events since the last call (the reader took them). */
uint32_t crs_board_take_motor_board_events(crs_board *board);
/* The lab's variables in C28x memory: `count` entries of `vars` (kept by the caller). */
void crs_board_attach_memory(crs_board *board, crs_mem_var *vars, uint32_t count);
/* The world's configuration (world.h): the board's world works out the fixtures' quantities after
 * every physics step from then on. */
void crs_board_attach_world(crs_board *board, const crs_world_config *config);
/* The board's counters now, into out[CRS_COUNTERS] (crs_counter's order): one call, however many. */
void crs_board_counters(const crs_board *board, int64_t *out);
/* Apply `event` now (before the tick board->tick runs): 0, or -1 for a kind the board does not know. */
int crs_board_apply_event(crs_board *board, const crs_board_event *event);

#endif
