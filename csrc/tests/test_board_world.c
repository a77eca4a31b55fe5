/* C-level tests of the world's per-tick quantities (csrc/plant/world.c) on hand-made sensor
 * readings; built with -Werror and under ASan/UBSan by tests/test_c_core.py. */
#include <stdio.h>

#include "world.h"

#include "checks.h"

/* sensordata laid out as a scene would: the peg tip (3), then the forces of hole, groove, egg,
 * scale (3 each) */
enum { TIP = 0, HOLE = 3, GROOVE = 6, EGG = 9, SCALE = 12, N = 15 };

/* One world on hand-made readings, with the egg's geom fields it writes when the egg breaks. */
typedef struct {
    double data[N];
    int32_t contype, conaffinity;
    double size[3], pos[3]; /* the egg's half-sizes and centre (m) */
    crs_world w;
} bench;

static void setup(bench *b, const double size[3], const double pos[3])
{
    *b = (bench){.contype = 0, .conaffinity = 1};
    for (int i = 0; i < 3; ++i) {
        b->size[i] = size[i];
        b->pos[i] = pos[i];
    }
    crs_world *w = &b->w;
    crs_world_init(w);
    w->enabled = 1;
    w->sensordata = b->data;
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
    w->egg_contype = &b->contype;
    w->egg_conaffinity = &b->conaffinity;
    w->egg_size_m = b->size;
    w->egg_pos_m = b->pos;
}

/* A fixture's sensor reads the force holding it: the arm presses the opposite. 9.80665 N of
 * downward press on the egg shows 1000 g; the force's size is the egg's force. */
static void test_egg_and_scale(void)
{
    bench b;
    setup(&b, (const double[3]){0.022, 0.022, 0.0285}, (const double[3]){0.0, 0.0, 0.269});
    b.data[EGG + 2] = 9.80665; /* the egg is held up by 9.80665 N: pressed down that hard */
    b.data[EGG + 0] = 0.3;     /* and pushed -x a little */
    crs_world_update(&b.w, 7);
    check_close("egg force", b.w.row[CRS_WORLD_ROW_EGG_FORCE], sqrt(9.80665 * 9.80665 + 0.09), 1e-12);
    check_close("grams: the downward part", b.w.row[CRS_WORLD_ROW_SCALE_G], 1000.0, 1e-9);
    check("whole", b.w.row[CRS_WORLD_ROW_EGG_BROKEN] == 0.0 && b.w.broke_tick == -1 && b.conaffinity == 1);
    /* pressing on the scale beside the egg counts on the scale, not on the egg */
    b.data[SCALE + 2] = 4.903325;
    crs_world_update(&b.w, 8);
    check_close("scale adds", b.w.row[CRS_WORLD_ROW_SCALE_G], 1500.0, 1e-9);
    b.data[SCALE + 2] = 0.0;
    /* just past the breaking force: broken, latched, the egg flattened onto the scale */
    b.data[EGG + 0] = 0.0;
    b.data[EGG + 2] = 20.0 + 1e-9;
    crs_world_update(&b.w, 9);
    check("broken", b.w.row[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && b.w.egg_broken == 1 && b.w.broke_tick == 9);
    check("no longer collides", b.contype == 0 && b.conaffinity == 0);
    check_close("flat", b.size[2], 0.0285 * 0.2, 1e-15);
    check_close("still on the scale", b.pos[2] - b.size[2], 0.269 - 0.0285, 1e-15);
    b.data[EGG + 2] = 0.0;
    crs_world_update(&b.w, 10);
    check("latched", b.w.row[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && b.w.broke_tick == 9);
    check_close("a broken egg holds nothing", b.w.row[CRS_WORLD_ROW_SCALE_G], 0.0, 0.0);
}

/* exactly the breaking force does not break it */
static void test_at_breaking_force(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    b.data[EGG + 2] = 20.0;
    crs_world_update(&b.w, 1);
    check("at the force: whole", b.w.egg_broken == 0 && b.conaffinity == 1);
}

/* The groove's side force: the horizontal force across the segment nearest the peg's tip. */
static void test_groove_side(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    /* on segment 1 (direction (3, -4)/5): a force along x has 4/5 of itself across */
    b.data[TIP + 0] = 0.015;
    b.data[TIP + 1] = -0.02;
    b.data[GROOVE + 0] = -2.0; /* the plate is held by -2 N in x: pressed +2 N */
    b.data[GROOVE + 2] = 1.0;  /* and pressed down 1 N, which is not across */
    crs_world_update(&b.w, 1);
    check_close("across segment 1", b.w.row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 1.6, 1e-12);
    check_close("whole force", b.w.row[CRS_WORLD_ROW_GROOVE_FORCE], sqrt(5.0), 1e-12);
    check_close("tip", b.w.row[CRS_WORLD_ROW_PEG_TIP + 1], -0.02, 0.0);
    /* on segment 2 (along -x): the same x force is along it, none across */
    b.data[TIP + 0] = 0.015;
    b.data[TIP + 1] = -0.041;
    crs_world_update(&b.w, 2);
    check_close("along segment 2", b.w.row[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 0.0, 1e-12);
    check_close("direct", crs_world_across_groove(b.w.groove_xy_m, 0.015, -0.041, 0.0, 3.0), 3.0, 1e-12);
    check_close("hole untouched", b.w.row[CRS_WORLD_ROW_HOLE_FORCE], 0.0, 0.0);
    check_close("no table", b.w.row[CRS_WORLD_ROW_TABLE_FORCE], 0.0, 0.0);
}

int main(void)
{
    test_egg_and_scale();
    test_at_breaking_force();
    test_groove_side();
    return checks_report();
}
