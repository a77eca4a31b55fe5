/* The contest world's facts, written once: how the egg breaks and lies, and the contest's rules
 * (the defaults of a world file's [contest] table; docs/worlds.md and docs/contest.md give each
 * number's source).
 *
 * The board's world (world.c) uses these values, and Python reads them through cffi
 * (crslab._core, API mode; crslab/world/world_facts.py names them for Python). Plain declarations
 * only: cffi reads this file (crslab/cheaders.py drops the initialisers). */
#ifndef CRSLAB_WORLD_FACTS_H
#define CRSLAB_WORLD_FACTS_H

/* What a kitchen scale divides the force on its platform by to show grams (m/s^2): scales are
 * calibrated to standard gravity. */
static const double CRS_SCALE_GRAVITY_M_S2 = 9.80665;
/* A broken egg keeps this share of its height, lying flat on its scale (drawn, no longer felt). */
static const double CRS_EGG_FLAT_SHARE = 0.2;
/* The peg's tip came down onto the egg faster than this (m/s): the egg broke in a fall (the arm
 * fell or struck it), not by a press. Twice the fastest approach a team designed for its press
 * (100 mm/s to the egg; most pressed at 10-20 mm/s), half its free moves' 400-600 mm/s. */
static const double CRS_EGG_FALL_M_S = 0.2;
/* What broke the egg (the world row's egg_broken_by). A side hit: the horizontal part of the
 * egg's force at the break is larger than its downward part; else a fall (above); else the press. */
enum {
    CRS_EGG_WHOLE = 0,
    CRS_EGG_BROKEN_BY_PRESS = 1,
    CRS_EGG_BROKEN_BY_SIDE = 2,
    CRS_EGG_BROKEN_BY_FALL = 3
};

/* A contact force above this (N) is a touch: MuJoCo reports exactly 0 without contact. */
static const double CRS_CONTEST_TOUCH_N = 0.05;

/* The contest's rules (crslab contest; a world file's [contest] table overrides each). */
static const double CRS_CONTEST_BAND_LOW_G = 500.0;    /* the egg's band on the scale: "the force */
static const double CRS_CONTEST_BAND_HIGH_G = 1000.0;  /* on egg varies from 500 gram to 1000 gram" */
static const double CRS_CONTEST_HOLD_S = 2.0;          /* pushes "held for 2 seconds" */
static const double CRS_CONTEST_HOLD_TOLERANCE_S = 0.2; /* what a TA with a stopwatch lets pass short
                                                         of each hold, the egg's and the peg's (a
                                                         human's reaction time is about 0.2 s; one
                                                         team's 2 s press was in the band 1.91 s) */
static const double CRS_CONTEST_PEG_MIN_DEPTH_M = 0.005; /* half the shallowest insertion teams
                                                            designed (10 mm) */
static const double CRS_CONTEST_PEG_HOLD_S = 0.5;      /* the peg "stays there a moment" */
static const double CRS_CONTEST_GROOVE_MIN_SHARE = 0.9; /* of the Z's length followed inside */
enum {
    CRS_CONTEST_OBSTACLE_AROUND = 1 /* 1: passing beside the obstacle avoids it too ("goes around
                                       the box"); 0: the tip must pass over its top */
};

#endif
