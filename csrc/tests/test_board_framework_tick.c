/* C-level tests of the framework's 1 ms tick, driven alone (no MuJoCo): crs_board_run with a stub
 * plant whose motor angles follow a script, and a small test lab compiled in. Built with -Werror
 * and under ASan/UBSan by tests/test_c_core.py; exit status 0 when every check passes.
 *
 * The expected commands are worked by hand from docs/framework.md sections 3 to 6: the hold
 * controller's u = Kp e - Kd v with its recursive velocity average, the references, the startup
 * gate, the clamp, the one-tick delay of `error`, the print triggers, the motor board, the drive
 * (the amplifier's torque-speed envelope and lag) and the serial line's ring. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coecsl.h"
#include "crs_arm.h"
#include "drive.h"
#include "firmware.h"
#include "framework.h"
#include "friction.h"
#include "framework_facts.h"
#include "generations.h"
#include "motor_board.h"
#include "firmware_native.h"
#include "board.h"

#include "checks.h"
#include "test_board.h"

static const double PI_D = 3.14159265358979323846;
static const double RAD_PER_COUNT = 3.14159265358979323846 / 144000.0;

/* ---- the test lab ------------------------------------------------------------------------- */

float offset_Enc2_rad = -0.42f;
float offset_Enc3_rad = 0.24f;
int UARTprint = 0;

enum { LAB_TORQUE, LAB_PRINT_TRIGGERS, LAB_BURSTS, LAB_ALTERNATE, LAB_ONE_LINE };
enum { MAX_CALLS = 20000 };

static struct {
    int mode;
    float torque[3];         /* LAB_TORQUE: written on every call */
    int line_chars;          /* LAB_ONE_LINE: a line this long on call 3 (and after it: "after") */
    long calls;
    int error_seen[MAX_CALLS]; /* the `error` argument of each call */
} lab_state;

static crs_board *the_sim; /* the board under test (the lab peeks at its tick) */

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor, (void)theta2motor, (void)theta3motor;
    const long call = lab_state.calls++;
    if (call < MAX_CALLS) lab_state.error_seen[call] = error;
    switch (lab_state.mode) {
    case LAB_TORQUE:
        *tau1 = lab_state.torque[0];
        *tau2 = lab_state.torque[1];
        *tau3 = lab_state.torque[2];
        break;
    case LAB_PRINT_TRIGGERS:
        if (call == 0 || call == 2) {
            serial_printf(&SerialA, "L%ld ", call); /* straight from lab() */
            SWI_post(&SWI_printf);
            SWI_post(&SWI_printf); /* two posts in one tick: printing() once */
            UARTprint = 1;
        }
        break;
    case LAB_BURSTS:
        if (call == 0 || call == 5 || call == 1000) {
            /* four 60-character lines: 58 letters and the course's "\n\r" */
            const int burst = call == 0 ? 0 : (call == 5 ? 1 : 2);
            for (int line = 0; line < 4; ++line) {
                char text[59];
                memset(text, 'A' + 4 * burst + line, 58);
                text[58] = '\0';
                serial_printf(&SerialA, "%s\n\r", text);
            }
        }
        break;
    case LAB_ONE_LINE:
        if (call == 3) {
            char text[4096];
            memset(text, 'x', (size_t)lab_state.line_chars - 2);
            text[lab_state.line_chars - 2] = '\0';
            serial_printf(&SerialA, "%s\n\r", text);
            serial_printf(&SerialA, "after\n\r");
        }
        break;
    case LAB_ALTERNATE:
        /* +-4.5 on joint 1 for 2 s, then 0 for 100 ms, then 1 */
        *tau1 = call < 2000 ? (call % 2 ? -4.5f : 4.5f) : (call < 2100 ? 0.0f : 1.0f);
        *tau2 = 0.0f;
        *tau3 = 0.0f;
        break;
    }
}

long printing_calls = 0;

void printing(void)
{
    serial_printf(&SerialA, "P%ld\n\r", printing_calls++);
}

TEST_BOARD_LAB_CALLS

/* ---- the stub plant ------------------------------------------------------------------------ */

static double plant_motor[3];         /* the arm's motor angles, rad */
static double qpos[3], qvel[3], ctrl[3], qfrc[3];
static int64_t plant_steps;
static void (*plant_script)(int64_t tick, double motor_rad[3]); /* the pose tick k sees */

static void stub_step(const void *model, void *data)
{
    (void)model, (void)data;
    plant_steps++;
    if (plant_script != NULL) plant_script(plant_steps, plant_motor);
    crs_motor_to_dh(plant_motor, qpos);
}

static crs_board *new_sim(int generation, int64_t startup_ticks, void (*script)(int64_t, double *))
{
    const test_plant plant = {qpos, qvel, ctrl, qfrc, stub_step};
    crs_board *board = test_board(generation, startup_ticks, &plant);
    plant_script = script;
    plant_steps = 0;
    memcpy(plant_motor, TEST_REST_MOTOR_RAD, sizeof plant_motor);
    if (script != NULL) script(0, plant_motor);
    crs_motor_to_dh(plant_motor, qpos);
    memset(&lab_state, 0, sizeof lab_state);
    UARTprint = 0;
    printing_calls = 0;
    the_sim = board;
    return board;
}

