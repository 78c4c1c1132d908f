//! The state of the raster pipeline in the thesis's vocabulary (ch. 1.4–1.6): which
//! tests a fragment must pass and how it updates the pixel. A plain value; the
//! pipeline cache turns each distinct value into a `VkPipeline`. The stencil
//! reference, the scissor rectangle and the blend constant are set per draw.

/// Comparison of the depth and stencil tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Compare {
    Never,
    Less,
    Equal,
    LessOrEqual,
    Greater,
    NotEqual,
    GreaterOrEqual,
    Always,
}

/// The depth (z) test: the fragment's depth against the pixel's z buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DepthTest {
    pub compare: Compare,
    /// Whether a passing fragment overwrites the z buffer.
    pub write: bool,
}

impl DepthTest {
    /// No test and no write: every fragment passes.
    pub const OFF: Self = Self {
        compare: Compare::Always,
        write: false,
    };
}

/// What happens to the pixel's stencil value (thesis §1.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StencilOp {
    Keep,
    Zero,
    /// Replace with the reference value.
    Replace,
    IncrementClamp,
    DecrementClamp,
    IncrementWrap,
    DecrementWrap,
    Invert,
}

/// The stencil test: `(reference & compare_mask) compare (stencil & compare_mask)`,
/// and the three updates for fail, depth fail and pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StencilTest {
    pub compare: Compare,
    pub compare_mask: u8,
    pub write_mask: u8,
    pub on_fail: StencilOp,
    pub on_depth_fail: StencilOp,
    pub on_pass: StencilOp,
}

impl StencilTest {
    /// No test and no update.
    pub const OFF: Self = Self {
        compare: Compare::Always,
        compare_mask: 0xff,
        write_mask: 0,
        on_fail: StencilOp::Keep,
        on_depth_fail: StencilOp::Keep,
        on_pass: StencilOp::Keep,
    };

    /// A test that passes where `(reference & compare_mask) compare
    /// (stencil & compare_mask)` and, where depth passes too, applies `on_pass`
    /// to the bits of `write_mask`; failing fragments leave the stencil alone.
    pub const fn on_pass(
        compare: Compare,
        compare_mask: u8,
        write_mask: u8,
        on_pass: StencilOp,
    ) -> Self {
        Self {
            compare,
            compare_mask,
            write_mask,
            on_fail: StencilOp::Keep,
            on_depth_fail: StencilOp::Keep,
            on_pass,
        }
    }
}

/// Blending factors: the thesis's table in Fig. 1.9 ("source" is the fragment,
/// "destination" the pixel).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlendFactor {
    Zero,
    One,
    Source,
    OneMinusSource,
    Destination,
    OneMinusDestination,
    SourceAlpha,
    OneMinusSourceAlpha,
    DestinationAlpha,
    OneMinusDestinationAlpha,
    Constant,
    OneMinusConstant,
    ConstantAlpha,
    OneMinusConstantAlpha,
    /// `min(alpha_P, 1 - alpha_F)`, fragment side only.
    SourceAlphaSaturate,
}

/// How the blended terms are combined.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlendOp {
    Add,
    Subtract,
    ReverseSubtract,
    Min,
    Max,
}

/// `pixel = fragment * fragment_factor (op) pixel * pixel_factor`, per channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Blend {
    pub fragment_factor: BlendFactor,
    pub pixel_factor: BlendFactor,
    pub op: BlendOp,
}

impl Blend {
    /// Adds the fragment to the pixel: counting.
    pub const ADD: Self = Self {
        fragment_factor: BlendFactor::One,
        pixel_factor: BlendFactor::One,
        op: BlendOp::Add,
    };
}

/// Bitwise combination of fragment F and pixel P (thesis Fig. 1.10).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LogicOp {
    Clear,
    And,
    /// F and not P.
    AndReverse,
    Copy,
    /// not F and P.
    AndInverted,
    NoOp,
    Xor,
    Or,
    Nor,
    Equivalent,
    Invert,
    /// F or not P.
    OrReverse,
    CopyInverted,
    /// not F or P.
    OrInverted,
    Nand,
    Set,
}

/// How a fragment that passed all tests updates the colour buffer (thesis §1.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColorUpdate {
    Overwrite,
    Blend(Blend),
    Logic(LogicOp),
}

/// Which colour channels may be written (thesis §1.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ChannelMask {
    pub red: bool,
    pub green: bool,
    pub blue: bool,
    pub alpha: bool,
}

impl ChannelMask {
    pub const ALL: Self = Self {
        red: true,
        green: true,
        blue: true,
        alpha: true,
    };
    pub const NONE: Self = Self {
        red: false,
        green: false,
        blue: false,
        alpha: false,
    };
}

/// The raster pipeline's state: tests and colour update, as one hashable value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RasterState {
    pub depth: DepthTest,
    pub stencil: StencilTest,
    pub color: ColorUpdate,
    pub color_mask: ChannelMask,
}

impl RasterState {
    /// Everything passes, the colour is overwritten.
    pub const OVERWRITE: Self = Self {
        depth: DepthTest::OFF,
        stencil: StencilTest::OFF,
        color: ColorUpdate::Overwrite,
        color_mask: ChannelMask::ALL,
    };

    /// The lower envelope of surfaces (thesis §3.2): the nearest fragment wins and
    /// writes its colour and depth. Ties keep the first drawn.
    pub const fn lower_envelope() -> Self {
        Self {
            depth: DepthTest {
                compare: Compare::Less,
                write: true,
            },
            ..Self::OVERWRITE
        }
    }

    /// Counting with blending: every fragment adds its colour to the pixel.
    pub const fn count_with_blending() -> Self {
        Self {
            color: ColorUpdate::Blend(Blend::ADD),
            ..Self::OVERWRITE
        }
    }

    /// Counting with the stencil: every fragment increments the pixel's stencil
    /// value, wrapping at 256; no colour is written.
    pub const fn count_with_stencil_wrap() -> Self {
        Self {
            stencil: StencilTest::on_pass(Compare::Always, 0xff, 0xff, StencilOp::IncrementWrap),
            color_mask: ChannelMask::NONE,
            ..Self::OVERWRITE
        }
    }

    pub const fn with_depth(mut self, depth: DepthTest) -> Self {
        self.depth = depth;
        self
    }

    pub const fn with_stencil(mut self, stencil: StencilTest) -> Self {
        self.stencil = stencil;
        self
    }

    pub const fn with_color(mut self, color: ColorUpdate) -> Self {
        self.color = color;
        self
    }

    pub const fn with_color_mask(mut self, mask: ChannelMask) -> Self {
        self.color_mask = mask;
        self
    }
}

/// Values of the state set per draw rather than baked into the pipeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawParams {
    pub stencil_reference: u8,
    /// The blending constant colour `C` of Fig. 1.9.
    pub blend_constant: [f32; 4],
    /// Scissor test rectangle in pixels `(x, y, width, height)`; `None` = whole picture.
    pub scissor: Option<[u32; 4]>,
}

impl Default for DrawParams {
    fn default() -> Self {
        Self {
            stencil_reference: 0,
            blend_constant: [0.0; 4],
            scissor: None,
        }
    }
}
