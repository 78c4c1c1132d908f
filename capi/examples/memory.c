/* A host with little memory: under a 3 GB address-space limit, a distance
 * transform of a 20000 x 20000 raster (16 GB of work) and a power diagram of
 * 5e7 sites return PIXGEO_STATUS_NO_MEMORY with the size they need, and so
 * does an interpolation of 8192 x 8192 pixels under 1.5 GB, where an
 * allocation failure would abort the host; the context keeps working
 * afterwards. */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "check.h"
#include "pixgeo.h"

#define SIDE 20000u

/* The call's status is PIXGEO_STATUS_NO_MEMORY, with the size it needs. */
static void expect_no_memory(PixgeoContext *ctx, PixgeoStatus status, const char *what) {
    CHECK(status == PIXGEO_STATUS_NO_MEMORY &&
              strstr(pixgeo_context_last_error(ctx), "needs about") != NULL,
          "%s: status %s: %s", what, pixgeo_status_string(status), pixgeo_context_last_error(ctx));
}

int main(void) {
    const struct rlimit limit = {3ul << 30, 3ul << 30};
    if (setrlimit(RLIMIT_AS, &limit) != 0) {
        perror("setrlimit");
        return 1;
    }
    PixgeoContextOptions context_options = pixgeo_context_options_default();
    context_options.pipeline_cache = false;
    PixgeoContext *ctx = NULL;
    if (pixgeo_context_create(&context_options, &ctx) != PIXGEO_STATUS_OK) {
        fprintf(stderr, "no context: %s\n", pixgeo_create_error());
        return 1;
    }
    uint8_t *mask = calloc((size_t)SIDE * SIDE, 1);
    CHECK(mask != NULL, "no room for the mask itself");
    if (mask != NULL) {
        mask[0] = 1;
        PixgeoVoronoiOptions raster = pixgeo_voronoi_options_default(SIDE, SIDE);
        expect_no_memory(ctx, pixgeo_distance_transform(ctx, mask, &raster, NULL, NULL, NULL, NULL),
                         "a 20000 x 20000 transform");
        free(mask);
    }
    /* 5e7 sites (800 MB of coordinates, 400 MB of weights) on a small picture:
     * their order and buckets would take more than the 1.8 GB left. */
    const size_t many = 50000000;
    double *xy = malloc(many * 2 * sizeof(double));
    double *weights = calloc(many, sizeof(double));
    CHECK(xy != NULL && weights != NULL, "no room for the sites themselves");
    if (xy != NULL && weights != NULL) {
        for (size_t i = 0; i < many; i++) {
            xy[2 * i] = (double)(i % 7919) / 79.19;
            xy[2 * i + 1] = (double)(i / 7919) / 631.0;
        }
        PixgeoVoronoiOptions picture = pixgeo_voronoi_options_default(64, 64);
        uint32_t labels[64 * 64];
        expect_no_memory(ctx, pixgeo_power_diagram(ctx, xy, weights, many, &picture, labels, NULL, NULL),
                         "a power diagram of 5e7 sites");
    }
    free(xy);
    free(weights);
    /* An 8192 x 8192 interpolation under 1.5 GB: the 512 MB raster is the
     * host's, the 24 bytes a pixel of work are not there. */
    const struct rlimit less = {3ul << 29, 3ul << 29};
    CHECK(setrlimit(RLIMIT_AS, &less) == 0, "setrlimit 1.5 GB");
    const size_t side = 8192;
    double *heights = malloc(side * side * sizeof(double));
    CHECK(heights != NULL, "no room for the raster itself");
    if (heights != NULL) {
        const double samples[8] = {0, 0, 8191, 0, 0, 8191, 8191, 8191};
        const double values[4] = {1, 2, 3, 4};
        PixgeoVoronoiOptions picture = pixgeo_voronoi_options_default(side, side);
        expect_no_memory(ctx,
                         pixgeo_interpolate(ctx, samples, values, 4, &picture,
                                            PIXGEO_INTERPOLATION_EXACT, heights, NULL),
                         "an 8192 x 8192 interpolation");
        free(heights);
    }
    uint8_t small[4] = {1, 0, 0, 0};
    double d[4];
    PixgeoVoronoiOptions two = pixgeo_voronoi_options_default(2, 2);
    CHECK(pixgeo_distance_transform(ctx, small, &two, NULL, d, NULL, NULL) == PIXGEO_STATUS_OK &&
              d[3] > 1.41 && d[3] < 1.42,
          "a small transform afterwards: %s", pixgeo_context_last_error(ctx));
    pixgeo_context_destroy(ctx);
    if (failures == 0) printf("all checks passed\n");
    return failures == 0 ? 0 : 1;
}
