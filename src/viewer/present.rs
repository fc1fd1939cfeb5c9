//! The present pass: draws a graph texture (linear float, or uint ids)
//! into a rectangle of the window with exposure and sRGB encoding, so the
//! surface and egui get a non-sRGB 8-bit target. Texels are fetched with
//! `textureLoad` (32-bit float textures are not filterable everywhere):
//! nearest texel, so at 1:1 the window shows exactly the render.

use crate::error::UserError;
use crate::format::TexFormat;

const SHADER: &str = r#"
struct View {
    origin: vec2f,
    size: vec2f,
    src_size: vec2f,
    exposure: f32,
    channel: u32,
}
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var src: texture_2d<SAMPLE>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4f {
    let p = vec2f(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4f(p * 2.0 - 1.0, 0.0, 1.0);
}

fn encode(x: f32) -> f32 {
    if x <= 0.0031308 { return 12.92 * x; }
    return 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

@fragment
fn fs(@builtin(position) pos: vec4f) -> @location(0) vec4f {
    let uv = (pos.xy - view.origin) / view.size;
    let texel = vec2i(clamp(floor(uv * view.src_size), vec2f(0.0), view.src_size - 1.0));
    let raw = vec4f(textureLoad(src, texel, 0));
    var c = raw.rgb;
    switch view.channel {
        case 1u: { c = vec3f(raw.r); }
        case 2u: { c = vec3f(raw.g); }
        case 3u: { c = vec3f(raw.b); }
        case 4u: { c = vec3f(raw.a); }
        default: {}
    }
    // Non-finite values show magenta, so they are seen, not hidden.
    if any(c != c) || any(abs(c) > vec3f(3.0e38)) { return vec4f(1.0, 0.0, 1.0, 1.0); }
    c = clamp(c * exp2(view.exposure), vec3f(0.0), vec3f(1.0));
    return vec4f(encode(c.r), encode(c.g), encode(c.b), 1.0);
}
"#;

/// Which channels of the texture to show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Channel {
    /// The colour as it is.
    #[default]
    Rgb,
    /// Red, as grey.
    R,
    /// Green, as grey.
    G,
    /// Blue, as grey.
    B,
    /// Alpha, as grey.
    A,
}

impl Channel {
    /// Every channel, in the panel's order.
    pub const ALL: [Channel; 5] = [Channel::Rgb, Channel::R, Channel::G, Channel::B, Channel::A];
    fn index(self) -> u32 {
        self as u32
    }
    /// The panel's name for it ("rgb", "r", ...).
    pub fn label(self) -> &'static str {
        ["rgb", "r", "g", "b", "a"][self as usize]
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ViewGpu {
    origin: [f32; 2],
    size: [f32; 2],
    src_size: [f32; 2],
    exposure: f32,
    channel: u32,
}

struct Variant {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

/// The present pass's pipelines (float and uint textures) and view
/// uniform, for one target format.
pub struct Present {
    float: Variant,
    uint: Variant,
    uniform: wgpu::Buffer,
    /// The bind group of the texture shown last: made again only when the
    /// texture changes (another resource, a rebuild), not every frame.
    bound: Option<(wgpu::Texture, wgpu::BindGroup)>,
}

fn variant(device: &wgpu::Device, target: wgpu::TextureFormat, uint: bool) -> Variant {
    let source = SHADER.replace("SAMPLE", if uint { "u32" } else { "f32" });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("present"), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let sample_type = if uint { wgpu::TextureSampleType::Uint } else { wgpu::TextureSampleType::Float { filterable: false } };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("present"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled: false },
                count: None,
            },
        ],
    });
    let pipeline_layout =
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("present"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("present"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState { module: &module, entry_point: Some("vs"), buffers: &[], compilation_options: Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            targets: &[Some(wgpu::ColorTargetState { format: target, blend: None, write_mask: wgpu::ColorWrites::ALL })],
            compilation_options: Default::default(),
        }),
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        multiview_mask: None,
        cache: None,
    });
    Variant { pipeline, layout }
}

/// A rectangle of the window in physical pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Left edge.
    pub x: f32,
    /// Top edge (y grows down).
    pub y: f32,
    /// Width; under 1 draws nothing.
    pub w: f32,
    /// Height; under 1 draws nothing.
    pub h: f32,
}

impl Present {
    /// Builds the pass for `target`, a non-sRGB format (the pass encodes
    /// sRGB itself); an error if the device refuses it.
    pub fn new(device: &wgpu::Device, target: wgpu::TextureFormat) -> Result<Present, UserError> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let present = Present {
            float: variant(device, target, false),
            uint: variant(device, target, true),
            uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("present view"),
                size: std::mem::size_of::<ViewGpu>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            bound: None,
        };
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(UserError::new(format!("the present pass was refused: {e}")));
        }
        Ok(present)
    }

    /// Records drawing `texture` into `rect` of `target` (cleared first).
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        texture: &wgpu::Texture,
        format: TexFormat,
        rect: Rect,
        exposure: f32,
        channel: Channel,
    ) {
        let view = ViewGpu {
            origin: [rect.x, rect.y],
            size: [rect.w.max(1.0), rect.h.max(1.0)],
            src_size: [texture.width() as f32, texture.height() as f32],
            exposure,
            channel: channel.index(),
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&view));
        let v = if format.is_uint() { &self.uint } else { &self.float };
        if self.bound.as_ref().is_none_or(|(t, _)| t != texture) {
            let src = texture.create_view(&Default::default());
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("present"),
                layout: &v.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: self.uniform.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&src) },
                ],
            });
            self.bound = Some((texture.clone(), group));
        }
        let Some((_, group)) = self.bound.as_ref() else { return };
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("present"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color { r: 0.08, g: 0.08, b: 0.08, a: 1.0 }), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if rect.w >= 1.0 && rect.h >= 1.0 {
            pass.set_viewport(rect.x, rect.y, rect.w, rect.h, 0.0, 1.0);
            pass.set_pipeline(&v.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
    }
}
