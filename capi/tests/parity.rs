//! The C library answers as the core does, bit for bit, on a context without
//! Vulkan (`device_name = "cpu"`) and on a device's: the nearest, the two
//! nearest and the furthest sites and Delaunay triangles of every input of the
//! parity generator, and a diagram of weighted sites.

// The tests call the C boundary as a C host does.
#![allow(unsafe_code)]

use std::{ffi::CStr, ptr};

use pixgeo::{
    algorithms::{
        delaunay::{delaunay, DelaunayOptions},
        higher_order::{furthest, k_nearest, KNearestOptions},
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Backend, Site,
};
use pixgeo_c::*;
use pixgeo_reference::hostile::hostile;

/// A context on `device` ("cpu" or "lavapipe"), destroyed when dropped.
struct Context(*mut PixgeoContext);

impl Context {
    fn new(device: &CStr) -> Self {
        let mut options = pixgeo_context_options_default();
        options.device_name = device.as_ptr();
        options.validation = std::env::var_os("PIXGEO_VALIDATION").is_some();
        let mut ctx = ptr::null_mut();
        // SAFETY: valid options and a place for the context.
        let status = unsafe { pixgeo_context_create(&options, &mut ctx) };
        assert_eq!(status, PixgeoStatus::Ok, "a {device:?} context");
        Self(ctx)
    }

    /// The last error's message.
    fn error(&self) -> String {
        // SAFETY: a live context; the message is valid until the next call.
        unsafe { CStr::from_ptr(pixgeo_context_last_error(self.0)) }
            .to_string_lossy()
            .into_owned()
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: made by `pixgeo_context_create`, destroyed once.
        unsafe { pixgeo_context_destroy(self.0) };
    }
}

/// `pixgeo_voronoi` and `pixgeo_furthest`: labels and distances of a picture.
type Raster = unsafe extern "C" fn(
    *mut PixgeoContext,
    *const f64,
    usize,
    *const PixgeoVoronoiOptions,
    *mut u32,
    *mut f32,
) -> PixgeoStatus;

fn bits(d: &[f32]) -> Vec<u32> {
    d.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn the_c_library_answers_as_the_core_on_every_context() {
    for device in [c"cpu", c"lavapipe"] {
        let ctx = Context::new(device);
        for case in hostile(28, 20) {
            let name = format!("{device:?} {}", case.name);
            let bbox = case.bbox();
            let frame = Frame::with_bbox(28, Some(20), bbox).unwrap();
            let xy: Vec<f64> = case.sites.iter().flat_map(|p| [p.x, p.y]).collect();
            let mut options = pixgeo_voronoi_options_default(28, 20);
            options.use_bbox = true;
            options.bbox = bbox;
            let (mut labels, mut distances) = (vec![0u32; frame.len()], vec![0f32; frame.len()]);

            let nearest =
                voronoi(&Backend::Cpu, &case.sites, &VoronoiOptions::exact(frame)).unwrap();
            let far = furthest(&Backend::Cpu, &case.sites, &frame, Metric::L2).unwrap();
            let rasters: [(&str, Raster, _, _); 2] = [
                ("nearest", pixgeo_voronoi, nearest.labels, nearest.distances),
                ("furthest", pixgeo_furthest, far.labels, far.distances),
            ];
            for (what, call, want_labels, want_distances) in rasters {
                // SAFETY: `xy` holds 2n doubles; the rasters hold the picture's pixels.
                let status = unsafe {
                    call(
                        ctx.0,
                        xy.as_ptr(),
                        case.sites.len(),
                        &options,
                        labels.as_mut_ptr(),
                        distances.as_mut_ptr(),
                    )
                };
                assert_eq!(status, PixgeoStatus::Ok, "{name} {what}: {}", ctx.error());
                assert!(labels == want_labels, "{name}: {what} labels");
                assert!(
                    bits(&distances) == bits(&want_distances),
                    "{name}: {what} distances"
                );
            }

            let two = k_nearest(
                &Backend::Cpu,
                &case.sites,
                &KNearestOptions::exact(frame, 2),
            );
            let (mut levels, mut level_distances) =
                (vec![0u32; 2 * frame.len()], vec![0f32; 2 * frame.len()]);
            // SAFETY: `xy` holds 2n doubles; the rasters hold two levels a pixel.
            let status = unsafe {
                pixgeo_k_nearest(
                    ctx.0,
                    xy.as_ptr(),
                    case.sites.len(),
                    &options,
                    2,
                    levels.as_mut_ptr(),
                    level_distances.as_mut_ptr(),
                )
            };
            let two = two.unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(
                status,
                PixgeoStatus::Ok,
                "{name} two nearest: {}",
                ctx.error()
            );
            assert!(levels == two.labels, "{name}: two nearest labels");
            assert!(
                bits(&level_distances) == bits(&two.distances),
                "{name}: two nearest distances"
            );

            let want = delaunay(&Backend::Cpu, &case.sites, &DelaunayOptions::default());
            let capacity = 2 * case.sites.len();
            let (mut triangles, mut count, mut repeats) = (vec![0u32; 3 * capacity], 0, 0);
            // SAFETY: room for `capacity` triangles and the two counts.
            let status = unsafe {
                pixgeo_delaunay(
                    ctx.0,
                    xy.as_ptr(),
                    case.sites.len(),
                    0,
                    triangles.as_mut_ptr(),
                    capacity,
                    &mut count,
                    &mut repeats,
                )
            };
            match want {
                Ok(d) => {
                    assert_eq!(status, PixgeoStatus::Ok, "{name}: {}", ctx.error());
                    let flat: Vec<u32> = d.triangles.iter().flatten().copied().collect();
                    assert!(triangles[..3 * count] == flat[..], "{name}: triangles");
                    assert_eq!(repeats, d.duplicates.len(), "{name}: repeats");
                }
                Err(e) => {
                    assert_eq!(status, PixgeoStatus::InvalidArgument, "{name}");
                    assert!(
                        ctx.error().contains(&e.to_string()),
                        "{name}: {}",
                        ctx.error()
                    );
                }
            }
        }
    }
}

#[test]
fn weighted_sites_answer_as_the_core_on_every_context() {
    let frame = Frame::pixels(24, 16).unwrap();
    let at = [
        (3.0, 4.0, 1.0),
        (17.5, 9.0, 2.0),
        (9.0, 12.5, 0.5),
        (20.0, 2.0, 1.5),
    ];
    let sites: Vec<Site> = at
        .iter()
        .map(|&(x, y, m)| Site {
            multiplicative: m,
            ..Site::point(glam::DVec2::new(x, y))
        })
        .collect();
    let given: Vec<PixgeoSite> = at
        .iter()
        .map(|&(x, y, m)| PixgeoSite {
            kind: PixgeoSiteKind::Point as u32,
            coords: [x, y, 0.0, 0.0, 0.0],
            multiplicative: m,
            additive: 0.0,
        })
        .collect();
    let want = voronoi(&Backend::Cpu, &sites, &VoronoiOptions::exact(frame)).unwrap();
    for device in [c"cpu", c"lavapipe"] {
        let ctx = Context::new(device);
        let options = pixgeo_voronoi_options_default(24, 16);
        let (mut labels, mut distances) = (vec![0u32; frame.len()], vec![0f32; frame.len()]);
        // SAFETY: `given` holds its sites; the rasters hold the picture's pixels.
        let status = unsafe {
            pixgeo_voronoi_sites(
                ctx.0,
                given.as_ptr(),
                given.len(),
                &options,
                labels.as_mut_ptr(),
                distances.as_mut_ptr(),
            )
        };
        assert_eq!(status, PixgeoStatus::Ok, "{device:?}: {}", ctx.error());
        assert!(labels == want.labels, "{device:?}: labels");
        assert!(
            bits(&distances) == bits(&want.distances),
            "{device:?}: distances"
        );
    }
}
