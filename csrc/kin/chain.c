#include "chain.h"

#include <math.h>
#include <string.h>

#include "vector_math.h"

/* A frame as the columns of its rotation (x, y, z axes in world coordinates) and its origin.
 * Applying a DH row to the columns directly costs about a third of a 4x4 product. */
typedef struct {
    double x[3], y[3], z[3], p[3];
} frame;

/* Values per block in the batch loops: the joint angles of a block get their sines and cosines
 * in one vectorizable loop, then the rows are composed. */
enum { BLOCK_VALUES = 1024 };

void dh_modified_transform(double a, double alpha_rad, double d, double theta_rad, double out[16])
{
    const double ct = cos(theta_rad), st = sin(theta_rad);
    const double ca = cos(alpha_rad), sa = sin(alpha_rad);
    out[0] = ct;       out[1] = -st;      out[2] = 0.0;  out[3] = a;
    out[4] = st * ca;  out[5] = ct * ca;  out[6] = -sa;  out[7] = -sa * d;
    out[8] = st * sa;  out[9] = ct * sa;  out[10] = ca;  out[11] = ca * d;
    out[12] = 0.0;     out[13] = 0.0;     out[14] = 0.0; out[15] = 1.0;
}

static int all_finite(const double *v, int n)
{
    for (int i = 0; i < n; ++i) {
        if (!isfinite(v[i])) return 0;
    }
    return 1;
}

chain_status chain_check(const dh_chain *c)
{
    if (c->n_rows < 1 || c->n_rows > CHAIN_MAX_ROWS) return CHAIN_BAD_ROW_COUNT;
    if (c->convention != CHAIN_STANDARD && c->convention != CHAIN_MODIFIED) return CHAIN_BAD_CONVENTION;
    if (!c->a || !c->alpha_rad || !c->d || !c->theta_rad || !c->joint_type) return CHAIN_NULL_TABLE;
    for (int i = 0; i < c->n_rows; ++i) {
        if (c->joint_type[i] != CHAIN_REVOLUTE && c->joint_type[i] != CHAIN_FIXED) return CHAIN_BAD_JOINT_TYPE;
    }
    if (!all_finite(c->a, c->n_rows) || !all_finite(c->alpha_rad, c->n_rows) || !all_finite(c->d, c->n_rows)
        || !all_finite(c->theta_rad, c->n_rows) || (c->base && !all_finite(c->base, 16))
        || (c->tool && !all_finite(c->tool, 16))) {
        return CHAIN_NOT_FINITE;
    }
    return CHAIN_OK;
}

int chain_joint_count(const dh_chain *c)
{
    int n = 0;
    for (int i = 0; i < c->n_rows; ++i) n += c->joint_type[i] == CHAIN_REVOLUTE;
    return n;
}

void chain_prepare(const dh_chain *c, chain_constants *rc)
{
    rc->n_joints = 0;
    for (int i = 0; i < c->n_rows; ++i) {
        rc->ca[i] = cos(c->alpha_rad[i]);
        rc->sa[i] = sin(c->alpha_rad[i]);
        rc->ct_fixed[i] = cos(c->theta_rad[i]);
        rc->st_fixed[i] = sin(c->theta_rad[i]);
        rc->joint[i] = c->joint_type[i] == CHAIN_REVOLUTE ? rc->n_joints++ : -1;
    }
}

static void frame_from_pose(const double *pose, frame *f)
{
    for (int r = 0; r < 3; ++r) {
        f->x[r] = pose ? pose[4 * r] : (r == 0);
        f->y[r] = pose ? pose[4 * r + 1] : (r == 1);
        f->z[r] = pose ? pose[4 * r + 2] : (r == 2);
        f->p[r] = pose ? pose[4 * r + 3] : 0.0;
    }
}

static void frame_to_pose(const frame *f, double *pose)
{
    for (int r = 0; r < 3; ++r) {
        pose[4 * r] = f->x[r];
        pose[4 * r + 1] = f->y[r];
        pose[4 * r + 2] = f->z[r];
        pose[4 * r + 3] = f->p[r];
    }
    pose[12] = 0.0; pose[13] = 0.0; pose[14] = 0.0; pose[15] = 1.0;
}

