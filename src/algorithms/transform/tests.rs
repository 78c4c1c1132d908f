//! The transforms against brute force: every pixel against every feature pixel,
//! on random, sparse, dense, lattice and degenerate masks, under every metric.

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;

/// Every pixel's smallest distance to a feature pixel, by brute force.
fn brute_force(mask: &[bool], w: usize, metric: Metric, [sy, sx]: [f64; 2]) -> Vec<f64> {
    let features: Vec<usize> = (0..mask.len()).filter(|&i| mask[i]).collect();
    (0..mask.len())
        .map(|p| {
            features
                .iter()
                .map(|&f| {
                    let dx = (p % w) as f64 - (f % w) as f64;
                    let dy = (p / w) as f64 - (f / w) as f64;
                    metric.distance(DVec2::new(dx * sx, dy * sy))
                })
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

fn masks() -> Vec<(String, usize, usize, Vec<bool>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut out = Vec::new();
    for (w, h) in [(1, 1), (1, 9), (9, 1), (17, 13), (32, 24)] {
        for density in [0.0, 0.02, 0.3, 0.9, 1.0] {
            let mask = (0..w * h).map(|_| rng.gen_bool(density)).collect();
            out.push((format!("{w}x{h} random {density}"), w, h, mask));
        }
        let mut single = vec![false; w * h];
        single[rng.gen_range(0..w * h)] = true;
        out.push((format!("{w}x{h} single"), w, h, single));
        let lattice = (0..w * h)
            .map(|i| i % w % 4 == 1 && i / w % 3 == 2)
            .collect();
        out.push((format!("{w}x{h} lattice"), w, h, lattice));
        let diagonal = (0..w * h).map(|i| i % w == i / w).collect();
        out.push((format!("{w}x{h} diagonal"), w, h, diagonal));
    }
    // Wide rows, and columns over several strips of the column pass, some
    // with no feature in a strip.
    for (w, h) in [(600, 3), (513, 5), (7, 100)] {
        for density in [0.004, 0.2] {
            let mask = (0..w * h).map(|_| rng.gen_bool(density)).collect();
            out.push((format!("{w}x{h} random {density}"), w, h, mask));
        }
    }
    out
}

fn metrics() -> Vec<Metric> {
    let hexagon: Vec<DVec2> = (0..6)
        .map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / 6.0 + 0.2) * 1.5)
        .collect();
    vec![
        Metric::L2,
        Metric::L1,
        Metric::LInf,
        Metric::Lp(3.0),
        Metric::Lp(1.5),
        Metric::Lp(0.5),
        Metric::polygon(&hexagon, DVec2::new(0.1, -0.2)).unwrap(),
    ]
}

/// Distances within a relative 1e-12 of brute force (L_p's powers round),
/// each pixel's feature a feature pixel at that distance, and the distances
/// alone those distances to the bit.
fn check(name: &str, mask: &[bool], w: usize, h: usize, options: &TransformOptions) {
    let t = distance_transform(mask, w as u32, h as u32, options).unwrap();
    let alone = distances_only(mask, w as u32, h as u32, options).unwrap();
    let bits = |d: &[f64]| d.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&alone), bits(&t.distances), "{name}: distances alone");
    let expected = brute_force(mask, w, options.metric, options.sampling);
    let exact = matches!(options.metric, Metric::L2 | Metric::L1 | Metric::LInf);
    for (p, (&d, &e)) in t.distances.iter().zip(&expected).enumerate() {
        let what = format!(
            "{name}, {}, {:?}: pixel {p}",
            options.metric, options.sampling
        );
        if e.is_infinite() {
            assert!(d.is_infinite() && t.feature_rows[p] == -1, "{what}");
            assert_eq!(t.feature_columns[p], -1, "{what}");
            continue;
        }
        let close = if exact {
            d == e
        } else {
            (d - e).abs() <= 1e-12 * e.max(1.0)
        };
        assert!(close, "{what}: {d} against {e}");
        let (row, column) = (t.feature_rows[p] as usize, t.feature_columns[p] as usize);
        assert!(mask[row * w + column], "{what}: not a feature");
    }
}

