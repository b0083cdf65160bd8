//! Graphics pipelines (dynamic rendering) for triangles, lines and screen-space overlays: one
//! sample per pixel into the colour and auxiliary targets, or multisampled into colour only.

use ash::vk;

use crate::context::Context;
use crate::error::{Result, VkError, VkResultExt};
use crate::samples;
use crate::scene::{COLOR_STRIDE, VERTEX_STRIDE};
use crate::shaders;

/// Format of the colour target.
pub(crate) const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// Auxiliary target 1: normal xyz + scalar.
pub(crate) const NORMAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// Auxiliary target 2: linear view depth.
pub(crate) const LINEAR_DEPTH_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// The pipelines of one pass: triangles, lines and overlays.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PipelineSet {
    /// Shaded triangles.
    pub fill: vk::Pipeline,
    /// Triangles without colour (hidden-line wireframe, and the auxiliary pass).
    pub fill_depth_only: vk::Pipeline,
    /// Lines into colour only; depth test is dynamic state.
    pub line: vk::Pipeline,
    /// Screen-space overlay rectangles (HUD, legends): colour only, blended, no depth test.
    pub overlay: vk::Pipeline,
}

impl PipelineSet {
    fn all(&self) -> [vk::Pipeline; 4] {
        [self.fill, self.fill_depth_only, self.line, self.overlay]
    }
}

/// Which attachments a pass draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pass {
    /// One sample per pixel: colour and the auxiliary targets (normal + scalar, linear depth).
    Single,
    /// The colour target only, with this many samples per pixel (resolved afterwards).
    Color(u32),
}

impl Pass {
    fn formats(self) -> &'static [vk::Format] {
        match self {
            Pass::Single => &[COLOR_FORMAT, NORMAL_FORMAT, LINEAR_DEPTH_FORMAT],
            Pass::Color(_) => &[COLOR_FORMAT],
        }
    }

    fn samples(self) -> vk::SampleCountFlags {
        match self {
            Pass::Single => vk::SampleCountFlags::TYPE_1,
            Pass::Color(n) => samples::flag(n),
        }
    }
}

/// The pipelines frames are drawn with, all sharing one layout: the single-sample set (colour
/// and auxiliary targets), and a colour-only set per sample count in use (made by
/// [`Pipelines::prepare`] when first asked for).
pub(crate) struct Pipelines {
    pub layout: vk::PipelineLayout,
    /// One sample per pixel, colour and auxiliary targets.
    pub single: PipelineSet,
    /// Colour only, per sample count above 1.
    multisampled: Vec<(u32, PipelineSet)>,
    /// Line widths are dynamic state (the device has `wideLines`).
    pub dynamic_line_width: bool,
    /// Supported line width range.
    pub line_width_range: [f32; 2],
    modules: Modules,
}

#[derive(Clone, Copy, Default)]
struct Modules {
    mesh_vert: vk::ShaderModule,
    mesh_frag: vk::ShaderModule,
    mesh_color_frag: vk::ShaderModule,
    line_vert: vk::ShaderModule,
    line_frag: vk::ShaderModule,
    overlay_vert: vk::ShaderModule,
    overlay_frag: vk::ShaderModule,
}