/* f = f * A for one DH row, given the row's theta as (ct, st). */
static inline void apply_row(frame *f, int modified, double ct, double st, double ca, double sa, double a,
                             double d)
{
    if (modified) {
        /* Rot_x(alpha) Trans_x(a): x stays, y and z turn about it; then Rot_z(theta) Trans_z(d). */
        for (int r = 0; r < 3; ++r) {
            const double y1 = ca * f->y[r] + sa * f->z[r];
            const double z1 = -sa * f->y[r] + ca * f->z[r];
            const double x1 = f->x[r];
            f->p[r] += a * x1 + d * z1;
            f->x[r] = ct * x1 + st * y1;
            f->y[r] = -st * x1 + ct * y1;
            f->z[r] = z1;
        }
    } else {
        /* Rot_z(theta) Trans_z(d): x and y turn about z; then Trans_x(a) Rot_x(alpha). */
        for (int r = 0; r < 3; ++r) {
            const double u = ct * f->x[r] + st * f->y[r];
            const double v = -st * f->x[r] + ct * f->y[r];
            const double z0 = f->z[r];
            f->p[r] += d * z0 + a * u;
            f->x[r] = u;
            f->y[r] = ca * v + sa * z0;
            f->z[r] = -sa * v + ca * z0;
        }
    }
}

/* f = f * t for a general homogeneous transform t (the tool). */
static void apply_pose(frame *f, const double *t)
{
    frame g;
    for (int r = 0; r < 3; ++r) {
        g.x[r] = f->x[r] * t[0] + f->y[r] * t[4] + f->z[r] * t[8];
        g.y[r] = f->x[r] * t[1] + f->y[r] * t[5] + f->z[r] * t[9];
        g.z[r] = f->x[r] * t[2] + f->y[r] * t[6] + f->z[r] * t[10];
        g.p[r] = f->p[r] + f->x[r] * t[3] + f->y[r] * t[7] + f->z[r] * t[11];
    }
    *f = g;
}

/* Walk one configuration, given the sines and cosines of its joint angles (theta, offsets
 * included). Writes any of: every frame (n_rows + 2 poses), the end pose, the Jacobian. */
static void walk(const dh_chain *c, const chain_constants *rc, const double *st, const double *ct,
                 double *frames, double *pose, double *jac)
{
    const int modified = c->convention == CHAIN_MODIFIED;
    const int nj = rc->n_joints;
    double axis[CHAIN_MAX_ROWS][3], origin[CHAIN_MAX_ROWS][3];
    frame f;
    frame_from_pose(c->base, &f);
    if (frames) frame_to_pose(&f, frames);
    for (int i = 0; i < c->n_rows; ++i) {
        const int j = rc->joint[i];
        if (jac && j >= 0 && !modified) { /* a standard row turns about z_{i-1} */
            memcpy(axis[j], f.z, sizeof f.z);
            memcpy(origin[j], f.p, sizeof f.p);
        }
        apply_row(&f, modified, j >= 0 ? ct[j] : rc->ct_fixed[i], j >= 0 ? st[j] : rc->st_fixed[i],
                  rc->ca[i], rc->sa[i], c->a[i], c->d[i]);
        if (jac && j >= 0 && modified) { /* a modified row turns about z_i */
            memcpy(axis[j], f.z, sizeof f.z);
            memcpy(origin[j], f.p, sizeof f.p);
        }
        if (frames) frame_to_pose(&f, frames + 16 * (i + 1));
    }
    if (c->tool) apply_pose(&f, c->tool);
    if (frames) frame_to_pose(&f, frames + 16 * (c->n_rows + 1));
    if (pose) frame_to_pose(&f, pose);
    if (jac) {
        for (int j = 0; j < nj; ++j) {
            const double *z = axis[j];
            const double r[3] = {f.p[0] - origin[j][0], f.p[1] - origin[j][1], f.p[2] - origin[j][2]};
            jac[0 * nj + j] = z[1] * r[2] - z[2] * r[1];
            jac[1 * nj + j] = z[2] * r[0] - z[0] * r[2];
            jac[2 * nj + j] = z[0] * r[1] - z[1] * r[0];
            jac[3 * nj + j] = z[0];
            jac[4 * nj + j] = z[1];
            jac[5 * nj + j] = z[2];
        }
    }
}

CRS_VECTOR_CLONES
static void sin_cos_block(const double *restrict a, double *restrict sa, double *restrict ca, size_t m)
{
    for (size_t i = 0; i < m; ++i) sa[i] = sin(a[i]);
    for (size_t i = 0; i < m; ++i) ca[i] = cos(a[i]);
}

