/* The framework objects a lab file names, and what the board does with them. */
#define _POSIX_C_SOURCE 199309L

#include "board.h"

#include <stdarg.h>
#include <stdint.h>
#include <time.h>

#include "DSP2833x_Device.h"
#include "coecsl.h"
#include "framework_facts.h"
#include "serial_format.h"
#include "serial_line.h"

serial_t SerialA;
SWI_Obj SWI_printf;
volatile struct GPIO_DATA_REGS GpioDataRegs;
volatile unsigned int IFR, IER; /* named by labs (IER |= M_INT1), nothing on a host */

static crs_sim *board_sim; /* the one board of this process */

int64_t crs_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void crs_board_attach(crs_sim *sim) { board_sim = sim; }

void crs_board_reset(void)
{
    /* the control card's LEDs start high: GPIO34 is bit 2 of the GPB registers, GPIO60 bit 28 */
    const uint32_t leds = CRS_LEDS_AT_START;
    GpioDataRegs.GPBDAT.all = ((leds & 1u) << 2) | (((leds >> 1) & 1u) << 28);
    GpioDataRegs.GPBSET.all = 0;
    GpioDataRegs.GPBCLEAR.all = 0;
    GpioDataRegs.GPBTOGGLE.all = 0;
    SWI_printf.posted = 0;
}

void SWI_post(SWI_Handle swi) { swi->posted = 1; }

void mains_code(void)
{
    /* On the board this never returns: it starts the 1 kHz loop. crslab runs that loop itself,
     * so a 2024-style main() calling mains_code() is never called. */
}

int serial_printf(struct crs_serial_port *port, char *fmt, ...)
{
    (void)port;
    crs_sim *sim = board_sim;
    if (sim == NULL || sim->shared == NULL || sim->overflow_tick >= 0) return 0;
    const int gen_b = sim->generation == CRS_GEN_B;
    const size_t buffer = gen_b ? CRS_GEN_B_PRINTF_BUFFER : CRS_GEN_A_PRINTF_BUFFER;
    char line[CRS_GEN_A_PRINTF_BUFFER > CRS_GEN_B_PRINTF_BUFFER ? CRS_GEN_A_PRINTF_BUFFER
                                                                 : CRS_GEN_B_PRINTF_BUFFER];
    va_list ap;
    va_start(ap, fmt);
    const size_t n = gen_b ? crs_format_gen_b(line, sizeof line, fmt, ap)
                           : crs_format_gen_a(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n >= buffer) {
        /* the characters and the terminating NUL overrun the board's buffer: memory is corrupt */
        sim->overflow_tick = sim->tick;
        sim->overflow_chars = n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
        sim->overflow_phase = sim->shared->phase;
        return 0;
    }
    const uint32_t ring = gen_b ? CRS_GEN_B_TX_RING : CRS_GEN_A_TX_RING;
    crs_shared *sh = sim->shared;
    const uint32_t taken = crs_line_queue(&sh->line, ring, sim->tick, line, (uint32_t)n);
    if (taken > 0 && sh->print_count < CRS_PRINT_CAPACITY) {
        /* a print mark: this call's tick and how many of its characters are on the line */
        sh->print_tick[sh->print_count] = sim->tick;
        sh->print_chars[sh->print_count] = taken;
        sh->print_count++;
    }
    if (taken < n) {
        if (sim->tx_first_drop_tick < 0) sim->tx_first_drop_tick = sim->tick;
        sim->tx_dropped += (int64_t)(n - taken);
    }
    return (int)taken;
}

void crs_board_after_lab(crs_sim *sim)
{
    int run = 0;
    if (sim->generation == CRS_GEN_B) {
        if (&UARTprint != NULL && UARTprint == 1) {
            UARTprint = 0;
            run = 1;
        }
    } else if (SWI_printf.posted) {
        SWI_printf.posted = 0;
        run = 1;
    }
    sim->print_triggers += run;
    if (run && printing != NULL) {
        sim->shared->phase = CRS_PHASE_PRINTING;
        sim->shared->phase_start_ns = crs_now_ns();
        printing();
        sim->printing_runs++;
    }
}

uint32_t crs_board_update_gpio(void)
{
    uint32_t dat = GpioDataRegs.GPBDAT.all;
    dat ^= GpioDataRegs.GPBTOGGLE.all;
    dat |= GpioDataRegs.GPBSET.all;
    dat &= ~GpioDataRegs.GPBCLEAR.all;
    GpioDataRegs.GPBDAT.all = dat;
    GpioDataRegs.GPBTOGGLE.all = 0;
    GpioDataRegs.GPBSET.all = 0;
    GpioDataRegs.GPBCLEAR.all = 0;
    return ((dat >> 2) & 1u) | (((dat >> 28) & 1u) << 1); /* GPIO34, GPIO60 */
}

int crs_lab_symbols(void)
{
    int has = 0;
    if (lab != NULL) has |= CRS_LAB_HAS_LAB;
    if (printing != NULL) has |= CRS_LAB_HAS_PRINTING;
    if (&UARTprint != NULL) has |= CRS_LAB_HAS_UARTPRINT;
    if (&offset_Enc2_rad != NULL) has |= CRS_LAB_HAS_OFFSET2;
    if (&offset_Enc3_rad != NULL) has |= CRS_LAB_HAS_OFFSET3;
    if (&Simulink_PlotVar1 != NULL && &Simulink_PlotVar2 != NULL && &Simulink_PlotVar3 != NULL
        && &Simulink_PlotVar4 != NULL) {
        has |= CRS_LAB_HAS_PLOTVARS;
    }
    return has;
}
