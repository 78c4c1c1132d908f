// Distance functions (src/geometry/metric.rs): kind 0 Euclidean, 1 L1,
// 2 L-infinity, 3 L_p with exponent p, 4 L_p with 2p a whole number (keys that
// are sums of powers, for exact point cones: DepthKey).

// Shaders built once per kind (variants METRIC_L2 METRIC_L1 METRIC_LINF
// METRIC_LP) have the kind as the constant METRIC_KIND; the others read it from
// their push constants. With the kind read at run time, exact Euclidean cones
// took about 3 times as long on lavapipe (measured): the L_p powers cost them
// too, as lavapipe runs every branch a fragment could take.
#if defined(METRIC_L2)
#define METRIC_KIND 0u
#elif defined(METRIC_L1)
#define METRIC_KIND 1u
#elif defined(METRIC_LINF)
#define METRIC_KIND 2u
#elif defined(METRIC_LP)
#define METRIC_KIND 3u
#elif defined(METRIC_LP_SUM)
#define METRIC_KIND 4u
#endif

// The metric's key of offset d: a monotone function of its distance (the squared
// distance for the Euclidean norm, the sum of the coordinates' p-th powers for
// kind 4, the distance itself otherwise). Keys of integer offsets are exact for
// kinds 0 to 2, and for kind 4 with integer p while below 2^24.
float metric_key_of(vec2 d, uint kind, float p) {
    vec2 a = abs(d);
    if (kind == 0u) {
        return dot(d, d);
    } else if (kind == 1u) {
        return a.x + a.y;
    } else if (kind == 2u) {
        return max(a.x, a.y);
    } else if (kind == 4u) {
        // |x|^p = |x|^(k / 2) for k = 2p: products, and a square root for odd k.
        int k = int(2.0 * p + 0.5);
        vec2 power = (k & 1) != 0 ? sqrt(a) : vec2(1.0);
        for (int i = 0; i < k / 2; i++) {
            power *= a;
        }
        return power.x + power.y;
    }
    // L_p: the distance itself, scaled by the larger coordinate so that large p
    // neither overflows nor underflows float32. The larger term is 1.
    float m = max(a.x, a.y);
    if (m == 0.0) {
        return 0.0;
    }
    return m * pow(1.0 + pow(min(a.x, a.y) / m, p), 1.0 / p);
}

// The distance of a key.
float metric_distance_of_key(float key, uint kind, float p) {
    if (kind == 0u) {
        return sqrt(key);
    } else if (kind == 4u) {
        return pow(key, 1.0 / p);
    }
    return key;
}
