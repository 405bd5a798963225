//! SSDO and SSAO on scenes whose answer is known: an open plane, a deep crease lit from either
//! side, a red wall over a white floor, and a ball on the ground against the ray-traced reference.

mod common;
use common::rect;
use glam::Vec3;
use vcut_envmap::{EnvMap, InvalidTexels, Layout};
use vcut_scene::Camera;
use vcut_ssdo::{GBuffer, Lighting, Method, Object, Params, ReferenceParams, SampleSets, reference, rel_l2, render};

fn camera(position: Vec3, target: Vec3) -> Camera {
    Camera { name: "test".into(), position, target, up: Vec3::Y, fov_y_deg: 40.0 }
}

/// A lat-long map of radiance `f(direction)`.
fn env(f: impl Fn(Vec3) -> f32) -> EnvMap {
    let layout = Layout::LatLong { width: 256, height: 128 };
    let mut texels = vec![[0.0f32; 3]; layout.texel_count()];
    layout.for_each_patch(1, |t, d, _| texels[t] = [f(d); 3]);
    EnvMap::new(layout, texels, "test", InvalidTexels::Reject).unwrap().0
}

fn mean(v: impl Iterator<Item = Vec3>) -> Vec3 {
    let (mut s, mut n) = (Vec3::ZERO, 0.0);
    for x in v {
        s += x;
        n += 1.0;
    }
    s / n
}

#[test]
fn a_plane_with_nothing_above_it_is_unoccluded_and_gets_the_whole_sky() {
    let ground =
        rect(Vec3::new(-2.0, 0.0, 2.0), Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -4.0), 4, Vec3::splat(0.5));
    let objects = [ground];
    let g = GBuffer::new(&objects, &camera(Vec3::new(0.0, 2.0, 2.5), Vec3::ZERO), 96, 72);
    assert!(g.covered() > 96 * 72 / 2);
    let light = Lighting::new(&EnvMap::constant([2.0; 3]), &objects, 16);
    assert!(light.sun.is_none());
    let p = Params::for_scene(2.0);
    let sets = SampleSets::halton(p.samples, p.sets);
    let ssao = render(&g, &light, &sets, &p, Method::Ssao);
    let ssdo = render(&g, &light, &sets, &p, Method::Ssdo);
    assert!(ssdo.occlusion.iter().all(|&o| o == 0.0), "no sample is occluded");
    assert!(ssdo.indirect.iter().all(|&c| c == Vec3::ZERO));
    // Under constant L the diffuse answer is ρ·L = 1 (SSAO: exactly, from the irradiance map;
    // SSDO: the 16-sample estimate of the same integral, blurred).
    let covered =
        |o: &vcut_ssdo::Output| o.direct.clone().into_iter().zip(o.covered.clone()).filter(|x| x.1).map(|x| x.0);
    for c in covered(&ssao) {
        assert!((c - Vec3::ONE).abs().max_element() < 0.01, "ssao {c}");
    }
    let m = mean(covered(&ssdo));
    assert!((m - Vec3::ONE).abs().max_element() < 0.05, "ssdo mean {m}");
    let r = reference(&objects, &g, &light, &ReferenceParams { pixel_rays: 16, vertex_rays: 16 });
    assert!(rel_l2(&ssao.total(), &r.total(), &r.covered) < 0.01);
}

/// A deep V crease along z: walls 70° from the ground meeting at the origin.
fn crease() -> Vec<Object> {
    let a = 70f32.to_radians();
    let (c, s) = (a.cos(), a.sin());
    let len = 1.0;
    // Left wall rises toward −x, right toward +x; both span z ∈ [−2, 2].
    let left =
        rect(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -4.0), Vec3::new(-c, s, 0.0) * len, 8, Vec3::splat(0.7));
    let right =
        rect(Vec3::new(0.0, 0.0, -2.0), Vec3::new(0.0, 0.0, 4.0), Vec3::new(c, s, 0.0) * len, 8, Vec3::splat(0.7));
    vec![left, right]
}

#[test]
fn a_crease_is_darker_with_ssdo_than_ssao_only_where_the_light_comes_from_the_occluded_side() {
    let objects = crease();
    // Look down into the crease from above.
    let g = GBuffer::new(&objects, &camera(Vec3::new(0.0, 3.0, 0.01), Vec3::ZERO), 80, 80);
    let mut p = Params::for_scene(1.0);
    p.radius = 0.5;
    p.depth_limit = 0.5;
    p.indirect = false;
    let sets = SampleSets::halton(p.samples, p.sets);
    // Pixels on the left wall's lower part: x in (−0.2, −0.05).
    let on_left_low = |k: usize| g.first[k].is_some_and(|s| s.position.x > -0.2 && s.position.x < -0.05);
    let pixels: Vec<usize> = (0..g.first.len()).filter(|&k| on_left_low(k)).collect();
    assert!(pixels.len() > 20);
    let mean_at = |o: &vcut_ssdo::Output| mean(pixels.iter().map(|&k| o.direct[k])).x;
    // Light low from +x: the right wall stands in its way.
    let side = env(|d| 0.05 + 40.0 * d.dot(Vec3::new(1.0, 0.2, 0.0).normalize()).max(0.0).powi(32));
    // Light from straight above: the crease is open to it.
    let above = env(|d| 0.05 + 40.0 * d.y.max(0.0).powi(32));
    let mut results = Vec::new();
    for map in [&side, &above] {
        let light = Lighting::new(map, &objects, p.samples);
        assert!(light.sun.is_none(), "broad lobes, no sun split off");
        let ssao = render(&g, &light, &sets, &p, Method::Ssao);
        let ssdo = render(&g, &light, &sets, &p, Method::Ssdo);
        results.push((mean_at(&ssdo), mean_at(&ssao)));
    }
    let (side_ssdo, side_ssao) = results[0];
    let (above_ssdo, above_ssao) = results[1];
    // Partly: SSDO's visibility is that of sample points within r_max, so a direction counts as
    // blocked only where its sample lands behind the far wall.
    assert!(side_ssdo < 0.8 * side_ssao, "light from the occluded side: ssdo {side_ssdo} vs ssao {side_ssao}");
    assert!(above_ssdo >= above_ssao, "light from the open side: ssdo {above_ssdo} vs ssao {above_ssao}");
}

