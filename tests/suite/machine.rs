//! The pixel machine's tests, blending, logic ops, readback and reductions, each
//! checked against what the thesis's model says the pixel must hold.

use pixgeo::machine::*;
use pixgeo::testing::{
    draw_cones, ConeDraw, ConeInstance, ConePush, SiteBatch, SiteShape, CONE_EXACT, CONE_PEEL,
    SITE_EXACT_BATCH,
};

fn machine() -> Machine {
    Machine::from_env().expect("a Vulkan device (run tools/setup)")
}

const W: u32 = 37;
const H: u32 = 23;

fn rect(x0: f32, y0: f32, x1: f32, y1: f32) -> RectDraw {
    // Pixel centres are at integer world points; a rectangle from x0 - 0.5 to
    // x1 + 0.5 covers pixel columns x0..=x1.
    RectDraw {
        lo: [x0 - 0.5, y0 - 0.5],
        hi: [x1 + 0.5, y1 + 0.5],
        depth: 0.0,
        value: [0.0; 4],
    }
}

#[test]
fn depth_test_keeps_nearest_and_logic_ops_combine_bits() {
    let m = machine();
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    let depth = m.image(Format::DepthStencil, W, H).unwrap();
    m.run(|p| {
        p.begin(
            Target {
                color: Some(&ids),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([0; 4])),
                depth: Some(1.0),
                stencil: Some(0),
            },
        )?;
        let env = RasterState::lower_envelope();
        let d = DrawParams::default();
        // Far rectangle over everything, near one over the left part.
        p.draw_rect(
            &env,
            &d,
            &RectDraw::full_picture(W, H)
                .uint([7, 0, 0, 0])
                .at_depth(0.5),
        )?;
        p.draw_rect(
            &env,
            &d,
            &rect(0.0, 0.0, 9.0, 22.0).uint([3, 0, 0, 0]).at_depth(0.25),
        )?;
        // Drawn later but farther: loses.
        p.draw_rect(
            &env,
            &d,
            &rect(0.0, 0.0, 4.0, 22.0).uint([9, 0, 0, 0]).at_depth(0.75),
        )?;
        // XOR then OR, no depth test.
        let xor = RasterState::OVERWRITE.with_color(ColorUpdate::Logic(LogicOp::Xor));
        p.draw_rect(
            &xor,
            &d,
            &rect(20.0, 0.0, 36.0, 22.0).uint([0b101, 0, 0, 0]),
        )?;
        let or = RasterState::OVERWRITE.with_color(ColorUpdate::Logic(LogicOp::Or));
        p.draw_rect(
            &or,
            &d,
            &rect(30.0, 0.0, 36.0, 22.0).uint([0b1000, 0, 0, 0]),
        )?;
        p.end()
    })
    .unwrap();
    let v = m.read_u32(&ids, PixelRect::of(&ids)).unwrap();
    let z = m.read_f32(&depth, PixelRect::of(&depth)).unwrap();
    for j in 0..H as usize {
        for i in 0..W as usize {
            let expect = match i {
                0..=9 => 3,
                20..=29 => 7 ^ 0b101,
                30.. => (7 ^ 0b101) | 0b1000,
                _ => 7,
            };
            assert_eq!(v[j * W as usize + i], expect, "pixel ({i}, {j})");
            let expect_z = if i <= 9 { 0.25 } else { 0.5 };
            assert_eq!(z[j * W as usize + i], expect_z, "depth ({i}, {j})");
        }
    }
    let mm = m.minmax(&ids, PixelRect::of(&ids)).unwrap();
    assert_eq!((mm.min[0], mm.max[0]), (2.0, 10.0));
    // Three distinct states were drawn: three pipelines; drawing them again from
    // the cache adds none.
    assert_eq!(m.pipeline_count(), 3);
    m.run(|p| {
        p.begin(
            Target {
                color: Some(&ids),
                depth_stencil: Some(&depth),
            },
            Clear::default(),
        )?;
        let xor = RasterState::OVERWRITE.with_color(ColorUpdate::Logic(LogicOp::Xor));
        p.draw_rect(
            &xor,
            &DrawParams::default(),
            &rect(0.0, 0.0, 1.0, 1.0).uint([0; 4]),
        )?;
        p.draw_rect(
            &RasterState::lower_envelope(),
            &DrawParams::default(),
            &RectDraw::full_picture(W, H).at_depth(0.9),
        )?;
        p.end()
    })
    .unwrap();
    assert_eq!(m.pipeline_count(), 3);
    let part = m
        .minmax(
            &ids,
            PixelRect {
                x: 10,
                y: 5,
                width: 10,
                height: 3,
            },
        )
        .unwrap();
    assert_eq!((part.min[0], part.max[0]), (7.0, 7.0));
    let h = m
        .histogram(
            &ids,
            PixelRect::of(&ids),
            Bins {
                channel: 0,
                low: 0.0,
                width: 4.0,
                bins: 4,
            },
        )
        .unwrap();
    // values 3 (10 cols), 7 (10 cols), 2 (10 cols), 10 (7 cols)
    assert_eq!(h, vec![20 * H, 10 * H, 7 * H, 0]);
}

