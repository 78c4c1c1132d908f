//! The region as a triangle mesh, and the mask that keeps the envelope's
//! pixels outside it from counting.

use super::*;

/// The region in picture pixels for its stencil mask, as triangles in the
/// `[x, y, depth]` layout of [`SITE_FAN`]: fans from each ring's first
/// vertex (filled by even-odd parity), and the band of pixels whose squares
/// meet its boundary (each edge swept by a pixel's square, a hexagon).
pub(super) struct RegionMesh {
    fans: Vec<[f32; 3]>,
    band: Vec<[f32; 3]>,
}

impl RegionMesh {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn new(region: &Region, frame: &Frame) -> Self {
        let vertex = |v: DVec2| [v.x as f32, v.y as f32, 0.0];
        let mut fans = Vec::new();
        for ring in &region.rings {
            let p: Vec<DVec2> = ring.iter().map(|v| frame.to_pixel(*v)).collect();
            for k in 1..p.len() - 1 {
                fans.extend([p[0], p[k], p[k + 1]].map(vertex));
            }
        }
        let mut band = Vec::new();
        for (a, b) in region.edges() {
            let (a, b) = (frame.to_pixel(a), frame.to_pixel(b));
            // A hair more than half a pixel, so that a square that only
            // touches the boundary still counts whatever the rasterizer's
            // rule for centres on an edge.
            let h = 0.5 + 1e-3;
            let corners: Vec<DVec2> = [a, b]
                .iter()
                .flat_map(|&e| {
                    [(-h, -h), (h, -h), (h, h), (-h, h)].map(|(x, y)| e + DVec2::new(x, y))
                })
                .collect();
            let hull: Vec<DVec2> = crate::geometry::exact::predicates::convex_hull(&corners)
                .into_iter()
                .map(|i| corners[i as usize])
                .collect();
            for k in 1..hull.len() - 1 {
                band.extend([hull[0], hull[k], hull[k + 1]].map(vertex));
            }
        }
        Self { fans, band }
    }
}

/// Pushes every pixel whose square misses the region to depth 0 (thesis
/// §5.4.1, widened by the boundary's band so that every point of the region is
/// within half a pixel's diagonal of a pixel left standing): the region's fans
/// invert the stencil's low bit, the band sets the next, then a picture-wide
/// rectangle at depth 0 is drawn where both are clear.
pub(super) fn mask_outside(
    machine: &Machine,
    ids: Option<&crate::machine::Image>,
    depth: &crate::machine::Image,
    region: &RegionMesh,
    x0: u32,
    y0: u32,
) -> Result<()> {
    let (w, h) = (depth.width(), depth.height());
    let mut vertices = region.fans.clone();
    vertices.extend(&region.band);
    vertices.push([0.0; 3]);
    let mesh = machine.vertex_buffer(&vertices)?;
    // Site ids, one per vertex.
    let zeros =
        machine.vertex_buffer(&crate::memory::filled(vertices.len(), 0u32, "vertex ids")?)?;
    let parity = RasterState {
        stencil: StencilTest::on_pass(Compare::Always, 1, 1, StencilOp::Invert),
        color_mask: ChannelMask::NONE,
        ..RasterState::OVERWRITE
    };
    let banded = RasterState {
        stencil: StencilTest::on_pass(Compare::Always, 2, 2, StencilOp::Replace),
        ..parity
    };
    let forbid = RasterState {
        depth: DepthTest {
            compare: Compare::Always,
            write: true,
        },
        stencil: StencilTest::on_pass(Compare::Equal, 3, 0, StencilOp::Keep),
        color_mask: ChannelMask::NONE,
        ..RasterState::OVERWRITE
    };
    let push = ConePush {
        picture_size: [w as f32, h as f32],
        offset: [x0 as f32, y0 as f32],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: 0.0,
        levels: 1,
        metric: (0, 2.0).into(),
    };
    let draw = |first_vertex: usize, count: usize| ConeDraw {
        mesh: &mesh,
        first_vertex: first_vertex as u32,
        vertex_count: count as u32,
        instances: &zeros,
        first_instance: 0,
        instance_count: u32::from(count > 0),
    };
    let (fans, band) = (region.fans.len(), region.band.len());
    machine.run(|pass| {
        pass.begin(
            Target {
                color: ids,
                depth_stencil: Some(depth),
            },
            Clear {
                stencil: Some(0),
                ..Clear::default()
            },
        )?;
        draw_cones(
            pass,
            &SITE_FAN,
            &parity,
            &DrawParams::default(),
            &push,
            &draw(0, fans),
        )?;
        let reference = DrawParams {
            stencil_reference: 2,
            ..DrawParams::default()
        };
        draw_cones(
            pass,
            &SITE_FAN,
            &banded,
            &reference,
            &push,
            &draw(fans, band),
        )?;
        pass.draw_rect(
            &forbid,
            &DrawParams::default(),
            &RectDraw::full_picture(w, h),
        )?;
        pass.end()
    })
}
