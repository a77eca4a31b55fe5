/* The course framework's numbers, written once (docs/framework.md sections 2 to 9, each with its
 * public source).
 *
 * Everything the real framework, its serial port and the motor board do by number lives here:
 * the emulated board (csrc/board) uses these values, and Python reads them through cffi
 * (crslab._core, API mode; crslab/framework_facts.py names them for Python). Plain
 * declarations only: cffi reads this file (crslab/cheaders.py drops the initialisers). */
#ifndef CRSLAB_FRAMEWORK_FACTS_H
#define CRSLAB_FRAMEWORK_FACTS_H

/* The 1 ms tick. */
enum {
    CRS_TICKS_PER_S = 1000,              /* the framework's timer interrupt: one tick a millisecond */
    CRS_STARTUP_TICKS = 4100,            /* first lab() call at 4.1 s; before it nothing reaches
                                            the motors (the brake releases at 4.0 s) */
    CRS_ENCODER_COUNTS_PER_REV = 288000  /* joints 1-3, per motor revolution (72:1 drive) */
};
static const double CRS_CLAMP_UNITS = 5.0; /* every command is clamped to +-5 command units */

/* The framework's hold controller (runs every tick from tick 0; its output is used outside the
 * safety envelope). Per joint: u = Kp e - Kd v, e = reference - angle (rad), v the velocity
 * averaged recursively over three ticks (rad/s). */
static const double CRS_HOLD_KP_FAR = 15.0;        /* units/rad when |e| > CRS_HOLD_KP_SWITCH_RAD */
static const double CRS_HOLD_KP_NEAR = 25.0;       /* units/rad when |e| <= CRS_HOLD_KP_SWITCH_RAD */
static const double CRS_HOLD_KP_SWITCH_RAD = 0.1;  /* error threshold between the two gains */
static const double CRS_HOLD_KD = 1.0;             /* units s/rad */
static const double CRS_HOLD_REANCHOR_RAD = 0.15;  /* outside the envelope, a reference farther than
                                                      this from its angle moves to the angle */
static const double CRS_TICK_S = 0.001;            /* 1 / CRS_TICKS_PER_S: one tick, s (also the
                                                      velocity's backward difference step) */

/* The wrist (joint 5) e-stop: from 4.1 s on, a wrist more than this from its hold reference
 * latches every output to zero. */
static const double CRS_WRIST_ESTOP_RAD = 0.11;

/* The motor board (Piccolo firmware, Gen B era hardware) between the framework and the
 * amplifiers. Commands arrive each ms as PWM counts. */
enum {
    CRS_MB_COUNTS_PER_UNIT = 300,  /* +-10 units = +-3000 counts */
    CRS_MB_REJECT_COUNTS = 1500,   /* |counts| above this is a bad message (|u| > 5) */
    CRS_MB_LIMIT_COUNTS = 1200,    /* |counts| above this (|u| > 4) ... */
    CRS_MB_OVER_LIMIT_TICKS = 500, /* ... on one joint for this many consecutive ms cuts every
                                      output until that joint's command is back within the limit */
    CRS_MB_TIMEOUT_TICKS = 100     /* no command for this many ms cuts every output */
};
/* Which motor-board model sits between the framework and the arm. */
enum {
    CRS_MOTOR_BOARD_NONE = 0,    /* Gen A's older hardware: undocumented, modelled as a wire */
    CRS_MOTOR_BOARD_PICCOLO = 1  /* the Gen B era Piccolo board */
};

/* Serial port SCI-A (serial_printf to Tera Term): a format buffer, a transmit ring that the TX
 * interrupt moves into the SCI's hardware FIFO, and its shift register, sent at the baud rate.
 * A serial_printf that formats as many characters as its buffer holds, or more, overflows it
 * (the terminating NUL has no room); characters that do not fit the ring are dropped. The buffer's
 * and the ring's sizes are the generation's (generations.c). */
enum {
    CRS_SCI_TX_FIFO = 16,           /* chars in the SCI's hardware FIFO */
    CRS_SCI_TX_SHIFT = 1,           /* the char being sent, in the shift register */
    CRS_SERIAL_BAUD = 115200,       /* bits/s */
    CRS_SERIAL_BITS_PER_CHAR = 10   /* 8N1: start bit, 8 data bits, stop bit; 11.52 chars per ms */
};

/* The host ports (docs/framework.md section 8; the bytes in docs/host-tools.md): SCI-B carries the
 * Simulink link, SCI-C the MATLAB variable protocol, both at CRS_SERIAL_BAUD through a transmit
 * ring of their own (its size the generation's: generations.c) in front of the SCI's FIFO and
 * shift register; the host always talks first. */
enum {
    CRS_MATLAB_START = 0x2A,         /* '*': a MATLAB message starts; its next byte counts it all */
    CRS_MATLAB_MESSAGE_CHARS = 101,  /* UARTMessageArray: the payload a message can hold */
    CRS_MATLAB_ECHO_ADDRESSES = 10,  /* Main_address (MAX_VAR_NUM): addresses a '0' echo keeps */
    CRS_SIMULINK_SYNC_1 = 0xFF,      /* a Simulink packet starts FF 7F (int16 0x7FFF, little-endian) */
    CRS_SIMULINK_SYNC_2 = 0x7F,
    CRS_SIMULINK_INPUTS = 7,         /* int16 values per packet, into SIMU_Var1..7_fromSIMU_16bit */
    CRS_SIMULINK_PLOTS = 4,          /* int32 values per reply: Simulink_PlotVar1..4 */
    CRS_SIMULINK_SCALE = 10000,      /* each PlotVar is sent as int32(10000 * value) */
    CRS_SIMULINK_PERIOD_MS = 5       /* the course's model sends a packet every 5 ms */
};

/* The F28335's data memory the course's linker command files give a lab's globals: the SARAM
 * blocks L1 to L7 on page 1 (4 K words each; TI's F28335 data sheet, memory map). A lab whose
 * sections end past it does not link on the real board, nor in crslab. 16-bit-word addresses. */
enum { CRS_DATA_RAM_START = 0x9000, CRS_DATA_RAM_END = 0x10000 };

/* What crslab lets one lab() call cost by default, in WebAssembly instructions: the F28335 has
 * 150 000 cycles per 1 ms tick, about half of which the framework leaves lab() before the next
 * tick's SPI read finds the last one unfinished; one instruction is counted as one cycle (see
 * docs/sandbox.md for what that comparison is worth). */
enum { CRS_LAB_BUDGET_INSTRUCTIONS = 75000, CRS_CPU_CYCLES_PER_TICK = 150000 };

/* The course's small printf (CRS_FORMATTER_SMALL, generations.h): precision of a bare %f. */
enum { CRS_SMALL_PRINTF_PRECISION = 5 };

/* The control card's LEDs at power-up: GPIO34 and GPIO60 start high (bits of the board's LED
 * word: bit 0 GPIO34, bit 1 GPIO60). */
enum { CRS_LEDS_AT_START = 3 };

#endif
