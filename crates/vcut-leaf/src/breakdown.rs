//! Where the two passes' error comes from: the frame and the path-traced reference split by
//! light path — the sun alone and the environment alone, each whole and unscattered (direct) —
//! and by material — the same with every leaf's gloss removed from the scene (matte) — so a
//! user sees which part of the renderer to spend on.
//!
//! Each part renders the frame with only that light (the environment's SH zeroed, or the sun
//! left out; the transfer's indirect part zeroed for a direct part) and traces the reference with
//! only that light (`depth` 0 for a direct part). The parts' errors do not add up to the whole:
//! the sun's and the environment's errors partly cancel.

use crate::reference::{ReferenceParams, reference, rel_l2};
use crate::scene::LeafScene;
use crate::sh::COEFFS;
use crate::shade::{LeafData, Lighting, Shader, SunMethod, TwoSided};
use glam::Vec3;
use vcut_envmap::EnvMap;

/// One light path's error.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// `sun`, `sun_direct`, `sun_direct_on_grid` (the sun moved onto the nearest direction the
    /// maps were computed for: what the maps err without blending), `environment`,
    /// `environment_direct`, and with every leaf's gloss removed from the frame and the reference
    /// (the scene rebuilt; the transfer does not depend on gloss) `environment_matte`,
    /// `environment_direct_matte`, `sun_matte`.
    pub name: &'static str,
    /// The part's relative L2 error against its own reference.
    pub rel_l2: f64,
    /// The part's error as a share of the whole reference's norm (what it adds to the whole).
    pub share_of_whole: f64,
    /// The part's reference norm over the whole's.
    pub weight: f64,
}

/// The frame's error per light path at `vertices`, seen from `eye`, against references traced
/// with `params` under `light` (its sun) and `env_without_sun`; `whole` is the reference with
/// all the light (at the same vertices). Eight more references: the cost of eight
/// [`reference`] calls.
pub fn breakdown(
    scene: &LeafScene,
    data: &LeafData,
    (light, env_without_sun): (&Lighting, &EnvMap),
    eye: Vec3,
    (vertices, whole): (&[usize], &[TwoSided]),
    params: &ReferenceParams,
) -> Result<Vec<Part>, crate::rle::RleError> {
    let mut direct_only = data.clone();
    for t in &mut direct_only.transfer.indirect {
        *t = [[Vec3::ZERO; COEFFS]; 2];
    }
    let sun_only = Lighting { env: [Vec3::ZERO; COEFFS], ..light.clone() };
    let env_only = Lighting { sun: None, sun_sh: [Vec3::ZERO; COEFFS], ..light.clone() };
    let black = EnvMap::constant([0.0; 3]);
    let matte = matte(scene);
    let frame_in = |scene: &LeafScene, l: &Lighting, d: &LeafData| -> Result<Vec<TwoSided>, crate::rle::RleError> {
        let mut shader = Shader::new();
        shader.prepare(scene, &d.lvc, l)?;
        let mut out = Vec::new();
        shader.shade(scene, d, l, SunMethod::Lvc, eye, &mut out);
        Ok(vertices.iter().map(|&v| out[v]).collect())
    };
    let frame = |l: &Lighting, d: &LeafData| frame_in(scene, l, d);
    let traced_in = |scene: &LeafScene, env: &EnvMap, sun: Option<crate::shade::SunLight>, depth: u32| {
        let p = ReferenceParams { depth, ..*params };
        reference(scene, env, sun, eye, vertices, &p).radiance
    };
    let traced = |env: &EnvMap, sun: Option<crate::shade::SunLight>, depth: u32| traced_in(scene, env, sun, depth);
    let on_grid =
        sun_only.with_sun_dir(data.lvc.directions().direction(light.sun.map_or(0, |s| data.lvc.sun_index(s.dir))));
    let norm = |x: &[TwoSided]| x.iter().flatten().map(|c| f64::from(c.length_squared())).sum::<f64>().sqrt();
    let whole = norm(whole);
    let parts = [
        ("sun", frame(&sun_only, data)?, traced(&black, light.sun, params.depth)),
        ("sun_direct", frame(&sun_only, &direct_only)?, traced(&black, light.sun, 0)),
        ("sun_direct_on_grid", frame(&on_grid, &direct_only)?, traced(&black, on_grid.sun, 0)),
        ("environment", frame(&env_only, data)?, traced(env_without_sun, None, params.depth)),
        ("environment_direct", frame(&env_only, &direct_only)?, traced(env_without_sun, None, 0)),
        (
            "environment_matte",
            frame_in(&matte, &env_only, data)?,
            traced_in(&matte, env_without_sun, None, params.depth),
        ),
        (
            "environment_direct_matte",
            frame_in(&matte, &env_only, &direct_only)?,
            traced_in(&matte, env_without_sun, None, 0),
        ),
        ("sun_matte", frame_in(&matte, &sun_only, data)?, traced_in(&matte, &black, light.sun, params.depth)),
    ];
    Ok(parts
        .into_iter()
        .map(|(name, got, want)| {
            let diff: Vec<TwoSided> = got.iter().zip(&want).map(|(a, b)| [a[0] - b[0], a[1] - b[1]]).collect();
            Part {
                name,
                rel_l2: rel_l2(&got, &want),
                share_of_whole: norm(&diff) / whole.max(f64::MIN_POSITIVE),
                weight: norm(&want) / whole.max(f64::MIN_POSITIVE),
            }
        })
        .collect())
}

