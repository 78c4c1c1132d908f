/* A C host using the rest of pixgeo: a diagram streamed in bands with its ties,
 * flooding and jump flooding, a raster's distance transform, the smallest and
 * largest triangles and quadrangles, and α-hulls, each checked against brute
 * force, and the options' struct_size guard. Exits 0 when every check passes.
 *
 *   tools/install ~/.local
 *   export PKG_CONFIG_PATH=~/.local/lib/pkgconfig LD_LIBRARY_PATH=~/.local/lib
 *   cc -std=c11 capi/examples/shapes.c $(pkg-config --cflags --libs pixgeo) -lm -o shapes-c
 *   ./shapes-c
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pixgeo.h"

enum { W = 40, H = 30, LATTICE = 12, N = 11 };

/* Lattice sites for ties: with L1 and integer coordinates every distance is
 * exact, so the sites at a pixel's smallest distance can be counted. */
static double lattice[2 * LATTICE];

static double l1(const double *xy, int s, int i, int j) {
    return fabs(xy[2 * s] - i) + fabs(xy[2 * s + 1] - j);
}

/* What the band callback saw. */
typedef struct {
    int rows;
    int wrong_labels;
    int wrong_ties;
    int tied_pixels;
    int stop_after;
} BandCheck;

static int check_band(const PixgeoBand *band, void *user_data) {
    BandCheck *seen = user_data;
    for (uint32_t r = 0; r < band->height; r++) {
        for (uint32_t c = 0; c < band->width; c++) {
            int i = (int)(band->x0 + c), j = (int)(band->y0 + r);
            double best = INFINITY;
            int tied = 0;
            for (int s = 0; s < LATTICE; s++) {
                double d = l1(lattice, s, i, j);
                if (d < best) {
                    best = d;
                    tied = 1;
                } else if (d == best) {
                    tied++;
                }
            }
            size_t k = (size_t)r * band->width + c;
            if (l1(lattice, (int)band->labels[k], i, j) != best) seen->wrong_labels++;
            if (band->ties[k] != (uint32_t)tied) seen->wrong_ties++;
            if (tied > 1) seen->tied_pixels++;
        }
    }
    seen->rows += (int)band->height;
    return seen->stop_after > 0 && seen->rows >= seen->stop_after;
}

/* A fixed random sequence, so that runs repeat. */
static unsigned long long state = 12345;
static double uniform(void) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(state >> 11) / 9007199254740992.0;
}

static double cross(const double *p, int a, int b, int c) {
    return (p[2 * b] - p[2 * a]) * (p[2 * c + 1] - p[2 * a + 1]) -
           (p[2 * b + 1] - p[2 * a + 1]) * (p[2 * c] - p[2 * a]);
}

/* Whether segments ab and cd cross properly (random points: no three on a line). */
static int crossing(const double *p, int a, int b, int c, int d) {
    return (cross(p, a, b, c) > 0) != (cross(p, a, b, d) > 0) &&
           (cross(p, c, d, a) > 0) != (cross(p, c, d, b) > 0);
}

/* The area of the polygon v[0..n) of points p, by the shoelace formula. */
static double area_of(const double *p, const uint32_t *v, int n) {
    double twice = 0;
    for (int k = 0; k < n; k++) {
        int a = (int)v[k], b = (int)v[(k + 1) % n];
        twice += p[2 * a] * p[2 * b + 1] - p[2 * b] * p[2 * a + 1];
    }
    return twice / 2;
}

