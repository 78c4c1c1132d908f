//! The diagrams drawn over the whole picture at once: the k nearest, order-k
//! and furthest, each level's outputs, and their cells.

use super::*;

/// Which diagram `pixgeo voronoi` computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Ordinary,
    Degree(u32),
    Order(u32),
    Furthest,
}

/// Diagrams held whole rather than streamed in tiles: `--degree`, `--order`,
/// `--furthest`, and every diagram on the CPU (an ordinary diagram is degree 1).
pub(super) fn whole_picture(
    args: &Args,
    backend: &Backend,
    sites: &[DVec2],
    world: &World,
    accuracy: Accuracy,
    speedup: Speedup,
    kind: Kind,
) -> Result<()> {
    refuse_window(args, "this diagram")?;
    if args.ties.is_some() {
        return Err(crate::device::DrawnOnly(
            "--ties counts equal distances of ordinary diagrams on a Vulkan device".into(),
        )
        .into());
    }
    if args.max_tile.is_some() {
        bail!(
            "--max-tile applies to ordinary diagrams on a Vulkan device; this diagram is computed whole"
        );
    }
    let frame = world.frame;
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let geo = world.georeference();
    let contour_step = args.contours.map(|s| s as f32);
    // One picture of labels (and their distances for contours).
    let draw = |path: &std::path::Path, labels: &[u32], distances: &[f32]| -> Result<()> {
        let mut png = PngStream::create(path, frame.width, frame.height)?;
        let contours = contour_step.map(|step| picture::Contours {
            distances,
            step,
            line: (1.0 / frame.scale) as f32,
        });
        png.write(&picture::label_rows(
            labels,
            frame.width,
            0,
            &pixels,
            contours,
        ))?;
        png.finish()?;
        Ok(())
    };

    let summary = if kind == Kind::Furthest {
        if accuracy != Accuracy::Exact {
            bail!("the furthest-site diagram is computed exactly; drop --mode");
        }
        let f = higher_order::furthest(backend, sites, &frame, args.metric)?;
        let size = [frame.width, frame.height, 1];
        if let Some(path) = &args.labels {
            raster::write(path, size, &f.labels, Some(&geo))?;
        }
        if let Some(path) = &args.distance {
            raster::write(path, size, &f.distances, Some(&geo))?;
        }
        if let Some(path) = args.png() {
            draw(path, &f.labels, &f.distances)?;
        }
        let source = cells::Source::Traced {
            labels: &f.labels,
            describe: &cells::site,
        };
        cells::write(args.vectors(), world, source, sites)?;
        json!({
            "kind": "furthest",
            "sites": sites.len(),
            "hull": f.hull.len(),
        })
    } else {
        let (k, order) = match kind {
            Kind::Order(k) => (k, true),
            Kind::Degree(k) => (k, false),
            _ => (1, false),
        };
        let progress = match backend {
            Backend::Cpu => Progress::new("voronoi: growing the sites", args.json),
            Backend::Device(_) => Progress::working("voronoi: drawing the levels", args.json),
        };
        let options = KNearestOptions::exact(frame, k)
            .metric(args.metric)
            .accuracy(accuracy)
            .speedup(speedup)
            .control(progress.control());
        let d = match backend {
            Backend::Device(machine) if args.peel => {
                higher_order::k_nearest_peeled(machine, sites, &options)?
            }
            _ => higher_order::k_nearest(backend, sites, &options)?,
        };
        drop(progress);
        // (rows, columns) for an ordinary diagram, (rows, columns, k) else.
        let bands = if kind == Kind::Ordinary { 1 } else { k };
        let size = [frame.width, frame.height, bands];
        if let Some(path) = &args.labels {
            let labels = if order {
                d.order_sets()
            } else {
                d.labels.clone()
            };
            raster::write(path, size, &labels, Some(&geo))?;
        }
        if let Some(path) = &args.distance {
            raster::write(path, size, &d.distances, Some(&geo))?;
        }
        write_level_cells(args, world, backend, sites, &d, kind)?;
        if let Some(path) = args.png() {
            let last = d.level_distances(k - 1);
            if order {
                // One colour per set: the set's hash picks it.
                let sets: Vec<u32> = d
                    .order_sets()
                    .chunks_exact(k as usize)
                    .map(set_colour_key)
                    .collect();
                draw(path, &sets, &last)?;
            } else {
                draw(path, &d.level_labels(k - 1), &last)?;
                if args.each_level {
                    for l in 0..k {
                        let level = level_path(path, l + 1);
                        draw(&level, &d.level_labels(l), &d.level_distances(l))?;
                        crate::wrote([Some(level.as_path())]);
                    }
                }
            }
        }
        // The envelope names the device, once.
        let mut stats = serde_json::to_value(&d.stats)?;
        if let Some(fields) = stats.as_object_mut() {
            fields.remove("device");
        }
        json!({
            "kind": match kind {
                Kind::Ordinary => "ordinary",
                Kind::Order(_) => "order",
                _ => "degree",
            },
            "levels": k,
            "metric": args.metric.to_string(),
            "mode": mode_name(args),
            "speedup": speedup,
            "stats": stats,
        })
    };
    if args.json {
        envelope::print_world("voronoi", backend.name(), world, &summary)?;
    } else {
        note!(
            "{} sites, {}x{} pixels on {}",
            sites.len(),
            frame.width,
            frame.height,
            backend.name()
        );
    }
    Ok(())
}