#[test]
fn stencil_counts_and_blending_adds() {
    let m = machine();
    let counts = m.image(Format::Rgba32Float, W, H).unwrap();
    let ds = m.image(Format::DepthStencil, W, H).unwrap();
    m.run(|p| {
        p.begin(
            Target {
                color: Some(&counts),
                depth_stencil: Some(&ds),
            },
            Clear {
                color: Some(ClearColor::Float([0.0; 4])),
                depth: Some(1.0),
                stencil: Some(0),
            },
        )?;
        let d = DrawParams::default();
        let count = RasterState::count_with_blending();
        for k in 0..5 {
            let x1 = 5.0 + 6.0 * k as f32;
            p.draw_rect(
                &count,
                &d,
                &rect(0.0, 0.0, x1, 22.0).float([1.0, 0.5, 0.0, 2.0]),
            )?;
        }
        // Stencil: count overlaps with wrap, then keep only pixels whose count is 2
        // and paint them via the stencil EQUAL test.
        let stencil_count = RasterState::count_with_stencil_wrap();
        p.draw_rect(&stencil_count, &d, &rect(0.0, 0.0, 36.0, 10.0))?;
        p.draw_rect(&stencil_count, &d, &rect(0.0, 5.0, 36.0, 22.0))?;
        let only_two = RasterState::OVERWRITE
            .with_stencil(StencilTest {
                compare: Compare::Equal,
                compare_mask: 0xff,
                write_mask: 0xff,
                on_fail: StencilOp::Keep,
                on_depth_fail: StencilOp::Keep,
                on_pass: StencilOp::Invert,
            })
            .with_color_mask(ChannelMask {
                red: false,
                green: false,
                blue: true,
                alpha: false,
            });
        let params = DrawParams {
            stencil_reference: 2,
            ..Default::default()
        };
        p.draw_rect(
            &only_two,
            &params,
            &RectDraw::full_picture(W, H).float([9.0; 4]),
        )?;
        // Scissor: only columns 0..2 of rows 0..2 get a constant blend added.
        let constant = RasterState::OVERWRITE.with_color(ColorUpdate::Blend(Blend {
            fragment_factor: BlendFactor::Constant,
            pixel_factor: BlendFactor::One,
            op: BlendOp::Add,
        }));
        let params = DrawParams {
            blend_constant: [0.0, 0.0, 0.0, 100.0],
            scissor: Some([0, 0, 2, 2]),
            ..Default::default()
        };
        p.draw_rect(
            &constant,
            &params,
            &RectDraw::full_picture(W, H).float([1.0; 4]),
        )?;
        p.end()
    })
    .unwrap();
    let v = m.read_f32(&counts, PixelRect::of(&counts)).unwrap();
    for j in 0..H as usize {
        for i in 0..W as usize {
            let n = (0..5).filter(|k| i <= 5 + 6 * k).count() as f32;
            let px = &v[4 * (j * W as usize + i)..][..4];
            let blue = if (5..=10).contains(&j) { 9.0 } else { 0.0 };
            let alpha = 2.0 * n + if i < 2 && j < 2 { 100.0 } else { 0.0 };
            assert_eq!(px, &[n, 0.5 * n, blue, alpha], "pixel ({i}, {j})");
        }
    }
    let mm = m.minmax(&counts, PixelRect::of(&counts)).unwrap();
    assert_eq!(mm.channels, 4);
    assert_eq!(mm.max, [5.0, 2.5, 9.0, 110.0]);
    assert_eq!(mm.min, [0.0, 0.0, 0.0, 0.0]);
    let h = m
        .histogram(
            &counts,
            PixelRect::of(&counts),
            Bins {
                channel: 0,
                low: 0.0,
                width: 1.0,
                bins: 6,
            },
        )
        .unwrap();
    assert_eq!(h, vec![7 * H, 6 * H, 6 * H, 6 * H, 6 * H, 6 * H]);
}

