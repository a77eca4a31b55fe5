/* C-level tests of the host ports (docs/host-tools.md, "The protocols byte by byte"), driven
 * alone: the
 * emulated C28x memory over hand-made variables, SerialC's MATLAB messages and SerialB's Simulink
 * packets through crs_board_run with a stub plant. Built with -Werror and under ASan/UBSan by
 * tests/test_c_core.py; exit status 0 when every check passes.
 *
 * Expected bytes are the worked vectors of docs/host-tools.md (whattoprint = 1.25 at 0xc816 reads
 * back as 2A 04 33 00 00 A0 3F); expected ticks are worked by hand from the line's 10 000 units
 * per character and 115 200 per ms: bytes 1..11 of a burst arrive during its first tick, and a
 * reply leaves from the moment its request's last byte arrived. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board_io.h"
#include "c28x_memory.h"
#include "coecsl.h"
#include "crs_arm.h"
#include "framework_facts.h"
#include "generations.h"
#include "host_ports.h"
#include "simulink_link.h"

/* the framework's own globals, in its stand-ins (csrc/firmware/firmware.c) */
extern int SIMU_Var1_fromSIMU_16bit, SIMU_Var7_fromSIMU_16bit;
extern float matlabLock;
#include "firmware_native.h"
#include "board.h"

#include "checks.h"
#include "test_board.h"

static void check_bytes(const char *what, const char *got, uint64_t got_n, const unsigned char *want,
                        uint64_t want_n)
{
    if (got_n != want_n || memcmp(got, want, want_n) != 0) {
        printf("FAIL %s: got %llu bytes:", what, (unsigned long long)got_n);
        for (uint64_t i = 0; i < got_n && i < 24; ++i) printf(" %02X", (unsigned char)got[i]);
        printf("; want %llu:", (unsigned long long)want_n);
        for (uint64_t i = 0; i < want_n && i < 24; ++i) printf(" %02X", want[i]);
        printf("\n");
        ++failures;
    }
}

/* ---- the test lab: records what each call saw --------------------------------------------- */

float offset_Enc2_rad = -0.42f;
float offset_Enc3_rad = 0.24f;
float Simulink_PlotVar1 = 0, Simulink_PlotVar2 = 0, Simulink_PlotVar3 = 0, Simulink_PlotVar4 = 0;

/* the lab's globals, laid out below as the linker would (Gen A addresses of the 2019 map) */
float whattoprint = 1.25f;      /* 0xc816 */
float theta1array[100];         /* 0xc4c0 */
int mode = -2;                  /* 0x9000: 16 bits on the C28x */
int count16 = 0x12345;          /* 0x9001: the board keeps 0x2345 */
long big = -70000;              /* 0x9002..3 */
double gain_d = 0.5;            /* 0x9004..5: a C28x double is 32 bits */
unsigned short flags = 0xBEEF;  /* 0x9006 */
const float fixed = 7.0f;       /* 0x9008..9: read-only */

enum { MAX_CALLS = 400 };
static float seen_whattoprint[MAX_CALLS];
static int seen_simu1[MAX_CALLS];
static long calls;

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    (void)theta1motor, (void)theta2motor, (void)theta3motor, (void)error;
    if (calls < MAX_CALLS) {
        seen_whattoprint[calls] = whattoprint;
        seen_simu1[calls] = SIMU_Var1_fromSIMU_16bit;
    }
    Simulink_PlotVar1 = (float)calls; /* the reply to a packet says which call it followed */
    Simulink_PlotVar2 = 2.0f / 3.0f;
    Simulink_PlotVar3 = -2.0f / 3.0f;
    Simulink_PlotVar4 = 1e6f;         /* 10000 * 1e6 is beyond a long: saturated */
    calls++;
    *tau1 = *tau2 = *tau3 = 0.0f;
}

void printing(void) {}

TEST_BOARD_LAB_CALLS

static crs_mem_var VARS[] = {
    {0x9000, 1, 1, sizeof(int), CRS_MEM_SIGNED, 1, &mode},
    {0x9001, 1, 1, sizeof(int), CRS_MEM_SIGNED, 1, &count16},
    {0x9002, 1, 2, sizeof(long), CRS_MEM_SIGNED, 1, &big},
    {0x9004, 1, 2, sizeof(double), CRS_MEM_FLOAT, 1, &gain_d},
    {0x9006, 1, 1, sizeof(unsigned short), CRS_MEM_UNSIGNED, 1, &flags},
    {0x9008, 1, 2, sizeof(float), CRS_MEM_FLOAT, 0, (void *)&fixed},
    {0xc4c0, 100, 2, sizeof(float), CRS_MEM_FLOAT, 1, theta1array},
    {0xc816, 1, 2, sizeof(float), CRS_MEM_FLOAT, 1, &whattoprint},
    {0xc818, 1, 2, sizeof(float), CRS_MEM_FLOAT, 1, &matlabLock},
};

