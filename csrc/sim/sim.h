/* The emulated CRS board and its simulation loop: what runs every 1 ms tick.
 *
 * Compiled together with one lab file into one shared object per lab (see crslab/lab/build.py)
 * and driven from Python in chunks of ticks (crslab/sim/worker.py). Everything the tick needs
 * lives in caller-owned structs; the only globals are the framework objects a lab file names
 * (SerialA, SWI_printf, GpioDataRegs), defined in board.c.
 *
 * Time: tick k happens at t = k ms. It sees the plant state after k physics steps of 1 ms, runs
 * the framework (and lab() once the startup gate is open), then the plant steps to t = k+1 ms.
 * Read by cffi (ABI mode): plain declarations only. */
#ifndef CRSLAB_SIM_H
#define CRSLAB_SIM_H

#include <stdint.h>

/* Shared-memory block the worker writes and the crslab process reads, even after a crash. */
enum { CRS_SERIAL_CAPACITY = 4194304, CRS_MARK_CAPACITY = 65536 };
enum { CRS_PHASE_IDLE = 0, CRS_PHASE_LAB = 1, CRS_PHASE_PRINTING = 2, CRS_PHASE_PHYSICS = 3,
       CRS_PHASE_LOADING = 4 /* the lab's shared object is being loaded: its constructors run */ };
enum { CRS_REFUSAL_TEXT = 256 };

/* A system call the sandbox refused: written by the worker's SIGSYS handler
 * (csrc/sandbox/trap.c) just before it ends the worker, read by the crslab process. */
typedef struct {
    int32_t refused;        /* 1 once a call was refused */
    int32_t syscall_nr;     /* its number (native architecture unless arch says otherwise) */
    uint32_t arch;          /* AUDIT_ARCH_* the call was made with */
    int32_t phase;          /* CRS_PHASE_* it was made in */
    int64_t tick;           /* the tick being run */
    uint64_t args[6];       /* its arguments */
    char text[CRS_REFUSAL_TEXT]; /* the path it named, NUL-terminated, truncated; else empty */
} crs_refusal;

typedef struct {
    int64_t tick;       /* tick being run (or next to run when idle) */
    int32_t phase;      /* CRS_PHASE_*: where the worker is */
    int32_t pad;
    int64_t phase_start_ns; /* CLOCK_MONOTONIC when that phase began */
    uint64_t serial_len;    /* bytes in serial[] not yet taken by the reader */
    uint64_t serial_dropped; /* bytes lost: more printed in one tick than serial[] or the marks hold */
    uint32_t mark_count;    /* entries in marks[] */
    uint32_t pad2;
    crs_refusal refusal;    /* what the sandbox refused, if anything */
    int64_t mark_tick[CRS_MARK_CAPACITY];   /* tick of each serial_printf call ... */
    uint64_t mark_offset[CRS_MARK_CAPACITY]; /* ... and where its bytes start in serial[] */
    char serial[CRS_SERIAL_CAPACITY];
} crs_shared;

/* Faults a scenario can inject; all off when zero. Noise is seeded (xorshift64*). */
typedef struct {
    uint64_t rng_state;          /* seed, never 0 */
    double noise_counts[3];      /* encoder noise, standard deviation in counts per joint */
    int64_t glitch_tick;         /* one tick where glitch_counts are added (-1: none) */
    int32_t glitch_counts[3];
    int32_t stuck_encoder[3];    /* 1: the encoder reading is frozen */
    int32_t dead_motor[3];       /* 1: the amplifier outputs nothing */
    int64_t stuck_counts[3];     /* frozen readings */
} crs_faults;

/* The hand that moves the arm in Lab 1: a bounded PID pulling the DH joints along a
 * minimum-jerk path from where the move started to the target, then holding there. */
typedef struct {
    int32_t active;              /* 0: not touching the arm */
    int32_t pad;
    int64_t start_tick, duration_ticks;
    double start_dh_rad[3], target_dh_rad[3];
    double kp_nm_per_rad, ki_nm_per_rad_s, kd_nm_s_per_rad, max_nm; /* gains and force bound */
    double integral_rad_s[3];
    double force_nm[3];          /* last applied generalized force on j1..j3, N.m */
} crs_hand;

/* Per-tick signals for scopes (rerun, CSV): filled when log_capacity > 0. */
typedef struct {
    int64_t capacity, count;     /* rows */
    int64_t *tick;
    double *enc_rad;             /* 3 per row: what lab() received (motor angles, rad) */
    double *tau_lab;             /* 3 per row: the lab's tau variables after lab(), command units */
    double *tau_applied;         /* 3 per row: what reached the motors, command units */
    double *plot;                /* 4 per row: Simulink_PlotVar1..4 after lab() */
    int32_t *safety;             /* safety flag */
    uint32_t *leds;              /* bit 0: GPIO34 (control card), bit 1: GPIO60 (e-stop box) */
    double *qpos_dh_rad;         /* 3 per row: the true plant joint angles (DH, rad) */
} crs_log;

