//! The 3D pass: every body's mesh drawn instanced (one draw per shape, all
//! its bodies in one call), then the overlay lines.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use crate::shapes::RenderMesh;

/// The depth buffer's format.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A mesh vertex.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
}

/// One drawn body: its model matrix (columns) and colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Instance {
    /// The model matrix's columns.
    pub model: [[f32; 4]; 4],
    /// Linear-free RGBA colour (written as is).
    pub color: [f32; 4],
}

impl Instance {
    /// A body at `model` in `color`.
    pub fn new(model: Mat4, color: [f32; 4]) -> Instance {
        Instance { model: model.to_cols_array_2d(), color }
    }
}

/// One overlay line end.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LineVertex {
    /// World position.
    pub position: [f32; 3],
    /// RGBA colour.
    pub color: [f32; 4],
}

/// The shader's uniforms.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    light_dir: [f32; 4],
    eye: [f32; 4],
}

/// What one frame draws: instances grouped by mesh, and two sets of lines
/// (depth-tested, and always on top), seen from `eye`.
#[derive(Default)]
pub struct DrawList {
    /// Where the eye is (flat shading turns faces towards it).
    pub eye: Vec3,
    /// Per mesh, its instances (the index is the mesh's in [`SceneRenderer::new`]).
    pub instances: Vec<Vec<Instance>>,
    /// Lines hidden behind bodies, as pairs of ends.
    pub lines: Vec<LineVertex>,
    /// Lines drawn over everything (contacts, the selection).
    pub lines_on_top: Vec<LineVertex>,
}

impl DrawList {
    /// Empties every list, keeping their storage.
    pub fn clear(&mut self, meshes: usize) {
        self.instances.resize_with(meshes, Vec::new);
        self.instances.iter_mut().for_each(Vec::clear);
        self.lines.clear();
        self.lines_on_top.clear();
    }

    /// Adds the line from `a` to `b`.
    pub fn line(&mut self, a: Vec3, b: Vec3, color: [f32; 4], on_top: bool) {
        let list = if on_top { &mut self.lines_on_top } else { &mut self.lines };
        list.push(LineVertex { position: a.into(), color });
        list.push(LineVertex { position: b.into(), color });
    }
}

/// Where a mesh lies in the shared vertex and index buffers.
struct MeshRange {
    base_vertex: i32,
    first_index: u32,
    index_count: u32,
}

/// A buffer that grows (doubling) to hold what it is given.
struct GrowBuffer {
    buffer: wgpu::Buffer,
    usage: wgpu::BufferUsages,
}

impl GrowBuffer {
    fn new(device: &wgpu::Device, usage: wgpu::BufferUsages) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grow"),
            size: 1 << 16,
            usage,
            mapped_at_creation: false,
        });
        GrowBuffer { buffer, usage }
    }

    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        if bytes.len() as u64 > self.buffer.size() {
            let size = (bytes.len() as u64).next_power_of_two();
            self.buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("grow"),
                size,
                usage: self.usage,
                mapped_at_creation: false,
            });
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// The pipelines and buffers of the 3D pass.
pub struct SceneRenderer {
    mesh_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    line_on_top_pipeline: wgpu::RenderPipeline,
    globals: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    meshes: Vec<MeshRange>,
    instances: GrowBuffer,
    lines: GrowBuffer,
    depth: Option<(wgpu::TextureView, [u32; 2])>,
    /// Per mesh: its first instance and count in the instance buffer; then
    /// the counts of both line lists, as uploaded by `prepare`.
    batches: Vec<(u32, u32)>,
    line_counts: [u32; 2],
}

