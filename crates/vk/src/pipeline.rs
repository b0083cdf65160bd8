//! Graphics pipelines (dynamic rendering) for triangles, lines and screen-space overlays.

use ash::vk;

use crate::context::Context;
use crate::error::{Result, VkResultExt};
use crate::scene::VERTEX_STRIDE;
use crate::shaders;

/// Format of the colour target.
pub(crate) const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// Auxiliary target 1: normal xyz + scalar.
pub(crate) const NORMAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// Auxiliary target 2: linear view depth.
pub(crate) const LINEAR_DEPTH_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// The pipelines every frame is drawn with, all sharing one layout.
pub(crate) struct Pipelines {
    pub layout: vk::PipelineLayout,
    /// Shaded triangles into colour and auxiliary targets.
    pub fill: vk::Pipeline,
    /// Triangles into depth and auxiliary targets only (hidden-line wireframe).
    pub fill_depth_only: vk::Pipeline,
    /// Lines into colour only; depth test is dynamic state.
    pub line: vk::Pipeline,
    /// Screen-space overlay rectangles (HUD, legends): colour only, blended, no depth test.
    pub overlay: vk::Pipeline,
    /// Line widths are dynamic state (the device has `wideLines`).
    pub dynamic_line_width: bool,
    /// Supported line width range.
    pub line_width_range: [f32; 2],
}

struct Modules {
    mesh_vert: vk::ShaderModule,
    mesh_frag: vk::ShaderModule,
    line_vert: vk::ShaderModule,
    line_frag: vk::ShaderModule,
    overlay_vert: vk::ShaderModule,
    overlay_frag: vk::ShaderModule,
}

fn module(ctx: &Context, bytes: &[u8]) -> Result<vk::ShaderModule> {
    let code = shaders::words(bytes)?;
    let info = vk::ShaderModuleCreateInfo::default().code(&code);
    // SAFETY: `ctx.device` is live; `code` is SPIR-V that naga produced and
    // validated at build time, as aligned u32 words (`shaders::words`).
    unsafe { ctx.device.create_shader_module(&info, None) }.call("vkCreateShaderModule")
}

impl Pipelines {
    pub fn new(ctx: &Context) -> Result<Self> {
        let range = vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .offset(0)
            .size(128);
        let ranges = [range];
        let layout_info = vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&ranges);
        // SAFETY: `ctx.device` is live; `layout_info` and its push-constant range
        // live through the call.
        let layout = unsafe { ctx.device.create_pipeline_layout(&layout_info, None) }
            .call("vkCreatePipelineLayout")?;
        let mut pipelines = Pipelines {
            layout,
            fill: vk::Pipeline::null(),
            fill_depth_only: vk::Pipeline::null(),
            line: vk::Pipeline::null(),
            overlay: vk::Pipeline::null(),
            dynamic_line_width: ctx.wide_lines,
            line_width_range: if ctx.wide_lines {
                ctx.limits.line_width_range
            } else {
                [1.0, 1.0]
            },
        };
        let mut modules = Modules {
            mesh_vert: vk::ShaderModule::null(),
            mesh_frag: vk::ShaderModule::null(),
            line_vert: vk::ShaderModule::null(),
            line_frag: vk::ShaderModule::null(),
            overlay_vert: vk::ShaderModule::null(),
            overlay_frag: vk::ShaderModule::null(),
        };
        let result = pipelines.build(ctx, &mut modules);
        // SAFETY: the modules were created by this device and are referenced only
        // while creating pipelines, which has returned (successfully or not);
        // null handles (modules never made) are skipped.
        unsafe {
            for m in [
                modules.mesh_vert,
                modules.mesh_frag,
                modules.line_vert,
                modules.line_frag,
                modules.overlay_vert,
                modules.overlay_frag,
            ] {
                if m != vk::ShaderModule::null() {
                    ctx.device.destroy_shader_module(m, None);
                }
            }
        }
        if let Err(e) = result {
            pipelines.destroy(ctx);
            return Err(e);
        }
        Ok(pipelines)
    }

    fn build(&mut self, ctx: &Context, modules: &mut Modules) -> Result<()> {
        modules.mesh_vert = module(ctx, shaders::MESH_VERT)?;
        modules.mesh_frag = module(ctx, shaders::MESH_FRAG)?;
        modules.line_vert = module(ctx, shaders::LINE_VERT)?;
        modules.line_frag = module(ctx, shaders::LINE_FRAG)?;
        modules.overlay_vert = module(ctx, shaders::OVERLAY_VERT)?;
        modules.overlay_frag = module(ctx, shaders::OVERLAY_FRAG)?;
        let all = vk::ColorComponentFlags::RGBA;
        let none = vk::ColorComponentFlags::empty();
        self.fill = self.create(
            ctx,
            modules.mesh_vert,
            modules.mesh_frag,
            Kind::Fill,
            [all, all, all],
        )?;
        self.fill_depth_only = self.create(
            ctx,
            modules.mesh_vert,
            modules.mesh_frag,
            Kind::Fill,
            [none, all, all],
        )?;
        self.line = self.create(
            ctx,
            modules.line_vert,
            modules.line_frag,
            Kind::Line,
            [all, none, none],
        )?;
        self.overlay = self.create(
            ctx,
            modules.overlay_vert,
            modules.overlay_frag,
            Kind::Overlay,
            [all, none, none],
        )?;
        Ok(())
    }

    fn create(
        &self,
        ctx: &Context,
        vert: vk::ShaderModule,
        frag: vk::ShaderModule,
        kind: Kind,
        write_masks: [vk::ColorComponentFlags; 3],
    ) -> Result<vk::Pipeline> {
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag)
                .name(c"main"),
        ];
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: VERTEX_STRIDE as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attr = |location, format, offset| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format,
            offset,
        };
        let mesh_attrs = [
            attr(0, vk::Format::R32G32B32_SFLOAT, 0),
            attr(1, vk::Format::R32G32B32_SFLOAT, 12),
            attr(2, vk::Format::R32_SFLOAT, 24),
        ];
        let attrs: &[vk::VertexInputAttributeDescription] = match kind {
            Kind::Fill | Kind::Overlay => &mesh_attrs,
            Kind::Line => &mesh_attrs[..1],
        };
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(attrs);
        let topology = match kind {
            Kind::Fill | Kind::Overlay => vk::PrimitiveTopology::TRIANGLE_LIST,
            Kind::Line => vk::PrimitiveTopology::LINE_LIST,
        };
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = rasterization(kind);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = depth_stencil(kind);
        let blend_attachments = write_masks.map(|mask| blend(kind, mask));
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic = dynamic_states(kind, self.dynamic_line_width);
        let dynamic_state = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let formats = [COLOR_FORMAT, NORMAL_FORMAT, LINEAR_DEPTH_FORMAT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(ctx.depth_format);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic_state)
            .layout(self.layout)
            .push_next(&mut rendering);
        // SAFETY: `ctx.device` is live; the shader modules and layout were created
        // by it, and every state structure `info` points to lives through the call.
        let pipelines = unsafe {
            ctx.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, result)| result)
        .call("vkCreateGraphicsPipelines")?;
        Ok(pipelines.first().copied().unwrap_or_default())
    }

    /// Clamps a requested line width to the device's range.
    pub fn line_width(&self, requested: f32) -> f32 {
        let [lo, hi] = self.line_width_range;
        if requested.is_finite() {
            requested.clamp(lo, hi)
        } else {
            lo
        }
    }

    pub fn destroy(&mut self, ctx: &Context) {
        // SAFETY: the pipelines and layout were created by this device; the owner
        // calls this after waiting for the device to be idle (or before any use);
        // null handles are skipped or ignored, and all are nulled below.
        unsafe {
            for p in [self.fill, self.fill_depth_only, self.line, self.overlay] {
                if p != vk::Pipeline::null() {
                    ctx.device.destroy_pipeline(p, None);
                }
            }
            ctx.device.destroy_pipeline_layout(self.layout, None);
        }
        self.fill = vk::Pipeline::null();
        self.fill_depth_only = vk::Pipeline::null();
        self.line = vk::Pipeline::null();
        self.overlay = vk::Pipeline::null();
        self.layout = vk::PipelineLayout::null();
    }
}

