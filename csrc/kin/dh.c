#include "dh.h"

#include <math.h>

void dh_standard_transform(double a, double alpha_rad, double d, double theta_rad, double out[16])
{
    const double ct = cos(theta_rad), st = sin(theta_rad);
    const double ca = cos(alpha_rad), sa = sin(alpha_rad);
    out[0] = ct;  out[1] = -st * ca; out[2] = st * sa;   out[3] = a * ct;
    out[4] = st;  out[5] = ct * ca;  out[6] = -ct * sa;  out[7] = a * st;
    out[8] = 0.0; out[9] = sa;       out[10] = ca;       out[11] = d;
    out[12] = 0.0; out[13] = 0.0;    out[14] = 0.0;      out[15] = 1.0;
}

void mat4_mul(const double a[16], const double b[16], double out[16])
{
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) {
                s += a[4 * r + k] * b[4 * k + c];
            }
            out[4 * r + c] = s;
        }
    }
}