/* Run exactly one tick. */
static void tick(crs_board *board)
{
    const int code = crs_board_run(board, board->tick + 1);
    if (code != CRS_RUN_DONE && code != CRS_RUN_EVENTS_FULL) {
        printf("FAIL crs_board_run stopped with %d at tick %lld\n", code, (long long)board->tick);
        ++failures;
    }
}

/* ---- the hold controller ------------------------------------------------------------------- */

/* Joint 1 turns 23 counts per tick from tick 100 on, joint 2 11 counts per tick; joint 3 rests.
 * Joint 1 leaves the envelope (|th1| > 0.6667 pi) after about 4170 ticks. */
enum { RAMP_START = 100, STEP1_COUNTS = 23, STEP2_COUNTS = 11 };

static void ramp_script(int64_t k, double motor[3])
{
    const int64_t n = k >= RAMP_START ? k - RAMP_START + 1 : 0;
    motor[0] = (double)(n * STEP1_COUNTS) * RAD_PER_COUNT;
    motor[1] = TEST_REST_MOTOR_RAD[1] + (double)(n * STEP2_COUNTS) * RAD_PER_COUNT;
    motor[2] = TEST_REST_MOTOR_RAD[2];
}

static void test_hold_controller_worked_sequence(void)
{
    crs_board *board = new_sim(CRS_GEN_A, 50, ramp_script);
    lab_state.mode = LAB_TORQUE;
    lab_state.torque[0] = 0.77f; /* used inside the envelope, discarded outside */

    /* tick 0: the references are 0 and the last angles 0, so the velocity sees the whole offset
     * in one ms. Joint 2: e = 0 - (-0.42) = 0.42 > 0.1 -> Kp 15; v = (-420 + 0 + 0) / 3 = -140;
     * u = 15 * 0.42 + 140 = 146.3. Joint 3: e = -0.24 -> Kp 15; v = 240 / 3 = 80; u = -3.6 - 80. */
    tick(board);
    check_close("tick 0: hold u1", board->hold.out[0], 0.0, 1e-9);
    check_close("tick 0: hold u2", board->hold.out[1], 146.3, 1e-3);
    check_close("tick 0: hold u3", board->hold.out[2], -83.6, 1e-3);
    check_close("tick 0: nothing reaches the motors before the gate", fabs(board->applied[1]), 0.0, 0.0);
    check("tick 0: references start at 0", board->hold.ref_rad[0] == 0.0f && board->hold.ref_rad[1] == 0.0f
                                               && board->hold.ref_rad[2] == 0.0f);
    while (board->tick < 50) tick(board);
    check("references stay 0 until the startup gate", board->hold.ref_rad[1] == 0.0f);
    tick(board); /* tick 50: inside the envelope the references follow the arm */
    check("inside, the references follow the angles", board->hold.ref_rad[1] == (float)board->enc_rad[1]
                                                           && board->hold.ref_rad[2] == (float)board->enc_rad[2]);
    check_close("inside, the lab's torque is used", board->applied[0], 0.77f, 0.0);

    while (board->tick < RAMP_START) tick(board);
    /* the ramp starts: r = 23 counts per ms. Joint 1 averages v with the two previous averages:
     * r/3, 4r/9, 16r/27, 55r/81; joint 2's line uses the older one twice: r/3, r/3, 5r/9, 5r/9.
     * The reference is last tick's angle, so e = -step and Kp = 25: u = -25 step - v. */
    const double step1 = STEP1_COUNTS * RAD_PER_COUNT, r1 = step1 / 0.001;
    const double step2 = STEP2_COUNTS * RAD_PER_COUNT, r2 = step2 / 0.001;
    const double v1[4] = {r1 / 3, 4 * r1 / 9, 16 * r1 / 27, 55 * r1 / 81};
    const double v2[4] = {r2 / 3, r2 / 3, 5 * r2 / 9, 5 * r2 / 9};
    for (int i = 0; i < 4; ++i) {
        tick(board);
        char what[80];
        snprintf(what, sizeof what, "ramp tick %d: joint 1 averages over three", i);
        check_close(what, board->hold.out[0], -25 * step1 - v1[i], 2e-3);
        snprintf(what, sizeof what, "ramp tick %d: joint 2's quirk", i);
        check_close(what, board->hold.out[1], -25 * step2 - v2[i], 2e-3);
    }

    /* the arm turns joint 1 out of the envelope */
    int64_t out_tick = -1;
    while (board->tick < 6000 && out_tick < 0) {
        tick(board);
        if (board->safety_flag) out_tick = board->tick - 1;
    }
    check("joint 1 leaves the envelope", out_tick > 0 && fabs(board->enc_rad[0]) > 0.6667 * PI_D);
    check("... a safety trip at that tick", board->safety_trips == 1 && board->safety_first_tick == out_tick);
    const long first_call_tick = 50;
    check("error is 0 in the call of the tick that left", lab_state.error_seen[out_tick - first_call_tick] == 0);
    /* outside: the hold output, with the reference one step behind: u1 = -25 step1 - r1 (v settled) */
    check_close("outside: joint 1 gets the hold output", board->applied[0], -25 * step1 - r1, 2e-3);
    check_close("outside: joint 2 gets the hold output", board->applied[1], -25 * step2 - r2, 2e-3);
    check_close("outside: joint 3 is held still", board->applied[2], 0.0, 1e-6);
    tick(board);
    check("error is 1 one tick later", lab_state.error_seen[out_tick + 1 - first_call_tick] == 1);
    /* the reference stays at the last inside angle while the arm moves on: after k more ticks
     * e = -(k + 1) step1; beyond 0.1 rad (k + 1 >= 200) Kp drops to 15 */
    while (board->tick < out_tick + 99) tick(board);
    tick(board); /* k = 99 */
    check_close("outside, k = 99: Kp 25", board->applied[0], -25 * 100 * step1 - r1, 2e-3);
    while (board->tick < out_tick + 250) tick(board);
    tick(board); /* k = 250 */
    check_close("outside, k = 250: Kp 15", board->applied[0], -15 * 251 * step1 - r1, 2e-3);
    /* at k = 298, e = -299 step1 = -0.15003 rad: the reference re-anchors to the arm, so at
     * k = 299 the error is one step again */
    while (board->tick < out_tick + 298) tick(board);
    tick(board);
    check_close("outside, k = 298: last pull before re-anchoring", board->applied[0], -15 * 299 * step1 - r1, 2e-3);
    check("re-anchored to the arm", board->hold.ref_rad[0] == (float)board->enc_rad[0]);
    tick(board);
    check_close("outside, k = 299: re-anchored", board->applied[0], -25 * step1 - r1, 2e-3);
    test_board_free(board);
}

