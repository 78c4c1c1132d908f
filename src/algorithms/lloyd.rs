//! Centroidal Voronoi tessellations by Lloyd's iterations, with a density
//! (Secord's weighted Voronoi stippling): each iteration is an exact Voronoi
//! diagram of the sites on the picture, then per-region sums (the thesis's
//! counting, §3.7), then every site moves to its region's centroid.
//!
//! The centroids are exact for the digital regions: a site's new position is
//! the double nearest to the weighted mean of its pixels' centres, computed
//! from sums in exact integer arithmetic (each density value turned into an
//! integer by one power of two) and rounded once. A site
//! whose region holds no weight stays where it is. The energy, the sum over
//! pixels of the density times the squared distance to the pixel's site, is
//! reported per iteration in doubles; it never increases, since both the
//! assignment to the nearest site and the move to the centroid lower it.

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    algorithms::{
        higher_order::cpu,
        voronoi::{voronoi_checked, VoronoiOptions},
    },
    cancel::Watch,
    geometry::{exact::mean::pixel_mean, frame::Checked, metric::Metric, Frame},
    Backend, Control, Error, Machine, Result,
};

/// Lloyd's iterations on `frame`: at most `iterations`, stopping once no site
/// moves farther than `tolerance` (world units); progress is reported after
/// each iteration.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct LloydOptions {
    pub frame: Frame,
    pub iterations: u32,
    pub tolerance: f64,
    pub control: Control,
}

impl LloydOptions {
    /// 50 iterations, stopping when no site moves a hundredth of a pixel.
    pub fn new(frame: Frame) -> Self {
        Self {
            frame,
            iterations: 50,
            tolerance: 0.01 / frame.scale,
            control: Control::new(),
        }
    }

    pub fn iterations(self, iterations: u32) -> Self {
        Self { iterations, ..self }
    }

