/* The course framework's generations, one row each (generations.h says what each field is;
 * docs/framework.md, the section named beside a field, gives its public source).
 *
 * A new generation is a row here (in the order the course used them; the last is what
 * `crslab new` writes by default) plus its headers in csrc/firmware/include, named as the real ones,
 * the one in its `include` among them. A lab file that includes no row's header is taken to be
 * written for the first row. */
#include "generations.h"

#include <stddef.h>

#include "firmware_board.h"
#include "framework_facts.h"

static const crs_generation ROWS[] = {
    {
        .id = CRS_GEN_A,
        .name = "A",
        .title = "the Gen A \"CRSRobot\" framework",
        .include = "coecsl.h", /* section 2 */
        .starter_includes = "#include <tistdtypes.h>\n#include <coecsl.h>\n#include \"user_includes.h\"\n"
                            "#include \"math.h\"",
        .formatter = CRS_FORMATTER_SMALL,   /* section 7 */
        .print_trigger = CRS_PRINT_SWI_POST, /* section 2 */
        .printf_buffer_chars = 2048,        /* section 6: BUF_SIZE, on the stack */
        .tx_ring_chars = 2048,              /* section 6: one BUF_SIZE ring for every port */
        .scib_tx_ring_chars = 2048,         /* section 8 */
        .scic_tx_ring_chars = 2048,
        .matlab = CRS_MATLAB_BIG_ENDIAN_WRITE | CRS_MATLAB_ECHO | CRS_MATLAB_LOCK, /* section 8 */
        .motor_board = CRS_MOTOR_BOARD_NONE, /* section 5: its older board is not documented */
        .framework_object = "user_CRSRobot.obj",
        .map_folder = "../CRSRobotProject/Debug/",
        /* section 9: as in the 2019 CRSRobot build's map */
        .ebss_origin = 0x9000,
        .my_vars_origin = 0xC816,
        .my_arrs_origin = 0xC4C0,
    },
    {
        .id = CRS_GEN_B,
        .name = "B",
        .title = "the Gen B \"me446 starter\" framework",
        .include = "F28335Serial.h", /* section 2 */
        .starter_includes = "#include \"math.h\"\n#include \"F28335Serial.h\"\n\n"
                            "#define PI 3.1415926535897932384626433832795\n"
                            "#define TWOPI 6.283185307179586476925286766559\n"
                            "#define HALFPI 1.5707963267948966192313216916398\n"
                            "#define GRAV 9.81",
        .formatter = CRS_FORMATTER_TI,        /* section 7 */
        .print_trigger = CRS_PRINT_UARTPRINT, /* section 2 */
        .printf_buffer_chars = 136,           /* section 6: BUF_SIZESCIA, static */
        .tx_ring_chars = 136,                 /* section 6 */
        .scib_tx_ring_chars = 136,            /* section 8: BUF_SIZESCIB */
        .scic_tx_ring_chars = 2000,           /* section 8: BUF_SIZESCIC */
        .matlab = 0,                          /* section 8: '0' is parsed, neither '0' nor '1' answered */
        .motor_board = CRS_MOTOR_BOARD_PICCOLO, /* section 5 */
        .framework_object = "F28335Serial.obj",
        .map_folder = "../CPU_FLASH/",
        /* section 9: no Gen B map survives; its command files give both sections page-1 RAM in
         * L1..L7, and crslab puts them at the start of L5 and L6, .ebss at the start of L1 */
        .ebss_origin = 0x9000,
        .my_vars_origin = 0xD000,
        .my_arrs_origin = 0xE000,
    },
};

enum { COUNT = (int32_t)(sizeof ROWS / sizeof ROWS[0]) };

int32_t crs_generation_count(void) { return COUNT; }

const crs_generation *crs_generation_at(int32_t index)
{
    return index >= 0 && index < COUNT ? &ROWS[index] : NULL;
}

const crs_generation *crs_generation_of(int32_t id)
{
    for (int32_t i = 0; i < COUNT; ++i) {
        if (ROWS[i].id == id) return &ROWS[i];
    }
    return NULL;
}

/* A transmit ring and the SCI's FIFO and shift register behind it fit the board's line queue. */
static int ring_fits(int32_t chars)
{
    return chars >= 1 && chars <= CRS_LINE_QUEUE_CAPACITY - CRS_SCI_TX_FIFO - CRS_SCI_TX_SHIFT;
}

const char *crs_generation_problem(const crs_generation *g)
{
    if (g == NULL) return "no such generation";
    if (g->formatter != CRS_FORMATTER_SMALL && g->formatter != CRS_FORMATTER_TI) {
        return "its formatter is none of CRS_FORMATTER_*";
    }
    if (g->print_trigger != CRS_PRINT_SWI_POST && g->print_trigger != CRS_PRINT_UARTPRINT) {
        return "its print trigger is none of CRS_PRINT_*";
    }
    if (g->motor_board != CRS_MOTOR_BOARD_NONE && g->motor_board != CRS_MOTOR_BOARD_PICCOLO) {
        return "its motor board is none of CRS_MOTOR_BOARD_*";
    }
    if (g->printf_buffer_chars < 2 || g->printf_buffer_chars > CRS_PRINTF_BUFFER_MAX) {
        return "its serial_printf buffer is not between 2 and CRS_PRINTF_BUFFER_MAX characters";
    }
    if (!ring_fits(g->tx_ring_chars) || !ring_fits(g->scib_tx_ring_chars)
        || !ring_fits(g->scic_tx_ring_chars)) {
        return "a transmit ring does not fit the board's line (CRS_LINE_QUEUE_CAPACITY)";
    }
    if (g->matlab & ~(CRS_MATLAB_BIG_ENDIAN_WRITE | CRS_MATLAB_ECHO | CRS_MATLAB_LOCK)) {
        return "its matlab bits are not all CRS_MATLAB_*";
    }
    return NULL;
}
