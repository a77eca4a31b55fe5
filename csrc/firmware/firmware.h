/* The firmware: a lab file linked with the course framework's stand-ins (this folder), as the real
 * lab is linked with the framework into the image the F28335 runs.
 *
 * crslab's default build compiles the firmware to a WebAssembly module (crslab/lab/firmware.py)
 * that the board (csrc/board, run by crslab's worker) instantiates with wasmtime: the firmware
 * computes on its own memory and reaches the board only through the imports below. A native build
 * (crslab debug, --sanitize, --native) links the same firmware into one shared object with the
 * board (csrc/board/firmware_native.c).
 *
 * Every address here is an address in the firmware's own memory. Nothing the board trusts lives
 * there: the board reads the firmware's variables as data, within the firmware's memory. */
#ifndef CRSLAB_FIRMWARE_H
#define CRSLAB_FIRMWARE_H

#include <stdint.h>

#if defined(__wasm__)
#define CRS_FW_EXPORT(name) __attribute__((export_name(#name), visibility("default")))
#define CRS_FW_IMPORT(name) __attribute__((import_module("board"), import_name(#name)))
#else
#define CRS_FW_EXPORT(name)
#define CRS_FW_IMPORT(name)
/* The lab stopped on a check the WebAssembly build compiles into it (crslab/lab/firmware.py:
 * a NULL pointer dereferenced, an integer division by zero): `kind` is CRS_FW_TRAP_NULL,
 * CRS_FW_TRAP_DIVIDE or CRS_FW_TRAP_OVERFLOW (csrc/port/firmware_board.h), `line` the lab file's line. The board
 * ends the run; the call does not return. */
void crs_board_fault(int32_t kind, int32_t line) CRS_FW_IMPORT(fault);

#endif

/* Where the board finds the framework's variables, addresses in the firmware's memory (0: the lab
 * does not define that symbol). Built once when the firmware starts (crs_fw_start). */
enum { CRS_FW_PLOTS = 4, CRS_FW_SIMULINK_INPUTS = 7 };
typedef struct {
    uintptr_t tau;                    /* float[3]: the lab's persistent torque variables */
    uintptr_t offset_enc2, offset_enc3; /* float: the lab's offset_Enc2_rad, offset_Enc3_rad */
    uintptr_t plot[CRS_FW_PLOTS];     /* float: Simulink_PlotVar1..4 */
    uintptr_t gpio;                   /* GpioDataRegs: 8 uint32 registers (GPA DAT SET CLEAR TOGGLE,
                                         then GPB's) */
    uintptr_t simulink_input[CRS_FW_SIMULINK_INPUTS]; /* int: SIMU_Var1..7_fromSIMU_16bit */
    uintptr_t matlab_lock;            /* float: Gen A's matlabLock */
    int32_t symbols;                  /* CRS_LAB_HAS_* (csrc/port/firmware_board.h) of what the lab defines */
    int32_t pad;
} crs_fw_table;

/* ---- exports: what the board calls ------------------------------------------------------- */

/* Once, before the first tick: the framework generation (a row's id, csrc/port/generations.c)
 * decides how serial_printf formats and what asks for printing(); returns the table above, or NULL
 * when no row has that id or its row cannot run (crs_generation_problem). */
const crs_fw_table *crs_fw_start(int32_t generation) CRS_FW_EXPORT(crs_fw_start);
/* One lab() call with the encoder angles (rad) and the safety flag; the torques land in the
 * table's tau. Returns 1 when the lab asked for printing() as its generation does (its row's
 * print trigger, CRS_PRINT_*: SWI_post(&SWI_printf), or UARTprint set to 1; the request is
 * cleared), else 0. */
int32_t crs_fw_lab(float theta1motor, float theta2motor, float theta3motor, int32_t error)
    CRS_FW_EXPORT(crs_fw_lab);
/* printing(), once. */
void crs_fw_printing(void) CRS_FW_EXPORT(crs_fw_printing);

/* ---- inside the firmware ------------------------------------------------------------------ */

/* The formatter (CRS_FORMATTER_*) of the generation the firmware was started for; 0 before
 * crs_fw_start. */
int32_t crs_fw_formatter(void);

/* ---- imports: what the firmware asks of the board ----------------------------------------- */

/* serial_printf formatted `formatted` characters for port `port`; the first of them (all of them
 * when they fit the generation's format buffer) are at `chars`. The board queues them on the
 * serial line and returns how many its transmit ring took; when they overflow the format buffer it
 * stops the run instead (the real board's memory would be corrupt) and returns 0. */
#if defined(__wasm__)
int32_t crs_board_serial_send(int32_t port, const char *chars, uint32_t formatted)
    CRS_FW_IMPORT(serial_send);
#else
/* A native firmware reaches the board through the function its port hands it when it attaches
 * the board (csrc/board/firmware_native.c), as a WebAssembly one through its import: the firmware
 * calls no name of the board's. NULL until then (serial_port.c: nothing is sent). */
typedef int32_t (*crs_fw_serial_send_fn)(int32_t port, const char *chars, uint32_t formatted);
extern crs_fw_serial_send_fn crs_board_serial_send;
#endif

/* The lab stopped on a check the WebAssembly build compiles into it (crslab/lab/firmware.py:
 * a NULL pointer dereferenced, an integer division by zero): `kind` is CRS_FW_TRAP_NULL,
 * CRS_FW_TRAP_DIVIDE or CRS_FW_TRAP_OVERFLOW (csrc/port/firmware_board.h), `line` the lab file's line. The board
 * ends the run; the call does not return. */
void crs_board_fault(int32_t kind, int32_t line) CRS_FW_IMPORT(fault);

#endif
