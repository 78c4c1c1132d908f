/* A host with little memory: under a 3 GB address-space limit, a distance
 * transform of a 20000 x 20000 raster (16 GB of work) returns
 * PIXGEO_STATUS_NO_MEMORY with the size it needs, where an allocation failure
 * would abort the host; the context keeps working afterwards. */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "check.h"
#include "pixgeo.h"

#define SIDE 20000u

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
        PixgeoStatus status = pixgeo_distance_transform(ctx, mask, &raster, NULL, NULL, NULL, NULL);
        CHECK(status == PIXGEO_STATUS_NO_MEMORY &&
                  strstr(pixgeo_context_last_error(ctx), "needs about") != NULL,
              "status %s: %s", pixgeo_status_string(status), pixgeo_context_last_error(ctx));
        free(mask);
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
