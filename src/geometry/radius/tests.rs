use super::*;

fn nearest(sites: &[DVec2], q: DVec2) -> f64 {
    sites
        .iter()
        .map(|s| (*s - q).length())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn cell_bounds_hold_every_owned_pixel() {
    let frame = Frame::pixels(61, 47).unwrap();
    // Clustered in one quarter, a regular row, duplicates, a co-circular
    // lattice and sites outside the picture.
    let mut sites: Vec<DVec2> = (0..40)
        .map(|i| DVec2::new((i * 7 % 23) as f64 * 0.9, (i * 11 % 19) as f64 * 1.1))
        .collect();
    sites.extend((0..6).map(|i| DVec2::new(10.0 * i as f64, 40.0)));
    sites.extend(
        (0..9).map(|i| DVec2::new(40.0 + 5.0 * (i % 3) as f64, 20.0 + 5.0 * (i / 3) as f64)),
    );
    sites.extend([
        DVec2::new(80.0, -10.0),
        DVec2::new(-3.0, 30.0),
        DVec2::new(30.0, 47.2),
        DVec2::new(30.0, 47.2),
    ]);
    for bin in [1.0, 2.5, 7.0, 64.0] {
        let bounds = cell_bounds(&sites, &frame, bin);
        assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, &format!("bin {bin}"));
    }
}

/// A nearest site of every pixel (under the metric) is in its tile's list,
/// and reaches the pixel.
#[test]
fn tile_candidates_list_every_owner() {
    let (frame, sites) = awkward_sites();
    for metric in [
        Metric::L2,
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.5),
        Metric::Lp(3.0),
    ] {
        for side in [1, 8, 13] {
            let tiles = tile_candidates(&sites, &frame, side, metric).unwrap();
            for y in 0..frame.height {
                for x in 0..frame.width {
                    let q = DVec2::new(x as f64, y as f64);
                    let d = sites
                        .iter()
                        .map(|s| metric.distance(*s - q))
                        .fold(f64::INFINITY, f64::min);
                    let t = (y / side) as usize * tiles.across + (x / side) as usize;
                    let list = &tiles.items[tiles.start[t] as usize..tiles.start[t + 1] as usize];
                    // Equal distances may round either way in the
                    // bounds: one of the nearest suffices.
                    let listed = list
                        .iter()
                        .map(|&i| (metric.distance(sites[i as usize] - q), i as usize))
                        .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
                    assert!(
                        listed.0 <= d * (1.0 + 1e-12),
                        "{metric} side {side}: pixel {q}: nearest listed at {}, nearest at {d}",
                        listed.0
                    );
                    assert!(
                        listed.0 <= tiles.reaches[listed.1] * (1.0 + 1e-9),
                        "{metric} side {side}: pixel {q}: site {} at {} beyond {}",
                        listed.1,
                        listed.0,
                        tiles.reaches[listed.1]
                    );
                }
            }
        }
    }
}

/// Every pixel centre lies within the radius and inside the box of each of
/// its nearest sites.
fn assert_bounds_hold_owned_pixels(
    sites: &[DVec2],
    frame: &Frame,
    bounds: &[CellBound],
    what: &str,
) {
    for y in 0..frame.height {
        for x in 0..frame.width {
            let q = DVec2::new(x as f64, y as f64);
            let d = nearest(sites, q);
            for (i, s) in sites.iter().enumerate() {
                if ((*s - q).length() - d).abs() < 1e-12 {
                    let b = &bounds[i];
                    assert!(
                        d <= b.radius + 1e-9,
                        "{what}: pixel {q} site {i} at {d} > {}",
                        b.radius
                    );
                    assert!(
                        q.cmpge(b.lo - 1e-9).all() && q.cmple(b.hi + 1e-9).all(),
                        "{what}: pixel {q} of site {i} outside {b:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn cell_bounds_from_strips_hold_every_owned_pixel() {
    // Enough sites for one triangulation per thread: a lattice across the
    // strips' edge (co-circular everywhere), random sites, duplicates and
    // a collinear run.
    let frame = Frame::pixels(120, 90).unwrap();
    let mut sites = frame.random_points(1800, 11).unwrap();
    sites.extend((0..1200).map(|i| DVec2::new((i % 40) as f64 * 3.0, 30.0 + (i / 40) as f64)));
    sites.extend_from_within(..200);
    sites.extend((0..100).map(|i| DVec2::new(i as f64 * 1.2, 45.0)));
    let bounds = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()));
    assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, "strips");
}

#[test]
fn cell_bounds_are_the_region_boxes() {
    // Every site's box is its region's (clipped by every other site) box
    // within the picture, whether from circumcentres or clipping, up to
    // the margins for rounding.
    let frame = Frame::pixels(200, 150).unwrap();
    let sites = frame.random_points(300, 3).unwrap();
    let bounds = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()));
    let picture = picture_corners(&frame);
    let mut inside = 0;
    for (i, b) in bounds.iter().enumerate() {
        let exact = clipped_bound(sites[i], sites.iter().copied(), &picture);
        assert!(
            (b.lo - exact.lo).abs().max_element() < 1e-4
                && (b.hi - exact.hi).abs().max_element() < 1e-4,
            "site {i}: {b:?} against {exact:?}"
        );
        inside += usize::from(b.lo.cmpgt(picture[0]).all() && b.hi.cmplt(picture[2]).all());
    }
    assert!(inside > 200, "only {inside} regions inside the picture");
}

