//! The programs that draw distance functions as surfaces, shared by the
//! diagrams of points and of sites, the k nearest, homothets and alpha hulls:
//! cones (thesis §3.3), their exact footprints and batches, screen-tile
//! envelopes, and the surfaces of sites with weights. Each program is declared
//! here as data for the machine, with the `repr(C)` layouts its vertex buffers
//! and push constants hold; their offsets feed the declarations, which the
//! compiler checks against the shaders.

use std::mem::{offset_of, size_of};

use crate::{
    error::Result,
    machine::{
        shaders, Buffer, Draw, DrawParams, Fragments, GraphicsProgram, Pass, RasterState, Shader,
        Topology, VertexAttribute, VertexBuffer, VertexFormat,
    },
};

/// Push constants of the cone programs (`glsl/common.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ConePush {
    /// Size of the target in pixels.
    pub picture_size: [f32; 2],
    /// The picture pixel shown at the target's pixel (0, 0): a tile's origin.
    pub offset: [f32; 2],
    pub vertex_depth_scale: f32,
    pub fragment_depth_scale: f32,
    /// Length of each pixel's list of nearest sites, for the k-nearest programs
    /// (else unused).
    pub levels: u32,
    /// The distance function of exact cones.
    pub metric: MetricCode,
}

/// A distance function as the shaders take it (`glsl/metric.glsl`): kind (0
/// Euclidean, 1 L1, 2 L-infinity, 3 L_p, 4 L_p with keys that are sums of
/// powers) and p. The kind also chooses the build of a metric's fragment
/// shader: it is the draw's variant.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MetricCode {
    pub kind: u32,
    pub p: f32,
}

impl From<(u32, f32)> for MetricCode {
    /// From `Metric::shader_code`'s pair.
    fn from((kind, p): (u32, f32)) -> Self {
        Self { kind, p }
    }
}

/// One cone of the programs that draw `glsl/cone.vert`: the unit mesh scaled to
/// the outer radius around the site, its corners clamped into `clip`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ConeInstance {
    /// Site x, y, outer radius and truncation radius, in picture pixels.
    pub site: [f32; 4],
    /// `(min x, min y, max x, max y)`: an exact cone's footprint is cut to this
    /// rectangle. Clamping its corners cuts an axis-aligned square exactly;
    /// other footprints, and fans (whose depth follows their corners), need a
    /// rectangle that holds them whole.
    pub clip: [f32; 4],
    pub id: u32,
}

impl ConeInstance {
    /// A cone drawn whole.
    pub fn new(id: u32, site: [f64; 2], outer_radius: f64, radius: f64) -> Self {
        Self {
            site: [site[0], site[1], outer_radius, radius].map(|v| v as f32),
            clip: [-f32::MAX, -f32::MAX, f32::MAX, f32::MAX],
            id,
        }
    }
}

/// One instance of [`CONE_EXACT_BATCH`]: up to eight exact cones drawn as one
/// rectangle that covers all their footprints. Unused slots repeat a used one.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ConeBatch {
    /// Pixel coordinates `(min x, min y, max x, max y)` of the rectangle.
    pub rect: [f32; 4],
    /// Site positions, two per group of four: `x0, y0, x1, y1, x2, ...`.
    pub sites: [f32; 16],
    /// Squared truncation radii.
    pub radii2: [f32; 8],
    pub ids: [u32; 8],
}

/// One site of [`SITE_EXACT`] (`glsl/site.vert`): its rectangle, shape words,
/// weights, kind and id.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct SiteInstance {
    /// (min x, min y, max x, max y) in picture pixels.
    pub rect: [f32; 4],
    /// shape0 and shape1 as `glsl/site_distance.glsl` reads them.
    pub shape: [f32; 8],
    /// (1 / (frame scale * m), a - the smallest a).
    pub weights: [f32; 2],
    /// Kind (0 point, 1 segment, 2 circle, 3 arc) and site id.
    pub kind_id: [u32; 2],
}

/// One instance of [`SITE_EXACT_BATCH`] (`glsl/site_batch.vert`): up to eight
/// sites of one shape drawn as one rectangle that covers all of theirs, or up
/// to four arcs, whose shapes take eight words. Unused slots repeat a used one.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SiteBatch {
    /// (min x, min y, max x, max y) in picture pixels.
    pub rect: [f32; 4],
    /// The first four shape words of each site (`SiteInstance::shape`); arc
    /// k's eight in `shapes[2 k]` and `shapes[2 k + 1]`.
    pub shapes: [[f32; 4]; 8],
    /// Each site's `SiteInstance::weights`.
    pub weights: [[f32; 2]; 8],
    pub ids: [u32; 8],
}

