/* The C library's <math.h> as a lab sees it in crslab's WebAssembly firmware, where the lab is
 * compiled with the C28x's widths (crslab/lab/c28x_ir.py): double is a 32-bit float there, as on
 * the F28335 (COFF ABI), so each function is the float one of the C library, as TI's run-time
 * library makes sin() and sinf() one function. */
#ifndef CRSLAB_C28X_MATH_H
#define CRSLAB_C28X_MATH_H

#define CRS_F(name) __asm__(#name "f")
double sin(double x) CRS_F(sin);
double cos(double x) CRS_F(cos);
double tan(double x) CRS_F(tan);
double asin(double x) CRS_F(asin);
double acos(double x) CRS_F(acos);
double atan(double x) CRS_F(atan);
double atan2(double y, double x) CRS_F(atan2);
double sinh(double x) CRS_F(sinh);
double cosh(double x) CRS_F(cosh);
double tanh(double x) CRS_F(tanh);
double exp(double x) CRS_F(exp);
double exp2(double x) CRS_F(exp2);
double log(double x) CRS_F(log);
double log10(double x) CRS_F(log10);
double log2(double x) CRS_F(log2);
double pow(double x, double y) CRS_F(pow);
double sqrt(double x) CRS_F(sqrt);
double cbrt(double x) CRS_F(cbrt);
double ceil(double x) CRS_F(ceil);
double floor(double x) CRS_F(floor);
double trunc(double x) CRS_F(trunc);
double round(double x) CRS_F(round);
double fabs(double x) CRS_F(fabs);
double fmod(double x, double y) CRS_F(fmod);
double hypot(double x, double y) CRS_F(hypot);
double fmin(double x, double y) CRS_F(fmin);
double fmax(double x, double y) CRS_F(fmax);
double copysign(double x, double y) CRS_F(copysign);
double remainder(double x, double y) CRS_F(remainder);
double modf(double x, double *whole) CRS_F(modf);
float sinf(float x);
float cosf(float x);
float tanf(float x);
float asinf(float x);
float acosf(float x);
float atanf(float x);
float atan2f(float y, float x);
float expf(float x);
float logf(float x);
float log10f(float x);
float powf(float x, float y);
float sqrtf(float x);
float ceilf(float x);
float floorf(float x);
float roundf(float x);
float fabsf(float x);
float fmodf(float x, float y);
float hypotf(float x, float y);
#undef CRS_F

/* an int argument goes to the C library as the 32-bit int it takes */
float crs_c28x_ldexpf(float x, long e) __asm__("ldexpf");
float crs_c28x_frexpf(float x, long *e) __asm__("frexpf");
static inline double ldexp(double x, int e) { return crs_c28x_ldexpf((float)x, e); }
static inline double frexp(double x, int *e)
{
    long e32 = 0;
    const float m = crs_c28x_frexpf((float)x, &e32);
    *e = (int)e32;
    return m;
}

#define M_PI 3.14159265358979323846
#define M_PI_2 1.57079632679489661923
#define M_E 2.7182818284590452354
#define HUGE_VAL (__builtin_huge_valf())
#define HUGE_VALF (__builtin_huge_valf())
#define INFINITY (__builtin_inff())
#define NAN (__builtin_nanf(""))
#define isnan(x) __builtin_isnan(x)
#define isinf(x) __builtin_isinf(x)
#define isfinite(x) __builtin_isfinite(x)
#define signbit(x) __builtin_signbit(x)

#endif