#[test]
fn bad_requests_are_errors() {
    let m = machine();
    assert!(m.image(Format::R32Uint, 0, 5).is_err());
    let side = m.max_picture_side();
    assert!(matches!(
        m.image(Format::R32Uint, side + 1, 1),
        Err(pixgeo::Error::PictureTooLarge { .. })
    ));
    let ids = m.image(Format::R32Uint, 4, 4).unwrap();
    assert!(m.read_f32(&ids, PixelRect::of(&ids)).is_err());
    assert!(m
        .minmax(
            &ids,
            PixelRect {
                x: 3,
                y: 0,
                width: 2,
                height: 1
            }
        )
        .is_err());
    // Blending into an integer target is refused, not undefined.
    let r = m.run(|p| {
        p.begin(
            Target {
                color: Some(&ids),
                depth_stencil: None,
            },
            Clear::default(),
        )?;
        p.draw_rect(
            &RasterState::count_with_blending(),
            &DrawParams::default(),
            &RectDraw::full_picture(4, 4),
        )
    });
    assert!(r.is_err());
    // Sites are batched for points, segments and circles under L2, L1 and L∞,
    // and Euclidean arcs: an L1 arc or an L_p batch is refused, as is a shader
    // build that does not exist.
    let depth = m.image(Format::DepthStencil, 4, 4).unwrap();
    let mesh = m.vertex_buffer(&[[0.0f32; 3]; 6]).unwrap();
    let batch = SiteBatch {
        rect: [0.0, 0.0, 4.0, 4.0],
        shapes: [[1.0; 4]; 8],
        weights: [[1.0, 0.0]; 8],
        ids: [0; 8],
    };
    let instances = m.vertex_buffer(&[batch]).unwrap();
    // Power-sum keys (kind 4) are built for exact point cones only.
    let refused = [
        (&SITE_EXACT_BATCH[SiteShape::Arc as usize], (1, 1.0)),
        (&SITE_EXACT_BATCH[SiteShape::Point as usize], (3, 3.0)),
        (&CONE_PEEL, (4, 3.0)),
    ];
    for (program, metric) in refused {
        let r = m.run(|p| {
            p.begin(
                Target {
                    color: Some(&ids),
                    depth_stencil: Some(&depth),
                },
                Clear::default(),
            )?;
            draw_cones(
                p,
                program,
                &RasterState::lower_envelope(),
                &DrawParams::default(),
                &ConePush {
                    picture_size: [4.0, 4.0],
                    offset: [0.0, 0.0],
                    vertex_depth_scale: 0.0,
                    fragment_depth_scale: 1.0,
                    levels: 1,
                    metric: metric.into(),
                },
                &ConeDraw {
                    mesh: &mesh,
                    first_vertex: 0,
                    vertex_count: 6,
                    instances: &instances,
                    first_instance: 0,
                    instance_count: 1,
                },
            )?;
            p.end()
        });
        assert!(r.is_err(), "{} with metric {metric:?}", program.name);
    }
    // Shaders' buffer accesses stay within the bound buffers.
    assert!(m.has_robust_buffer_access());
    // A draw must give its program's push bytes and vertex buffers, ranges
    // within those buffers, and a program writing ids needs an integer target.
    let floats = m.image(Format::R32Float, 4, 4).unwrap();
    let push = ConePush {
        picture_size: [4.0, 4.0],
        offset: [0.0, 0.0],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: 1.0,
        levels: 1,
        metric: (0, 2.0).into(),
    };
    let cones = m
        .vertex_buffer(&[ConeInstance::new(0, [1.0, 1.0], 2.0, 2.0)])
        .unwrap();
    let whole = bytemuck::bytes_of(&push);
    let both = [&mesh, &cones];
    let draws: [(&Image, &[u8], &[&Buffer], _, _, &str); 5] = [
        (&ids, &whole[..8], &both, 0..6, 0..1, "push"),
        (&ids, whole, &both[..1], 0..6, 0..1, "vertex buffers"),
        (&floats, whole, &both, 0..6, 0..1, "needs a"),
        (&ids, whole, &both, 0..7, 0..1, "of a vertex buffer of 72"),
        (&ids, whole, &both, 0..6, 1..2, "2 instances"),
    ];
    for (target, push, buffers, vertices, instances, refusal) in draws {
        let r = m.run(|p| {
            p.begin(
                Target {
                    color: Some(target),
                    depth_stencil: None,
                },
                Clear::default(),
            )?;
            p.draw(
                &RasterState::OVERWRITE,
                &DrawParams::default(),
                &Draw {
                    program: &CONE_EXACT,
                    variant: 0,
                    push,
                    vertex_buffers: buffers,
                    vertices,
                    instances,
                },
            )?;
            p.end()
        });
        let usage = matches!(r, Err(pixgeo::Error::Usage(_)));
        let message = r.err().map(|e| e.to_string()).unwrap_or_default();
        assert!(usage && message.contains(refusal), "{refusal}: {message}");
    }
}

