//! The furthest-site diagram (§3.7.1): the upper envelope of the cones of the
//! sites that may own furthest regions.

use super::*;
use crate::memory::Gather;
use crate::Backend;

/// The sites that may own furthest regions: for a convex unit ball (L_p with
/// p >= 1, convex polygons) a distance is a convex function, largest over the
/// sites at a corner of their convex hull; otherwise every site may.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn furthest_candidates(sites: &[DVec2], hull: &[u32], metric: Metric) -> Vec<u32> {
    if metric.is_convex() {
        hull.to_vec()
    } else {
        (0..sites.len() as u32).collect()
    }
}

/// The furthest-site diagram (thesis §3.7.1) with its distances.
#[derive(Clone, Debug)]
pub struct Furthest {
    pub width: u32,
    pub height: u32,
    /// The picture: [`Frame::to_world`] maps its pixels to world points.
    pub frame: Frame,
    /// Furthest site per pixel, row-major.
    pub labels: Vec<u32>,
    /// Distance to it in world units.
    pub distances: Vec<f32>,
    /// Indices of the sites drawn: the vertices of the convex hull (every site
    /// for metrics whose balls are not convex: L_p with p < 1, star polygons).
    pub hull: Vec<u32>,
}

/// Computes the furthest-site diagram of `sites` (world coordinates) on
/// `frame`: drawn as the upper envelope on a device, searched on the CPU
/// (`cpu::furthest_checked`); both proved exactly, the same
/// labels and distances.
pub fn furthest(
    backend: &Backend,
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Result<Furthest> {
    furthest_checked(backend, Checked::new(sites)?, frame, metric)
}

/// [`furthest`] of sites checked where they entered.
pub(crate) fn furthest_checked(
    backend: &Backend,
    sites: Checked<'_>,
    frame: &Frame,
    metric: Metric,
) -> Result<Furthest> {
    let Some(machine) = backend.machine() else {
        return super::cpu::furthest_checked(sites, frame, metric);
    };
    let drawn = draw_furthest(machine, sites, frame, metric, true)?;
    let sites = sites.sites();
    let ids = drawn.ids.as_ref().expect("labels were asked for");
    let rect = PixelRect::of(ids);
    let labels = machine.read_u32(ids, rect)?;
    exactly_furthest(sites, frame, metric, labels, drawn.owners)
}

/// The sites that may own furthest regions, each the first index of its
/// position, so that equal distances go to the smaller index.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn furthest_owners(sites: &[DVec2], metric: Metric) -> Vec<u32> {
    let first = first_of_each(sites);
    let points: Vec<DVec2> = first.iter().map(|&i| sites[i as usize]).collect();
    furthest_candidates(&points, &convex_hull(&points), metric)
        .into_iter()
        .map(|k| first[k as usize])
        .collect()
}

/// The furthest-site diagram from `proposed` labels (the device's or the
/// CPU's in doubles), each proved or mended exactly: the same labels and
/// distances on every route, equal distances to the smaller index.
pub(crate) fn exactly_furthest(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
    mut labels: Vec<u32>,
    hull: Vec<u32>,
) -> Result<Furthest> {
    let mut distances =
        crate::memory::filled(labels.len(), 0.0f32, "the furthest sites' distances")?;
    Certifier::new(sites, frame, metric)?.furthest(
        &furthest_owners(sites, metric),
        &mut labels,
        &mut distances,
    )?;
    Ok(Furthest {
        width: frame.width,
        height: frame.height,
        frame: *frame,
        labels,
        distances,
        hull,
    })
}

/// The upper envelope of the sites' cones, still on the device.
pub(crate) struct DrawnFurthest {
    /// Furthest site per pixel, when asked for.
    pub ids: Option<Image>,
    /// The envelope's keys times `scale`.
    pub depth: Image,
    pub scale: f64,
    /// The sites drawn.
    pub owners: Vec<u32>,
}

/// The distance (world units) a depth of keys times `scale` stands for.
pub(crate) fn distance_of_depth(metric: Metric, scale: f64, z: f32, frame: &Frame) -> f64 {
    metric.distance_of_key(z as f64 / scale) / frame.scale
}

