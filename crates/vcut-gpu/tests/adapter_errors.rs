//! What an adapter lacks is a `GpuError` naming the adapter and the missing capability, never a
//! panic: format checks, wgpu validation errors inside `Gpu::checked`, and errors raised
//! outside any scope (kept for `Gpu::take_errors`). Runs on whatever adapter there is (CI: the
//! Vulkan and the OpenGL one); skipped, saying so, without one.

use vcut_gpu::{GpuError, test_device as gpu};

/// A block-compressed format: sampled on many adapters, rendered to on none.
const NEVER_RENDERABLE: wgpu::TextureFormat = wgpu::TextureFormat::Bc1RgbaUnorm;

fn pipeline_into(gpu: &vcut_gpu::Gpu, format: wgpu::TextureFormat) -> wgpu::RenderPipeline {
    let shader = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("test"),
        source: wgpu::ShaderSource::Wgsl(
            "@vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }
             @fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(1.0); }"
                .into(),
        ),
    });
    gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("into an unrenderable format"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &shader,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &shader,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

#[test]
fn a_missing_capability_is_an_error_naming_the_adapter() {
    let Some(gpu) = gpu("a_missing_capability_is_an_error_naming_the_adapter") else { return };
    let adapter = gpu.describe();

    let e = gpu.require_format(NEVER_RENDERABLE, wgpu::TextureUsages::RENDER_ATTACHMENT, "draw leaves").unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, GpuError::Unsupported { .. }), "{e:?}");
    assert!(text.contains(&adapter) && text.contains("draw leaves") && text.contains("Bc1RgbaUnorm"), "{text}");
    // What every pass here needs is there.
    let packed = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
    gpu.require_format(wgpu::TextureFormat::Rgba32Uint, packed, "run SSDO").unwrap();

    // A validation error inside a checked scope: an error value, no panic.
    let e = gpu.checked("build a pipeline", || pipeline_into(&gpu, NEVER_RENDERABLE)).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, GpuError::Gpu { .. }), "{e:?}");
    assert!(text.contains(&adapter) && text.contains("failed to build a pipeline"), "{text}");
    assert!(text.contains("create_render_pipeline") && !text.contains('\n'), "{text}");
    // Nothing leaked past the scope; the device still works.
    gpu.take_errors("after the scope").unwrap();
    gpu.checked("build a pipeline", || pipeline_into(&gpu, wgpu::TextureFormat::Rgba8Unorm)).unwrap();

    // Outside any scope the error is kept (not a panic) and handed out once.
    let _ = pipeline_into(&gpu, NEVER_RENDERABLE);
    let e = gpu.take_errors("draw a frame").unwrap_err().to_string();
    assert!(e.contains("failed to draw a frame") && e.contains("create_render_pipeline"), "{e}");
    gpu.take_errors("again").unwrap();
}

/// An image is read back whole however many bands its read-back takes (a screenshot larger than
/// the device's largest buffer), and a size past the device's textures is refused naming it.
#[test]
fn an_image_reads_back_whole_in_bands() {
    let Some(gpu) = gpu("an_image_reads_back_whole_in_bands") else { return };
    let (w, h) = (37u32, 29u32);
    let texels: Vec<u8> = (0..w * h * 4).map(|i| (i * 7 % 251) as u8).collect();
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("pattern"),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    gpu.queue.write_texture(
        texture.as_image_copy(),
        &texels,
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: Some(h) },
        wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
    );
    assert_eq!(gpu.read_texture(&texture, (w, h), 4).unwrap(), texels, "one band");
    for rows in [1u32, 3, 28] {
        let band = u64::from(rows) * u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        assert_eq!(gpu.read_texture_in_bands(&texture, (w, h), 4, band).unwrap(), texels, "{rows} rows a band");
    }
    let max = gpu.device.limits().max_texture_dimension_2d;
    gpu.check_target((max, 1), "--width").unwrap();
    let e = gpu.check_target((1, max + 1), "--height").unwrap_err().to_string();
    assert!(e.contains(&gpu.describe()) && e.contains("--height") && e.contains(&max.to_string()), "{e}");
}