#[test]
fn depth_extremes_find_the_extreme_pixels_and_those_near_them() {
    let m = machine();
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    let depth = m.image(Format::Depth, W, H).unwrap();
    m.run(|p| {
        p.begin(
            Target {
                color: Some(&ids),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([0; 4])),
                depth: Some(0.5),
                stencil: None,
            },
        )?;
        let always = RasterState {
            depth: DepthTest {
                compare: Compare::Always,
                write: true,
            },
            ..RasterState::OVERWRITE
        };
        let d = DrawParams::default();
        p.draw_rect(&always, &d, &rect(3.0, 2.0, 5.0, 4.0).at_depth(0.25))?;
        p.draw_rect(&always, &d, &rect(30.0, 20.0, 30.0, 20.0).at_depth(0.125))?;
        p.draw_rect(&always, &d, &rect(10.0, 7.0, 11.0, 7.0).at_depth(0.875))?;
        p.end()
    })
    .unwrap();
    let at = |i: usize, j: usize| j * W as usize + i;
    let plain = m.depth_extremes(&depth, None).unwrap();
    assert_eq!((plain.min, plain.max), (0.125, 0.875));
    assert_eq!((plain.at_min, plain.at_max), (at(30, 20), at(10, 7)));
    assert!(plain.near.is_empty());
    // Within 0.2 of the minimum: the lone pixel and the 3x3 block.
    let low = m
        .depth_extremes(
            &depth,
            Some(NearExtreme {
                maximum: false,
                within: 0.2,
                squared_scale: 0.0,
                capacity: 64,
            }),
        )
        .unwrap();
    let mut near = low.near.clone();
    near.sort_unstable();
    let mut expect: Vec<usize> = (2..=4)
        .flat_map(|j| (3..=5).map(move |i| at(i, j)))
        .collect();
    expect.push(at(30, 20));
    expect.sort_unstable();
    assert_eq!(near, expect);
    assert_eq!((low.near_count, low.at_min), (10, at(30, 20)));
    // The maximum's two pixels, and a list too short for the others.
    let high = m
        .depth_extremes(
            &depth,
            Some(NearExtreme {
                maximum: true,
                within: 0.5,
                squared_scale: 0.0,
                capacity: 4,
            }),
        )
        .unwrap();
    assert_eq!(high.at_max, at(10, 7));
    assert_eq!(high.near.len(), 4);
    // Everything but the ten low pixels is within 0.5 of the maximum.
    assert_eq!(high.near_count, W as usize * H as usize - 10);
}

