//! Textures a glTF material names: decoded once (PNG or JPEG through `image`), kept linear, and
//! sampled by texture coordinates as glTF samples them by default — bilinear between texel
//! centres, repeating outside [0, 1], (0, 0) at the image's top-left corner.
//!
//! A base-colour texture is sRGB-encoded (glTF's rule) and decoded to linear; a
//! metallic-roughness texture is linear data (roughness in G, metallic in B).

use glam::{Vec2, Vec3};

/// A decoded texture: linear RGB texels, row-major from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
    /// Where it came from (a file or `NAME.gltf image N`), for messages.
    pub source: String,
}

/// The sRGB transfer function inverted: an 8-bit-range value in [0, 1] to linear.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

impl Texture {
    /// Decodes PNG or JPEG `bytes`; `srgb` says the values are sRGB-encoded colour (linearised)
    /// rather than data. The error names `source`.
    pub fn decode(bytes: &[u8], source: &str, srgb: bool) -> Result<Texture, String> {
        let image = image::load_from_memory(bytes).map_err(|e| format!("{source}: cannot decode: {e}"))?;
        let rgb = image.to_rgb32f();
        let (width, height) = rgb.dimensions();
        if width == 0 || height == 0 {
            return Err(format!("{source}: empty image"));
        }
        let texels = rgb
            .pixels()
            .map(|p| {
                let c = Vec3::new(p[0], p[1], p[2]).clamp(Vec3::ZERO, Vec3::ONE);
                if srgb { Vec3::new(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)) } else { c }
            })
            .collect();
        Ok(Texture { width, height, texels, source: source.into() })
    }

    /// Width and height in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The value at texture coordinates `uv`: bilinear between texel centres, repeating.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as f32, self.height as f32);
        let (x, y) = (uv.x * w - 0.5, uv.y * h - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: f32, n: u32| (i as i64).rem_euclid(i64::from(n)) as usize;
        let at = |i: f32, j: f32| self.texels[wrap(j, self.height) * self.width as usize + wrap(i, self.width)];
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }

    /// The mean texel.
    pub fn mean(&self) -> Vec3 {
        self.texels.iter().fold(Vec3::ZERO, |a, &t| a + t) / self.texels.len() as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) -> Vec<u8> {
        let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    #[test]
    fn sampling_is_bilinear_between_centres_and_repeats() {
        // 2×1: black then white, as data.
        let t = Texture::decode(&png(2, 1, |x, _| [255 * x as u8; 3]), "t", false).unwrap();
        assert_eq!(t.size(), (2, 1));
        assert!((t.sample(Vec2::new(0.25, 0.5)).x - 0.0).abs() < 1e-6);
        assert!((t.sample(Vec2::new(0.75, 0.5)).x - 1.0).abs() < 1e-6);
        assert!((t.sample(Vec2::new(0.5, 0.5)).x - 0.5).abs() < 1e-6);
        // Past the right edge it blends back to the left texel.
        assert!((t.sample(Vec2::new(1.0, 0.5)).x - 0.5).abs() < 1e-6);
        assert!((t.sample(Vec2::new(1.25, 0.5)).x - 0.0).abs() < 1e-6);
        assert!((t.mean().y - 0.5).abs() < 1e-6);
        // sRGB 188 is linear 0.5 (within 8-bit rounding).
        let s = Texture::decode(&png(1, 1, |_, _| [188, 188, 188]), "s", true).unwrap();
        assert!((s.mean().x - 0.5).abs() < 0.005, "{}", s.mean());
        let e = Texture::decode(b"not an image", "bad.png", true).unwrap_err();
        assert!(e.contains("bad.png"), "{e}");
    }
}