/// The cells of a diagram held whole: exact for the Euclidean diagram of
/// points on a Vulkan device; otherwise traced from the labels of the K-th
/// level (`--degree`), or of each set's region (`--order`).
fn write_level_cells(
    args: &Args,
    world: &World,
    backend: &Backend,
    sites: &[DVec2],
    d: &higher_order::KNearest,
    kind: Kind,
) -> Result<()> {
    let outputs = args.vectors();
    if !outputs.any() {
        return Ok(());
    }
    if (kind, args.metric) == (Kind::Ordinary, Metric::L2) {
        let source = cells::Source::Exact { backend, sites };
        return cells::write(outputs, world, source, sites);
    }
    let k = d.k;
    match kind {
        Kind::Order(_) => {
            // Each set of K sites, numbered in the order first seen.
            let mut sets: Vec<Vec<u32>> = Vec::new();
            let mut number: std::collections::HashMap<Vec<u32>, u32> = Default::default();
            let labels: Vec<u32> = d
                .order_sets()
                .chunks_exact(k as usize)
                .map(|set| {
                    *number.entry(set.to_vec()).or_insert_with(|| {
                        sets.push(set.to_vec());
                        sets.len() as u32 - 1
                    })
                })
                .collect();
            let describe = |l: u32| {
                let mut m = serde_json::Map::new();
                m.insert("sites".into(), json!(sets[l as usize]));
                m
            };
            let source = cells::Source::Traced {
                labels: &labels,
                describe: &describe,
            };
            cells::write(outputs, world, source, sites)
        }
        _ => {
            let describe = |l: u32| {
                let mut m = cells::site(l);
                m.insert("level".into(), json!(k));
                m
            };
            let labels = d.level_labels(k - 1);
            let source = cells::Source::Traced {
                labels: &labels,
                describe: &describe,
            };
            cells::write(outputs, world, source, sites)
        }
    }
}

/// A colour key for a set of site ids (FNV-1a over the ids); "no site" only for
/// an empty set.
fn set_colour_key(set: &[u32]) -> u32 {
    if set.first() == Some(&u32::MAX) {
        return u32::MAX;
    }
    let hash = set.iter().fold(0x811c_9dc5u32, |h, id| {
        id.to_le_bytes()
            .iter()
            .fold(h, |h, b| (h ^ *b as u32).wrapping_mul(0x0100_0193))
    });
    // Keep clear of the "no site" value.
    hash % (u32::MAX - 1)
}

/// `picture.png` -> `picture-3.png`.
fn level_path(path: &std::path::Path, level: u32) -> PathBuf {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("level");
    let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("png");
    path.with_file_name(format!("{stem}-{level}.{ext}"))
}
