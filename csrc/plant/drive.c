/* The amplifiers and motors between the motor board and the joints (see drive.h). */
#include "drive.h"

#include <math.h>

#include "framework_facts.h"

double crs_drive_follow(const crs_drive_config *config)
{
    return config->lag_s > 0.0 ? -expm1(-CRS_TICK_S / config->lag_s) : 1.0;
}

void crs_drive_step(const crs_drive_config *config, crs_drive *drive, double follow, const double command_units[3],
                    const double motor_rad_s[3], const int32_t dead[3], double torque_units[3])
{
    for (int j = 0; j < 3; ++j) {
        if (dead[j]) {
            drive->torque_units[j] = 0.0;
            torque_units[j] = 0.0;
            continue;
        }
        const double emf = config->backemf_units_s_per_rad[j] * motor_rad_s[j];
        const double most = config->stall_units[j] - emf, least = -config->stall_units[j] - emf;
        double target = command_units[j];
        target = target > most ? most : (target < least ? least : target);
        drive->torque_units[j] += follow * (target - drive->torque_units[j]);
        torque_units[j] = drive->torque_units[j];
    }
}

