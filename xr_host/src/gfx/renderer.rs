//! The mesh and line renderer: one multiview render pass (one layer per
//! eye, `gl_ViewIndex` picks the eye's matrix), a shaded-triangle pipeline
//! and a line pipeline (curves, spines, sections, the ray).
//!
//! Shaders are GLSL in `xr_host/shaders/`, compiled to SPIR-V by
//! `xr_host/shaders/compile.sh` (glslangValidator) and committed, so a
//! build needs no shader compiler.

use shapewright::math::fm::DetMath as _;
use std::io::Cursor;
use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};
use shapewright::mesh::TriMesh;

use super::resource::HostBuffer;
use super::{GfxError, GpuContext};

const MESH_VERT: &[u8] = include_bytes!("../../shaders/mesh.vert.spv");
const MESH_FRAG: &[u8] = include_bytes!("../../shaders/mesh.frag.spv");
const LINE_VERT: &[u8] = include_bytes!("../../shaders/line.vert.spv");
const LINE_FRAG: &[u8] = include_bytes!("../../shaders/line.frag.spv");

/// The depth attachment format (universally supported).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// At most this many views per pass (the shaders hold two matrices).
pub const MAX_VIEWS: u32 = 2;

/// One eye (or the single offscreen camera).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewCamera {
    /// Projection × view, Vulkan clip conventions (y down, depth 0..1).
    pub view_proj: Mat4,
    /// Eye position in world space (for the headlight).
    pub eye: Vec3,
}

/// A mesh to draw: its GPU buffers, a model matrix and a color.
#[derive(Clone, Copy)]
pub struct MeshDraw<'a> {
    /// The uploaded mesh.
    pub mesh: &'a GpuMesh,
    /// World from model.
    pub model: Mat4,
    /// Linear RGBA base color.
    pub color: [f32; 4],
    /// Vertices `[a, b)` are not drawn (one object of a combined mesh).
    pub hidden: Option<(u32, u32)>,
}

/// A line vertex: world position and linear RGB color. Consecutive pairs
/// form segments.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct LineVertex {
    /// Position.
    pub pos: [f32; 3],
    /// Color.
    pub color: [f32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Default)]
struct MeshVertex {
    pos: [f32; 3],
    normal: [f32; 3],
}

#[repr(C)]
#[derive(Clone, Copy)]
struct ViewsUbo {
    view_proj: [[f32; 16]; 2],
    eye: [[f32; 4]; 2],
}

#[repr(C)]
#[derive(Clone, Copy)]
struct Push {
    model: [f32; 16],
    color: [f32; 4],
}

/// A triangle mesh in GPU memory, ready to draw.
pub struct GpuMesh {
    vertices: HostBuffer,
    vertex_count: u32,
}

impl GpuMesh {
    /// Number of vertices drawn (three per triangle).
    pub fn vertex_count(&self) -> u32 {
        self.vertex_count
    }
}

/// Line segments in GPU memory.
pub struct GpuLines {
    vertices: HostBuffer,
    vertex_count: u32,
}

/// A framebuffer over a color and depth view, destroyed on drop.
pub struct Framebuffer {
    ctx: Arc<GpuContext>,
    handle: vk::Framebuffer,
    extent: vk::Extent2D,
}

impl Drop for Framebuffer {
    fn drop(&mut self) {
        // SAFETY: created on this device; GPU work using it has completed.
        unsafe { self.ctx.device().destroy_framebuffer(self.handle, None) };
    }
}

/// Pipelines, render pass and per-view uniforms for one color format and
/// view count.
pub struct Renderer {
    ctx: Arc<GpuContext>,
    view_count: u32,
    render_pass: vk::RenderPass,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    layout: vk::PipelineLayout,
    mesh_pipeline: vk::Pipeline,
    line_pipeline: vk::Pipeline,
    /// Flat triangles with per-vertex colour (the palette, text): the line
    /// shaders with a triangle topology.
    flat_pipeline: vk::Pipeline,
    ubo: HostBuffer,
}