/* ---- the stub plant and the run ------------------------------------------------------------ */

static double qpos[3], qvel[3], ctrl[3], qfrc[3];
static void stub_step(const void *model, void *data) { (void)model, (void)data; }

static crs_board *new_sim(int generation)
{
    const test_plant plant = {qpos, qvel, ctrl, qfrc, stub_step};
    crs_board *board = test_board(generation, 0, &plant);
    board->memory.vars = VARS;
    board->memory.count = sizeof VARS / sizeof VARS[0];
    calls = 0;
    whattoprint = 1.25f;
    matlabLock = 0.0f;
    SIMU_Var1_fromSIMU_16bit = 0;
    return board;
}

static void run_to(crs_board *board, int64_t tick)
{
    const int code = crs_board_run(board, tick);
    if (code != CRS_RUN_DONE) {
        printf("FAIL crs_board_run stopped with %d at tick %lld\n", code, (long long)board->tick);
        ++failures;
    }
}

/* What the host sends between chunks: into the port's inbox. */
static void host_sends(crs_board *board, int port, const unsigned char *bytes, uint32_t n)
{
    crs_host_port *hp = &board->shared->host_ports[port];
    memcpy(hp->inbox + hp->inbox_len, bytes, n);
    hp->inbox_len += n;
}

/* What left the board on a port since the last look. */
static uint64_t host_takes(crs_board *board, int port, char *out)
{
    crs_host_port *hp = &board->shared->host_ports[port];
    const uint64_t n = hp->out_len;
    memcpy(out, hp->out, n);
    hp->out_len = 0;
    return n;
}

static char got[8192];

/* ---- the memory ---------------------------------------------------------------------------- */

static void test_memory_words_are_the_c28x_representation(void)
{
    crs_board *board = new_sim(CRS_GEN_A);
    const crs_c28x_memory *mem = &board->memory;
    check("an int is its low 16 bits: -2", crs_mem_read_word(mem, 0x9000) == 0xFFFE);
    check("an int is its low 16 bits: 0x12345 -> 0x2345", crs_mem_read_word(mem, 0x9001) == 0x2345);
    /* -70000 = 0xFFFEEE90: low word first */
    check("a long's low word", crs_mem_read_word(mem, 0x9002) == 0xEE90);
    check("a long's high word", crs_mem_read_word(mem, 0x9003) == 0xFFFE);
    check("a double is a C28x float: 0.5 = 0x3F000000", crs_mem_read32(mem, 0x9004) == 0x3F000000u);
    check("whattoprint 1.25 = 0x3FA00000", crs_mem_read32(mem, 0xc816) == 0x3FA00000u);
    check("a 32-bit access at an odd address is at the even one below",
          crs_mem_read32(mem, 0xc817) == 0x3FA00000u);
    check("two ints read as one 32-bit word: the neighbour is the high half",
          crs_mem_read32(mem, 0x9000) == 0x2345FFFEu);
    check("no variable: 0", crs_mem_read_word(mem, 0x8FFF) == 0 && crs_mem_read32(mem, 0xc81a) == 0);

    crs_mem_write_word(mem, 0x9000, 0x8000);
    check("a word written into an int is sign-extended", mode == -32768);
    crs_mem_write_word(mem, 0x9006, 0xFFFF);
    check("an unsigned short takes the word", flags == 0xFFFF);
    crs_mem_write32(mem, 0x9002, 0x7FFFFFFFu);
    check("a long takes 32 bits", big == 0x7FFFFFFFL);
    crs_mem_write32(mem, 0x9004, 0xC0200000u); /* -2.5f */
    check("a double takes the float", gain_d == -2.5);
    crs_mem_write32(mem, 0x9008, 0x40400000u);
    check("a const is never written", fixed == 7.0f);
    crs_mem_write32(mem, 0xc4c0 + 2 * 99, 0x40400000u);
    check("the last element of an array", theta1array[99] == 3.0f);
    crs_mem_write_word(mem, 0xc4c0 + 2 * 100, 0x1234); /* whatever lies there: nothing */
    check("beyond the array nothing is written", crs_mem_read_word(mem, 0xc4c0 + 200) == 0);
    /* half a float: the other half stays */
    crs_mem_write_word(mem, 0xc817, 0x4040); /* 1.25 = 3FA0 0000 -> 4040 0000 = 3.0 */
    check("one word of a float", whattoprint == 3.0f);
    mode = -2;
    flags = 0xBEEF;
    test_board_free(board);
}

