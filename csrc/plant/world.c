/* The world's quantities per tick: see world.h. */
#include "world.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

static const crs_world_column COLUMNS[] = {
    {"peg_tip", "m", "the peg's tip", CRS_WORLD_ROW_PEG_TIP, 3},
    {"peg_depth", "m", "how deep the peg's tip is in the hole (below its top, within its radius)",
     CRS_WORLD_ROW_PEG_DEPTH, 1},
    {"egg_force", "N", "the force the arm presses on the egg", CRS_WORLD_ROW_EGG_FORCE, 1},
    {"egg_force_xyz", "N", "the force the arm presses on the egg, world frame", CRS_WORLD_ROW_EGG_FORCE_XYZ, 3},
    {"scale_g", "g", "what the scale shows", CRS_WORLD_ROW_SCALE_G, 1},
    {"egg_broken", "0/1", "the egg is broken", CRS_WORLD_ROW_EGG_BROKEN, 1},
    {"egg_broken_by", "code", "what broke the egg: 0 whole, 1 the press, 2 a side hit, 3 a fall",
     CRS_WORLD_ROW_EGG_BROKEN_BY, 1},
    {"egg_touch_speed", "m/s", "how fast the peg came down when its contact with the egg began",
     CRS_WORLD_ROW_EGG_TOUCH_SPEED, 1},
    {"hole_force", "N", "the force on the hole block", CRS_WORLD_ROW_HOLE_FORCE, 1},
    {"obstacle_force", "N", "the force on the obstacle", CRS_WORLD_ROW_OBSTACLE_FORCE, 1},
    {"obstacle_peg_force", "N", "the force on the obstacle by the peg", CRS_WORLD_ROW_OBSTACLE_PEG_FORCE, 1},
    {"obstacle_forearm_force", "N", "the force on the obstacle by the forearm",
     CRS_WORLD_ROW_OBSTACLE_FOREARM_FORCE, 1},
    {"obstacle_upper_arm_force", "N", "the force on the obstacle by the upper arm",
     CRS_WORLD_ROW_OBSTACLE_UPPER_ARM_FORCE, 1},
    {"groove_force", "N", "the force on the groove plate", CRS_WORLD_ROW_GROOVE_FORCE, 1},
    {"groove_side_force", "N", "the groove's force across its segment", CRS_WORLD_ROW_GROOVE_SIDE_FORCE, 1},
    {"groove_offset", "m", "the peg's distance from the groove's centre line", CRS_WORLD_ROW_GROOVE_OFFSET, 1},
    {"groove_along", "m", "where along the groove the peg is nearest", CRS_WORLD_ROW_GROOVE_ALONG, 1},
    {"groove_segment", "index", "the groove's segment the peg is nearest", CRS_WORLD_ROW_GROOVE_SEGMENT, 1},
    {"table_force", "N", "the force on the table", CRS_WORLD_ROW_TABLE_FORCE, 1},
};
enum { N_COLUMNS = (int)(sizeof COLUMNS / sizeof COLUMNS[0]) };

static const char *const FIXTURE_NAMES[CRS_FIXTURES] = {
    [CRS_FIXTURE_TABLE] = "table",
    [CRS_FIXTURE_HOLE] = "hole",
    [CRS_FIXTURE_OBSTACLE] = "obstacle",
    [CRS_FIXTURE_OBSTACLE_FOREARM] = "obstacle_forearm",
    [CRS_FIXTURE_OBSTACLE_UPPER_ARM] = "obstacle_upper_arm",
    [CRS_FIXTURE_GROOVE] = "groove",
    [CRS_FIXTURE_EGG] = "egg",
    [CRS_FIXTURE_SCALE] = "scale",
};

const crs_world_column *crs_world_columns(int32_t *count)
{
    *count = N_COLUMNS;
    return COLUMNS;
}

const char *crs_world_fixture_name(int32_t fixture)
{
    return fixture >= 0 && fixture < CRS_FIXTURES ? FIXTURE_NAMES[fixture] : NULL;
}

const char *crs_egg_broken_by_name(int32_t broken_by)
{
    switch (broken_by) {
    case CRS_EGG_BROKEN_BY_PRESS: return "the press";
    case CRS_EGG_BROKEN_BY_SIDE: return "a side hit";
    case CRS_EGG_BROKEN_BY_FALL: return "a fall";
    default: return "";
    }
}

void crs_world_init(crs_world *w)
{
    memset(w, 0, sizeof *w);
    w->config.peg_tip_adr = -1;
    for (int i = 0; i < CRS_FIXTURES; ++i) w->config.sensor_adr[i] = -1;
    w->state.broke_tick = -1;
    w->state.row[CRS_WORLD_ROW_GROOVE_SEGMENT] = -1.0;
}

