/* The world's quantities per tick: see world.h. */
#include "world.h"

#include <math.h>
#include <string.h>

enum { CRS_EGG_FLAT_PERCENT = 20 }; /* a broken egg keeps a fifth of its height (drawn, not felt) */

void crs_world_init(crs_world *w)
{
    memset(w, 0, sizeof *w);
    w->peg_tip_adr = -1;
    for (int i = 0; i < CRS_WORLD_FIXTURES; ++i) w->sensor_adr[i] = -1;
    w->broke_tick = -1;
}

/* The force (N) the arm presses on fixture `i`: minus what its sensor reads (the force holding
 * the fixture in place); zero when the world has no such fixture. */
static void pressed(const crs_world *w, int i, double f[3])
{
    const int32_t adr = w->sensor_adr[i];
    for (int k = 0; k < 3; ++k) f[k] = adr >= 0 ? -w->sensordata[adr + k] : 0.0;
}

static double norm3(const double f[3]) { return sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]); }

double crs_world_across_groove(const double xy[8], double px, double py, double fx, double fy)
{
    double best = INFINITY, across = 0.0;
    for (int s = 0; s < 3; ++s) {
        const double ax = xy[2 * s], ay = xy[2 * s + 1];
        const double dx = xy[2 * s + 2] - ax, dy = xy[2 * s + 3] - ay;
        const double len2 = dx * dx + dy * dy;
        double t = len2 > 0.0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        const double ex = ax + t * dx - px, ey = ay + t * dy - py;
        const double dist2 = ex * ex + ey * ey;
        if (dist2 < best && len2 > 0.0) {
            best = dist2;
            const double len = sqrt(len2);
            across = fabs(-dy / len * fx + dx / len * fy); /* onto the segment's left normal */
        }
    }
    return across;
}

void crs_world_update(crs_world *w, int64_t tick)
{
    double *row = w->row;
    if (w->peg_tip_adr >= 0) {
        for (int k = 0; k < 3; ++k) row[CRS_WORLD_ROW_PEG_TIP + k] = w->sensordata[w->peg_tip_adr + k];
    }
    double f[3];
    pressed(w, CRS_WORLD_EGG, f);
    const double egg_n = norm3(f);
    const double egg_down_n = -f[2];
    pressed(w, CRS_WORLD_SCALE, f);
    const double scale_down_n = -f[2] + egg_down_n; /* the scale carries what presses the egg down */
    row[CRS_WORLD_ROW_EGG_FORCE] = egg_n;
    row[CRS_WORLD_ROW_SCALE_G] = w->gravity_m_s2 > 0.0 ? scale_down_n / w->gravity_m_s2 * 1000.0 : 0.0;
    if (!w->egg_broken && w->breaking_force_n > 0.0 && egg_n > w->breaking_force_n) {
        w->egg_broken = 1;
        w->broke_tick = tick;
        /* crushed: the shell no longer holds anything up, and it lies flat on the scale */
        if (w->egg_contype != NULL) *w->egg_contype = 0;
        if (w->egg_conaffinity != NULL) *w->egg_conaffinity = 0;
        if (w->egg_size_m != NULL && w->egg_pos_m != NULL) {
            const double bottom = w->egg_pos_m[2] - w->egg_size_m[2];
            w->egg_size_m[2] *= CRS_EGG_FLAT_PERCENT / 100.0;
            w->egg_pos_m[2] = bottom + w->egg_size_m[2];
        }
    }
    row[CRS_WORLD_ROW_EGG_BROKEN] = w->egg_broken;
    pressed(w, CRS_WORLD_HOLE, f);
    row[CRS_WORLD_ROW_HOLE_FORCE] = norm3(f);
    pressed(w, CRS_WORLD_OBSTACLE, f);
    row[CRS_WORLD_ROW_OBSTACLE_FORCE] = norm3(f);
    pressed(w, CRS_WORLD_GROOVE, f);
    row[CRS_WORLD_ROW_GROOVE_FORCE] = norm3(f);
    row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE] = w->sensor_adr[CRS_WORLD_GROOVE] >= 0
        ? crs_world_across_groove(w->groove_xy_m, row[CRS_WORLD_ROW_PEG_TIP], row[CRS_WORLD_ROW_PEG_TIP + 1],
                                  f[0], f[1])
        : 0.0;
    pressed(w, CRS_WORLD_TABLE, f);
    row[CRS_WORLD_ROW_TABLE_FORCE] = norm3(f);
}
