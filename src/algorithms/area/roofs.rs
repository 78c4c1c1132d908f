//! The saddle roofs over pairs of sites (thesis §7.3), drawn with the depth
//! test so each pixel keeps its extreme triangle or quadrangle.

use super::*;
use crate::memory::Gather;

/// Push constants of the roof programs (`glsl/roof.glsl`): `[width, height,
/// bound, depth per area, maximum, segment]`.
pub(super) type RoofWords = [u32; 6];

/// Saddle roofs over pairs of sites (thesis §7.3), one per instance without
/// vertex buffers, reading the sites (`f64` pairs) and the site drawn in each
/// pixel from storage buffers 0 and 1: the area as depth, the pair as colour.
pub(super) static ROOF: GraphicsProgram = GraphicsProgram::new(
    "Roof",
    shaders::ROOF_VERT,
    Fragments::One(shaders::ROOF_FRAG_TRIANGLE),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<RoofWords>(),
);

/// [`ROOF`] keeping per pair and side of its line the nearest (or farthest)
/// site in storage buffer 2; writes no attachment.
pub(super) static ROOF_SIDES: GraphicsProgram = GraphicsProgram::new(
    "RoofSides",
    shaders::ROOF_VERT,
    Fragments::One(shaders::ROOF_FRAG_SIDES),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<RoofWords>(),
);

/// "No site" in a pixel, "no pair" in the pair picture.
pub(super) const NO_SITE: u32 = u32::MAX;

/// Instance k's pair (i, j), i < j: k = j (j - 1) / 2 + i (`glsl/roof.glsl`).
pub(super) fn pair_of(k: u32) -> (u32, u32) {
    let k = k as u64;
    let mut j = ((1.0 + (1.0 + 8.0 * k as f64).sqrt()) / 2.0).floor() as u64;
    while j * (j - 1) / 2 > k {
        j -= 1;
    }
    while (j + 1) * j / 2 <= k {
        j += 1;
    }
    ((k - j * (j - 1) / 2) as u32, j as u32)
}

/// The roofs of every pair of the chosen sites on one picture.
pub(super) struct Roofs<'m> {
    pub(super) machine: &'m Machine,
    pub(super) frame: Frame,
    /// The chosen sites in picture pixels, `[x, y]` as f64.
    pub(super) sites: Buffer,
    /// The chosen site drawn in each pixel (an index into the chosen ones).
    pub(super) owners: Buffer,
    pub(super) owner: Vec<u32>,
    /// Chosen sites whose pixel shows another.
    pub(super) shared: Vec<u32>,
    pub(super) chosen: usize,
    pub(super) extreme: Extreme,
    /// How far the roofs reach across (an area in pixels squared), if bounded.
    pub(super) bound_px: Option<f64>,
    /// Depth per unit of area (world units squared).
    pub(super) depth_per_area: f64,
}