/* ---- SerialC ------------------------------------------------------------------------------- */

static void test_gen_a_read_write_and_its_timing(void)
{
    crs_board *board = new_sim(CRS_GEN_A);
    run_to(board, 10);
    static const unsigned char read[] = {0x2A, 0x09, 0x32, 0x00, 0x00, 0xC8, 0x16, 0x00, 0x01};
    host_sends(board, CRS_HOST_PORT_C, read, sizeof read);
    /* the 9 bytes arrive during tick 10, the last one 90 000 line units (of 115 200) into it; the
     * reply leaves from then on: 2 bytes by 110 000, the other 5 during tick 11 */
    static const unsigned char reply[] = {0x2A, 0x04, 0x33, 0x00, 0x00, 0xA0, 0x3F};
    run_to(board, 11);
    check_bytes("the reply starts as the request's last byte arrives", got,
                host_takes(board, CRS_HOST_PORT_C, got), reply, 2);
    run_to(board, 12);
    check_bytes("read whattoprint = 1.25 (the worked vector)", got, host_takes(board, CRS_HOST_PORT_C, got),
                reply + 2, sizeof reply - 2);
    check("a Gen A read sets matlabLock", matlabLock == 1.0f);

    /* write 3.75 in two pieces, as ME446_serialwrite's two fwrite calls; no timeout */
    static const unsigned char head[] = {0x2A, 0x0B, 0x33, 0x00, 0x00, 0xC8, 0x16};
    static const unsigned char value[] = {0x00, 0x00, 0x70, 0x40};
    host_sends(board, CRS_HOST_PORT_C, head, sizeof head);
    run_to(board, 50);
    check("half a write changes nothing", whattoprint == 1.25f);
    host_sends(board, CRS_HOST_PORT_C, value, sizeof value);
    run_to(board, 52);
    /* the value's 4 bytes arrive during tick 50: lab() of tick 50 sees 1.25, tick 51 sees 3.75 */
    check("lab() of the tick the write arrives sees the old value", seen_whattoprint[50] == 1.25f);
    check("the next lab() sees the new value", seen_whattoprint[51] == 3.75f);
    check("a write has no reply", host_takes(board, CRS_HOST_PORT_C, got) == 0);

    /* '1' (Gen A): the value big endian: -2.5 = C0 20 00 00 */
    static const unsigned char write_be[] = {0x2A, 0x0B, 0x31, 0x00, 0x00, 0xC8, 0x16, 0xC0, 0x20, 0x00, 0x00};
    host_sends(board, CRS_HOST_PORT_C, write_be, sizeof write_be);
    run_to(board, 60);
    check("'1' writes a big-endian value", whattoprint == -2.5f);

    /* two pairs in one '3': theta1array[0] = 1.0 and theta1array[1] = -1.0 */
    static const unsigned char pairs[] = {0x2A, 0x13, 0x33, 0x00, 0x00, 0xC4, 0xC0, 0x00, 0x00, 0x80, 0x3F,
                                          0x00, 0x00, 0xC4, 0xC2, 0x00, 0x00, 0x80, 0xBF};
    host_sends(board, CRS_HOST_PORT_C, pairs, sizeof pairs);
    run_to(board, 70);
    check("a '3' of two pairs writes both", theta1array[0] == 1.0f && theta1array[1] == -1.0f);

    /* '0' echo of two addresses: address and value, both big endian */
    static const unsigned char echo[] = {0x2A, 0x0B, 0x30, 0x00, 0x00, 0xC8, 0x16, 0x00, 0x00, 0xC4, 0xC0};
    host_sends(board, CRS_HOST_PORT_C, echo, sizeof echo);
    run_to(board, 80);
    static const unsigned char echoed[] = {0x2A, 0x13, 0x30, 0x00, 0x00, 0xC8, 0x16, 0xC0, 0x20, 0x00, 0x00,
                                           0x00, 0x00, 0xC4, 0xC0, 0x3F, 0x80, 0x00, 0x00};
    check_bytes("'0' echoes addresses and big-endian values", got, host_takes(board, CRS_HOST_PORT_C, got),
                echoed, sizeof echoed);

    /* a 2-byte message re-dispatches the last message's payload: a '2' read is read afresh */
    host_sends(board, CRS_HOST_PORT_C, read, sizeof read);
    run_to(board, 90);
    host_takes(board, CRS_HOST_PORT_C, got);
    whattoprint = 0.5f; /* 3F000000 */
    static const unsigned char again[] = {0x2A, 0x02};
    host_sends(board, CRS_HOST_PORT_C, again, sizeof again);
    run_to(board, 100);
    static const unsigned char reread[] = {0x2A, 0x04, 0x33, 0x00, 0x00, 0x00, 0x3F};
    check_bytes("L = 2 answers the last read again", got, host_takes(board, CRS_HOST_PORT_C, got), reread,
                sizeof reread);

    /* an unknown command: no reply; junk before a '*' is skipped */
    static const unsigned char junk[] = {0x00, 0x41, 0x2A, 0x04, 0x39, 0x39};
    host_sends(board, CRS_HOST_PORT_C, junk, sizeof junk);
    host_sends(board, CRS_HOST_PORT_C, read, sizeof read);
    run_to(board, 110);
    check_bytes("junk and an unknown command are ignored", got, host_takes(board, CRS_HOST_PORT_C, got),
                reread, sizeof reread);

    /* a length byte of 0 wedges the receiver for good */
    static const unsigned char wedge[] = {0x2A, 0x00};
    host_sends(board, CRS_HOST_PORT_C, wedge, sizeof wedge);
    host_sends(board, CRS_HOST_PORT_C, read, sizeof read);
    run_to(board, 130);
    check("a length byte of 0 wedges the receiver", host_takes(board, CRS_HOST_PORT_C, got) == 0
          && board->shared->host_ports[CRS_HOST_PORT_C].wedged == 1
          && board->shared->host_ports[CRS_HOST_PORT_C].wedged_tick == 110);
    test_board_free(board);
}

