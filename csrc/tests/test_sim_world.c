/* C-level tests of the world's per-tick quantities (csrc/plant/world.c) on hand-made sensor
 * readings; built with -Werror and under ASan/UBSan by tests/test_c_core.py. */
#include <stdio.h>

#include "world.h"

#include "checks.h"

/* sensordata laid out as a scene would: the peg tip (3), then the forces of hole, groove, egg,
 * scale (3 each) */
enum { TIP = 0, HOLE = 3, GROOVE = 6, EGG = 9, SCALE = 12, N = 15 };

static void setup(crs_world *w, double *data, int32_t *contype, int32_t *conaffinity, double *size,
                  double *pos)
{
    crs_world_init(w);
    w->enabled = 1;
    w->sensordata = data;
    w->peg_tip_adr = TIP;
    w->sensor_adr[CRS_WORLD_HOLE] = HOLE;
    w->sensor_adr[CRS_WORLD_GROOVE] = GROOVE;
    w->sensor_adr[CRS_WORLD_EGG] = EGG;
    w->sensor_adr[CRS_WORLD_SCALE] = SCALE;
    w->breaking_force_n = 20.0;
    w->gravity_m_s2 = 9.80665;
    /* a Z: (0, 0) -> (3, -4) -> (0, -4) -> (3, -8) cm */
    const double z[8] = {0.0, 0.0, 0.03, -0.04, 0.0, -0.04, 0.03, -0.08};
    for (int i = 0; i < 8; ++i) w->groove_xy_m[i] = z[i];
    w->egg_contype = contype;
    w->egg_conaffinity = conaffinity;
    w->egg_size_m = size;
    w->egg_pos_m = pos;
}

/* A fixture's sensor reads the force holding it: the arm presses the opposite. 9.80665 N of
 * downward press on the egg shows 1000 g; the force's size is the egg's force. */
static void test_egg_and_scale(void)
{
    double data[N] = {0};
    int32_t contype = 0, conaffinity = 1;
    double size[3] = {0.022, 0.022, 0.0285}, pos[3] = {0.0, 0.0, 0.269};
    crs_world w;
    setup(&w, data, &contype, &conaffinity, size, pos);
    data[EGG + 2] = 9.80665; /* the egg is held up by 9.80665 N: pressed down that hard */
    data[EGG + 0] = 0.3;     /* and pushed -x a little */
    crs_world_update(&w, 7);
    check_close("egg force", w.row[CRS_WORLD_ROW_EGG_FORCE], sqrt(9.80665 * 9.80665 + 0.09), 1e-12);
    check_close("grams: the downward part", w.row[CRS_WORLD_ROW_SCALE_G], 1000.0, 1e-9);
    check("whole", w.row[CRS_WORLD_ROW_EGG_BROKEN] == 0.0 && w.broke_tick == -1 && conaffinity == 1);
    /* pressing on the scale beside the egg counts on the scale, not on the egg */
    data[SCALE + 2] = 4.903325;
    crs_world_update(&w, 8);
    check_close("scale adds", w.row[CRS_WORLD_ROW_SCALE_G], 1500.0, 1e-9);
    data[SCALE + 2] = 0.0;
    /* just past the breaking force: broken, latched, the egg flattened onto the scale */
    data[EGG + 0] = 0.0;
    data[EGG + 2] = 20.0 + 1e-9;
    crs_world_update(&w, 9);
    check("broken", w.row[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && w.egg_broken == 1 && w.broke_tick == 9);
    check("no longer collides", contype == 0 && conaffinity == 0);
    check_close("flat", size[2], 0.0285 * 0.2, 1e-15);
    check_close("still on the scale", pos[2] - size[2], 0.269 - 0.0285, 1e-15);
    data[EGG + 2] = 0.0;
    crs_world_update(&w, 10);
    check("latched", w.row[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && w.broke_tick == 9);
    check_close("a broken egg holds nothing", w.row[CRS_WORLD_ROW_SCALE_G], 0.0, 0.0);
}

/* exactly the breaking force does not break it */
static void test_at_breaking_force(void)
{
    double data[N] = {0};
    int32_t contype = 0, conaffinity = 1;
    double size[3] = {1, 1, 1}, pos[3] = {0, 0, 1};
    crs_world w;
    setup(&w, data, &contype, &conaffinity, size, pos);
    data[EGG + 2] = 20.0;
    crs_world_update(&w, 1);
    check("at the force: whole", w.egg_broken == 0 && conaffinity == 1);
}

/* The groove's side force: the horizontal force across the segment nearest the peg's tip. */
static void test_groove_side(void)
{
    double data[N] = {0};
    int32_t contype = 0, conaffinity = 1;
    double size[3] = {1, 1, 1}, pos[3] = {0, 0, 1};
    crs_world w;
    setup(&w, data, &contype, &conaffinity, size, pos);
    /* on segment 1 (direction (3, -4)/5): a force along x has 4/5 of itself across */
    data[TIP + 0] = 0.015;
    data[TIP + 1] = -0.02;
    data[GROOVE + 0] = -2.0; /* the plate is held by -2 N in x: pressed +2 N */
    data[GROOVE + 2] = 1.0;  /* and pressed down 1 N, which is not across */
    crs_world_update(&w, 1);
    check_close("across segment 1", w.row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 1.6, 1e-12);
    check_close("whole force", w.row[CRS_WORLD_ROW_GROOVE_FORCE], sqrt(5.0), 1e-12);
    check_close("tip", w.row[CRS_WORLD_ROW_PEG_TIP + 1], -0.02, 0.0);
    /* on segment 2 (along -x): the same x force is along it, none across */
    data[TIP + 0] = 0.015;
    data[TIP + 1] = -0.041;
    crs_world_update(&w, 2);
    check_close("along segment 2", w.row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 0.0, 1e-12);
    check_close("direct", crs_world_across_groove(w.groove_xy_m, 0.015, -0.041, 0.0, 3.0), 3.0, 1e-12);
    check_close("hole untouched", w.row[CRS_WORLD_ROW_HOLE_FORCE], 0.0, 0.0);
    check_close("no table", w.row[CRS_WORLD_ROW_TABLE_FORCE], 0.0, 0.0);
}

int main(void)
{
    test_egg_and_scale();
    test_at_breaking_force();
    test_groove_side();
    return checks_report();
}
