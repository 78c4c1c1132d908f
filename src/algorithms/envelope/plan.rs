//! The cones of a point diagram, sized, shaped and batched once for every tile
//! and every try: the thesis's §3.5 bounds or a radius per site, each cone's
//! footprint, and the depth scale they share.

use crate::memory::Gather;
use glam::DVec2;

use crate::{
    error::{Error, Result},
    geometry::{
        chain,
        cone::{check_fan_size, MAX_FAN_TRIANGLES},
        metric::{DepthKey, Metric},
        radius::{self, TileCandidates},
        Frame,
    },
    machine::Machine,
};

use super::{
    accuracy::{metric_fan, Accuracy, Speedup},
    footprint::{
        batches_of, cone_attempts, groups_of, reach_cones, shape_cones, Footprint, Shaped,
        BALL_CORNERS,
    },
    render::{render, Draws, Picture, TileView},
    tuning::Tuning,
    DepthMap, BATCH, SCREEN_TILE_SIDE,
};
use crate::algorithms::cones::ConeBatch;

/// The farthest (pixels) an exact cone may reach: float32 positions and
/// distances there are good to about a sixtieth of a pixel, and farther out
/// two sites' distances could tie or swap by more.
pub const MAX_EXACT_REACH: f64 = (1u32 << 18) as f64;

/// How many cones were drawn with one kind of footprint.
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ConeGroup {
    /// `tiles` (exact cones found per screen tile, not drawn), `batch` (exact
    /// cones drawn eight to a rectangle), `polygon` (an exact cone's own
    /// footprint), `ball`, `fan` or `chain`.
    pub kind: &'static str,
    /// The side of a screen tile in pixels, cones to a batch, corners of a
    /// polygon or ball, triangles of a fan or chain.
    pub size: u32,
    pub cones: usize,
}

/// What a point diagram asks of its cones.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConeSpec {
    pub metric: Metric,
    /// As drawn (`drawn_accuracy`).
    pub accuracy: Accuracy,
    pub speedup: Speedup,
    /// Count the cones at each pixel's lowest depth in the stencil.
    pub ties: bool,
    /// Exact cones may write power sums (`DepthKey::for_cones`) for peeling.
    pub power_keys: bool,
    /// Mark the pixels whose runner-up is within rounding of their nearest,
    /// where the screen tiles' lists can tell (`ConePlan::marks_near_ties`).
    pub mark_near_ties: bool,
}

/// One try's cones, with the quadtree radius it uses (if any).
struct Attempt {
    radius: Option<f64>,
    /// In draw order; the batched ones are drawn through `batches`.
    cones: Vec<Shaped>,
    batches: Vec<ConeBatch>,
}

/// Powers of two that map cone heights (fan) or squared distances (exact) into the
/// depth range [0, 1]; powers of two keep the mapping exact.
#[derive(Clone, Copy, Debug)]
pub(super) struct DepthScale {
    pub vertex: f64,
    pub fragment: f64,
}

/// The cones of a point diagram, ready to draw into any tile of its picture.
pub(crate) struct ConePlan {
    spec: ConeSpec,
    /// The tries, each drawn where the one before left pixels uncovered (the
    /// quadtree's radii); one for every other speedup.
    attempts: Vec<Attempt>,
    /// Exact cones taken per screen tile from the sites listed for it
    /// ([`crate::algorithms::cones::NEAREST_TILES`]) instead of drawn.
    tiled: bool,
    /// The screen tiles' candidates, where found directly (L_p and L∞).
    candidates: Option<TileCandidates>,
    key: DepthKey,
    scale: DepthScale,
    meshes: chain::FanMeshes,
    /// Every site (picture pixels), by id.
    sites: Vec<DVec2>,
}

