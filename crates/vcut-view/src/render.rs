//! The scene renderer (environment background + meshes with per-vertex colours, the CPU
//! renderer's display transform) on a [`Gpu`]. It takes draw inputs — [`Meshes`] (what a
//! session's frame shows, read only when its versions change), [`LeafMesh`] and [`Shown`] —
//! not sessions; `crate::headless` renders sessions to images with it.

use crate::camera::OrbitCamera;
use crate::gpu::{Gpu, ViewError};
use glam::{Mat3, Vec3};
use std::time::Instant;
use vcut_envmap::{EnvMap, Layout};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniforms {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    env_x: [f32; 4],
    env_y: [f32; 4],
    env_z: [f32; 4],
    params: [f32; 4],
    flags: [u32; 4],
    viewport: [f32; 4],
}

/// A region of the render target, in pixels from the top left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    /// Left edge.
    pub x: f32,
    /// Top edge.
    pub y: f32,
    /// Width.
    pub width: f32,
    /// Height.
    pub height: f32,
}

impl Viewport {
    /// The whole of a `width × height` target.
    pub fn full(width: u32, height: u32) -> Viewport {
        Viewport { x: 0.0, y: 0.0, width: width as f32, height: height as f32 }
    }
}

/// Bytes per mesh vertex: position, colour, textured colour (3 floats each), uv (2).
const MESH_VERTEX_BYTES: usize = 44;

/// Depth format of the scene pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The environment's texels (only read with `textureLoad`, never rendered to: every adapter
/// samples 32-bit floats, though OpenGL cannot render to them).
const ENV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

struct ObjectBuffers {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    vertex_count: usize,
}

/// A mesh object's vertex buffers and its albedo texture's bind group.
struct MeshObject {
    buffers: ObjectBuffers,
    albedo: wgpu::BindGroup,
}

/// One object's vertices as drawn: a pixel shows `colour + textured × albedo(uv)`, the albedo
/// the object's texture sampled as the CPU renderer samples it (bilinear, repeating, sRGB
/// decoded) — 1 for an object without one.
pub struct ObjectVertices {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per vertex, what is added as it is (linear radiance, or display values; see
    /// [`Shown::radiance`]).
    pub colours: Vec<Vec3>,
    /// Per vertex, what the texture's albedo multiplies (empty: nothing).
    pub textured: Vec<Vec3>,
    /// Per vertex, texture coordinates (empty: none).
    pub uvs: Vec<glam::Vec2>,
}

/// The meshes of a frame as the renderer reads them (the cut viewer's session is one): read
/// only when their versions change.
pub trait Meshes {
    /// Versions of the environment's texels, the vertex positions and the vertex colours: a
    /// change uploads that part again.
    fn versions(&self) -> [u64; 3];
    /// The environment drawn behind.
    fn env(&self) -> &EnvMap;
    /// Every object's triangles (vertex indices).
    fn triangles(&self) -> Vec<&[[u32; 3]]>;
    /// Every object's vertices.
    fn vertices(&self) -> Vec<ObjectVertices>;
    /// Every object's albedo texture (`None`: white), read when the object count changes.
    fn albedo_textures(&self) -> Vec<Option<&vcut_scene::texture::Texture>>;
}

/// A plant's leaves as the renderer reads them.
pub struct LeafMesh<'a> {
    /// Vertex positions.
    pub positions: &'a [Vec3],
    /// Per vertex, the radiance of its side along the normal and of the other side.
    pub radiance: &'a [[Vec3; 2]],
    /// The triangles drawn.
    pub triangles: &'a [[u32; 3]],
    /// Bumped whenever any of the above changes.
    pub version: u64,
    /// The environment drawn behind.
    pub env: &'a EnvMap,
}

/// How a frame is shown.
#[derive(Clone, Copy)]
pub struct Shown<'a> {
    /// The environment drawn behind.
    pub env: &'a EnvMap,
    /// The camera.
    pub camera: &'a OrbitCamera,
    /// Exposure applied to radiance.
    pub exposure: f32,
    /// The colours are radiance (exposure and the display transform applied); else display
    /// values shown as they are (the difference heat map).
    pub radiance: bool,
    /// Where in the target, in pixels.
    pub viewport: Viewport,
}

/// How a pipeline meets the depth buffer.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Depth {
    /// Tested (nearer wins) and written: meshes and leaves.
    Write,
    /// At the far plane, where nothing nearer was drawn: the background.
    Behind,
    /// Over everything: the screen-space image.
    Over,
}