int main(void) {
    PixgeoContextOptions context_options = pixgeo_context_options_default();
    const char *validation = getenv("PIXGEO_VALIDATION");
    context_options.validation = validation != NULL && strcmp(validation, "1") == 0;
    /* This host keeps no pipelines between runs: no file is written. */
    context_options.pipeline_cache = false;
    PixgeoContext *ctx = NULL;
    PixgeoStatus created = pixgeo_context_create(&context_options, &ctx);
    if (created != PIXGEO_STATUS_OK) {
        fprintf(stderr, "no context (%s): %s\n", pixgeo_status_string(created),
                pixgeo_create_error());
        return 1;
    }
    CHECK(strcmp(pixgeo_status_string(PIXGEO_STATUS_BUFFER_TOO_SMALL), "buffer too small") == 0 &&
              strcmp(pixgeo_status_string(99), "unknown status") == 0,
          "status strings");

    /* Bands with ties, under L1, cut into tiles of 16 pixels so that several
     * bands arrive. */
    for (int s = 0; s < LATTICE; s++) {
        lattice[2 * s] = 4 + 8 * (s % 4);
        lattice[2 * s + 1] = 5 + 9 * (s / 4);
    }
    PixgeoVoronoiOptions options = pixgeo_voronoi_options_default(W, H);
    options.metric = PIXGEO_METRIC_L1;
    options.max_tile = 16;
    BandCheck seen = {0};
    PixgeoStatus status =
        pixgeo_voronoi_bands(ctx, lattice, LATTICE, &options, true, true, check_band, &seen);
    CHECK(status == PIXGEO_STATUS_OK, "bands: %s", pixgeo_context_last_error(ctx));
    CHECK(seen.rows == H && seen.wrong_labels == 0 && seen.wrong_ties == 0,
          "bands: %d rows, %d labels and %d tie counts wrong", seen.rows, seen.wrong_labels,
          seen.wrong_ties);
    CHECK(seen.tied_pixels > 0, "an L1 lattice has tied pixels");

    /* A callback stops the call by returning non-zero. */
    BandCheck stopping = {.stop_after = 1};
    status = pixgeo_voronoi_bands(ctx, lattice, LATTICE, &options, true, true, check_band,
                                  &stopping);
    CHECK(status == PIXGEO_STATUS_STOPPED && stopping.rows < H, "stop: status %d, %d rows",
          (int)status, stopping.rows);

    /* Flooding and jump flooding: each site's pixel is its own, and almost every
     * pixel gets a nearest site (flooding keeps regions connected; jump
     * flooding errs on a few pixels). */
    double seeds[2 * N];
    for (int s = 0; s < N; s++) {
        seeds[2 * s] = (7 * s + 3) % W;
        seeds[2 * s + 1] = (11 * s + 2) % H;
    }
    uint32_t *flooded = malloc(sizeof(uint32_t) * W * H);
    PixgeoVoronoiOptions picture = pixgeo_voronoi_options_default(W, H);
    /* Two sites in one pixel are refused: flooding grows one region per pixel. */
    double twice[2 * N];
    memcpy(twice, seeds, sizeof seeds);
    twice[2] = twice[0] + 0.2;
    twice[3] = twice[1] - 0.3;
    CHECK(pixgeo_flood(ctx, twice, N, &picture, PIXGEO_FLOOD_METHOD_FLOOD, flooded) ==
              PIXGEO_STATUS_INVALID_ARGUMENT &&
              strstr(pixgeo_context_last_error(ctx), "one site per pixel") != NULL,
          "two sites in one pixel: %s", pixgeo_context_last_error(ctx));
    for (int method = 0; method < 2; method++) {
        status = pixgeo_flood(ctx, seeds, N, &picture, (uint32_t)method, flooded);
        CHECK(status == PIXGEO_STATUS_OK, "flood %d: %s", method, pixgeo_context_last_error(ctx));
        int own = 0, nearest = 0;
        for (int s = 0; s < N; s++) {
            own += flooded[(int)seeds[2 * s + 1] * W + (int)seeds[2 * s]] == (uint32_t)s;
        }
        for (int j = 0; j < H; j++) {
            for (int i = 0; i < W; i++) {
                double best = INFINITY;
                for (int s = 0; s < N; s++) {
                    best = fmin(best, hypot(seeds[2 * s] - i, seeds[2 * s + 1] - j));
                }
                uint32_t l = flooded[j * W + i];
                nearest += l < N && hypot(seeds[2 * l] - i, seeds[2 * l + 1] - j) == best;
            }
        }
        CHECK(own == N && nearest >= W * H * 98 / 100, "flood %d: %d own seeds, %d nearest",
              method, own, nearest);
    }
    free(flooded);

    /* The distance and feature transform of a raster, anisotropic, against
     * brute force; a spacing of 0 is refused. */
    {
        unsigned char mask[W * H] = {0};
        mask[3 * W + 5] = mask[20 * W + 31] = mask[29 * W + 0] = 1;
        PixgeoVoronoiOptions raster = pixgeo_voronoi_options_default(W, H);
        const double sampling[2] = {2.0, 0.5};
        double *d = malloc(sizeof(double) * W * H);
        int32_t *rows = malloc(sizeof(int32_t) * W * H);
        int32_t *columns = malloc(sizeof(int32_t) * W * H);
        status = pixgeo_distance_transform(ctx, mask, &raster, sampling, d, rows, columns);
        CHECK(status == PIXGEO_STATUS_OK, "transform: %s", pixgeo_context_last_error(ctx));
        int wrong = 0;
        for (int j = 0; j < H; j++) {
            for (int i = 0; i < W; i++) {
                double best = INFINITY;
                for (int k = 0; k < W * H; k++) {
                    if (mask[k]) best = fmin(best, hypot(2.0 * (j - k / W), 0.5 * (i - k % W)));
                }
                int r = rows[j * W + i], c = columns[j * W + i];
                wrong += d[j * W + i] != best || !mask[r * W + c] ||
                         hypot(2.0 * (j - r), 0.5 * (i - c)) != best;
            }
        }
        CHECK(wrong == 0, "transform: %d pixels wrong", wrong);
        const double flat[2] = {0.0, 1.0};
        CHECK(pixgeo_distance_transform(ctx, mask, &raster, flat, d, NULL, NULL) ==
                      PIXGEO_STATUS_INVALID_ARGUMENT &&
                  strstr(pixgeo_context_last_error(ctx), "sampling") != NULL,
              "a spacing of 0: %s", pixgeo_context_last_error(ctx));
        free(d);
        free(rows);
        free(columns);
    }

    /* Triangles and quadrangles against every subset. */
    double p[2 * N];
    for (int k = 0; k < 2 * N; k++) p[k] = uniform() * 100;
    double smallest3 = INFINITY, largest3 = 0, smallest4 = INFINITY, largest4 = 0;
    for (int a = 0; a < N; a++)
        for (int b = a + 1; b < N; b++)
            for (int c = b + 1; c < N; c++) {
                double t = fabs(cross(p, a, b, c)) / 2;
                smallest3 = fmin(smallest3, t);
                largest3 = fmax(largest3, t);
                for (int d = c + 1; d < N; d++) {
                    /* The three cyclic orders of four points; the simple ones count. */
                    const uint32_t orders[3][4] = {
                        {a, b, c, d}, {a, b, d, c}, {a, c, b, d}};
                    for (int o = 0; o < 3; o++) {
                        const uint32_t *v = orders[o];
                        if (crossing(p, v[0], v[1], v[2], v[3]) ||
                            crossing(p, v[1], v[2], v[3], v[0]))
                            continue;
                        double q = fabs(area_of(p, v, 4));
                        smallest4 = fmin(smallest4, q);
                        largest4 = fmax(largest4, q);
                    }
                }
            }
    const double expected[2][2] = {{smallest3, largest3}, {smallest4, largest4}};
    PixgeoAreaOptions area_options = pixgeo_area_options_default();
    for (int method = 0; method < 2; method++) {
        for (int extreme = 0; extreme < 2; extreme++) {
            area_options.method = (uint32_t)method;
            area_options.extreme = (uint32_t)extreme;
            for (int shape = 0; shape < 2; shape++) {
                PixgeoPolygonAnswer answer;
                status = shape == 0 ? pixgeo_triangle(ctx, p, N, &area_options, &answer)
                                    : pixgeo_quadrangle(ctx, p, N, &area_options, &answer);
                double want = expected[shape][extreme];
                CHECK(status == PIXGEO_STATUS_OK && answer.vertex_count == (uint32_t)(3 + shape) &&
                          fabs(answer.area - want) <= 1e-9 * want &&
                          fabs(area_of(p, answer.sites, (int)answer.vertex_count) - want) <=
                              1e-9 * want,
                      "method %d extreme %d shape %d: area %g, expected %g: %s", method, extreme,
                      shape, answer.area, want, pixgeo_context_last_error(ctx));
            }
        }
    }

    /* The convex hull (α = 0): its boundary turns left, and every site is on
     * or inside it. Too small an array first gets BufferTooSmall and the sizes. */
    PixgeoAlphaOptions alpha = pixgeo_alpha_options_default();
    alpha.side = 96;
    PixgeoAlphaHull hull;
    uint8_t one_pixel;
    status = pixgeo_alpha_hull(ctx, p, N, &alpha, &hull, &one_pixel, 1, NULL, 0);
    CHECK(status == PIXGEO_STATUS_BUFFER_TOO_SMALL && hull.width > 0 && hull.height > 0,
          "alpha with 1 byte: status %d, %ux%u", (int)status, hull.width, hull.height);
    size_t pixels = (size_t)hull.width * hull.height;
    uint8_t *classes = malloc(pixels);
    uint32_t boundary[N];
    status = pixgeo_alpha_hull(ctx, p, N, &alpha, &hull, classes, pixels, boundary, N);
    CHECK(status == PIXGEO_STATUS_OK && hull.boundary_count >= 3 && isnan(hull.radius),
          "alpha: %s", pixgeo_context_last_error(ctx));
    size_t inside = 0;
    for (size_t k = 0; k < pixels; k++) inside += classes[k] == PIXGEO_ALPHA_CLASS_INSIDE;
    CHECK(inside == hull.inside && inside > 0, "inside %zu, reported %zu", inside, hull.inside);
    int outside = 0;
    for (size_t e = 0; e < hull.boundary_count; e++) {
        int a = (int)boundary[e], b = (int)boundary[(e + 1) % hull.boundary_count];
        for (int s = 0; s < N; s++) outside += cross(p, a, b, s) < 0;
    }
    CHECK(outside == 0, "%d sites right of a hull edge", outside);
    free(classes);

    /* Options not made by their *_default() are refused by struct_size. */
    PixgeoAreaOptions zeroed = {0};
    PixgeoPolygonAnswer unused;
    CHECK(pixgeo_triangle(ctx, p, N, &zeroed, &unused) == PIXGEO_STATUS_INVALID_ARGUMENT &&
              strstr(pixgeo_context_last_error(ctx), "pixgeo_area_options_default") != NULL,
          "zeroed options: %s", pixgeo_context_last_error(ctx));
    PixgeoVoronoiOptions newer = pixgeo_voronoi_options_default(W, H);
    newer.struct_size += 8;
    uint32_t labels[W * H];
    CHECK(pixgeo_voronoi(ctx, p, N, &newer, labels, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT &&
              strstr(pixgeo_context_last_error(ctx), "struct_size") != NULL,
          "a larger struct_size: %s", pixgeo_context_last_error(ctx));

    pixgeo_context_destroy(ctx);
    if (failures == 0) printf("all checks passed\n");
    return failures == 0 ? 0 : 1;
}
