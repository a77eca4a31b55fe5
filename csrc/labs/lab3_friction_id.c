/* crslab's Lab 3 friction identification, written the way a Gen A lab file is: the course's
 * method of measuring each joint's friction as a table of lines (Vpos, Vneg, Cpos, Cneg).
 *
 * Each joint in turn is driven at a series of constant motor speeds (speeds_rad_s, about 0.05
 * to 2 rad/s), first positive, then negative, by a velocity loop, while the other two joints
 * are held still:
 *     u = Kv (w_des - w) + Ki (theta_ref - theta) + G(theta)          (command units)
 * where w is the motor speed (the mean of the last three backward differences), theta_ref the
 * integral of the desired speed (so the second term is the integral of the velocity error) and
 * G the course's gravity model with its p vector (G2 = -p4 g sin th2M, G3 = -p5 g cos th3M).
 * Once the joint is moving steadily, the mean of u over a window of motor angle symmetric about
 * the pose where gravity leaves the joint alone (the upper arm or the forearm vertical) is what
 * friction takes at that speed: what the gravity model misses averages out over the window.
 *
 * Every pass prints one line (speed and mean command, motor angle and command units):
 *     joint 1 speed 0.0500 rad/s command 0.3761
 * `crslab friction` runs this lab on crslab's arm and fits the course's lines; on a real arm,
 * save Tera Term's log of a run and give it to `crslab friction --log FILE`. The poses:
 * joint 1 turns about (th2M, th3M) = (0, 0); joint 2 about th2M = 0 with th3M = 0; joint 3
 * about th3M = -pi/2 (forearm up) with th2M = -0.6: each inside the safety envelope with
 * margin. At the end the arm goes back to its resting pose and the torques go to zero.
 *
 * Simulink_PlotVar1..4: the swept joint's speed (rad/s), its command (units), the desired
 * speed (rad/s) and the swept joint's number. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"
#include "math.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;

float Simulink_PlotVar1 = 0;
float Simulink_PlotVar2 = 0;
float Simulink_PlotVar3 = 0;
float Simulink_PlotVar4 = 0;

#define NSPEEDS 9
#pragma DATA_SECTION(speeds_rad_s, ".my_arrs")
float speeds_rad_s[NSPEEDS] = {0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0};
#pragma DATA_SECTION(n_speeds, ".my_vars")
float n_speeds = NSPEEDS;
/* which joints to measure: 1 measures it, 0 skips it */
#pragma DATA_SECTION(measure_joint, ".my_arrs")
float measure_joint[3] = {1, 1, 1};

/* the velocity loop of the swept joint, and the PD that holds the others */
#pragma DATA_SECTION(Kv, ".my_vars")
float Kv = 3.0;     /* command units per rad/s */
#pragma DATA_SECTION(Ki, ".my_vars")
float Ki = 100.0;   /* command units per rad */
float Kp_hold = 60.0, Kd_hold = 2.0;
float accel_rad_s2 = 40.0;  /* how fast the desired speed is reached */
float move_speed_rad_s = 0.5; /* moves between poses */

/* the course's gravity model, command units: p4 and p5 of its p vector */
float p4 = 0.0753, p5 = 0.0298;

/* per joint: the pose of the other joints, the centre of the sweep, how far each pass goes
 * either side of it and the half-width of the window measured (rad, motor angles) */
float pose_rad[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, -0.6, -HALFPI}};
float sweep_rad[3] = {0.6, 0.6, 0.4};
float window_rad[3] = {0.3, 0.3, 0.2};

enum { MOVING = 0, PAUSING = 1, PASSING = 2, RETURNING = 3, DONE = 4 };
int phase = MOVING;
int joint = -1;      /* the joint being measured, 0..2 */
int speed_index = 0;
int direction = 1;   /* +1 or -1 */
long phase_ticks = 0;
float w_des = 0.0;   /* desired speed of the swept joint, rad/s */
float w_goal = 0.0;
float ref[3];        /* references, motor angles */
float move_from[3], move_to[3];
long move_ticks = 0;
int started = 0;

float theta_old[3] = {0, 0, 0};
float omega_raw1[3] = {0, 0, 0};
float omega_raw2[3] = {0, 0, 0};

/* the window being measured */
double sum_u = 0.0;
long n_u = 0;
float theta_first = 0, theta_last = 0;

/* what printing() prints */
int print_kind = 0; /* 0 the header, 1 a pass's result, 2 done */
int print_joint = 0;
float print_speed = 0, print_command = 0;

long mycount = 0;

static float gravity(int j, const float theta[3])
{
    if (j == 1) return -p4 * GRAV * sin(theta[1]);
    if (j == 2) return -p5 * GRAV * cos(theta[2]);
    return 0.0;
}

static void start_move(const float *goal)
{
    float longest = 0.0;
    for (int j = 0; j < 3; ++j) {
        move_from[j] = ref[j];
        move_to[j] = goal[j];
        if (fabs(goal[j] - ref[j]) > longest) longest = fabs(goal[j] - ref[j]);
    }
    move_ticks = (long)(1000.0 * longest / move_speed_rad_s) + 1;
    phase_ticks = 0;
}

/* the next joint to measure from `after` on, or 3 when none is left */
static int next_joint(int after)
{
    int j = after + 1;
    while (j < 3 && measure_joint[j] == 0) j++;
    return j;
}

