/* C-level tests of the world's per-tick quantities (csrc/plant/world.c) on hand-made sensor
 * readings, each against numbers worked out by hand; built with -Werror and under ASan/UBSan by
 * tests/test_c_core.py. */
#include <stdio.h>
#include <string.h>

#include "world.h"

#include "checks.h"

/* sensordata laid out as a scene would: the peg tip (3), then each fixture's force (3 each) */
enum { TIP = 0, FORCES = 3, N = FORCES + 3 * CRS_FIXTURES };

/* One world on hand-made readings, with the egg's geom fields it writes when the egg breaks. */
typedef struct {
    double data[N];
    int32_t contype, conaffinity;
    double size[3], pos[3]; /* the egg's half-sizes and centre (m) */
    crs_world w;
} bench;

/* the force sensor reading of fixture i (the force holding it: the arm presses the opposite) */
static double *held(bench *b, int fixture) { return &b->data[FORCES + 3 * fixture]; }

static void setup(bench *b, const double size[3], const double pos[3])
{
    memset(b, 0, sizeof *b);
    b->conaffinity = 1;
    for (int i = 0; i < 3; ++i) {
        b->size[i] = size[i];
        b->pos[i] = pos[i];
    }
    crs_world_config c = {.sensordata = b->data, .peg_tip_adr = TIP, .has_hole = 1, .has_groove = 1,
                          .timestep_s = 0.001, .breaking_force_n = 20.0,
                          .hole_xy_m = {0.10, 0.20}, .hole_top_z_m = 0.16, .hole_radius_m = 0.007,
                          .egg_contype = &b->contype, .egg_conaffinity = &b->conaffinity,
                          .egg_size_m = b->size, .egg_pos_m = b->pos};
    for (int i = 0; i < CRS_FIXTURES; ++i) c.sensor_adr[i] = FORCES + 3 * i;
    /* a Z: (0, 0) -> (3, -4) -> (0, -4) -> (3, -8) cm: segments 5, 3 and 5 cm long */
    const double z[8] = {0.0, 0.0, 0.03, -0.04, 0.0, -0.04, 0.03, -0.08};
    memcpy(c.groove_xy_m, z, sizeof z);
    crs_world_init(&b->w);
    crs_world_attach(&b->w, &c);
}

static const double *row(bench *b) { return b->w.state.row; }

