//! The k nearest by the thesis's peeling (§3.7): one cone pass a level, the
//! previous level's depths as the second depth test.

use super::*;
use crate::memory::Gather;

/// Computes every pixel's k nearest sites by the thesis's peeling (§3.7): level
/// by level, the cones are drawn against the previous level's depth z and site,
/// held in a storage buffer, and only fragments after that level in the order
/// (distance, site id) take part, so that the depth test LESS, over cones drawn
/// in the order of their ids, finds the next layer.
///
/// The thesis's second depth test keeps fragments strictly deeper than z and
/// counts equally far sites with the stencil, repeating the first one's site on
/// each of their levels; ordering ties by id instead names every equally far
/// site on a level of its own, so that the sets of the order-k diagram hold k
/// distinct sites. The levels equal [`k_nearest`]'s, ties included up to the
/// k-th level's choice among equally far sites.
///
/// Exact cones only.
pub fn k_nearest_peeled(
    machine: &Machine,
    sites: &[DVec2],
    options: &KNearestOptions,
) -> Result<KNearest> {
    with_repeats(
        Checked::new(sites)?,
        &options.frame,
        options.metric,
        options.k,
        |sites, k| {
            let options = KNearestOptions {
                k,
                ..options.clone()
            };
            peel(machine, sites, &options)
        },
    )
}

/// [`k_nearest_peeled`] of distinct sites.
fn peel(machine: &Machine, sites: &[DVec2], options: &KNearestOptions) -> Result<KNearest> {
    check_levels(machine, options)?;
    if options.accuracy != Accuracy::Exact || matches!(options.metric, Metric::Polygon(_)) {
        return Err(Error::unsupported_option("peeling draws exact cones of the L_p metrics; use the default level method for fans and polygons".into(),));
    }
    let (frame, k) = (options.frame, options.k);
    let started = Instant::now();
    let (cones, mut stats) = level_cones(machine, sites, options);
    let instances: Vec<ConeInstance> = cones
        .iter()
        .map(|&(i, p, r)| {
            ConeInstance::new(
                i,
                p.into(),
                FanShape::with_triangles(r, FOOTPRINT_CORNERS).outer_radius,
                r,
            )
        })
        .chain(std::iter::once(bytemuck::Zeroable::zeroed()))
        .gather("instances")?;
    let reach = cones.iter().map(|c| c.2).fold(1.0, f64::max) * 1.001;
    let metric = options.metric;
    let scale = metric.key_scale(reach);
    stats.bounds_ms = ms(started);

    let started = Instant::now();
    let (w, h) = (frame.width, frame.height);
    let pixels = frame.len();
    let ids = machine.image(Format::R32Uint, w, h)?;
    let depth = machine.image(Format::DepthStencil, w, h)?;
    let octagon = machine.vertex_buffer(&unit_footprint(FOOTPRINT_CORNERS))?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    // The previous level: depth -1 (below every cone) and no site.
    let mut previous = machine.readback_buffer(8 * pixels as u64)?;
    let mut words = crate::memory::filled(pixels, (-1.0f32).to_bits(), "depths")?;
    words.resize(2 * pixels, u32::MAX);
    previous.write(&words);
    let push = ConePush {
        fragment_depth_scale: scale as f32,
        ..picture_push(&frame, k, metric)
    };
    let register = RasterState {
        depth: DepthTest {
            compare: Compare::Less,
            write: true,
        },
        ..RasterState::OVERWRITE
    };
    let draw = |buffer, vertices, instances, count| ConeDraw {
        mesh: buffer,
        first_vertex: 0,
        vertex_count: vertices,
        instances,
        first_instance: 0,
        instance_count: count,
    };
    let cones_draw = draw(
        &octagon,
        FOOTPRINT_CORNERS,
        &instance_buffer,
        cones.len() as u32,
    );
    let target = Target {
        color: Some(&ids),
        depth_stencil: Some(&depth),
    };
    let params = DrawParams::default();
    let mut labels = crate::memory::filled(pixels * k as usize, u32::MAX, "labels")?;
    let mut distances = crate::memory::filled(pixels * k as usize, f32::INFINITY, "distances")?;
    let to_world = (1.0 / frame.scale) as f32;
    let unscale = (1.0 / scale) as f32;
    for level in 0..k as usize {
        machine.run(|pass| {
            let fresh = Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: None,
            };
            pass.bind_fragment_buffers(&[&previous], None)?;
            pass.begin(target, fresh)?;
            draw_cones(pass, &CONE_PEEL, &register, &params, &push, &cones_draw)?;
            pass.end()?;
            // This level becomes the next one's z and sites.
            pass.feed_fragment_buffer(&depth, &previous, 0)?;
            pass.feed_fragment_buffer(&ids, &previous, 4 * pixels as u64)
        })?;
        let rect = PixelRect::of(&ids);
        let level_ids = machine.read_u32(&ids, rect)?;
        let level_depths = machine.read_f32(&depth, rect)?;
        for (p, (id, z)) in level_ids.iter().zip(&level_depths).enumerate() {
            let at = p * k as usize + level;
            labels[at] = *id;
            if *id != u32::MAX {
                distances[at] = metric.distance_of_key((z * unscale) as f64) as f32 * to_world;
            }
        }
    }
    stats.render_ms = ms(started);
    let mut near = KNearest {
        width: w,
        height: h,
        frame,
        k,
        labels,
        distances,
        stats,
    };
    certify_levels(&mut near, sites, metric)?;
    Ok(near)
}