/// Draws the upper envelope of the cones of `sites` under `metric` (only the
/// sites that can own a region).
pub(crate) fn draw_furthest(
    machine: &Machine,
    sites: Checked<'_>,
    frame: &Frame,
    metric: Metric,
    labels: bool,
) -> Result<DrawnFurthest> {
    let sites = sites.sites();
    frame.check()?;
    let side = machine.max_picture_side();
    if frame.width > side || frame.height > side {
        return Err(Error::out_of_range(format!(
            "the upper envelope is drawn in one image of at most {side}x{side} pixels on this device"
        )));
    }
    let owners = furthest_candidates(sites, &convex_hull(sites), metric);
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).gather("pixels")?;
    // A polygon's distance is drawn exactly by the fan over the polygon; the other
    // metrics' cones evaluate the distance per fragment.
    let (program, unit) = match metric {
        Metric::Polygon(g) => (&CONE_FAN, unit_fan_over(&g.vertices, 1.0)),
        _ => (&CONE_EXACT, unit_footprint(FOOTPRINT_CORNERS)),
    };
    // Upside-down cones reach every pixel: a site's furthest region may lie
    // anywhere in the picture.
    let instances: Vec<ConeInstance> = owners
        .iter()
        .map(|&i| {
            let p = pixels[i as usize];
            let r = frame.farthest_pixel(p) + 0.5;
            let outer = match metric {
                // The polygon's inscribed ball must hold the disc of radius r.
                Metric::Polygon(_) => metric.euclidean_bounds().1 * r,
                _ => FanShape::with_triangles(r, FOOTPRINT_CORNERS).outer_radius,
            };
            ConeInstance::new(i, p.into(), outer, r)
        })
        .gather("outer")?;
    let reach = instances
        .iter()
        .map(|c| c.site[3] as f64)
        .fold(1.0, f64::max)
        * 1.001;
    let scale = metric.key_scale(reach);
    let ids = labels
        .then(|| machine.image(Format::R32Uint, frame.width, frame.height))
        .transpose()?;
    let depth = machine.image(Format::Depth, frame.width, frame.height)?;
    let mesh = machine.vertex_buffer(&unit)?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    // Polygon keys are distances, so one scale serves fan heights and keys.
    let push = ConePush {
        vertex_depth_scale: scale as f32,
        fragment_depth_scale: scale as f32,
        ..picture_push(frame, 1, metric)
    };
    // Euclidean furthest regions are convex: each cone is drawn only inside the
    // bounding box of a region that holds its own (one draw per cone with a
    // scissor), instead of over the whole picture.
    let scissors: Vec<Option<[u32; 4]>> = if metric == Metric::L2 && owners.len() >= 3 {
        let owned: Vec<DVec2> = owners.iter().map(|&i| pixels[i as usize]).gather("owned")?;
        (0..owned.len())
            .map(|k| Some(furthest_region_box(&owned, k, frame.width, frame.height)))
            .gather("owned")?
    } else {
        Vec::from([None])
    };
    // The upper envelope: the furthest fragment wins, ties the last drawn (or-equal,
    // so that a lone site's own pixel at distance 0 still gets it).
    let state = RasterState {
        depth: DepthTest {
            compare: Compare::GreaterOrEqual,
            write: true,
        },
        ..RasterState::OVERWRITE
    };
    machine.run(|pass| {
        pass.begin(
            Target {
                color: ids.as_ref(),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: ids.as_ref().map(|_| ClearColor::Uint([u32::MAX; 4])),
                depth: Some(0.0),
                stencil: None,
            },
        )?;
        for (k, scissor) in scissors.iter().enumerate() {
            if scissor.is_some_and(|r| r[2] == 0 || r[3] == 0) {
                continue;
            }
            draw_cones(
                pass,
                program,
                &state,
                &DrawParams {
                    scissor: *scissor,
                    ..DrawParams::default()
                },
                &push,
                &ConeDraw {
                    mesh: &mesh,
                    first_vertex: 0,
                    vertex_count: unit.len() as u32,
                    instances: &instance_buffer,
                    first_instance: if scissors.len() == 1 { 0 } else { k as u32 },
                    instance_count: if scissors.len() == 1 {
                        instances.len() as u32
                    } else {
                        1
                    },
                },
            )?;
        }
        pass.end()
    })?;
    Ok(DrawnFurthest {
        ids,
        depth,
        scale,
        owners,
    })
}

/// The pixel rectangle `(x, y, width, height)` around the part of the picture
/// where `sites[k]` is at least as far as each of the other sites (up to 64 of
/// them: its neighbours first, so that fewer still bound a superset), with a
/// pixel to spare; zero-sized when that part misses the picture.
fn furthest_region_box(sites: &[DVec2], k: usize, width: u32, height: u32) -> [u32; 4] {
    let (w, h) = (width as f64 - 0.5, height as f64 - 0.5);
    let mut polygon = Vec::from([
        DVec2::new(-0.5, -0.5),
        DVec2::new(w, -0.5),
        DVec2::new(w, h),
        DVec2::new(-0.5, h),
    ]);
    let n = sites.len();
    let others = (1..n).map(|d| (k + if d % 2 == 1 { d / 2 + 1 } else { n - d / 2 }) % n);
    let p = sites[k];
    for j in others.take(64) {
        let q = sites[j];
        // |x − p| ≥ |x − q|  ⇔  2 x·(q − p) ≥ |q|² − |p|².
        let (a, b) = (2.0 * (q - p), q.length_squared() - p.length_squared());
        let keep = |x: DVec2| a.dot(x) - b >= -1e-6 * (1.0 + b.abs());
        let mut clipped = Vec::new();
        for e in 0..polygon.len() {
            let (u, v) = (polygon[e], polygon[(e + 1) % polygon.len()]);
            if keep(u) {
                clipped.push(u);
            }
            if keep(u) != keep(v) {
                let (fu, fv) = (a.dot(u) - b, a.dot(v) - b);
                clipped.push(u + (v - u) * (fu / (fu - fv)));
            }
        }
        polygon = clipped;
        if polygon.is_empty() {
            return [0; 4];
        }
    }
    let lo = polygon.iter().fold(DVec2::INFINITY, |a, p| a.min(*p)) - 1.0;
    let hi = polygon.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p)) + 1.0;
    let x0 = lo.x.floor().clamp(0.0, width as f64) as u32;
    let y0 = lo.y.floor().clamp(0.0, height as f64) as u32;
    let x1 = hi.x.ceil().clamp(0.0, width as f64) as u32;
    let y1 = hi.y.ceil().clamp(0.0, height as f64) as u32;
    [x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0)]
}