/// Per-vertex normals where they agree with the face (smooth surfaces),
/// the face normal where they do not (creases), so STL boxes and smooth
/// spheres both shade right. 30° crease threshold.
fn expand_vertices(mesh: &TriMesh) -> Vec<MeshVertex> {
    let cos_crease = 30f64.to_radians().fcos();
    let has_normals = mesh.has_vertex_normals();
    let mut out = Vec::with_capacity(mesh.triangles.len() * 3);
    for t in &mesh.triangles {
        let idx = t.map(|i| i as usize);
        if idx.iter().any(|&i| i >= mesh.positions.len()) {
            // Three (degenerate, invisible) vertices still, so triangle
            // ranges stay vertex ranges (`MeshDraw::hidden`).
            out.extend([MeshVertex::default(); 3]);
            continue;
        }
        let p = idx.map(|i| glam::DVec3::from_array(mesh.positions[i]));
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for (k, &i) in idx.iter().enumerate() {
            let mut n = face;
            if has_normals {
                let vn = glam::DVec3::from_array(mesh.normals[i]).normalize_or_zero();
                if vn.dot(face) >= cos_crease {
                    n = vn;
                }
            }
            out.push(MeshVertex {
                pos: p[k].as_vec3().to_array(),
                normal: n.as_vec3().to_array(),
            });
        }
    }
    out
}

/// The render pass: one subpass drawing into a colour and a depth
/// attachment, with `view_count` multiview layers; the colour image is
/// left in `final_layout`.
fn render_pass(
    dev: &ash::Device,
    color_format: vk::Format,
    view_count: u32,
    final_layout: vk::ImageLayout,
) -> Result<vk::RenderPass, GfxError> {
    let view_mask = (1u32 << view_count) - 1;
    let attachments = [
        vk::AttachmentDescription {
            format: color_format,
            samples: vk::SampleCountFlags::TYPE_1,
            load_op: vk::AttachmentLoadOp::CLEAR,
            store_op: vk::AttachmentStoreOp::STORE,
            stencil_load_op: vk::AttachmentLoadOp::DONT_CARE,
            stencil_store_op: vk::AttachmentStoreOp::DONT_CARE,
            initial_layout: vk::ImageLayout::UNDEFINED,
            final_layout,
            ..Default::default()
        },
        vk::AttachmentDescription {
            format: DEPTH_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
            load_op: vk::AttachmentLoadOp::CLEAR,
            store_op: vk::AttachmentStoreOp::DONT_CARE,
            stencil_load_op: vk::AttachmentLoadOp::DONT_CARE,
            stencil_store_op: vk::AttachmentStoreOp::DONT_CARE,
            initial_layout: vk::ImageLayout::UNDEFINED,
            final_layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            ..Default::default()
        },
    ];
    let color_ref = [vk::AttachmentReference {
        attachment: 0,
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    }];
    let depth_ref = vk::AttachmentReference {
        attachment: 1,
        layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    };
    let subpasses = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&color_ref)
        .depth_stencil_attachment(&depth_ref)];
    let deps = [
        vk::SubpassDependency {
            src_subpass: vk::SUBPASS_EXTERNAL,
            dst_subpass: 0,
            src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS,
            dst_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS,
            dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ..Default::default()
        },
        vk::SubpassDependency {
            src_subpass: 0,
            dst_subpass: vk::SUBPASS_EXTERNAL,
            src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
            dst_stage_mask: vk::PipelineStageFlags::TRANSFER,
            src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            dst_access_mask: vk::AccessFlags::TRANSFER_READ,
            ..Default::default()
        },
    ];
    let masks = [view_mask];
    let mut multiview = vk::RenderPassMultiviewCreateInfo::default()
        .view_masks(&masks)
        .correlation_masks(&masks);
    let rp_info = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpasses)
        .dependencies(&deps)
        .push_next(&mut multiview);
    // SAFETY: live device; all referenced arrays live across the call;
    // destroyed in Drop.
    unsafe { dev.create_render_pass(&rp_info, None) }
        .map_err(|r| GfxError::vk("vkCreateRenderPass", r))
}

