//! One tile's lower envelope of cones: drawn as batches, polygons, balls and
//! fans, or taken per screen tile from lists of sites
//! ([`crate::algorithms::cones::NEAREST_TILES`]).

use crate::memory::Gather;
use glam::DVec2;

use crate::{
    algorithms::cones::{
        draw_cones, draw_over_target, ConeBatch, ConeDraw, ConeInstance, ConePush, CONE_EXACT,
        CONE_EXACT_BATCH, CONE_FAN, NEAREST_TILES,
    },
    error::Result,
    geometry::{
        chain,
        cone::{unit_fan, unit_footprint},
        frame::distance2_to_rect,
        metric::{DepthKey, Metric},
        radius::TileCandidates,
    },
    machine::{
        ChannelMask, Clear, ClearColor, Compare, DepthTest, DrawParams, Format, Image, Machine,
        Pass, RasterState, StencilOp, StencilTest, Target,
    },
};

use super::{
    accuracy::{metric_fan, Accuracy},
    footprint::{groups_of, Footprint, Shaped, BALL_CORNERS},
    plan::DepthScale,
    records_image,
    screen_tiles::tile_records,
    UNIT_SQUARE,
};

/// The GPU-side buffers of one tile.
pub(crate) struct Picture {
    pub ids: Image,
    pub depth: Image,
}

impl Picture {
    /// Tile images of `width` x `height` pixels, with a stencil where `stencil`.
    pub fn new(machine: &Machine, width: u32, height: u32, stencil: bool) -> Result<Self> {
        let depth = if stencil {
            Format::DepthStencil
        } else {
            Format::Depth
        };
        Ok(Self {
            ids: machine.image(Format::R32Uint, width, height)?,
            depth: machine.image(depth, width, height)?,
        })
    }

    /// Begins rendering into the tile, its ids cleared to "no site", its depths
    /// to the farthest, and its stencil to 0 where `stencil`.
    fn begin<'r>(&'r self, pass: &mut Pass<'_, 'r>, stencil: bool) -> Result<()> {
        pass.begin(
            Target {
                color: Some(&self.ids),
                depth_stencil: Some(&self.depth),
            },
            Clear {
                color: Some(ClearColor::Uint([u32::MAX; 4])),
                depth: Some(1.0),
                stencil: stencil.then_some(0),
            },
        )
    }
}

/// The part of the picture a tile image shows: pixel `(i, j)` of the tile image is
/// pixel `origin + (i, j)` of the picture.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TileView {
    pub origin: DVec2,
    pub width: u32,
    pub height: u32,
}

impl TileView {
    /// The tile's pixel centres: corners `(lo, hi)` in picture pixels.
    pub fn centres(&self) -> (DVec2, DVec2) {
        let size = DVec2::new(self.width as f64, self.height as f64);
        (self.origin, self.origin + size - 1.0)
    }

    /// Whether a disc of radius `r` around `p` (picture pixels) meets the tile.
    fn reaches(&self, p: DVec2, r: f64) -> bool {
        let (lo, hi) = self.centres();
        distance2_to_rect(p, lo, hi) <= r * r
    }

    /// Whether the rectangle `[lo, hi]` (picture pixels) holds a pixel centre of
    /// the tile's range.
    fn meets(&self, lo: [f32; 2], hi: [f32; 2]) -> bool {
        let (a, b) = self.centres();
        lo[0] as f64 <= b.x && hi[0] as f64 >= a.x && lo[1] as f64 <= b.y && hi[1] as f64 >= a.y
    }
}

/// What one pass draws.
pub(super) struct Draws<'a> {
    /// All cones in draw order; the batched ones are drawn through `batches`.
    pub cones: &'a [Shaped],
    pub batches: &'a [ConeBatch],
    pub accuracy: Accuracy,
    pub metric: Metric,
    /// What exact cones write.
    pub key: DepthKey,
    /// Fan meshes of other metrics, made once for every tile and pass.
    pub meshes: &'a chain::FanMeshes,
    pub scale: DepthScale,
    /// Count the cones at each pixel's lowest depth in the stencil.
    pub ties: bool,
    /// Take the envelope of exact cones per screen tile from the sites whose
    /// box meets it ([`NEAREST_TILES`]) instead of drawing them.
    pub tiled: bool,
    /// Mark near ties in the tiles' labels (`ConePlan::marks_near_ties`).
    pub mark_near_ties: bool,
    /// Or from each tile's candidates, found directly.
    pub candidates: Option<&'a TileCandidates>,
    /// Every site (picture pixels), by id.
    pub sites: &'a [DVec2],
}

/// Draws the lower envelope of exact cones into the tile from the screen
/// tiles' lists of sites ([`tile_records`]); `false` where the lists would be
/// too long.
fn render_tiles(
    machine: &Machine,
    picture: &Picture,
    view: &TileView,
    draws: &Draws<'_>,
    push: &ConePush,
) -> Result<bool> {
    let Some(texels) = tile_records(view, draws)? else {
        return Ok(false);
    };
    let Some((upload, records)) = records_image(machine, texels)? else {
        return Ok(false);
    };
    machine.run(|pass| {
        pass.upload_for_fragments(&upload, &records)?;
        pass.bind_fragment_buffers(&[], Some(&records))?;
        picture.begin(pass, false)?;
        draw_over_target(
            pass,
            &NEAREST_TILES,
            &RasterState::lower_envelope(),
            &DrawParams::default(),
            &ConePush {
                levels: if draws.mark_near_ties { 2 } else { 1 },
                ..*push
            },
        )?;
        pass.end()
    })?;
    Ok(true)
}

