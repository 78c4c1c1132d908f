//! The C library answers as the core does, bit for bit, on a context without
//! Vulkan (`device_name = "cpu"`) and on a device's: the nearest and furthest
//! sites and Delaunay triangles of every input of the parity generator.

use std::{ffi::CStr, ptr};

use pixgeo::{
    algorithms::{
        delaunay::{delaunay, DelaunayOptions},
        higher_order::furthest,
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Backend,
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