/// The shapes of sites, each drawn by its own build of the site programs: the
/// fragment shader then carries no other shape's code, which lavapipe would
/// run under masks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SiteShape {
    Point,
    Segment,
    Circle,
    Arc,
}

impl SiteShape {
    /// The shape drawn for a [`SiteInstance`]'s kind (0 point, 1 segment, 2
    /// circle, 3 arc).
    pub(crate) fn of_kind(kind: u32) -> Self {
        match kind {
            0 => SiteShape::Point,
            1 => SiteShape::Segment,
            2 => SiteShape::Circle,
            _ => SiteShape::Arc,
        }
    }
}

/// An instanced draw of cones: `vertex_count` vertices of the unit fan mesh from
/// `first_vertex`, once per instance in `first_instance..first_instance + count`.
/// The mesh holds `[f32; 3]` unit vertices (cos, sin, h); for the programs of
/// `glsl/cone.vert` the instances are [`ConeInstance`]s. The fan programs take
/// their per-vertex ids in place of the instances.
#[derive(Clone, Copy)]
pub struct ConeDraw<'a> {
    pub mesh: &'a Buffer,
    pub first_vertex: u32,
    pub vertex_count: u32,
    pub instances: &'a Buffer,
    pub first_instance: u32,
    pub instance_count: u32,
}

/// Draws `cones` with `program` (a "display list" translated per site,
/// thesis §3.3), built for `push`'s distance function.
pub fn draw_cones<'r>(
    pass: &mut Pass<'_, 'r>,
    program: &'static GraphicsProgram,
    state: &RasterState,
    params: &DrawParams,
    push: &ConePush,
    cones: &ConeDraw<'r>,
) -> Result<()> {
    pass.draw(
        state,
        params,
        &Draw {
            program,
            variant: push.metric.kind,
            push: bytemuck::bytes_of(push),
            vertex_buffers: &[cones.mesh, cones.instances],
            vertices: cones.first_vertex..cones.first_vertex + cones.vertex_count,
            instances: cones.first_instance..cones.first_instance + cones.instance_count,
        },
    )
}

/// One triangle over the target with `program` (one of [`NEAREST_TILES`] and
/// [`SITE_TILES`]), whose fragments read their tiles' sites from the records
/// image of the bound set.
pub(crate) fn draw_over_target(
    pass: &mut Pass<'_, '_>,
    program: &'static GraphicsProgram,
    state: &RasterState,
    params: &DrawParams,
    push: &ConePush,
) -> Result<()> {
    pass.draw(
        state,
        params,
        &Draw {
            program,
            variant: push.metric.kind,
            push: bytemuck::bytes_of(push),
            vertex_buffers: &[],
            vertices: 0..3,
            instances: 0..1,
        },
    )
}

/// Draws `tiles` screen tiles of [`K_NEAREST_TILES`] keeping `push.levels`
/// levels, whose records come from the second storage buffer of the bound set.
pub(crate) fn draw_k_nearest_tiles(
    pass: &mut Pass<'_, '_>,
    state: &RasterState,
    params: &DrawParams,
    push: &ConePush,
    tiles: u32,
) -> Result<()> {
    pass.draw(
        state,
        params,
        &Draw {
            program: k_nearest_tiles(push.levels),
            variant: push.metric.kind,
            push: bytemuck::bytes_of(push),
            vertex_buffers: &[],
            vertices: 0..6,
            instances: 0..tiles,
        },
    )
}

const fn attribute(location: u32, offset: usize, format: VertexFormat) -> VertexAttribute {
    VertexAttribute {
        location,
        offset: offset as u32,
        format,
    }
}

/// The unit mesh of cones and rectangles: `[f32; 3]` per vertex at location 0.
const MESH: VertexBuffer = VertexBuffer {
    stride: size_of::<[f32; 3]>() as u32,
    per_instance: false,
    attributes: &[attribute(0, 0, VertexFormat::F32x3)],
};

const CONE_INSTANCES: VertexBuffer = VertexBuffer {
    stride: size_of::<ConeInstance>() as u32,
    per_instance: true,
    attributes: &[
        attribute(1, offset_of!(ConeInstance, site), VertexFormat::F32x4),
        attribute(2, offset_of!(ConeInstance, id), VertexFormat::U32),
        attribute(3, offset_of!(ConeInstance, clip), VertexFormat::F32x4),
    ],
};

