/* The port between the firmware (csrc/firmware: the lab file and the framework's stand-ins) and
 * the board (csrc/board): the numbers both sides of it agree on. The firmware includes this folder
 * (csrc/port) and nothing of the board's; the board's board.h includes this header. Read by cffi
 * (plain declarations only), before board.h.
 *
 * The rest of what the two sides share is in this folder too: the course framework's numbers
 * (framework_facts.h) and its generations' rows (generations.h, generations.c), which the board
 * and every firmware compile. What the firmware exports and imports is firmware.h's. */
#ifndef CRSLAB_FIRMWARE_BOARD_H
#define CRSLAB_FIRMWARE_BOARD_H

/* Characters a serial line's queue holds (the transmit ring, the SCI's FIFO and its shift
 * register): a generation's transmit ring must fit in it (generations.c). */
enum { CRS_LINE_QUEUE_CAPACITY = 4096 };

/* Which symbols the lab file defines (crs_fw_table.symbols, firmware.h; the board's
 * crs_fw_view.symbols, board.h): a bit each. */
enum {
    CRS_LAB_HAS_LAB = 1, CRS_LAB_HAS_PRINTING = 2, CRS_LAB_HAS_UARTPRINT = 4,
    CRS_LAB_HAS_OFFSET2 = 8, CRS_LAB_HAS_OFFSET3 = 16, CRS_LAB_HAS_PLOTVARS = 32
};

/* How the firmware stopped the run (the WebAssembly board; a native firmware dies by a signal). */
enum {
    CRS_FW_TRAP_NONE = 0,
    CRS_FW_TRAP_MEMORY = 1,       /* a load or store outside the firmware's memory */
    CRS_FW_TRAP_STACK = 2,        /* the call stack overflowed (runaway recursion) */
    CRS_FW_TRAP_DIVIDE = 3,       /* an integer division by zero */
    CRS_FW_TRAP_OVERFLOW = 4,     /* INT_MIN / -1 */
    CRS_FW_TRAP_CONVERSION = 5,   /* a float too large, or NaN, converted to an integer */
    CRS_FW_TRAP_UNREACHABLE = 6,  /* abort(), assert(), __builtin_trap(), and the check the lab is
                                     compiled with that a pointer it dereferences is not NULL */
    CRS_FW_TRAP_CALL = 7,         /* a call through a bad function pointer */
    CRS_FW_TRAP_INTERRUPT = 8,    /* stopped at its deadline: lab() or printing() did not return */
    CRS_FW_TRAP_EXIT = 9,         /* exit(code) */
    CRS_FW_TRAP_REFUSED = 10,     /* a call the board does not give a firmware (a file, the clock...) */
    CRS_FW_TRAP_OTHER = 11,       /* anything else wasmtime reports */
    CRS_FW_TRAP_LOAD = 12,        /* the firmware could not be loaded */
    CRS_FW_TRAP_NULL = 13,        /* a NULL pointer dereferenced (a check compiled into the lab) */
    /* a worker its boards share (a server's run host) gives one call only so much: */
    CRS_FW_TRAP_TOO_COSTLY = 14,  /* one call cost more instructions than that */
    CRS_FW_TRAP_TOO_LONG = 15,    /* one call ran longer than that */
    CRS_FW_TRAP_STOPPED = 16      /* the crslab process stopped the board (a page's Stop, a closed page) */
};

#endif
