/* Friction on each motor angle (see models/crs_arm/README.md, "Friction"): the part of it that
 * acts while the joint slides. Its parameters,
 * crs_friction, are read by cffi (ABI mode): plain declarations only. The numbers come from the plant parameters
 * (crslab/plant/plant_params.py, PlantParams.friction_nm, whose rule this is; models/crs_arm/params.toml
 * [friction]).
 *
 * The friction on a motor angle has two parts:
 * - the static band [Sneg, Spos] (N.m): MuJoCo's friction constraint (frictionloss, solved as a
 *   hard constraint by the noslip pass) with the actuator's constant bias centring it. A stuck
 *   joint stays stuck while the other torques on it lie within the band; sliding, the constraint
 *   gives the band's edge, Spos moving positive and Sneg moving negative;
 * - beyond the band's edge, this file: moving at motor speed w > 0 (rad/s) it adds
 *       (Cpos - Spos) (1 - exp(-w / w_t)) + Vpos w
 *   against the motion, and likewise with Cneg - Sneg and Vneg moving negative, so that once
 *   w is well above the transition speed w_t the friction is the course's line Cpos + Vpos w
 *   (Cneg + Vneg w). At w = 0 it adds nothing: the band alone decides.
 *
 * It is explicit in time (the speed of the tick, before the step), which is stable while
 * 0.001 s x its steepest slope, |C - S| / w_t + V (N.m s/rad), stays well under twice the motor's
 * inertia (kg.m^2): crslab's arm has at most about 25 N.m s/rad (motor 3 moving negative)
 * against at least 0.2 kg.m^2. */
#ifndef CRSLAB_FRICTION_H
#define CRSLAB_FRICTION_H


/* Friction on each motor angle beyond its static band (csrc/plant/friction.h), set from the plant
 * parameters before the first tick; the static band itself is MuJoCo's friction constraint. In
 * command units (N.m over the motor gain); _pos moving positive, _neg moving negative. */
typedef struct {
    double slide_pos_units[3];             /* Cpos - Spos: the line's intercept beyond the band's edge */
    double slide_neg_units[3];             /* Cneg - Sneg (negative when |Cneg| > |Sneg|) */
    double viscous_pos_units_s_per_rad[3]; /* Vpos: the line's slope */
    double viscous_neg_units_s_per_rad[3]; /* Vneg */
    double transition_rad_s;               /* speed over which the band's edge becomes the line */
} crs_friction;

/* The sliding friction on each motor at `motor_rad_s` (rad/s), command units (positive: pushing
 * the motor angle positive), written into `torque_units`. */
void crs_friction_torque(const crs_friction *friction, const double motor_rad_s[3], double torque_units[3]);

/* Adds crs_friction_torque to `ctrl_units` (what the actuators get). */
void crs_friction_add(const crs_friction *friction, const double motor_rad_s[3], double ctrl_units[3]);

#endif