impl ConePlan {
    /// Sizes and shapes the cones of `sites` (picture pixels).
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn new(
        machine: &Machine,
        sites: Vec<DVec2>,
        frame: &Frame,
        spec: ConeSpec,
    ) -> Result<Self> {
        let tuning = Tuning::of(machine)?;
        // Exact cones are found per screen tile where their boxes are tight (local
        // radii) and ties need not count each cone's own fragments; their squares
        // cut to the boxes are drawn where the tiles' lists would be too long.
        let tiled =
            spec.accuracy == Accuracy::Exact && spec.speedup == Speedup::Local && !spec.ties;
        // L_p and L∞ tiles find their candidates directly, in fewer measurements
        // than the regions' boxes take (L∞'s boxes hold diamonds) and with shorter
        // lists; the regions' reaches come with them. L1's boxes from Delaunay
        // neighbours cost less.
        let candidates = match spec.metric {
            Metric::Lp(_) | Metric::LInf if tiled => {
                radius::tile_candidates(&sites, frame, SCREEN_TILE_SIDE, spec.metric)
            }
            _ => None,
        };
        let attempts = match &candidates {
            Some(c) => Vec::from([(None, reach_cones(&sites, frame, spec.metric, &c.reaches))]),
            None => cone_attempts(&sites, frame, spec.speedup, spec.metric)?,
        };
        // Exact cones discard fragments beyond their radius.
        let exact_reach = attempts
            .iter()
            .flat_map(|(_, cones)| cones)
            .map(|c| c.radius)
            .fold(1.0, f64::max)
            * 1.001;
        if spec.accuracy == Accuracy::Exact && exact_reach > MAX_EXACT_REACH {
            return Err(Error::out_of_range(format!(
                "sites lie up to {exact_reach:.3e} pixels from pixels they own: the device's \
                 float32 resolves distances there to {:.2e} pixels, not exactly (up to {MAX_EXACT_REACH} \
                 pixels it resolves a sixtieth); use the CPU algorithm (--device cpu), exact in f64",
                exact_reach * f32::EPSILON as f64
            )));
        }
        if let Accuracy::Fan {
            epsilon,
            triangles: None,
        } = spec.accuracy
        {
            check_fan_size(exact_reach, epsilon)?;
        }
        let key = match (spec.power_keys, spec.accuracy) {
            (true, Accuracy::Exact) => DepthKey::for_cones(spec.metric, exact_reach),
            _ => DepthKey::Metric(spec.metric),
        };
        let attempts: Vec<Attempt> = attempts
            .into_iter()
            .map(|(radius, cones)| {
                let cones = if tiled {
                    cones
                        .iter()
                        .map(|cone| Shaped {
                            cone: *cone,
                            footprint: Footprint::Polygon(4),
                            outer_radius: cone.reach * std::f64::consts::SQRT_2,
                        })
                        .collect()
                } else {
                    shape_cones(&cones, frame, &spec, key, &tuning)
                };
                Attempt {
                    radius,
                    batches: batches_of(&cones),
                    cones,
                }
            })
            .gather("batches")?;
        // A cone sized by the quadtree may reach past every pixel a site owns.
        let shaped = || attempts.iter().flat_map(|a| &a.cones);
        if let Some(t) = shaped().find_map(|s| match s.footprint {
            Footprint::Fan(t) if t > MAX_FAN_TRIANGLES => Some(t),
            _ => None,
        }) {
            return Err(Error::out_of_range(format!(
                "a fan cone would need {t} triangles, more than {MAX_FAN_TRIANGLES}: \
                 give a larger epsilon, or use exact mode"
            )));
        }
        // One depth scale for every tile and attempt, the largest cone's: exact
        // cones discard fragments beyond their radius; fan heights reach the
        // outer radius at the rim.
        let scale = match spec.accuracy {
            Accuracy::Exact => DepthScale {
                vertex: 0.0,
                fragment: key.scale(exact_reach),
            },
            Accuracy::Fan { .. } => {
                let reach = shaped().map(|s| s.outer_radius).fold(1.0, f64::max) * 1.001;
                DepthScale {
                    vertex: reach.log2().ceil().exp2().recip(),
                    fragment: 0.0,
                }
            }
        };
        Ok(Self {
            spec,
            attempts,
            tiled,
            candidates,
            key,
            scale,
            meshes: chain::FanMeshes::new(spec.metric),
            sites,
        })
    }

