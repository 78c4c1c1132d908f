//! What is drawn per site: its shape, fans, batches of instances and the
//! rectangles of exact mode.

use super::*;

/// A diagram's statistics before drawing: `reaches` are the largest shape
/// distances (pixels) of the sites drawn.
pub(super) fn site_stats(machine: &Machine, sites: usize, reaches: &[f64]) -> VoronoiStats {
    let mut stats = VoronoiStats {
        device: machine.device_name().to_string(),
        sites,
        cones: reaches.len(),
        passes: 1,
        ..Default::default()
    };
    if !reaches.is_empty() {
        stats.radius_min = reaches.iter().copied().fold(f64::INFINITY, f64::min);
        stats.radius_max = reaches.iter().copied().fold(0.0, f64::max);
        stats.radius_mean = reaches.iter().sum::<f64>() / reaches.len() as f64;
    }
    stats
}

/// The power of two that maps weighted distances from the smallest additive
/// weight up to the envelope's `reach` into [0, 1) as depths.
pub(super) fn depth_scale_of(reach: f64, least_additive: f64) -> f64 {
    let span = (reach - least_additive).max(1e-30) * 1.001;
    span.log2().ceil().exp2().recip()
}

/// The shape a site is drawn as.
pub(super) fn site_shape(site: &Site) -> SiteShape {
    match site.shape {
        Shape::Point(_) => SiteShape::Point,
        Shape::Segment(..) => SiteShape::Segment,
        Shape::Circle { .. } => SiteShape::Circle,
        Shape::Arc { .. } => SiteShape::Arc,
    }
}

/// Fan vertices of N words (see [`SITE_FAN`] and
/// [`SITE_FAN_FOLDED`]) with their sites' ids.
#[derive(Default)]
pub(super) struct FanBuffers<const N: usize> {
    vertices: Vec<[f32; N]>,
    ids: Vec<u32>,
}

impl<const N: usize> FanBuffers<N>
where
    [f32; N]: bytemuck::Pod,
{
    pub(super) fn push(&mut self, vertex: [f32; N], id: u32) {
        self.vertices.push(vertex);
        self.ids.push(id);
    }

    pub(super) fn append(&mut self, mut other: Self) {
        self.vertices.append(&mut other.vertices);
        self.ids.append(&mut other.ids);
    }

    /// The two vertex buffers for `program` and the vertices' count.
    pub(super) fn upload(
        mut self,
        machine: &Machine,
        program: &'static GraphicsProgram,
    ) -> Result<(&'static GraphicsProgram, Buffer, Buffer, u32)> {
        let count = self.vertices.len() as u32;
        // Vulkan buffers cannot be empty.
        self.push([0.0; N], 0);
        Ok((
            program,
            machine.vertex_buffer(&self.vertices)?,
            machine.vertex_buffer(&self.ids)?,
            count,
        ))
    }
}

/// What one diagram draws.
pub(super) enum SiteDraw {
    /// Batches of small sites of the shapes [`batched`] under the metric, and
    /// one rectangle per other site, both sorted by shape.
    Exact {
        batches: Vec<(SiteShape, SiteBatch)>,
        singles: Vec<SiteInstance>,
    },
    /// Each site's fan surface.
    Fan(Vec<(u32, FanSurface)>),
}

/// One draw of `program` per run of a shape among the `instances` (rectangles
/// of the unit square `mesh`), whose shapes in order are `shapes`.
pub(super) fn rect_draws<'a>(
    mesh: &'a Buffer,
    programs: &'static [GraphicsProgram; 4],
    shapes: impl Iterator<Item = SiteShape>,
    instances: &'a Buffer,
) -> Vec<(&'static GraphicsProgram, ConeDraw<'a>)> {
    let mut draws: Vec<(&'static GraphicsProgram, ConeDraw<'a>)> = Vec::new();
    for (k, shape) in shapes.enumerate() {
        let program = &programs[shape as usize];
        match draws.last_mut() {
            Some((last, draw)) if std::ptr::eq(*last, program) => draw.instance_count += 1,
            _ => draws.push((
                program,
                ConeDraw {
                    mesh,
                    first_vertex: 0,
                    vertex_count: UNIT_SQUARE.len() as u32,
                    instances,
                    first_instance: k as u32,
                    instance_count: 1,
                },
            )),
        }
    }
    draws
}