/* ---- the safety envelope's trips and the scope log ---------------------------------------- */

/* Joint 1 outside the envelope (2.2 rad > 0.6667 pi) for the ticks [200, 300) and [500, 520). */
static void two_trips_script(int64_t k, double motor[3])
{
    motor[0] = (k >= 200 && k < 300) || (k >= 500 && k < 520) ? 2.2 : 0.0;
    motor[1] = TEST_REST_MOTOR_RAD[1];
    motor[2] = TEST_REST_MOTOR_RAD[2];
}

static void test_safety_trips_are_counted_and_every_tick_logged(void)
{
    crs_board *board = new_sim(CRS_GEN_A, 50, two_trips_script);
    board->config.log_every_ticks = 1;
    lab_state.mode = LAB_TORQUE;
    check("the run is inside the envelope at first", crs_board_run(board, 200) == CRS_RUN_DONE
                                                        && board->safety_trips == 0 && board->safety_first_tick == -1);
    check("ticks 0 to 199 are in the scope log, in order", board->shared->log.count == 200
                                                           && board->shared->log.tick[0] == 0
                                                           && board->shared->log.tick[199] == 199);
    crs_board_run(board, 1000);
    check("two trips: the arm left the envelope twice", board->safety_trips == 2);
    check("the first at tick 200", board->safety_first_tick == 200);
    check("120 ticks outside in all", board->safety_ticks == 120);
    const crs_scope_log *lg = &board->shared->log;
    int64_t flagged = 0;
    for (int64_t i = 0; i < lg->count; ++i) flagged += lg->safety[i];
    check("the log's safety column has those 120 ticks", lg->count == 1000 && flagged == 120
                                                         && lg->safety[199] == 0 && lg->safety[200] == 1
                                                         && lg->safety[299] == 1 && lg->safety[300] == 0);
    /* the scope log fills: the chunk ends before the first tick with no room, and goes on once
     * the reader took the rows */
    board->shared->log.count = CRS_LOG_CAPACITY - 3;
    check("a full log ends the chunk early", crs_board_run(board, 2000) == CRS_RUN_LOG_FULL && board->tick == 1003
                                                && lg->count == CRS_LOG_CAPACITY);
    board->shared->log.count = 0;
    check("taken, it goes on", crs_board_run(board, 2000) == CRS_RUN_DONE && lg->count == 997 && lg->tick[0] == 1003);
    /* every fifth tick (the page's scopes) */
    board->shared->log.count = 0;
    board->config.log_every_ticks = 5;
    crs_board_run(board, 2013);
    check("every fifth tick", lg->count == 3 && lg->tick[0] == 2000 && lg->tick[1] == 2005 && lg->tick[2] == 2010);
    board->config.log_every_ticks = 0;
    crs_board_run(board, 2100);
    check("no log: nothing written", lg->count == 3);
    test_board_free(board);
}

/* ---- startup gate, clamp, NaN ------------------------------------------------------------ */

