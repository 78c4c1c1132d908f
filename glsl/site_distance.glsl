// The distance from a pixel to a site of any shape (src/geometry/site.rs), for
// the build's shape (POINT, SEGMENT, CIRCLE or ARC) and metric:
//   point    shape0.xy
//   segment  shape0.xy to shape0.zw
//   circle   centre shape0.xy, radius shape0.z
//   arc      centre shape0.xy, radius shape0.z, counter-clockwise over
//            shape0.w radians from direction shape1.xy to direction shape1.zw
//            (unit vectors of its ends' angles)
// Included by site_exact.frag (one site per rectangle) and site_batch.frag
// (eight).

const float TAU = 6.28318530718;

float norm(vec2 v) {
    return metric_distance_of_key(metric_key(v), METRIC_KIND, picture.metric_p);
}

// The smallest norm on the segment of offsets a + t (b - a), t in [0, 1]: closed
// form for L2; otherwise the ends and the zeros of each coordinate (the minimum
// for L1, and for p < 1, where each |coordinate|^p is concave between its zeros),
// the diagonals for L-infinity, and golden-section search for the other convex
// L_p (src/geometry/chain.rs).
float segment_norm(vec2 a, vec2 b) {
    vec2 e = b - a;
    float ee = dot(e, e);
    if (METRIC_KIND == 0u) {
        float t = ee > 0.0 ? clamp(-dot(a, e) / ee, 0.0, 1.0) : 0.0;
        return length(a + t * e);
    }
    float best = min(norm(a), norm(b));
    for (int axis = 0; axis < 2; axis++) {
        if (e[axis] != 0.0) {
            float t = -a[axis] / e[axis];
            if (t > 0.0 && t < 1.0) {
                best = min(best, norm(a + t * e));
            }
        }
    }
    // L-infinity is linear between the zeros and the diagonals |x| = |y|.
    if (METRIC_KIND == 2u) {
        for (int sign = -1; sign <= 1; sign += 2) {
            float den = e.x - float(sign) * e.y;
            if (den != 0.0) {
                float t = (float(sign) * a.y - a.x) / den;
                if (t > 0.0 && t < 1.0) {
                    best = min(best, norm(a + t * e));
                }
            }
        }
    }
    // L1 and L-infinity are piecewise linear: their candidates are exact.
    bool search = METRIC_KIND == 3u && picture.metric_p >= 1.0;
    if (search && ee > 0.0) {
        float lo = 0.0;
        float hi = 1.0;
        const float g = 0.61803398875;
        for (int i = 0; i < 40; i++) {
            float m1 = hi - g * (hi - lo);
            float m2 = lo + g * (hi - lo);
            if (norm(a + m1 * e) <= norm(a + m2 * e)) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        best = min(best, norm(a + 0.5 * (lo + hi) * e));
    }
    return best;
}

// Whether the direction v from the centre lies on the arc from direction u0
// counter-clockwise over span radians to direction u1 (a whole circle from
// 2π on): by the side of each end's direction that v lies on, no angles.
bool on_arc(vec2 v, vec2 u0, vec2 u1, float span) {
    if (span >= TAU) {
        return true;
    }
    bool after_start = u0.x * v.y - u0.y * v.x >= 0.0;
    bool before_end = v.x * u1.y - v.y * u1.x >= 0.0;
    return span <= 3.14159265 ? after_start && before_end : after_start || before_end;
}

// The metric distance from p to the arc of the circle around c of radius r from
// angle a0 (direction u0) over span (radians, to direction u1): under L1 and
// L-infinity the smallest over a few candidates, otherwise samples at equal
// angles, the best brackets refined by golden-section search
// (src/geometry/site.rs, curve_distance). The candidates are found without
// angles: float32 trigonometry (asin near ±1 above all) moved them by up to
// a hundredth of a pixel.
float curve_distance(vec2 p, vec2 c, float r, float a0, float span, vec2 u0, vec2 u1) {
    float best = 3.0e38;
    vec2 offset = p - c;
    // Cusps where the offset lies along a kink ray of the ball: the axes for L1
    // and p < 1, the diagonals for L-infinity (src/geometry/site.rs). The
    // points p + t v on the circle solve |offset + t v|² = r², stably.
    bool axes = METRIC_KIND == 1u || (METRIC_KIND == 3u && picture.metric_p < 1.0);
    if (axes || METRIC_KIND == 2u) {
        for (int ray = 0; ray < 2; ray++) {
            vec2 v = axes ? (ray == 0 ? vec2(1.0, 0.0) : vec2(0.0, 1.0))
                          : (ray == 0 ? vec2(1.0, 1.0) : vec2(1.0, -1.0));
            float a = dot(v, v);
            float b = dot(offset, v);
            float k = (length(offset) - r) * (length(offset) + r);
            float disc = b * b - a * k;
            if (disc >= 0.0) {
                float q = -(b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
                float roots[2] = float[2](q / a, q != 0.0 ? k / q : 0.0);
                for (int i = 0; i < 2; i++) {
                    vec2 w = offset + roots[i] * v;
                    if (on_arc(w, u0, u1, span)) {
                        best = min(best, norm(roots[i] * v));
                    }
                }
            }
        }
    }
    // L1 and L-infinity balls are piecewise linear: the smallest distance is at
    // an end, a cusp, or where a side of the ball touches the circle, whose
    // normal there is the side's (src/geometry/site.rs).
    if (METRIC_KIND == 1u || METRIC_KIND == 2u) {
        vec2 normal = METRIC_KIND == 1u ? vec2(0.70710678) : vec2(1.0, 0.0);
        for (int k = 0; k < 4; k++) {
            if (on_arc(normal, u0, u1, span)) {
                best = min(best, norm(offset - r * normal));
            }
            normal = vec2(-normal.y, normal.x);
        }
        if (span < TAU) {
            best = min(best, norm(offset - r * u0));
            best = min(best, norm(offset - r * u1));
        }
        return best;
    }
    const int SAMPLES = 32;
    const int REFINEMENTS = 24;
    int n = max(2, int(ceil(float(SAMPLES) * span / TAU)));
    float step = span / float(n);
    // The two (convex metrics) or four (star-shaped balls) best samples.
    int brackets = (METRIC_KIND == 3u && picture.metric_p < 1.0) ? 4 : 2;
    float best_d[4] = float[4](3.0e38, 3.0e38, 3.0e38, 3.0e38);
    int best_k[4] = int[4](0, 0, 0, 0);
    for (int k = 0; k <= n; k++) {
        float a = a0 + step * float(k);
        float d = norm(p - c - r * vec2(cos(a), sin(a)));
        for (int b = 0; b < 4; b++) {
            if (d < best_d[b]) {
                for (int m = 3; m > b; m--) {
                    best_d[m] = best_d[m - 1];
                    best_k[m] = best_k[m - 1];
                }
                best_d[b] = d;
                best_k[b] = k;
                break;
            }
        }
    }
    best = min(best, best_d[0]);
    const float g = 0.61803398875;
    for (int b = 0; b < brackets; b++) {
        float lo = a0 + step * float(max(best_k[b] - 1, 0));
        float hi = a0 + step * float(min(best_k[b] + 1, n));
        for (int i = 0; i < REFINEMENTS; i++) {
            float m1 = hi - g * (hi - lo);
            float m2 = lo + g * (hi - lo);
            float d1 = norm(p - c - r * vec2(cos(m1), sin(m1)));
            float d2 = norm(p - c - r * vec2(cos(m2), sin(m2)));
            if (d1 <= d2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        float a = 0.5 * (lo + hi);
        best = min(best, norm(p - c - r * vec2(cos(a), sin(a))));
    }
    return best;
}

// The unweighted distance from pixel p to the site.
float site_distance(vec2 p, vec4 shape0, vec4 shape1) {
#if defined(POINT)
    return norm(p - shape0.xy);
#elif defined(SEGMENT)
    return segment_norm(shape0.xy - p, shape0.zw - p);
#elif defined(CIRCLE)
    if (METRIC_KIND != 0u) {
        return shape0.z == 0.0
            ? norm(p - shape0.xy)
            : curve_distance(p, shape0.xy, shape0.z, shape1.x, TAU, vec2(1.0, 0.0), vec2(1.0, 0.0));
    }
    return abs(length(p - shape0.xy) - shape0.z);
#else
    float d;
    float span = shape0.w;
    if (METRIC_KIND != 0u) {
        float start = atan(shape1.y, shape1.x);
        d = shape0.z == 0.0
            ? norm(p - shape0.xy)
            : curve_distance(p, shape0.xy, shape0.z, start, min(span, TAU), shape1.xy, shape1.zw);
    } else {
        vec2 v = p - shape0.xy;
        float r = shape0.z;
        d = abs(length(v) - r);
        // Outside the arc's wedge the nearest point is an end. The wedge is
        // told by the side of each end's direction that v lies on (no angles
        // per fragment): both sides for a span up to a half turn, either
        // beyond.
        vec2 u0 = shape1.xy;
        vec2 u1 = shape1.zw;
        bool after_start = u0.x * v.y - u0.y * v.x >= 0.0;
        bool before_end = v.x * u1.y - v.y * u1.x >= 0.0;
        bool inside = span <= 3.14159265 ? after_start && before_end : after_start || before_end;
        if (span < TAU && dot(v, v) > 0.0 && !inside) {
            d = min(length(v - r * u0), length(v - r * u1));
        }
    }
    return d;
#endif
}
