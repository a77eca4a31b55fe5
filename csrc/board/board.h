/* The emulated CRS board and its simulation loop: what runs every 1 ms tick.
 *
 * The board is trusted C: the framework's tick, the hold controller, the safety envelope, the
 * clamp, the motor board, the drive, the serial lines, the host ports, MuJoCo's step. It calls the
 * firmware (the lab file linked with the framework's stand-ins, csrc/firmware) through its port
 * (firmware_port.h): a WebAssembly module run by wasmtime (firmware_wasm.c, compiled into
 * crslab._core), or the same firmware linked natively into one shared object with the board
 * (firmware_native.c: crslab debug, --sanitize, --native). Python drives it in chunks of ticks
 * (crslab/worker/main.py). Everything the tick needs lives in caller-owned structs.
 *
 * Time: tick k happens at t = k ms. It sees the plant state after k physics steps of 1 ms, runs
 * the framework (and lab() once the startup gate is open), then the plant steps to t = k+1 ms.
 * Read by cffi (ABI mode): plain declarations only. */
#ifndef CRSLAB_BOARD_H
#define CRSLAB_BOARD_H

#include <stdint.h>

#include "firmware_board.h"
#include "drive.h"
#include "friction.h"
#include "hand.h"
#include "plant_faults.h"
#include "push.h"
#include "world.h"

/* Shared-memory block the worker writes and the crslab process reads, even after a crash. */
enum { CRS_SERIAL_CAPACITY = 4194304, CRS_MARK_CAPACITY = 65536, CRS_PRINT_CAPACITY = 65536 };
enum { CRS_PHASE_IDLE = 0, CRS_PHASE_LAB = 1, CRS_PHASE_PRINTING = 2, CRS_PHASE_PHYSICS = 3,
       CRS_PHASE_LOADING = 4 /* the firmware is being loaded: its constructors run */ };
enum { CRS_REFUSAL_TEXT = 256 };
enum { CRS_FIRST_OVER_TICKS = 8 }; /* the ticks of this many first lab() calls over the budget are kept */

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

/* The board's serial transmit line: characters serial_printf queued (in the transmit ring, the
 * SCI's FIFO and its shift register) that have not fully left the board yet. They leave back to
 * back at the baud rate. Line time: 1 ms = CRS_SERIAL_BAUD units, so one character takes
 * CRS_TICKS_PER_S * CRS_SERIAL_BITS_PER_CHAR units (framework_facts.h). */
typedef struct {
    int64_t head_done;  /* line time at which queue[first] has fully left */
    uint32_t first;     /* index of the oldest queued character */
    uint32_t len;       /* queued characters */
    char queue[CRS_LINE_QUEUE_CAPACITY];
} crs_serial_line;

/* A host port (SerialB: Simulink, SerialC: MATLAB; csrc/board/host_ports.h) in the shared block.
 * Between chunks the crslab process puts what the host sent in inbox[] and takes out[]; inside a
 * chunk the board moves the inbox onto the receive line (from the next tick to run on, at the
 * baud rate), answers, and sends its replies through the port's transmit ring and line. */
enum { CRS_HOST_PORT_B = 0, CRS_HOST_PORT_C = 1, CRS_HOST_PORTS = 2 };
enum { CRS_HOST_INBOX_CAPACITY = 4096, CRS_HOST_OUT_CAPACITY = 262144 };
typedef struct {
    uint32_t inbox_len;     /* bytes in inbox[]: the host sent them; the next tick puts them on rx */
    int32_t wedged;         /* SerialC: 1 once its receiver took a length byte of 0 or 1 */
    int64_t wedged_tick;    /* ... at this tick */
    uint64_t out_len;       /* bytes in out[] that left the board, not yet taken by the reader */
    uint64_t out_dropped;   /* bytes lost: more left within one chunk than out[] holds */
    int64_t tx_dropped;     /* reply bytes the transmit ring had no room for (dropped, as on the board) */
    int64_t tx_first_drop_tick; /* the first tick that dropped any (valid when tx_dropped > 0) */
    crs_serial_line rx;     /* the host's bytes on their way in (the queue holds what arrives) */
    crs_serial_line tx;     /* replies in the transmit ring, FIFO and shift register */
    char inbox[CRS_HOST_INBOX_CAPACITY];
    char out[CRS_HOST_OUT_CAPACITY];
} crs_host_port;

