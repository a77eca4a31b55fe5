/* The push: an external force at the end effector, the point where the course's forward
 * kinematics puts x, y, z (csrc/kin/crs_arm.h; MuJoCo's site "ee"), as the course's Lab 4
 * simulation pushes the arm to stand in for a hand. A scenario's `push` events set it
 * (crslab/scenario/push_events.py, crslab/worker/event_effects.py); its state is crs_push, below.
 *
 * The force is given in the world frame (DH frame 0, N): a frame a scenario names is turned into
 * the world's in Python when the file is read. It is constant, or a square wave: +force_n for
 * half_period_ticks from start_tick, then -force_n as long, and so on, worked out from the tick
 * number alone, so where chunks of ticks begin and end changes nothing.
 *
 * It reaches the plant as the generalized forces it makes on the joints, tau = J^T F (N.m on the
 * DH joints j1..j3, J the course's Jacobian of the end-effector point in metres), added to
 * MuJoCo's qfrc_applied beside the hand's. That is what MuJoCo's mj_applyFT gives for the same
 * force at that point of the forearm (tests/test_push.py checks it), and it leaves xfrc_applied to
 * the viewer's and the page's mouse. Pure functions on caller-owned memory. */
#ifndef CRSLAB_PUSH_H
#define CRSLAB_PUSH_H

#include <stdint.h>

/* A push at the end effector (csrc/plant/push.h; the scenario's `push` events): a force at the
 * point the course's forward kinematics computes, constant or a square wave. */
typedef struct {
    int32_t active;              /* 0: no push */
    int32_t pad;
    int64_t start_tick;          /* the tick it began: its square wave counts from here */
    int64_t half_period_ticks;   /* 0: constant; else the force flips sign every this many ticks */
    double force_n[3];           /* world frame (DH frame 0), N: the force of the first half period */
    double now_n[3];             /* this tick's force, world frame, N (0 when inactive) */
} crs_push;

/* The push's force at `tick` (world frame, N) into force_n: 0 when inactive or before its start;
 * force_n, or its opposite in the odd half periods of a square wave. */
void crs_push_force(const crs_push *push, int64_t tick, double force_n[3]);

/* The generalized forces (N.m on the DH joints j1..j3) of force_n (world frame, N) at the end
 * effector of the arm at DH angles dh_rad: J^T F. */
void crs_push_joint_torques(const double dh_rad[3], const double force_n[3], double tau_nm[3]);

/* One tick: the push's force at `tick` into push->now_n, and its generalized forces added to
 * qfrc_nm (j1..j3) for the arm at dh_rad. Nothing is added while the push is inactive. */
void crs_push_apply(crs_push *push, int64_t tick, const double dh_rad[3], double qfrc_nm[3]);

#endif
