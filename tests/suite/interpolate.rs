//! Interpolation against definitions evaluated in rationals: Sibson's
//! interpolant by clipping Voronoi regions, the linear one in a Delaunay
//! triangle found by brute force, every pixel correctly rounded, on random,
//! lattice, one-ulp and far-magnitude sites. Discrete Sibson interpolation
//! against its definition by brute force (every pixel against every pixel),
//! on the device and the CPU, and near the exact interpolant on linear data.

use crate::common::{machine, ulps, uniform};
use glam::DVec2;
use num_rational::BigRational;
use pixgeo::Backend;
use pixgeo::{
    algorithms::interpolate::{
        discrete_sibson, interpolate, interpolate_points, InterpolateOptions, Method,
    },
    geometry::{
        predicates::{incircle, orient},
        Frame,
    },
    machine::PixelRect,
};
use pixgeo_reference::sibson::sibson;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// The definition: pixel q takes the mean of the values of the nearest
/// sites of every pixel p whose disc (radius: p's distance to its nearest
/// site, ties to the lower index) holds q's centre; NaN where none does or
/// outside the hull (the caller's check).
fn brute(sites: &[DVec2], values: &[f64], w: usize, h: usize) -> Vec<f64> {
    // Pixels a quarter of the larger side beyond the frame scatter too.
    let m = (w.max(h) as f64 * 0.25).ceil() as i64;
    let (pw, ph) = (w as i64 + 2 * m, h as i64 + 2 * m);
    let nearest: Vec<(DVec2, usize, f64)> = (0..pw * ph)
        .map(|k| {
            let p = DVec2::new((k % pw - m) as f64, (k / pw - m) as f64);
            let (s, r2) = (0..sites.len())
                .map(|s| (s, p.distance_squared(sites[s])))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
                .unwrap();
            (p, s, r2)
        })
        .collect();
    (0..w * h)
        .map(|q| {
            let at = DVec2::new((q % w) as f64, (q / w) as f64);
            let (mut n, mut s) = (0, 0.0);
            for &(from, site, r2) in &nearest {
                if from.distance_squared(at) <= r2 {
                    n += 1;
                    s += values[site];
                }
            }
            s / n as f64
        })
        .collect()
}

#[test]
fn discrete_sibson_is_its_definition_on_the_device_and_the_cpu() {
    let machine = machine();
    let (w, h) = (40usize, 30usize);
    let frame = Frame::pixels(w as u32, h as u32).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    // Random sites, and a lattice whose pixels have tied nearest sites.
    let lattice: Vec<DVec2> = (0..5)
        .flat_map(|a| (0..4).map(move |b| DVec2::new(2.0 + 9.0 * a as f64, 1.5 + 8.5 * b as f64)))
        .collect();
    for sites in [uniform(&mut rng, 25, w as f64, h as f64), lattice] {
        let values: Vec<f64> = (0..sites.len())
            .map(|k| (k as f64 * 0.37).sin() * 10.0)
            .collect();
        let on_device = discrete_sibson(Some(&machine), &sites, &values, &frame).unwrap();
        let on_cpu = discrete_sibson(None, &sites, &values, &frame).unwrap();
        assert_eq!(on_device.len(), w * h);
        let want = brute(&sites, &values, w, h);
        for k in 0..w * h {
            assert!(
                on_device[k].to_bits() == on_cpu[k].to_bits()
                    || (on_device[k].is_nan() && on_cpu[k].is_nan()),
                "pixel {k}"
            );
            if !on_device[k].is_nan() {
                assert!(
                    (on_device[k] - want[k]).abs() <= 1e-12,
                    "pixel {k}: {} {}",
                    on_device[k],
                    want[k]
                );
            }
        }
    }
}

#[test]
fn discrete_sibson_reproduces_linear_data_near_sibsons_interpolant() {
    // Sibson's interpolant reproduces linear functions exactly; the discrete
    // one within about a pixel's worth of the gradient (here 0.56 a pixel).
    let (w, h) = (120u32, 90u32);
    let frame = Frame::pixels(w, h).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let sites = uniform(&mut rng, 60, w as f64, h as f64);
    let f = |p: DVec2| 0.5 * p.x - 0.25 * p.y + 3.0;
    let values: Vec<f64> = sites.iter().map(|&p| f(p)).collect();
    let got = discrete_sibson(None, &sites, &values, &frame).unwrap();
    let mut errors = Vec::new();
    for (k, v) in got.iter().enumerate() {
        let p = DVec2::new((k % w as usize) as f64, (k / w as usize) as f64);
        if !v.is_nan() {
            errors.push((v - f(p)).abs());
        }
    }
    let outside = got.iter().filter(|v| v.is_nan()).count();
    assert!(outside > 0, "{outside} outside");
    errors.sort_by(f64::total_cmp);
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let p99 = errors[errors.len() * 99 / 100];
    let max = errors[errors.len() - 1];
    eprintln!("linear data: mean error {mean:.4}, 99th percentile {p99:.4}, largest {max:.4}");
    // Measured: 0.095, 0.58 and 1.20 (without the margin around the frame,
    // 0.20, 1.87 and 2.80); the largest near the hull's edges, where the
    // regions a pixel steals reach far.
    assert!(mean < 0.12 && p99 < 0.8 && max < 1.6, "{mean} {p99} {max}");
    assert!(discrete_sibson(None, &sites, &values[1..], &frame).is_err());
}

