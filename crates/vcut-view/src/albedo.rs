//! Albedo textures on the GPU: an object's base-colour texture uploaded as 8-bit sRGB texels and
//! sampled as the CPU renderer samples it ([`vcut_scene::texture::Texture::sample`]: bilinear
//! between texel centres, repeating, decoded to linear before filtering), one bind group per
//! object; an object without one binds a white texel.

use crate::gpu::Gpu;
use vcut_scene::texture::Texture;

/// The bind group layout: the texture (binding 0) and its sampler (binding 1).
pub(crate) fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("albedo"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// Bilinear, repeating, no mipmaps (as the CPU renderer samples).
pub(crate) fn sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("albedo"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// `texture` (white when `None`) uploaded and bound with `sampler`.
pub(crate) fn bind_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    sampler: &wgpu::Sampler,
    texture: Option<&Texture>,
) -> wgpu::BindGroup {
    let max = gpu.device.limits().max_texture_dimension_2d;
    let (width, height, srgb, texels) = match texture {
        Some(t) => fit(t, max),
        None => (1, 1, true, vec![[255; 4]]),
    };
    let format = if srgb { wgpu::TextureFormat::Rgba8UnormSrgb } else { wgpu::TextureFormat::Rgba8Unorm };
    let gpu_texture = gpu.texture_with("albedo", format, (width, height), bytemuck::cast_slice(&texels));
    let view = gpu_texture.create_view(&Default::default());
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("albedo"),
        layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(sampler) },
        ],
    })
}

/// The texture's RGBA texels, halved (2 × 2 box, in its own encoding) until both sides are at
/// most `max`: an adapter's size limit (2048 on some OpenGL ones).
fn fit(t: &Texture, max: u32) -> (u32, u32, bool, Vec<[u8; 4]>) {
    let (mut w, mut h) = t.size();
    let mut texels: Vec<[u8; 4]> = t.texels().iter().map(|c| [c[0], c[1], c[2], 255]).collect();
    while w > max.max(1) || h > max.max(1) {
        let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
        let at = |x: u32, y: u32| texels[(y.min(h - 1) * w + x.min(w - 1)) as usize];
        let halved = (0..nh)
            .flat_map(|y| (0..nw).map(move |x| (x, y)))
            .map(|(x, y)| {
                let q = [at(2 * x, 2 * y), at(2 * x + 1, 2 * y), at(2 * x, 2 * y + 1), at(2 * x + 1, 2 * y + 1)];
                std::array::from_fn(|c| ((q.iter().map(|p| u32::from(p[c])).sum::<u32>() + 2) / 4) as u8)
            })
            .collect();
        (texels, w, h) = (halved, nw, nh);
    }
    (w, h, t.is_srgb(), texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_texture_too_large_is_halved_until_it_fits() {
        let png = {
            let img = image::RgbImage::from_fn(5, 3, |x, _| image::Rgb([if x % 2 == 0 { 0 } else { 200 }, 10, 20]));
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::Png).unwrap();
            out.into_inner()
        };
        let t = Texture::decode(&png, "test", true).unwrap();
        let (w, h, srgb, texels) = fit(&t, 2);
        assert_eq!((w, h, srgb), (2, 1, true));
        // Columns 0–1 average 100; column 4 (the odd one out) stands with itself.
        assert_eq!(texels[0], [100, 10, 20, 255]);
        let (w, h, _, same) = fit(&t, 8);
        assert_eq!((w, h, same.len()), (5, 3, 15));
    }
}