static void test_gen_b_ignores_echo_and_big_endian_writes_and_its_ring_limits_a_read(void)
{
    crs_board *board = new_sim(CRS_GEN_B);
    static const unsigned char write_be[] = {0x2A, 0x0B, 0x31, 0x00, 0x00, 0xC8, 0x16, 0xC0, 0x20, 0x00, 0x00};
    static const unsigned char echo[] = {0x2A, 0x07, 0x30, 0x00, 0x00, 0xC8, 0x16};
    host_sends(board, CRS_HOST_PORT_C, write_be, sizeof write_be);
    host_sends(board, CRS_HOST_PORT_C, echo, sizeof echo);
    run_to(board, 10);
    check("Gen B ignores '1' and '0'", whattoprint == 1.25f && host_takes(board, CRS_HOST_PORT_C, got) == 0);
    static const unsigned char read1[] = {0x2A, 0x09, 0x32, 0x00, 0x00, 0xC8, 0x16, 0x00, 0x01};
    host_sends(board, CRS_HOST_PORT_C, read1, sizeof read1);
    run_to(board, 20);
    host_takes(board, CRS_HOST_PORT_C, got);
    check("a Gen B read leaves matlabLock alone", matlabLock == 0.0f);

    /* 600 floats from theta1array on: the 2000-byte ring plus the FIFO and the shift register take
     * the header and 503 floats and 2 bytes of the next; the reply takes 176 ms to leave */
    for (int i = 0; i < 100; ++i) theta1array[i] = (float)i;
    static const unsigned char read600[] = {0x2A, 0x09, 0x32, 0x00, 0x00, 0xC4, 0xC0, 0x02, 0x58};
    host_sends(board, CRS_HOST_PORT_C, read600, sizeof read600);
    run_to(board, 300);
    const uint64_t n = host_takes(board, CRS_HOST_PORT_C, got);
    check("the reply is cut at the ring", n == 2017);
    check("its header counts 603 mod 256", (unsigned char)got[1] == (603 & 0xFF) && got[2] == '3');
    float f;
    memcpy(&f, got + 3 + 4 * 99, 4);
    check("float 99 is theta1array[99]", f == 99.0f);
    memcpy(&f, got + 3 + 4 * 100, 4);
    check("float 100 runs into whatever follows (nothing: 0)", f == 0.0f);
    check("the dropped bytes are counted", board->shared->host_ports[CRS_HOST_PORT_C].tx_dropped == 2403 - 2017);
    test_board_free(board);
}