impl<'m> Roofs<'m> {
    /// The roofs of the `chosen` sites' pairs reaching across as far as `bound`
    /// (an area; `None`: the whole picture), for sites whose hull is `hull`.
    pub(super) fn new(
        machine: &'m Machine,
        sites: &[DVec2],
        chosen: &[u32],
        side: u32,
        extreme: Extreme,
        bound: Option<f64>,
        hull: &[u32],
    ) -> Result<Self> {
        if !machine.has_float64() || !machine.has_fragment_atomics64() {
            return Err(Error::unsupported_option(format!(
                "{} lacks double precision or 64-bit atomics in shaders, which the saddle roofs need",
                machine.device_name()
            )));
        }
        if chosen.len() > 65535 {
            return Err(Error::out_of_range(format!(
                "{} sites make more pairs than one draw can number; at most 65535",
                chosen.len()
            )));
        }
        if side == 0 || side > machine.max_picture_side() {
            return Err(Error::out_of_range(format!(
                "picture side {side}: it must be between 1 and {} on this device",
                machine.max_picture_side()
            )));
        }
        let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).gather("points")?;
        let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        let pad = DVec2::splat(0.01 * (hi - lo).max_element());
        let frame = Frame::fitting(side, lo - pad, hi + pad)?;
        let (w, h) = (frame.width as usize, frame.height as usize);
        let mut owner = crate::memory::filled(w * h, NO_SITE, "the roofs' owners")?;
        let mut shared = Vec::new();
        let mut position: Vec<[f64; 2]> =
            crate::memory::room(points.len(), "the sites' positions")?;
        for (k, p) in points.iter().enumerate() {
            let c = frame.to_pixel(*p);
            position.push([c.x, c.y]);
            let (i, j) = (c.x.round(), c.y.round());
            let inside = i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h;
            let at = j as usize * w + i as usize;
            if inside && owner[at] == NO_SITE {
                owner[at] = k as u32;
            } else {
                shared.push(k as u32);
            }
        }
        let mut sites_buffer = machine.storage_buffer((position.len() * 16) as u64)?;
        sites_buffer.write(&position);
        let mut owners = machine.storage_buffer((owner.len() * 4) as u64)?;
        owners.write(&owner);
        // Widened a little: the shaders take the bound in float32.
        let bound = bound.map(|b| b * (1.0 + 1e-5));
        // Depths: areas up to the bound map into [0, 1/2] (the clear value 1
        // stays clear of the near list); the largest triangle in the hull has at
        // least 3√3/(4π) of its area, so the hull's area keeps it well inside
        // [0, 1].
        let depth_per_area = match bound {
            Some(b) => 0.5 / b,
            None => 1.0 / (convex_ring_area(sites, hull) * 1.001),
        };
        let px2 = frame.scale * frame.scale;
        Ok(Self {
            machine,
            frame,
            sites: sites_buffer,
            owners,
            owner,
            shared,
            chosen: points.len(),
            extreme,
            bound_px: bound.map(|b| b * px2),
            depth_per_area,
        })
    }

    /// A bound on a roof depth's error: the double-precision area of a thin
    /// triangle loses about 2^-50 of the picture's diagonal squared (pixels
    /// squared), and float32 depths round by 2^-24.
    pub(super) fn depth_error(&self) -> f64 {
        let (w, h) = (self.frame.width as f64, self.frame.height as f64);
        let area_error = 2f64.powi(-50) * (w * w + h * h);
        area_error * self.depth_per_area / (self.frame.scale * self.frame.scale) + 2f64.powi(-23)
    }

    /// The area (world units squared) of a roof's depth.
    pub(super) fn area_of_depth(&self, z: f32) -> f64 {
        z as f64 / self.depth_per_area
    }

    pub(super) fn count(&self) -> usize {
        self.chosen * (self.chosen - 1) / 2
    }

    /// The roof programs' push constants (`glsl/roof.glsl`): areas there are in
    /// pixels squared.
    pub(super) fn push(&self, segment: bool) -> RoofWords {
        let depth_per_pixel_area = self.depth_per_area / (self.frame.scale * self.frame.scale);
        [
            (self.frame.width as f32).to_bits(),
            (self.frame.height as f32).to_bits(),
            (self.bound_px.unwrap_or(0.0) as f32).to_bits(),
            (depth_per_pixel_area as f32).to_bits(),
            u32::from(self.extreme == Extreme::Largest),
            u32::from(segment),
        ]
    }

    /// Every pair's roof (`segment`: only over the segment's strip) into
    /// `target`, the fragment shader reading `buffers`: instanced, in about 64
    /// submissions so that `progress(done, total)` can tell how far it is.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn draw_roofs(
        &self,
        program: &'static GraphicsProgram,
        state: &RasterState,
        target: Target<'_>,
        clear: Clear,
        buffers: &[&Buffer],
        segment: bool,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<()> {
        let push = self.push(segment);
        let count = self.count() as u32;
        let chunk = count.div_ceil(64).max(1 << 14);
        // At least one submission, which clears the target.
        for first in (0..count.max(1)).step_by(chunk as usize) {
            let last = (first + chunk).min(count);
            self.machine.run(|pass| {
                pass.bind_fragment_buffers(buffers, None)?;
                pass.begin(target, if first == 0 { clear } else { Clear::default() })?;
                pass.draw(
                    state,
                    &DrawParams::default(),
                    &Draw {
                        program,
                        variant: 0,
                        push: bytemuck::bytes_of(&push),
                        vertex_buffers: &[],
                        vertices: 0..4,
                        instances: first..last,
                    },
                )?;
                pass.end()
            })?;
            progress(last as u64, count as u64);
        }
        Ok(())
    }

    /// Every pair's roof with the depth test keeping the extreme: the depth
    /// ([`Roofs::area_of_depth`]) and the pair picture.
    pub(super) fn draw_triangles(
        &self,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(Image, Image)> {
        let machine = self.machine;
        let (w, h) = (self.frame.width, self.frame.height);
        let depth = machine.image(Format::Depth, w, h)?;
        let pairs = machine.image(Format::R32Uint, w, h)?;
        let (compare, clear) = match self.extreme {
            Extreme::Smallest => (Compare::Less, 1.0),
            Extreme::Largest => (Compare::Greater, 0.0),
        };
        let state = RasterState::OVERWRITE.with_depth(DepthTest {
            compare,
            write: true,
        });
        // A triangle is found by its longest edge's roof: the segment's strip.
        self.draw_roofs(
            &ROOF,
            &state,
            Target {
                color: Some(&pairs),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([NO_SITE; 4])),
                depth: Some(clear),
                stencil: None,
            },
            &[&self.sites, &self.owners],
            true,
            progress,
        )?;
        Ok((depth, pairs))
    }

    /// Every pair's roof keeping, per pair and side, the extreme (area bits,
    /// site) key; returns the keys, two per pair (left, right).
    pub(super) fn draw_sides(&self, progress: &mut dyn FnMut(u64, u64)) -> Result<Vec<u64>> {
        let machine = self.machine;
        let (w, h) = (self.frame.width, self.frame.height);
        let slots = 2 * self.count();
        let mut best = machine.storage_buffer((slots * 8) as u64)?;
        best.fill(match self.extreme {
            Extreme::Smallest => 0xFF,
            Extreme::Largest => 0,
        });
        let depth = machine.image(Format::Depth, w, h)?;
        // A quadrangle's diagonal need not be its longest edge: the whole line.
        self.draw_roofs(
            &ROOF_SIDES,
            &RasterState::OVERWRITE,
            Target {
                color: None,
                depth_stencil: Some(&depth),
            },
            Clear {
                depth: Some(1.0),
                ..Clear::default()
            },
            &[&self.sites, &self.owners, &best],
            false,
            progress,
        )?;
        Ok(best.read(slots))
    }

    /// The pixels that show a site.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a picture whose room was reserved where it was placed"
    )]
    pub(super) fn owned_pixels(&self) -> Vec<usize> {
        (0..self.owner.len())
            .filter(|&k| self.owner[k] != NO_SITE)
            .collect()
    }

    /// The pair picture at `pixels`: one pixel at a time for a few, the whole
    /// picture for many.
    pub(super) fn pairs_at(
        &self,
        machine: &Machine,
        pairs: &Image,
        pixels: &[usize],
    ) -> Result<Vec<u32>> {
        let w = self.frame.width as usize;
        if pixels.len() > 16 {
            let all = machine.read_u32(pairs, PixelRect::of(pairs))?;
            return pixels.iter().map(|&k| all[k]).gather("roof pixels");
        }
        pixels
            .iter()
            .map(|&k| {
                let rect = PixelRect {
                    x: (k % w) as u32,
                    y: (k / w) as u32,
                    width: 1,
                    height: 1,
                };
                Ok(machine.read_u32(pairs, rect)?[0])
            })
            .gather("roof heights")?
    }
}

pub(super) fn extreme_at(near: &crate::machine::DepthExtremes, extreme: Extreme) -> usize {
    match extreme {
        Extreme::Smallest => near.at_min,
        Extreme::Largest => near.at_max,
    }
}