static void test_startup_gate_and_clamp(void)
{
    crs_board *board = new_sim(CRS_GEN_A, CRS_STARTUP_TICKS, NULL);
    lab_state.mode = LAB_TORQUE;
    lab_state.torque[0] = 40.0f;
    lab_state.torque[1] = -40.0f;
    lab_state.torque[2] = 0.5f;
    crs_board_run(board, CRS_STARTUP_TICKS);
    check("lab() is not called before 4.1 s", lab_state.calls == 0 && board->lab_calls == 0);
    check("nothing is commanded before 4.1 s", board->command[0] == 0.0 && board->applied[0] == 0.0);
    tick(board);
    check("the first lab() call is at tick 4100", lab_state.calls == 1 && board->tick == 4101);
    check_close("40 is clamped to 5", board->applied[0], 5.0, 0.0);
    check_close("-40 is clamped to -5", board->applied[1], -5.0, 0.0);
    check_close("0.5 passes", board->applied[2], 0.5, 0.0);
    lab_state.torque[2] = NAN;
    tick(board);
    check("a NaN torque applies nothing and is counted",
          board->applied[2] == 0.0 && board->nan_count == 1 && board->nan_first_tick == 4101 && board->nan_first_joint == 3);
    test_board_free(board);
}

/* ---- print triggers ---------------------------------------------------------------------- */

static void test_print_triggers(void)
{
    for (int32_t row = 0; row < crs_generation_count(); ++row) {
        const crs_generation *gen = crs_generation_at(row);
        crs_board *board = new_sim(gen->id, 10, NULL);
        lab_state.mode = LAB_PRINT_TRIGGERS;
        crs_board_run(board, 200);
        crs_shared *sh = board->shared;
        const char *want = "L0 P0\n\rL2 P1\n\r"; /* printing() once per tick that asked, after lab() */
        char what[80];
        snprintf(what, sizeof what, "gen %s: printing() runs once, after lab(), when asked", gen->name);
        check(what, sh->serial_len == strlen(want) && memcmp(sh->serial, want, strlen(want)) == 0);
        check("printing() ran twice", board->printing_runs == 2);
        if (gen->print_trigger == CRS_PRINT_UARTPRINT) check("UARTprint is cleared", UARTprint == 0);
        /* each print's bytes leave at 11.52 per ms from the tick it was made in */
        check("the first bytes leave in the tick of the first call", sh->mark_count >= 2 && sh->mark_tick[0] == 10);
        test_board_free(board);
    }
}

/* ---- the generations' table -------------------------------------------------------------- */

static void test_generation_rows_and_an_unknown_generation(void)
{
    check("two generations", crs_generation_count() == 2 && crs_generation_at(2) == NULL && crs_generation_at(-1) == NULL);
    const crs_generation *a = crs_generation_of(CRS_GEN_A), *b = crs_generation_of(CRS_GEN_B);
    check("Gen A's row", a != NULL && strcmp(a->name, "A") == 0 && a->printf_buffer_chars == 2048
                             && a->formatter == CRS_FORMATTER_SMALL && a->print_trigger == CRS_PRINT_SWI_POST
                             && a->matlab == (CRS_MATLAB_BIG_ENDIAN_WRITE | CRS_MATLAB_ECHO | CRS_MATLAB_LOCK));
    check("Gen B's row", b != NULL && strcmp(b->include, "F28335Serial.h") == 0 && b->printf_buffer_chars == 136
                             && b->tx_ring_chars == 136 && b->scic_tx_ring_chars == 2000 && b->matlab == 0
                             && b->motor_board == CRS_MOTOR_BOARD_PICCOLO);
    check("every row can run", crs_generation_problem(a) == NULL && crs_generation_problem(b) == NULL);
    crs_generation bad = *b;
    bad.formatter = 3;
    check("a row with no such formatter cannot", crs_generation_problem(&bad) != NULL);
    bad = *b;
    bad.printf_buffer_chars = CRS_PRINTF_BUFFER_MAX + 1;
    check("nor one whose buffer the firmware cannot hold", crs_generation_problem(&bad) != NULL);
    bad = *b;
    bad.tx_ring_chars = CRS_LINE_QUEUE_CAPACITY;
    check("nor one whose ring the line cannot hold", crs_generation_problem(&bad) != NULL);

    check("no generation 0 or 3", crs_generation_of(0) == NULL && crs_generation_of(3) == NULL);
    check("the firmware refuses generation 3", crs_fw_start(3) == NULL);
    crs_board *board = calloc(1, sizeof *board);
    crs_board_defaults(board);
    board->shared = calloc(1, sizeof(crs_shared));
    check("a board is of no generation until told", board->config.generation == 0);
    board->config.generation = 3;
    const int code = crs_fw_native_attach(board);
    check("the board refuses to load a firmware for generation 3, and says which it knows",
          code == CRS_RUN_TRAPPED && board->trap.kind == CRS_FW_TRAP_LOAD
              && strcmp(board->trap.text, "the board knows no framework generation 3 (it knows A (1), B (2))") == 0);
    test_board_free(board);
}

/* ---- the motor board -------------------------------------------------------------------- */

