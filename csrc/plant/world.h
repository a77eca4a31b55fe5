/* The world the arm touches (crslab/world): what its fixtures feel, worked out once per tick after
 * mj_step from the scene's sensors (crslab/world/scene.py), in a caller-owned crs_world.
 *
 * The scene carries a position sensor at the peg's tip and a force sensor on each fixture body;
 * MuJoCo fills them during the step, for the state the step started from (the state the tick's
 * row of the scope log shows). A fixture's sensor reads the force that holds it in place, so the
 * force the arm presses on it is the opposite. Read by cffi (ABI mode): plain declarations only. */
#ifndef CRSLAB_WORLD_H
#define CRSLAB_WORLD_H

#include <stdint.h>

/* The fixtures with a force sensor (crs_world.sensor_adr after the peg tip). */
enum {
    CRS_WORLD_TABLE = 0, CRS_WORLD_HOLE = 1, CRS_WORLD_OBSTACLE = 2, CRS_WORLD_GROOVE = 3,
    CRS_WORLD_EGG = 4, CRS_WORLD_SCALE = 5, CRS_WORLD_FIXTURES = 6
};
/* One row of world quantities in the scope log (crs_world.row, crs_log.world). */
enum {
    CRS_WORLD_ROW_PEG_TIP = 0,        /* 3: the peg's tip x, y, z, m */
    CRS_WORLD_ROW_EGG_FORCE = 3,      /* N the arm presses on the egg */
    CRS_WORLD_ROW_SCALE_G = 4,        /* what the scale shows, grams (tared) */
    CRS_WORLD_ROW_EGG_BROKEN = 5,     /* 0 or 1, latched */
    CRS_WORLD_ROW_HOLE_FORCE = 6,     /* N on the hole block */
    CRS_WORLD_ROW_OBSTACLE_FORCE = 7, /* N on the obstacle (the peg or any arm link) */
    CRS_WORLD_ROW_GROOVE_SIDE_FORCE = 8, /* N across the groove's segment the peg is nearest */
    CRS_WORLD_ROW_GROOVE_FORCE = 9,   /* N on the groove plate */
    CRS_WORLD_ROW_TABLE_FORCE = 10,   /* N on the table */
    CRS_WORLD_ROW = 11
};

typedef struct {
    /* configuration, set by the worker from the world and its compiled scene */
    int32_t enabled;              /* 0: world none, nothing to do */
    int32_t peg_tip_adr;          /* index of the peg tip's position in sensordata; -1: no peg */
    int32_t sensor_adr[CRS_WORLD_FIXTURES]; /* index of each fixture's force in sensordata; -1: none */
    int32_t pad;
    const double *sensordata;     /* MuJoCo's mjData.sensordata */
    double breaking_force_n;      /* the egg breaks when pressed harder (0: it never breaks) */
    double gravity_m_s2;          /* g, for the scale's grams */
    double groove_xy_m[8];        /* entrance, corner 1, corner 2, exit (x, y) */
    int32_t *egg_contype;         /* the egg geom's collision bits in mjModel: cleared when it breaks */
    int32_t *egg_conaffinity;
    double *egg_size_m;           /* the egg geom's half sizes and position in mjModel: flattened */
    double *egg_pos_m;            /* onto the scale when it breaks (what the viewers draw) */

    /* state: this tick's quantities (row) and the latch */
    int32_t egg_broken;           /* 1 from the tick the egg broke on */
    int32_t pad2;
    int64_t broke_tick;           /* -1 until it breaks */
    double row[CRS_WORLD_ROW];    /* CRS_WORLD_ROW_*: the quantities of the step just taken */
} crs_world;

/* Zero the world: disabled, no sensors, the egg whole. */
void crs_world_init(crs_world *w);
/* This step's quantities from the sensors into w->row; the egg breaks (latched) when the arm
 * presses it harder than w->breaking_force_n. `tick` is the tick whose step this was. */
void crs_world_update(crs_world *w, int64_t tick);
/* The component (N) of a horizontal force (fx, fy) across the segment of the polyline
 * `xy` (4 points) nearest to the point (px, py): what the groove's side walls push with. */
double crs_world_across_groove(const double xy[8], double px, double py, double fx, double fy);

#endif
