/* Hostile test lab: calls the board's serial port import (board.serial_send, what serial_printf
 * calls) itself, with pointers and lengths serial_printf never gives it: a pointer past the end of
 * its memory, a "negative" one, characters that run off the end of its memory, and a length of
 * 4 GB. The board reads only what lies inside the firmware's memory and stops the run on the
 * length, as on a line too long for the format buffer. Prints like the faulty labs; its sends come
 * on its 1020th to 1023rd calls, the 4 GB one on its 1024th (tick 5123). */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include <stdint.h>
#include <stdio.h>
#include <string.h>

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
int32_t sent_past_end = -1, sent_negative = -1, sent_at_end = -1;

__attribute__((import_module("board"), import_name("serial_send")))
int32_t board_send(int32_t port, const char *chars, uint32_t formatted);

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor; (void)theta2motor; (void)theta3motor; (void)error;
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    const uintptr_t memory_end = (uintptr_t)__builtin_wasm_memory_size(0) * 65536u;
    if ((mycount % 500) == 0) {
        SWI_post(&SWI_printf);
    }
    if (mycount == 1019) {
        sent_past_end = board_send(0, (const char *)(memory_end + 100u), 10);
    } else if (mycount == 1020) {
        sent_negative = board_send(0, (const char *)(uintptr_t)0xFFFFFFF0u, 10);
    } else if (mycount == 1021) {
        char *last = (char *)(memory_end - 4u);
        memcpy(last, "END!", 4);
        sent_at_end = board_send(0, last, 40); /* 36 of the 40 lie past the end */
    } else if (mycount == 1022) {
        char line[64];
        int n = snprintf(line, sizeof line, "|%ld %ld %ld\n\r", (long)sent_past_end, (long)sent_negative,
                         (long)sent_at_end);
        board_send(0, line, (uint32_t)n);
    } else if (mycount == 1023) {
        board_send(0, "huge", 0xFFFFFFFFu); /* -1: a length of 4 GB */
    }
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "count %ld theta1 %.2f\n\r", mycount, 0.0);
}
