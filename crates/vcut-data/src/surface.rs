//! The `surface` section (one per object that has any, `a` = object): what shades it per pixel
//! beyond its BRDF parameters — its texture coordinates and its glTF material's textures. A file
//! written before the section existed has none, and its objects shade as before.
//!
//! Little-endian: the vertex count (u32); a flags byte (1: texture coordinates, 2: base colour,
//! 4: metallic-roughness, 8: glTF factors); the coordinates (two f32 per vertex); the factors
//! (base colour RGB, metallic, roughness: five f32); each texture present as its byte length
//! (u32) and [`Texture::to_bytes`].

use crate::sections::{Cursor, PayloadError};
use glam::Vec2;
use vcut_scene::Mesh;
use vcut_scene::loaders::MaterialTextures;
use vcut_scene::texture::{PbrFactors, Texture};

/// The payload for `mesh` with `textures`; `None` when it has neither coordinates nor textures.
pub fn encode(mesh: &Mesh, textures: &MaterialTextures) -> Option<Vec<u8>> {
    let slots = [&textures.base_colour, &textures.metallic_roughness];
    if mesh.uvs().is_none() && slots.iter().all(|t| t.is_none()) {
        return None;
    }
    let mut out = Vec::new();
    out.extend_from_slice(&(mesh.vertex_count() as u32).to_le_bytes());
    let flags = u8::from(mesh.uvs().is_some())
        | slots.iter().enumerate().map(|(k, t)| u8::from(t.is_some()) << (k + 1)).sum::<u8>()
        | u8::from(textures.factors.is_some()) << 3;
    out.push(flags);
    for uv in mesh.uvs().unwrap_or_default() {
        out.extend_from_slice(&uv.x.to_le_bytes());
        out.extend_from_slice(&uv.y.to_le_bytes());
    }
    if let Some(f) = textures.factors {
        for x in [f.base_colour[0], f.base_colour[1], f.base_colour[2], f.metallic, f.roughness] {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    for t in slots.into_iter().flatten() {
        let bytes = t.to_bytes();
        out.extend_from_slice(&(bytes.len() as u32).to_le_bytes());
        out.extend_from_slice(&bytes);
    }
    Some(out)
}

/// Reads a payload [`encode`] wrote for a mesh of `vertices` vertices.
pub fn decode(bytes: &[u8], vertices: usize) -> Result<(Option<Vec<Vec2>>, MaterialTextures), PayloadError> {
    let mut r = Cursor::new(bytes);
    let n = r.u32()? as usize;
    if n != vertices {
        return Err(PayloadError::Inconsistent(format!("surface of {n} vertices for a mesh of {vertices}")));
    }
    let flags = r.u8()?;
    if flags > 15 {
        return Err(PayloadError::UnknownCode { what: "surface flags", code: u32::from(flags) });
    }
    let uvs = if flags & 1 == 1 {
        let need = n.checked_mul(8).ok_or(PayloadError::Truncated { at: 5, need: usize::MAX })?;
        let raw = r.take(need)?;
        let uvs: Vec<Vec2> = raw
            .chunks_exact(8)
            .map(|c| {
                Vec2::new(f32::from_le_bytes([c[0], c[1], c[2], c[3]]), f32::from_le_bytes([c[4], c[5], c[6], c[7]]))
            })
            .collect();
        if let Some(uv) = uvs.iter().find(|uv| !uv.is_finite()) {
            return Err(PayloadError::Inconsistent(format!("texture coordinates {uv} are not finite")));
        }
        Some(uvs)
    } else {
        None
    };
    let factors = if flags & 8 == 8 {
        let mut x = [0f32; 5];
        for v in &mut x {
            *v = f32::from_le_bytes(r.take(4)?.try_into().expect("4 bytes"));
        }
        if !x.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)) {
            return Err(PayloadError::Inconsistent(format!("glTF factors {x:?} are not all in [0, 1]")));
        }
        Some(PbrFactors { base_colour: [x[0], x[1], x[2]], metallic: x[3], roughness: x[4] })
    } else {
        None
    };
    let mut texture = |bit: u8, what: &str| -> Result<Option<Texture>, PayloadError> {
        if flags & bit == 0 {
            return Ok(None);
        }
        let len = r.u32()? as usize;
        Texture::from_bytes(r.take(len)?, what).map(Some).map_err(PayloadError::Inconsistent)
    };
    let base_colour = texture(2, "base colour texture")?;
    let metallic_roughness = texture(4, "metallic-roughness texture")?;
    if r.rest() != 0 {
        return Err(PayloadError::Inconsistent(format!("{} bytes after the surface", r.rest())));
    }
    Ok((uvs, MaterialTextures { base_colour, metallic_roughness, factors }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use vcut_scene::MeshOptions;

    #[test]
    fn surfaces_round_trip_and_damage_is_refused() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
        let uv = vec![Vec2::ZERO, Vec2::X, Vec2::new(0.25, 3.5)];
        let (mesh, _) =
            Mesh::build_with_uvs(p.clone(), None, Some(uv.clone()), vec![[0, 2, 1]], MeshOptions::default()).unwrap();
        // A 2×1 sRGB texture: width, height, flag, texels.
        let texture = Texture::from_bytes(&[2, 0, 0, 0, 1, 0, 0, 0, 1, 10, 20, 30, 200, 210, 220], "t").unwrap();
        let textures = MaterialTextures { base_colour: Some(texture.clone()), ..Default::default() };
        let bytes = encode(&mesh, &textures).unwrap();
        let (got_uv, got_t) = decode(&bytes, 3).unwrap();
        assert_eq!(got_uv.as_deref(), mesh.uvs());
        assert_eq!(got_t, textures);
        // With a metallic-roughness texture and its factors.
        let factors = PbrFactors { base_colour: [0.5, 0.25, 1.0], metallic: 1.0, roughness: 0.75 };
        let full = MaterialTextures {
            base_colour: Some(texture.clone()),
            metallic_roughness: Some(texture),
            factors: Some(factors),
        };
        let full_bytes = encode(&mesh, &full).unwrap();
        assert_eq!(decode(&full_bytes, 3).unwrap().1, full);
        // A factor out of range (metallic 2) is refused.
        let mut bad = full_bytes.clone();
        bad[5 + 24 + 12..5 + 24 + 16].copy_from_slice(&2f32.to_le_bytes());
        assert!(decode(&bad, 3).unwrap_err().to_string().contains("factors"), "{:?}", decode(&bad, 3));
        // Nothing to store: no section.
        let (plain, _) = Mesh::build(p, None, vec![[0, 2, 1]], MeshOptions::default()).unwrap();
        assert!(encode(&plain, &MaterialTextures::default()).is_none());
        // The wrong mesh, a cut payload, unknown flags, trailing bytes.
        assert!(decode(&bytes, 4).unwrap_err().to_string().contains("mesh of 4"));
        assert!(decode(&bytes[..bytes.len() - 1], 3).is_err());
        let mut flags = bytes.clone();
        flags[4] = 17;
        assert!(decode(&flags, 3).is_err());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode(&longer, 3).unwrap_err().to_string().contains("after the surface"));
    }
}
