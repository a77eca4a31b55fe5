/* SerialA, the port both framework generations print to Tera Term through: serial_printf formats
 * as the lab's generation does (serial_format.h) into the framework's format buffer and hands the
 * characters to the board's serial line (firmware.h: crs_board_serial_send). */
#include <stdarg.h>
#include <stdint.h>

#include "crslab_serial.h"
#include "firmware.h"
#include "framework_facts.h"
#include "serial_format.h"

int32_t crs_fw_generation(void);

/* Gen A's serial_t and Gen B's serialSCIA_t are both this struct (crslab_serial.h). */
struct crs_serial_port SerialA = {0};

enum {
    FORMAT_BUFFER = CRS_GEN_A_PRINTF_BUFFER > CRS_GEN_B_PRINTF_BUFFER ? CRS_GEN_A_PRINTF_BUFFER
                                                                       : CRS_GEN_B_PRINTF_BUFFER
};

int serial_printf(struct crs_serial_port *port, char *fmt, ...)
{
    /* Gen A formats into a buffer on the stack; Gen B's is static, and so is this one (the largest
     * of the two, so the board sees every character of a line that fits either) */
    static char line[FORMAT_BUFFER];
    va_list ap;
    va_start(ap, fmt);
    const size_t n = crs_fw_generation() == CRS_GEN_B ? crs_format_gen_b(line, sizeof line, fmt, ap)
                                                      : crs_format_gen_a(line, sizeof line, fmt, ap);
    va_end(ap);
    const uint32_t formatted = n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
    /* how many characters the transmit ring took */
    return (int)crs_board_serial_send(port != NULL ? (int32_t)port->id : 0, line, formatted);
}