/* Why crs_sim_run returned. */
enum {
    CRS_RUN_DONE = 0,        /* reached until_tick */
    CRS_RUN_SERIAL_FULL = 1, /* serial buffer or marks more than half full: drain and go on */
    CRS_RUN_LOG_FULL = 2,    /* scope log full: drain and go on */
    CRS_RUN_NAN_STRICT = 3   /* a NaN/Inf torque in strict mode */
};

typedef void (*crs_mj_step_fn)(const void *model, void *data);

typedef struct {
    /* plant: MuJoCo model and data and views of their arrays (owned by Python) */
    const void *mj_model;
    void *mj_data;
    crs_mj_step_fn mj_step;
    const double *qpos;          /* j1..j3 DH angles, rad */
    const double *qvel;          /* rad/s */
    double *ctrl;                /* motor1..3 commands, command units (actuator gear: N.m/unit) */
    double *qfrc_applied;        /* hand forces on j1..j3, N.m */

    /* configuration */
    int32_t generation;          /* 1: Gen A (SWI_post), 2: Gen B (UARTprint) */
    int32_t strict_nan;          /* 1: a NaN/Inf torque stops the run */
    int64_t startup_ticks;       /* lab() first runs at this tick (4100, or 0) */
    double rest_motor_rad[3];    /* true resting pose the encoders were zeroed at */
    int64_t budget_ns;           /* lab() time budget for the overrun count */
    uint32_t serial_line_limit;  /* real serial buffer of this generation, bytes */
    int32_t time_lab;            /* 1: time every lab() call (and let a hang be seen); 0: don't */

    /* framework state */
    int64_t tick;                /* next tick to run */
    float tau[3];                /* the lab's persistent torque variables, command units */
    int32_t safety_flag;         /* this tick's envelope flag, passed as `error` next tick */
    double hold_motor_rad[3];    /* last in-envelope encoder angles, held when outside */
    double prev_enc_rad[3];      /* last tick's encoder angles (for the hold PD's velocity) */
    double enc_rad[3];           /* this tick's encoder angles */
    double applied[3];           /* command units sent to the motors this tick */
    int32_t estop_latched;       /* wrist e-stop: every output latched to zero */
    int32_t has_hold;            /* hold_motor_rad is valid */
    uint32_t leds;               /* bit 0: GPIO34 high, bit 1: GPIO60 high */
    int32_t pad3;

    /* diagnostics */
    int64_t lab_calls;
    int64_t lab_ns_total, lab_ns_max, lab_max_tick;
    int64_t over_budget;         /* calls slower than budget_ns */
    int64_t first_over_tick[8];  /* first few ticks that overran */
    int64_t nan_first_tick;      /* -1 until a NaN/Inf torque is seen */
    int32_t nan_first_joint;     /* 1..3 */
    int32_t nan_count;
    int64_t long_line_tick;      /* -1 until a serial line exceeds serial_line_limit */
    uint32_t long_line_bytes;
    int32_t printing_runs_pad;
    int64_t printing_runs;

    crs_shared *shared;
    crs_faults faults;
    crs_hand hand;
    crs_log log;
} crs_sim;

/* Zero everything and set the defaults (generation 1, startup 4100, budget 1 ms, ...). */
void crs_sim_init(crs_sim *sim);
/* Run ticks until sim->tick == until_tick or an early stop (CRS_RUN_*). */
int crs_sim_run(crs_sim *sim, int64_t until_tick);
/* Encoder counts of a motor angle relative to the rest pose (288 000 counts per revolution). */
int64_t crs_encoder_counts(double motor_rad, double rest_motor_rad);
/* The framework's safety envelope on motor angles (rad): 1 when outside. */
int crs_outside_envelope(const double enc_rad[3]);
/* Which framework-used symbols the lab file defines: a bit per CRS_LAB_HAS_*. */
enum {
    CRS_LAB_HAS_LAB = 1, CRS_LAB_HAS_PRINTING = 2, CRS_LAB_HAS_UARTPRINT = 4,
    CRS_LAB_HAS_OFFSET2 = 8, CRS_LAB_HAS_OFFSET3 = 16, CRS_LAB_HAS_PLOTVARS = 32
};
int crs_lab_symbols(void);

#endif
