/* The motor board: whole PWM counts, the over-limit cut-out and the no-command timeout. */
#include "motor_board.h"

#include <string.h>

#include "framework_facts.h"

void crs_motor_board_init(crs_motor_board *mb)
{
    memset(mb, 0, sizeof *mb);
}

static void record(crs_motor_board *mb, int64_t tick, int32_t off)
{
    if (mb->event_count >= CRS_MB_EVENT_CAPACITY) return;
    mb->event_tick[mb->event_count] = tick;
    mb->event_joint[mb->event_count] = mb->cause_joint;
    mb->event_off[mb->event_count] = off;
    mb->event_count++;
}

int crs_motor_board_step(int32_t model, crs_motor_board *mb, int64_t tick, const double *command_units)
{
    if (model != CRS_MOTOR_BOARD_PICCOLO) {
        if (command_units != NULL) {
            for (int j = 0; j < 3; ++j) mb->held_units[j] = mb->out_units[j] = command_units[j];
        }
        return 0;
    }
    int32_t counts[3] = {0, 0, 0};
    int arrived = command_units != NULL;
    for (int j = 0; arrived && j < 3; ++j) {
        const double c = command_units[j] * CRS_MB_COUNTS_PER_UNIT;
        /* a NaN or a wild value is a bad message, like anything beyond the reject limit */
        if (!(c >= -CRS_MB_REJECT_COUNTS && c <= CRS_MB_REJECT_COUNTS)) {
            arrived = 0;
        } else {
            counts[j] = (int32_t)c; /* truncated toward zero */
        }
    }
    int over_joint = 0;
    if (arrived) {
        mb->since_command = 0;
        for (int j = 0; j < 3; ++j) {
            const int over = counts[j] > CRS_MB_LIMIT_COUNTS || counts[j] < -CRS_MB_LIMIT_COUNTS;
            mb->over_ticks[j] = over ? mb->over_ticks[j] + 1 : 0;
            if (over_joint == 0 && mb->over_ticks[j] > CRS_MB_OVER_LIMIT_TICKS) over_joint = j + 1;
        }
        for (int j = 0; j < 3; ++j) mb->held_units[j] = (double)counts[j] / CRS_MB_COUNTS_PER_UNIT;
    } else if (mb->since_command < CRS_MB_TIMEOUT_TICKS) {
        mb->since_command++;
    }
    const int timed_out = mb->since_command >= CRS_MB_TIMEOUT_TICKS;
    const int off = over_joint != 0 || timed_out;
    if (off && !mb->off) {
        mb->cause_joint = over_joint != 0 ? over_joint : 0;
        mb->cutouts++;
        record(mb, tick, 1);
    } else if (!off && mb->off) {
        record(mb, tick, 0);
    }
    mb->off = off;
    for (int j = 0; j < 3; ++j) mb->out_units[j] = off ? 0.0 : mb->held_units[j];
    return mb->event_count >= CRS_MB_EVENT_CAPACITY;
}