#[test]
fn every_metric_matches_brute_force() {
    for (name, w, h, mask) in masks() {
        for metric in metrics() {
            check(&name, &mask, w, h, &TransformOptions::new().metric(metric));
        }
    }
}

#[test]
fn separable_metrics_take_anisotropic_sampling() {
    for (name, w, h, mask) in masks() {
        for metric in [Metric::L2, Metric::L1, Metric::LInf, Metric::Lp(3.0)] {
            for sampling in [[2.0, 1.0], [0.3, 1.7], [1.0, 1e-3]] {
                let options = TransformOptions::new().metric(metric).sampling(sampling);
                check(&name, &mask, w, h, &options);
            }
        }
    }
}

#[test]
fn equal_sampling_scales_other_metrics() {
    let (name, w, h, mask) = masks().swap_remove(25);
    for metric in &metrics()[5..] {
        let options = TransformOptions::new().metric(*metric).sampling([2.5, 2.5]);
        check(&name, &mask, w, h, &options);
    }
}

#[test]
fn large_exponents_keep_their_keys_in_range() {
    // 400 * log2(57) passes f64's exponent: these take the grown diagram.
    let (name, w, h, mask) = masks().swap_remove(26);
    for metric in [Metric::Lp(400.0), Metric::Lp(80.0)] {
        check(&name, &mask, w, h, &TransformOptions::new().metric(metric));
    }
    let error = distance_transform(
        &mask,
        w as u32,
        h as u32,
        &TransformOptions::new()
            .metric(Metric::Lp(400.0))
            .sampling([1.0, 2.0]),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("equal sampling"), "{error}");
}

#[test]
fn bad_input_is_refused() {
    let mask = vec![true; 6];
    let refused = |w, h, options: TransformOptions| {
        distance_transform(&mask, w, h, &options)
            .unwrap_err()
            .to_string()
    };
    assert!(refused(4, 2, TransformOptions::new()).contains("needs 8 values"));
    assert!(refused(0, 6, TransformOptions::new()).contains("raster"));
    for sampling in [
        [0.0, 1.0],
        [1.0, f64::NAN],
        [-1.0, 1.0],
        [f64::INFINITY, 1.0],
    ] {
        let error = refused(3, 2, TransformOptions::new().sampling(sampling));
        assert!(error.contains("sampling"), "{error}");
    }
    let error = refused(3, 2, TransformOptions::new().metric(Metric::Lp(-2.0)));
    assert!(error.contains("p > 0"), "{error}");
    let error = refused(
        3,
        2,
        TransformOptions::new()
            .metric(Metric::Lp(0.5))
            .sampling([1.0, 2.0]),
    );
    assert!(error.contains("equal sampling"), "{error}");
}

/// Components by flood fill from each unlabelled feature pixel in scan order.
fn flood_components(mask: &[bool], w: usize) -> Vec<u32> {
    let h = mask.len() / w;
    let mut labels = vec![NO_COMPONENT; mask.len()];
    let mut next = 0;
    for start in 0..mask.len() {
        if !mask[start] || labels[start] != NO_COMPONENT {
            continue;
        }
        let mut stack = vec![start];
        labels[start] = next;
        while let Some(p) = stack.pop() {
            let (x, y) = ((p % w) as i64, (p / w) as i64);
            for (dx, dy) in (-1..=1).flat_map(|dx| (-1..=1).map(move |dy| (dx, dy))) {
                let (qx, qy) = (x + dx, y + dy);
                if qx < 0 || qy < 0 || qx >= w as i64 || qy >= h as i64 {
                    continue;
                }
                let q = qy as usize * w + qx as usize;
                if mask[q] && labels[q] == NO_COMPONENT {
                    labels[q] = next;
                    stack.push(q);
                }
            }
        }
        next += 1;
    }
    labels
}

