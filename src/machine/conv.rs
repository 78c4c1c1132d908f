//! Pure mappings from the machine's state values to Vulkan enums.

use ash::vk;

use super::state::{
    BlendFactor, BlendOp, ChannelMask, ColorUpdate, Compare, LogicOp, RasterState, StencilOp,
    StencilTest,
};

pub(crate) fn map_compare(c: Compare) -> vk::CompareOp {
    match c {
        Compare::Never => vk::CompareOp::NEVER,
        Compare::Less => vk::CompareOp::LESS,
        Compare::Equal => vk::CompareOp::EQUAL,
        Compare::LessOrEqual => vk::CompareOp::LESS_OR_EQUAL,
        Compare::Greater => vk::CompareOp::GREATER,
        Compare::NotEqual => vk::CompareOp::NOT_EQUAL,
        Compare::GreaterOrEqual => vk::CompareOp::GREATER_OR_EQUAL,
        Compare::Always => vk::CompareOp::ALWAYS,
    }
}

pub(crate) fn map_stencil_op(op: StencilOp) -> vk::StencilOp {
    match op {
        StencilOp::Keep => vk::StencilOp::KEEP,
        StencilOp::Zero => vk::StencilOp::ZERO,
        StencilOp::Replace => vk::StencilOp::REPLACE,
        StencilOp::IncrementClamp => vk::StencilOp::INCREMENT_AND_CLAMP,
        StencilOp::DecrementClamp => vk::StencilOp::DECREMENT_AND_CLAMP,
        StencilOp::IncrementWrap => vk::StencilOp::INCREMENT_AND_WRAP,
        StencilOp::DecrementWrap => vk::StencilOp::DECREMENT_AND_WRAP,
        StencilOp::Invert => vk::StencilOp::INVERT,
    }
}

pub(crate) fn map_stencil(s: &StencilTest) -> vk::StencilOpState {
    vk::StencilOpState {
        fail_op: map_stencil_op(s.on_fail),
        pass_op: map_stencil_op(s.on_pass),
        depth_fail_op: map_stencil_op(s.on_depth_fail),
        compare_op: map_compare(s.compare),
        compare_mask: s.compare_mask.into(),
        write_mask: s.write_mask.into(),
        reference: 0,
    }
}

pub(crate) fn map_blend_factor(f: BlendFactor) -> vk::BlendFactor {
    match f {
        BlendFactor::Zero => vk::BlendFactor::ZERO,
        BlendFactor::One => vk::BlendFactor::ONE,
        BlendFactor::Source => vk::BlendFactor::SRC_COLOR,
        BlendFactor::OneMinusSource => vk::BlendFactor::ONE_MINUS_SRC_COLOR,
        BlendFactor::Destination => vk::BlendFactor::DST_COLOR,
        BlendFactor::OneMinusDestination => vk::BlendFactor::ONE_MINUS_DST_COLOR,
        BlendFactor::SourceAlpha => vk::BlendFactor::SRC_ALPHA,
        BlendFactor::OneMinusSourceAlpha => vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
        BlendFactor::DestinationAlpha => vk::BlendFactor::DST_ALPHA,
        BlendFactor::OneMinusDestinationAlpha => vk::BlendFactor::ONE_MINUS_DST_ALPHA,
        BlendFactor::Constant => vk::BlendFactor::CONSTANT_COLOR,
        BlendFactor::OneMinusConstant => vk::BlendFactor::ONE_MINUS_CONSTANT_COLOR,
        BlendFactor::ConstantAlpha => vk::BlendFactor::CONSTANT_ALPHA,
        BlendFactor::OneMinusConstantAlpha => vk::BlendFactor::ONE_MINUS_CONSTANT_ALPHA,
        BlendFactor::SourceAlphaSaturate => vk::BlendFactor::SRC_ALPHA_SATURATE,
    }
}

pub(crate) fn map_blend_op(op: BlendOp) -> vk::BlendOp {
    match op {
        BlendOp::Add => vk::BlendOp::ADD,
        BlendOp::Subtract => vk::BlendOp::SUBTRACT,
        BlendOp::ReverseSubtract => vk::BlendOp::REVERSE_SUBTRACT,
        BlendOp::Min => vk::BlendOp::MIN,
        BlendOp::Max => vk::BlendOp::MAX,
    }
}

pub(crate) fn map_logic_op(op: LogicOp) -> vk::LogicOp {
    match op {
        LogicOp::Clear => vk::LogicOp::CLEAR,
        LogicOp::And => vk::LogicOp::AND,
        LogicOp::AndReverse => vk::LogicOp::AND_REVERSE,
        LogicOp::Copy => vk::LogicOp::COPY,
        LogicOp::AndInverted => vk::LogicOp::AND_INVERTED,
        LogicOp::NoOp => vk::LogicOp::NO_OP,
        LogicOp::Xor => vk::LogicOp::XOR,
        LogicOp::Or => vk::LogicOp::OR,
        LogicOp::Nor => vk::LogicOp::NOR,
        LogicOp::Equivalent => vk::LogicOp::EQUIVALENT,
        LogicOp::Invert => vk::LogicOp::INVERT,
        LogicOp::OrReverse => vk::LogicOp::OR_REVERSE,
        LogicOp::CopyInverted => vk::LogicOp::COPY_INVERTED,
        LogicOp::OrInverted => vk::LogicOp::OR_INVERTED,
        LogicOp::Nand => vk::LogicOp::NAND,
        LogicOp::Set => vk::LogicOp::SET,
    }
}

pub(crate) fn map_channel_mask(m: ChannelMask) -> vk::ColorComponentFlags {
    let mut f = vk::ColorComponentFlags::empty();
    if m.red {
        f |= vk::ColorComponentFlags::R;
    }
    if m.green {
        f |= vk::ColorComponentFlags::G;
    }
    if m.blue {
        f |= vk::ColorComponentFlags::B;
    }
    if m.alpha {
        f |= vk::ColorComponentFlags::A;
    }
    f
}

pub(crate) fn map_depth_stencil(
    state: &RasterState,
) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    let stencil = map_stencil(&state.stencil);
    let stencil_on = state.stencil != StencilTest::OFF;
    vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(state.depth.write)
        .depth_compare_op(map_compare(state.depth.compare))
        .stencil_test_enable(stencil_on)
        .front(stencil)
        .back(stencil)
}

/// The colour attachment's blend state and the pipeline-wide logic op, if any.
pub(crate) fn map_color_update(
    state: &RasterState,
) -> (vk::PipelineColorBlendAttachmentState, Option<vk::LogicOp>) {
    let attachment = vk::PipelineColorBlendAttachmentState::default()
        .color_write_mask(map_channel_mask(state.color_mask));
    match state.color {
        ColorUpdate::Overwrite => (attachment, None),
        ColorUpdate::Logic(op) => (attachment, Some(map_logic_op(op))),
        ColorUpdate::Blend(b) => (
            attachment
                .blend_enable(true)
                .src_color_blend_factor(map_blend_factor(b.fragment_factor))
                .dst_color_blend_factor(map_blend_factor(b.pixel_factor))
                .color_blend_op(map_blend_op(b.op))
                .src_alpha_blend_factor(map_blend_factor(b.fragment_factor))
                .dst_alpha_blend_factor(map_blend_factor(b.pixel_factor))
                .alpha_blend_op(map_blend_op(b.op)),
            None,
        ),
    }
}
