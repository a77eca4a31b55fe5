/* crslab's C28x arithmetic check (crslab/lab/c28x_check.py) compiles a lab a second time, for
 * analysis only, for a target with the C28x's widths and no C library: this declares the math
 * functions a lab calls, as C11 names them (double is 32 bits there, as on the C28x). */
#ifndef CRSLAB_C28X_CHECK_MATH_H
#define CRSLAB_C28X_CHECK_MATH_H

double sin(double x);
double cos(double x);
double tan(double x);
double asin(double x);
double acos(double x);
double atan(double x);
double atan2(double y, double x);
double sinh(double x);
double cosh(double x);
double tanh(double x);
double exp(double x);
double log(double x);
double log10(double x);
double pow(double x, double y);
double sqrt(double x);
double ceil(double x);
double floor(double x);
double fabs(double x);
double fmod(double x, double y);
double hypot(double x, double y);
double round(double x);
float sinf(float x);
float cosf(float x);
float tanf(float x);
float atan2f(float y, float x);
float sqrtf(float x);
float fabsf(float x);
float powf(float x, float y);
float expf(float x);
float logf(float x);
int abs(int x);
long labs(long x);

#define M_PI 3.14159265358979323846
#define HUGE_VAL (__builtin_huge_val())
#define INFINITY (__builtin_inff())
#define NAN (__builtin_nanf(""))
#define isnan(x) __builtin_isnan(x)
#define isinf(x) __builtin_isinf(x)

#endif
