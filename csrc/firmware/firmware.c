/* The framework's stand-ins that a lab file links against, and the firmware's entry points
 * (firmware.h): what the course framework does around lab() on the real board, inside the firmware.
 * The board (csrc/board) does the rest: encoders, safety envelope, hold controller, clamp, motor
 * board, serial line, timer. */
#include "firmware.h"

#include <stddef.h>
#include <stdint.h>

#include "DSP2833x_Device.h"
#include "coecsl.h"
#include "firmware_board.h"
#include "framework_facts.h"
#include "generations.h"

/* The lab's int. The WebAssembly firmware compiles the lab with the C28x's widths, where an int is
 * 16 bits (crslab/lab/c28x_ir.py); a native build compiles it with the host's. */
#if defined(__wasm__)
typedef int16_t crs_lab_int;
#else
typedef int crs_lab_int;
#endif

/* ---- the lab file's symbols (weak: a lab may lack some) ----------------------------------- */
/* lab() and printing() are called through these, compiled into the lab's own translation unit
 * after its definitions (crslab/lab/entry_points.py): each passes the framework's arguments to the
 * function as the lab defines it (six parameters, none, K&R style), as the C28x's calling convention
 * lets the real framework call it through its own seven-parameter declaration. Absent when the lab
 * does not define the function. */
extern void crs_lab_call_lab(float theta1motor, float theta2motor, float theta3motor, float *tau1,
                             float *tau2, float *tau3, int error) __attribute__((weak));
extern void crs_lab_call_printing(void) __attribute__((weak));
extern crs_lab_int UARTprint __attribute__((weak));
extern float offset_Enc2_rad __attribute__((weak));
extern float offset_Enc3_rad __attribute__((weak));
extern float Simulink_PlotVar1 __attribute__((weak));
extern float Simulink_PlotVar2 __attribute__((weak));
extern float Simulink_PlotVar3 __attribute__((weak));
extern float Simulink_PlotVar4 __attribute__((weak));

/* ---- the framework's objects a lab file names --------------------------------------------- */
SWI_Obj SWI_printf;
volatile struct GPIO_DATA_REGS GpioDataRegs;
volatile unsigned int IFR, IER; /* named by labs (IER |= M_INT1); nothing reads them */

/* What Simulink sends down to the board: seven int16 values, which the course framework keeps in
 * these globals (the names of its Gen B serial code). A lab reads them by declaring
 * `extern int SIMU_Var1_fromSIMU_16bit;`. On the DSP `int` is 16 bits, so the values stay in int16
 * range. Weak, so a lab file that defines one of these names keeps its own (in the WebAssembly
 * firmware the lab's unit defines them all, in their place in .ebss: crslab/lab/c28x_ir.py).
 * The board writes 32-bit numbers (csrc/board/simulink_link.c, when a Simulink packet arrives, and
 * a scenario between ticks) into `simulink_written`; before each lab() call a value written since
 * the last call is stored into the lab's int, as the board's serial interrupt stores it. */
__attribute__((weak)) crs_lab_int SIMU_Var1_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var2_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var3_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var4_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var5_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var6_fromSIMU_16bit = 0;
__attribute__((weak)) crs_lab_int SIMU_Var7_fromSIMU_16bit = 0;
static int32_t simulink_written[CRS_FW_SIMULINK_INPUTS]; /* what the board wrote */
static int32_t simulink_stored[CRS_FW_SIMULINK_INPUTS];  /* what was last stored into the lab's */

/* Gen A's framework variable in .my_vars, set to 1.0 by every MATLAB read (csrc/board/matlab_link.c)
 * and used by nothing else. Weak: a lab that defines the name keeps its own. */
__attribute__((weak)) float matlabLock = 0.0f;

#if defined(__wasm32__)
/* the board reads the table as 32-bit words (csrc/board/firmware_wasm.c) */
_Static_assert(sizeof(crs_fw_table) == 18 * 4, "crs_fw_table is 18 words in WebAssembly");
#endif

static float tau[3];          /* the lab's torque variables: they persist between calls */
/* What the lab's generation's row says the firmware does, copied when it starts (0 before). Plain
 * numbers, read through a switch: a lab that scribbles over them stops printing, and never sends
 * the firmware through a wild pointer. */
static int32_t print_trigger; /* CRS_PRINT_* */
static int32_t formatter;     /* CRS_FORMATTER_* */
static crs_fw_table table;

int32_t crs_fw_formatter(void) { return formatter; }

void SWI_post(SWI_Handle swi) { swi->posted = 1; }

void mains_code(void)
{
    /* On the board this never returns: it starts the 1 kHz loop and the idle loop. crslab's board
     * runs that loop itself, so a 2024-style main() calling mains_code() is never called. */
}

static uintptr_t address(const volatile void *p) { return (uintptr_t)p; }