/// Values near the largest double are averaged as small ones are: the
/// raster of values times 2^1020 is the raster of the values, times 2^1020,
/// bit for bit, with no overflow to infinity or NaN.
#[test]
fn discrete_sibson_of_values_near_the_largest_double() {
    let frame = Frame::pixels(40, 30).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let sites = uniform(&mut rng, 12, 40.0, 30.0);
    let values: Vec<f64> = (0..12)
        .map(|i| if i % 2 == 0 { 1.5 } else { -1.75 })
        .collect();
    let huge: Vec<f64> = values.iter().map(|v| v * 2f64.powi(1020)).collect();
    let small = discrete_sibson(None, &sites, &values, &frame).unwrap();
    let large = discrete_sibson(None, &sites, &huge, &frame).unwrap();
    assert!(large.iter().any(|v| v.is_finite()));
    for (a, b) in small.iter().zip(&large) {
        assert!(
            (a.is_nan() && b.is_nan()) || (a * 2f64.powi(1020)).to_bits() == b.to_bits(),
            "{a} {b}"
        );
    }
}

fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap()
}

fn nearest(r: &BigRational) -> f64 {
    num_traits::ToPrimitive::to_f64(r).unwrap()
}

/// Every Delaunay triangle, counter-clockwise, by brute force: no site
/// strictly inside its circumcircle. Where sites are co-circular, the
/// triangles of every Delaunay triangulation.
fn delaunay_by_brute_force(sites: &[DVec2]) -> Vec<[usize; 3]> {
    let n = sites.len();
    let mut found = Vec::new();
    for a in 0..n {
        for b in 0..n {
            for c in 0..n {
                let [pa, pb, pc] = [sites[a], sites[b], sites[c]];
                if orient(pa, pb, pc) > 0.0 && sites.iter().all(|&s| incircle(pa, pb, pc, s) <= 0.0)
                {
                    found.push([a, b, c]);
                }
            }
        }
    }
    found
}

/// The linear interpolant at `q` in each of `triangles` holding it.
fn linear_in(
    triangles: &[[usize; 3]],
    sites: &[DVec2],
    values: &[f64],
    q: DVec2,
) -> Vec<BigRational> {
    let area = |u: DVec2, v: DVec2| {
        (rational(u.x) - rational(q.x)) * (rational(v.y) - rational(q.y))
            - (rational(u.y) - rational(q.y)) * (rational(v.x) - rational(q.x))
    };
    triangles
        .iter()
        .filter(|t| (0..3).all(|k| orient(sites[t[k]], sites[t[(k + 1) % 3]], q) >= 0.0))
        .map(|&[a, b, c]| {
            let w = [
                area(sites[b], sites[c]),
                area(sites[c], sites[a]),
                area(sites[a], sites[b]),
            ];
            let total = &w[0] + &w[1] + &w[2];
            let sum = &w[0] * rational(values[a])
                + &w[1] * rational(values[b])
                + &w[2] * rational(values[c]);
            sum / total
        })
        .collect()
}

