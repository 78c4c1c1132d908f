//! Nearest sites and distances on the Earth, for sites and places given as
//! longitude and latitude in degrees (a geographic coordinate system): great
//! circles on a sphere of radius [`EARTH_RADIUS`] metres.
//!
//! The great-circle distance grows with the chord between two points' unit
//! vectors, so the nearest site by great circle is the nearest by chord: a
//! k-d tree over the sites' unit vectors finds it. Each unit vector is within
//! [`VECTOR_ERROR`] of the true one in every component, so every chord is
//! within [`CHORD_ERROR`] of its true length. A place whose two nearest sites'
//! chords differ by more than twice that has its nearest site proven. For the
//! others (sites within about a micrometre of equidistant) every site within
//! the bound is compared again in rational intervals: the cosines and sines
//! of the degrees, π/180 among them, bracketed to 64, then 160, then 320 bits,
//! until one site's dot product with the place is above every other's.
//! Sites still equidistant at 320 bits (true ties, as far as any evidence
//! goes) are counted and the lower index wins, as everywhere in pixgeo.
//! Distances are `R · atan2(|u × v|, u · v)`, well conditioned from 0 to
//! antipodes, within [`DISTANCE_ERROR`] metres of the sphere's.
//!
//! On a Vulkan device, [`great_circle_grid`] finds the nearest sites of a
//! longitude-latitude grid with the device as a filter (`device.rs`), to the
//! same answer.

use crate::memory::Gather;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

mod device;

use crate::{
    cancel::Watch, control::Control, geometry::exact::sphere::nearest_on_sphere, Backend, Error,
    Result,
};

/// The sphere's radius: the IUGG mean radius of the Earth (R1), in metres.
pub const EARTH_RADIUS: f64 = 6_371_008.8;

/// A bound on each component's error of a unit vector computed from degrees:
/// the conversion to radians and `sin`/`cos` (each within an ulp or two) and
/// the products, with room.
pub const VECTOR_ERROR: f64 = 64.0 * f64::EPSILON;

/// A bound on the error of a computed chord between two unit vectors (the
/// vectors' errors and the arithmetic's).
pub const CHORD_ERROR: f64 = 8.0 * VECTOR_ERROR;

/// A bound on a distance's error, metres: the angle between two computed
/// unit vectors is within about `2√3 VECTOR_ERROR` of the true one, with
/// room for the arithmetic.
pub const DISTANCE_ERROR: f64 = EARTH_RADIUS * 8.0 * VECTOR_ERROR;

/// Every place's nearest site and its great-circle distance.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GreatCircle {
    /// Each place's nearest site (an index into the sites).
    pub labels: Vec<u32>,
    /// Each place's distance to it in metres, within [`DISTANCE_ERROR`].
    pub distances: Vec<f64>,
    /// Places with two or more sites equidistant to 320 bits: the lower
    /// index is their label.
    pub equidistant: usize,
    /// Places the device's filter left to the host to decide (0 on the
    /// CPU, which decides every place).
    pub decided_on_host: usize,
}

/// The unit vector of longitude `lon` and latitude `lat`, degrees.
pub fn unit_vector(p: DVec2) -> DVec3 {
    let (lon, lat) = (p.x.to_radians(), p.y.to_radians());
    DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
}

/// The great-circle distance in metres between two points (degrees).
pub fn distance(a: DVec2, b: DVec2) -> f64 {
    angle(unit_vector(a), unit_vector(b)) * EARTH_RADIUS
}

fn angle(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length().atan2(u.dot(v))
}

/// Refuses positions that are not longitude and latitude in degrees.
fn check(points: &[DVec2], what: &str) -> Result<()> {
    match points
        .iter()
        .position(|p| !(p.x.is_finite() && (-90.0..=90.0).contains(&p.y)))
    {
        Some(i) => Err(Error::out_of_range(format!(
            "{what} {i} at ({}, {}): under a geographic coordinate system x is a \
             longitude and y a latitude in [-90, 90], degrees",
            points[i].x, points[i].y
        ))),
        None => Ok(()),
    }
}

/// How to find nearest sites by great circle: the work's progress (places
/// done) and cancellation.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct GreatCircleOptions {
    pub control: Control,
}

impl GreatCircleOptions {
    pub fn control(self, control: Control) -> Self {
        Self { control }
    }
}

/// Every pixel's nearest site by great circle and its distance, for the grid
/// whose columns have longitudes `lons` and whose rows have latitudes `lats`
/// (degrees; places row by row): on a device by a float filter the host
/// decides where it is unsure ([`GreatCircle::decided_on_host`]), on the CPU
/// by [`great_circle_nearest`]; the same answer bit for bit.
pub fn great_circle_grid(
    backend: &Backend,
    sites: &[DVec2],
    lons: &[f64],
    lats: &[f64],
    options: &GreatCircleOptions,
) -> Result<GreatCircle> {
    let control = &options.control;
    let progress = |done, total| control.report(done, total);
    control.run(|| match backend {
        Backend::Device(machine) => device::grid(machine, sites, lons, lats, &progress),
        Backend::Cpu => {
            let count = lons.len().saturating_mul(lats.len());
            let mut places = crate::memory::room(count, "the grid's places")?;
            places.extend(
                lats.iter()
                    .flat_map(|&y| lons.iter().map(move |&x| DVec2::new(x, y))),
            );
            nearest_places(sites, &places, &progress)
        }
    })
}

