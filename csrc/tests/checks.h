/* The C tests' checks (csrc/tests/test_*.c, built and run by tests/test_c_core.py): a check that
 * fails prints one line and is counted; main() ends with `return checks_report();`. */
#ifndef CRSLAB_TESTS_CHECKS_H
#define CRSLAB_TESTS_CHECKS_H

#include <math.h>
#include <stdio.h>

static int failures = 0;

static inline void check(const char *what, int ok)
{
    if (!ok) {
        printf("FAIL %s\n", what);
        ++failures;
    }
}

/* |got - want| <= tol, in the quantity's own unit (rad, m, command units, ...). */
static inline void check_close(const char *what, double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol)) {
        printf("FAIL %s: got %.15g want %.15g\n", what, got, want);
        ++failures;
    }
}

/* What main() returns: 0 when every check passed (it prints "all passed"), else 1. */
static inline int checks_report(void)
{
    if (failures) {
        printf("%d failures\n", failures);
        return 1;
    }
    printf("all passed\n");
    return 0;
}

#endif
