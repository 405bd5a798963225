//! Textures a glTF material names: decoded once (PNG or JPEG through `image`), kept linear, and
//! sampled by texture coordinates as glTF samples them by default — bilinear between texel
//! centres, repeating outside [0, 1], (0, 0) at the image's top-left corner.
//!
//! A base-colour texture is sRGB-encoded (glTF's rule) and decoded to linear; a
//! metallic-roughness texture is linear data (roughness in G, metallic in B). Texels are kept as
//! the 8 bits per channel the files hold (a 16-bit PNG is rounded to 8), so a texture stays
//! small in memory and in a `.vcuts` file ([`Texture::to_bytes`]) and decodes the same everywhere.

use crate::material::Material;
use glam::{Vec2, Vec3};

/// The factors of a glTF metallic-roughness material: what its textures multiply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PbrFactors {
    /// `baseColorFactor` (RGB, linear).
    pub base_colour: [f32; 3],
    /// `metallicFactor`.
    pub metallic: f32,
    /// `roughnessFactor` (perceptual).
    pub roughness: f32,
}

/// The textures of a glTF material that the BRDF parameters read, and the factors they multiply.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MaterialTextures {
    /// `baseColorTexture`, linear (decoded from sRGB).
    pub base_colour: Option<Texture>,
    /// `metallicRoughnessTexture`: roughness in G, metallic in B (linear).
    pub metallic_roughness: Option<Texture>,
    /// The material's factors, kept with a metallic-roughness texture (which needs them: glTF's
    /// mapping is not linear in metallic).
    pub factors: Option<PbrFactors>,
}

impl MaterialTextures {
    /// The BRDF parameters at texture coordinates `uv` of an object whose own material is
    /// `material`. With a metallic-roughness texture and its factors: glTF's mapping
    /// ([`Material::from_gltf_pbr`]) of base colour `factor × texture`, metallic and roughness
    /// `factor × texture` there. Otherwise `material`, its `kd` times the base-colour texture
    /// there (if any).
    pub fn material_at(&self, material: &Material, uv: Vec2) -> Material {
        match (&self.metallic_roughness, self.factors) {
            (Some(t), Some(f)) => {
                let base = self.base_colour.as_ref().map_or(Vec3::ONE, |t| t.sample(uv));
                let mr = t.sample(uv);
                let c = Vec3::from(f.base_colour) * base;
                Material::from_gltf_pbr(c.to_array(), f.metallic * mr.z, f.roughness * mr.y)
            }
            _ => self.base_colour_at(material, uv),
        }
    }

    /// `material` with its `kd` times the base-colour texture at `uv` (if any): what
    /// [`MaterialTextures::material_at`] gives without a metallic-roughness texture.
    pub fn base_colour_at(&self, material: &Material, uv: Vec2) -> Material {
        let base = self.base_colour.as_ref().map_or(Vec3::ONE, |t| t.sample(uv));
        Material { kd: (Vec3::from(material.kd) * base).to_array(), ..*material }
    }

    /// The diffuse albedo averaged over a mesh's vertices at coordinates `uvs` (`material`'s
    /// `kd` without them): one albedo for a renderer that takes one per object (the
    /// screen-space methods).
    pub fn mean_albedo(&self, material: &Material, uvs: Option<&[Vec2]>) -> Vec3 {
        match uvs {
            Some(uvs) if self.vary() && !uvs.is_empty() => {
                uvs.iter().map(|&uv| Vec3::from(self.material_at(material, uv).kd)).sum::<Vec3>() / uvs.len() as f32
            }
            _ => Vec3::from(material.kd),
        }
    }

    /// Whether the textures vary the material over a surface (given texture coordinates).
    pub fn vary(&self) -> bool {
        self.base_colour.is_some() || (self.metallic_roughness.is_some() && self.factors.is_some())
    }
}

/// A decoded texture: 8-bit RGB texels, row-major from the top, and whether they are
/// sRGB-encoded colour. Two textures are equal when their texels and encoding are, wherever they
/// came from.
#[derive(Debug, Clone)]
pub struct Texture {
    width: u32,
    height: u32,
    srgb: bool,
    texels: Vec<[u8; 3]>,
    /// Where it came from (a file or `NAME.gltf image N`), for messages.
    pub source: String,
}

impl PartialEq for Texture {
    fn eq(&self, other: &Texture) -> bool {
        (self.width, self.height, self.srgb) == (other.width, other.height, other.srgb) && self.texels == other.texels
    }
}

/// The linear value of each 8-bit sRGB level.
static SRGB_LEVELS: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|l| srgb_to_linear(l as f32 / 255.0)));

/// The sRGB transfer function inverted: an 8-bit-range value in [0, 1] to linear.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

impl Texture {
    /// Decodes PNG or JPEG `bytes`; `srgb` says the values are sRGB-encoded colour (linearised)
    /// rather than data. The error names `source`.
    pub fn decode(bytes: &[u8], source: &str, srgb: bool) -> Result<Texture, String> {
        let image = image::load_from_memory(bytes).map_err(|e| format!("{source}: cannot decode: {e}"))?;
        let rgb = image.to_rgb8();
        let (width, height) = rgb.dimensions();
        Self::from_texels(width, height, srgb, rgb.pixels().map(|p| p.0).collect(), source)
    }