/// Filled triangles (depth-biased) or lines; no culling.
fn rasterization(kind: Kind) -> vk::PipelineRasterizationStateCreateInfo<'static> {
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    if kind == Kind::Fill {
        // Push surfaces back a little so edges drawn on them pass the depth test.
        raster
            .depth_bias_enable(true)
            .depth_bias_constant_factor(1.0)
            .depth_bias_slope_factor(1.0)
    } else {
        raster
    }
}

/// Colour writes of one attachment: overlays blend with straight alpha (colour
/// `a * src + (1 - a) * dst`), everything else overwrites.
fn blend(kind: Kind, mask: vk::ColorComponentFlags) -> vk::PipelineColorBlendAttachmentState {
    let state = vk::PipelineColorBlendAttachmentState::default().color_write_mask(mask);
    if kind != Kind::Overlay || mask.is_empty() {
        return state.blend_enable(false);
    }
    state
        .blend_enable(true)
        .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .color_blend_op(vk::BlendOp::ADD)
        .src_alpha_blend_factor(vk::BlendFactor::ONE)
        .dst_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .alpha_blend_op(vk::BlendOp::ADD)
}

/// Triangles test and write depth; lines only test it (less-or-equal); overlays ignore it.
fn depth_stencil(kind: Kind) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(kind != Kind::Overlay)
        .depth_write_enable(kind == Kind::Fill)
        .depth_compare_op(match kind {
            Kind::Fill => vk::CompareOp::LESS,
            Kind::Line | Kind::Overlay => vk::CompareOp::LESS_OR_EQUAL,
        })
}

/// Viewport and scissor always; lines also set depth test and (with
/// `wideLines`) their width per draw.
fn dynamic_states(kind: Kind, dynamic_line_width: bool) -> Vec<vk::DynamicState> {
    let mut dynamic = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    if kind == Kind::Line {
        dynamic.push(vk::DynamicState::DEPTH_TEST_ENABLE);
        if dynamic_line_width {
            dynamic.push(vk::DynamicState::LINE_WIDTH);
        }
    }
    dynamic
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Fill,
    Line,
    Overlay,
}