/* Joint offsets by joint index (not row index). */
static void joint_offsets(const dh_chain *c, const chain_constants *rc, double *offset)
{
    for (int i = 0; i < c->n_rows; ++i) {
        if (rc->joint[i] >= 0) offset[rc->joint[i]] = c->theta_rad[i];
    }
}

/* Points fixed in the frames, from one configuration's frames (as chain_frames_batch lays out). */
static void map_points(int rows, const double *frames, const double *local_point, double *points)
{
    for (int i = 0; i < rows; ++i) {
        const double *t = frames + 16 * (i + 1), *l = local_point + 3 * i;
        for (int r = 0; r < 3; ++r) {
            points[3 * i + r] = t[4 * r] * l[0] + t[4 * r + 1] * l[1] + t[4 * r + 2] * l[2] + t[4 * r + 3];
        }
    }
}

/* What one batch call asks for; NULL outputs are skipped. */
typedef struct {
    double *frames, *pose, *jac, *points;
    const double *local_point;
} batch_outputs;

/* The shared batch loop: sines and cosines per block, then one walk per configuration. */
static void walk_batch(const dh_chain *c, const double *q_rad, const batch_outputs *out, size_t n)
{
    chain_constants rc;
    chain_prepare(c, &rc);
    const size_t nj = (size_t)rc.n_joints, rows = (size_t)c->n_rows;
    const size_t per_block = nj ? BLOCK_VALUES / nj : BLOCK_VALUES;
    const size_t frame_stride = 16 * (rows + 2);
    double offset[CHAIN_MAX_ROWS], scratch_frames[16 * (CHAIN_MAX_ROWS + 2)];
    double theta[BLOCK_VALUES], st[BLOCK_VALUES], ct[BLOCK_VALUES];
    joint_offsets(c, &rc, offset);
    for (size_t b = 0; b < n; b += per_block) {
        const size_t m = (n - b < per_block) ? n - b : per_block;
        for (size_t i = 0; i < m; ++i) {
            for (size_t j = 0; j < nj; ++j) theta[i * nj + j] = q_rad[(b + i) * nj + j] + offset[j];
        }
        sin_cos_block(theta, st, ct, m * nj);
        for (size_t i = 0; i < m; ++i) {
            const size_t k = b + i;
            double *frames = out->frames ? out->frames + k * frame_stride
                                         : (out->points ? scratch_frames : NULL);
            walk(c, &rc, st + i * nj, ct + i * nj, frames, out->pose ? out->pose + 16 * k : NULL,
                 out->jac ? out->jac + 6 * nj * k : NULL);
            if (out->points) map_points(c->n_rows, frames, out->local_point, out->points + 3 * rows * k);
        }
    }
}

void chain_fk_batch(const dh_chain *c, const double *q_rad, double *pose, size_t n)
{
    const batch_outputs out = {.pose = pose};
    walk_batch(c, q_rad, &out, n);
}

void chain_frames_batch(const dh_chain *c, const double *q_rad, double *frames, size_t n)
{
    const batch_outputs out = {.frames = frames};
    walk_batch(c, q_rad, &out, n);
}

void chain_jacobian_batch(const dh_chain *c, const double *q_rad, double *jac, double *pose, size_t n)
{
    const batch_outputs out = {.pose = pose, .jac = jac};
    walk_batch(c, q_rad, &out, n);
}

void chain_points_batch(const dh_chain *c, const double *q_rad, const double *local_point, double *points,
                        size_t n)
{
    const batch_outputs out = {.points = points, .local_point = local_point};
    walk_batch(c, q_rad, &out, n);
}

void chain_pose_jacobian(const dh_chain *c, const chain_constants *k, const double *q_rad, double pose[16],
                         double *jac)
{
    double st[CHAIN_MAX_ROWS], ct[CHAIN_MAX_ROWS];
    for (int j = 0, i = 0; i < c->n_rows; ++i) {
        if (k->joint[i] < 0) continue;
        st[j] = sin(q_rad[j] + c->theta_rad[i]);
        ct[j] = cos(q_rad[j] + c->theta_rad[i]);
        ++j;
    }
    walk(c, k, st, ct, NULL, pose, jac);
}