#[test]
fn components_match_a_flood_fill_and_pixels_take_their_nearest() {
    for (name, w, h, mask) in masks() {
        let (labels, count) = components(&mask, w).unwrap();
        let expected = flood_components(&mask, w);
        assert_eq!(labels, expected, "{name}");
        assert_eq!(
            count,
            expected
                .iter()
                .filter(|&&l| l != NO_COMPONENT)
                .max()
                .map_or(0, |m| m + 1),
            "{name}"
        );
        let t = distance_transform(&mask, w as u32, h as u32, &TransformOptions::new()).unwrap();
        let nearest = t.at_nearest(&labels, NO_COMPONENT);
        for (p, (&component, &d)) in nearest.iter().zip(&t.distances).enumerate() {
            // The component of some feature pixel at the smallest distance.
            let at = |f: usize| {
                let (dx, dy) = (
                    (p % w) as f64 - (f % w) as f64,
                    (p / w) as f64 - (f / w) as f64,
                );
                (dx * dx + dy * dy).sqrt()
            };
            let found = (0..w * h).any(|f| mask[f] && labels[f] == component && at(f) == d);
            let none = component == NO_COMPONENT && d.is_infinite();
            assert!(found || none, "{name}: pixel {p}");
        }
    }
}

/// A `w` x `h` raster whose features are its border: a bar of free pixels.
fn bar(w: usize, h: usize) -> Vec<bool> {
    (0..w * h)
        .map(|p| p % w == 0 || p % w == w - 1 || p / w == 0 || p / w == h - 1)
        .collect()
}

