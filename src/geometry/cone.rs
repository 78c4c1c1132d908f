//! Cones as triangle fans and the thesis's error analysis (§3.3, §3.4).
//!
//! A fan of T triangles has its rim vertices on the true cone, at radius `r` and
//! height `r`; between two vertices it lies above the cone by at most the factor
//! `1 / cos(pi / T)`. Its inscribed circle has radius `r cos(pi / T)`.

use std::f64::consts::PI;

/// Triangles for an ε distance diagram with a fan of outer radius `radius`
/// (thesis eq. 3.1): the smallest T with `cos(pi / T) >= (r - ε) / r`.
/// For a picture-wide cone (`r = p sqrt 2`) at ε = 1: 85 for p = 1024, 84 for 1000.
pub(crate) fn triangles_for_distance_error(radius: f64, epsilon: f64) -> u32 {
    if epsilon >= radius {
        return 3;
    }
    let t = (PI / ((radius - epsilon) / radius).acos()).ceil();
    (t as u32).max(3)
}

/// The most triangles a fan may have. Past it a fan resolves nothing a
/// picture shows (at radius 1000 its error is below a millionth of a pixel),
/// and one such fan per site would exhaust memory.
pub const MAX_FAN_TRIANGLES: u32 = 1 << 16;

/// The smallest distance error a fan may be asked for, in pixels: below the
/// rasterizer's subpixel grid (1/256 pixel) a finer fan changes no pixel.
pub(crate) const MIN_FAN_EPSILON: f64 = 1e-3;

/// Refuses a fan of error `epsilon` that would need more than
/// [`MAX_FAN_TRIANGLES`] at `radius`.
pub(crate) fn check_fan_size(radius: f64, epsilon: f64) -> crate::Result<()> {
    let needed = if epsilon >= radius {
        3.0
    } else {
        (PI / ((radius - epsilon) / radius).acos()).ceil()
    };
    if needed > MAX_FAN_TRIANGLES as f64 {
        return Err(crate::Error::out_of_range(format!(
            "a fan within {epsilon} pixels at radius {radius:.1} needs {needed:.0} triangles, more \
             than {MAX_FAN_TRIANGLES}: give a larger epsilon, or use exact mode"
        )));
    }
    Ok(())
}

/// The worst distance overestimate of a fan with `triangles` whose inscribed circle
/// has radius `radius`: `radius (1 / cos(pi / T) - 1)`.
pub(crate) fn fan_distance_error(radius: f64, triangles: u32) -> f64 {
    radius * (1.0 / (PI / triangles as f64).cos() - 1.0)
}

/// The worst displacement of a bisector caused by fan cones of `triangles`
/// (thesis §3.4, Fig. 3.7): one cone exact, the other too steep by
/// `k = 1 / cos(pi / T)`. A pixel at distance `distance` from the nearer site, for
/// two sites `separation` apart, can land on the wrong side of their bisector by
/// at most `(k^2 - 1) distance^2 / (2 separation) = tan^2(pi / T) distance^2 / (2 a)`.
pub fn bisector_deviation(triangles: u32, distance: f64, separation: f64) -> f64 {
    let t = (PI / triangles as f64).tan();
    t * t * distance * distance / (2.0 * separation)
}

/// Triangles for a *site diagram* of a `side` x `side` picture whose bisectors
/// deviate by at most `deviation` pixels: the thesis's worst case of two sites at
/// (1, 0) and (0, 1), whose bisector runs to the opposite corner (distance
/// `side sqrt 2`). 2642 for a 1000² picture at one pixel.
#[cfg(test)]
pub(crate) fn triangles_for_site_diagram(side: f64, deviation: f64) -> u32 {
    let separation = 2f64.sqrt();
    let distance = side * 2f64.sqrt();
    // tan^2(pi/T) d^2 / (2a) <= dev  <=>  pi / T <= atan(sqrt(2 a dev) / d)
    let t = PI / ((2.0 * separation * deviation).sqrt() / distance).atan();
    let mut t = t.ceil() as u32;
    // Guard against rounding at the boundary.
    while t > 3 && bisector_deviation(t - 1, distance, separation) <= deviation {
        t -= 1;
    }
    t.max(3)
}