/// Four-word groups of `glsl/cone_batch.vert`: the rectangle, four of site
/// pairs, two of squared radii, two of ids.
const CONE_BATCHES: VertexBuffer = {
    const SITES: usize = offset_of!(ConeBatch, sites);
    const RADII: usize = offset_of!(ConeBatch, radii2);
    const IDS: usize = offset_of!(ConeBatch, ids);
    VertexBuffer {
        stride: size_of::<ConeBatch>() as u32,
        per_instance: true,
        attributes: &[
            attribute(1, offset_of!(ConeBatch, rect), VertexFormat::F32x4),
            attribute(2, SITES, VertexFormat::F32x4),
            attribute(3, SITES + 16, VertexFormat::F32x4),
            attribute(4, SITES + 32, VertexFormat::F32x4),
            attribute(5, SITES + 48, VertexFormat::F32x4),
            attribute(6, RADII, VertexFormat::F32x4),
            attribute(7, RADII + 16, VertexFormat::F32x4),
            attribute(8, IDS, VertexFormat::U32x4),
            attribute(9, IDS + 16, VertexFormat::U32x4),
        ],
    }
};

const SITE_INSTANCES: VertexBuffer = VertexBuffer {
    stride: size_of::<SiteInstance>() as u32,
    per_instance: true,
    attributes: &[
        attribute(1, offset_of!(SiteInstance, rect), VertexFormat::F32x4),
        attribute(2, offset_of!(SiteInstance, shape), VertexFormat::F32x4),
        attribute(3, offset_of!(SiteInstance, shape) + 16, VertexFormat::F32x4),
        attribute(4, offset_of!(SiteInstance, weights), VertexFormat::F32x2),
        attribute(5, offset_of!(SiteInstance, kind_id), VertexFormat::U32x2),
    ],
};

/// Four-word groups of `glsl/site_batch.vert`: the rectangle, eight shapes,
/// four of weight pairs, two of ids.
const SITE_BATCHES: VertexBuffer = {
    const SHAPES: usize = offset_of!(SiteBatch, shapes);
    const WEIGHTS: usize = offset_of!(SiteBatch, weights);
    const IDS: usize = offset_of!(SiteBatch, ids);
    VertexBuffer {
        stride: size_of::<SiteBatch>() as u32,
        per_instance: true,
        attributes: &[
            attribute(1, offset_of!(SiteBatch, rect), VertexFormat::F32x4),
            attribute(2, SHAPES, VertexFormat::F32x4),
            attribute(3, SHAPES + 16, VertexFormat::F32x4),
            attribute(4, SHAPES + 32, VertexFormat::F32x4),
            attribute(5, SHAPES + 48, VertexFormat::F32x4),
            attribute(6, SHAPES + 64, VertexFormat::F32x4),
            attribute(7, SHAPES + 80, VertexFormat::F32x4),
            attribute(8, SHAPES + 96, VertexFormat::F32x4),
            attribute(9, SHAPES + 112, VertexFormat::F32x4),
            attribute(10, WEIGHTS, VertexFormat::F32x4),
            attribute(11, WEIGHTS + 16, VertexFormat::F32x4),
            attribute(12, WEIGHTS + 32, VertexFormat::F32x4),
            attribute(13, WEIGHTS + 48, VertexFormat::F32x4),
            attribute(14, IDS, VertexFormat::U32x4),
            attribute(15, IDS + 16, VertexFormat::U32x4),
        ],
    }
};

/// Per-vertex site ids of the fan surfaces, at location 1.
const FAN_IDS: VertexBuffer = VertexBuffer {
    stride: size_of::<u32>() as u32,
    per_instance: false,
    attributes: &[attribute(1, 0, VertexFormat::U32)],
};

/// A program taking [`ConePush`] constants.
const fn cone_program(
    name: &'static str,
    vertex: Shader,
    fragments: Fragments,
    topology: Topology,
    vertex_buffers: &'static [VertexBuffer],
) -> GraphicsProgram {
    GraphicsProgram::new(
        name,
        vertex,
        fragments,
        topology,
        vertex_buffers,
        size_of::<ConePush>(),
    )
}

/// Instanced triangle-fan cones; depth is the interpolated cone height.
pub(crate) static CONE_FAN: GraphicsProgram = cone_program(
    "ConeFan",
    shaders::CONE_VERT,
    Fragments::One(shaders::CONE_FAN_FRAG),
    Topology::TriangleFan,
    &[MESH, CONE_INSTANCES],
);