#[test]
fn a_triangulation_that_is_not_delaunay_is_not_trusted() {
    // A lattice is co-circular everywhere, so its triangulation takes either
    // diagonal of each square; with its sites moved by up to 8 pixels
    // (of 10 between them), many of those triangles are wrong.
    let frame = Frame::pixels(80, 80).unwrap();
    let lattice: Vec<DVec2> = (0..64)
        .map(|i| DVec2::new((i % 8) as f64 * 10.0 + 4.0, (i / 8) as f64 * 10.0 + 4.0))
        .collect();
    let points: Vec<delaunator::Point> = lattice
        .iter()
        .map(|p| delaunator::Point { x: p.x, y: p.y })
        .collect();
    let jitter = Frame::pixels(2, 2).unwrap().random_points(64, 9).unwrap();
    let sites: Vec<DVec2> = lattice
        .iter()
        .zip(&jitter)
        .map(|(p, j)| *p + (*j - 0.5) * 8.0)
        .collect();
    let strip_of = vec![0; sites.len()];
    let strip = Strip {
        index: 0,
        strip_of: &strip_of,
        members: (0..sites.len() as u32).collect(),
        triangulation: delaunator::triangulate(&points),
    };
    let mut bounds = vec![
        CellBound {
            radius: 0.0,
            lo: DVec2::ZERO,
            hi: DVec2::ZERO
        };
        sites.len()
    ];
    let strip_bounds = strip_cell_bounds(&sites, &strip, &picture_corners(&frame));
    assert_eq!(strip_bounds.len(), sites.len());
    for (i, b) in strip_bounds {
        bounds[i as usize] = b;
    }
    assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, "jittered lattice");
}

/// A small picture with random sites, a lattice, a diagonal run, duplicates
/// and sites outside the picture.
fn awkward_sites() -> (Frame, Vec<DVec2>) {
    let frame = Frame::pixels(64, 48).unwrap();
    let mut sites = frame.random_points(60, 5).unwrap();
    sites.extend((0..12).map(|i| DVec2::new(8.0 * (i % 4) as f64, 30.0 + 6.0 * (i / 4) as f64)));
    sites.extend((0..6).map(|i| DVec2::new(40.0 + 3.0 * i as f64, 3.0 * i as f64)));
    sites.extend_from_within(..5);
    sites.extend([DVec2::new(70.0, -6.0), DVec2::new(-4.0, 20.0)]);
    (frame, sites)
}

/// Calls `f(q, i, d)` for every pixel centre q and each site i at its
/// smallest `metric` distance d (every one of them where several tie).
fn for_each_owner(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
    mut f: impl FnMut(DVec2, usize, f64),
) {
    for y in 0..frame.height {
        for x in 0..frame.width {
            let q = DVec2::new(x as f64, y as f64);
            let distances: Vec<f64> = sites.iter().map(|s| metric.distance(*s - q)).collect();
            let d = distances.iter().copied().fold(f64::INFINITY, f64::min);
            for (i, &own) in distances.iter().enumerate() {
                if own == d {
                    f(q, i, own);
                }
            }
        }
    }
}