static void test_motor_board_cuts_out_after_500_ms_over_4_units(void)
{
    crs_board *board = new_sim(CRS_GEN_B, 100, NULL);
    board->config.motor_board = CRS_MOTOR_BOARD_PICCOLO;
    lab_state.mode = LAB_ALTERNATE;
    /* 4.5 units = 1350 counts > 1200: ticks 100 .. 599 (500 ms) reach the motors, 600 on do not */
    crs_board_run(board, 600);
    check_close("+-4.5 reaches the motors for 500 ms", fabs(board->applied[0]), 4.5, 0.0);
    check("... and the board is on", board->motor_board.off == 0);
    tick(board);
    check("at 500 ms over the limit every output is cut", board->applied[0] == 0.0 && board->motor_board.off == 1);
    check("the cut-out is reported: tick 600, joint 1",
          board->motor_board.event_count == 1 && board->motor_board.event_tick[0] == 600
              && board->motor_board.event_joint[0] == 1 && board->motor_board.event_off[0] == 1);
    crs_board_run(board, 2100);
    check("cut while the lab keeps commanding 4.5", board->applied[0] == 0.0 && board->motor_board.off == 1);
    tick(board); /* tick 2100: the lab commands 0 */
    check("back when the command drops to 4 units or less", board->motor_board.off == 0);
    check("the end is reported at tick 2100",
          board->motor_board.event_count == 2 && board->motor_board.event_tick[1] == 2100 && board->motor_board.event_off[1] == 0);
    crs_board_run(board, 2201);
    check_close("later commands reach the motors again", board->applied[0], 1.0, 0.0);
    check("one cut-out in all", board->motor_board.cutouts == 1);
    test_board_free(board);
}

static void test_motor_board_timeout_and_counts(void)
{
    crs_motor_board mb;
    int32_t model = CRS_MOTOR_BOARD_PICCOLO;
    crs_motor_board_init(&mb);
    const double cmd[3] = {1.23456, -4.0, 4.0033};
    crs_motor_board_step(model, &mb, 0, cmd);
    /* whole PWM counts, truncated toward zero: 370.368 -> 370, -1200, 1200.99 -> 1200 */
    check_close("1.23456 units is sent as 370 counts", mb.out_units[0], 370.0 / 300.0, 1e-12);
    check_close("-4 units is within the limit", mb.out_units[1], -4.0, 1e-12);
    check("4.0033 units is 1200 counts: not over the limit", mb.over_ticks[2] == 0);
    for (int64_t t = 1; t < 100; ++t) crs_motor_board_step(model, &mb, t, NULL);
    check_close("without commands the outputs hold for 99 ms", mb.out_units[0], 370.0 / 300.0, 1e-12);
    check("... still on", mb.off == 0);
    crs_motor_board_step(model, &mb, 100, NULL);
    check("100 ms without a command cuts every output", mb.off == 1 && mb.out_units[0] == 0.0);
    check("reported as a missing command (joint 0)", mb.event_count == 1 && mb.event_joint[0] == 0 && mb.event_tick[0] == 100);
    const double next[3] = {2.0, 0.0, 0.0};
    crs_motor_board_step(model, &mb, 150, next);
    check_close("a command brings them back", mb.out_units[0], 2.0, 1e-12);
    check("... reported", mb.off == 0 && mb.event_count == 2 && mb.event_off[1] == 0);
    /* over the limit on joint 2 for 499 ms, then within: no cut-out */
    const double over[3] = {0.0, -4.5, 0.0}, within[3] = {0.0, 4.0, 0.0};
    for (int64_t t = 0; t < 499; ++t) crs_motor_board_step(model, &mb, 200 + t, over);
    crs_motor_board_step(model, &mb, 699, within);
    for (int64_t t = 0; t < 499; ++t) crs_motor_board_step(model, &mb, 700 + t, over);
    check("499 ms over the limit, twice, is not 500 consecutive", mb.off == 0 && mb.cutouts == 1);
    /* none: a wire */
    crs_motor_board_init(&mb);
    model = CRS_MOTOR_BOARD_NONE;
    const double big[3] = {4.9, -4.9, 4.9};
    for (int64_t t = 0; t < 2000; ++t) crs_motor_board_step(model, &mb, t, big);
    check("no motor board: commands pass unchanged", mb.off == 0 && mb.out_units[1] == -4.9);
}

/* ---- the serial line -------------------------------------------------------------------- */