/* 9.80665 N of downward press on the egg shows 1000 g; the force's size is the egg's force. */
static void test_egg_and_scale(void)
{
    bench b;
    setup(&b, (const double[3]){0.022, 0.022, 0.0285}, (const double[3]){0.0, 0.0, 0.269});
    held(&b, CRS_FIXTURE_EGG)[2] = 9.80665; /* the egg is held up by 9.80665 N: pressed down that hard */
    held(&b, CRS_FIXTURE_EGG)[0] = 0.3;     /* and pushed -x a little */
    crs_world_update(&b.w, 7);
    check_close("egg force", row(&b)[CRS_WORLD_ROW_EGG_FORCE], sqrt(9.80665 * 9.80665 + 0.09), 1e-12);
    check_close("egg force x", row(&b)[CRS_WORLD_ROW_EGG_FORCE_XYZ], -0.3, 0.0);
    check_close("egg force z: down", row(&b)[CRS_WORLD_ROW_EGG_FORCE_XYZ + 2], -9.80665, 0.0);
    check_close("grams: the downward part", row(&b)[CRS_WORLD_ROW_SCALE_G], 1000.0, 1e-9);
    check("whole", row(&b)[CRS_WORLD_ROW_EGG_BROKEN] == 0.0 && row(&b)[CRS_WORLD_ROW_EGG_BROKEN_BY] == 0.0
                       && b.w.state.broke_tick == -1 && b.conaffinity == 1);
    /* pressing on the scale beside the egg counts on the scale, not on the egg */
    held(&b, CRS_FIXTURE_SCALE)[2] = 4.903325;
    crs_world_update(&b.w, 8);
    check_close("scale adds", row(&b)[CRS_WORLD_ROW_SCALE_G], 1500.0, 1e-9);
    held(&b, CRS_FIXTURE_SCALE)[2] = 0.0;
    /* just past the breaking force: broken, latched, the egg flattened onto the scale */
    held(&b, CRS_FIXTURE_EGG)[0] = 0.0;
    held(&b, CRS_FIXTURE_EGG)[2] = 20.0 + 1e-9;
    crs_world_update(&b.w, 9);
    check("broken", row(&b)[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && b.w.state.egg_broken == 1
                        && b.w.state.broke_tick == 9);
    check("by the press", row(&b)[CRS_WORLD_ROW_EGG_BROKEN_BY] == CRS_EGG_BROKEN_BY_PRESS);
    check("no longer collides", b.contype == 0 && b.conaffinity == 0);
    check_close("flat: a fifth of its height", b.size[2], 0.0285 * 0.2, 1e-15);
    check_close("still on the scale", b.pos[2] - b.size[2], 0.269 - 0.0285, 1e-15);
    held(&b, CRS_FIXTURE_EGG)[2] = 0.0;
    crs_world_update(&b.w, 10);
    check("latched", row(&b)[CRS_WORLD_ROW_EGG_BROKEN] == 1.0 && b.w.state.broke_tick == 9
                         && row(&b)[CRS_WORLD_ROW_EGG_BROKEN_BY] == CRS_EGG_BROKEN_BY_PRESS);
    check_close("a broken egg holds nothing", row(&b)[CRS_WORLD_ROW_SCALE_G], 0.0, 0.0);
}

/* exactly the breaking force does not break it */
static void test_at_breaking_force(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    held(&b, CRS_FIXTURE_EGG)[2] = 20.0;
    crs_world_update(&b.w, 1);
    check("at the force: whole", b.w.state.egg_broken == 0 && b.conaffinity == 1);
}

/* The tip comes down from z0 by `mm_per_tick` a tick onto the egg; on the tick it touches, the egg
 * holds it with `force` (x, y, z as the sensor reads). Returns what broke it. */
static int32_t break_egg(double mm_per_tick, const double force[3])
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    double z = 0.30;
    for (int k = 0; k < 5; ++k) {
        b.data[TIP + 2] = z;
        crs_world_update(&b.w, k);
        z -= mm_per_tick / 1000.0;
    }
    check_close("no touch yet: no speed", row(&b)[CRS_WORLD_ROW_EGG_TOUCH_SPEED], 0.0, 0.0);
    b.data[TIP + 2] = z;
    for (int k = 0; k < 3; ++k) held(&b, CRS_FIXTURE_EGG)[k] = force[k];
    crs_world_update(&b.w, 5);
    /* the speed of the step into the touch: mm_per_tick mm in 1 ms */
    check_close("touch speed", row(&b)[CRS_WORLD_ROW_EGG_TOUCH_SPEED], mm_per_tick, 1e-9);
    return (int32_t)row(&b)[CRS_WORLD_ROW_EGG_BROKEN_BY];
}

/* What broke it: a side hit when its horizontal force outweighs the downward one; a fall when the
 * tip came down faster than CRS_EGG_FALL_M_S (0.2 m/s = 0.2 mm per 1 ms tick); else the press. */
static void test_what_broke_the_egg(void)
{
    const double down[3] = {0.0, 0.0, 25.0}, side[3] = {18.0, -12.0, 15.0}, steep[3] = {12.0, 9.0, 20.0};
    check("slow, from above: the press", break_egg(0.02, down) == CRS_EGG_BROKEN_BY_PRESS);
    check("fast, from above: a fall", break_egg(0.5, down) == CRS_EGG_BROKEN_BY_FALL);
    check("just over the fall's speed", break_egg(0.2001, down) == CRS_EGG_BROKEN_BY_FALL);
    check("at the fall's speed: the press", break_egg(0.1999, down) == CRS_EGG_BROKEN_BY_PRESS);
    /* |(18, -12)| = 21.6 > 15: sideways, however slow */
    check("from the side: a side hit", break_egg(0.02, side) == CRS_EGG_BROKEN_BY_SIDE);
    /* |(12, 9)| = 15 < 20 down */
    check("slanted but mostly down: the press", break_egg(0.02, steep) == CRS_EGG_BROKEN_BY_PRESS);
    check("names", strcmp(crs_egg_broken_by_name(CRS_EGG_BROKEN_BY_SIDE), "a side hit") == 0
                       && strcmp(crs_egg_broken_by_name(CRS_EGG_WHOLE), "") == 0);
}