#[test]
fn a_profiler_labels_and_times_every_pass_and_run() {
    let profiler = Profiler::new();
    let m = Machine::new(&MachineOptions::from_env().profiler(Some(profiler.clone())))
        .expect("a Vulkan device (run tools/setup)");
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    m.run(|p| {
        let target = Target {
            color: Some(&ids),
            depth_stencil: None,
        };
        p.begin(target, Clear::default())?;
        p.end()?;
        p.begin(target, Clear::default())?;
        let full = RectDraw::full_picture(W, H).uint([5, 0, 0, 0]);
        p.draw_rect(
            &RasterState::lower_envelope(),
            &DrawParams::default(),
            &full,
        )?;
        p.end()
    })
    .unwrap();
    let counts = m.minmax(&ids, PixelRect::of(&ids)).unwrap();
    assert_eq!(counts.max[0], 5.0);
    assert_eq!(m.read_u32(&ids, PixelRect::of(&ids)).unwrap()[0], 5);

    let timeline = profiler.timeline();
    let labels: Vec<&str> = timeline.passes.iter().map(|p| p.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "render: clear",
            "render: Rect",
            "reduce MinMax",
            "copy to buffer"
        ]
    );
    // One host span per run: the drawing, the reduction, the readback.
    assert_eq!(timeline.host.len(), 3);
    for pass in &timeline.passes {
        let ms = pass.gpu_ms.expect("lavapipe and GPUs write timestamps");
        assert!(ms.is_finite() && ms >= 0.0, "{pass:?}");
        assert!(
            pass.start_ms.is_finite() && pass.start_ms >= 0.0,
            "{pass:?}"
        );
    }
    let by_pass = timeline.gpu_ms_by_pass();
    assert_eq!(by_pass.len(), 4);

    let trace = pixgeo_io::trace::chrome_trace(&timeline);
    let events = trace["traceEvents"].as_array().unwrap();
    let spans = events.iter().filter(|e| e["ph"] == "X").count();
    assert_eq!(spans, timeline.passes.len() + timeline.host.len());
    assert!(events
        .iter()
        .any(|e| e["name"] == "reduce MinMax" && e["tid"] == 2));

    // A machine without a profiler records nothing anywhere.
    let before = profiler.timeline();
    let other = machine();
    let picture = other.image(Format::R32Uint, W, H).unwrap();
    other.minmax(&picture, PixelRect::of(&picture)).unwrap();
    assert_eq!(profiler.timeline(), before);
}

/// A machine with the validation layer on whatever the environment says: the
/// tests of the machine's rules need it to see what a broken rule would do.
fn validated(options: MachineOptions) -> Machine {
    Machine::new(&options.validation(true)).expect("a Vulkan device with its validation layer")
}

fn clear_ids(ids: &Image) -> Target<'_> {
    Target {
        color: Some(ids),
        depth_stencil: None,
    }
}

#[test]
fn a_machine_refuses_another_machines_images_and_buffers() {
    let (a, b) = (machine(), machine());
    let theirs = b.image(Format::R32Uint, W, H).unwrap();
    let err = a
        .run(|p| p.begin(clear_ids(&theirs), Clear::default()))
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    let err = a.read_u32(&theirs, PixelRect::of(&theirs)).unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    let ours = a.image(Format::R32Uint, W, H).unwrap();
    let their_buffer = b.readback_buffer(4 * u64::from(W * H)).unwrap();
    let err = a
        .run(|p| p.copy_to_buffer(&ours, PixelRect::of(&ours), &their_buffer))
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    // Each machine still works with its own.
    assert_eq!(
        b.read_u32(&theirs, PixelRect::sized(1, 1)).unwrap().len(),
        1
    );
}

#[test]
fn a_run_inside_a_run_is_refused_and_the_machine_goes_on() {
    let m = validated(MachineOptions::from_env());
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    let clear = Clear {
        color: Some(ClearColor::Uint([5; 4])),
        ..Clear::default()
    };
    let err = m
        .run(|p| {
            p.begin(clear_ids(&ids), clear)?;
            p.end()?;
            m.read_u32(&ids, PixelRect::of(&ids)).map(|_| ())
        })
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    let err = m.run(|_| m.minmax(&ids, PixelRect::of(&ids))).unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    m.run(|p| {
        p.begin(clear_ids(&ids), clear)?;
        p.end()
    })
    .unwrap();
    assert!(m
        .read_u32(&ids, PixelRect::of(&ids))
        .unwrap()
        .iter()
        .all(|&v| v == 5));
}

#[test]
fn a_failed_run_leaves_its_images_as_they_were() {
    let m = validated(MachineOptions::from_env());
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    let clear = Clear {
        color: Some(ClearColor::Uint([9; 4])),
        ..Clear::default()
    };
    m.run(|p| {
        p.begin(clear_ids(&ids), clear)?;
        p.end()
    })
    .unwrap();
    m.read_u32(&ids, PixelRect::of(&ids)).unwrap(); // now a copy source
                                                    // Recorded, never submitted: the image stays a copy source on the device.
    let err = m
        .run(|p| {
            p.begin(clear_ids(&ids), Clear::default())?;
            p.end()?;
            Err::<(), _>(pixgeo::Error::malformed("stop".into()))
        })
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::InvalidInput(_)));
    // A barrier from the failed run's layout would be a validation error here.
    let read = m.read_u32(&ids, PixelRect::of(&ids)).unwrap();
    assert!(read.iter().all(|&v| v == 9));
}