/// Draws a frame: meshes, then the background behind them.
pub struct SceneRenderer {
    format: wgpu::TextureFormat,
    uniforms: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    background: wgpu::RenderPipeline,
    mesh: wgpu::RenderPipeline,
    albedo_layout: wgpu::BindGroupLayout,
    albedo_sampler: wgpu::Sampler,
    image_layout: wgpu::BindGroupLayout,
    image: wgpu::RenderPipeline,
    env_size: (u32, u32),
    objects: Vec<MeshObject>,
    uploaded: Option<[u64; 3]>,
    leaf: wgpu::RenderPipeline,
    leaves: Option<(ObjectBuffers, u64)>,
}

/// The lat-long texels to draw `env` with (its rotation and intensity go in the uniforms):
/// lat-long maps as they are, cube maps resampled, anything wider than `max_width` reduced.
fn background_texels(env: &EnvMap, max_width: u32) -> (u32, u32, Vec<[f32; 4]>) {
    let mut plain = env.clone();
    plain.set_rotation(glam::Quat::IDENTITY);
    plain.set_intensity(1.0);
    let map = match env.layout() {
        Layout::LatLong { width, .. } if width <= max_width => plain,
        Layout::LatLong { .. } => plain.to_latlong(max_width, 2),
        Layout::Cube { size, .. } => plain.to_latlong((4 * size).min(max_width), 2),
    };
    let Layout::LatLong { width, height } = map.layout() else { unreachable!("resampled to lat-long") };
    let texels = map.texels().iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
    (width, height, texels)
}