#[test]
fn a_red_wall_bleeds_red_onto_a_white_floor_in_the_indirect_term() {
    let floor =
        rect(Vec3::new(0.0, 0.0, 2.0), Vec3::new(3.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -4.0), 8, Vec3::splat(0.8));
    let wall = rect(
        Vec3::new(0.0, 0.0, -2.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.0, 0.0, 4.0),
        8,
        Vec3::new(0.9, 0.05, 0.05),
    );
    let objects = [floor, wall];
    let g = GBuffer::new(&objects, &camera(Vec3::new(3.0, 1.5, 0.0), Vec3::new(0.5, 0.3, 0.0)), 96, 72);
    let light = Lighting::new(&EnvMap::constant([1.0; 3]), &objects, 16);
    let mut p = Params::for_scene(2.0);
    p.radius = 0.6;
    p.depth_limit = 0.6;
    let sets = SampleSets::halton(p.samples, p.sets);
    let ssdo = render(&g, &light, &sets, &p, Method::Ssdo);
    let near_wall: Vec<usize> = (0..g.first.len())
        .filter(|&k| g.first[k].is_some_and(|s| s.object == 0 && s.position.x < 0.3 && s.position.z.abs() < 1.5))
        .collect();
    assert!(near_wall.len() > 20);
    let bleed = mean(near_wall.iter().map(|&k| ssdo.indirect[k]));
    assert!(bleed.x > 0.0 && bleed.x > 3.0 * bleed.y && bleed.x > 3.0 * bleed.z, "indirect near the wall {bleed}");
    let far: Vec<usize> =
        (0..g.first.len()).filter(|&k| g.first[k].is_some_and(|s| s.object == 0 && s.position.x > 1.5)).collect();
    assert!(far.len() > 20);
    let far_bleed = mean(far.iter().map(|&k| ssdo.indirect[k]));
    assert!(far_bleed.x < 0.2 * bleed.x, "it fades away from the wall: {far_bleed} vs {bleed}");
    // The reference agrees that the floor near the wall gets red light.
    let r = reference(&objects, &g, &light, &ReferenceParams { pixel_rays: 64, vertex_rays: 64 });
    let ref_bleed = mean(near_wall.iter().map(|&k| r.indirect[k]));
    assert!(ref_bleed.x > 3.0 * ref_bleed.y, "{ref_bleed}");
}

#[test]
fn ssdo_is_nearer_the_reference_than_ssao_and_peeling_changes_the_classification() {
    // A ball over the ground under the sky with its sun.
    let mut objects = vec![rect(
        Vec3::new(-2.0, 0.0, 2.0),
        Vec3::new(4.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -4.0),
        16,
        Vec3::splat(0.6),
    )];
    let ball = vcut_scene::shapes::sphere(0.5, 32, 16).unwrap();
    objects.push(Object::from_mesh(&ball, Vec3::new(0.0, 0.55, 0.0), Vec3::new(0.7, 0.5, 0.3)));
    let sky = vcut_envmap::procedural::PreethamSky::default().bake(512);
    let g = GBuffer::new(&objects, &camera(Vec3::new(2.0, 1.6, 2.4), Vec3::new(0.0, 0.3, 0.0)), 120, 90);
    let light = Lighting::new(&sky, &objects, 16);
    assert!(light.sun.is_some());
    let mut p = Params::for_scene(2.0);
    p.radius = 0.4;
    p.depth_limit = 0.4;
    let sets = SampleSets::halton(p.samples, p.sets);
    let r = reference(&objects, &g, &light, &ReferenceParams { pixel_rays: 64, vertex_rays: 64 }).total();
    let covered: Vec<bool> = g.first.iter().map(Option::is_some).collect();
    let e_ao = rel_l2(&render(&g, &light, &sets, &p, Method::Ssao).total(), &r, &covered);
    let ssdo = render(&g, &light, &sets, &p, Method::Ssdo);
    let e_do = rel_l2(&ssdo.total(), &r, &covered);
    assert!(e_do < e_ao, "ssdo {e_do} vs ssao {e_ao}");
    p.peel = true;
    let peeled = render(&g, &light, &sets, &p, Method::Ssdo);
    assert_ne!(peeled.occlusion, ssdo.occlusion, "the second layer reclassifies some samples");
    assert!(g.second.iter().any(Option::is_some));
}