#[test]
fn a_device_no_one_has_is_named_as_the_user_wrote_it() {
    let mut options = MachineOptions::from_env();
    options.device = DeviceChoice::parse(" No Such GPU 9000 ");
    let error = Machine::new(&options)
        .err()
        .expect("no device has that name");
    assert!(matches!(error, pixgeo::Error::NoDevice(_)), "{error}");
    assert!(
        error
            .to_string()
            .contains("device `No Such GPU 9000` matches none of"),
        "{error}"
    );
}

#[test]
fn what_the_device_did_not_enable_is_refused() {
    let m = validated(MachineOptions::from_env().core_features_only(true));
    assert!(!m.has_logic_op() && !m.has_float64() && !m.has_fragment_atomics64());
    let ids = m.image(Format::R32Uint, W, H).unwrap();
    let xor = RasterState::OVERWRITE.with_color(ColorUpdate::Logic(LogicOp::Xor));
    let err = m
        .run(|p| {
            p.begin(clear_ids(&ids), Clear::default())?;
            p.draw_rect(&xor, &DrawParams::default(), &RectDraw::full_picture(W, H))?;
            p.end()
        })
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Unsupported(_)), "{err}");

    // glsl/roof.frag computes in double precision with 64-bit atomics.
    static ROOF: GraphicsProgram = GraphicsProgram::new(
        "Roof",
        shaders::ROOF_VERT,
        Fragments::One(shaders::ROOF_FRAG_TRIANGLE),
        Topology::TriangleStrip,
        &[],
        std::mem::size_of::<[u32; 6]>(),
    );
    const { assert!(shaders::ROOF_FRAG_TRIANGLE.needs.float64) };
    let words = [0u32; 6];
    let err = m
        .run(|p| {
            p.begin(clear_ids(&ids), Clear::default())?;
            p.draw(
                &RasterState::OVERWRITE,
                &DrawParams::default(),
                &Draw {
                    program: &ROOF,
                    variant: 0,
                    push: bytemuck::cast_slice(&words),
                    vertex_buffers: &[],
                    vertices: 0..4,
                    instances: 0..1,
                },
            )?;
            p.end()
        })
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Unsupported(_)), "{err}");
}

/// One pass of jump flooding (push `[width, height, step, first pixel]`),
/// declared as a user would, with each buffer's reach: a pixel's seed each.
static FLOOD_STEP: ComputeProgram = ComputeProgram::new(
    "FloodStep",
    shaders::JUMP_FLOOD_COMP,
    16,
    &[
        Extent::Push(|p| 4 * p[0] as u64 * p[1] as u64),
        Extent::Push(|p| 4 * p[0] as u64 * p[1] as u64),
    ],
);

#[test]
fn a_dispatch_past_a_buffers_end_is_refused_before_it_runs() {
    let m = machine();
    let (w, h) = (16u32, 8u32);
    let full = m.storage_buffer(4 * u64::from(w * h)).unwrap();
    let short = m.storage_buffer(4 * u64::from(w * h) - 4).unwrap();
    let push = |w: u32, h: u32| [w, h, 1, 0];
    let dispatch = |before: &Buffer, after: &Buffer, push: [u32; 4]| {
        m.run(|p| {
            p.dispatch(
                &FLOOD_STEP,
                &[before, after],
                w * h,
                bytemuck::bytes_of(&push),
            )
        })
    };
    dispatch(&full, &full, push(w, h)).expect("buffers that hold the picture");
    for (before, after) in [(&short, &full), (&full, &short)] {
        let err = dispatch(before, after, push(w, h)).unwrap_err();
        assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
        assert!(err.to_string().contains("reaches 512 bytes"), "{err}");
    }
    // A picture the push constants say is larger than the buffers.
    let err = dispatch(&full, &full, push(w, h + 1)).unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
    // Fewer buffers than the kernel declares.
    let err = m
        .run(|p| {
            p.dispatch(
                &FLOOD_STEP,
                &[&full],
                w * h,
                bytemuck::bytes_of(&push(w, h)),
            )
        })
        .unwrap_err();
    assert!(matches!(err, pixgeo::Error::Usage(_)), "{err}");
}