/// A cone to draw: enough triangles for the requested accuracy and an outer radius
/// whose inscribed circle covers `radius`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FanShape {
    pub triangles: u32,
    /// Radius of the rim vertices.
    pub outer_radius: f64,
}

impl FanShape {
    /// The fan for an ε distance diagram that covers every point within `radius`:
    /// outer radius `radius + ε`, T from eq. 3.1, so the inscribed circle has radius
    /// at least `radius` and the overestimate within `radius` is at most ε.
    pub(crate) fn for_distance_error(radius: f64, epsilon: f64) -> Self {
        let outer = radius + epsilon;
        Self {
            triangles: triangles_for_distance_error(outer, epsilon),
            outer_radius: outer,
        }
    }

    /// A fan of exactly `triangles` whose inscribed circle has radius `radius`.
    pub(crate) fn with_triangles(radius: f64, triangles: u32) -> Self {
        let triangles = triangles.max(3);
        Self {
            triangles,
            outer_radius: radius / (PI / triangles as f64).cos(),
        }
    }
}

/// The unit fan of `triangles`: the apex (0, 0, 0), then `triangles + 1` rim
/// vertices (cos, sin, 1), the last closing the fan.
#[expect(clippy::disallowed_methods, reason = "one cone's fan")]
pub(crate) fn unit_fan(triangles: u32) -> Vec<[f32; 3]> {
    let mut v = Vec::with_capacity(triangles as usize + 2);
    v.push([0.0, 0.0, 0.0]);
    for k in 0..=triangles {
        let a = 2.0 * PI * (k % triangles) as f64 / triangles as f64;
        v.push([a.cos() as f32, a.sin() as f32, 1.0]);
    }
    v
}

/// A regular polygon of `corners` with circumradius 1, as a fan from its first
/// corner (`corners - 2` triangles): the footprint of an exact cone, whose depth
/// comes from the fragment shader rather than from the vertices.
#[expect(clippy::disallowed_methods, reason = "one fan's rim")]
pub(crate) fn unit_footprint(corners: u32) -> Vec<[f32; 3]> {
    (0..corners)
        .map(|k| {
            // Start at 45° so a square is axis-aligned.
            let a = 2.0 * PI * k as f64 / corners as f64 + PI / 4.0;
            [a.cos() as f32, a.sin() as f32, 0.0]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_distance_diagram_triangle_counts() {
        // §3.3: "assuming a picture size of 1024×1024 pixels, 85 triangles"; §3.6
        // gives 84 for 1000² with ε = 1.
        assert_eq!(triangles_for_distance_error(1024.0 * 2f64.sqrt(), 1.0), 85);
        assert_eq!(triangles_for_distance_error(1000.0 * 2f64.sqrt(), 1.0), 84);
    }

    #[test]
    fn thesis_site_diagram_triangle_count() {
        // §3.4: "a maximal deviation of at most 1 pixel ... 1000×1000 ... 2642".
        assert_eq!(triangles_for_site_diagram(1000.0, 1.0), 2642);
    }

    #[test]
    fn fan_covers_its_radius_within_epsilon() {
        for r in [1.0, 7.5, 40.0, 1448.0] {
            let f = FanShape::for_distance_error(r, 1.0);
            let inscribed = f.outer_radius * (PI / f.triangles as f64).cos();
            assert!(inscribed >= r, "{f:?} does not cover {r}");
            assert!(fan_distance_error(r, f.triangles) <= 1.0 + 1e-12);
        }
        // A truncated cone needs far fewer triangles than a picture-wide one.
        assert!(FanShape::for_distance_error(20.0, 1.0).triangles < 12);
    }
}