/// Draws the lower envelope of the cones that reach `view` into the tile;
/// whether it was found from screen tiles' lists of sites.
pub(super) fn render(
    machine: &Machine,
    picture: &Picture,
    view: &TileView,
    draws: &Draws<'_>,
) -> Result<bool> {
    let push = ConePush {
        picture_size: [view.width as f32, view.height as f32],
        offset: [view.origin.x as f32, view.origin.y as f32],
        vertex_depth_scale: draws.scale.vertex as f32,
        fragment_depth_scale: draws.scale.fragment as f32,
        levels: 1,
        // Polygons are drawn as fans only (see `voronoi_bands`).
        metric: draws.key.shader_code().unwrap_or((0, 2.0)).into(),
    };
    if draws.tiled && render_tiles(machine, picture, view, draws, &push)? {
        return Ok(true);
    }
    let batches: Vec<ConeBatch> = draws
        .batches
        .iter()
        .filter(|b| view.meets([b.rect[0], b.rect[1]], [b.rect[2], b.rect[3]]))
        .copied()
        .gather("batches")?;
    let visible: Vec<Shaped> = draws
        .cones
        .iter()
        .filter(|s| s.footprint != Footprint::Batch && view.reaches(s.cone.site, s.cone.radius))
        .copied()
        .gather("visible")?;
    let groups = groups_of(&visible);
    let mut mesh: Vec<[f32; 3]> = UNIT_SQUARE.to_vec();
    let mut ranges = crate::memory::room(groups.len(), "draw ranges")?;
    for g in &groups {
        let vertices = match g.footprint {
            Footprint::Batch => unreachable!("batched cones are drawn as batches"),
            Footprint::Polygon(k) => unit_footprint(k),
            Footprint::Ball => draws
                .meshes
                .unit_mesh(
                    chain::MetricFan::Uniform {
                        corners: BALL_CORNERS,
                    },
                    1.0,
                )
                .to_vec(),
            Footprint::Fan(t) if draws.metric == Metric::L2 => unit_fan(t),
            Footprint::Fan(_) => draws
                .meshes
                .unit_mesh(metric_fan(draws.accuracy), 1.0)
                .to_vec(),
            Footprint::Chain(level) => draws
                .meshes
                .unit_mesh(metric_fan(draws.accuracy), chain::level_radius(level))
                .to_vec(),
        };
        ranges.push((mesh.len() as u32, vertices.len() as u32));
        mesh.extend(vertices);
    }
    let instances: Vec<ConeInstance> = visible
        .iter()
        .map(|s| {
            let c = &s.cone;
            let cone = ConeInstance::new(c.id, c.site.into(), s.outer_radius, c.radius);
            match s.footprint {
                // Clamping an axis-aligned square's corners cuts it exactly.
                Footprint::Polygon(4) if draws.accuracy == Accuracy::Exact => {
                    let (lo, hi) = c.clip();
                    ConeInstance {
                        clip: [lo.x, lo.y, hi.x, hi.y].map(|v| v as f32),
                        ..cone
                    }
                }
                _ => cone,
            }
        })
        .chain(std::iter::once(bytemuck::Zeroable::zeroed()))
        .gather("clip")?;
    let mesh_buffer = machine.vertex_buffer(&mesh)?;
    let instance_buffer = machine.vertex_buffer(&instances)?;
    let batch_buffer = if batches.is_empty() {
        None
    } else {
        Some(machine.vertex_buffer(&batches)?)
    };
    let state = RasterState::lower_envelope();
    let params = DrawParams::default();
    machine.run(|pass| {
        picture.begin(pass, draws.ties)?;
        if let Some(batch_buffer) = &batch_buffer {
            draw_cones(
                pass,
                &CONE_EXACT_BATCH,
                &state,
                &params,
                &push,
                &ConeDraw {
                    mesh: &mesh_buffer,
                    first_vertex: 0,
                    vertex_count: UNIT_SQUARE.len() as u32,
                    instances: batch_buffer,
                    first_instance: 0,
                    instance_count: batches.len() as u32,
                },
            )?;
        }
        // The lower envelope, then (for ties) the thesis's second pass of §3.6.4:
        // every cone again with the depth test EQUAL, the stencil counting the
        // cones that reach the lowest depth.
        let count = RasterState {
            depth: DepthTest {
                compare: Compare::Equal,
                write: false,
            },
            stencil: StencilTest::on_pass(Compare::Always, 0xff, 0xff, StencilOp::IncrementClamp),
            color_mask: ChannelMask::NONE,
            ..RasterState::OVERWRITE
        };
        let passes: &[&RasterState] = if draws.ties {
            &[&state, &count]
        } else {
            &[&state]
        };
        for state in passes {
            for (g, &(first_vertex, vertex_count)) in groups.iter().zip(&ranges) {
                let program = match draws.accuracy {
                    Accuracy::Exact => &CONE_EXACT,
                    Accuracy::Fan { .. } => &CONE_FAN,
                };
                draw_cones(
                    pass,
                    program,
                    state,
                    &params,
                    &push,
                    &ConeDraw {
                        mesh: &mesh_buffer,
                        first_vertex,
                        vertex_count,
                        instances: &instance_buffer,
                        first_instance: g.first,
                        instance_count: g.count,
                    },
                )?;
            }
        }
        pass.end()
    })?;
    Ok(false)
}