/// `scene` with every leaf's gloss removed.
pub fn matte(scene: &LeafScene) -> LeafScene {
    let objects = scene
        .objects()
        .iter()
        .cloned()
        .map(|mut o| {
            if let crate::scene::Surface::Leaf(m) = &mut o.surface {
                m.gloss = [crate::material::Gloss::NONE; 2];
            }
            o
        })
        .collect();
    LeafScene::new(objects).expect("the scene's own objects")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lvc::{Lvc, LvcParams};
    use crate::prt::{PrtParams, Transfer};
    use crate::scene::{LeafObject, Surface};
    use vcut_scene::{Mesh, MeshOptions};

    #[test]
    fn the_parts_are_named_weighed_and_on_grid_when_the_sun_is() {
        let pos = vec![
            Vec3::new(-0.5, 0.0, -0.5),
            Vec3::new(0.5, 0.0, -0.5),
            Vec3::new(0.5, 0.0, 0.5),
            Vec3::new(-0.5, 0.0, 0.5),
        ];
        let mesh = Mesh::build(pos, None, vec![[0, 2, 1], [0, 3, 2]], MeshOptions::default()).unwrap().0;
        let leaf = LeafObject { name: "leaf".into(), mesh, uv: None, surface: Surface::Leaf(Box::default()) };
        let scene = LeafScene::new(vec![leaf]).unwrap();
        let lvc =
            Lvc::compute(&scene, &LvcParams { resolution: 4, disk_samples: 4, ..LvcParams::default() }, |_, _| {});
        // The sun on a direction the maps were computed for: on the grid already.
        let sun_dir = lvc.directions().direction(lvc.sun_index(Vec3::new(0.3, 1.0, 0.2)));
        let data =
            LeafData::new(lvc, Transfer::compute(&scene, &PrtParams { rays: 16, ..PrtParams::default() }, |_, _| {}))
                .unwrap();
        let env = EnvMap::constant([0.2; 3]);
        let light = Lighting::new(&env, Some(crate::shade::SunLight { dir: sun_dir, irradiance: Vec3::splat(3.0) }));
        let eye = Vec3::new(0.5, 2.0, 1.0);
        let vertices: Vec<usize> = (0..scene.vertex_count()).collect();
        let params = ReferenceParams { paths: 64, ..ReferenceParams::default() };
        let whole = reference(&scene, &env, light.sun, eye, &vertices, &params).radiance;
        let parts = breakdown(&scene, &data, (&light, &env), eye, (&vertices, &whole), &params).unwrap();
        let names: Vec<&str> = parts.iter().map(|p| p.name).collect();
        assert_eq!(
            names,
            [
                "sun",
                "sun_direct",
                "sun_direct_on_grid",
                "environment",
                "environment_direct",
                "environment_matte",
                "environment_direct_matte",
                "sun_matte"
            ]
        );
        for p in &parts {
            assert!(p.rel_l2.is_finite() && p.weight > 0.0 && p.weight < 1.5, "{p:?}");
            assert!((p.share_of_whole - p.rel_l2 * p.weight).abs() < 1e-9, "{p:?}");
        }
        assert_eq!(parts[2], Part { name: "sun_direct_on_grid", ..parts[1].clone() });
        // The sun carries most of the light here (3 against a 0.2 sky).
        assert!(parts[0].weight > parts[3].weight, "{parts:?}");
        // Without gloss a leaf sends less light toward the eye: its parts weigh less.
        assert!(parts[5].weight < parts[3].weight && parts[7].weight < parts[0].weight, "{parts:?}");
    }
}
