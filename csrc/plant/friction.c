/* Friction on each motor angle while it slides (see friction.h). */
#include "friction.h"

#include <math.h>

/* speeds over this many transition speeds have the whole sliding friction (see below) */
static const double RISE_IS_ONE = 40.0;

void crs_friction_torque(const crs_friction *friction, const double motor_rad_s[3], double torque_units[3])
{
    for (int j = 0; j < 3; ++j) {
        const double w = motor_rad_s[j];
        double slide = 0.0, viscous = 0.0;
        if (w > 0.0) {
            slide = friction->slide_pos_units[j];
            viscous = friction->viscous_pos_units_s_per_rad[j];
        } else if (w < 0.0) {
            slide = friction->slide_neg_units[j];
            viscous = friction->viscous_neg_units_s_per_rad[j];
        }
        /* the share of the way from the band's edge to the line: 0 at rest, 1 well above w_t
         * (from |w| = 40 w_t on, exp(-40) < 2^-54 rounds 1 - exp(-|w| / w_t) to exactly 1: the
         * call is saved, not a bit changes) */
        const double wt = friction->transition_rad_s, speed = fabs(w);
        const double rise = wt <= 0.0 ? (w != 0.0) : speed >= RISE_IS_ONE * wt ? 1.0 : -expm1(-speed / wt);
        torque_units[j] = -(slide * rise + viscous * w);
    }
}

void crs_friction_add(const crs_friction *friction, const double motor_rad_s[3], double ctrl_units[3])
{
    double torque[3];
    crs_friction_torque(friction, motor_rad_s, torque);
    for (int j = 0; j < 3; ++j) ctrl_units[j] += torque[j];
}