/// Checks every pixel of the exact and the linear method against the
/// rational definitions; `half` is the box the Sibson oracle clips from.
/// Returns the pixels rationals settled, for both methods.
fn check_against_definitions(sites: &[DVec2], values: &[f64], frame: &Frame, half: f64) -> u64 {
    let machine = machine();
    let run = |method| {
        interpolate(
            &Backend::Device(&machine),
            sites,
            values,
            &InterpolateOptions::new(*frame, method),
        )
        .unwrap()
    };
    let (exact, linear) = (run(Method::Exact), run(Method::Linear));
    let w = frame.width as usize;
    let triangles = delaunay_by_brute_force(sites);
    let pixels = exact.values.par_iter().zip(&linear.values).enumerate();
    let inside = pixels
        .filter(|&(k, (&got, &lin))| {
            let q = frame.to_world(DVec2::new((k % w) as f64, (k / w) as f64));
            let want_linear = linear_in(&triangles, sites, values, q);
            if want_linear.is_empty() {
                assert!(lin.is_nan(), "linear, pixel {k} at {q} outside: {lin}");
            } else {
                let rounded: Vec<u64> = want_linear.iter().map(|r| nearest(r).to_bits()).collect();
                assert!(rounded.contains(&lin.to_bits()), "linear, pixel {k} at {q}");
            }
            match sibson(sites, values, q, half) {
                Some(r) => {
                    let want = nearest(&r);
                    assert_eq!(
                        got.to_bits(),
                        want.to_bits(),
                        "Sibson, {k} at {q}: {got} {want}"
                    );
                    true
                }
                // On the hull's edge Sibson's interpolant is the linear one.
                None if want_linear.is_empty() => {
                    assert!(got.is_nan(), "Sibson, pixel {k} at {q} outside: {got}");
                    false
                }
                None => {
                    assert_eq!(got.to_bits(), lin.to_bits(), "Sibson on the hull, {k}");
                    false
                }
            }
        })
        .count();
    assert!(inside > 0);
    exact.decided_exactly + linear.decided_exactly
}

#[test]
fn exact_and_linear_interpolants_are_their_definitions_correctly_rounded() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let frame = Frame::pixels(18, 14).unwrap();
    let values = |n: usize| -> Vec<f64> { (0..n).map(|k| (k as f64 * 0.71).sin() * 7.3).collect() };
    // Random sites, a few outside the frame.
    let random = uniform(&mut rng, 12, 22.0, 17.0)
        .into_iter()
        .map(|p| p - DVec2::new(2.0, 1.5))
        .collect::<Vec<_>>();
    check_against_definitions(&random, &values(12), &frame, 1e4);
    // A lattice on pixel centres a tenth apart (not a power of two):
    // co-circular quadruples, pixel centres on sites, on inner edges and on
    // the hull.
    let frame_lattice = Frame::with_bbox(16, Some(13), [0.05, 0.05, 1.65, 1.35]).unwrap();
    let lattice: Vec<DVec2> = (0..3)
        .flat_map(|a| (0..3).map(move |b| (1 + 5 * a, 1 + 5 * b)))
        .map(|(i, j)| frame_lattice.to_world(DVec2::new(i as f64, j as f64)))
        .collect();
    check_against_definitions(&lattice, &values(9), &frame_lattice, 1e40);
    // The same lattice, each site moved by an ulp or two: nearly co-circular.
    let nudged: Vec<DVec2> = lattice
        .iter()
        .enumerate()
        .map(|(k, p)| {
            DVec2::new(
                ulps(p.x, k as i64 % 3 - 1),
                ulps(p.y, (k as i64 * 5) % 3 - 1),
            )
        })
        .collect();
    check_against_definitions(&nudged, &values(9), &frame_lattice, 1e40);
    // Far magnitudes: the random sites at 1e300 and 1e-300 times a pixel.
    for unit in [1e300, 1e-300] {
        let far: Vec<DVec2> = random.iter().map(|&p| p * unit).collect();
        let bbox = [0.0, 0.0, 18.0 * unit, 14.0 * unit];
        let frame_far = Frame::with_bbox(18, Some(14), bbox).unwrap();
        check_against_definitions(&far, &values(12), &frame_far, 1e4 * unit);
    }
}

#[test]
fn rationals_settle_what_double_double_cannot() {
    // Values symmetric about zero: Sibson's interpolant is exactly 0 along
    // the axis of symmetry, which no error bound rounds, so rationals do.
    let sites = [
        (0.0, 0.0),
        (10.0, 0.0),
        (0.0, 10.0),
        (10.0, 10.0),
        (5.0, 3.0),
        (5.0, 7.0),
    ]
    .map(|(x, y)| DVec2::new(x, y));
    let values = [1.0, -1.0, 1.0, -1.0, 0.0, 0.0];
    let frame = Frame::pixels(11, 11).unwrap();
    let settled = check_against_definitions(&sites, &values, &frame, 1e4);
    assert!(settled >= 9, "{settled} pixels settled by rationals");
}