impl SceneRenderer {
    /// A renderer drawing into targets of `format`.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat, env: &EnvMap) -> Result<SceneRenderer, ViewError> {
        gpu.require_format(format, wgpu::TextureUsages::RENDER_ATTACHMENT, "draw the scene")?;
        gpu.require_format(DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT, "draw the scene")?;
        gpu.require_format(ENV_FORMAT, wgpu::TextureUsages::TEXTURE_BINDING, "draw the environment")?;
        Ok(gpu.checked("build the scene renderer", || Self::build(gpu, format, env))?)
    }

    fn build(gpu: &Gpu, format: wgpu::TextureFormat, env: &EnvMap) -> SceneRenderer {
        let device = &gpu.device;
        let shader = device.create_shader_module(wgpu::include_wgsl!("shaders/scene.wgsl"));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let image_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("image"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let image_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("image"),
            bind_group_layouts: &[Some(&layout), Some(&image_layout)],
            immediate_size: 0,
        });
        let albedo_layout = crate::albedo::layout(device);
        let mesh_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("mesh"),
            bind_group_layouts: &[Some(&layout), Some(&albedo_layout)],
            immediate_size: 0,
        });
        let target = [Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })];
        let pipeline = |label: &str,
                        layout: &wgpu::PipelineLayout,
                        vs: &str,
                        fs: &str,
                        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                        depth: Depth| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth == Depth::Write),
                    depth_compare: Some(match depth {
                        Depth::Write => wgpu::CompareFunction::Less,
                        Depth::Behind => wgpu::CompareFunction::LessEqual,
                        Depth::Over => wgpu::CompareFunction::Always,
                    }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &target,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let background = pipeline("background", &pipeline_layout, "vs_background", "fs_background", &[], Depth::Behind);
        let image = pipeline("image", &image_pipeline_layout, "vs_background", "fs_image", &[], Depth::Over);
        // Meshes: position, the colour added, the colour the albedo texture multiplies, uv.
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: MESH_VERTEX_BYTES as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x2],
        };
        let mesh = pipeline("mesh", &mesh_pipeline_layout, "vs_mesh", "fs_mesh", &[Some(vertex_layout)], Depth::Write);
        // Leaves: position, the radiance of the side along the normal, of the side against it.
        let leaf_layout = wgpu::VertexBufferLayout {
            array_stride: 36,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3],
        };
        let leaf = pipeline("leaf", &pipeline_layout, "vs_leaf", "fs_leaf", &[Some(leaf_layout)], Depth::Write);
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("uniforms"),
            size: std::mem::size_of::<Uniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (bind_group, env_size) = Self::env_bind_group(gpu, &layout, &uniforms, env);
        SceneRenderer {
            format,
            uniforms,
            layout,
            bind_group,
            background,
            mesh,
            albedo_sampler: crate::albedo::sampler(device),
            albedo_layout,
            image_layout,
            image,
            env_size,
            objects: Vec::new(),
            leaf,
            leaves: None,
            uploaded: None,
        }
    }

    fn env_bind_group(
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        uniforms: &wgpu::Buffer,
        env: &EnvMap,
    ) -> (wgpu::BindGroup, (u32, u32)) {
        let max = gpu.device.limits().max_texture_dimension_2d.min(8192);
        let (w, h, texels) = background_texels(env, max);
        let texture = gpu.texture_with("environment", ENV_FORMAT, (w, h), bytemuck::cast_slice(&texels));
        let view = texture.create_view(&Default::default());
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: uniforms.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view) },
            ],
        });
        (bind_group, (w, h))
    }

    /// Uploads what changed in `meshes` since the last call (environment texels, vertex
    /// positions, colours); returns the milliseconds spent.
    pub fn upload(&mut self, gpu: &Gpu, meshes: &dyn Meshes) -> Result<f64, ViewError> {
        Ok(gpu.checked("upload the frame", || self.upload_unchecked(gpu, meshes))?)
    }

    fn upload_unchecked(&mut self, gpu: &Gpu, meshes: &dyn Meshes) -> f64 {
        let start = Instant::now();
        let versions = meshes.versions();
        if self.uploaded.is_some_and(|u| u[0] != versions[0]) {
            let (bg, size) = Self::env_bind_group(gpu, &self.layout, &self.uniforms, meshes.env());
            self.bind_group = bg;
            self.env_size = size;
        }
        if self.uploaded.is_some_and(|u| u[1] == versions[1] && u[2] == versions[2]) {
            return 0.0;
        }
        let vertices = meshes.vertices();
        if self.objects.len() != vertices.len() {
            let textures = meshes.albedo_textures();
            self.objects = meshes
                .triangles()
                .iter()
                .zip(&vertices)
                .enumerate()
                .map(|(o, (triangles, v))| {
                    let indices: Vec<u32> = triangles.iter().flatten().copied().collect();
                    let vertex_count = v.positions.len();
                    let texture = textures.get(o).copied().flatten();
                    MeshObject {
                        buffers: ObjectBuffers {
                            vertices: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                                label: Some("vertices"),
                                size: (vertex_count.max(1) * MESH_VERTEX_BYTES) as u64,
                                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                                mapped_at_creation: false,
                            }),
                            indices: {
                                let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                                    label: Some("indices"),
                                    size: (indices.len().max(1) * 4).next_multiple_of(4) as u64,
                                    usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
                                    mapped_at_creation: false,
                                });
                                gpu.queue.write_buffer(&buffer, 0, bytemuck::cast_slice(&indices));
                                buffer
                            },
                            index_count: indices.len() as u32,
                            vertex_count,
                        },
                        albedo: crate::albedo::bind_group(gpu, &self.albedo_layout, &self.albedo_sampler, texture),
                    }
                })
                .collect();
        }
        for (object, v) in self.objects.iter().zip(&vertices) {
            let data: Vec<[f32; 11]> = (0..v.positions.len().min(object.buffers.vertex_count))
                .map(|i| {
                    let (p, c) = (v.positions[i], v.colours.get(i).copied().unwrap_or(Vec3::ZERO));
                    let t = v.textured.get(i).copied().unwrap_or(Vec3::ZERO);
                    let uv = v.uvs.get(i).copied().unwrap_or(glam::Vec2::ZERO);
                    [p.x, p.y, p.z, c.x, c.y, c.z, t.x, t.y, t.z, uv.x, uv.y]
                })
                .collect();
            gpu.queue.write_buffer(&object.buffers.vertices, 0, bytemuck::cast_slice(&data));
        }
        self.uploaded = Some(versions);
        start.elapsed().as_secs_f64() * 1e3
    }

    /// Records the scene pass into `target` (with `depth` of the same size): the whole target
    /// cleared to black, the uploaded meshes drawn as `shown` says (in its viewport, a region
    /// of the target) — or, with `image` (a linear texture of the viewport's size holding f32
    /// bits, w = covered), that image instead of the meshes: the screen-space modes.
    pub fn draw(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        (target, depth): (&wgpu::TextureView, &wgpu::TextureView),
        shown: Shown<'_>,
        image: Option<&wgpu::TextureView>,
    ) {
        let mut pass = self.begin(gpu, encoder, (target, depth), shown);
        if let Some(image) = image {
            let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("image"),
                layout: &self.image_layout,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(image) }],
            });
            pass.set_pipeline(&self.image);
            pass.set_bind_group(1, &group, &[]);
            pass.draw(0..3, 0..1);
            return;
        }
        pass.set_pipeline(&self.mesh);
        for MeshObject { buffers: o, albedo } in &self.objects {
            if o.index_count == 0 {
                continue;
            }
            pass.set_bind_group(1, albedo, &[]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.index_count, 0, 0..1);
        }
        // After the meshes, at the far plane: only the pixels they left are shaded (on a CPU
        // rasterizer the background's lookups were most of a frame's time).
        pass.set_pipeline(&self.background);
        pass.draw(0..3, 0..1);
    }

    /// Writes the uniforms and opens the scene pass over `viewport` (target cleared to black,
    /// depth to 1), the scene bind group set.
    fn begin<'e>(
        &self,
        gpu: &Gpu,
        encoder: &'e mut wgpu::CommandEncoder,
        (target, depth): (&wgpu::TextureView, &wgpu::TextureView),
        Shown { env, camera, exposure, radiance, viewport }: Shown<'_>,
    ) -> wgpu::RenderPass<'e> {
        let (width, height) = (viewport.width.max(1.0), viewport.height.max(1.0));
        let vp = camera.view_projection(width / height);
        let map_from_world = Mat3::from_quat(env.rotation().inverse());
        let u = Uniforms {
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            eye: camera.eye().extend(1.0).to_array(),
            env_x: map_from_world.x_axis.extend(0.0).to_array(),
            env_y: map_from_world.y_axis.extend(0.0).to_array(),
            env_z: map_from_world.z_axis.extend(0.0).to_array(),
            params: [exposure, env.intensity(), width, height],
            flags: [u32::from(radiance), u32::from(!self.format.is_srgb()), self.env_size.0, self.env_size.1],
            viewport: [viewport.x, viewport.y, width, height],
        };
        gpu.queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&u));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_viewport(viewport.x, viewport.y, width, height, 0.0, 1.0);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass
    }

    /// Uploads a plant's drawn triangles and two-sided radiance when their version changed
    /// (and its environment the first time); returns the milliseconds spent.
    pub fn upload_leaves(&mut self, gpu: &Gpu, leaves: &LeafMesh<'_>) -> Result<f64, ViewError> {
        Ok(gpu.checked("upload the leaves", || self.upload_leaves_unchecked(gpu, leaves))?)
    }

    fn upload_leaves_unchecked(&mut self, gpu: &Gpu, leaves: &LeafMesh<'_>) -> f64 {
        let start = Instant::now();
        if self.leaves.as_ref().is_some_and(|(_, v)| *v == leaves.version) {
            return 0.0;
        }
        if self.leaves.is_none() {
            let (bg, size) = Self::env_bind_group(gpu, &self.layout, &self.uniforms, leaves.env);
            self.bind_group = bg;
            self.env_size = size;
        }
        let data: Vec<[f32; 9]> = leaves
            .positions
            .iter()
            .zip(leaves.radiance)
            .map(|(p, r)| [p.x, p.y, p.z, r[0].x, r[0].y, r[0].z, r[1].x, r[1].y, r[1].z])
            .collect();
        let indices: Vec<u32> = leaves.triangles.iter().flatten().copied().collect();
        let buffer = |label: &str, bytes: &[u8], usage: wgpu::BufferUsages| {
            let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (bytes.len().max(4)).next_multiple_of(4) as u64,
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&b, 0, bytes);
            b
        };
        let buffers = ObjectBuffers {
            vertices: buffer("leaf vertices", bytemuck::cast_slice(&data), wgpu::BufferUsages::VERTEX),
            indices: buffer("leaf indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
            index_count: indices.len() as u32,
            vertex_count: data.len(),
        };
        self.leaves = Some((buffers, leaves.version));
        start.elapsed().as_secs_f64() * 1e3
    }

    /// Records the uploaded leaves: the environment behind, each triangle showing the side
    /// that faces the camera (front faces — counter-clockwise, as the vertex normals wind — show
    /// the side along the normal).
    pub fn draw_leaves(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        (target, depth): (&wgpu::TextureView, &wgpu::TextureView),
        shown: Shown<'_>,
    ) {
        let mut pass = self.begin(gpu, encoder, (target, depth), shown);
        pass.set_pipeline(&self.background);
        pass.draw(0..3, 0..1);
        if let Some((b, _)) = &self.leaves
            && b.index_count > 0
        {
            pass.set_pipeline(&self.leaf);
            pass.set_vertex_buffer(0, b.vertices.slice(..));
            pass.set_index_buffer(b.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..b.index_count, 0, 0..1);
        }
    }
}

/// A depth texture view for a `width × height` target.
pub fn depth_view(gpu: &Gpu, width: u32, height: u32) -> wgpu::TextureView {
    gpu.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d { width: width.max(1), height: height.max(1), depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}