/* The scope log (rerun, CSV, the contest's card): one row per logged tick (every tick, or every
 * tick divisible by crs_board_config.log_every_ticks), each column an array of its own, in the
 * shared block: the board writes a tick's row, then counts it, so the reader has every row of
 * every tick that ran, even when the worker died after it (crslab/run/shared_block.py takes them
 * between chunks and sets count back to 0). A chunk that fills it ends early (CRS_RUN_LOG_FULL). */
enum { CRS_LOG_CAPACITY = 20000 }; /* rows: the longest chunk crslab asks for (crslab/run/pacing.py) */
typedef struct {
    int64_t count;                               /* rows written since the reader last took them */
    int64_t tick[CRS_LOG_CAPACITY];
    double enc_rad[3 * CRS_LOG_CAPACITY];        /* what lab() received (motor angles, rad) */
    double tau_lab[3 * CRS_LOG_CAPACITY];        /* the lab's tau variables after lab(), command units */
    double tau_applied[3 * CRS_LOG_CAPACITY];    /* what reached the motors, command units */
    double plot[4 * CRS_LOG_CAPACITY];           /* Simulink_PlotVar1..4 after lab() */
    int32_t safety[CRS_LOG_CAPACITY];            /* the safety flag */
    uint32_t leds[CRS_LOG_CAPACITY];             /* bit 0: GPIO34 (control card), bit 1: GPIO60 (e-stop box) */
    int32_t motor_board_off[CRS_LOG_CAPACITY];   /* 1: the motor board has cut every output */
    int32_t pad;
    double qpos_dh_rad[3 * CRS_LOG_CAPACITY];    /* the true plant joint angles (DH, rad) */
    double ee[3 * CRS_LOG_CAPACITY];             /* the end effector x y z by the course's FK, m */
    double push_force[3 * CRS_LOG_CAPACITY];     /* the push's force, world frame, N */
    double world[CRS_WORLD_ROW * CRS_LOG_CAPACITY]; /* the world's quantities (world.h), in a world
                                                      with fixtures */
} crs_scope_log;

typedef struct {
    int64_t tick;       /* tick being run (or next to run when idle) */
    int32_t phase;      /* CRS_PHASE_*: where the worker is */
    int32_t stop;       /* set by the crslab process (a page's Stop, a page that closed): the board
                           ends its chunk before the next tick (CRS_RUN_STOPPED), and a call running
                           now is ended (CRS_FW_TRAP_STOPPED) */
    uint64_t serial_len;    /* bytes in serial[] not yet taken by the reader */
    uint64_t serial_dropped; /* bytes lost: more left the board in one chunk than serial[] or the marks hold */
    uint32_t mark_count;    /* entries in mark_tick/mark_offset */
    uint32_t print_count;   /* entries in print_tick/print_chars */
    crs_refusal refusal;    /* what the sandbox refused, if anything */
    int64_t mark_tick[CRS_MARK_CAPACITY];   /* a tick whose millisecond carried bytes off the board ... */
    uint64_t mark_offset[CRS_MARK_CAPACITY]; /* ... and where those bytes start in serial[] */
    int64_t print_tick[CRS_PRINT_CAPACITY];   /* the tick of a serial_printf the ring took bytes of ... */
    uint32_t print_chars[CRS_PRINT_CAPACITY]; /* ... and how many (they leave in order, after the
                                                  bytes of the serial_printf before it) */
    crs_serial_line line;   /* what is still on its way out (taken by the reader when a run ends) */
    char serial[CRS_SERIAL_CAPACITY]; /* every byte that left the board, in order */
    crs_host_port host_ports[CRS_HOST_PORTS]; /* SerialB and SerialC */
    crs_scope_log log;      /* the scope rows of the ticks run since the reader last took them */
} crs_shared;

/* The framework's hold controller (docs/framework.md section 4), in the DSP's float arithmetic. */
typedef struct {
    float ref_rad[3];            /* references (motor angles), 0 at power-up */
    float prev_enc_rad[3];       /* last tick's angles, 0 at power-up */
    float vel_old1_rad_s[3];     /* the last two averaged velocities */
    float vel_old2_rad_s[3];
    float out[3];                /* this tick's output, command units */
} crs_hold;

/* The motor board between the framework's commands and the amplifiers (framework_facts.h): what
 * it holds (its model, CRS_MOTOR_BOARD_*, is crs_board_config.motor_board). */
