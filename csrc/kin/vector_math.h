/* Internal: lets gcc vectorize loops that call libm (glibc's libmvec on x86-64), and build one
 * copy of a hot batch loop per instruction set, picked at load time. Elsewhere both are no-ops
 * and the loops stay plain scalar C. Not part of the Python-visible API (no declarations).
 * The core is linked with link-time optimization, which merges the files' declarations of a
 * function: where the merged one lacks the simd attribute, every loop calling it stays scalar.
 * So every file of the core that calls atan2 includes this header (two that did not left the
 * batch IK scalar); tests/test_kin_batch_placement.py checks that the core calls libmvec's
 * atan2, sin and cos. */
#ifndef CRSLAB_VECTOR_MATH_H
#define CRSLAB_VECTOR_MATH_H

#include <math.h>

#if defined(__x86_64__) && defined(__GLIBC__) && defined(__GNUC__) && !defined(__clang__) \
    && !defined(__SANITIZE_ADDRESS__)
#define CRS_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#define CRS_SIMD_DECL __attribute__((simd("notinbranch")))
extern double sin(double) CRS_SIMD_DECL;
extern double cos(double) CRS_SIMD_DECL;
extern double atan2(double, double) CRS_SIMD_DECL;
#else
#define CRS_VECTOR_CLONES
#endif

#endif
