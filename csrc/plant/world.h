/* The world the arm touches (crslab/world): what its fixtures feel, worked out once per tick after
 * mj_step from the scene's sensors (crslab/world/scene.py), in a caller-owned crs_world.
 *
 * The scene carries a position sensor at the peg's tip and a force sensor on each fixture body
 * (crs_world_fixture_name gives the bodies' names, in this order); MuJoCo fills them during the
 * step, for the state the step started from (the state the tick's row of the scope log shows). A
 * fixture's sensor reads the force that holds it in place, so the force the arm presses on it is
 * the opposite. The obstacle is three bodies at one place, each touched by one part of the arm
 * only (collision bits): what each part presses on it is its own sensor's.
 *
 * Every quantity of the world is computed here and only here (the scope log's world row, the
 * peg's depth in the hole, the groove's nearest segment, the egg's break and what broke it);
 * Python reads them from the row, or calls these functions through cffi. Read by cffi: plain
 * declarations only. */
#ifndef CRSLAB_WORLD_H
#define CRSLAB_WORLD_H

#include <stdint.h>

#include "world_facts.h"

/* The fixtures with a force sensor, in the scene's sensor order after the peg tip's position. */
enum {
    CRS_FIXTURE_TABLE = 0,
    CRS_FIXTURE_HOLE = 1,
    CRS_FIXTURE_OBSTACLE = 2,           /* the obstacle as the peg (and its gripper) meets it */
    CRS_FIXTURE_OBSTACLE_FOREARM = 3,   /* ... as the forearm (and the wrist) meets it */
    CRS_FIXTURE_OBSTACLE_UPPER_ARM = 4, /* ... as the upper arm meets it */
    CRS_FIXTURE_GROOVE = 5,
    CRS_FIXTURE_EGG = 6,
    CRS_FIXTURE_SCALE = 7,
    CRS_FIXTURES = 8
};

/* One row of world quantities in the scope log (crs_world_state.row, crs_log.world): each
 * quantity's offset; crs_world_columns() gives names, widths and units in the same order. */
enum {
    CRS_WORLD_ROW_PEG_TIP = 0,             /* 3: the peg's tip x, y, z, m */
    CRS_WORLD_ROW_PEG_DEPTH = 3,           /* m below the hole's top, within its radius; else 0 */
    CRS_WORLD_ROW_EGG_FORCE = 4,           /* N the arm presses on the egg (its size) */
    CRS_WORLD_ROW_EGG_FORCE_XYZ = 5,       /* 3: that force, world frame, N */
    CRS_WORLD_ROW_SCALE_G = 8,             /* what the scale shows, grams (tared) */
    CRS_WORLD_ROW_EGG_BROKEN = 9,          /* 0 or 1, latched */
    CRS_WORLD_ROW_EGG_BROKEN_BY = 10,      /* CRS_EGG_WHOLE, CRS_EGG_BROKEN_BY_*, latched */
    CRS_WORLD_ROW_EGG_TOUCH_SPEED = 11,    /* m/s down when the present egg contact began; 0 off it */
    CRS_WORLD_ROW_HOLE_FORCE = 12,         /* N on the hole block */
    CRS_WORLD_ROW_OBSTACLE_FORCE = 13,     /* N on the obstacle, all parts of the arm together */
    CRS_WORLD_ROW_OBSTACLE_PEG_FORCE = 14, /* N on it by the peg and its gripper */
    CRS_WORLD_ROW_OBSTACLE_FOREARM_FORCE = 15,   /* N by the forearm and the wrist */
    CRS_WORLD_ROW_OBSTACLE_UPPER_ARM_FORCE = 16, /* N by the upper arm */
    CRS_WORLD_ROW_GROOVE_FORCE = 17,       /* N on the groove plate */
    CRS_WORLD_ROW_GROOVE_SIDE_FORCE = 18,  /* N across the groove's segment the tip is nearest */
    CRS_WORLD_ROW_GROOVE_OFFSET = 19,      /* m from the Z's centre line (x-y) to the tip */
    CRS_WORLD_ROW_GROOVE_ALONG = 20,       /* m along the centre line from the entrance to the
                                              point nearest the tip */
    CRS_WORLD_ROW_GROOVE_SEGMENT = 21,     /* the nearest segment, 0 to 2; -1 without a groove */
    CRS_WORLD_ROW_TABLE_FORCE = 22,        /* N on the table */
    CRS_WORLD_ROW = 23
};

/* One quantity of the row: its name (the scope log's column, the CSV's with _x _y _z for three),
 * unit, what it is, and its place. */
typedef struct {
    const char *name;
    const char *unit;
    const char *what;
    int32_t offset;
    int32_t width;
} crs_world_column;

