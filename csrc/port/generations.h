/* The course framework's generations, one row each (docs/framework.md section 2): everything that
 * differs between them is a field of crs_generation, and the rows are in generations.c.
 *
 * Both sides read the rows: the board (csrc/board, crslab._core and a native lab's shared object)
 * and the firmware (csrc/firmware, compiled with the lab: crslab/lab/firmware.py builds
 * generations.c into it too); Python reads them through cffi (crslab/generations.py). A lab's
 * generation is a row's `id` (crs_board.generation); an id no row has is refused where the firmware
 * is loaded, on both sides. Plain declarations only: cffi reads this file. */
#ifndef CRSLAB_GENERATIONS_H
#define CRSLAB_GENERATIONS_H

#include <stdint.h>

/* The ids of the course's two generations (their rows' `id`). */
enum {
    CRS_GEN_A = 1, /* "CRSRobot", DSP/BIOS (to spring 2022) */
    CRS_GEN_B = 2  /* "me446 starter", C2000Ware (fall 2022 on) */
};

/* How serial_printf turns a format into characters (csrc/firmware/serial_format.h). */
enum {
    CRS_FORMATTER_SMALL = 1, /* the course's small printf: truncates, 16-bit %d, %b */
    CRS_FORMATTER_TI = 2     /* TI's vsprintf: rounds, C's conversions at the C28x's widths */
};

/* What makes the framework call the lab's printing() once after lab() returns. */
enum {
    CRS_PRINT_SWI_POST = 1,  /* lab() calls SWI_post(&SWI_printf) (DSP/BIOS software interrupt) */
    CRS_PRINT_UARTPRINT = 2  /* lab() sets the lab's `int UARTprint` to 1; the idle loop clears it */
};

/* What the framework's SerialC (MATLAB) code does besides '2' (read) and '3' (write), as bits
 * (csrc/board/matlab_link.c). */
enum {
    CRS_MATLAB_BIG_ENDIAN_WRITE = 1, /* '1': '3' with the value big endian */
    CRS_MATLAB_ECHO = 2,             /* '0': reply each address and its value */
    CRS_MATLAB_LOCK = 4              /* every read sets the framework's matlabLock (.my_vars) to 1 */
};

/* The largest serial_printf buffer a row may have: the firmware formats into one this large. */
enum { CRS_PRINTF_BUFFER_MAX = 2048 };

typedef struct crs_generation {
    int32_t id;                    /* what crs_board.generation holds; 1 and up */
    const char *name;              /* "A": `crslab new --gen`, messages */
    const char *title;             /* what a starting file (`crslab new`) calls it */
    const char *include;           /* the header whose #include says a lab was written for it */
    const char *starter_includes;  /* the lines a starting file of this generation begins with */
    int32_t formatter;             /* CRS_FORMATTER_* */
    int32_t print_trigger;         /* CRS_PRINT_* */
    int32_t printf_buffer_chars;   /* serial_printf's format buffer, the terminating NUL included:
                                      a line of this many characters or more overflows it */
    int32_t tx_ring_chars;         /* SerialA's transmit ring (the SCI's FIFO and shift register
                                      come on top), chars */
    int32_t scib_tx_ring_chars;    /* SerialB's (Simulink's), chars */
    int32_t scic_tx_ring_chars;    /* SerialC's (MATLAB's), chars */
    int32_t matlab;                /* CRS_MATLAB_* bits */
    int32_t motor_board;           /* CRS_MOTOR_BOARD_* of its era's hardware: a run's default */
    const char *framework_object;  /* the framework's object file holding its variables (the map) */
    const char *map_folder;        /* where the course's MATLAB scripts look for the map */
    int32_t ebss_origin;           /* where the linker puts the lab's sections on page 1: */
    int32_t my_vars_origin;        /*   .ebss (every other global), .my_vars, .my_arrs; */
    int32_t my_arrs_origin;        /*   16-bit-word addresses */
} crs_generation;

/* How many rows there are, and row `index` (0 .. count - 1; NULL outside). */
int32_t crs_generation_count(void);
const crs_generation *crs_generation_at(int32_t index);
/* The row whose id is `id`, or NULL when there is none. */
const crs_generation *crs_generation_of(int32_t id);
/* Why row `g` cannot be run (an unknown formatter, print trigger or motor board, a buffer or ring
 * out of range), or NULL when it can. */
const char *crs_generation_problem(const crs_generation *g);

#endif