#[test]
fn region_boxes_hold_every_owned_pixel() {
    // Under L1 and L∞ (ties included, which fill whole areas): random sites,
    // a lattice, a diagonal run, duplicates and sites outside the picture.
    let (frame, sites) = awkward_sites();
    for metric in [Metric::L1, Metric::LInf] {
        let boxes = region_boxes(&sites, &frame, metric).unwrap();
        let mut bounded = 0;
        for_each_owner(&sites, &frame, metric, |q, i, _| {
            if let Some((lo, hi)) = boxes[i] {
                assert!(
                    q.cmpge(lo - 1e-9).all() && q.cmple(hi + 1e-9).all(),
                    "{metric}: pixel {q} of site {i} outside {lo} .. {hi}"
                );
            }
        });
        for (lo, hi) in boxes.iter().flatten() {
            bounded += (lo.is_finite() && hi.is_finite()) as usize;
        }
        // The duplicates are left out.
        assert!(boxes.iter().filter(|b| b.is_none()).count() >= 5);
        // Sites inside the hull get boxes bounded on all four sides.
        assert!(
            bounded > sites.len() / 4,
            "{metric}: {bounded} bounded boxes"
        );
    }
    assert!(region_boxes(&sites, &frame, Metric::L2).is_none());
}

#[test]
fn lp_table_bounds_the_distance_within_a_percent() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let mut unit = || rng.gen::<f64>();
    for p in [0.02, 0.3, 0.5, 1.0, 1.5, 3.0, 60.0] {
        let table = LpTable::new(p);
        let metric = Metric::Lp(p);
        let mut offsets: Vec<DVec2> = (0..20000)
            .map(|_| DVec2::new(unit() - 0.5, unit() - 0.5) * 10f64.powf(6.0 * unit() - 2.0))
            .collect();
        // Axes, diagonals, tiny ratios and zero.
        offsets.extend([
            DVec2::new(3.0, 0.0),
            DVec2::new(0.0, -2.5),
            DVec2::new(7.0, 7.0),
            DVec2::new(5.0, 1e-300),
            DVec2::new(1.0, 1e-9),
            DVec2::ZERO,
        ]);
        for d in offsets {
            let key = metric.key(d);
            let (lo, hi) = (table.bound(d, false), table.bound(d, true));
            assert!(
                lo <= key && key <= hi,
                "p = {p}, {d}: {lo} <= {key} <= {hi}"
            );
            assert!(hi <= lo * 1.0081 + 1e-300, "p = {p}, {d}: {lo} .. {hi}");
        }
    }
}

#[test]
fn metric_regions_hold_every_owned_pixel() {
    // Every pixel centre lies within its nearest sites' radii (ties included),
    // measured in the metric, and inside their boxes: random sites, a
    // lattice, a diagonal run, duplicates and sites outside the picture.
    let (frame, sites) = awkward_sites();
    let metrics = [
        Metric::L2,
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.1),
        Metric::Lp(0.5),
        Metric::Lp(3.0),
        Metric::Lp(60.0),
    ];
    for metric in metrics {
        let regions = local_metric_regions(&sites, &frame, metric).unwrap();
        for_each_owner(&sites, &frame, metric, |q, i, own| {
            let Region { reach, lo, hi } = regions[i];
            assert!(
                own <= reach * (1.0 + 1e-12),
                "{metric}: pixel {q} of site {i} at {own} beyond {reach}"
            );
            assert!(
                q.cmpge(lo).all() && q.cmple(hi).all(),
                "{metric}: pixel {q} of site {i} outside its box {lo}..{hi}"
            );
        });
        // Far tighter than the stretched Euclidean cover where the stretch
        // is large (2.83 for L0.5, 2^9.5 for L0.1).
        let (cell, bin) = k_cell_and_bin(&frame, sites.len(), 1);
        let b = metric.euclidean_bounds().1;
        let stretched: f64 = k_local_radii(&sites, &frame, 1, cell, bin, metric.stretch())
            .iter()
            .map(|r| r * b)
            .sum();
        let native: f64 = regions.iter().map(|r| r.reach).sum();
        if matches!(metric, Metric::Lp(p) if p < 1.0) {
            assert!(
                native < 0.5 * stretched,
                "{metric}: {native} vs {stretched}"
            );
        }
    }
    let gauge = Metric::polygon(
        &[
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(-1.0, -1.0),
        ],
        DVec2::ZERO,
    );
    assert!(local_metric_regions(&sites, &frame, gauge.unwrap()).is_none());
}