void crs_world_attach(crs_world *w, const crs_world_config *config)
{
    crs_world_init(w);
    w->config = *config;
    w->enabled = 1;
}

/* The force (N) the arm presses on fixture `i`: minus what its sensor reads (the force holding
 * the fixture in place); zero when the world has no such fixture. */
static void pressed(const crs_world_config *c, int i, double f[3])
{
    const int32_t adr = c->sensor_adr[i];
    for (int k = 0; k < 3; ++k) f[k] = adr >= 0 ? -c->sensordata[adr + k] : 0.0;
}

static double norm3(const double f[3]) { return sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]); }

crs_groove_point crs_groove_nearest(const double xy[8], double px, double py)
{
    crs_groove_point best = {.segment = 0, .offset_m = INFINITY};
    double start = 0.0; /* the centre line's length before this segment */
    for (int s = 0; s < 3; ++s) {
        const double ax = xy[2 * s], ay = xy[2 * s + 1];
        const double dx = xy[2 * s + 2] - ax, dy = xy[2 * s + 3] - ay;
        const double len = sqrt(dx * dx + dy * dy);
        if (len > 0.0) {
            double t = ((px - ax) * dx + (py - ay) * dy) / (len * len);
            t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
            const double offset = hypot(ax + t * dx - px, ay + t * dy - py);
            if (offset < best.offset_m) {
                best = (crs_groove_point){.segment = s, .offset_m = offset, .along_m = start + t * len,
                                          .across_x = -dy / len, .across_y = dx / len};
            }
        }
        start += len;
    }
    return best;
}

double crs_groove_across(const double xy[8], double px, double py, double fx, double fy)
{
    const crs_groove_point p = crs_groove_nearest(xy, px, py);
    return fabs(p.across_x * fx + p.across_y * fy);
}

double crs_peg_depth(const double hole_xy[2], double top_z_m, double radius_m, const double tip[3])
{
    const double depth = top_z_m - tip[2];
    const int within = hypot(tip[0] - hole_xy[0], tip[1] - hole_xy[1]) <= radius_m;
    return depth > 0.0 && within ? depth : 0.0;
}

void crs_peg_depths(const double hole_xy[2], double top_z_m, double radius_m, const double *tips, int64_t n,
                    double *depth_m)
{
    for (int64_t i = 0; i < n; ++i) depth_m[i] = crs_peg_depth(hole_xy, top_z_m, radius_m, &tips[3 * i]);
}

void crs_groove_nearest_many(const double xy[8], const double *points, int64_t n, int64_t stride, int32_t *segment,
                             double *offset_m, double *along_m)
{
    for (int64_t i = 0; i < n; ++i) {
        const crs_groove_point p = crs_groove_nearest(xy, points[i * stride], points[i * stride + 1]);
        segment[i] = p.segment;
        offset_m[i] = p.offset_m;
        along_m[i] = p.along_m;
    }
}

int32_t crs_egg_break_cause(const double f[3], double touch_speed_m_s)
{
    if (hypot(f[0], f[1]) > -f[2]) return CRS_EGG_BROKEN_BY_SIDE;
    if (touch_speed_m_s > CRS_EGG_FALL_M_S) return CRS_EGG_BROKEN_BY_FALL;
    return CRS_EGG_BROKEN_BY_PRESS;
}

void crs_egg_flatten(double size_m[3], double pos_m[3])
{
    const double bottom = pos_m[2] - size_m[2];
    size_m[2] *= CRS_EGG_FLAT_SHARE;
    pos_m[2] = bottom + size_m[2];
}

/* The egg: its force, the scale, the touch's speed, the break (latched, classified, the egg laid
 * flat and no longer colliding). */