const crs_fw_table *crs_fw_start(int32_t gen)
{
    const crs_generation *row = crs_generation_of(gen);
    if (crs_generation_problem(row) != NULL) return NULL;
    print_trigger = row->print_trigger;
    formatter = row->formatter;
    /* the control card's LEDs start high: GPIO34 is bit 2 of the GPB registers, GPIO60 bit 28 */
    const uint32_t leds = CRS_LEDS_AT_START;
    GpioDataRegs.GPBDAT.all = ((leds & 1u) << 2) | (((leds >> 1) & 1u) << 28);
    SWI_printf.posted = 0;

    int32_t has = 0;
    if (crs_lab_call_lab != NULL) has |= CRS_LAB_HAS_LAB;
    if (crs_lab_call_printing != NULL) has |= CRS_LAB_HAS_PRINTING;
    if (&UARTprint != NULL) has |= CRS_LAB_HAS_UARTPRINT;
    if (&offset_Enc2_rad != NULL) has |= CRS_LAB_HAS_OFFSET2;
    if (&offset_Enc3_rad != NULL) has |= CRS_LAB_HAS_OFFSET3;
    const float *plots[CRS_FW_PLOTS] = {&Simulink_PlotVar1, &Simulink_PlotVar2, &Simulink_PlotVar3,
                                        &Simulink_PlotVar4};
    if (plots[0] != NULL && plots[1] != NULL && plots[2] != NULL && plots[3] != NULL) {
        has |= CRS_LAB_HAS_PLOTVARS;
    }
    table.symbols = has;
    table.tau = address(tau);
    table.offset_enc2 = address(&offset_Enc2_rad);
    table.offset_enc3 = address(&offset_Enc3_rad);
    for (int i = 0; i < CRS_FW_PLOTS; ++i) table.plot[i] = address(plots[i]);
    table.gpio = address(&GpioDataRegs);
    for (int i = 0; i < CRS_FW_SIMULINK_INPUTS; ++i) {
        simulink_written[i] = simulink_stored[i] = 0;
        table.simulink_input[i] = address(&simulink_written[i]);
    }
    table.matlab_lock = address(&matlabLock);
    return &table;
}

/* The values the board wrote since the last call, stored into the lab's ints. */
static void store_simulink_inputs(void)
{
    static crs_lab_int *const inputs[CRS_FW_SIMULINK_INPUTS] = {
        &SIMU_Var1_fromSIMU_16bit, &SIMU_Var2_fromSIMU_16bit, &SIMU_Var3_fromSIMU_16bit,
        &SIMU_Var4_fromSIMU_16bit, &SIMU_Var5_fromSIMU_16bit, &SIMU_Var6_fromSIMU_16bit,
        &SIMU_Var7_fromSIMU_16bit};
    for (int i = 0; i < CRS_FW_SIMULINK_INPUTS; ++i) {
        if (simulink_written[i] != simulink_stored[i]) {
            simulink_stored[i] = simulink_written[i];
            *inputs[i] = (crs_lab_int)simulink_written[i];
        }
    }
}

int32_t crs_fw_lab(float theta1motor, float theta2motor, float theta3motor, int32_t error)
{
    store_simulink_inputs();
    if (crs_lab_call_lab == NULL) return 0;
    crs_lab_call_lab(theta1motor, theta2motor, theta3motor, &tau[0], &tau[1], &tau[2], (int)error);
    /* after lab() returns: Gen A's SWI runs printing() once however often it was posted; Gen B's
     * idle loop sees UARTprint at 1, clears it and calls printing() */
    switch (print_trigger) {
    case CRS_PRINT_SWI_POST:
        if (SWI_printf.posted) {
            SWI_printf.posted = 0;
            return 1;
        }
        return 0;
    case CRS_PRINT_UARTPRINT:
        if (&UARTprint != NULL && UARTprint == 1) {
            UARTprint = 0;
            return 1;
        }
        return 0;
    default: /* not started, or the lab wrote over print_trigger */
        return 0;
    }
}

void crs_fw_printing(void)
{
    if (crs_lab_call_printing != NULL) crs_lab_call_printing();
}

#if defined(__wasm__)
/* The check the WebAssembly build compiles the lab with (clang's -fsanitize=null, without its
 * run-time library): clang passes where in the source the check failed. On the F28335 a NULL
 * pointer does not stop the board (address 0 is RAM, M0); crslab stops the run at the line, as a
 * native build does (SIGSEGV), since it is never what the lab meant. (An integer division by zero
 * goes on as on the C28x: crslab/lab/c28x_arithmetic.py.) */
typedef struct {
    const char *file;
    uint32_t line, column;
} crs_ubsan_location;

void __ubsan_handle_type_mismatch_v1_abort(const crs_ubsan_location *where, uintptr_t pointer);
void __ubsan_handle_type_mismatch_v1_abort(const crs_ubsan_location *where, uintptr_t pointer)
{
    (void)pointer;
    crs_board_fault(CRS_FW_TRAP_NULL, (int32_t)where->line);
    __builtin_trap();
}
#endif
