/* A board for the C tests of the framework's tick (test_sim_*.c): the test's own lab as the native
 * firmware, a stub plant (the test's arrays and step function) and the arm at rest. Include after
 * checks.h. */
#ifndef CRSLAB_TESTS_TEST_BOARD_H
#define CRSLAB_TESTS_TEST_BOARD_H

#include <stdlib.h>
#include <string.h>

#include "crs_arm.h"
#include "firmware_native.h"
#include "board.h"

/* The calls the firmware makes to the test's lab() and printing() (crslab's builds append them to a
 * lab's translation unit: crslab/lab/entry_points.py). Put after both definitions. */
#define TEST_BOARD_LAB_CALLS                                                                         \
    void crs_lab_call_lab(float t1, float t2, float t3, float *tau1, float *tau2, float *tau3,      \
                          int error);                                                                \
    void crs_lab_call_lab(float t1, float t2, float t3, float *tau1, float *tau2, float *tau3,      \
                          int error)                                                                 \
    {                                                                                                \
        lab(t1, t2, t3, tau1, tau2, tau3, error);                                                    \
    }                                                                                                \
    void crs_lab_call_printing(void);                                                                \
    void crs_lab_call_printing(void) { printing(); }

static const double TEST_REST_MOTOR_RAD[3] = {0.0, -0.42, 0.24}; /* motor angles 1..3, rad */

typedef struct {
    double *qpos, *qvel, *ctrl, *qfrc; /* 3 each: DH angles (rad), rad/s, ctrl, N.m */
    crs_mj_step_fn step;
} test_plant;

/* A new board of `generation` whose first lab() call is at tick `startup_ticks`; the plant's
 * angles start at rest. Free it with test_board_free. */
static inline crs_board *test_board(int generation, int64_t startup_ticks, const test_plant *plant)
{
    crs_board *board = calloc(1, sizeof *board);
    crs_board_defaults(board);
    board->shared = calloc(1, sizeof(crs_shared));
    board->config.generation = generation;
    if (crs_fw_native_attach(board) != 0) { /* the test's lab is this board's firmware */
        printf("FAIL crs_fw_native_attach for generation %d: %s\n", generation, board->trap.text);
        ++failures;
    }
    board->config.startup_ticks = startup_ticks;
    board->config.time_lab = 0;
    memcpy(board->config.rest_motor_rad, TEST_REST_MOTOR_RAD, sizeof TEST_REST_MOTOR_RAD);
    crs_motor_to_dh(TEST_REST_MOTOR_RAD, plant->qpos);
    board->plant = (crs_board_plant){.step = plant->step, .qpos = plant->qpos, .qvel = plant->qvel,
                                   .ctrl = plant->ctrl, .qfrc_applied = plant->qfrc};
    return board;
}

static inline void test_board_free(crs_board *board)
{
    free(board->shared);
    free(board);
}

#endif
