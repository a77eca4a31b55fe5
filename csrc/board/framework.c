/* The real framework's 1 ms duties, as docs/framework.md sections 3 and 4 describe them: the encoders
 * and the hold controller. */
#include "framework.h"

#include <float.h>
#include <math.h>

#include "crs_arm.h"
#include "framework_facts.h"
#include "plant_faults.h"

static const double RAD_PER_COUNT = 2.0 * 3.14159265358979323846 / CRS_ENCODER_COUNTS_PER_REV;

int64_t crs_encoder_counts(double motor_rad, double rest_motor_rad)
{
    return llround((motor_rad - rest_motor_rad) / RAD_PER_COUNT);
}

void crs_read_encoders(crs_board *board, const double motor_rad[3], double enc_rad[3])
{
    const double offset[3] = {
        0.0,
        board->fw.offset_enc2 != NULL ? (double)*board->fw.offset_enc2 : 0.0,
        board->fw.offset_enc3 != NULL ? (double)*board->fw.offset_enc3 : 0.0,
    };
    for (int j = 0; j < 3; ++j) {
        const int64_t counts = crs_faulty_encoder_counts(&board->faults, board->tick, j,
                                                         crs_encoder_counts(motor_rad[j], board->config.rest_motor_rad[j]));
        /* encoder 2 is mounted reversed: the chip counts down and the framework negates it */
        const int64_t raw = (j == 1) ? -counts : counts;
        const double angle = (double)((j == 1) ? -raw : raw) * RAD_PER_COUNT;
        /* the framework works in float, as the DSP does */
        enc_rad[j] = (double)(float)(angle + offset[j]);
    }
}

int crs_outside_envelope(const double enc_rad[3]) { return crs_outside_envelope_motor(enc_rad); }

/* A float as the F28335's FPU keeps it: it has no subnormal numbers (a result below FLT_MIN is
 * zero, TI's C28x FPU documentation). At rest the hold's velocity average (v1 + v2) / 3 would
 * otherwise decay into the subnormals and stay at the smallest one for good (it rounds back up),
 * where an x86 divides some hundred times slower. */
static float c28x_float(float x) { return fabsf(x) < FLT_MIN ? 0.0f : x; }

void crs_hold_update(crs_hold *h, const double enc_rad[3])
{
    const float kp_far = (float)CRS_HOLD_KP_FAR, kp_near = (float)CRS_HOLD_KP_NEAR;
    const float kp_switch = (float)CRS_HOLD_KP_SWITCH_RAD, kd = (float)CRS_HOLD_KD;
    const float dt = (float)CRS_TICK_S;
    for (int j = 0; j < 3; ++j) {
        const float angle = (float)enc_rad[j];
        const float e = h->ref_rad[j] - angle;
        float v = (angle - h->prev_enc_rad[j]) / dt;
        /* averaged with the two previous averages; the real board's joint 2 line uses the older
         * one twice */
        v = c28x_float(j == 1 ? (v + h->vel_old2_rad_s[j] + h->vel_old2_rad_s[j]) / 3.0f
                              : (v + h->vel_old1_rad_s[j] + h->vel_old2_rad_s[j]) / 3.0f);
        h->vel_old2_rad_s[j] = h->vel_old1_rad_s[j];
        h->vel_old1_rad_s[j] = v;
        h->prev_enc_rad[j] = angle;
        const float kp = fabsf(e) > kp_switch ? kp_far : kp_near;
        h->out[j] = kp * e - kd * v;
    }
}

void crs_hold_follow(crs_hold *h, const double enc_rad[3])
{
    for (int j = 0; j < 3; ++j) h->ref_rad[j] = (float)enc_rad[j];
}

void crs_hold_reanchor(crs_hold *h, const double enc_rad[3])
{
    const float reach = (float)CRS_HOLD_REANCHOR_RAD;
    for (int j = 0; j < 3; ++j) {
        if (fabsf(h->ref_rad[j] - (float)enc_rad[j]) > reach) h->ref_rad[j] = (float)enc_rad[j];
    }
}