/* What a run's world is configured with: set once when the run starts (crs_world_attach). */
typedef struct {
    const double *sensordata;     /* MuJoCo's mjData.sensordata */
    int32_t peg_tip_adr;          /* index of the peg tip's position in sensordata; -1: no peg */
    int32_t sensor_adr[CRS_FIXTURES]; /* index of each fixture's force in sensordata; -1: none */
    int32_t has_hole;             /* 0: the world has no hole (the depth is 0) */
    int32_t has_groove;           /* 0: no groove (its offset, along and segment say so) */
    int32_t pad;
    double timestep_s;            /* one physics step, s: the tip's speed */
    double breaking_force_n;      /* the egg breaks when pressed harder (0: it never breaks) */
    double hole_xy_m[2];          /* the hole's axis */
    double hole_top_z_m;          /* its top (the block's) */
    double hole_radius_m;         /* its radius below the chamfer */
    double groove_xy_m[8];        /* the Z's centre line: entrance, corner 1, corner 2, exit (x, y) */
    int32_t *egg_contype;         /* the egg geom's collision bits in mjModel: cleared when it breaks */
    int32_t *egg_conaffinity;
    double *egg_size_m;           /* the egg geom's half sizes and position in mjModel: flattened */
    double *egg_pos_m;            /* onto the scale when it breaks (what the viewers draw) */
} crs_world_config;

/* What a run's world changes each tick. */
typedef struct {
    int32_t egg_broken;           /* 1 from the tick the egg broke on */
    int32_t egg_broken_by;        /* CRS_EGG_BROKEN_BY_* from then on */
    int64_t broke_tick;           /* -1 until it breaks */
    int32_t egg_touching;         /* the peg touched the egg on the last step */
    int32_t has_last_tip;         /* last_tip_z_m holds the last step's tip */
    double last_tip_z_m;
    double egg_touch_speed_m_s;   /* how fast the tip came down when this contact began */
    double row[CRS_WORLD_ROW];    /* CRS_WORLD_ROW_*: the quantities of the step just taken */
} crs_world_state;

typedef struct {
    int32_t enabled;              /* 0: world none, nothing to do */
    int32_t pad;
    crs_world_config config;
    crs_world_state state;
} crs_world;

/* The nearest point of the groove's centre line to a point (x-y). */
typedef struct {
    int32_t segment;              /* 0 to 2 */
    int32_t pad;
    double offset_m;              /* distance from the point to the centre line */
    double along_m;               /* from the entrance along the centre line to the nearest point */
    double across_x, across_y;    /* the segment's unit normal (its left) */
} crs_groove_point;

/* Zero the world: disabled, no sensors, the egg whole. */
void crs_world_init(crs_world *w);
/* Configure the world for a run (one assignment) and enable it; its state starts afresh. */
void crs_world_attach(crs_world *w, const crs_world_config *config);
/* This step's quantities from the sensors into w->state.row; the egg breaks (latched) when the
 * arm presses it harder than the breaking force. `tick` is the tick whose step this was. */
void crs_world_update(crs_world *w, int64_t tick);
/* The row's quantities, in order; *count gets how many. */
const crs_world_column *crs_world_columns(int32_t *count);
/* The name of fixture `fixture` (CRS_FIXTURE_*): its body in the scene, its sensor `NAME_force`;
 * NULL outside 0 .. CRS_FIXTURES - 1. */
const char *crs_world_fixture_name(int32_t fixture);
/* What CRS_EGG_BROKEN_BY_* says in words ("the press", "a side hit", "a fall"; "" when whole). */
const char *crs_egg_broken_by_name(int32_t broken_by);

/* The nearest point of the polyline `xy` (4 points: the groove's centre line) to (px, py). */
crs_groove_point crs_groove_nearest(const double xy[8], double px, double py);
/* The component (N) of a horizontal force (fx, fy) across the segment of the polyline `xy`
 * nearest to the point (px, py): what the groove's side walls push with. */
double crs_groove_across(const double xy[8], double px, double py, double fx, double fy);
/* How deep (m) a tip at `tip` is in a hole of radius `radius_m` whose axis is at `hole_xy` and
 * whose top is at `top_z_m`: below the top while within the radius of the axis; 0 elsewhere. */
double crs_peg_depth(const double hole_xy[2], double top_z_m, double radius_m, const double tip[3]);
/* crs_peg_depth of `n` tips (x, y, z, one after the other) into depth_m[n]. */
void crs_peg_depths(const double hole_xy[2], double top_z_m, double radius_m, const double *tips, int64_t n,
                    double *depth_m);
/* crs_groove_nearest of `n` points (x, y, each `stride` doubles after the last) into segment[n],
 * offset_m[n] and along_m[n]. */
void crs_groove_nearest_many(const double xy[8], const double *points, int64_t n, int64_t stride, int32_t *segment,
                             double *offset_m, double *along_m);
/* What broke an egg pressed with force `f` (N, world frame) by a tip that came down onto it at
 * `touch_speed_m_s`: CRS_EGG_BROKEN_BY_SIDE, _FALL or _PRESS. */
int32_t crs_egg_break_cause(const double f[3], double touch_speed_m_s);
/* Lay an egg geom (half sizes and centre, m) flat onto what it stands on: it keeps
 * CRS_EGG_FLAT_SHARE of its height, its bottom where it was. */
void crs_egg_flatten(double size_m[3], double pos_m[3]);

#endif