    pub fn tolerance(self, tolerance: f64) -> Self {
        Self { tolerance, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// One iteration: the sites' energy before it and how far they moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LloydStep {
    /// Σ density · squared distance to the pixel's nearest site, world units,
    /// before the move.
    pub energy: f64,
    /// The largest distance a site moved.
    pub largest_move: f64,
}

/// Where the iterations leave the sites.
#[derive(Clone, Debug, PartialEq)]
pub struct Lloyd {
    /// The sites, in input order.
    pub sites: Vec<DVec2>,
    /// Every pixel's nearest site among them, row-major.
    pub labels: Vec<u32>,
    /// Each iteration run.
    pub steps: Vec<LloydStep>,
    /// The energy of the final sites.
    pub energy: f64,
    /// Whether the last move was within the tolerance.
    pub converged: bool,
    /// Sites whose region holds no weight at the end (they stayed put).
    pub idle: usize,
}

/// Lloyd's iterations from `sites` (world coordinates) on `backend` (the
/// device's cones or the CPU pixel algorithms, the same labels), over
/// `density` (one value per pixel of the frame, row-major, finite and not
/// negative; uniform without one).
pub fn lloyd(
    backend: &Backend,
    sites: &[DVec2],
    density: Option<&[f64]>,
    options: &LloydOptions,
) -> Result<Lloyd> {
    options
        .control
        .run(|| iterate(backend.machine(), sites, density, options))
}

fn iterate(
    machine: Option<&Machine>,
    sites: &[DVec2],
    density: Option<&[f64]>,
    options: &LloydOptions,
) -> Result<Lloyd> {
    let frame = options.frame;
    let checked = Checked::new(sites)?;
    if options.tolerance.is_nan() || options.tolerance < 0.0 {
        return Err(Error::out_of_range(format!(
            "the tolerance is a distance of 0 or more, not {}",
            options.tolerance
        )));
    }
    let weights = Weights::new(&frame, density)?;
    // The moved sites are centroids of pixel centres: finite, as many.
    let label = |sites: &[DVec2]| nearest_labels(machine, Checked::derived(sites), &frame);
    let watch = Watch::current();
    let mut labels = nearest_labels(machine, checked, &frame)?;
    let mut sites = sites.to_vec();
    let mut steps = Vec::new();
    let mut converged = false;
    for _ in 0..options.iterations {
        watch.check()?;
        let sums = weights.sums(&frame, &labels, sites.len())?;
        let energy = weights.energy(&frame, &labels, &sites);
        let mut largest_move: f64 = 0.0;
        for (site, sum) in sites.iter_mut().zip(&sums) {
            if let Some(centroid) = sum.centroid(&frame) {
                largest_move = largest_move.max(site.distance(centroid));
                *site = centroid;
            }
        }
        steps.push(LloydStep {
            energy,
            largest_move,
        });
        labels = label(&sites)?;
        options
            .control
            .report(steps.len() as u64, options.iterations as u64);
        if largest_move <= options.tolerance {
            converged = true;
            break;
        }
    }
    let sums = weights.sums(&frame, &labels, sites.len())?;
    Ok(Lloyd {
        energy: weights.energy(&frame, &labels, &sites),
        idle: sums.iter().filter(|s| s.weight == 0).count(),
        sites,
        labels,
        steps,
        converged,
    })
}

/// Every pixel's nearest site (exact, ties to the lower index), drawn on
/// `machine` or by the CPU pixel algorithms without one.
pub(crate) fn nearest_labels(
    machine: Option<&Machine>,
    sites: Checked<'_>,
    frame: &Frame,
) -> Result<Vec<u32>> {
    match machine {
        Some(m) => Ok(voronoi_checked(
            &Backend::Device(m),
            sites,
            &VoronoiOptions::exact(*frame).distances(false),
        )?
        .labels),
        None => Ok(cpu::k_nearest_checked(sites, frame, 1, Metric::L2, &mut |_, _| {})?.labels),
    }
}

/// Refuses density values that are negative or not finite.
pub fn check_density(values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        Some(i) => Err(Error::not_finite(
            Some(i),
            format!(
                "density value {i} is {}: densities are finite and not negative",
                values[i]
            ),
        )),
        None => Ok(()),
    }
}

/// The density as integers: each value `v` is `q · 2^unit` with `q` a whole
/// number, one `unit` for all (the lowest set bit among the values), so that
/// sums of `q` times pixel coordinates are exact in 128 bits.
struct Weights {
    /// `q` per pixel; `None` for a uniform density (every `q` 1).
    q: Option<Vec<u64>>,
    unit: i32,
}

/// A region's sums: Σq and Σq·(2i + 1), Σq·(2j + 1) over its pixels (i, j).
#[derive(Clone, Copy, Default)]
struct Sums {
    weight: u128,
    x: u128,
    y: u128,
}

impl Sums {
    fn add(&mut self, other: &Sums) {
        self.weight += other.weight;
        self.x += other.x;
        self.y += other.y;
    }

