/* The drive between the motor board's outputs and the joints: per motor, the amplifier and the
 * motor (what the command units become as torque). Read by cffi (ABI mode): plain declarations
 * only. The numbers come from the plant parameters
 * (crslab/plant/plant_params.py, models/crs_arm/params.toml [drive]).
 *
 * The amplifier delivers the commanded torque while its supply voltage lasts. At motor speed w
 * (rad/s, motor angle) the motor's back-EMF leaves it at most
 *     stall_units - backemf_units_s_per_rad * w   forward, and
 *    -stall_units - backemf_units_s_per_rad * w   backward,
 * so a motor driven forward levels off at the speed where what is left equals the friction, and
 * braking gets more than driving. The delivered torque follows with a first-order lag (lag_s;
 * exact for a constant target over the 1 ms step). A dead motor (a scenario fault) delivers
 * nothing, whatever its lag.
 *
 * Split as MuJoCo splits mjModel and mjData: crs_drive_config is what a run is configured with
 * (set before its first tick, only read by a tick); crs_drive is what the ticks change. */
#ifndef CRSLAB_DRIVE_H
#define CRSLAB_DRIVE_H

#include <stdint.h>

/* The amplifiers and motors between the motor board and the joints, set from the plant parameters
 * (crslab/plant/plant_params.py) before the first tick. */
typedef struct {
    double stall_units[3];             /* torque delivered at standstill, at most, command units */
    double backemf_units_s_per_rad[3]; /* what each rad/s of motor speed takes off that, units s/rad */
    double lag_s;                      /* first-order lag of the delivered torque; 0: none */
} crs_drive_config;

/* What the drive delivers now. */
typedef struct {
    double torque_units[3];            /* the torque each motor delivers, command units */
} crs_drive;

/* The share of the way to its target the delivered torque goes in one 1 ms step (1 with no
 * lag): what crs_drive_step takes as `follow`. It depends on lag_s alone, which changes only
 * between chunks of ticks: computed once per chunk, not every tick. */
double crs_drive_follow(const crs_drive_config *config);

/* One ms: `command_units` is what the motor board gives the amplifiers, `motor_rad_s` the motor
 * speeds, `dead` the dead-motor faults (1: nothing delivered), `follow` crs_drive_follow(config).
 * Writes the torque each motor delivers (command units) into `torque_units` and `drive`. */
void crs_drive_step(const crs_drive_config *config, crs_drive *drive, double follow, const double command_units[3],
                    const double motor_rad_s[3], const int32_t dead[3], double torque_units[3]);

#endif
