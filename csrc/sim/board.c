/* The framework objects a lab file names, and what the board does with them. */
#define _POSIX_C_SOURCE 199309L

#include "board.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "DSP2833x_Device.h"
#include "coecsl.h"

serial_t SerialA;
SWI_Obj SWI_printf;
volatile struct GPIO_DATA_REGS GpioDataRegs;

static crs_sim *board_sim; /* the one board of this process */

int64_t crs_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

void crs_board_attach(crs_sim *sim) { board_sim = sim; }

void SWI_post(SWI_Handle swi) { swi->posted = 1; }

void mains_code(void)
{
    /* On the board this never returns: it starts the 1 kHz loop. crslab runs that loop itself,
     * so a 2024-style main() calling mains_code() is never called. */
}

int serial_printf(struct crs_serial_port *port, char *fmt, ...)
{
    char line[8192];
    va_list ap;
    (void)port;
    va_start(ap, fmt);
    const int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    crs_sim *sim = board_sim;
    if (n <= 0 || sim == NULL || sim->shared == NULL) return n;
    size_t len = (size_t)n < sizeof line ? (size_t)n : sizeof line - 1;
    if ((uint32_t)n > sim->serial_line_limit && sim->long_line_tick < 0) {
        sim->long_line_tick = sim->tick;
        sim->long_line_bytes = (uint32_t)n;
    }
    crs_shared *sh = sim->shared;
    if (sh->serial_len + len > CRS_SERIAL_CAPACITY || sh->mark_count >= CRS_MARK_CAPACITY) {
        sh->serial_dropped += len;
        return n;
    }
    sh->mark_tick[sh->mark_count] = sim->tick;
    sh->mark_offset[sh->mark_count] = sh->serial_len;
    sh->mark_count++;
    memcpy(sh->serial + sh->serial_len, line, len);
    sh->serial_len += len;
    return n;
}

void crs_board_after_lab(crs_sim *sim)
{
    int run = 0;
    if (sim->generation == 2) {
        if (&UARTprint != NULL && UARTprint == 1) {
            UARTprint = 0;
            run = 1;
        }
    } else if (SWI_printf.posted) {
        SWI_printf.posted = 0;
        run = 1;
    }
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