static void egg_update(crs_world *w, int64_t tick, const double tip_speed_down)
{
    const crs_world_config *c = &w->config;
    crs_world_state *s = &w->state;
    double *row = s->row;
    double egg[3], scale[3];
    pressed(c, CRS_FIXTURE_EGG, egg);
    pressed(c, CRS_FIXTURE_SCALE, scale);
    const double egg_n = norm3(egg);
    const double scale_down_n = -scale[2] - egg[2]; /* the scale carries what presses the egg down */
    const int touching = egg_n > 0.0;
    if (touching && !s->egg_touching) s->egg_touch_speed_m_s = tip_speed_down > 0.0 ? tip_speed_down : 0.0;
    if (!touching) s->egg_touch_speed_m_s = 0.0;
    s->egg_touching = touching;
    row[CRS_WORLD_ROW_EGG_FORCE] = egg_n;
    for (int k = 0; k < 3; ++k) row[CRS_WORLD_ROW_EGG_FORCE_XYZ + k] = egg[k];
    row[CRS_WORLD_ROW_SCALE_G] = scale_down_n / CRS_SCALE_GRAVITY_M_S2 * 1000.0;
    row[CRS_WORLD_ROW_EGG_TOUCH_SPEED] = s->egg_touch_speed_m_s;
    if (!s->egg_broken && c->breaking_force_n > 0.0 && egg_n > c->breaking_force_n) {
        s->egg_broken = 1;
        s->egg_broken_by = crs_egg_break_cause(egg, s->egg_touch_speed_m_s);
        s->broke_tick = tick;
        /* crushed: the shell no longer holds anything up, and it lies flat on the scale */
        if (c->egg_contype != NULL) *c->egg_contype = 0;
        if (c->egg_conaffinity != NULL) *c->egg_conaffinity = 0;
        if (c->egg_size_m != NULL && c->egg_pos_m != NULL) crs_egg_flatten(c->egg_size_m, c->egg_pos_m);
    }
    row[CRS_WORLD_ROW_EGG_BROKEN] = s->egg_broken;
    row[CRS_WORLD_ROW_EGG_BROKEN_BY] = s->egg_broken_by;
}

void crs_world_update(crs_world *w, int64_t tick)
{
    const crs_world_config *c = &w->config;
    crs_world_state *s = &w->state;
    double *row = s->row;
    double tip_speed_down = 0.0;
    if (c->peg_tip_adr >= 0) {
        for (int k = 0; k < 3; ++k) row[CRS_WORLD_ROW_PEG_TIP + k] = c->sensordata[c->peg_tip_adr + k];
        const double z = row[CRS_WORLD_ROW_PEG_TIP + 2];
        if (s->has_last_tip && c->timestep_s > 0.0) tip_speed_down = (s->last_tip_z_m - z) / c->timestep_s;
        s->last_tip_z_m = z;
        s->has_last_tip = 1;
    }
    const double *tip = &row[CRS_WORLD_ROW_PEG_TIP];
    row[CRS_WORLD_ROW_PEG_DEPTH] = c->has_hole ? crs_peg_depth(c->hole_xy_m, c->hole_top_z_m, c->hole_radius_m, tip)
                                               : 0.0;
    egg_update(w, tick, tip_speed_down);
    double f[3];
    pressed(c, CRS_FIXTURE_HOLE, f);
    row[CRS_WORLD_ROW_HOLE_FORCE] = norm3(f);
    double total[3] = {0.0, 0.0, 0.0};
    static const struct { int fixture, column; } PARTS[3] = {
        {CRS_FIXTURE_OBSTACLE, CRS_WORLD_ROW_OBSTACLE_PEG_FORCE},
        {CRS_FIXTURE_OBSTACLE_FOREARM, CRS_WORLD_ROW_OBSTACLE_FOREARM_FORCE},
        {CRS_FIXTURE_OBSTACLE_UPPER_ARM, CRS_WORLD_ROW_OBSTACLE_UPPER_ARM_FORCE},
    };
    for (int p = 0; p < 3; ++p) {
        pressed(c, PARTS[p].fixture, f);
        row[PARTS[p].column] = norm3(f);
        for (int k = 0; k < 3; ++k) total[k] += f[k];
    }
    row[CRS_WORLD_ROW_OBSTACLE_FORCE] = norm3(total);
    pressed(c, CRS_FIXTURE_GROOVE, f);
    row[CRS_WORLD_ROW_GROOVE_FORCE] = norm3(f);
    if (c->has_groove) {
        const crs_groove_point p = crs_groove_nearest(c->groove_xy_m, tip[0], tip[1]);
        row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE] = fabs(p.across_x * f[0] + p.across_y * f[1]);
        row[CRS_WORLD_ROW_GROOVE_OFFSET] = p.offset_m;
        row[CRS_WORLD_ROW_GROOVE_ALONG] = p.along_m;
        row[CRS_WORLD_ROW_GROOVE_SEGMENT] = p.segment;
    } else {
        row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE] = row[CRS_WORLD_ROW_GROOVE_OFFSET] = 0.0;
        row[CRS_WORLD_ROW_GROOVE_ALONG] = 0.0;
        row[CRS_WORLD_ROW_GROOVE_SEGMENT] = -1.0;
    }
    pressed(c, CRS_FIXTURE_TABLE, f);
    row[CRS_WORLD_ROW_TABLE_FORCE] = norm3(f);
}