    fn from_texels(width: u32, height: u32, srgb: bool, texels: Vec<[u8; 3]>, source: &str) -> Result<Texture, String> {
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return Err(format!("{source}: {} texels for a {width}×{height} image", texels.len()));
        }
        Ok(Texture { width, height, srgb, texels, source: source.into() })
    }

    /// The texture as bytes (little-endian width and height as u32, the sRGB flag as a byte, then
    /// the texels, 3 bytes each): what a `.vcuts` file stores.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(9 + 3 * self.texels.len());
        out.extend_from_slice(&self.width.to_le_bytes());
        out.extend_from_slice(&self.height.to_le_bytes());
        out.push(u8::from(self.srgb));
        out.extend(self.texels.iter().flatten());
        out
    }

    /// Reads what [`Texture::to_bytes`] wrote; errors name `source`.
    pub fn from_bytes(bytes: &[u8], source: &str) -> Result<Texture, String> {
        let short = || format!("{source}: a texture of {} bytes is truncated", bytes.len());
        let head = bytes.get(..9).ok_or_else(short)?;
        let width = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
        let height = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
        let srgb = match head[8] {
            0 => false,
            1 => true,
            f => return Err(format!("{source}: sRGB flag {f} is not 0 or 1")),
        };
        let body = &bytes[9..];
        let want = (width as usize).checked_mul(height as usize).and_then(|n| n.checked_mul(3));
        if want != Some(body.len()) {
            return Err(format!("{source}: {} texel bytes for a {width}×{height} texture", body.len()));
        }
        let texels = body.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Self::from_texels(width, height, srgb, texels, source)
    }

    fn linear(&self, t: [u8; 3]) -> Vec3 {
        if self.srgb {
            let l = &*SRGB_LEVELS;
            Vec3::new(l[t[0] as usize], l[t[1] as usize], l[t[2] as usize])
        } else {
            Vec3::new(f32::from(t[0]), f32::from(t[1]), f32::from(t[2])) / 255.0
        }
    }

    /// Width and height in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The texels as stored (8 bits per channel, row-major from the top).
    pub fn texels(&self) -> &[[u8; 3]] {
        &self.texels
    }

    /// Whether the texels are sRGB-encoded colour (else linear data).
    pub fn is_srgb(&self) -> bool {
        self.srgb
    }

    /// The linear value of 8-bit level `level` in this texture's encoding.
    pub fn level_value(&self, level: u8) -> f32 {
        if self.srgb { SRGB_LEVELS[level as usize] } else { f32::from(level) / 255.0 }
    }

    /// The value at texture coordinates `uv`: bilinear between texel centres, repeating.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as f32, self.height as f32);
        let (x, y) = (uv.x * w - 0.5, uv.y * h - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let wrap = |i: f32, n: u32| (i as i64).rem_euclid(i64::from(n)) as usize;
        let at =
            |i: f32, j: f32| self.linear(self.texels[wrap(j, self.height) * self.width as usize + wrap(i, self.width)]);
        let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
        let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }

    /// The mean texel.
    pub fn mean(&self) -> Vec3 {
        self.texels.iter().fold(Vec3::ZERO, |a, &t| a + self.linear(t)) / self.texels.len() as f32
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
        // Bytes round-trip; damaged ones are refused naming the source.
        assert_eq!(Texture::from_bytes(&s.to_bytes(), "s").unwrap(), s);
        assert_eq!(Texture::from_bytes(&t.to_bytes(), "t").unwrap(), t);
        let mut cut = t.to_bytes();
        cut.pop();
        assert!(Texture::from_bytes(&cut, "file section").unwrap_err().contains("file section"));
        assert!(Texture::from_bytes(&[0; 4], "x").is_err());
    }

    #[test]
    fn a_metallic_roughness_texture_varies_the_material_as_gltf_maps_it() {
        // Left texel: a rough dielectric (roughness 255, metallic 0); right: a smooth metal
        // (roughness 51, metallic 255). Base colour (0.5, 0.25, 1) by factor, white texture.
        let mr =
            Texture::decode(&png(2, 1, |x, _| if x == 0 { [0, 255, 0] } else { [0, 51, 255] }), "mr", false).unwrap();
        let textures = MaterialTextures {
            base_colour: None,
            metallic_roughness: Some(mr),
            factors: Some(PbrFactors { base_colour: [0.5, 0.25, 1.0], metallic: 1.0, roughness: 1.0 }),
        };
        assert!(textures.vary());
        let own = Material::lambert([0.1; 3]);
        let dielectric = textures.material_at(&own, Vec2::new(0.25, 0.5));
        assert_eq!(dielectric, Material::from_gltf_pbr([0.5, 0.25, 1.0], 0.0, 1.0));
        assert_eq!(dielectric.kd, [0.5, 0.25, 1.0]);
        let metal = textures.material_at(&own, Vec2::new(0.75, 0.5));
        assert_eq!(metal.kd, [0.0; 3]);
        assert_eq!(metal.ks, [0.5, 0.25, 1.0]);
        assert!((metal.roughness - 0.04).abs() < 1e-6, "α = (51/255)² = 0.04: {}", metal.roughness);
        // Halfway: glTF's mapping of the interpolated metallic and roughness.
        let half = textures.material_at(&own, Vec2::new(0.5, 0.5));
        assert!((half.kd[0] - 0.25).abs() < 1e-6 && (half.ks[0] - (0.02 + 0.25)).abs() < 1e-6, "{half:?}");
        // Without the factors (or the texture), only a base colour varies kd of the object's own.
        let base = Texture::decode(&png(1, 1, |_, _| [188, 188, 188]), "b", true).unwrap();
        let plain = MaterialTextures { base_colour: Some(base), ..Default::default() };
        let m = plain.material_at(&own, Vec2::ZERO);
        assert!((m.kd[0] - 0.05).abs() < 1e-3 && m.model == own.model, "{m:?}");
        assert!(!MaterialTextures::default().vary());
    }
}