static void test_serial_ring_drops(void)
{
    crs_board *board = new_sim(CRS_GEN_B, 10, NULL);
    lab_state.mode = LAB_BURSTS;
    crs_board_run(board, 2000);
    crs_shared *sh = board->shared;
    /* burst 1 (tick 10) into an idle line: the ring takes 136 of a call; after each call the
     * interrupt moves 17 into the FIFO and the shift register. Line 1: 60. Line 2: 60 queued, 43
     * in the ring, room 93: 60. Line 3: 120 queued, 103 in the ring, room 33: 33. Line 4: none.
     * 153 sent, 87 dropped. Burst 2 (tick 15): 11.52 chars per ms left during ticks 10..14, so
     * floor(57.6) = 57 are gone: 96 queued, 79 in the ring, room 57: line 1 loses 3, lines 2-4
     * all 180. Burst 3 (tick 1010) finds an idle line again: as burst 1. */
    char want[1024];
    size_t n = 0;
    const char first_letter[3] = {'A', 'E', 'I'};
    const int kept[3][4] = {{60, 60, 33, 0}, {57, 0, 0, 0}, {60, 60, 33, 0}};
    for (int b = 0; b < 3; ++b) {
        for (int line = 0; line < 4; ++line) {
            for (int i = 0; i < kept[b][line]; ++i) want[n++] = i < 58 ? (char)(first_letter[b] + line) : (i == 58 ? '\n' : '\r');
        }
    }
    check("the line carries exactly what the ring kept", sh->serial_len == n && memcmp(sh->serial, want, n) == 0);
    check("87 + 183 + 87 characters dropped, the first at tick 10",
          board->tx_dropped == 357 && board->tx_first_drop_tick == 10);
    /* a print mark for each serial_printf the ring took characters of: its tick and how many */
    const int64_t mark_tick[7] = {10, 10, 10, 15, 1010, 1010, 1010};
    const uint32_t mark_chars[7] = {60, 60, 33, 57, 60, 60, 33};
    int marks_ok = sh->print_count == 7;
    for (int i = 0; marks_ok && i < 7; ++i) {
        marks_ok = sh->print_tick[i] == mark_tick[i] && sh->print_chars[i] == mark_chars[i];
    }
    check("print marks: the tick and the kept characters of each serial_printf", marks_ok);
    /* characters leave at 11.52 per ms: 11 in tick 10, 23 by the end of tick 11, ... */
    check("tick 10 sends 11", sh->mark_tick[0] == 10 && sh->mark_offset[1] == 11);
    check("tick 11 sends 12", sh->mark_tick[1] == 11 && sh->mark_offset[2] == 23);
    /* bursts 1 and 2 keep the line busy: 153 + 57 = 210 characters take 210 / 11.52 = 18.2 ms
     * from the start of tick 10, so the last one leaves during tick 28 */
    int last_of_bursts_1_2 = -1;
    for (uint32_t i = 0; i < sh->mark_count; ++i) {
        if (sh->mark_tick[i] < 1010) last_of_bursts_1_2 = (int)sh->mark_tick[i];
    }
    check("bursts 1 and 2 have left by tick 28", last_of_bursts_1_2 == 28);
    check("nothing left on the line", sh->line.len == 0);
    test_board_free(board);
}

static void test_printf_overflow_stops_the_run(void)
{
    const struct {
        int generation, chars, overflows;
    } cases[4] = {{CRS_GEN_B, 135, 0}, {CRS_GEN_B, 136, 1}, {CRS_GEN_A, 2047, 0}, {CRS_GEN_A, 2048, 1}};
    for (int i = 0; i < 4; ++i) {
        crs_board *board = new_sim(cases[i].generation, 10, NULL);
        lab_state.mode = LAB_ONE_LINE;
        lab_state.line_chars = cases[i].chars;
        const int code = crs_board_run(board, 100);
        char what[120];
        snprintf(what, sizeof what, "gen %c, a %d-character line: %s", cases[i].generation == CRS_GEN_A ? 'A' : 'B',
                 cases[i].chars, cases[i].overflows ? "the run stops at once" : "fits the buffer (with its NUL)");
        if (cases[i].overflows) {
            check(what, code == CRS_RUN_PRINTF_OVERFLOW && board->tick == 13 && board->overflow_tick == 13
                            && board->overflow_chars == (uint32_t)cases[i].chars && board->overflow_phase == CRS_PHASE_LAB
                            && lab_state.calls == 4);
            check("nothing of the overflowing line is sent", board->shared->line.len == 0 && board->shared->serial_len == 0);
        } else {
            check(what, code == CRS_RUN_DONE && board->overflow_tick < 0);
        }
        test_board_free(board);
    }
}

/* ---- the drive ------------------------------------------------------------------------------ */

static void test_drive_envelope_lag_and_dead_motor(void)
{
    crs_drive_config c;
    crs_drive d;
    memset(&c, 0, sizeof c);
    memset(&d, 0, sizeof d);
    for (int j = 0; j < 3; ++j) {
        c.stall_units[j] = 3.0;
        c.backemf_units_s_per_rad[j] = 1.0;
    }
    const int32_t alive[3] = {0, 0, 0};
    double out[3];
    /* at 1 rad/s the amplifier gives at most 3 - 1 = 2 forward and -3 - 1 = -4 backward */
    const double command[3] = {1.5, 5.0, -5.0}, speed[3] = {1.0, 1.0, 1.0};
    crs_drive_step(&c, &d, crs_drive_follow(&c), command, speed, alive, out);
    check_close("drive: inside the envelope the command is delivered", out[0], 1.5, 1e-12);
    check_close("drive: driving at 1 rad/s gets stall - backemf * w", out[1], 2.0, 1e-12);
    check_close("drive: braking at 1 rad/s gets -stall - backemf * w", out[2], -4.0, 1e-12);
    /* beyond the no-load speed (3 rad/s) even a zero command brakes: 3 - 4 = -1 */
    const double zero[3] = {0.0, 0.0, 0.0}, fast[3] = {4.0, -4.0, 0.0};
    crs_drive_step(&c, &d, crs_drive_follow(&c), zero, fast, alive, out);
    check_close("drive: past the no-load speed a zero command brakes", out[0], -1.0, 1e-12);
    check_close("drive: ... in either direction", out[1], 1.0, 1e-12);
    check_close("drive: at rest a zero command is zero", out[2], 0.0, 0.0);

    /* a 2 ms lag: a step to 1 unit reaches 1 - exp(-1/2), then 1 - exp(-1) */
    memset(d.torque_units, 0, sizeof d.torque_units);
    c.lag_s = 0.002;
    const double one[3] = {1.0, 1.0, 1.0}, still[3] = {0.0, 0.0, 0.0};
    crs_drive_step(&c, &d, crs_drive_follow(&c), one, still, alive, out);
    check_close("drive lag: first ms", out[0], 1.0 - exp(-0.5), 1e-12);
    crs_drive_step(&c, &d, crs_drive_follow(&c), one, still, alive, out);
    check_close("drive lag: second ms", out[0], 1.0 - exp(-1.0), 1e-12);
    const int32_t dead[3] = {0, 1, 0};
    crs_drive_step(&c, &d, crs_drive_follow(&c), one, still, dead, out);
    check_close("drive: a dead motor delivers nothing at once", out[1], 0.0, 0.0);
    check_close("drive: ... and keeps no torque", d.torque_units[1], 0.0, 0.0);
    check_close("drive lag: third ms on a live motor", out[0], 1.0 - exp(-1.5), 1e-12);
}

