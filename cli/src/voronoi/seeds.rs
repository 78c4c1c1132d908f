//! Label maps of the sites' pixels for flooding and jump flooding (`--method
//! flood`, `--method jfa`).

use super::*;

/// `--method flood` and `--method jfa`: label maps of the sites' pixels.
pub(super) fn seed_pixels(args: &Args, sites: &[DVec2], world: &World) -> Result<()> {
    let frame = world.frame;
    refuse_window(args, "a flooded diagram")?;
    args.refuse_cone_options("flooding")?;
    if args.degree.is_some() || args.order.is_some() || args.furthest || args.ties.is_some() {
        bail!("--method flood and jfa make the nearest-site map only (no --degree, --order, --furthest or --ties)");
    }
    if args.metric != Metric::L2 {
        bail!("--method flood and jfa are Euclidean");
    }
    let seeds = pixgeo::algorithms::flooding::seeds_of(&frame, sites)?;
    let machine = crate::device::machine_on(args.device.as_deref())?;
    let started = std::time::Instant::now();
    let (labels, stats) = match args.method {
        Method::Flood => {
            let f =
                pixgeo::algorithms::flooding::flood(&machine, frame.width, frame.height, &seeds)?;
            (f.labels, serde_json::to_value(&f.stats)?)
        }
        _ => (
            pixgeo::algorithms::flooding::jump_flood(&machine, frame.width, frame.height, &seeds)?,
            json!({}),
        ),
    };
    let elapsed = started.elapsed().as_secs_f64() * 1e3;
    let (w, h) = (frame.width, frame.height);
    // Distances in world units from each pixel centre to its region's site.
    let distances: Vec<f32> = labels
        .iter()
        .enumerate()
        .map(|(k, &l)| {
            let q = frame.to_world(DVec2::new((k as u32 % w) as f64, (k as u32 / w) as f64));
            sites
                .get(l as usize)
                .map_or(f32::INFINITY, |s| s.distance(q) as f32)
        })
        .collect();
    let geo = world.georeference();
    if let Some(path) = &args.labels {
        raster::write(path, [w, h, 1], &labels, Some(&geo))?;
    }
    if let Some(path) = &args.distance {
        raster::write(path, [w, h, 1], &distances, Some(&geo))?;
    }
    let source = cells::Source::Traced {
        labels: &labels,
        describe: &cells::site,
    };
    cells::write(args.vectors(), world, source, sites)?;
    if let Some(path) = args.png() {
        let contours = args.contours.map(|step| picture::Contours {
            distances: &distances,
            step: step as f32,
            line: (1.0 / frame.scale) as f32,
        });
        let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
        let mut png = PngStream::create(path, w, h)?;
        png.write(&picture::label_rows(&labels, w, 0, &pixels, contours))?;
        png.finish()?;
    }
    let method = if args.method == Method::Flood {
        "flood"
    } else {
        "jfa"
    };
    if args.json {
        let summary = json!({
            "method": method,
            "sites": sites.len(),
            "total_ms": elapsed,
            "stats": stats,
        });
        envelope::print_world("voronoi", machine.device_name(), world, &summary)?;
    } else {
        note!(
            "{method}: {} sites on {w}x{h} pixels in {elapsed:.1} ms",
            sites.len()
        );
    }
    Ok(())
}