#[test]
fn cell_bounds_are_the_region_widths() {
    // Uniform sites: the radius is the farthest corner of the exact region, which
    // lies within a pixel diagonal of the farthest owned pixel centre unless
    // the corner sits in a sliver between pixel centres.
    let frame = Frame::pixels(200, 150).unwrap();
    let sites = frame.random_points(300, 7).unwrap();
    let radii: Vec<f64> = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()))
        .iter()
        .map(|b| b.radius)
        .collect();
    let mut width = vec![0.0f64; sites.len()];
    for y in 0..150 {
        for x in 0..200 {
            let q = DVec2::new(x as f64, y as f64);
            let (i, d) = sites
                .iter()
                .map(|s| (*s - q).length())
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            width[i] = width[i].max(d);
        }
    }
    let excess: f64 = radii.iter().zip(&width).map(|(r, w)| r - w).sum();
    assert!(radii.iter().zip(&width).all(|(r, w)| r + 1e-9 >= *w));
    assert!(
        excess / (sites.len() as f64) < 1.0,
        "mean excess {}",
        excess / 300.0
    );
}

#[test]
fn tile_lists_hold_every_pixels_k_nearest() {
    // Every site among a pixel's k nearest (ties included) is in its tile's
    // list and within its radius; lists run nearest to the centre first.
    let frame = Frame::pixels(75, 52).unwrap();
    let mut sites = frame.random_points(60, 3).unwrap();
    sites.extend([DVec2::new(-9.0, 20.0), DVec2::new(30.0, 30.0)]);
    sites.extend((0..9).map(|i| DVec2::new(60.0 + (i % 3) as f64, 40.0 + (i / 3) as f64)));
    for (k, side, stretch) in [(1, 16, 1.0), (5, 16, 1.0), (12, 7, 1.0), (3, 16, 1.5)] {
        let tiles = k_tile_lists(&sites, &frame, k, side, stretch);
        for (t, list) in tiles.lists.iter().enumerate() {
            let (lo, hi) = tiles.rect(t, &frame);
            let centre = (lo + hi) * 0.5;
            let d: Vec<f64> = list
                .iter()
                .map(|&i| sites[i as usize].distance_squared(centre))
                .collect();
            assert!(
                d.windows(2).all(|w| w[0] <= w[1]),
                "k {k}: tile {t} out of order"
            );
            for y in lo.y as u32..=hi.y as u32 {
                for x in lo.x as u32..=hi.x as u32 {
                    let q = DVec2::new(x as f64, y as f64);
                    let mut by: Vec<f64> = sites.iter().map(|s| s.distance(q)).collect();
                    by.sort_by(f64::total_cmp);
                    let kth = by[k - 1];
                    for (i, s) in sites.iter().enumerate() {
                        if s.distance(q) <= kth {
                            assert!(
                                list.contains(&(i as u32)),
                                "k {k}: pixel {q}: site {i} not in tile {t}"
                            );
                            assert!(s.distance(q) <= tiles.radii[i] + 1e-9);
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn quadtree_bounds_bracket_the_width() {
    let frame = Frame::pixels(64, 64).unwrap();
    let sites: Vec<DVec2> = (0..64)
        .map(|i| DVec2::new((i % 8) as f64 * 8.0 + 3.0, (i / 8) as f64 * 8.0 + 4.0))
        .collect();
    let b = quadtree_width_bounds(&sites, &frame);
    assert_eq!(b.full_level, Some(3));
    assert_eq!(b.upper, Some(8.0 * 2f64.sqrt()));
    let width = (0..64 * 64)
        .map(|k| nearest(&sites, DVec2::new((k % 64) as f64, (k / 64) as f64)))
        .fold(0.0, f64::max);
    assert!(width <= b.upper.unwrap());
    // A quarter empty: no level below the root is full.
    let quarter: Vec<DVec2> = sites
        .iter()
        .copied()
        .filter(|p| p.x < 32.0 || p.y < 32.0)
        .collect();
    assert_eq!(quadtree_width_bounds(&quarter, &frame).full_level, Some(0));
}