#[test]
fn interpolation_refuses_what_it_cannot_answer() {
    let machine = machine();
    let sites = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE];
    let frame = Frame::pixels(4, 4).unwrap();
    let go = |values: &[f64], method| {
        interpolate(
            &Backend::Device(&machine),
            &sites,
            values,
            &InterpolateOptions::new(frame, method),
        )
    };
    assert!(go(&[1.0, 2.0, 3.0], Method::Exact).is_err());
    assert!(go(&[1.0, 2.0, f64::NAN, 4.0], Method::Linear).is_err());
    // The same point with two values.
    let twice = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ZERO];
    let err = interpolate(
        &Backend::Device(&machine),
        &twice,
        &[1.0, 2.0, 3.0, 4.0],
        &InterpolateOptions::new(frame, Method::Exact),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("same point"), "{err}");
    // With equal values a repeated point is one.
    assert!(interpolate(
        &Backend::Device(&machine),
        &twice,
        &[1.0, 2.0, 3.0, 1.0],
        &InterpolateOptions::new(frame, Method::Exact)
    )
    .is_ok());
    let points = [DVec2::new(0.25, 0.5), DVec2::new(f64::NAN, 0.0)];
    assert!(interpolate_points(
        &Backend::Device(&machine),
        &sites,
        &[0.0; 4],
        &points,
        Method::Exact
    )
    .is_err());
    assert!(interpolate_points(
        &Backend::Device(&machine),
        &sites,
        &[0.0; 4],
        &points[..1],
        Method::Discrete
    )
    .is_err());
    // Sites on one line have no inside: every pixel is NaN.
    let line = [DVec2::ZERO, DVec2::ONE, DVec2::splat(2.0)];
    let on_line = interpolate(
        &Backend::Device(&machine),
        &line,
        &[1.0; 3],
        &InterpolateOptions::new(frame, Method::Exact),
    );
    assert!(on_line.map_or(true, |i| i.values.iter().all(|v| v.is_nan())));
}

#[test]
fn interpolants_at_points_match_the_raster() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let sites = uniform(&mut rng, 40, 30.0, 30.0);
    let values: Vec<f64> = sites.iter().map(|p| p.x * p.y).collect();
    let frame = Frame::pixels(30, 30).unwrap();
    for method in [Method::Exact, Method::Linear] {
        let raster = interpolate(
            &Backend::Device(&machine),
            &sites,
            &values,
            &InterpolateOptions::new(frame, method),
        )
        .unwrap();
        let centres: Vec<DVec2> = (0..900)
            .map(|k| DVec2::new((k % 30) as f64, (k / 30) as f64))
            .collect();
        let at = interpolate_points(
            &Backend::Device(&machine),
            &sites,
            &values,
            &centres,
            method,
        )
        .unwrap();
        for k in 0..900 {
            assert_eq!(raster.values[k].to_bits(), at.values[k].to_bits());
        }
        // Nearest and linear data: Sibson and linear reproduce a plane.
        let plane: Vec<f64> = sites.iter().map(|p| 3.0 * p.x - 2.0 * p.y + 1.0).collect();
        let flat = interpolate(
            &Backend::Device(&machine),
            &sites,
            &plane,
            &InterpolateOptions::new(frame, method),
        )
        .unwrap();
        for (k, v) in flat.values.iter().enumerate() {
            let p = centres[k];
            assert!(
                v.is_nan() || (v - (3.0 * p.x - 2.0 * p.y + 1.0)).abs() < 1e-9,
                "{k}: {v}"
            );
        }
    }
    let near = interpolate(
        &Backend::Device(&machine),
        &sites,
        &values,
        &InterpolateOptions::new(frame, Method::Nearest),
    );
    assert!(near.unwrap().values.iter().all(|v| v.is_finite()));
    // A window is the whole raster's pixels bit for bit; discrete refuses one.
    let window = PixelRect {
        x: 7,
        y: 11,
        width: 13,
        height: 5,
    };
    for method in [Method::Exact, Method::Linear, Method::Nearest] {
        let whole = interpolate(
            &Backend::Device(&machine),
            &sites,
            &values,
            &InterpolateOptions::new(frame, method),
        );
        let whole = whole.unwrap().values;
        let part = interpolate(
            &Backend::Device(&machine),
            &sites,
            &values,
            &InterpolateOptions::new(frame, method).window(Some(window)),
        );
        for (k, v) in part.unwrap().values.iter().enumerate() {
            let (i, j) = (7 + k % 13, 11 + k / 13);
            assert_eq!(v.to_bits(), whole[j * 30 + i].to_bits(), "{method:?} {k}");
        }
    }
    let discrete = Method::Discrete;
    let refused = interpolate(
        &Backend::Device(&machine),
        &sites,
        &values,
        &InterpolateOptions::new(frame, discrete).window(Some(window)),
    );
    assert!(refused.is_err());
}