static void test_drive_between_motor_board_and_ctrl(void)
{
    crs_board *board = new_sim(CRS_GEN_A, 0, NULL);
    check("drive: ideal until the plant sets it", isinf(board->config.drive.stall_units[0]));
    lab_state.mode = LAB_TORQUE;
    lab_state.torque[0] = 4.5f;
    lab_state.torque[1] = -1.0f;
    for (int j = 0; j < 3; ++j) {
        board->config.drive.stall_units[j] = 3.0;
        board->config.drive.backemf_units_s_per_rad[j] = 1.0;
    }
    memset(qvel, 0, sizeof qvel);
    tick(board);
    check_close("drive: the motor board's 4.5 units become the 3 units the amplifier can give", ctrl[0], 3.0,
                1e-12);
    check_close("drive: -1 unit passes", ctrl[1], -1.0, 1e-6);
    check_close("drive: the command that reached the amplifier is still logged as applied", board->applied[0], 4.5,
                1e-6);
    test_board_free(board);
}

/* ---- friction while a joint slides ------------------------------------------------------------ */

static void test_sliding_friction_goes_from_the_band_edge_to_the_line(void)
{
    /* motor 1 (units): band edges Spos 0.30, Sneg -0.25; lines Cpos 0.36 + 0.25 w, Cneg -0.30 + 0.24 w;
     * motor 2 has stiction (Spos 0.5 above Cpos 0.4); motor 3 none: no friction beyond the band */
    crs_friction f;
    memset(&f, 0, sizeof f);
    f.transition_rad_s = 0.02;
    f.slide_pos_units[0] = 0.36 - 0.30;
    f.slide_neg_units[0] = -0.30 - -0.25;
    f.viscous_pos_units_s_per_rad[0] = 0.25;
    f.viscous_neg_units_s_per_rad[0] = 0.24;
    f.slide_pos_units[1] = 0.4 - 0.5;
    double out[3];
    const double fast[3] = {1.0, 1.0, 1.0};
    crs_friction_torque(&f, fast, out);
    /* far above w_t: what the band gives (Spos, MuJoCo's) plus this reaches the line, against the motion */
    check_close("friction: moving positive, the line's part beyond Spos", out[0],
                -((0.36 - 0.30) * (1.0 - exp(-50.0)) + 0.25), 1e-12);
    check_close("friction: Spos + that is the line 0.36 + 0.25 w", 0.30 - out[0], 0.61, 1e-12);
    check_close("friction: stiction above the line: sliding gives some back", out[1], 0.1 * (1.0 - exp(-50.0)), 1e-12);
    check_close("friction: no slope, no gap: nothing", out[2], 0.0, 0.0);
    const double back[3] = {-0.5, 0.0, 0.0};
    crs_friction_torque(&f, back, out);
    check_close("friction: moving negative, Cneg - Sneg and Vneg w", out[0],
                -((-0.30 - -0.25) * (1.0 - exp(-25.0)) + 0.24 * -0.5), 1e-12);
    check("friction: moving negative it pushes positive", out[0] > 0.0);
    check_close("friction: at rest nothing beyond the band", out[1], 0.0, 0.0);
    /* at w = w_t the gap is 1 - 1/e of the way */
    const double slow[3] = {0.02, -0.02, 0.0};
    crs_friction_torque(&f, slow, out);
    check_close("friction: at the transition speed, 63 % of Cpos - Spos", out[0],
                -(0.06 * (1.0 - exp(-1.0)) + 0.25 * 0.02), 1e-12);
    check_close("friction: moving negative, motor 2's gap on the positive side does not count", out[1], 0.0,
                0.0);
    /* the tick adds it to what the drive delivers */
    double ctrl_units[3] = {1.0, 1.0, 1.0};
    crs_friction_add(&f, fast, ctrl_units);
    check_close("friction: added to ctrl", ctrl_units[0], 1.0 - (0.06 * (1.0 - exp(-50.0)) + 0.25), 1e-12);
}

/* Far above w_t the board skips expm1: the torque must be the formula's to the last bit, on both
 * sides of the speed where it stops calling it (40 w_t) and far beyond. */