    /// The weighted mean of the region's pixel centres, rounded once: the
    /// centre of pixel i is `origin + (2i + 1) / (2 scale)`. The density's
    /// power of two cancels.
    fn centroid(&self, frame: &Frame) -> Option<DVec2> {
        if self.weight == 0 {
            return None;
        }
        let along = |sum: u128, origin: f64| pixel_mean(origin, sum, 2 * self.weight, frame.scale);
        Some(DVec2::new(
            along(self.x, frame.origin.x),
            along(self.y, frame.origin.y),
        ))
    }
}

impl Weights {
    fn new(frame: &Frame, density: Option<&[f64]>) -> Result<Self> {
        let Some(values) = density else {
            return Ok(Self { q: None, unit: 0 });
        };
        let pixels = frame.len();
        if values.len() != pixels {
            return Err(Error::malformed(format!(
                "the density has {} values for a {}x{} picture",
                values.len(),
                frame.width,
                frame.height
            )));
        }
        check_density(values)?;
        let (low, high) = values
            .par_iter()
            .filter(|v| **v > 0.0)
            .map(|&v| {
                let (mantissa, scale) = parts(v);
                let low = scale + mantissa.trailing_zeros() as i32;
                (low, scale + 63 - mantissa.leading_zeros() as i32)
            })
            .reduce(|| (i32::MAX, i32::MIN), |a, b| (a.0.min(b.0), a.1.max(b.1)));
        if low == i32::MAX {
            return Err(Error::degenerate(
                "the density is zero everywhere: no site has a region to move to".into(),
            ));
        }
        // q < 2^(high - low + 1); times 2i + 1 < 2^(side bits + 1); summed
        // over every pixel: all within 128 bits.
        let q_bits = high - low + 1;
        let side_bits = 33 - frame.width.max(frame.height).leading_zeros() as i32;
        let pixel_bits = 64 - (pixels as u64).leading_zeros() as i32;
        let room = 127 - side_bits - pixel_bits;
        if q_bits > room.min(64) {
            return Err(Error::out_of_range(format!(
                "the density's values need {q_bits} bits as whole multiples of one power of \
                 two, above the {} that keep this picture's sums exact: round them (to 8 or \
                 16-bit levels, say)",
                room.min(64)
            )));
        }
        let q = values
            .par_iter()
            .map(|&v| {
                // Exact: v is a whole multiple of 2^low, below 2^64 of them.
                let (mantissa, scale) = parts(v);
                if v == 0.0 {
                    0
                } else if scale >= low {
                    mantissa << (scale - low)
                } else {
                    mantissa >> (low - scale)
                }
            })
            .collect();
        Ok(Self {
            q: Some(q),
            unit: low,
        })
    }

    fn q(&self, k: usize) -> u64 {
        self.q.as_ref().map_or(1, |q| q[k])
    }

    /// Each site's sums over its region.
    fn sums(&self, frame: &Frame, labels: &[u32], sites: usize) -> Result<Vec<Sums>> {
        let width = frame.width as usize;
        let zero = || crate::memory::filled(sites, Sums::default(), "the regions' sums");
        labels
            .par_chunks(width)
            .enumerate()
            .fold(zero, |sums, (j, row)| {
                let mut sums = sums?;
                for (i, &l) in row.iter().enumerate() {
                    let q = self.q(j * width + i) as u128;
                    if q == 0 || l as usize >= sites {
                        continue;
                    }
                    let s = &mut sums[l as usize];
                    s.weight += q;
                    s.x += q * (2 * i as u128 + 1);
                    s.y += q * (2 * j as u128 + 1);
                }
                Ok(sums)
            })
            .reduce(zero, |a, b| {
                let (mut a, b) = (a?, b?);
                a.iter_mut().zip(&b).for_each(|(a, b)| a.add(b));
                Ok(a)
            })
    }

    /// Σ density · squared distance from each pixel's centre to its site.
    fn energy(&self, frame: &Frame, labels: &[u32], sites: &[DVec2]) -> f64 {
        let width = frame.width as usize;
        let unit = 2f64.powi(self.unit);
        labels
            .par_chunks(width)
            .enumerate()
            .map(|(j, row)| {
                row.iter()
                    .enumerate()
                    .filter(|(_, &l)| (l as usize) < sites.len())
                    .map(|(i, &l)| {
                        let centre = frame.to_world(DVec2::new(i as f64, j as f64));
                        self.q(j * width + i) as f64 * centre.distance_squared(sites[l as usize])
                    })
                    .sum::<f64>()
            })
            .sum::<f64>()
            * unit
    }
}

/// A finite double `v >= 0` as `mantissa · 2^scale`, the mantissa whole.
fn parts(v: f64) -> (u64, i32) {
    let raw = v.to_bits();
    let exponent = ((raw >> 52) & 0x7ff) as i32;
    let fraction = raw & ((1 << 52) - 1);
    if exponent == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), exponent - 1075)
    }
}
