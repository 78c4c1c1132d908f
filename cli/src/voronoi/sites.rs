//! The diagram of weighted points, segments, circles and arcs (`--sites` with
//! shapes).

use super::*;

/// The diagram of weighted points, segments, circles and arcs (thesis §3.8–3.9).
pub(super) fn general_sites(args: &Args, sites: &[Site], world: &World) -> Result<()> {
    let frame = world.frame;
    refuse_window(args, "a diagram of weighted or extended sites")?;
    if args.degree.is_some() || args.order.is_some() || args.furthest || args.peel {
        bail!("--degree, --order, --furthest and --peel take unweighted points; these sites have weights or shapes");
    }
    if !matches!(args.method, Method::Auto | Method::Cones) {
        bail!("--method grid, flood and jfa take unweighted points; these sites have weights or shapes (use --method cones)");
    }
    let chosen = args.backend(false)?;
    let backend = chosen.backend();
    let options = VoronoiOptions::exact(frame)
        .metric(args.metric)
        .accuracy(args.accuracy())
        .speedup(args.speedup())
        .ties(args.ties.is_some())
        .max_tile(args.max_tile);
    let device = backend.name().to_string();
    let d = pixgeo::algorithms::voronoi::voronoi(&backend, sites, &options)?;
    let (size, geo) = ([frame.width, frame.height, 1], world.georeference());
    if let Some(p) = &args.labels {
        raster::write(p, size, &d.labels, Some(&geo))?;
    }
    if let Some(p) = &args.distance {
        raster::write(p, size, &d.distances, Some(&geo))?;
    }
    // A dot at the middle of each site's shape.
    let middles: Vec<DVec2> = sites
        .iter()
        .map(|s| {
            let (lo, hi) = s.bounds();
            0.5 * (lo + hi)
        })
        .collect();
    let source = cells::Source::Traced {
        labels: &d.labels,
        describe: &cells::site,
    };
    cells::write(args.vectors(), world, source, &middles)?;
    if let Some(p) = args.png() {
        let marks: Vec<DVec2> = middles.iter().map(|&m| frame.to_pixel(m)).collect();
        let contours = args.contours.map(|step| picture::Contours {
            distances: &d.distances,
            step: step as f32,
            line: (1.0 / frame.scale) as f32,
        });
        let rgb = picture::label_rows(&d.labels, frame.width, 0, &marks, contours);
        let mut out = PngStream::create(p, frame.width, frame.height)?;
        out.write(&rgb)?;
        out.finish()?;
    }
    if args.json {
        let summary = json!({
            "metric": args.metric.to_string(),
            "mode": mode_name(args),
            "stats": d.stats,
        });
        envelope::print_world("voronoi", &device, world, &summary)?;
    } else {
        note!(
            "{} sites, {}x{} pixels on {}: {} drawn, {:.1} ms rendering",
            d.stats.sites,
            frame.width,
            frame.height,
            d.stats.device,
            d.stats.cones,
            d.stats.render_ms
        );
    }
    Ok(())
}
