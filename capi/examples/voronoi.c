/* A C host using pixgeo: a Voronoi diagram, the k nearest and the furthest sites,
 * exact distances between point sets, the settle point and a diagram of weighted
 * and extended sites, each checked against its definition, and the errors a
 * caller can get. Exits 0 when every check
 * passes.
 *
 *   tools/install ~/.local
 *   export PKG_CONFIG_PATH=~/.local/lib/pkgconfig LD_LIBRARY_PATH=~/.local/lib
 *   cc -std=c11 capi/examples/voronoi.c $(pkg-config --cflags --libs pixgeo) -lm -o voronoi-c
 *   ./voronoi-c
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pixgeo.h"

enum { W = 64, H = 48, N = 7 };

int main(void) {
    PixgeoContextOptions context_options = pixgeo_context_options_default();
    const char *validation = getenv("PIXGEO_VALIDATION");
    context_options.validation = validation != NULL && strcmp(validation, "1") == 0;

    PixgeoContext *ctx = NULL;
    if (pixgeo_context_create(&context_options, &ctx) != PIXGEO_STATUS_OK) {
        fprintf(stderr, "no context: %s\n", pixgeo_create_error());
        return 1;
    }
    printf("device: %s\n", pixgeo_context_device_name(ctx));

    /* The library loaded is the one this header describes. */
    char version[32];
    snprintf(version, sizeof version, "%d.%d.%d", PIXGEO_VERSION_MAJOR, PIXGEO_VERSION_MINOR,
             PIXGEO_VERSION_PATCH);
    CHECK(strcmp(pixgeo_version(), version) == 0, "library %s, header %s", pixgeo_version(),
          version);

    /* Sites: some inside, one on the border, one outside the picture. */
    const double xy[2 * N] = {10, 10, 50.5, 20, 30, 45, 0, 0, 63, 47, 31.25, 23.75, -20, 30};
    uint32_t *labels = malloc(sizeof(uint32_t) * W * H);
    float *distances = malloc(sizeof(float) * W * H);
    PixgeoVoronoiOptions options = pixgeo_voronoi_options_default(W, H);
    PixgeoStatus status = pixgeo_voronoi(ctx, xy, N, &options, labels, distances);
    CHECK(status == PIXGEO_STATUS_OK, "voronoi: %s", pixgeo_context_last_error(ctx));

    /* Every pixel: its site is a nearest one, its distance the nearest distance. */
    int wrong = 0;
    for (int j = 0; j < H; j++) {
        for (int i = 0; i < W; i++) {
            double best = INFINITY;
            for (int s = 0; s < N; s++) {
                double d = hypot(xy[2 * s] - i, xy[2 * s + 1] - j);
                if (d < best) best = d;
            }
            uint32_t label = labels[j * W + i];
            double mine = label < N ? hypot(xy[2 * label] - i, xy[2 * label + 1] - j) : INFINITY;
            if (mine > best + 1e-4 || fabs(distances[j * W + i] - best) > 1e-4) wrong++;
        }
    }
    CHECK(wrong == 0, "%d pixels differ from the definition", wrong);
    CHECK(labels[10 * W + 10] == 0, "pixel (10, 10) belongs to site 0");

    /* Tiles of 20 pixels give the same labels. */
    uint32_t *tiled = malloc(sizeof(uint32_t) * W * H);
    options.max_tile = 20;
    status = pixgeo_voronoi(ctx, xy, N, &options, tiled, NULL);
    CHECK(status == PIXGEO_STATUS_OK, "tiled: %s", pixgeo_context_last_error(ctx));
    CHECK(memcmp(tiled, labels, sizeof(uint32_t) * W * H) == 0, "tiled labels differ");

    /* Cones drawn and the grid searched give the same labels. */
    for (uint32_t method = PIXGEO_VORONOI_METHOD_CONES; method <= PIXGEO_VORONOI_METHOD_GRID;
         method++) {
        options = pixgeo_voronoi_options_default(W, H);
        options.method = method;
        status = pixgeo_voronoi(ctx, xy, N, &options, tiled, NULL);
        CHECK(status == PIXGEO_STATUS_OK, "method %u: %s", method, pixgeo_context_last_error(ctx));
        CHECK(memcmp(tiled, labels, sizeof(uint32_t) * W * H) == 0, "method %u differs", method);
    }

    /* A window (x0, y0, width, height) is the whole diagram's pixels there. */
    options = pixgeo_voronoi_options_default(W, H);
    options.window[0] = 13;
    options.window[1] = 7;
    options.window[2] = 40;
    options.window[3] = 30;
    status = pixgeo_voronoi(ctx, xy, N, &options, tiled, NULL);
    CHECK(status == PIXGEO_STATUS_OK, "window: %s", pixgeo_context_last_error(ctx));
    wrong = 0;
    for (int j = 0; j < 30; j++)
        for (int i = 0; i < 40; i++)
            if (tiled[j * 40 + i] != labels[(j + 7) * W + i + 13]) wrong++;
    CHECK(wrong == 0, "%d window pixels differ from the whole diagram", wrong);
    options.window[2] = W; /* leaves the picture */
    CHECK(pixgeo_voronoi(ctx, xy, N, &options, tiled, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT,
          "a window past the picture is refused");

    /* Fan cones with 6 triangles stay within their error bound (< 0.16 r). */
    options = pixgeo_voronoi_options_default(W, H);
    options.accuracy = PIXGEO_ACCURACY_FAN;
    options.triangles = 6;
    options.speedup = PIXGEO_SPEEDUP_QUADTREE;
    status = pixgeo_voronoi(ctx, xy, N, &options, tiled, distances);
    CHECK(status == PIXGEO_STATUS_OK, "fan: %s", pixgeo_context_last_error(ctx));

    /* The L1 distance: every pixel's site at the smallest |dx| + |dy|. */
    options = pixgeo_voronoi_options_default(W, H);
    options.metric = PIXGEO_METRIC_L1;
    status = pixgeo_voronoi(ctx, xy, N, &options, labels, distances);
    CHECK(status == PIXGEO_STATUS_OK, "L1: %s", pixgeo_context_last_error(ctx));
    wrong = 0;
    for (int p = 0; p < W * H; p++) {
        double i = p % W, j = p / W, best = INFINITY;
        for (int s = 0; s < N; s++) best = fmin(best, fabs(xy[2 * s] - i) + fabs(xy[2 * s + 1] - j));
        uint32_t site = labels[p];
        double mine = site < N ? fabs(xy[2 * site] - i) + fabs(xy[2 * site + 1] - j) : INFINITY;
        if (mine > best + 1e-4 || fabs(distances[p] - best) > 1e-4) wrong++;
    }
    CHECK(wrong == 0, "%d L1 pixels differ from the definition", wrong);

    /* A polygonal distance whose unit ball is the L1 diamond around a shifted
     * kernel: the same distances (thesis §3.6.5). */
    const double diamond[8] = {6, 5, 5, 6, 4, 5, 5, 4};
    float *polygon_distances = malloc(sizeof(float) * W * H);
    options.metric = PIXGEO_METRIC_POLYGON;
    options.polygon = diamond;
    options.polygon_count = 4;
    options.kernel[0] = 5;
    options.kernel[1] = 5;
    status = pixgeo_voronoi(ctx, xy, N, &options, tiled, polygon_distances);
    CHECK(status == PIXGEO_STATUS_OK, "polygon: %s", pixgeo_context_last_error(ctx));
    wrong = 0;
    for (int p = 0; p < W * H; p++)
        if (fabs(polygon_distances[p] - distances[p]) > 0.02) wrong++;
    CHECK(wrong == 0, "%d polygon pixels differ from L1", wrong);
    options.kernel[0] = 9; /* outside the diamond: not star-shaped around it */
    status = pixgeo_voronoi(ctx, xy, N, &options, tiled, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "a polygon around the wrong kernel accepted");
    free(polygon_distances);
    options.polygon = NULL;
    options.metric = PIXGEO_METRIC_LP;
    options.metric_p = 0.0;
    status = pixgeo_voronoi(ctx, xy, N, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "L_p with p = 0 accepted");

    /* The three nearest sites of every pixel, in order. */
    enum { K = 3 };
    uint32_t *knn = malloc(sizeof(uint32_t) * W * H * K);
    float *knn_d = malloc(sizeof(float) * W * H * K);
    options = pixgeo_voronoi_options_default(W, H);
    status = pixgeo_k_nearest(ctx, xy, N, &options, K, knn, knn_d);
    CHECK(status == PIXGEO_STATUS_OK, "k nearest: %s", pixgeo_context_last_error(ctx));
    wrong = 0;
    for (int p = 0; p < W * H; p++) {
        double i = p % W, j = p / W, d[N];
        for (int s = 0; s < N; s++) d[s] = hypot(xy[2 * s] - i, xy[2 * s + 1] - j);
        for (int l = 0; l < K; l++) {
            /* The l-th smallest distance: select it from what remains. */
            int m = l;
            for (int s = l + 1; s < N; s++)
                if (d[s] < d[m]) m = s;
            double t = d[l];
            d[l] = d[m];
            d[m] = t;
            uint32_t site = knn[p * K + l];
            double mine = site < N ? hypot(xy[2 * site] - i, xy[2 * site + 1] - j) : INFINITY;
            if (fabs(mine - d[l]) > 1e-4 || fabs(knn_d[p * K + l] - d[l]) > 1e-4) wrong++;
        }
    }
    CHECK(wrong == 0, "%d levels differ from the definition", wrong);

    /* The furthest site of every pixel. */
    status = pixgeo_furthest(ctx, xy, N, &options, labels, distances);
    CHECK(status == PIXGEO_STATUS_OK, "furthest: %s", pixgeo_context_last_error(ctx));
    wrong = 0;
    for (int p = 0; p < W * H; p++) {
        double i = p % W, j = p / W, far = 0;
        for (int s = 0; s < N; s++) far = fmax(far, hypot(xy[2 * s] - i, xy[2 * s + 1] - j));
        if (fabs(distances[p] - far) > 1e-4) wrong++;
    }
    CHECK(wrong == 0, "%d furthest distances differ", wrong);

    /* Exact distances between point sets, with the answering pair. */
    const double red[6] = {0, 0, 1, 0, 0, 1};
    const double blue[4] = {0, 0.5, 3, 4};
    PixgeoPair red_to_blue, blue_to_red, pair;
    status = pixgeo_hausdorff(ctx, red, 3, blue, 2, &red_to_blue, &blue_to_red);
    CHECK(status == PIXGEO_STATUS_OK, "hausdorff: %s", pixgeo_context_last_error(ctx));
    CHECK(red_to_blue.distance == sqrt(1.25) && red_to_blue.from == 1 && red_to_blue.to == 0,
          "red to blue %g", red_to_blue.distance);
    CHECK(blue_to_red.distance == sqrt(18.0) && blue_to_red.from == 1 && blue_to_red.to == 2,
          "blue to red %g", blue_to_red.distance);
    status = pixgeo_diameter(ctx, blue, 2, &pair);
    CHECK(status == PIXGEO_STATUS_OK && pair.distance == sqrt(21.25), "diameter %g", pair.distance);
    status = pixgeo_max_distance(ctx, red, 3, blue, 2, &pair);
    CHECK(status == PIXGEO_STATUS_OK && pair.distance == 5.0 && pair.from == 0 && pair.to == 1,
          "maximum distance %g", pair.distance);
    status = pixgeo_diameter(ctx, blue, 2, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "null answer accepted");

    /* Homothets: a right triangle's smallest circle is on its hypotenuse; the
     * largest empty circle centred in its bounding box sits on the top side at
     * x = 25/8, as far from (0, 3) as from (4, 0). */
    PixgeoSite corners[3] = {
        {PIXGEO_SITE_KIND_POINT, {0, 0}, 1, 0},
        {PIXGEO_SITE_KIND_POINT, {4, 0}, 1, 0},
        {PIXGEO_SITE_KIND_POINT, {0, 3}, 1, 0},
    };
    PixgeoHomothetOptions circle = pixgeo_homothet_options_default(); /* a circle */
    circle.side = 128;
    PixgeoHomothet homothet;
    status = pixgeo_enclose(ctx, corners, 3, &circle, 0, &homothet);
    CHECK(status == PIXGEO_STATUS_OK && fabs(homothet.scale - 2.5) < 1e-9 &&
              fabs(homothet.centre[0] - 2) < 1e-9 && fabs(homothet.centre[1] - 1.5) < 1e-9,
          "enclose %g: %s", homothet.scale, pixgeo_context_last_error(ctx));
    const double box[8] = {0, 0, 4, 0, 4, 3, 0, 3};
    const size_t box_size = 4;
    status = pixgeo_empty(ctx, corners, 3, box, &box_size, 1, false, &circle, &homothet);
    CHECK(status == PIXGEO_STATUS_OK && fabs(homothet.scale - 3.125) < 1e-9 &&
              fabs(homothet.centre[0] - 3.125) < 1e-9 && fabs(homothet.centre[1] - 3) < 1e-9,
          "empty %g: %s", homothet.scale, pixgeo_context_last_error(ctx));
    status = pixgeo_enclose(ctx, corners, 3, &circle, 4, &homothet);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "k beyond the sites accepted");

    /* The Delaunay triangulation of a square's corners, its centre and a
     * repeated corner: four triangles around the centre. */
    const double square[12] = {0, 0, 2, 0, 2, 2, 0, 2, 1, 1, 2, 2};
    uint32_t mesh[36];
    size_t triangle_count = 0, duplicate_count = 0;
    status = pixgeo_delaunay(ctx, square, 6, 0, mesh, 2, &triangle_count, &duplicate_count);
    CHECK(status == PIXGEO_STATUS_BUFFER_TOO_SMALL && triangle_count == 4,
          "delaunay into room for 2 of 4 triangles: %s", pixgeo_status_string(status));
    status = pixgeo_delaunay(ctx, square, 6, 0, mesh, 12, &triangle_count, &duplicate_count);
    CHECK(status == PIXGEO_STATUS_OK && triangle_count == 4 && duplicate_count == 1,
          "delaunay: %zu triangles, %zu repeats: %s", triangle_count, duplicate_count,
          pixgeo_context_last_error(ctx));
    for (size_t t = 0; t < triangle_count; t++) {
        const uint32_t *v = &mesh[3 * t];
        double ax = square[2 * v[0]], ay = square[2 * v[0] + 1];
        double cross = (square[2 * v[1]] - ax) * (square[2 * v[2] + 1] - ay) -
                       (square[2 * v[1] + 1] - ay) * (square[2 * v[2]] - ax);
        CHECK(cross > 0 && (v[0] == 4 || v[1] == 4 || v[2] == 4), "triangle %zu", t);
    }
    const double line[6] = {0, 0, 1, 1, 2, 2};
    status = pixgeo_delaunay(ctx, line, 3, 0, mesh, 12, &triangle_count, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "collinear points accepted");

    /* The settle point: the potential area of the best pixel against its
     * definition, the pixels nearer to it than to every site. */
    options = pixgeo_voronoi_options_default(W, H);
    uint32_t *area = malloc(sizeof(uint32_t) * W * H);
    PixgeoSettle settle;
    status = pixgeo_settle(ctx, xy, N, NULL, 0, &options, PIXGEO_SETTLE_METHOD_SPANS, area, &settle);
    CHECK(status == PIXGEO_STATUS_OK, "settle: %s", pixgeo_context_last_error(ctx));
    uint32_t largest = 0;
    for (int k = 0; k < W * H; k++) largest = area[k] > largest ? area[k] : largest;
    CHECK(settle.area == largest && area[settle.pixel_y * W + settle.pixel_x] == largest,
          "settle area %u, map maximum %u", settle.area, largest);
    uint32_t won = 0;
    for (int j = 0; j < H; j++) {
        for (int i = 0; i < W; i++) {
            double nearest = INFINITY;
            for (int s = 0; s < N; s++) {
                double dx = xy[2 * s] - i, dy = xy[2 * s + 1] - j;
                nearest = fmin(nearest, dx * dx + dy * dy);
            }
            double tx = (double)settle.pixel_x - i, ty = (double)settle.pixel_y - j;
            won += tx * tx + ty * ty < nearest;
        }
    }
    CHECK(won == settle.area, "settle pixel wins %u pixels, pixgeo says %u", won, settle.area);
    CHECK(settle.refined_area > 0.5 * settle.area && settle.refined_area < 2.0 * settle.area,
          "refined area %g", settle.refined_area);
    PixgeoSettle faithful;
    status = pixgeo_settle(ctx, xy, N, NULL, 0, &options, PIXGEO_SETTLE_METHOD_FAITHFUL, NULL,
                           &faithful);
    CHECK(status == PIXGEO_STATUS_OK && faithful.area == settle.area &&
              faithful.pixel_x == settle.pixel_x && faithful.pixel_y == settle.pixel_y,
          "faithful settle point");
    status = pixgeo_settle(ctx, xy, N, NULL, 1, &options, PIXGEO_SETTLE_METHOD_SPANS, NULL, &settle);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "null own stores accepted");
    free(area);

    /* One of Lloyd's iterations against its definition: every site moves to
     * the mean of the pixel centres nearest to it (ties to the lower index),
     * Σi / count rounded once, bit for bit. */
    double moved[2 * N];
    memcpy(moved, xy, sizeof moved);
    PixgeoLloyd lloyd;
    options = pixgeo_voronoi_options_default(W, H);
    CHECK(pixgeo_lloyd(ctx, moved, N, &options, 1, NAN, NULL, NULL, &lloyd) ==
              PIXGEO_STATUS_INVALID_ARGUMENT,
          "lloyd took a NaN tolerance");
    status = pixgeo_lloyd(ctx, moved, N, &options, 1, 0.0, NULL, NULL, &lloyd);
    CHECK(status == PIXGEO_STATUS_OK && lloyd.iterations == 1, "lloyd: %s",
          pixgeo_context_last_error(ctx));
    for (int s = 0; s < N; s++) {
        uint64_t count = 0, sx = 0, sy = 0;
        for (int j = 0; j < H; j++) {
            for (int i = 0; i < W; i++) {
                int best = 0;
                double nearest = INFINITY;
                for (int t = 0; t < N; t++) {
                    double dx = xy[2 * t] - i, dy = xy[2 * t + 1] - j;
                    if (dx * dx + dy * dy < nearest) nearest = dx * dx + dy * dy, best = t;
                }
                if (best == s) count++, sx += i, sy += j;
            }
        }
        double want_x = count ? (double)sx / count : xy[2 * s];
        double want_y = count ? (double)sy / count : xy[2 * s + 1];
        CHECK(moved[2 * s] == want_x && moved[2 * s + 1] == want_y,
              "lloyd site %d at (%.17g, %.17g), its centroid (%.17g, %.17g)", s, moved[2 * s],
              moved[2 * s + 1], want_x, want_y);
    }

    /* Natural-neighbour and linear interpolation reproduce a plane exactly
     * (each value the double nearest the exact one, here a whole number);
     * with the frame's corners among the samples every pixel has a value. */
    double samples[2 * (N + 4)], heights[N + 4];
    memcpy(samples, xy, sizeof(double) * 2 * N);
    const double frame_corners[8] = {0, 0, W - 1, 0, 0, H - 1, W - 1, H - 1};
    memcpy(samples + 2 * N, frame_corners, sizeof frame_corners);
    for (int s = 0; s < N + 4; s++) heights[s] = 2.0 * samples[2 * s] + 3.0 * samples[2 * s + 1] + 1.0;
    double *surface = malloc(sizeof(double) * W * H);
    for (uint32_t method = PIXGEO_INTERPOLATION_EXACT; method <= PIXGEO_INTERPOLATION_LINEAR;
         method += PIXGEO_INTERPOLATION_LINEAR) {
        uint64_t exactly = 0;
        status = pixgeo_interpolate(ctx, samples, heights, N + 4, &options, method, surface, &exactly);
        CHECK(status == PIXGEO_STATUS_OK, "interpolate: %s", pixgeo_context_last_error(ctx));
        for (int k = 0; k < W * H; k++)
            CHECK(surface[k] == 2.0 * (k % W) + 3.0 * (k / W) + 1.0, "interpolated plane at pixel %d: %g",
                  k, surface[k]);
    }
    status = pixgeo_interpolate(ctx, samples, heights, N + 4, &options, 7, surface, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "interpolation method 7 accepted");
    free(surface);

    /* A power diagram: three heavy sites hide a light one inside their
     * triangle; every label has the least power |p - s|^2 - w (whole numbers
     * here, so doubles compare them exactly), ties to the lower index. */
    const double heavy_xy[8] = {4, 4, 60, 4, 32, 44, 32, 17};
    const double heavy_w[4] = {1600, 1600, 1600, 0};
    uint32_t *power_labels = malloc(sizeof(uint32_t) * W * H);
    double *powers = malloc(sizeof(double) * W * H);
    uint8_t hidden[4];
    status = pixgeo_power_diagram(ctx, heavy_xy, heavy_w, 4, &options, power_labels, powers, hidden);
    CHECK(status == PIXGEO_STATUS_OK, "power diagram: %s", pixgeo_context_last_error(ctx));
    CHECK(hidden[0] == 0 && hidden[1] == 0 && hidden[2] == 0 && hidden[3] == 1, "hidden sites");
    for (int k = 0; k < W * H; k++) {
        int best = 0;
        double least = INFINITY;
        for (int t = 0; t < 4; t++) {
            double dx = heavy_xy[2 * t] - k % W, dy = heavy_xy[2 * t + 1] - k / W;
            double power = dx * dx + dy * dy - heavy_w[t];
            if (power < least) least = power, best = t;
        }
        CHECK(power_labels[k] == (uint32_t)best && powers[k] == least, "power at pixel %d", k);
    }
    uint32_t regular[3 * 4];
    size_t regular_count = 0;
    status = pixgeo_regular_triangulation(ctx, heavy_xy, heavy_w, 4, regular, 4, &regular_count, NULL);
    CHECK(status == PIXGEO_STATUS_OK && regular_count == 1, "regular triangulation: %zu triangles",
          regular_count);
    free(power_labels);
    free(powers);

    /* Weighted points, a segment, a circle and an arc (thesis §3.8-3.9): every
     * pixel's label has the smallest weighted distance; fans stay within their
     * bound of it. */
    const PixgeoSite shapes[4] = {
        {PIXGEO_SITE_KIND_POINT, {10, 10, 0, 0, 0}, 2.0, 0.0},
        {PIXGEO_SITE_KIND_SEGMENT, {40, 5, 60, 5, 0}, 1.0, 0.0},
        {PIXGEO_SITE_KIND_CIRCLE, {20, 36, 6, 0, 0}, 1.0, 1.0},
        {PIXGEO_SITE_KIND_ARC, {50, 36, 8, 0, 3.14159265}, 1.0, -1.0},
    };
    for (int fan = 0; fan < 2; fan++) {
        options = pixgeo_voronoi_options_default(W, H);
        options.accuracy = fan ? PIXGEO_ACCURACY_FAN : PIXGEO_ACCURACY_EXACT;
        status = pixgeo_voronoi_sites(ctx, shapes, 4, &options, labels, distances);
        CHECK(status == PIXGEO_STATUS_OK, "voronoi_sites: %s", pixgeo_context_last_error(ctx));
        int off = 0;
        for (int j = 0; j < H; j++) {
            for (int i = 0; i < W; i++) {
                double d[4];
                /* Distances to each shape, weighted. */
                d[0] = hypot(i - 10.0, j - 10.0) / 2.0;
                double t = fmin(fmax((i - 40.0) / 20.0, 0.0), 1.0);
                d[1] = hypot(i - (40.0 + 20.0 * t), j - 5.0);
                d[2] = fabs(hypot(i - 20.0, j - 36.0) - 6.0) + 1.0;
                double a = atan2(j - 36.0, i - 50.0);
                d[3] = (a >= 0.0 && a <= 3.14159265)
                           ? fabs(hypot(i - 50.0, j - 36.0) - 8.0)
                           : fmin(hypot(i - 58.0, j - 36.0), hypot(i - 42.0, j - 36.0));
                d[3] -= 1.0;
                double best = fmin(fmin(d[0], d[1]), fmin(d[2], d[3]));
                uint32_t label = labels[j * W + i];
                double slack = fan ? 2.05 : 1e-3;
                if (label >= 4 || d[label] > best + slack ||
                    fabs(distances[j * W + i] - best) > slack / 2.0 + 1e-3)
                    off++;
            }
        }
        CHECK(off == 0, "%d pixels of the site diagram (fan %d) differ from the definition", off, fan);
    }
    PixgeoSite bad_weight = shapes[0];
    bad_weight.multiplicative = 0.0;
    status = pixgeo_voronoi_sites(ctx, &bad_weight, 1, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "zero weight accepted");
    PixgeoSite bad_kind = shapes[0];
    bad_kind.kind = 9;
    status = pixgeo_voronoi_sites(ctx, &bad_kind, 1, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "site kind 9 accepted");

    /* Enumerations are integers: values outside them are refused, never read. */
    PixgeoVoronoiOptions odd = pixgeo_voronoi_options_default(W, H);
    odd.metric = 77;
    CHECK(pixgeo_voronoi(ctx, xy, N, &odd, labels, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT,
          "metric 77 accepted");
    odd = pixgeo_voronoi_options_default(W, H);
    odd.accuracy = 77;
    CHECK(pixgeo_voronoi(ctx, xy, N, &odd, labels, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT,
          "accuracy 77 accepted");
    odd = pixgeo_voronoi_options_default(W, H);
    odd.speedup = (uint32_t)-3;
    CHECK(pixgeo_voronoi(ctx, xy, N, &odd, labels, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT,
          "speedup -3 accepted");
    CHECK(strstr(pixgeo_context_last_error(ctx), "PixgeoSpeedup") != NULL, "message: %s",
          pixgeo_context_last_error(ctx));
    odd = pixgeo_voronoi_options_default(W, H);
    odd.method = 9;
    CHECK(pixgeo_voronoi(ctx, xy, N, &odd, labels, NULL) == PIXGEO_STATUS_INVALID_ARGUMENT,
          "method 9 accepted");
    odd = pixgeo_voronoi_options_default(W, H);
    CHECK(pixgeo_settle(ctx, xy, N, NULL, 0, &odd, 5, NULL, &settle) ==
              PIXGEO_STATUS_INVALID_ARGUMENT,
          "settle method 5 accepted");
    PixgeoContextOptions odd_device = pixgeo_context_options_default();
    odd_device.device = 42;
    PixgeoContext *no_ctx = NULL;
    CHECK(pixgeo_context_create(&odd_device, &no_ctx) == PIXGEO_STATUS_INVALID_ARGUMENT &&
              no_ctx == NULL,
          "device 42 accepted");
    /* Devices are named as PIXGEO_DEVICE and the command line's --device name them. */
    PixgeoContextOptions named = pixgeo_context_options_default();
    named.validation = context_options.validation;
    named.device_name = "lavapipe";
    PixgeoContext *soft = NULL;
    CHECK(pixgeo_context_create(&named, &soft) == PIXGEO_STATUS_OK &&
              strstr(pixgeo_context_device_name(soft), "llvmpipe") != NULL,
          "device_name lavapipe: %s", pixgeo_create_error());
    pixgeo_context_destroy(soft);
    /* `cpu` needs no Vulkan: what has a CPU algorithm answers as the device
     * does, bit for bit; what is only drawn says so. */
    named.device_name = "cpu";
    CHECK(pixgeo_context_create(&named, &soft) == PIXGEO_STATUS_OK &&
              strcmp(pixgeo_context_device_name(soft), "cpu") == 0,
          "device_name cpu: %s", pixgeo_create_error());
    uint32_t *on_cpu = malloc(sizeof(uint32_t) * W * H);
    float *on_cpu_d = malloc(sizeof(float) * W * H);
    options = pixgeo_voronoi_options_default(W, H);
    CHECK(pixgeo_voronoi(ctx, xy, N, &options, labels, distances) == PIXGEO_STATUS_OK &&
              pixgeo_voronoi(soft, xy, N, &options, on_cpu, on_cpu_d) == PIXGEO_STATUS_OK,
          "voronoi on cpu: %s", pixgeo_context_last_error(soft));
    CHECK(memcmp(labels, on_cpu, sizeof(uint32_t) * W * H) == 0 &&
              memcmp(distances, on_cpu_d, sizeof(float) * W * H) == 0,
          "the CPU's diagram differs from the device's");
    CHECK(pixgeo_furthest(ctx, xy, N, &options, labels, distances) == PIXGEO_STATUS_OK &&
              pixgeo_furthest(soft, xy, N, &options, on_cpu, on_cpu_d) == PIXGEO_STATUS_OK,
          "furthest on cpu: %s", pixgeo_context_last_error(soft));
    CHECK(memcmp(labels, on_cpu, sizeof(uint32_t) * W * H) == 0 &&
              memcmp(distances, on_cpu_d, sizeof(float) * W * H) == 0,
          "the CPU's furthest sites differ from the device's");
    uint32_t dev_mesh[3 * 2 * N], cpu_mesh[3 * 2 * N];
    size_t triangles = 0, cpu_triangles = 0;
    CHECK(pixgeo_delaunay(ctx, xy, N, 0, dev_mesh, 2 * N, &triangles, NULL) == PIXGEO_STATUS_OK &&
              pixgeo_delaunay(soft, xy, N, 0, cpu_mesh, 2 * N, &cpu_triangles, NULL) ==
                  PIXGEO_STATUS_OK,
          "delaunay on cpu: %s", pixgeo_context_last_error(soft));
    CHECK(triangles == cpu_triangles &&
              memcmp(dev_mesh, cpu_mesh, sizeof(uint32_t) * 3 * triangles) == 0,
          "the CPU's triangulation differs from the device's");
    PixgeoPair there, back, cpu_there, cpu_back;
    CHECK(pixgeo_hausdorff(ctx, xy, 4, xy + 8, N - 4, &there, &back) == PIXGEO_STATUS_OK &&
              pixgeo_hausdorff(soft, xy, 4, xy + 8, N - 4, &cpu_there, &cpu_back) ==
                  PIXGEO_STATUS_OK &&
              memcmp(&there, &cpu_there, sizeof there) == 0 &&
              memcmp(&back, &cpu_back, sizeof back) == 0,
          "hausdorff on cpu: %s", pixgeo_context_last_error(soft));
    CHECK(pixgeo_flood(soft, xy, N - 1, &options, 0, on_cpu) == PIXGEO_STATUS_NO_DEVICE &&
              strstr(pixgeo_context_last_error(soft), "flooding") != NULL,
          "flooding without a device: %s", pixgeo_context_last_error(soft));
    pixgeo_context_destroy(soft);
    free(on_cpu_d);
    free(on_cpu);

    /* Errors come back as status codes with a message. */
    status = pixgeo_voronoi(ctx, NULL, N, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "null sites accepted");
    const double bad[2] = {1.0, NAN};
    options = pixgeo_voronoi_options_default(W, H);
    status = pixgeo_voronoi(ctx, bad, 1, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "NaN accepted");
    CHECK(strstr(pixgeo_context_last_error(ctx), "non-finite") != NULL, "message: %s",
          pixgeo_context_last_error(ctx));
    status = pixgeo_voronoi(ctx, xy, 0, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_INVALID_ARGUMENT, "empty site list accepted");
    options = pixgeo_voronoi_options_default(1u << 25, 1);
    status = pixgeo_voronoi(ctx, xy, N, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_TOO_LARGE, "oversized picture accepted");
    options = pixgeo_voronoi_options_default(W, H);
    status = pixgeo_voronoi(ctx, xy, N, &options, labels, NULL);
    CHECK(status == PIXGEO_STATUS_OK && pixgeo_context_last_error(ctx)[0] == '\0',
          "a good call after errors");

    free(knn_d);
    free(knn);
    free(tiled);
    free(distances);
    free(labels);
    pixgeo_context_destroy(ctx);
    pixgeo_context_destroy(NULL);

    if (failures == 0) printf("all checks passed\n");
    return failures == 0 ? 0 : 1;
}
