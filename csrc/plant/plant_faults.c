/* Faults a scenario injects on the plant's hardware (see plant_faults.h). */
#include "plant_faults.h"

#include <math.h>

static const double PI = 3.14159265358979323846;

/* xorshift64* and Box-Muller: seeded encoder noise */
static double uniform01(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    return ((x * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

static double gaussian(uint64_t *state)
{
    const double u1 = uniform01(state), u2 = uniform01(state);
    return sqrt(-2.0 * log(u1 > 1e-300 ? u1 : 1e-300)) * cos(2.0 * PI * u2);
}

int64_t crs_faulty_encoder_counts(crs_faults *f, int64_t tick, int joint, int64_t counts)
{
    if (f->noise_counts[joint] > 0.0) counts += llround(f->noise_counts[joint] * gaussian(&f->rng_state));
    if (tick == f->glitch_tick) counts += f->glitch_counts[joint];
    /* a stuck encoder repeats its last reading, noise and all, whatever the joint does */
    if (f->stuck_encoder[joint]) {
        counts = f->stuck_counts[joint];
    } else {
        f->stuck_counts[joint] = counts;
    }
    return counts;
}
