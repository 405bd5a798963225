//! SSDO and SSAO on the GPU (WGSL, `shaders/ssdo.wgsl`; feature `gpu`): the same passes as
//! this crate's CPU twin — two-layer G-buffer, sun shadow map, sampling, bounce, blur, composite — over the same
//! inputs (objects, lighting, samples, parameters), so the two images can be compared.

use crate::{Lighting, Method, Object, Params, SampleSets};
use glam::Vec3;
use vcut_gpu::{Gpu, GpuError};
use vcut_scene::Camera;

/// Every colour texture of the passes: four 32-bit floats stored as their bits (the shader's
/// `ld` and `st`) — as exact as Rgba32Float, and renderable on every adapter, where OpenGL
/// (llvmpipe included) cannot render to Rgba32Float.
const PACKED: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The sun's shadow map: its depths as f32 bits beside the depth buffer (OpenGL shaders cannot
/// read a depth texture with `textureLoad`), cleared to the bits of 1.0 as a depth buffer is.
const SHADOW: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const SHADOW_CLEAR: wgpu::Color = wgpu::Color { r: 1_065_353_216.0, g: 0.0, b: 0.0, a: 0.0 };
/// Side of the sun's shadow map (as the CPU's `Lighting::new`).
const SHADOW_SIZE: u32 = 2048;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniforms {
    view_proj: [[f32; 4]; 4],
    shadow_view: [[f32; 4]; 4],
    eye: [f32; 4],
    sun_dir: [f32; 4],
    sun_irradiance: [f32; 4],
    size: [f32; 4],
    p0: [f32; 4],
    p1: [u32; 4],
    p2: [u32; 4],
    p3: [f32; 4],
}

/// The compiled passes.
pub struct GpuSsdo {
    gbuffer: wgpu::RenderPipeline,
    gbuffer_second: wgpu::RenderPipeline,
    shadow: wgpu::RenderPipeline,
    sample: wgpu::RenderPipeline,
    indirect: wgpu::RenderPipeline,
    blur: wgpu::RenderPipeline,
    composite: wgpu::RenderPipeline,
}

/// One frame's resources, encoded and submitted by [`SsdoFrame::run`].
pub struct SsdoFrame {
    width: u32,
    height: u32,
    commands: Vec<Pass>,
    out: wgpu::Texture,
    /// Kept alive for the bind groups.
    _resources: Vec<wgpu::Texture>,
}

struct Draw {
    pipeline: wgpu::RenderPipeline,
    groups: Vec<wgpu::BindGroup>,
    meshes: Vec<(wgpu::Buffer, wgpu::Buffer, u32)>,
    fullscreen: bool,
}

struct Pass {
    label: &'static str,
    targets: Vec<wgpu::TextureView>,
    /// What the targets are cleared to.
    clear: wgpu::Color,
    depth: Option<wgpu::TextureView>,
    draw: Option<Draw>,
}

fn texture(
    gpu: &Gpu,
    label: &str,
    (w, h): (u32, u32),
    format: wgpu::TextureFormat,
    extra: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w.max(1), height: h.max(1), depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | extra,
        view_formats: &[],
    })
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&Default::default())
}

fn table(gpu: &Gpu, label: &str, size: usize, texels: &[Vec3]) -> wgpu::Texture {
    let s = (size as u32).max(1);
    // Only read: no render-attachment use.
    let data: Vec<[f32; 4]> = texels.iter().map(|c| [c.x, c.y, c.z, 1.0]).collect();
    gpu.texture_with(label, PACKED, (s, s), bytemuck::cast_slice(&data))
}

fn bind_group(
    gpu: &Gpu,
    pipeline: &wgpu::RenderPipeline,
    index: u32,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry { binding: i as u32, resource: r.clone() })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(index),
        entries: &entries,
    })
}

impl GpuSsdo {
    /// Compiles the passes, or says what the adapter lacks for them.
    pub fn new(gpu: &Gpu) -> Result<GpuSsdo, GpuError> {
        const WHAT: &str = "run the screen-space (SSAO/SSDO) passes";
        let usages = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        gpu.require_format(PACKED, usages, WHAT)?;
        gpu.require_format(DEPTH, usages, WHAT)?;
        gpu.require_format(SHADOW, usages, WHAT)?;
        gpu.require_downlevel(wgpu::DownlevelFlags::FRAGMENT_STORAGE, WHAT)?;
        let limits = gpu.device.limits();
        if limits.max_color_attachments < 2 || limits.max_color_attachment_bytes_per_sample < 32 {
            return Err(GpuError::Unsupported {
                adapter: gpu.describe(),
                what: WHAT.into(),
                lacks: format!(
                    "two 16-byte colour targets per pass (it allows {} targets, {} bytes per sample)",
                    limits.max_color_attachments, limits.max_color_attachment_bytes_per_sample
                ),
            });
        }
        gpu.checked("compile the screen-space passes", || Self::compile(gpu))
    }