    /// The number of tries.
    pub fn attempts(&self) -> usize {
        self.attempts.len()
    }

    /// Whether exact cones are taken per screen tile where the lists allow.
    pub(crate) fn is_tiled(&self) -> bool {
        self.tiled
    }

    /// Whether a tile drawn from its screen tiles' lists marks near ties in
    /// its labels' top bit (`glsl/nearest_tiles.frag`): for L2, L1 and L∞,
    /// whose lists come by id, and ids below the top bit.
    pub(crate) fn marks_near_ties(&self) -> bool {
        self.spec.mark_near_ties
            && self.tiled
            && matches!(self.key.shader_code(), Some((0..=2, _)))
            && self.sites.len() < 1 << 31
    }

    /// How the depths drawn map to distances (world units).
    pub(crate) fn depth_map(&self, pixels_per_unit: f64) -> DepthMap {
        let exact = self.spec.accuracy == Accuracy::Exact;
        DepthMap {
            key: exact.then_some(self.key),
            scale: if exact {
                self.scale.fragment
            } else {
                self.scale.vertex
            },
            pixels_per_unit,
            offset: 0.0,
        }
    }

    /// Draws try `attempt`'s lower envelope into `picture`, which shows `view`;
    /// whether it was found from screen tiles' lists of sites. `aligned`: the
    /// view's screen tiles are the picture's, so that its candidates serve.
    pub fn render(
        &self,
        machine: &Machine,
        picture: &Picture,
        view: &TileView,
        attempt: usize,
        aligned: bool,
    ) -> Result<bool> {
        let Attempt { cones, batches, .. } = &self.attempts[attempt];
        let draws = Draws {
            cones,
            batches,
            accuracy: self.spec.accuracy,
            metric: self.spec.metric,
            key: self.key,
            meshes: &self.meshes,
            scale: self.scale,
            ties: self.spec.ties,
            tiled: self.tiled,
            mark_near_ties: self.marks_near_ties(),
            candidates: self.candidates.as_ref().filter(|_| aligned),
            sites: &self.sites,
        };
        render(machine, picture, view, &draws)
    }

    /// The quadtree radii of tries up to `attempt`.
    #[expect(
        clippy::disallowed_methods,
        reason = "one radius per attempt, a handful"
    )]
    pub(crate) fn radii_tried(&self, attempt: usize) -> Vec<f64> {
        self.attempts[..=attempt]
            .iter()
            .filter_map(|a| a.radius)
            .collect()
    }

    /// The Euclidean radii of try `attempt`'s cones.
    pub fn radii(&self, attempt: usize) -> impl Iterator<Item = f64> + Clone + '_ {
        self.attempts[attempt].cones.iter().map(|s| s.cone.radius)
    }

    /// Try `attempt`'s cones by footprint, or as screen tiles where every tile
    /// was drawn from lists.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn groups(&self, attempt: usize, drawn_by_tiles: bool) -> Vec<ConeGroup> {
        let cones = &self.attempts[attempt].cones;
        if drawn_by_tiles {
            return Vec::from([ConeGroup {
                kind: "tiles",
                size: SCREEN_TILE_SIDE,
                cones: cones.len(),
            }]);
        }
        groups_of(cones)
            .into_iter()
            .map(|g| ConeGroup {
                kind: match g.footprint {
                    Footprint::Batch => "batch",
                    Footprint::Polygon(_) => "polygon",
                    Footprint::Ball => "ball",
                    Footprint::Fan(_) => "fan",
                    Footprint::Chain(_) => "chain",
                },
                size: match g.footprint {
                    Footprint::Batch => BATCH as u32,
                    Footprint::Polygon(k) | Footprint::Fan(k) => k,
                    Footprint::Ball => BALL_CORNERS,
                    Footprint::Chain(level) => {
                        self.meshes
                            .unit_mesh(metric_fan(self.spec.accuracy), chain::level_radius(level))
                            .len() as u32
                            - 2
                    }
                },
                cones: g.count as usize,
            })
            .collect()
    }
}
