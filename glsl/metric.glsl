// Distance functions (src/geometry/metric.rs): kind 0 Euclidean, 1 L1,
// 2 L-infinity, 3 L_p with exponent p.

// The metric's key of offset d: a monotone function of its distance (the squared
// distance for the Euclidean norm, the sum of p-th powers for L_p). Keys of
// integer offsets are exact for kinds 0 to 2.
float metric_key_of(vec2 d, uint kind, float p) {
    vec2 a = abs(d);
    if (kind == 0u) {
        return dot(d, d);
    } else if (kind == 1u) {
        return a.x + a.y;
    } else if (kind == 2u) {
        return max(a.x, a.y);
    }
    return pow(a.x, p) + pow(a.y, p);
}

// The distance of a key.
float metric_distance_of_key(float key, uint kind, float p) {
    if (kind == 0u) {
        return sqrt(key);
    } else if (kind == 3u) {
        return pow(key, 1.0 / p);
    }
    return key;
}