/* ---- SerialB ------------------------------------------------------------------------------- */

static void test_simulink_packets_are_answered_at_once_and_reach_the_lab(void)
{
    crs_board *board = new_sim(CRS_GEN_B);
    /* V1 = -3 (FD FF), V2..V7 = 2..7 */
    static const unsigned char packet[] = {0xFF, 0x7F, 0xFD, 0xFF, 0x02, 0x00, 0x03, 0x00, 0x04, 0x00,
                                           0x05, 0x00, 0x06, 0x00, 0x07, 0x00};
    /* right after reset the first byte is tested for 7F alone: the FF takes the flag, the 7F
     * after it is not a start, and the first packet goes unanswered */
    host_sends(board, CRS_HOST_PORT_B, packet, sizeof packet);
    run_to(board, 20);
    check("the first packet after reset is lost", host_takes(board, CRS_HOST_PORT_B, got) == 0
          && SIMU_Var1_fromSIMU_16bit == 0);
    host_sends(board, CRS_HOST_PORT_B, packet, sizeof packet);
    /* bytes 1..11 arrive during tick 20, 12..16 during tick 21: the 7F (byte 2, 20 000 line units
     * into tick 20) is answered at once with the PlotVars after lab() of tick 20, 9 of the reply's
     * bytes leaving during tick 20; the values are stored after tick 21's lab() */
    run_to(board, 21);
    uint64_t n = host_takes(board, CRS_HOST_PORT_B, got);
    check("the reply starts before the packet has all arrived", n == 9);
    run_to(board, 23);
    check("lab() of tick 21 has not seen the values", seen_simu1[21] == 0);
    check("lab() of tick 22 sees them", seen_simu1[22] == -3 && SIMU_Var7_fromSIMU_16bit == 7);
    n += host_takes(board, CRS_HOST_PORT_B, got + n);
    int32_t v[4];
    memcpy(v, got, sizeof v);
    check("the reply is 16 bytes", n == 16);
    check("PlotVar1: lab() of tick 20 was call 20", v[0] == 200000);
    check("PlotVar2: 2/3 truncated", v[1] == 6666 && v[2] == -6666);
    check("PlotVar4: saturated", v[3] == INT32_MAX);

    /* the first byte after reset is tested for 7F alone; a stray FF 7F while hunting syncs */
    crs_board *fresh = new_sim(CRS_GEN_A);
    static const unsigned char bare[] = {0x7F, 0x09, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    host_sends(fresh, CRS_HOST_PORT_B, bare, sizeof bare);
    run_to(fresh, 5);
    check("right after reset a lone 7F starts a packet", SIMU_Var1_fromSIMU_16bit == 9
          && host_takes(fresh, CRS_HOST_PORT_B, got) == 16);
    static const unsigned char noise[] = {0x12, 0xFF, 0x7F, 0x01, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    host_sends(fresh, CRS_HOST_PORT_B, noise, sizeof noise);
    run_to(fresh, 10);
    check("a packet after a stray byte", SIMU_Var1_fromSIMU_16bit == 1 && host_takes(fresh, CRS_HOST_PORT_B, got) == 16);
    free(fresh->shared);
    free(fresh);
    test_board_free(board);
}

static void test_simulink_scaling(void)
{
    check("2/3 -> 6666", crs_simulink_scaled(2.0f / 3.0f) == 6666);
    check("-2/3 -> -6666", crs_simulink_scaled(-2.0f / 3.0f) == -6666);
    check("4e-5 -> 0", crs_simulink_scaled(4e-5f) == 0);
    check("1.5 -> 15000", crs_simulink_scaled(1.5f) == 15000);
    check("-1e6 saturates", crs_simulink_scaled(-1e6f) == INT32_MIN);
    check("NaN -> 0", crs_simulink_scaled(NAN) == 0);
}

int main(void)
{
    test_memory_words_are_the_c28x_representation();
    test_gen_a_read_write_and_its_timing();
    test_gen_b_ignores_echo_and_big_endian_writes_and_its_ring_limits_a_read();
    test_simulink_packets_are_answered_at_once_and_reach_the_lab();
    test_simulink_scaling();
    return checks_report();
}