impl SceneRenderer {
    /// Pipelines drawing into `format`, and every mesh uploaded once.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, meshes: &[&RenderMesh]) -> Self {
        let shader = device.create_shader_module(wgpu::include_wgsl!("shader.wgsl"));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: globals.as_entire_binding() }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let mesh_pipeline = mesh_pipeline(device, &pipeline_layout, &shader, format);
        let lines = |on_top| line_pipeline(device, &pipeline_layout, &shader, format, on_top);
        let (line_pipeline, line_on_top_pipeline) = (lines(false), lines(true));
        let (vertices, indices, ranges) = upload_meshes(device, meshes);
        SceneRenderer {
            mesh_pipeline,
            line_pipeline,
            line_on_top_pipeline,
            globals,
            bind_group,
            vertices,
            indices,
            meshes: ranges,
            instances: GrowBuffer::new(device, wgpu::BufferUsages::VERTEX),
            lines: GrowBuffer::new(device, wgpu::BufferUsages::VERTEX),
            depth: None,
            batches: Vec::new(),
            line_counts: [0; 2],
        }
    }

    /// Uploads one frame's uniforms, instances and lines, and sizes the depth
    /// buffer to the target.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        view_proj: Mat4,
        list: &DrawList,
        target_size: [u32; 2],
    ) {
        let light = Vec3::new(0.4, 1.0, 0.3).normalize();
        let g = Globals {
            view_proj: view_proj.to_cols_array_2d(),
            light_dir: [light.x, light.y, light.z, 0.0],
            eye: list.eye.extend(1.0).into(),
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
        self.batches.clear();
        let mut all = Vec::with_capacity(list.instances.iter().map(Vec::len).sum());
        for group in list.instances.iter().take(self.meshes.len()) {
            self.batches.push((all.len() as u32, group.len() as u32));
            all.extend_from_slice(group);
        }
        self.instances.write(device, queue, bytemuck::cast_slice(&all));
        let mut lines = Vec::with_capacity(list.lines.len() + list.lines_on_top.len());
        lines.extend_from_slice(&list.lines);
        lines.extend_from_slice(&list.lines_on_top);
        self.lines.write(device, queue, bytemuck::cast_slice(&lines));
        self.line_counts = [list.lines.len() as u32, list.lines_on_top.len() as u32];
        if self.depth.as_ref().is_none_or(|d| d.1 != target_size) {
            self.depth = Some((depth_view(device, target_size), target_size));
        }
    }

    /// Records the 3D pass into `target`, cleared first, drawing in the
    /// `viewport` rectangle (x, y, width, height in pixels).
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        viewport: [f32; 4],
    ) {
        let Some((depth, _)) = &self.depth else { return };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(CLEAR_COLOR),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let [x, y, w, h] = viewport;
        if w < 1.0 || h < 1.0 {
            return;
        }
        pass.set_viewport(x, y, w, h, 0.0, 1.0);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_pipeline(&self.mesh_pipeline);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_vertex_buffer(1, self.instances.buffer.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for (mesh, &(first, count)) in self.meshes.iter().zip(&self.batches) {
            if count > 0 {
                let indices = mesh.first_index..mesh.first_index + mesh.index_count;
                pass.draw_indexed(indices, mesh.base_vertex, first..first + count);
            }
        }
        let [depth_tested, on_top] = self.line_counts;
        pass.set_vertex_buffer(0, self.lines.buffer.slice(..));
        if depth_tested > 0 {
            pass.set_pipeline(&self.line_pipeline);
            pass.draw(0..depth_tested, 0..1);
        }
        if on_top > 0 {
            pass.set_pipeline(&self.line_on_top_pipeline);
            pass.draw(depth_tested..depth_tested + on_top, 0..1);
        }
    }
}

/// The background: a dark blue-grey.
pub const CLEAR_COLOR: wgpu::Color = wgpu::Color { r: 0.11, g: 0.12, b: 0.15, a: 1.0 };

fn depth_view(device: &wgpu::Device, [width, height]: [u32; 2]) -> wgpu::TextureView {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth"),
        size: wgpu::Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    texture.create_view(&Default::default())
}

fn upload_meshes(
    device: &wgpu::Device,
    meshes: &[&RenderMesh],
) -> (wgpu::Buffer, wgpu::Buffer, Vec<MeshRange>) {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let mut ranges = Vec::new();
    for mesh in meshes {
        ranges.push(MeshRange {
            base_vertex: vertices.len() as i32,
            first_index: indices.len() as u32,
            index_count: mesh.indices.len() as u32,
        });
        vertices.extend(
            mesh.positions
                .iter()
                .zip(&mesh.normals)
                .map(|(p, n)| Vertex { position: (*p).into(), normal: (*n).into() }),
        );
        indices.extend_from_slice(&mesh.indices);
    }
    let buffer = |label, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let v = buffer("vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
    let i = buffer("indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX);
    (v, i, ranges)
}

fn mesh_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let vertex = wgpu::VertexBufferLayout {
        array_stride: size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
    };
    let instance = wgpu::VertexBufferLayout {
        array_stride: size_of::<Instance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &wgpu::vertex_attr_array![
            2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4
        ],
    };
    pipeline(
        device,
        layout,
        shader,
        format,
        ("vs_mesh", "fs_mesh"),
        &[Some(vertex), Some(instance)],
        wgpu::PrimitiveTopology::TriangleList,
        wgpu::CompareFunction::Less,
    )
}

fn line_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    on_top: bool,
) -> wgpu::RenderPipeline {
    let vertex = wgpu::VertexBufferLayout {
        array_stride: size_of::<LineVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
    };
    let compare =
        if on_top { wgpu::CompareFunction::Always } else { wgpu::CompareFunction::LessEqual };
    pipeline(
        device,
        layout,
        shader,
        format,
        ("vs_line", "fs_line"),
        &[Some(vertex)],
        wgpu::PrimitiveTopology::LineList,
        compare,
    )
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    (vs, fs): (&str, &str),
    buffers: &[Option<wgpu::VertexBufferLayout>],
    topology: wgpu::PrimitiveTopology,
    depth_compare: wgpu::CompareFunction,
) -> wgpu::RenderPipeline {
    let triangles = topology == wgpu::PrimitiveTopology::TriangleList;
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(vs),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some(vs),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            cull_mode: triangles.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(triangles),
            depth_compare: Some(depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(fs),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                // Bodies are opaque (blending costs a software rasteriser a
                // read per pixel); overlay lines are see-through.
                blend: (!triangles).then_some(wgpu::BlendState::ALPHA_BLENDING),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