enum { CRS_MB_EVENT_CAPACITY = 64 };
typedef struct {
    int32_t off;                 /* 1: every output is cut this tick */
    int32_t cause_joint;         /* while off: 1..3, the joint over the limit; 0: no command */
    int32_t since_command;       /* ms since the last command arrived */
    int32_t over_ticks[3];       /* consecutive commands over the limit, per joint */
    double held_units[3];        /* the last command that arrived, command units (whole counts) */
    double out_units[3];         /* what the amplifiers get: held_units, or 0 while off */
    int64_t cutouts;             /* cut-outs so far */
    uint32_t event_count;        /* cut-outs starting or ending since the reader last looked */
    uint32_t pad2;
    int64_t event_tick[CRS_MB_EVENT_CAPACITY];
    int32_t event_joint[CRS_MB_EVENT_CAPACITY]; /* cause_joint of the cut-out */
    int32_t event_off[CRS_MB_EVENT_CAPACITY];   /* 1: the cut-out starts; 0: it ends */
} crs_motor_board;

/* The emulated C28x data memory (csrc/board/c28x_memory.h): the lab's globals at the 16-bit-word
 * addresses the TI linker would give them (crslab/lab/c28x_memory.py lays them out), each
 * read and written in its C28x representation. Filled by the worker once the lab is loaded. */
enum {
    CRS_MEM_SIGNED = 0,   /* a signed integer: its low 16 * words bits */
    CRS_MEM_UNSIGNED = 1, /* an unsigned integer: the same bits, zero-extended when written back */
    CRS_MEM_FLOAT = 2,    /* IEEE: 2 words hold a float (the C28x's double too), 4 a long double */
    CRS_MEM_BOOL = 3,     /* a _Bool: one word, 0 or 1 */
    CRS_MEM_OPAQUE = 4    /* a pointer or a variable crslab cannot reach: reads 0, writes ignored */
};
typedef struct {
    uint32_t address;     /* its first 16-bit word (C28x data address) */
    uint32_t count;       /* elements */
    uint32_t words;       /* C28x words per element: 1, 2 or 4 */
    uint32_t host_bytes;  /* bytes per element in the worker */
    int32_t kind;         /* CRS_MEM_* */
    int32_t writable;     /* 0: const (read-only memory in the worker) */
    void *host;           /* the variable in the worker; NULL: not reachable (reads 0) */
} crs_mem_var;
typedef struct {
    uint32_t count;       /* entries of vars: sorted by address, not overlapping */
    uint32_t pad;
    crs_mem_var *vars;
} crs_c28x_memory;

/* The receivers of the host ports, as the framework's RX interrupts keep them (docs/host-tools.md,
 * "The protocols byte by byte"); room for more than the board keeps (framework_facts.h). */
enum { CRS_MATLAB_BUFFER = 256, CRS_MATLAB_ECHO_BUFFER = 64, CRS_SIMULINK_BUFFER = 16 };
typedef struct {
    int32_t receiving;    /* 1 after a '*': counting the message */
    int32_t length;       /* receivelength: the length byte minus 1 */
    int32_t count;        /* bytes since the '*' (the length byte is the first) */
    int32_t wedged;       /* 1: the count can never reach the length (a length byte of 0 or 1) */
    uint32_t echo_count;  /* '0' echo: addresses sampled so far in this message */
    uint32_t pad;
    uint32_t echo_address[CRS_MATLAB_ECHO_BUFFER]; /* as received (big-endian on the wire) */
    uint32_t echo_value[CRS_MATLAB_ECHO_BUFFER];   /* the 32 bits at each, when its last byte came */
    uint8_t message[CRS_MATLAB_BUFFER];            /* UARTMessageArray: the payload, command first */
} crs_matlab_rx;
typedef struct {
    int32_t check_first;  /* checkfirstcommandbyte: 1 once a byte was taken outside a packet */
    int32_t receiving;    /* 1 after FF 7F: counting the packet's data bytes */
    int32_t count;
    int32_t pad;
    uint8_t data[CRS_SIMULINK_BUFFER];
} crs_simulink_rx;

/* Where the board finds the firmware's variables: pointers into the firmware's memory, checked
 * to lie inside it when the firmware was loaded (firmware_port.h); NULL where the lab defines no
 * such symbol. The firmware may write anything there: the board reads it as data. */
