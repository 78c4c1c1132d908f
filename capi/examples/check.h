/* The examples' check: a failed condition prints its message and is counted,
 * and the run goes on, so that one run reports every failure. */
#ifndef PIXGEO_EXAMPLE_CHECK_H
#define PIXGEO_EXAMPLE_CHECK_H

#include <stdio.h>

static int failures = 0;

#define CHECK(cond, ...)                             \
    do {                                             \
        if (!(cond)) {                               \
            fprintf(stderr, "FAILED: " __VA_ARGS__); \
            fprintf(stderr, "\n");                   \
            failures++;                              \
        }                                            \
    } while (0)

#endif
