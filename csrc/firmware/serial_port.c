/* SerialA, the port every framework generation prints to Tera Term through: serial_printf formats
 * as the lab's generation does (its row's formatter, serial_format.h) into the framework's format
 * buffer and hands the characters to the board's serial line (firmware.h: crs_board_serial_send),
 * which holds them to the generation's buffer and ring sizes. */
#include <stdarg.h>
#include <stdint.h>

#include "crslab_serial.h"
#include "firmware.h"
#include "generations.h"
#include "serial_format.h"

/* Gen A's serial_t and Gen B's serialSCIA_t are both this struct (crslab_serial.h). */
struct crs_serial_port SerialA = {0};

#if !defined(__wasm__)
crs_fw_serial_send_fn crs_board_serial_send = NULL; /* the native port sets it (firmware.h) */
#endif

int serial_printf(struct crs_serial_port *port, char *fmt, ...)
{
    /* Gen A formats into a buffer on the stack; Gen B's is static, and so is this one (as large as
     * any generation's, so the board sees every character of a line that fits the lab's) */
    static char line[CRS_PRINTF_BUFFER_MAX];
    const crs_format_fn format = crs_format_of(crs_fw_formatter());
    if (format == NULL) return 0; /* before the firmware is started (a constructor): nothing is sent */
#if !defined(__wasm__)
    if (crs_board_serial_send == NULL) return 0; /* (the same, natively: no board attached yet) */
#endif
    va_list ap;
    va_start(ap, fmt);
    const size_t n = format(line, sizeof line, fmt, ap);
    va_end(ap);
    const uint32_t formatted = n > UINT32_MAX ? UINT32_MAX : (uint32_t)n;
    /* how many characters the transmit ring took */
    return (int)crs_board_serial_send(port != NULL ? (int32_t)port->id : 0, line, formatted);
}