typedef struct {
    float *tau;                  /* [3]: the lab's persistent torque variables, command units */
    float *offset_enc2;          /* offset_Enc2_rad, rad */
    float *offset_enc3;          /* offset_Enc3_rad, rad */
    float *plot[4];              /* Simulink_PlotVar1..4 */
    uint32_t *gpio;              /* GpioDataRegs: GPA DAT SET CLEAR TOGGLE, GPB DAT SET CLEAR TOGGLE */
    int32_t *simulink_input[7];  /* SIMU_Var1..7_fromSIMU_16bit (int: 32 bits in the firmware) */
    float *matlab_lock;          /* Gen A's matlabLock */
    int32_t symbols;             /* CRS_LAB_HAS_* */
    int32_t pad;
} crs_fw_view;

enum { CRS_FW_TRAP_TEXT = 16384 }; /* room for the C library's frames above the lab's (long paths) */
typedef struct {
    int32_t kind;                /* CRS_FW_TRAP_* */
    int32_t phase;               /* CRS_PHASE_* it happened in */
    int64_t tick;
    int32_t exit_code;           /* CRS_FW_TRAP_EXIT: the code passed to exit() */
    int32_t line;                /* the lab file's line, when a check compiled into the lab said (0: not) */
    char text[CRS_FW_TRAP_TEXT];    /* wasmtime's message and the firmware's frames, or what a refused
                                    call tried; NUL-terminated, untrusted text */
} crs_fw_trap;

/* What lab()'s cost is counted in (crs_board.cost_unit). */
enum {
    CRS_COST_NS = 0,             /* native firmware: the time lab() took, ns (monotonic clock) */
    CRS_COST_INSTRUCTIONS = 1    /* WebAssembly firmware: instructions executed (wasmtime's fuel) */
};

/* Why crs_board_run returned. */
enum {
    CRS_RUN_DONE = 0,        /* reached until_tick */
    CRS_RUN_SERIAL_FULL = 1, /* serial buffer or marks more than half full: drain and go on */
    CRS_RUN_LOG_FULL = 2,    /* scope log full: drain and go on */
    CRS_RUN_NAN_STRICT = 3,  /* a NaN/Inf torque in strict mode */
    CRS_RUN_PRINTF_OVERFLOW = 4, /* a serial_printf overflowed the board's format buffer */
    CRS_RUN_EVENTS_FULL = 5, /* motor-board events full: take them and go on */
    CRS_RUN_TRAPPED = 6,     /* the firmware stopped (crs_board.trap says how) */
    CRS_RUN_CUT = 7,         /* the chunk had its share of a worker its boards share: go on later */
    CRS_RUN_STOPPED = 8,     /* the crslab process asked the board to stop (crs_shared.stop) */
    CRS_RUN_BREAK = 9        /* crslab debug --break-when: its condition holds before this tick */
};

/* Debugging (crslab debug, csrc/board/debug.c): all off when zero. */
typedef struct {
    int32_t break_when;          /* 1: end the run before the first tick whose lab() call begins
                                  * with the lab's crs_debug_condition() true (once) */
    int32_t trap_fp;             /* 1: an operation in lab() that makes a NaN or an Inf raises SIGFPE */
} crs_debug;

typedef void (*crs_mj_step_fn)(const void *model, void *data);

/* The MuJoCo model and data a board steps, and the arrays of the data it reads and writes. */
typedef struct {
    const void *model;
    void *data;
    crs_mj_step_fn step;
    const double *qpos;                /* j1..j3 DH angles, rad */
    const double *qvel;                /* rad/s */
    double *ctrl;                      /* motor1..3 torques the drive delivers, with the sliding
                                          friction on each motor, command units (gear: N.m/unit) */
    double *qfrc_applied;              /* the hand's and the push's forces on j1..j3, N.m */
} crs_board_plant;

/* What a run is configured with, as MuJoCo's mjModel is: set before the first tick (the
 * generation by crs_board_init, the cost unit and the row by the firmware's port, the rest by
 * crs_board_configure, in one assignment) and only read by a tick; a scenario's friction event
 * changes the friction between chunks, as a scenario edits MuJoCo's model. */
typedef struct {
    int32_t generation;          /* the id of a row of generations.c (0 until set: no row) */
    int32_t strict_nan;          /* 1: a NaN/Inf torque stops the run */
    const struct crs_generation *gen; /* its row (generations.h), once the firmware's port checked it */
    int64_t startup_ticks;       /* lab() first runs at this tick (CRS_STARTUP_TICKS, or 0) */
    double rest_motor_rad[3];    /* true resting pose the encoders were zeroed at */
    int64_t budget;              /* lab()'s budget per call, in cost_unit, for the overrun count */
    int32_t time_lab;            /* 1: count every lab() call's cost (and let a hang be seen) */
    int32_t cost_unit;           /* CRS_COST_*: set by the firmware's port */
    int64_t log_every_ticks;     /* the scope log keeps the ticks divisible by this (1: every
                                    tick; 0: no log) */
    crs_debug debug;
    int32_t motor_board;         /* CRS_MOTOR_BOARD_*: NONE passes commands through */
    int32_t pad;
    crs_drive_config drive;
    crs_friction friction;       /* the sliding friction beyond the static band */
    crs_hand_config hand;
} crs_board_config;