impl Modules {
    fn all(&self) -> [vk::ShaderModule; 7] {
        [
            self.mesh_vert,
            self.mesh_frag,
            self.mesh_color_frag,
            self.line_vert,
            self.line_frag,
            self.overlay_vert,
            self.overlay_frag,
        ]
    }
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
            single: PipelineSet::default(),
            multisampled: Vec::new(),
            dynamic_line_width: ctx.wide_lines,
            line_width_range: if ctx.wide_lines {
                ctx.limits.line_width_range
            } else {
                [1.0, 1.0]
            },
            modules: Modules::default(),
        };
        let result = pipelines
            .load_modules(ctx)
            .and_then(|()| pipelines.build(ctx, Pass::Single));
        match result {
            Ok(set) => {
                pipelines.single = set;
                Ok(pipelines)
            }
            Err(e) => {
                pipelines.destroy(ctx);
                Err(e)
            }
        }
    }

    fn load_modules(&mut self, ctx: &Context) -> Result<()> {
        let m = &mut self.modules;
        m.mesh_vert = module(ctx, shaders::MESH_VERT)?;
        m.mesh_frag = module(ctx, shaders::MESH_FRAG)?;
        m.mesh_color_frag = module(ctx, shaders::MESH_COLOR_FRAG)?;
        m.line_vert = module(ctx, shaders::LINE_VERT)?;
        m.line_frag = module(ctx, shaders::LINE_FRAG)?;
        m.overlay_vert = module(ctx, shaders::OVERLAY_VERT)?;
        m.overlay_frag = module(ctx, shaders::OVERLAY_FRAG)?;
        Ok(())
    }

    /// Makes the colour-only pipelines for `samples` per pixel if they are not there yet
    /// (nothing for 1, whose pipelines [`Pipelines::new`] made).
    pub fn prepare(&mut self, ctx: &Context, samples: u32) -> Result<()> {
        if samples <= 1 || self.multisampled.iter().any(|(n, _)| *n == samples) {
            return Ok(());
        }
        let set = self.build(ctx, Pass::Color(samples))?;
        self.multisampled.push((samples, set));
        Ok(())
    }

    /// The colour-only pipelines for `samples` per pixel ([`Pipelines::prepare`]d before).
    pub fn multisampled(&self, samples: u32) -> Result<&PipelineSet> {
        self.multisampled
            .iter()
            .find(|(n, _)| *n == samples)
            .map(|(_, set)| set)
            .ok_or(VkError::Vulkan {
                call: "multisampled pipelines",
                result: vk::Result::ERROR_UNKNOWN,
            })
    }

    /// The pipelines of `pass`; on failure, those made so far are destroyed.
    fn build(&self, ctx: &Context, pass: Pass) -> Result<PipelineSet> {
        let m = self.modules;
        let all = vk::ColorComponentFlags::RGBA;
        let none = vk::ColorComponentFlags::empty();
        let (mesh_frag, masks): (_, &[_]) = match pass {
            Pass::Single => (m.mesh_frag, &[all, all, all]),
            Pass::Color(_) => (m.mesh_color_frag, &[all]),
        };
        let depth_only_masks: Vec<_> = masks
            .iter()
            .enumerate()
            .map(|(i, &mask)| if i == 0 { none } else { mask })
            .collect();
        let colour_only: Vec<_> = masks
            .iter()
            .enumerate()
            .map(|(i, _)| if i == 0 { all } else { none })
            .collect();
        let specs = [
            (m.mesh_vert, mesh_frag, Kind::Fill, masks.to_vec()),
            (m.mesh_vert, mesh_frag, Kind::Fill, depth_only_masks),
            (m.line_vert, m.line_frag, Kind::Line, colour_only.clone()),
            (m.overlay_vert, m.overlay_frag, Kind::Overlay, colour_only),
        ];
        let mut made = Vec::with_capacity(specs.len());
        for (vert, frag, kind, masks) in specs {
            match self.create(ctx, (vert, frag), kind, pass, &masks) {
                Ok(p) => made.push(p),
                Err(e) => {
                    // SAFETY: these pipelines were just created by this device and
                    // never used.
                    unsafe {
                        for p in made {
                            ctx.device.destroy_pipeline(p, None);
                        }
                    }
                    return Err(e);
                }
            }
        }
        Ok(PipelineSet {
            fill: made[0],
            fill_depth_only: made[1],
            line: made[2],
            overlay: made[3],
        })
    }

    fn create(
        &self,
        ctx: &Context,
        (vert, frag): (vk::ShaderModule, vk::ShaderModule),
        kind: Kind,
        pass: Pass,
        write_masks: &[vk::ColorComponentFlags],
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
        // Binding 0: the packed vertices; binding 1 (triangles only): their colours.
        let bindings = [
            vk::VertexInputBindingDescription {
                binding: 0,
                stride: VERTEX_STRIDE as u32,
                input_rate: vk::VertexInputRate::VERTEX,
            },
            vk::VertexInputBindingDescription {
                binding: 1,
                stride: COLOR_STRIDE as u32,
                input_rate: vk::VertexInputRate::VERTEX,
            },
        ];
        let attr = |location, binding, format, offset| vk::VertexInputAttributeDescription {
            location,
            binding,
            format,
            offset,
        };
        let mesh_attrs = [
            attr(0, 0, vk::Format::R32G32B32_SFLOAT, 0),
            attr(1, 0, vk::Format::R32G32B32_SFLOAT, 12),
            attr(2, 0, vk::Format::R32_SFLOAT, 24),
            attr(3, 1, vk::Format::R32G32B32_SFLOAT, 0),
        ];
        let (bindings, attrs): (&[_], &[_]) = match kind {
            Kind::Fill => (&bindings, &mesh_attrs),
            Kind::Overlay => (&bindings[..1], &mesh_attrs[..3]),
            Kind::Line => (&bindings[..1], &mesh_attrs[..1]),
        };
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(bindings)
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
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(pass.samples());
        let depth = depth_stencil(kind);
        let blend_attachments: Vec<_> = write_masks.iter().map(|&m| blend(kind, m)).collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic = dynamic_states(kind, self.dynamic_line_width);
        let dynamic_state = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(pass.formats())
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
        let sets = std::iter::once(self.single).chain(self.multisampled.drain(..).map(|(_, s)| s));
        // SAFETY: the pipelines, modules and layout were created by this device; the
        // owner calls this after waiting for the device to be idle (or before any use);
        // null handles are skipped or ignored, and all are nulled below.
        unsafe {
            for p in sets.flat_map(|s| s.all()) {
                if p != vk::Pipeline::null() {
                    ctx.device.destroy_pipeline(p, None);
                }
            }
            for m in self.modules.all() {
                if m != vk::ShaderModule::null() {
                    ctx.device.destroy_shader_module(m, None);
                }
            }
            ctx.device.destroy_pipeline_layout(self.layout, None);
        }
        self.single = PipelineSet::default();
        self.modules = Modules::default();
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
