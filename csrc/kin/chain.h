/* Serial chains described by a Denavit-Hartenberg table: forward kinematics of every frame,
 * points fixed in the frames (joint centres), and the geometric Jacobian, one configuration or
 * a batch of them.
 *
 * Conventions. Matrices are row-major: a pose is 4x4 (16 doubles), a rotation 3x3 (9 doubles).
 * Angles are in radians; lengths in the chain's own unit (m for the Panda, in for the CRS arm),
 * which every output keeps.
 *   standard (distal) DH, row i:   A_i = Rot_z(theta_i) Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i);
 *                                  a revolute row turns about z_{i-1}.
 *   modified (Craig) DH, row i:    A_i = Rot_x(alpha_{i-1}) Trans_x(a_{i-1}) Rot_z(theta_i) Trans_z(d_i);
 *                                  row i stores (a_{i-1}, alpha_{i-1}, d_i, theta_i) and turns
 *                                  about z_i.
 * theta_i = q_j + theta_rad[i] for the j-th revolute row; a fixed row uses theta_rad[i] alone and
 * takes no joint variable. World frame = base * A_1 ... A_n (* tool for the end effector).
 * All functions are pure and write only to the caller's buffers.
 */
#ifndef CRSLAB_CHAIN_H
#define CRSLAB_CHAIN_H

#include <stddef.h>

enum { CHAIN_MAX_ROWS = 32 };

typedef enum { CHAIN_STANDARD = 0, CHAIN_MODIFIED = 1 } chain_convention;
typedef enum { CHAIN_REVOLUTE = 0, CHAIN_FIXED = 1 } chain_joint_type;

typedef enum {
    CHAIN_OK = 0,
    CHAIN_BAD_ROW_COUNT = 1,  /* n_rows outside 1..CHAIN_MAX_ROWS */
    CHAIN_BAD_CONVENTION = 2, /* convention is neither standard nor modified */
    CHAIN_BAD_JOINT_TYPE = 3, /* a joint_type entry is neither revolute nor fixed */
    CHAIN_NOT_FINITE = 4,     /* a table entry, the base or the tool is NaN or infinite */
    CHAIN_NULL_TABLE = 5      /* a, alpha_rad, d, theta_rad or joint_type is NULL */
} chain_status;

/* A DH table. The arrays belong to the caller and must outlive every call that uses them. */
typedef struct {
    int n_rows;               /* rows of the DH table, 1..CHAIN_MAX_ROWS */
    int convention;           /* chain_convention */
    const double *a;          /* [n_rows] link length (chain unit) */
    const double *alpha_rad;  /* [n_rows] link twist (rad) */
    const double *d;          /* [n_rows] link offset (chain unit) */
    const double *theta_rad;  /* [n_rows] joint offset, added to q (rad); a fixed row's theta */
    const int *joint_type;    /* [n_rows] chain_joint_type */
    const double *base;       /* [16] pose of DH frame 0 in the world, or NULL for identity */
    const double *tool;       /* [16] pose of the end effector in the last DH frame, or NULL */
} dh_chain;

/* Modified (Craig) DH link transform Rot_x(alpha) Trans_x(a) Rot_z(theta) Trans_z(d); the
 * standard one is dh_standard_transform in dh.h. */
void dh_modified_transform(double a, double alpha_rad, double d, double theta_rad, double out[16]);

/* CHAIN_OK when the table is usable, otherwise what is wrong with it. */
chain_status chain_check(const dh_chain *c);

/* Number of revolute rows: the length of one configuration q. */
int chain_joint_count(const dh_chain *c);

/* End-effector pose (tool applied) for n configurations: q_rad is n x joints, pose n x 16. */
void chain_fk_batch(const dh_chain *c, const double *q_rad, double *pose, size_t n);

/* Every frame for n configurations: frames is n x (n_rows + 2) x 16, holding the world poses of
 * DH frames 0 (the base) to n_rows, then the end effector (tool applied). */
void chain_frames_batch(const dh_chain *c, const double *q_rad, double *frames, size_t n);

/* Points fixed in the frames (seed 002's joint centres): point i (0-based) is local_point[i],
 * given in DH frame i + 1, mapped to the world. local_point is n_rows x 3, points n x n_rows x 3. */
void chain_points_batch(const dh_chain *c, const double *q_rad, const double *local_point, double *points,
                        size_t n);

/* A table's per-row constants (twist and fixed-row sines and cosines, joint index per row),
 * computed once by chain_prepare for repeated single-configuration calls such as an IK loop. */
typedef struct {
    double ca[CHAIN_MAX_ROWS], sa[CHAIN_MAX_ROWS];             /* cos, sin of alpha */
    double ct_fixed[CHAIN_MAX_ROWS], st_fixed[CHAIN_MAX_ROWS]; /* cos, sin of theta_rad */
    int joint[CHAIN_MAX_ROWS];                                 /* joint index of a row, -1 if fixed */
    int n_joints;
} chain_constants;

void chain_prepare(const dh_chain *c, chain_constants *k);

/* End-effector pose (16) of one configuration and, when jac is not NULL, its 6 x joints
 * geometric Jacobian (as in chain_jacobian_batch); k comes from chain_prepare(c, k). */
void chain_pose_jacobian(const dh_chain *c, const chain_constants *k, const double *q_rad, double pose[16],
                         double *jac);

/* Geometric Jacobian of the end effector (tool point) in world axes, n x 6 x joints: rows 0-2
 * map joint rates (rad/s) to linear velocity (chain unit/s), rows 3-5 to angular velocity (rad/s).
 * pose (n x 16) receives the end-effector pose as a by-product, or pass NULL. */
void chain_jacobian_batch(const dh_chain *c, const double *q_rad, double *jac, double *pose, size_t n);

#endif