static void go_to_joint(const float theta[3])
{
    float goal[3];
    joint = next_joint(joint);
    if (joint > 2) {
        goal[0] = 0.0;
        goal[1] = offset_Enc2_rad;
        goal[2] = offset_Enc3_rad;
        start_move(goal);
        phase = RETURNING;
        return;
    }
    for (int j = 0; j < 3; ++j) goal[j] = pose_rad[joint][j];
    goal[joint] = pose_rad[joint][joint] - sweep_rad[joint];
    start_move(goal);
    speed_index = 0;
    direction = 1;
    phase = MOVING;
}

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    float theta[3];
    float omega[3];
    float u[3];
    theta[0] = theta1motor;
    theta[1] = theta2motor;
    theta[2] = theta3motor;

    if (!started) {
        for (int j = 0; j < 3; ++j) {
            ref[j] = theta[j];
            theta_old[j] = theta[j];
        }
        started = 1;
        print_kind = 0;
        SWI_post(&SWI_printf);
        go_to_joint(theta);
    }

    for (int j = 0; j < 3; ++j) {
        float raw = (theta[j] - theta_old[j]) / 0.001;
        omega[j] = (raw + omega_raw1[j] + omega_raw2[j]) / 3.0;
        omega_raw2[j] = omega_raw1[j];
        omega_raw1[j] = raw;
        theta_old[j] = theta[j];
    }

    phase_ticks++;
    if (phase == MOVING || phase == RETURNING) {
        float share = (float)phase_ticks / (float)move_ticks;
        if (share > 1.0) share = 1.0;
        for (int j = 0; j < 3; ++j) ref[j] = move_from[j] + share * (move_to[j] - move_from[j]);
        if (phase_ticks >= move_ticks + 500) { /* arrived, and half a second to settle */
            if (phase == RETURNING) {
                phase = DONE;
                print_kind = 2;
                SWI_post(&SWI_printf);
            } else {
                phase = PAUSING;
                phase_ticks = 0;
            }
        }
    } else if (phase == PAUSING) {
        if (phase_ticks >= 250) {
            if (speed_index >= (int)n_speeds || speed_index >= NSPEEDS) {
                go_to_joint(theta);
            } else {
                phase = PASSING;
                phase_ticks = 0;
                w_des = 0.0;
                w_goal = direction * speeds_rad_s[speed_index];
                sum_u = 0.0;
                n_u = 0;
            }
        }
    } else if (phase == PASSING) {
        /* the desired speed rises to its goal at accel_rad_s2; the reference integrates it */
        float step = accel_rad_s2 * 0.001;
        if (w_des < w_goal - step) {
            w_des += step;
        } else if (w_des > w_goal + step) {
            w_des -= step;
        } else {
            w_des = w_goal;
        }
        ref[joint] += w_des * 0.001;
        float end = pose_rad[joint][joint] + direction * sweep_rad[joint];
        if ((direction > 0 && ref[joint] >= end) || (direction < 0 && ref[joint] <= end)) {
            ref[joint] = end;
            w_des = 0.0;
            if (n_u > 1) {
                print_kind = 1;
                print_joint = joint + 1;
                print_speed = (theta_last - theta_first) / ((n_u - 1) * 0.001);
                print_command = sum_u / n_u;
                SWI_post(&SWI_printf);
            }
            if (direction < 0) speed_index++;
            direction = -direction;
            phase = PAUSING;
            phase_ticks = 0;
        }
    }

    for (int j = 0; j < 3; ++j) {
        if (phase == DONE) {
            u[j] = 0.0;
        } else if (phase == PASSING && j == joint) {
            u[j] = Kv * (w_des - omega[j]) + Ki * (ref[j] - theta[j]) + gravity(j, theta);
        } else {
            u[j] = Kp_hold * (ref[j] - theta[j]) - Kd_hold * omega[j] + gravity(j, theta);
        }
    }

    if (phase == PASSING) {
        float lo = pose_rad[joint][joint] - window_rad[joint];
        float hi = pose_rad[joint][joint] + window_rad[joint];
        if (theta[joint] >= lo && theta[joint] <= hi && w_des == w_goal) {
            if (n_u == 0) theta_first = theta[joint];
            theta_last = theta[joint];
            sum_u += u[joint];
            n_u++;
        }
        Simulink_PlotVar1 = omega[joint];
        Simulink_PlotVar2 = u[joint];
        Simulink_PlotVar3 = w_des;
    }
    Simulink_PlotVar4 = joint + 1;

    *tau1 = u[0];
    *tau2 = u[1];
    *tau3 = u[2];

    if ((mycount % 500) == 0) {
        GpioDataRegs.GPBTOGGLE.bit.GPIO34 = 1;
    }
    mycount++;
    (void)error;
}

void printing(void)
{
    if (print_kind == 0) {
        serial_printf(&SerialA, "Lab 3 friction identification: joint, speed (rad/s), mean command (units)\n\r");
    } else if (print_kind == 1) {
        serial_printf(&SerialA, "joint %d speed %.4f rad/s command %.4f\n\r", print_joint, print_speed,
                      print_command);
    } else {
        serial_printf(&SerialA, "done\n\r");
    }
}