/* The board: what it is configured with (config), what it steps (plant, world) and what its ticks
 * change (the rest), as MuJoCo's mjData. */
typedef struct {
    crs_board_config config;
    crs_board_plant plant;       /* MuJoCo's model and data, views of their arrays (owned by Python) */

    /* framework state */
    int64_t tick;                /* next tick to run */
    float tau[3];                /* the lab's persistent torque variables, command units */
    int32_t safety_flag;         /* this tick's envelope flag, passed as `error` next tick */
    double enc_rad[3];           /* this tick's encoder angles */
    double command[3];           /* command units the framework sent the motor board this tick */
    double applied[3];           /* command units that reached the amplifiers this tick */
    int32_t estop_latched;       /* wrist e-stop: every output latched to zero */
    uint32_t leds;               /* bit 0: GPIO34 high, bit 1: GPIO60 high */
    crs_hold hold;

    /* diagnostics */
    int64_t lab_calls;
    int64_t lab_cost_total, lab_cost_max, lab_max_tick; /* lab()'s cost, in cost_unit */
    int64_t over_budget;         /* calls that cost more than budget */
    int64_t first_over_tick[CRS_FIRST_OVER_TICKS]; /* the ticks of the first calls that overran */
    int64_t nan_first_tick;      /* -1 until a NaN/Inf torque is seen */
    int32_t nan_first_joint;     /* 1..3 */
    int32_t nan_count;
    int64_t printing_runs;
    int64_t print_triggers;      /* ticks whose lab() triggered printing (SWI post, UARTprint) */
    int64_t safety_trips;        /* ticks the arm went outside the safety envelope (from inside):
                                    the framework's hold took over the torques from then on */
    int64_t safety_first_tick;   /* -1 until the first of them */
    int64_t safety_ticks;        /* ticks outside the envelope, in all (the hold's torques applied) */
    int64_t tx_dropped;          /* characters the transmit ring had no room for */
    int64_t tx_first_drop_tick;  /* -1 until one is dropped */
    int64_t overflow_tick;       /* -1 until a serial_printf overflows the format buffer */
    uint32_t overflow_chars;     /* how many characters that serial_printf formatted */
    int32_t overflow_phase;      /* CRS_PHASE_LAB or CRS_PHASE_PRINTING */
    int64_t console_bytes;       /* what the firmware wrote with printf/puts (CCS's console on the
                                    real board, not Tera Term): counted, never shown */
    crs_fw_trap trap;               /* how the firmware stopped, when crs_board_run says CRS_RUN_TRAPPED */

    /* the firmware */
    crs_fw_view fw;
    void *firmware;              /* its port's state (firmware_wasm.c); NULL for a native firmware */

    crs_shared *shared;
    crs_faults faults;
    crs_hand hand;
    crs_push push;
    crs_motor_board motor_board;
    crs_drive drive;
    crs_world world;             /* what the world's fixtures feel (csrc/plant/world.h) */

    /* the host ports: the lab's variables in C28x memory, and the two receivers */
    crs_c28x_memory memory;
    crs_matlab_rx matlab;
    crs_simulink_rx simulink;
} crs_board;

/* Zero everything and set the defaults (startup gate at CRS_STARTUP_TICKS, no motor board, ...;
 * no generation: the caller sets board->config.generation); the firmware's port then sets the view
 * and the cost unit. */
void crs_board_defaults(crs_board *board);
/* Run ticks until board->tick == until_tick or an early stop (CRS_RUN_*). */
int crs_board_run(crs_board *board, int64_t until_tick);
/* Encoder counts of a motor angle relative to the rest pose (CRS_ENCODER_COUNTS_PER_REV). */
int64_t crs_encoder_counts(double motor_rad, double rest_motor_rad);
/* The framework's safety envelope on motor angles (rad): 1 when outside. */
int crs_outside_envelope(const double enc_rad[3]);


#endif