#[test]
fn a_bars_axis_is_its_middle_row() {
    let w = 48;
    for metric in [Metric::L2, Metric::L1, Metric::LInf] {
        for sampling in [[1.0, 1.0], [2.0, 1.0], [1.0, 3.0]] {
            // 9 free rows have one middle row; 10 have two, and the upper is
            // taken on the tie.
            for (h, middle) in [(11, 5), (12, 5)] {
                let options = TransformOptions::new().metric(metric).sampling(sampling);
                let t = distance_transform(&bar(w, h), w as u32, h as u32, &options).unwrap();
                let axis = medial_axis(&t, &options, Pruning::default()).unwrap();
                // Away from the ends, whose corners grow bisectors of their own.
                for x in h..w - h {
                    let column: Vec<usize> = (0..h).filter(|&y| axis[y * w + x]).collect();
                    assert_eq!(
                        column,
                        [middle],
                        "{metric}, {sampling:?}, {h} rows, column {x}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_disks_axis_is_its_centre() {
    let (w, c, r) = (81, 40i64, 36i64);
    let mask: Vec<bool> = (0..w * w)
        .map(|p| {
            let (dx, dy) = ((p % w) as i64 - c, (p / w) as i64 - c);
            dx * dx + dy * dy > r * r
        })
        .collect();
    let options = TransformOptions::new();
    let t = distance_transform(&mask, w as u32, w as u32, &options).unwrap();
    let axis = medial_axis(&t, &options, Pruning::default()).unwrap();
    let on: Vec<(i64, i64)> = (0..w * w)
        .filter(|&p| axis[p])
        .map(|p| ((p % w) as i64 - c, (p / w) as i64 - c))
        .collect();
    assert!(on.contains(&(0, 0)), "{on:?}");
    // The centre, and a few lone pixels near the rim where lattice points of
    // the digital circle tie at a distance of about 4.
    let lone = |&(x, y): &(i64, i64)| {
        let touching = on
            .iter()
            .filter(|&&(u, v)| (u - x).abs() <= 1 && (v - y).abs() <= 1)
            .count();
        touching == 1 && x * x + y * y >= 30 * 30
    };
    assert!(
        on.iter()
            .all(|&(x, y)| x * x + y * y <= 4 * 4 || lone(&(x, y))),
        "{on:?}"
    );
    assert!(on.iter().filter(|p| lone(p)).count() <= 4, "{on:?}");
    // Without pruning, a digital circle's notches grow spurs too.
    let spurs = medial_axis(
        &t,
        &options,
        Pruning {
            length: 0.0,
            angle: 0.0,
        },
    )
    .unwrap();
    assert!(spurs.iter().zip(&axis).all(|(&s, &a)| s || !a));
    assert!(spurs.iter().filter(|&&s| s).count() > 4 * on.len());
}

/// The holes of `set` (row-major, `w` wide): the 4-connected pieces of the
/// rest that do not reach the raster's edge.
fn holes(set: &[bool], w: usize) -> usize {
    let h = set.len() / w;
    let mut seen = vec![false; set.len()];
    let mut count = 0;
    for start in (0..set.len()).filter(|&p| !set[p]) {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut stack, mut edge) = (vec![start], false);
        while let Some(p) = stack.pop() {
            let (x, y) = (p % w, p / w);
            edge |= x == 0 || y == 0 || x + 1 == w || y + 1 == h;
            let beside = [
                (x > 0).then(|| p - 1),
                (x + 1 < w).then(|| p + 1),
                (y > 0).then(|| p - w),
                (y + 1 < h).then(|| p + w),
            ];
            for q in beside.into_iter().flatten() {
                if !set[q] && !seen[q] {
                    seen[q] = true;
                    stack.push(q);
                }
            }
        }
        count += !edge as usize;
    }
    count
}

/// Pruning keeps topology: every free region with two features at all keeps
/// one connected axis with a loop around each of its holes, under every
/// metric, on random, lattice and diagonal masks and rings.
#[test]
fn axes_keep_each_regions_pieces_and_loops() {
    let mut cases = masks();
    // Squares with holes, one inside another.
    for (w, rings) in [(12, 1), (21, 2)] {
        let mask = (0..w * w)
            .map(|p| {
                let (x, y) = ((p % w) as i64, (p / w) as i64);
                let c = (w / 2) as i64;
                let d = (x - c).abs().max((y - c).abs());
                d == 0 || (rings == 2 && d == 5) || d as usize >= w / 2
            })
            .collect();
        cases.push((format!("{rings} rings"), w, w, mask));
    }
    for (name, w, h, mask) in cases {
        for metric in [Metric::L2, Metric::L1, Metric::LInf] {
            let options = TransformOptions::new().metric(metric);
            let t = distance_transform(&mask, w as u32, h as u32, &options).unwrap();
            let axis = medial_axis(&t, &options, Pruning::default()).unwrap();
            let free: Vec<bool> = mask.iter().map(|&m| !m).collect();
            let (regions, count) = components(&free, w).unwrap();
            for r in 0..count {
                let region: Vec<bool> = regions.iter().map(|&c| c == r).collect();
                let mine: Vec<bool> = (0..w * h).map(|p| region[p] && axis[p]).collect();
                let features: std::collections::HashSet<_> = (0..w * h)
                    .filter(|&p| region[p])
                    .map(|p| (t.feature_rows[p], t.feature_columns[p]))
                    .collect();
                let name = format!("{name}, {metric}, region {r}");
                if features.len() < 2 {
                    assert!(!mine.contains(&true), "{name}: an axis of one feature");
                    continue;
                }
                assert_eq!(components(&mine, w).unwrap().1, 1, "{name}: not one piece");
                assert_eq!(holes(&mine, w), holes(&region, w), "{name}: loops");
            }
            assert!(axis.iter().zip(&mask).all(|(&a, &m)| !(a && m)), "{name}");
        }
    }
}

/// The axis of a picture whose `#` are free pixels, and the picture's width.
fn axis_of(picture: &[&str]) -> (Vec<bool>, usize) {
    let w = picture[0].len();
    let mask: Vec<bool> = picture
        .iter()
        .flat_map(|r| r.bytes().map(|b| b != b'#'))
        .collect();
    let options = TransformOptions::new();
    let t = distance_transform(&mask, w as u32, picture.len() as u32, &options).unwrap();
    (medial_axis(&t, &options, Pruning::default()).unwrap(), w)
}

fn pixels(picture: &[&str]) -> Vec<bool> {
    picture
        .iter()
        .flat_map(|r| r.bytes().map(|b| b == b'#'))
        .collect()
}

/// Thin shapes keep an axis along them, where length pruning alone had left
/// none; scikit-image's test shapes give its axis less the tips it grows into
/// square corners, which pruning takes, and keep the loop around a hole.
#[test]
fn thin_shapes_and_scikit_images_shapes() {
    let pad = |rows: usize, columns: usize| -> Vec<String> {
        (0..rows + 4)
            .map(|y| {
                (0..columns + 4)
                    .map(
                        |x| match (2..rows + 2).contains(&y) && (2..columns + 2).contains(&x) {
                            true => '#',
                            false => '.',
                        },
                    )
                    .collect()
            })
            .collect()
    };
    for (rows, columns, at_least) in [(3, 9, 5), (1, 3, 1), (3, 5, 2)] {
        let picture = pad(rows, columns);
        let picture: Vec<&str> = picture.iter().map(|r| r.as_str()).collect();
        let (axis, w) = axis_of(&picture);
        let on: Vec<usize> = (0..axis.len()).filter(|&p| axis[p]).collect();
        assert!(on.len() >= at_least, "{rows}x{columns}: {on:?}");
        // All in the middle row, one run.
        assert!(
            on.iter().all(|&p| p / w == 2 + rows / 2),
            "{rows}x{columns}: {on:?}"
        );
        assert!(
            on.windows(2).all(|p| p[1] == p[0] + 1),
            "{rows}x{columns}: {on:?}"
        );
    }
    // scikit-image's TestMedialAxis: the rectangle, with a hole, and its
    // expected axes.
    let rectangle = [
        "...............",
        ".#############.",
        ".#############.",
        ".#############.",
        ".#############.",
        ".#############.",
        ".#############.",
        ".#############.",
        "...............",
    ];
    let theirs = [
        "...............",
        ".#...........#.",
        "..#.........#..",
        "...#.......#...",
        "....#######....",
        "...#.......#...",
        "..#.........#..",
        ".#...........#.",
        "...............",
    ];
    let mut holed = rectangle;
    holed[4] = ".###.......###.";
    let theirs_holed = [
        "...............",
        ".#...........#.",
        "..###########..",
        "..#.........#..",
        "..#.........#..",
        "..#.........#..",
        "..###########..",
        ".#...........#.",
        "...............",
    ];
    for (picture, expected, loops) in [(rectangle, theirs, 0), (holed, theirs_holed, 1)] {
        let (axis, w) = axis_of(&picture);
        let expected = pixels(&expected);
        assert!(
            axis.iter().zip(&expected).all(|(&a, &e)| !a || e),
            "{axis:?}"
        );
        // Less only the corner tips: the two pixels nearest each corner.
        let missing = expected
            .iter()
            .zip(&axis)
            .filter(|&(&e, &a)| e && !a)
            .count();
        assert!(missing <= 8, "{missing}");
        assert_eq!(components(&axis, w).unwrap().1, 1);
        assert_eq!(holes(&axis, w), loops);
    }
    // Their thick vertical line: the middle column.
    let line: Vec<&str> = std::iter::repeat_n("..###....", 9).collect();
    let (axis, w) = axis_of(&line);
    assert!((0..axis.len()).all(|p| axis[p] == (p % w == 3)), "{axis:?}");
}

#[test]
fn bad_pruning_is_refused() {
    let options = TransformOptions::new();
    let t = distance_transform(&bar(8, 8), 8, 8, &options).unwrap();
    for (length, angle) in [(-1.0, 45.0), (f64::NAN, 45.0), (4.0, 181.0), (4.0, -1.0)] {
        let err = medial_axis(&t, &options, Pruning { length, angle }).unwrap_err();
        assert!(err.to_string().contains("pruning"), "{err}");
    }
}

#[test]
fn progress_counts_every_row_of_every_pass() {
    let (w, h) = (600usize, 70usize);
    let mut features = vec![false; w * h];
    features[5 * w + 7] = true;
    let told = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let tell = told.clone();
    let report = move |done: u64, total: u64| tell.lock().unwrap().push((done, total));
    let options = TransformOptions::new().control(crate::Control::new().progress(report));
    distance_transform(&features, w as u32, h as u32, &options).unwrap();
    let told = told.lock().unwrap().clone();
    // The rows of each pass.
    let total = 2 * h as u64;
    assert!(
        told.iter().all(|&(d, t)| t == total && d <= total),
        "{told:?}"
    );
    assert_eq!(told.iter().map(|t| t.0).max(), Some(total));
}