/// Each of `places`' nearest site among `sites` by great circle, and the
/// distance to it.
pub fn great_circle_nearest(
    sites: &[DVec2],
    places: &[DVec2],
    options: &GreatCircleOptions,
) -> Result<GreatCircle> {
    let control = &options.control;
    control.run(|| nearest_places(sites, places, &|done, total| control.report(done, total)))
}

fn nearest_places(
    sites: &[DVec2],
    places: &[DVec2],
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<GreatCircle> {
    if sites.is_empty() {
        return Err(Error::too_few(1, 0, "no sites".into()));
    }
    if sites.len() >= u32::MAX as usize {
        return Err(Error::out_of_range("too many sites".into()));
    }
    check(sites, "site")?;
    check(places, "place")?;
    let tree = Tree::new(sites.iter().map(|&p| unit_vector(p)).gather("tree")?);
    let watch = Watch::current();
    let total = places.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let chunks: Vec<(Vec<u32>, Vec<f64>, usize)> = places
        .par_chunks(PLACES_PER_LOOK)
        .map(|chunk| {
            watch.check()?;
            let mut labels = crate::memory::room(chunk.len(), "labels")?;
            let mut distances = crate::memory::room(chunk.len(), "distances")?;
            let mut equidistant = 0;
            for &place in chunk {
                let u = unit_vector(place);
                let (i, tied) = nearest(&tree, sites, place, u);
                equidistant += usize::from(tied);
                labels.push(i);
                distances.push(angle(u, tree.points[i as usize]) * EARTH_RADIUS);
            }
            let now = done.fetch_add(chunk.len() as u64, std::sync::atomic::Ordering::Relaxed);
            progress(now + chunk.len() as u64, total);
            Ok((labels, distances, equidistant))
        })
        .collect::<Result<_>>()?;
    let mut answer = GreatCircle::default();
    for (labels, distances, equidistant) in chunks {
        answer.labels.extend(labels);
        answer.distances.extend(distances);
        answer.equidistant += equidistant;
    }
    Ok(answer)
}

/// The nearest site to `place` (whose unit vector is `u`) and whether two or
/// more stay equidistant: by the chords in doubles where the two nearest
/// differ by more than their error, else in rational intervals.
fn nearest(tree: &Tree, sites: &[DVec2], place: DVec2, u: DVec3) -> (u32, bool) {
    let [(first, i), (second, _)] = tree.two_nearest(u);
    if second.sqrt() - first.sqrt() > 2.0 * CHORD_ERROR {
        return (i, false);
    }
    let reach = first.sqrt() + 2.0 * CHORD_ERROR;
    nearest_on_sphere(place, sites, &tree.within(u, reach))
}

/// Places handled between looks at the cancel flag and reports of progress.
const PLACES_PER_LOOK: usize = 1 << 14;

/// A static k-d tree over 3-D points: the median of each range, split on the
/// axes in turn.
struct Tree {
    /// The points by their input index.
    points: Vec<DVec3>,
    /// Input indices in tree order.
    order: Vec<u32>,
}

impl Tree {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    fn new(points: Vec<DVec3>) -> Self {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        build(&points, &mut order, 0);
        Self { points, order }
    }

    /// The two nearest points to `q` (squared chords and input indices),
    /// nearer first, ties to the lower index; with one point, it twice over
    /// at an infinite second distance.
    fn two_nearest(&self, q: DVec3) -> [(f64, u32); 2] {
        let mut best = [(f64::INFINITY, u32::MAX); 2];
        self.search(q, 0, self.order.len(), 0, &mut best);
        if best[1].1 == u32::MAX {
            best[1] = (f64::INFINITY, best[0].1);
        }
        best
    }

    /// The input indices of the points within chord `reach` of `q`.
    fn within(&self, q: DVec3, reach: f64) -> Vec<u32> {
        let mut found = Vec::new();
        self.gather(q, reach * reach, 0, self.order.len(), 0, &mut found);
        found
    }

    fn gather(&self, q: DVec3, r2: f64, lo: usize, hi: usize, depth: usize, found: &mut Vec<u32>) {
        if lo >= hi {
            return;
        }
        let mid = (lo + hi) / 2;
        let i = self.order[mid];
        let p = self.points[i as usize];
        if (p - q).length_squared() <= r2 {
            found.push(i);
        }
        let diff = q[depth % 3] - p[depth % 3];
        if diff <= 0.0 || diff * diff <= r2 {
            self.gather(q, r2, lo, mid, depth + 1, found);
        }
        if diff >= 0.0 || diff * diff <= r2 {
            self.gather(q, r2, mid + 1, hi, depth + 1, found);
        }
    }

    fn search(&self, q: DVec3, lo: usize, hi: usize, depth: usize, best: &mut [(f64, u32); 2]) {
        if lo >= hi {
            return;
        }
        let mid = (lo + hi) / 2;
        let i = self.order[mid];
        let p = self.points[i as usize];
        let d = (p - q).length_squared();
        let candidate = (d, i);
        let before = |a: (f64, u32), b: (f64, u32)| a.0 < b.0 || (a.0 == b.0 && a.1 < b.1);
        if before(candidate, best[0]) {
            best[1] = best[0];
            best[0] = candidate;
        } else if before(candidate, best[1]) {
            best[1] = candidate;
        }
        let axis = depth % 3;
        let diff = q[axis] - p[axis];
        let (near, far) = if diff < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.search(q, near.0, near.1, depth + 1, best);
        // The far side holds points at least |diff| away along this axis.
        if diff * diff <= best[1].0 {
            self.search(q, far.0, far.1, depth + 1, best);
        }
    }
}

fn build(points: &[DVec3], order: &mut [u32], depth: usize) {
    if order.len() <= 1 {
        return;
    }
    let axis = depth % 3;
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| {
        points[a as usize][axis].total_cmp(&points[b as usize][axis])
    });
    let (left, right) = order.split_at_mut(mid);
    build(points, left, depth + 1);
    build(points, &mut right[1..], depth + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_are_the_haversines_and_nearest_is_brute_force() {
        // London to Paris on the mean sphere: 343.56 km (haversine).
        let london = DVec2::new(-0.1278, 51.5074);
        let paris = DVec2::new(2.3522, 48.8566);
        assert!((distance(london, paris) - 343_556.0).abs() < 1.0);
        // Antipodes: half the circumference, well conditioned.
        let far = distance(DVec2::new(10.0, 20.0), DVec2::new(-170.0, -20.0));
        assert!((far - std::f64::consts::PI * EARTH_RADIUS).abs() < 1e-6);
        let sites: Vec<DVec2> = (0..200)
            .map(|k| {
                let t = k as f64;
                DVec2::new(
                    (t * 97.31).rem_euclid(360.0) - 180.0,
                    (t * 41.7).rem_euclid(180.0) - 90.0,
                )
            })
            .collect();
        let places: Vec<DVec2> = (0..2000)
            .map(|k| {
                let t = k as f64 + 0.5;
                DVec2::new(
                    (t * 13.7).rem_euclid(360.0) - 180.0,
                    (t * 7.3).rem_euclid(180.0) - 90.0,
                )
            })
            .collect();
        let answer = great_circle_nearest(&sites, &places, &Default::default()).unwrap();
        for (k, &place) in places.iter().enumerate() {
            let brute = sites
                .iter()
                .map(|&s| distance(place, s))
                .fold(f64::INFINITY, f64::min);
            assert!(
                (answer.distances[k] - brute).abs() <= 2.0 * DISTANCE_ERROR,
                "{k}"
            );
        }
        assert!(
            great_circle_nearest(&sites, &[DVec2::new(0.0, 91.0)], &Default::default()).is_err()
        );
    }

    #[test]
    fn sites_an_ulp_from_equidistant_are_told_apart_and_true_ties_counted() {
        // Site 0, on the meridian, is one ulp of 0.90439° farther than site 1,
        // on the equator: 2e-12 m farther, and equally far in doubles, where
        // the lower index would win.
        let a: f64 = 0.90439;
        let sites = [
            DVec2::new(0.0, f64::from_bits(a.to_bits() + 1)),
            DVec2::new(a, 0.0),
        ];
        let place = DVec2::ZERO;
        let tree = Tree::new(sites.iter().map(|&p| unit_vector(p)).collect());
        let [(first, i), (second, _)] = tree.two_nearest(unit_vector(place));
        assert_eq!((first, i), (second, 0));
        let answer = great_circle_nearest(&sites, &[place], &Default::default()).unwrap();
        assert_eq!((answer.labels[0], answer.equidistant), (1, 0));
        // Truly equidistant sites (and a third one farther) stay tied: the
        // lower index, counted.
        let sites = [
            DVec2::new(5.0, 40.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(-10.0, 0.0),
        ];
        let answer =
            great_circle_nearest(&sites, &[DVec2::new(0.0, 0.0)], &Default::default()).unwrap();
        assert_eq!((answer.labels[0], answer.equidistant), (1, 1));
        // The same longitude a turn apart is the same meridian.
        let sites = [DVec2::new(370.0, 0.0), DVec2::new(-10.0, 0.0)];
        let answer =
            great_circle_nearest(&sites, &[DVec2::new(0.0, 0.0)], &Default::default()).unwrap();
        assert_eq!((answer.labels[0], answer.equidistant), (0, 1));
    }
}