/* A touch's speed stays what it was when the touch began, and is 0 off the egg. */
static void test_touch_speed_is_the_contacts_start(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    b.data[TIP + 2] = 0.300;
    crs_world_update(&b.w, 0);
    b.data[TIP + 2] = 0.2999; /* 0.1 mm in 1 ms: 0.1 m/s */
    held(&b, CRS_FIXTURE_EGG)[2] = 3.0;
    crs_world_update(&b.w, 1);
    check_close("touch", row(&b)[CRS_WORLD_ROW_EGG_TOUCH_SPEED], 0.1, 1e-9);
    b.data[TIP + 2] = 0.2999; /* stopped, still pressing */
    crs_world_update(&b.w, 2);
    check_close("kept while pressing", row(&b)[CRS_WORLD_ROW_EGG_TOUCH_SPEED], 0.1, 1e-9);
    held(&b, CRS_FIXTURE_EGG)[2] = 0.0;
    crs_world_update(&b.w, 3);
    check_close("off the egg", row(&b)[CRS_WORLD_ROW_EGG_TOUCH_SPEED], 0.0, 0.0);
}

/* The groove's side force, nearest point and along-distance on the 3-4-5 Z. */
static void test_groove(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    /* on segment 0 (direction (3, -4)/5), 1 cm left of its middle (1.5, -2) cm: the left normal
     * is (4, 3)/5, so the tip at (1.5 + 0.8, -2 + 0.6) cm */
    b.data[TIP + 0] = 0.023;
    b.data[TIP + 1] = -0.014;
    held(&b, CRS_FIXTURE_GROOVE)[0] = -2.0; /* the plate is held by -2 N in x: pressed +2 N */
    held(&b, CRS_FIXTURE_GROOVE)[2] = 1.0;  /* and pressed down 1 N, which is not across */
    crs_world_update(&b.w, 1);
    /* +2 N along x: across (4, 3)/5 is 1.6 N, along (3, -4)/5 1.2 N */
    check_close("across segment 0", row(&b)[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 1.6, 1e-12);
    check_close("whole force", row(&b)[CRS_WORLD_ROW_GROOVE_FORCE], sqrt(5.0), 1e-12);
    check_close("offset", row(&b)[CRS_WORLD_ROW_GROOVE_OFFSET], 0.01, 1e-12);
    check_close("along: half of 5 cm", row(&b)[CRS_WORLD_ROW_GROOVE_ALONG], 0.025, 1e-12);
    check("segment 0", row(&b)[CRS_WORLD_ROW_GROOVE_SEGMENT] == 0.0);
    /* a force along the segment has nothing across it */
    held(&b, CRS_FIXTURE_GROOVE)[0] = -3.0;
    held(&b, CRS_FIXTURE_GROOVE)[1] = 4.0;
    crs_world_update(&b.w, 2);
    check_close("along segment 0: none across", row(&b)[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 0.0, 1e-12);
    /* on segment 1 (along -x, from (3, -4) to (0, -4)), 1 mm below it at x = 1 cm: the same
     * force has its y part, 4 N, across; along: 5 cm + 2 cm */
    b.data[TIP + 0] = 0.010;
    b.data[TIP + 1] = -0.041;
    crs_world_update(&b.w, 3);
    check_close("across segment 1", row(&b)[CRS_WORLD_ROW_GROOVE_SIDE_FORCE], 4.0, 1e-12);
    check_close("offset 1 mm", row(&b)[CRS_WORLD_ROW_GROOVE_OFFSET], 0.001, 1e-12);
    check_close("along 7 cm", row(&b)[CRS_WORLD_ROW_GROOVE_ALONG], 0.07, 1e-12);
    check("segment 1", row(&b)[CRS_WORLD_ROW_GROOVE_SEGMENT] == 1.0);
    check_close("direct", crs_groove_across(b.w.config.groove_xy_m, 0.01, -0.041, 0.0, 3.0), 3.0, 1e-12);
    /* past the exit (3, -8) cm by 1 cm along segment 2: the nearest point is the exit itself */
    const crs_groove_point p = crs_groove_nearest(b.w.config.groove_xy_m, 0.036, -0.088);
    check("past the exit: segment 2", p.segment == 2);
    check_close("past the exit: 13 cm along", p.along_m, 0.13, 1e-12);
    check_close("past the exit: 1 cm off", p.offset_m, 0.01, 1e-12);
    check_close("hole untouched", row(&b)[CRS_WORLD_ROW_HOLE_FORCE], 0.0, 0.0);
    check_close("table untouched", row(&b)[CRS_WORLD_ROW_TABLE_FORCE], 0.0, 0.0);
}

/* The peg's depth: below the hole's top while within its radius of the axis (0.10, 0.20). */
static void test_peg_depth(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    const double cases[][4] = {
        /* x, y, z, depth */
        {0.10, 0.20, 0.12, 0.04},       /* on the axis, 4 cm below the top */
        {0.106, 0.20, 0.15, 0.01},      /* 6 mm off the axis: inside the 7 mm radius */
        {0.10, 0.2071, 0.12, 0.0},      /* 7.1 mm off: outside */
        {0.10, 0.20, 0.161, 0.0},       /* above the top */
    };
    for (int i = 0; i < 4; ++i) {
        for (int k = 0; k < 3; ++k) b.data[TIP + k] = cases[i][k];
        crs_world_update(&b.w, i);
        check_close("depth", row(&b)[CRS_WORLD_ROW_PEG_DEPTH], cases[i][3], 1e-12);
        check_close("depth, direct", crs_peg_depth(b.w.config.hole_xy_m, 0.16, 0.007, cases[i]), cases[i][3], 1e-12);
    }
    b.w.config.has_hole = 0;
    for (int k = 0; k < 3; ++k) b.data[TIP + k] = cases[0][k];
    crs_world_update(&b.w, 9);
    check_close("no hole: no depth", row(&b)[CRS_WORLD_ROW_PEG_DEPTH], 0.0, 0.0);
}

/* What each part of the arm presses on the obstacle; the total is their sum as forces. */
static void test_obstacle_parts(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    held(&b, CRS_FIXTURE_OBSTACLE)[0] = -3.0;             /* the peg pushes +x with 3 N */
    held(&b, CRS_FIXTURE_OBSTACLE_FOREARM)[1] = -4.0;     /* the forearm +y with 4 N */
    held(&b, CRS_FIXTURE_OBSTACLE_UPPER_ARM)[0] = 3.0;    /* the upper arm -x with 3 N */
    crs_world_update(&b.w, 1);
    check_close("by the peg", row(&b)[CRS_WORLD_ROW_OBSTACLE_PEG_FORCE], 3.0, 0.0);
    check_close("by the forearm", row(&b)[CRS_WORLD_ROW_OBSTACLE_FOREARM_FORCE], 4.0, 0.0);
    check_close("by the upper arm", row(&b)[CRS_WORLD_ROW_OBSTACLE_UPPER_ARM_FORCE], 3.0, 0.0);
    check_close("together: (0, 4, 0)", row(&b)[CRS_WORLD_ROW_OBSTACLE_FORCE], 4.0, 1e-15);
}

/* The column table names the enum's offsets, in order, without gaps. */
static void test_columns(void)
{
    int32_t n = 0;
    const crs_world_column *c = crs_world_columns(&n);
    int32_t at = 0;
    for (int i = 0; i < n; ++i) {
        check("in order, no gaps", c[i].offset == at && c[i].width >= 1);
        for (int j = 0; j < i; ++j) check("unique names", strcmp(c[i].name, c[j].name) != 0);
        at += c[i].width;
    }
    check("the row's width", at == CRS_WORLD_ROW);
    check("first and last", strcmp(c[0].name, "peg_tip") == 0 && strcmp(c[n - 1].name, "table_force") == 0
                                && c[n - 1].offset == CRS_WORLD_ROW_TABLE_FORCE);
    check("fixtures", strcmp(crs_world_fixture_name(CRS_FIXTURE_OBSTACLE_FOREARM), "obstacle_forearm") == 0
                          && crs_world_fixture_name(CRS_FIXTURES) == NULL && crs_world_fixture_name(-1) == NULL);
}

/* A world attached again starts afresh: the egg whole, nothing latched. */
static void test_attach_resets_the_state(void)
{
    bench b;
    setup(&b, (const double[3]){1, 1, 1}, (const double[3]){0, 0, 1});
    held(&b, CRS_FIXTURE_EGG)[2] = 30.0;
    crs_world_update(&b.w, 1);
    check("broken", b.w.state.egg_broken == 1);
    const crs_world_config c = b.w.config;
    crs_world_attach(&b.w, &c);
    check("whole again", b.w.state.egg_broken == 0 && b.w.state.broke_tick == -1 && b.w.enabled == 1
                             && b.w.config.breaking_force_n == 20.0);
    crs_world_init(&b.w);
    check("init: disabled", b.w.enabled == 0 && b.w.config.sensor_adr[CRS_FIXTURE_EGG] == -1
                                && b.w.state.row[CRS_WORLD_ROW_GROOVE_SEGMENT] == -1.0);
}

int main(void)
{
    test_egg_and_scale();
    test_at_breaking_force();
    test_what_broke_the_egg();
    test_touch_speed_is_the_contacts_start();
    test_groove();
    test_peg_depth();
    test_obstacle_parts();
    test_columns();
    test_attach_resets_the_state();
    return checks_report();
}