/// Instanced cone footprints; depth is the exact key of the distance per
/// fragment.
pub static CONE_EXACT: GraphicsProgram = cone_program(
    "ConeExact",
    shaders::CONE_VERT,
    Fragments::ByVariant(&shaders::CONE_EXACT_FRAG),
    Topology::TriangleFan,
    &[MESH, CONE_INSTANCES],
);

/// Up to eight exact cones in one bounding rectangle, the envelope taken per
/// fragment; see [`ConeBatch`].
pub(crate) static CONE_EXACT_BATCH: GraphicsProgram = cone_program(
    "ConeExactBatch",
    shaders::CONE_BATCH_VERT,
    Fragments::ByVariant(&shaders::CONE_BATCH_FRAG),
    Topology::TriangleList,
    &[MESH, CONE_BATCHES],
);

/// The lower envelope of exact cones from screen-tile lists: one triangle over
/// the target, each fragment taking the nearest of the sites binned to its
/// tile, read from the records image (`glsl/nearest_tiles.frag`).
pub(crate) static NEAREST_TILES: GraphicsProgram = cone_program(
    "NearestTiles",
    shaders::PICTURE_VERT,
    Fragments::ByVariant(&shaders::NEAREST_TILES_FRAG),
    Topology::TriangleList,
    &[],
);

/// Instanced exact cone footprints inserting `(squared distance, id)` keys into
/// each pixel's sorted list of the k nearest, a storage buffer bound with
/// [`Pass::bind_fragment_buffers`]; writes no attachment.
pub(crate) static CONE_K_NEAREST: GraphicsProgram = cone_program(
    "ConeKNearest",
    shaders::CONE_VERT,
    Fragments::ByVariant(&shaders::CONE_KNEAREST_FRAG_EXACT),
    Topology::TriangleFan,
    &[MESH, CONE_INSTANCES],
);

/// [`CONE_K_NEAREST`] with triangle-fan cones: the key's distance is the fan's
/// interpolated height.
pub(crate) static CONE_K_NEAREST_FAN: GraphicsProgram = cone_program(
    "ConeKNearestFan",
    shaders::CONE_VERT,
    Fragments::ByVariant(&shaders::CONE_KNEAREST_FRAG_FAN),
    Topology::TriangleFan,
    &[MESH, CONE_INSTANCES],
);

/// Exact cones peeled against the previous level's depth and site, held in
/// the fragment storage buffer (thesis §3.7).
pub static CONE_PEEL: GraphicsProgram = cone_program(
    "ConePeel",
    shaders::CONE_VERT,
    Fragments::ByVariant(&shaders::CONE_PEEL_FRAG),
    Topology::TriangleFan,
    &[MESH, CONE_INSTANCES],
);

/// One rectangle per screen tile whose fragments keep the k lowest layers of
/// the cones binned to the tile (tile records and cones in the second storage
/// buffer, keys written to the first), built for lists of 1, 2, 3, 4, 6, 8,
/// 12, 16, 24 and 32; see [`k_nearest_tiles`].
pub(crate) static K_NEAREST_TILES: [GraphicsProgram; 10] = {
    const fn tiles(name: &'static str, builds: &'static [Shader]) -> GraphicsProgram {
        cone_program(
            name,
            shaders::TILES_VERT,
            Fragments::ByVariant(builds),
            Topology::TriangleList,
            &[],
        )
    }
    [
        tiles("KNearestTiles(1)", &shaders::CONE_TILES_FRAG_K1),
        tiles("KNearestTiles(2)", &shaders::CONE_TILES_FRAG_K2),
        tiles("KNearestTiles(3)", &shaders::CONE_TILES_FRAG_K3),
        tiles("KNearestTiles(4)", &shaders::CONE_TILES_FRAG_K4),
        tiles("KNearestTiles(6)", &shaders::CONE_TILES_FRAG_K6),
        tiles("KNearestTiles(8)", &shaders::CONE_TILES_FRAG_K8),
        tiles("KNearestTiles(12)", &shaders::CONE_TILES_FRAG_K12),
        tiles("KNearestTiles(16)", &shaders::CONE_TILES_FRAG_K16),
        tiles("KNearestTiles(24)", &shaders::CONE_TILES_FRAG_K24),
        tiles("KNearestTiles(32)", &shaders::CONE_TILES_FRAG_K32),
    ]
};

/// The build of [`K_NEAREST_TILES`] whose lists hold `levels` keys: the
/// shortest that does.
pub(crate) fn k_nearest_tiles(levels: u32) -> &'static GraphicsProgram {
    let build = match levels {
        0..=1 => 0,
        2 => 1,
        3 => 2,
        4 => 3,
        5..=6 => 4,
        7..=8 => 5,
        9..=12 => 6,
        13..=16 => 7,
        17..=24 => 8,
        _ => 9,
    };
    &K_NEAREST_TILES[build]
}