impl Renderer {
    /// A renderer drawing into `color_format` images with `view_count`
    /// layers (1 offscreen, 2 for a stereo headset). `final_layout` is the
    /// layout the color image is left in (TRANSFER_SRC for readback,
    /// COLOR_ATTACHMENT for OpenXR swapchain images).
    pub fn new(
        ctx: &Arc<GpuContext>,
        color_format: vk::Format,
        view_count: u32,
        final_layout: vk::ImageLayout,
    ) -> Result<Self, GfxError> {
        if view_count == 0 || view_count > MAX_VIEWS {
            return Err(GfxError::BadViewCount(view_count));
        }
        let dev = ctx.device();
        let ubo = HostBuffer::new(
            ctx,
            std::mem::size_of::<ViewsUbo>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        // Partially built objects are collected here so an error midway
        // destroys what was made.
        let mut this = Self {
            ctx: ctx.clone(),
            view_count,
            render_pass: vk::RenderPass::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            layout: vk::PipelineLayout::null(),
            mesh_pipeline: vk::Pipeline::null(),
            line_pipeline: vk::Pipeline::null(),
            flat_pipeline: vk::Pipeline::null(),
            ubo,
        };
        this.render_pass = render_pass(dev, color_format, view_count, final_layout)?;
        this.make_descriptors()?;
        let set_layouts = [this.set_layout];
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: std::mem::size_of::<Push>() as u32,
        }];
        // SAFETY: live device and set layout; destroyed in Drop.
        this.layout = unsafe {
            dev.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&push),
                None,
            )
        }
        .map_err(|r| GfxError::vk("vkCreatePipelineLayout", r))?;

        // Both vertex layouts are two vec3s (position, then normal or
        // colour); the flat pipeline is the line shaders on triangles.
        let attrs = [
            (0, vk::Format::R32G32B32_SFLOAT, 0),
            (1, vk::Format::R32G32B32_SFLOAT, 12),
        ];
        let (mesh_stride, line_stride) = (
            std::mem::size_of::<MeshVertex>() as u32,
            std::mem::size_of::<LineVertex>() as u32,
        );
        use vk::PrimitiveTopology as Topology;
        this.mesh_pipeline = this.pipeline(
            MESH_VERT,
            MESH_FRAG,
            Topology::TRIANGLE_LIST,
            &attrs,
            mesh_stride,
        )?;
        this.line_pipeline = this.pipeline(
            LINE_VERT,
            LINE_FRAG,
            Topology::LINE_LIST,
            &attrs,
            line_stride,
        )?;
        this.flat_pipeline = this.pipeline(
            LINE_VERT,
            LINE_FRAG,
            Topology::TRIANGLE_LIST,
            &attrs,
            line_stride,
        )?;
        Ok(this)
    }

    /// The descriptor set layout, pool and set holding the views' uniform
    /// buffer, the set written once.
    fn make_descriptors(&mut self) -> Result<(), GfxError> {
        let bindings = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::VERTEX)];
        let dev = self.ctx.device();
        // SAFETY: live device; destroyed in Drop.
        self.set_layout = unsafe {
            dev.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
        }
        .map_err(|r| GfxError::vk("vkCreateDescriptorSetLayout", r))?;
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::UNIFORM_BUFFER,
            descriptor_count: 1,
        }];
        // SAFETY: live device; destroyed in Drop.
        self.pool = unsafe {
            dev.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .map_err(|r| GfxError::vk("vkCreateDescriptorPool", r))?;
        let set_layouts = [self.set_layout];
        // SAFETY: pool and layout are live and the pool has room for one set.
        self.set = unsafe {
            dev.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(self.pool)
                    .set_layouts(&set_layouts),
            )
        }
        .map_err(|r| GfxError::vk("vkAllocateDescriptorSets", r))?[0];
        let buf_info = [vk::DescriptorBufferInfo {
            buffer: self.ubo.handle(),
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let writes = [vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .buffer_info(&buf_info)];
        // SAFETY: the set and buffer are live; the set is not in use.
        unsafe { dev.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }

    fn pipeline(
        &self,
        vert: &[u8],
        frag: &[u8],
        topology: vk::PrimitiveTopology,
        attrs: &[(u32, vk::Format, u32)],
        stride: u32,
    ) -> Result<vk::Pipeline, GfxError> {
        let dev = self.ctx.device();
        let vs = ShaderModule::new(&self.ctx, vert)?;
        let fs = ShaderModule::new(&self.ctx, frag)?;
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vs.0)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fs.0)
                .name(c"main"),
        ];
        let binding = [vk::VertexInputBindingDescription {
            binding: 0,
            stride,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes: Vec<_> = attrs
            .iter()
            .map(
                |&(location, format, offset)| vk::VertexInputAttributeDescription {
                    location,
                    binding: 0,
                    format,
                    offset,
                },
            )
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&binding)
            .vertex_attribute_descriptions(&attributes);
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
        let blend_att = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_att);
        let dyn_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dyn_states);
        let info = [vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(self.layout)
            .render_pass(self.render_pass)
            .subpass(0)];
        // SAFETY: every state struct, module and layout lives across the
        // call; the pipeline is destroyed in Drop.
        let pipes =
            unsafe { dev.create_graphics_pipelines(vk::PipelineCache::null(), &info, None) }
                .map_err(|(_, r)| GfxError::vk("vkCreateGraphicsPipelines", r))?;
        Ok(pipes[0])
    }

    /// The number of views (array layers) this renderer draws.
    pub fn view_count(&self) -> u32 {
        self.view_count
    }

    /// The context.
    pub fn context(&self) -> &Arc<GpuContext> {
        &self.ctx
    }

    /// Uploads `mesh` (positions converted to f32; creases get face normals).
    pub fn upload_mesh(&self, mesh: &TriMesh) -> Result<GpuMesh, GfxError> {
        let verts = expand_vertices(mesh);
        let vertices =
            HostBuffer::with_data(&self.ctx, &verts, vk::BufferUsageFlags::VERTEX_BUFFER)?;
        Ok(GpuMesh {
            vertices,
            vertex_count: verts.len() as u32,
        })
    }

    /// Uploads line segments (pairs of vertices).
    pub fn upload_lines(&self, lines: &[LineVertex]) -> Result<GpuLines, GfxError> {
        let vertices =
            HostBuffer::with_data(&self.ctx, lines, vk::BufferUsageFlags::VERTEX_BUFFER)?;
        Ok(GpuLines {
            vertices,
            vertex_count: (lines.len() / 2 * 2) as u32,
        })
    }

    /// A framebuffer over `color` and `depth` views with `view_count` layers.
    pub fn framebuffer(
        &self,
        color: vk::ImageView,
        depth: vk::ImageView,
        extent: vk::Extent2D,
    ) -> Result<Framebuffer, GfxError> {
        let atts = [color, depth];
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&atts)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: views are live and compatible with the render pass (the
        // caller made them with this renderer's formats and view count).
        let handle = unsafe { self.ctx.device().create_framebuffer(&info, None) }
            .map_err(|r| GfxError::vk("vkCreateFramebuffer", r))?;
        Ok(Framebuffer {
            ctx: self.ctx.clone(),
            handle,
            extent,
        })
    }

    /// Writes the per-view matrices. Call before recording, while no
    /// submitted frame is using the uniform buffer.
    pub fn set_views(&self, views: &[ViewCamera]) -> Result<(), GfxError> {
        if views.len() != self.view_count as usize {
            return Err(GfxError::BadViewCount(views.len() as u32));
        }
        let mut ubo = ViewsUbo {
            view_proj: [[0.0; 16]; 2],
            eye: [[0.0; 4]; 2],
        };
        for (i, v) in views.iter().enumerate() {
            ubo.view_proj[i] = v.view_proj.to_cols_array();
            ubo.eye[i] = v.eye.extend(1.0).to_array();
        }
        self.ubo.write(0, &[ubo])
    }

    /// Records the render pass into `cmd`: clear, meshes, flat triangles
    /// (`ui`: the palette and text, in a [`GpuLines`] buffer read as a
    /// triangle list), then lines.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        fb: &Framebuffer,
        clear: [f32; 4],
        meshes: &[MeshDraw<'_>],
        ui: Option<&GpuLines>,
        lines: Option<&GpuLines>,
    ) {
        let dev = self.ctx.device();
        let clears = [
            vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            },
        ];
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: fb.extent,
        };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(fb.handle)
            .render_area(area)
            .clear_values(&clears);
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: fb.extent.width as f32,
            height: fb.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: `cmd` is recording; every handle used was created on this
        // device and outlives the submission (the caller waits on it).
        unsafe {
            dev.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE);
            dev.cmd_set_viewport(cmd, 0, &[viewport]);
            dev.cmd_set_scissor(cmd, 0, &[area]);
            dev.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                0,
                &[self.set],
                &[],
            );
            dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.mesh_pipeline);
            for d in meshes.iter().filter(|d| d.mesh.vertex_count > 0) {
                self.push(cmd, d.model, d.color);
                dev.cmd_bind_vertex_buffers(cmd, 0, &[d.mesh.vertices.handle()], &[0]);
                let n = d.mesh.vertex_count;
                let (a, b) = d
                    .hidden
                    .map_or((n, n), |(a, b)| (a.min(n), b.clamp(a.min(n), n)));
                for (first, end) in [(0, a), (b, n)] {
                    if end > first {
                        dev.cmd_draw(cmd, end - first, 1, first, 0);
                    }
                }
            }
            if let Some(u) = ui.filter(|u| u.vertex_count > 0) {
                dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.flat_pipeline);
                self.push(cmd, Mat4::IDENTITY, [1.0; 4]);
                dev.cmd_bind_vertex_buffers(cmd, 0, &[u.vertices.handle()], &[0]);
                dev.cmd_draw(cmd, u.vertex_count, 1, 0, 0);
            }
            if let Some(l) = lines.filter(|l| l.vertex_count > 0) {
                dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.line_pipeline);
                self.push(cmd, Mat4::IDENTITY, [1.0; 4]);
                dev.cmd_bind_vertex_buffers(cmd, 0, &[l.vertices.handle()], &[0]);
                dev.cmd_draw(cmd, l.vertex_count, 1, 0, 0);
            }
            dev.cmd_end_render_pass(cmd);
        }
    }

    fn push(&self, cmd: vk::CommandBuffer, model: Mat4, color: [f32; 4]) {
        let p = Push {
            model: model.to_cols_array(),
            color,
        };
        // SAFETY: `Push` is repr(C) plain floats; viewing it as bytes is sound.
        let bytes = unsafe {
            std::slice::from_raw_parts(
                (&p as *const Push).cast::<u8>(),
                std::mem::size_of::<Push>(),
            )
        };
        // SAFETY: `cmd` is recording inside this renderer's pass; the range
        // matches the layout's push-constant range.
        unsafe {
            self.ctx.device().cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytes,
            )
        };
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        let dev = self.ctx.device();
        // SAFETY: all handles were created on this device (null ones are
        // ignored by Vulkan); no submitted work uses them any more.
        unsafe {
            let _ = dev.device_wait_idle();
            dev.destroy_pipeline(self.mesh_pipeline, None);
            dev.destroy_pipeline(self.line_pipeline, None);
            dev.destroy_pipeline(self.flat_pipeline, None);
            dev.destroy_pipeline_layout(self.layout, None);
            dev.destroy_descriptor_pool(self.pool, None);
            dev.destroy_descriptor_set_layout(self.set_layout, None);
            dev.destroy_render_pass(self.render_pass, None);
        }
    }
}

struct ShaderModule<'a>(vk::ShaderModule, &'a GpuContext);

impl<'a> ShaderModule<'a> {
    fn new(ctx: &'a GpuContext, spv: &[u8]) -> Result<Self, GfxError> {
        let words = ash::util::read_spv(&mut Cursor::new(spv))
            .map_err(|e| GfxError::Shader(e.to_string()))?;
        // SAFETY: `words` is SPIR-V produced by glslangValidator from the
        // committed shaders; the module is destroyed in Drop.
        let m = unsafe {
            ctx.device()
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
        }
        .map_err(|r| GfxError::vk("vkCreateShaderModule", r))?;
        Ok(Self(m, ctx))
    }
}

impl Drop for ShaderModule<'_> {
    fn drop(&mut self) {
        // SAFETY: modules may be destroyed once pipelines are created.
        unsafe { self.1.device().destroy_shader_module(self.0, None) };
    }
}