static void test_sliding_friction_is_the_formula_bit_for_bit(void)
{
    crs_friction f;
    memset(&f, 0, sizeof f);
    f.transition_rad_s = 0.02;
    for (int j = 0; j < 3; ++j) {
        f.slide_pos_units[j] = 0.06 + 0.01 * j;
        f.slide_neg_units[j] = -0.05 - 0.01 * j;
        f.viscous_pos_units_s_per_rad[j] = 0.25;
        f.viscous_neg_units_s_per_rad[j] = 0.24;
    }
    int differ = 0;
    for (int i = -200000; i <= 200000; ++i) {
        const double w = i * 1e-5 * (1.0 + 1e-9 * i); /* -2 .. 2 rad/s, through 0.8 = 40 w_t */
        const double speeds[3] = {w, -w, 0.8 + i * 1e-17};
        double out[3];
        crs_friction_torque(&f, speeds, out);
        for (int j = 0; j < 3; ++j) {
            const double v = speeds[j];
            const double slide = v > 0.0 ? f.slide_pos_units[j] : v < 0.0 ? f.slide_neg_units[j] : 0.0;
            const double visc = v > 0.0 ? f.viscous_pos_units_s_per_rad[j]
                                        : v < 0.0 ? f.viscous_neg_units_s_per_rad[j] : 0.0;
            const double want = -(slide * -expm1(-fabs(v) / f.transition_rad_s) + visc * v);
            if (memcmp(&want, &out[j], sizeof want) != 0) ++differ;
        }
    }
    check("friction: 1.2 million speeds, each the formula's torque bit for bit", differ == 0);
}

/* At rest the hold's velocity average (v1 + v2) / 3 decays; in IEEE floats it would end on the
 * smallest subnormal for good (it rounds back up). The F28335's FPU has no subnormals: zero. */
static void test_hold_velocity_at_rest_ends_at_zero(void)
{
    crs_hold h;
    memset(&h, 0, sizeof h);
    const double still[3] = {0.1, -0.2, 0.3};
    const double moved[3] = {0.1 + 0.001, -0.2 - 0.002, 0.3 + 0.0005};
    crs_hold_update(&h, still);
    crs_hold_update(&h, moved);
    int ended = -1;
    for (int k = 0; k < 2000 && ended < 0; ++k) {
        crs_hold_update(&h, moved);
        int zero = 1;
        for (int j = 0; j < 3; ++j) {
            const float a = h.vel_old1_rad_s[j], b = h.vel_old2_rad_s[j];
            check("hold: no subnormal velocity", (a == 0.0f || fabsf(a) >= FLT_MIN) && (b == 0.0f || fabsf(b) >= FLT_MIN));
            zero = zero && a == 0.0f && b == 0.0f;
        }
        if (zero) ended = k;
    }
    /* the slowest is joint 2's line, which averages the older value twice: v(k) = 2 v(k - 2) / 3,
     * sqrt(2/3) = 0.816 a tick; from 2/3 rad/s to FLT_MIN (1.18e-38) that is
     * ln(0.667 / 1.18e-38) / ln(1 / 0.816) = 430 ticks */
    check("hold: at rest the velocity average reaches exactly zero", ended > 400 && ended < 480);
}

static void test_friction_between_drive_and_ctrl(void)
{
    crs_board *board = new_sim(CRS_GEN_A, 0, NULL);
    lab_state.mode = LAB_TORQUE;
    lab_state.torque[0] = 2.0f;
    lab_state.torque[1] = 0.0f;
    lab_state.torque[2] = 0.0f;
    board->config.friction.transition_rad_s = 0.02;
    board->config.friction.viscous_pos_units_s_per_rad[0] = 0.25;
    board->config.friction.viscous_neg_units_s_per_rad[2] = 0.2;
    memset(qvel, 0, sizeof qvel);
    qvel[0] = 2.0;           /* motor 1 at 2 rad/s */
    qvel[1] = 0.5;           /* j2 at 0.5, j3 at -1.5: motor 3 (j2 + j3) at -1 rad/s */
    qvel[2] = -1.5;
    tick(board);
    check_close("friction: the drive's 2 units less Vpos w = 0.5", ctrl[0], 1.5, 1e-6);
    check_close("friction: motor 3 turns at j2 + j3 and is pushed back by Vneg w", ctrl[2], 0.2, 1e-6);
    check_close("friction: the command logged is the motor board's, friction apart", board->applied[0], 2.0, 1e-6);
    test_board_free(board);
}

int main(void)
{
    test_hold_controller_worked_sequence();
    test_safety_trips_are_counted_and_every_tick_logged();
    test_startup_gate_and_clamp();
    test_print_triggers();
    test_generation_rows_and_an_unknown_generation();
    test_motor_board_cuts_out_after_500_ms_over_4_units();
    test_motor_board_timeout_and_counts();
    test_serial_ring_drops();
    test_printf_overflow_stops_the_run();
    test_drive_envelope_lag_and_dead_motor();
    test_drive_between_motor_board_and_ctrl();
    test_sliding_friction_goes_from_the_band_edge_to_the_line();
    test_friction_between_drive_and_ctrl();
    test_sliding_friction_is_the_formula_bit_for_bit();
    test_hold_velocity_at_rest_ends_at_zero();
    return checks_report();
}