    fn compile(gpu: &Gpu) -> GpuSsdo {
        let device = &gpu.device;
        let shader = device.create_shader_module(wgpu::include_wgsl!("shaders/ssdo.wgsl"));
        let vertex = wgpu::VertexBufferLayout {
            array_stride: 28,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32],
        };
        let depth_state = |format| {
            Some(wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            })
        };
        let make =
            |label: &str, vs: &str, fs: Option<&str>, targets: &[wgpu::TextureFormat], mesh: bool, depth: bool| {
                let targets: Vec<Option<wgpu::ColorTargetState>> = targets
                    .iter()
                    .map(|&format| {
                        Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })
                    })
                    .collect();
                let buffers = [Some(vertex.clone())];
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: None,
                    vertex: wgpu::VertexState {
                        module: &shader,
                        entry_point: Some(vs),
                        compilation_options: Default::default(),
                        buffers: if mesh { &buffers } else { &[] },
                    },
                    primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                    depth_stencil: if depth { depth_state(DEPTH) } else { None },
                    multisample: Default::default(),
                    fragment: fs.map(|fs| wgpu::FragmentState {
                        module: &shader,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        GpuSsdo {
            gbuffer: make("gbuffer", "vs_gbuffer", Some("fs_gbuffer"), &[PACKED; 2], true, true),
            gbuffer_second: make(
                "gbuffer second layer",
                "vs_gbuffer",
                Some("fs_gbuffer_second"),
                &[PACKED; 2],
                true,
                true,
            ),
            shadow: make("shadow", "vs_shadow", Some("fs_shadow"), &[SHADOW], true, true),
            sample: make("sample", "vs_fullscreen", Some("fs_sample"), &[PACKED; 2], false, false),
            indirect: make("indirect", "vs_fullscreen", Some("fs_indirect"), &[PACKED], false, false),
            blur: make("blur", "vs_fullscreen", Some("fs_blur"), &[PACKED; 2], false, false),
            composite: make("composite", "vs_fullscreen", Some("fs_composite"), &[PACKED], false, false),
        }
    }

    /// Builds a `width × height` frame of `method` over `objects` seen by `camera`.
    #[allow(clippy::too_many_arguments)]
    pub fn frame(
        &self,
        gpu: &Gpu,
        objects: &[Object],
        light: &Lighting,
        camera: &Camera,
        params: &Params,
        method: Method,
        size: (u32, u32),
    ) -> Result<SsdoFrame, GpuError> {
        gpu.checked("set up a screen-space frame", || {
            self.build_frame(gpu, objects, light, camera, params, method, size)
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn build_frame(
        &self,
        gpu: &Gpu,
        objects: &[Object],
        light: &Lighting,
        camera: &Camera,
        params: &Params,
        method: Method,
        (width, height): (u32, u32),
    ) -> SsdoFrame {
        let (w, h) = (width.max(1), height.max(1));
        let size = (w, h);
        let vp = camera.view_projection(w as f32 / h as f32);
        let sets = SampleSets::halton(params.samples, params.sets);
        let (cone, irr) = light.env.tables();
        let (shadow_view, half, bias) = match &light.shadow {
            Some(m) => (m.view(), m.half(), m.bias()),
            None => (glam::Mat4::IDENTITY, 1.0, 0.0),
        };
        let sun = light.sun.filter(|_| light.shadow.is_some());
        let base = Uniforms {
            view_proj: vp.to_cols_array_2d(),
            shadow_view: shadow_view.to_cols_array_2d(),
            eye: camera.position.extend(1.0).to_array(),
            sun_dir: sun.map_or([0.0; 4], |s| s.dir.extend(1.0).to_array()),
            sun_irradiance: sun.map_or([0.0; 4], |s| s.irradiance.extend(0.0).to_array()),
            size: [w as f32, h as f32, SHADOW_SIZE as f32, half],
            p0: [params.radius, params.depth_limit, params.bleed, bias],
            p1: [sets.n as u32, sets.sets.len() as u32, u32::from(params.peel), u32::from(method == Method::Ssdo)],
            p2: [
                u32::from(method == Method::Ssdo && params.indirect),
                params.blur_radius as u32,
                cone.size() as u32,
                irr.size() as u32,
            ],
            p3: [4.0 * half, 0.0, 0.0, 0.0],
        };
        let uniform = |u: Uniforms| {
            let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ssdo uniforms"),
                size: std::mem::size_of::<Uniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            gpu.queue.write_buffer(&b, 0, bytemuck::bytes_of(&u));
            b
        };
        let u_main = uniform(base);
        let u_h = uniform(Uniforms { p3: [4.0 * half, 1.0, 0.0, 0.0], ..base });
        let u_v = uniform(Uniforms { p3: [4.0 * half, 0.0, 1.0, 0.0], ..base });
        let points: Vec<[f32; 4]> = sets.sets.iter().flatten().map(|p| p.extend(0.0).to_array()).collect();
        let samples = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("samples"),
            size: (points.len().max(1) * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&samples, 0, bytemuck::cast_slice(&points));
        let albedo_data: Vec<[f32; 4]> = objects.iter().map(|o| o.albedo.extend(0.0).to_array()).collect();
        let albedos = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("albedos"),
            size: (albedo_data.len().max(1) * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&albedos, 0, bytemuck::cast_slice(&albedo_data));
        let meshes: Vec<(wgpu::Buffer, wgpu::Buffer, u32)> = objects
            .iter()
            .enumerate()
            .filter(|(_, o)| !o.triangles.is_empty())
            .map(|(k, o)| {
                let data: Vec<[f32; 7]> =
                    o.positions.iter().zip(&o.normals).map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z, k as f32]).collect();
                let indices: Vec<u32> = o.triangles.iter().flatten().copied().collect();
                let vb = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("ssdo vertices"),
                    size: (data.len().max(1) * 28) as u64,
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                gpu.queue.write_buffer(&vb, 0, bytemuck::cast_slice(&data));
                let ib = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("ssdo indices"),
                    size: (indices.len().max(1) * 4) as u64,
                    usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                gpu.queue.write_buffer(&ib, 0, bytemuck::cast_slice(&indices));
                (vb, ib, indices.len() as u32)
            })
            .collect();
        let none = wgpu::TextureUsages::empty();
        let g1: Vec<wgpu::Texture> =
            ["g position", "g normal"].iter().map(|l| texture(gpu, l, size, PACKED, none)).collect();
        let g2: Vec<wgpu::Texture> =
            ["g2 position", "g2 normal"].iter().map(|l| texture(gpu, l, size, PACKED, none)).collect();
        let depth1 = texture(gpu, "depth", size, DEPTH, none);
        let depth2 = texture(gpu, "depth 2", size, DEPTH, none);
        let shadow_depth = texture(gpu, "shadow depth", (SHADOW_SIZE, SHADOW_SIZE), DEPTH, none);
        let shadow = texture(gpu, "shadow", (SHADOW_SIZE, SHADOW_SIZE), SHADOW, none);
        let cone_t = table(gpu, "cone", cone.size(), cone.texels());
        let irr_t = table(gpu, "irradiance", irr.size(), irr.texels());
        let env = texture(gpu, "env term", size, PACKED, none);
        let sun_t = texture(gpu, "sun term", size, PACKED, none);
        let indirect = texture(gpu, "indirect", size, PACKED, none);
        let blur_h: Vec<wgpu::Texture> = (0..2).map(|_| texture(gpu, "blur h", size, PACKED, none)).collect();
        let blur_v: Vec<wgpu::Texture> = (0..2).map(|_| texture(gpu, "blur v", size, PACKED, none)).collect();
        let out = texture(gpu, "ssdo out", size, PACKED, wgpu::TextureUsages::COPY_SRC);

        let gviews: Vec<wgpu::TextureView> = g1.iter().chain(&g2).map(view).collect();
        // Group 1 holds the G-buffer; each pass's layout (derived from its shader) has only the
        // bindings it reads: `used` lists them.
        let g_group = |p: &wgpu::RenderPipeline, used: &[u32]| {
            let all = [
                wgpu::BindingResource::TextureView(&gviews[0]),
                wgpu::BindingResource::TextureView(&gviews[1]),
                albedos.as_entire_binding(),
                wgpu::BindingResource::TextureView(&gviews[2]),
                samples.as_entire_binding(),
            ];
            let entries: Vec<wgpu::BindGroupEntry<'_>> =
                used.iter().map(|&b| wgpu::BindGroupEntry { binding: b, resource: all[b as usize].clone() }).collect();
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &p.get_bind_group_layout(1),
                entries: &entries,
            })
        };
        // Group 0: the uniforms (`None`: the pass reads none and its derived layout is empty).
        let u_group = |p: &wgpu::RenderPipeline, b: Option<&wgpu::Buffer>| match b {
            Some(b) => bind_group(gpu, p, 0, &[b.as_entire_binding()]),
            None => bind_group(gpu, p, 0, &[]),
        };
        let (env_v, sun_v, ind_v) = (view(&env), view(&sun_t), view(&indirect));
        let (cone_v, irr_v, shadow_v) = (view(&cone_t), view(&irr_t), view(&shadow));
        let (bh, bv): (Vec<wgpu::TextureView>, Vec<wgpu::TextureView>) =
            (blur_h.iter().map(view).collect(), blur_v.iter().map(view).collect());
        // Group 2 by binding: the pass-specific inputs; the layouts hold only what each uses.
        let group2 = |p: &wgpu::RenderPipeline, entries: &[(u32, &wgpu::TextureView)]| {
            let entries: Vec<wgpu::BindGroupEntry<'_>> = entries
                .iter()
                .map(|(b, v)| wgpu::BindGroupEntry { binding: *b, resource: wgpu::BindingResource::TextureView(v) })
                .collect();
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &p.get_bind_group_layout(2),
                entries: &entries,
            })
        };
        let peel = params.peel;
        let mut commands = vec![
            Pass {
                label: "g-buffer",
                targets: g1.iter().map(view).collect(),

                clear: wgpu::Color::TRANSPARENT,
                depth: Some(view(&depth1)),
                draw: Some(Draw {
                    pipeline: self.gbuffer.clone(),
                    groups: vec![u_group(&self.gbuffer, Some(&u_main))],
                    meshes: meshes.iter().map(|(a, b, n)| (a.clone(), b.clone(), *n)).collect(),
                    fullscreen: false,
                }),
            },
            // The second layer (cleared even when not peeling: the samples' pass reads it).
            Pass {
                label: "g-buffer second layer",
                targets: g2.iter().map(view).collect(),

                clear: wgpu::Color::TRANSPARENT,
                depth: Some(view(&depth2)),
                draw: peel.then(|| Draw {
                    pipeline: self.gbuffer_second.clone(),
                    groups: vec![u_group(&self.gbuffer_second, Some(&u_main)), g_group(&self.gbuffer_second, &[0])],
                    meshes: meshes.iter().map(|(a, b, n)| (a.clone(), b.clone(), *n)).collect(),
                    fullscreen: false,
                }),
            },
            Pass {
                label: "shadow map",
                targets: vec![view(&shadow)],
                clear: SHADOW_CLEAR,
                depth: Some(view(&shadow_depth)),
                draw: sun.is_some().then(|| Draw {
                    pipeline: self.shadow.clone(),
                    groups: vec![u_group(&self.shadow, Some(&u_main))],
                    meshes: meshes.iter().map(|(a, b, n)| (a.clone(), b.clone(), *n)).collect(),
                    fullscreen: false,
                }),
            },
        ];
        let fullscreen = |pipeline: &wgpu::RenderPipeline,
                          u: Option<&wgpu::Buffer>,
                          g: &[u32],
                          inputs: &[(u32, &wgpu::TextureView)]| Draw {
            pipeline: pipeline.clone(),
            groups: vec![u_group(pipeline, u), g_group(pipeline, g), group2(pipeline, inputs)],
            meshes: Vec::new(),
            fullscreen: true,
        };
        let all = [0, 1, 2, 3, 4];
        commands.push(Pass {
            label: "sampling",
            targets: vec![view(&env), view(&sun_t)],

            clear: wgpu::Color::TRANSPARENT,
            depth: None,
            draw: Some(fullscreen(&self.sample, Some(&u_main), &all, &[(0, &cone_v), (1, &irr_v), (3, &shadow_v)])),
        });
        let bounce = method == Method::Ssdo && params.indirect;
        commands.push(Pass {
            label: "bounce",
            targets: vec![view(&indirect)],

            clear: wgpu::Color::TRANSPARENT,
            depth: None,
            draw: bounce.then(|| fullscreen(&self.indirect, Some(&u_main), &all, &[(0, &env_v), (1, &sun_v)])),
        });
        commands.push(Pass {
            label: "blur horizontal",
            targets: blur_h.iter().map(view).collect(),

            clear: wgpu::Color::TRANSPARENT,
            depth: None,
            draw: Some(fullscreen(&self.blur, Some(&u_h), &[0, 1], &[(0, &env_v), (1, &ind_v)])),
        });
        commands.push(Pass {
            label: "blur vertical",
            targets: blur_v.iter().map(view).collect(),

            clear: wgpu::Color::TRANSPARENT,
            depth: None,
            draw: Some(fullscreen(&self.blur, Some(&u_v), &[0, 1], &[(0, &bh[0]), (1, &bh[1])])),
        });
        commands.push(Pass {
            label: "composite",
            targets: vec![view(&out)],

            clear: wgpu::Color::TRANSPARENT,
            depth: None,
            draw: Some(fullscreen(&self.composite, None, &[0], &[(0, &bv[0]), (1, &bv[1]), (2, &sun_v)])),
        });
        let mut resources = g1;
        resources.extend(g2);
        resources.extend([depth1, depth2, shadow_depth, shadow, cone_t, irr_t, env, sun_t, indirect]);
        resources.extend(blur_h);
        resources.extend(blur_v);
        SsdoFrame { width: w, height: h, commands, out, _resources: resources }
    }
}