/// One rectangle per site with weights, by [`SiteShape`]; the fragment writes
/// the exact weighted distance (see [`SiteInstance`]).
pub(crate) static SITE_EXACT: [GraphicsProgram; 4] = {
    const fn site(name: &'static str, builds: &'static [Shader]) -> GraphicsProgram {
        cone_program(
            name,
            shaders::SITE_VERT,
            Fragments::ByVariant(builds),
            Topology::TriangleList,
            &[MESH, SITE_INSTANCES],
        )
    }
    [
        site("SiteExact(Point)", &shaders::SITE_EXACT_FRAG_POINT),
        site("SiteExact(Segment)", &shaders::SITE_EXACT_FRAG_SEGMENT),
        site("SiteExact(Circle)", &shaders::SITE_EXACT_FRAG_CIRCLE),
        site("SiteExact(Arc)", &shaders::SITE_EXACT_FRAG_ARC),
    ]
};

/// Up to eight sites of one shape in one rectangle, by [`SiteShape`], the
/// envelope taken per fragment; see [`SiteBatch`]. Built for L2, L1 and L∞,
/// and arcs for L2 alone.
pub static SITE_EXACT_BATCH: [GraphicsProgram; 4] = {
    const fn batch(name: &'static str, builds: &'static [Shader]) -> GraphicsProgram {
        cone_program(
            name,
            shaders::SITE_BATCH_VERT,
            Fragments::ByVariant(builds),
            Topology::TriangleList,
            &[MESH, SITE_BATCHES],
        )
    }
    [
        batch("SiteExactBatch(Point)", &shaders::SITE_BATCH_FRAG_POINT),
        batch("SiteExactBatch(Segment)", &shaders::SITE_BATCH_FRAG_SEGMENT),
        batch("SiteExactBatch(Circle)", &shaders::SITE_BATCH_FRAG_CIRCLE),
        batch(
            "SiteExactBatch(Arc)",
            &[shaders::SITE_BATCH_FRAG_ARC_METRIC_L2],
        ),
    ]
};

/// The lower envelope of sites of one shape under L2, L1 or L∞ from screen-tile
/// lists, by [`SiteShape`]: one triangle over the target, each fragment taking
/// the lowest weighted distance of the sites listed for its tile, read from the
/// records image (`glsl/site_tiles.frag`).
pub(crate) static SITE_TILES: [GraphicsProgram; 4] = {
    const fn tiles(name: &'static str, builds: &'static [Shader]) -> GraphicsProgram {
        cone_program(
            name,
            shaders::PICTURE_VERT,
            Fragments::ByVariant(builds),
            Topology::TriangleList,
            &[],
        )
    }
    [
        tiles("SiteTiles(Point)", &shaders::SITE_TILES_FRAG_POINT),
        tiles("SiteTiles(Segment)", &shaders::SITE_TILES_FRAG_SEGMENT),
        tiles("SiteTiles(Circle)", &shaders::SITE_TILES_FRAG_CIRCLE),
        tiles("SiteTiles(Arc)", &shaders::SITE_TILES_FRAG_ARC),
    ]
};

/// Triangles of fan surfaces with per-vertex position, depth and site id (two
/// per-vertex buffers: `[f32; 3]` and `u32`), drawn as a list.
pub(crate) static SITE_FAN: GraphicsProgram = cone_program(
    "SiteFan",
    shaders::SITE_FAN_VERT_PLAIN,
    Fragments::One(shaders::SITE_FAN_FRAG_PLAIN),
    Topology::TriangleList,
    &[MESH, FAN_IDS],
);

/// [`SITE_FAN`] for folded surfaces: vertices `[x, y, depth of a signed value,
/// depth of zero]`, and each fragment's depth is the zero's plus the magnitude
/// of the value's difference from it.
pub static SITE_FAN_FOLDED: GraphicsProgram = cone_program(
    "SiteFanFolded",
    shaders::SITE_FAN_VERT_FOLDED,
    Fragments::One(shaders::SITE_FAN_FRAG_FOLDED),
    Topology::TriangleList,
    &[
        VertexBuffer {
            stride: size_of::<[f32; 4]>() as u32,
            per_instance: false,
            attributes: &[attribute(0, 0, VertexFormat::F32x4)],
        },
        FAN_IDS,
    ],
);