/// Whether sites of `shape` under `metric` are drawn in batches: those whose
/// distance costs a few operations (Euclidean points, segments, circles and
/// arcs; L1 and L∞ points and segments). A batch evaluates eight per fragment
/// (four arcs), so the searches of curves under other metrics and of L_p stay
/// one to a rectangle.
fn batched(metric: Metric, shape: SiteShape) -> bool {
    match metric {
        Metric::L2 => true,
        Metric::L1 | Metric::LInf => matches!(shape, SiteShape::Point | SiteShape::Segment),
        _ => false,
    }
}

/// Splits sites' rectangles (sorted by shape) into batches of up to eight
/// neighbours along a Hilbert curve, for the shapes [`batched`] under `metric`
/// with small rectangles, and the rest, drawn one by one. A batch's rectangle
/// is the bounding box of its sites', so one large site would widen it for all
/// eight: a batched site's rectangle is no larger than a batched cone's square.
pub(super) fn batch_sites(
    instances: Vec<SiteInstance>,
    metric: Metric,
    tuning: &Tuning,
) -> (Vec<(SiteShape, SiteBatch)>, Vec<SiteInstance>) {
    let side_limit = (2.0 * tuning.batch_radius) as f32;
    let (mut batched, singles): (Vec<SiteInstance>, Vec<SiteInstance>) =
        instances.into_iter().partition(|i| {
            batched(metric, SiteShape::of_kind(i.kind_id[0]))
                && i.rect[2] - i.rect[0] <= side_limit
                && i.rect[3] - i.rect[1] <= side_limit
        });
    batched.sort_by_cached_key(|i| {
        let q = |v: f32| (v.max(0.0) as u32).min(65535);
        let centre = |a: usize| q(0.5 * (i.rect[a] + i.rect[a + 2]));
        (i.kind_id[0], hilbert_index(centre(0), centre(1)))
    });
    let mut batches = Vec::new();
    for run in batched.chunk_by(|a, b| a.kind_id[0] == b.kind_id[0]) {
        let shape = SiteShape::of_kind(run[0].kind_id[0]);
        // An arc's shape takes two of the batch's shape slots.
        let words = if shape == SiteShape::Arc { 2 } else { 1 };
        for chunk in run.chunks(BATCH / words) {
            let mut batch = SiteBatch {
                rect: [f32::MAX, f32::MAX, f32::MIN, f32::MIN],
                shapes: [[0.0; 4]; BATCH],
                weights: [[0.0; 2]; BATCH],
                ids: [0; BATCH],
            };
            for k in 0..BATCH / words {
                let site = &chunk[k.min(chunk.len() - 1)];
                for w in 0..words {
                    batch.shapes[words * k + w].copy_from_slice(&site.shape[4 * w..][..4]);
                }
                batch.weights[k] = site.weights;
                batch.ids[k] = site.kind_id[1];
                for a in 0..2 {
                    batch.rect[a] = batch.rect[a].min(site.rect[a]);
                    batch.rect[a + 2] = batch.rect[a + 2].max(site.rect[a + 2]);
                }
            }
            batches.push((shape, batch));
        }
    }
    (batches, singles)
}

/// The site's instance: shape words in pixel coordinates, weights that turn pixel
/// distances into weighted world distances less the smallest additive weight.
pub(super) fn instance(
    id: u32,
    s: &Site,
    rect: [f32; 4],
    scale: f64,
    least_additive: f64,
) -> SiteInstance {
    let f = |v: f64| v as f32;
    let (kind, shape) = match s.shape {
        Shape::Point(p) => (0, [f(p.x), f(p.y), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Shape::Segment(a, b) => (1, [f(a.x), f(a.y), f(b.x), f(b.y), 0.0, 0.0, 0.0, 0.0]),
        Shape::Circle { center, radius } => (
            2,
            [f(center.x), f(center.y), f(radius), 0.0, 0.0, 0.0, 0.0, 0.0],
        ),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => (
            3,
            [
                f(center.x),
                f(center.y),
                f(radius),
                f(end - start),
                f(start.cos()),
                f(start.sin()),
                f(end.cos()),
                f(end.sin()),
            ],
        ),
    };
    SiteInstance {
        rect,
        shape,
        weights: [
            f(1.0 / (scale * s.multiplicative)),
            f(s.additive - least_additive),
        ],
        kind_id: [kind, id],
    }
}
