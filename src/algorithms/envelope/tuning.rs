//! The costs that steer how cones are drawn, one profile per kind of device:
//! lavapipe sets up and bins every triangle on the CPU, so there a triangle
//! weighs as much as hundreds of fragments. The figures behind each value are
//! in docs/tuning.md ("Device profiles").

use std::f64::consts::PI;

use crate::{
    error::{Error, Result},
    machine::{DeviceClass, Machine},
};

/// What one kind of device makes cheap or dear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Tuning {
    /// A triangle's cost in fragments.
    pub triangle_fragments: f64,
    /// Largest radius of a batched cone. A batch's rectangle is the bounding box
    /// of its cones, so one long cone would widen it for all eight; longer cones
    /// get a polygon of their own.
    pub batch_radius: f64,
    /// The same for L_p whose keys cost powers (see `DepthKey`): a batch
    /// evaluates eight per fragment, a cone of its own one, so only small cones
    /// batch.
    pub batch_radius_lp: f64,
}

impl Tuning {
    /// Mesa's lavapipe, measured on 2 cores.
    pub(crate) const SOFTWARE: Self = Self {
        triangle_fragments: 400.0,
        batch_radius: 48.0,
        batch_radius_lp: 12.0,
    };

    /// GPUs: lavapipe's values until a GPU's figures choose others (see
    /// docs/tuning.md); `PIXGEO_TUNING` tries others without a rebuild.
    pub const GPU: Self = Self::SOFTWARE;

    /// The profile of the machine's device, with what `PIXGEO_TUNING` changes.
    pub fn of(machine: &Machine) -> Result<Self> {
        let profile = match machine.device_class() {
            DeviceClass::Software => Self::SOFTWARE,
            DeviceClass::Gpu => Self::GPU,
        };
        match std::env::var("PIXGEO_TUNING") {
            Ok(text) => profile.with(&text),
            Err(_) => Ok(profile),
        }
    }

    /// The profile with the values `text` names: `name=value` pairs separated
    /// by commas, e.g. `triangle_fragments=40,batch_radius=64`.
    pub fn with(mut self, text: &str) -> Result<Self> {
        for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let bad = |why: &str| {
                Error::malformed(format!(
                    "PIXGEO_TUNING: `{pair}` {why}; it takes name=value pairs, comma-separated, \
                     of triangle_fragments, batch_radius and batch_radius_lp"
                ))
            };
            let (name, value) = pair
                .split_once('=')
                .ok_or_else(|| bad("is not name=value"))?;
            let value: f64 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| bad("needs a finite value of at least 0"))?;
            match name.trim() {
                "triangle_fragments" => self.triangle_fragments = value,
                "batch_radius" => self.batch_radius = value,
                "batch_radius_lp" => self.batch_radius_lp = value,
                _ => return Err(bad("names no tuning value")),
            }
        }
        Ok(self)
    }

    /// Corners of a long exact cone's footprint polygon, a regular K-gon around
    /// the disc of `radius` it must cover: K - 2 triangles of area
    /// `K tan(pi / K) r²`. Hexagons give way to octagons where the fragments
    /// the octagon saves pay for its two more triangles (about radius 73 on
    /// lavapipe).
    pub(crate) fn polygon_corners(&self, radius: f64) -> u32 {
        let area = |k: f64| k * (PI / k).tan();
        let saved = (area(6.0) - area(8.0)) * radius * radius;
        if saved > 2.0 * self.triangle_fragments {
            8
        } else {
            6
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_named_and_checked() {
        let t = Tuning::SOFTWARE
            .with("triangle_fragments=40, batch_radius_lp=6")
            .unwrap();
        assert_eq!(t.triangle_fragments, 40.0);
        assert_eq!(t.batch_radius_lp, 6.0);
        assert_eq!(t.batch_radius, Tuning::SOFTWARE.batch_radius);
        for bad in [
            "triangles=4",
            "batch_radius",
            "batch_radius=-1",
            "batch_radius=inf",
        ] {
            let error = Tuning::SOFTWARE.with(bad).unwrap_err().to_string();
            assert!(error.contains("PIXGEO_TUNING"), "{error}");
        }
    }

    #[test]
    fn octagons_where_their_fragments_pay_for_two_triangles() {
        let t = Tuning::SOFTWARE;
        assert_eq!(t.polygon_corners(72.0), 6);
        assert_eq!(t.polygon_corners(74.0), 8);
        let cheap = t.with("triangle_fragments=0").unwrap();
        assert_eq!(cheap.polygon_corners(1.0), 8);
    }
}
