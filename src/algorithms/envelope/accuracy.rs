//! How cones are drawn (fans within ε, or exact per fragment) and how far
//! they reach.

use crate::{
    error::{Error, Result},
    geometry::{
        chain,
        cone::{MAX_FAN_TRIANGLES, MIN_FAN_EPSILON},
        metric::Metric,
    },
};

/// How cones are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Accuracy {
    /// Triangle fans. With `triangles: None` each cone gets the fewest triangles for
    /// an ε distance diagram at its own radius; `Some(T)` fixes T for every cone.
    Fan {
        epsilon: f64,
        triangles: Option<u32>,
    },
    /// The exact distance per fragment.
    Exact,
}

impl Accuracy {
    /// Fans for a distance diagram within one pixel.
    pub const FAN: Self = Self::Fan {
        epsilon: 1.0,
        triangles: None,
    };

    /// A clear error for a fan without a finite ε of at least
    /// `MIN_FAN_EPSILON` pixels, or with fewer than 3 or more than
    /// `MAX_FAN_TRIANGLES` triangles.
    pub fn check(self) -> Result<()> {
        if let Self::Fan { epsilon, triangles } = self {
            if !(epsilon >= MIN_FAN_EPSILON && epsilon.is_finite()) {
                return Err(Error::out_of_range(format!(
                    "fan epsilon {epsilon:?} must be a finite distance of at least {MIN_FAN_EPSILON} \
                     pixels (the rasterizer's subpixel grid is 1/256 pixel)"
                )));
            }
            if triangles.is_some_and(|t| !(3..=MAX_FAN_TRIANGLES).contains(&t)) {
                return Err(Error::out_of_range(format!(
                    "a fan has at least 3 and at most {MAX_FAN_TRIANGLES} triangles"
                )));
            }
        }
        Ok(())
    }

    /// [`Accuracy::check`], and a clear error for fans of a metric whose
    /// ball is not convex (L_p with p < 1): a fan's flat sides cut through
    /// such a ball, so no ε bounds its distances, which can be far too small
    /// along the axes.
    pub fn check_for(self, metric: Metric) -> Result<()> {
        self.check()?;
        match (self, metric) {
            (Self::Fan { .. }, Metric::Lp(p)) if p < 1.0 => {
                Err(Error::unsupported_option(format!(
                    "fans cannot keep a distance bound under L_p with p = {p} < 1, whose ball is \
                 not convex; draw it exactly (the default mode), which has no error"
                )))
            }
            _ => Ok(()),
        }
    }
}

/// How far cones reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Speedup {
    /// Every cone covers the whole picture.
    None,
    /// One radius for all cones from the quadtree (thesis §3.5); uncovered pixels
    /// are found with minmax and the cones redrawn larger.
    Quadtree,
    /// A radius per site from the sites around it.
    Local,
}

/// The accuracy a diagram is drawn with: a polygon's distance is piecewise
/// linear, so the fan over the polygon itself is exact, and is what exact mode
/// draws; every other metric as asked.
pub(crate) fn drawn_accuracy(metric: Metric, accuracy: Accuracy) -> Accuracy {
    match (metric, accuracy) {
        (Metric::Polygon(_), Accuracy::Exact) => Accuracy::FAN,
        _ => accuracy,
    }
}

/// How fans of metrics other than L2 are built for `accuracy` (a fan mode).
pub(crate) fn metric_fan(accuracy: Accuracy) -> chain::MetricFan {
    match accuracy {
        Accuracy::Fan {
            triangles: Some(corners),
            ..
        } => chain::MetricFan::Uniform { corners },
        Accuracy::Fan { epsilon, .. } => chain::MetricFan::Chain { epsilon },
        Accuracy::Exact => unreachable!("exact cones have no fan"),
    }
}