impl SsdoFrame {
    /// Encodes every pass, submits, and waits for the GPU.
    pub fn run(&self, gpu: &Gpu) -> Result<(), GpuError> {
        self.submit(gpu, &self.commands)
    }

    /// Runs the passes one submission each, waiting after each: the wall time of every pass
    /// (label, ms), for finding where a frame's time goes. Their sum exceeds [`Self::run`]'s
    /// time by the submissions' overhead.
    pub fn run_passes(&self, gpu: &Gpu) -> Result<Vec<(&'static str, f64)>, GpuError> {
        self.commands
            .iter()
            .map(|p| {
                let t = std::time::Instant::now();
                self.submit(gpu, std::slice::from_ref(p))?;
                Ok((p.label, t.elapsed().as_secs_f64() * 1e3))
            })
            .collect()
    }

    fn submit(&self, gpu: &Gpu, passes: &[Pass]) -> Result<(), GpuError> {
        gpu.checked("run the screen-space passes", || self.encode_and_submit(gpu, passes))?;
        gpu.wait()
    }

    fn encode_and_submit(&self, gpu: &Gpu, passes: &[Pass]) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        for p in passes {
            let attachments: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = p
                .targets
                .iter()
                .map(|v| {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(p.clear), store: wgpu::StoreOp::Store },
                    })
                })
                .collect();
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(p.label),
                color_attachments: &attachments,
                depth_stencil_attachment: p.depth.as_ref().map(|d| wgpu::RenderPassDepthStencilAttachment {
                    view: d,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let Some(d) = &p.draw else { continue };
            pass.set_pipeline(&d.pipeline);
            for (i, g) in d.groups.iter().enumerate() {
                pass.set_bind_group(i as u32, g, &[]);
            }
            if d.fullscreen {
                pass.draw(0..3, 0..1);
            }
            for (vb, ib, n) in &d.meshes {
                pass.set_vertex_buffer(0, vb.slice(..));
                pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*n, 0, 0..1);
            }
        }
        gpu.queue.submit([encoder.finish()]);
    }

    /// The composited linear radiance (Rgba32Uint holding f32 bits; w = 1 where a surface is).
    pub fn output(&self) -> wgpu::TextureView {
        view(&self.out)
    }

    /// Reads the composited linear radiance back: per pixel (RGB, covered).
    pub fn read(&self, gpu: &Gpu) -> Result<(Vec<Vec3>, Vec<bool>), GpuError> {
        let bytes = gpu.read_texture(&self.out, (self.width, self.height), 16)?;
        let texels: Vec<[f32; 4]> = bytes
            .chunks_exact(16)
            .map(|t| std::array::from_fn(|i| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]])))
            .collect();
        Ok((texels.iter().map(|t| Vec3::new(t[0], t[1], t[2])).collect(), texels.iter().map(|t| t[3] > 0.5).collect()))
    }
}
