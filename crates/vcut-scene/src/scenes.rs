//! The built-in scenes, as scene descriptions (so they can be printed as TOML and edited).
//!
//! - `teapot`: the Utah teapot, a sphere and a ground plane under the built-in sky — 3 objects,
//!   11,564 vertices (teapot 8,257 + sphere 1,626 + ground 1,681), like the paper's Fig. 8 (11,565).
//! - `bunny`: the 35,947-vertex Stanford bunny (from the shared assets) on a 64×64-cell ground
//!   plane (4,225 vertices) — 2 objects, 39,059 vertices: the OBJ's 1,113 vertices that no face
//!   uses are dropped, which the paper's count (40,172 = 35,947 + 4,225) still included.
//! - `spheres`: two spheres over a plane — small, for tests.
//! - `showroom` (or `showroom:N`, N objects, default [`SHOWROOM_DEFAULT`], at most
//!   [`SHOWROOM_MAX`]): teapots, spheres, tori and boxes of mixed sizes, 3 units apart on a
//!   square grid over a ground plane, every one movable — the many-object scene of the scaling
//!   bench (about 530 vertices an object: N = 64 is 36,641 vertices with the ground).
//! - `assembly` (or `assembly:N`, as many objects as `showroom` takes): the showroom's objects
//!   [`ASSEMBLY_SPACING`] apart, where neighbours nearly touch — a dense arrangement, where
//!   every receiver sits next to the fields that shadow it.

use crate::desc::{CameraDesc, EnvironmentDesc, ObjectDesc, SceneDesc};
use crate::material::Material;

/// Names accepted by [`builtin`] (`showroom` and `assembly` also as `NAME:N`).
pub const BUILTIN_SCENES: [&str; 5] = ["teapot", "bunny", "spheres", "showroom", "assembly"];

/// Objects of `builtin:showroom` without a count.
pub const SHOWROOM_DEFAULT: usize = 16;
/// Most objects of `builtin:showroom:N`.
pub const SHOWROOM_MAX: usize = 1024;
/// Distance between neighbouring objects of the showroom.
pub const SHOWROOM_SPACING: f32 = 3.0;
/// Distance between neighbouring objects of the assembly: a little more than the showroom's
/// largest objects are across, so neighbours nearly touch without overlapping.
pub const ASSEMBLY_SPACING: f32 = 1.55;

/// The description of built-in scene `name`, if there is one.
pub fn builtin(name: &str) -> Option<SceneDesc> {
    for (prefix, spacing) in [("showroom", SHOWROOM_SPACING), ("assembly", ASSEMBLY_SPACING)] {
        if let Some(count) = name.strip_prefix(prefix) {
            let count = match count.strip_prefix(':') {
                None if count.is_empty() => SHOWROOM_DEFAULT,
                Some(n) => n.parse().ok().filter(|n| (1..=SHOWROOM_MAX).contains(n))?,
                None => return None,
            };
            return Some(grid(count, spacing));
        }
    }
    let ground = |size: f32, res: u32| ObjectDesc {
        name: Some("ground".into()),
        source: "builtin:plane".into(),
        size: Some(size),
        resolution: Some(res),
        material: Some(Material::lambert([0.5, 0.5, 0.5])),
        ..ObjectDesc::default()
    };
    match name {
        "teapot" => Some(SceneDesc {
            environment: EnvironmentDesc {
                sun_elevation_deg: 35.0,
                sun_azimuth_deg: 30.0,
                ..EnvironmentDesc::default()
            },
            objects: vec![
                ObjectDesc {
                    name: Some("teapot".into()),
                    source: "builtin:teapot".into(),
                    resolution: Some(TEAPOT_RESOLUTION),
                    moves: true,
                    material: Some(Material::blinn_phong([0.6, 0.45, 0.3], [0.35, 0.35, 0.35], 15.0)),
                    ..ObjectDesc::default()
                },
                ObjectDesc {
                    name: Some("sphere".into()),
                    source: "builtin:sphere".into(),
                    size: Some(1.0),
                    resolution: Some(SPHERE_RINGS),
                    translation: [-3.2, 1.0, 2.2],
                    moves: true,
                    material: Some(Material::blinn_phong([0.25, 0.4, 0.65], [0.4, 0.4, 0.4], 40.0)),
                    ..ObjectDesc::default()
                },
                ground(14.0, TEAPOT_GROUND_CELLS),
            ],
            cameras: vec![CameraDesc { position: [5.0, 6.0, 10.0], target: [0.0, 1.2, 0.0], ..CameraDesc::default() }],
            precompute: None,
        }),
        "bunny" => Some(SceneDesc {
            environment: EnvironmentDesc {
                sun_elevation_deg: 40.0,
                sun_azimuth_deg: 60.0,
                ..EnvironmentDesc::default()
            },
            objects: vec![
                ObjectDesc {
                    name: Some("bunny".into()),
                    source: "asset:meshes/stanford-bunny.obj".into(),
                    stand_height: Some(1.0),
                    moves: true,
                    material: Some(Material::blinn_phong([0.7, 0.65, 0.6], [0.25, 0.25, 0.25], 15.0)),
                    ..ObjectDesc::default()
                },
                ground(5.0, 64),
            ],
            cameras: vec![CameraDesc { position: [1.5, 1.6, 3.2], target: [0.0, 0.45, 0.0], ..CameraDesc::default() }],
            precompute: None,
        }),
        "spheres" => Some(SceneDesc {
            environment: EnvironmentDesc { resolution: 256, ..EnvironmentDesc::default() },
            objects: vec![
                ObjectDesc {
                    name: Some("ball".into()),
                    source: "builtin:sphere".into(),
                    resolution: Some(12),
                    translation: [0.0, 1.5, 0.0],
                    moves: true,
                    ..ObjectDesc::default()
                },
                ObjectDesc {
                    name: Some("small".into()),
                    source: "builtin:sphere".into(),
                    size: Some(0.5),
                    resolution: Some(8),
                    translation: [2.0, 0.5, 0.0],
                    ..ObjectDesc::default()
                },
                ground(8.0, 16),
            ],
            cameras: vec![CameraDesc { position: [0.0, 3.0, 8.0], target: [0.0, 0.8, 0.0], ..CameraDesc::default() }],
            precompute: None,
        }),
        _ => None,
    }
}

/// `builtin:showroom:COUNT`: `count` movable objects (teapots, spheres, tori and boxes in
/// turn, their sizes cycling through five factors so shapes and sizes mix) on a square grid
/// [`SHOWROOM_SPACING`] apart, over a ground plane 2 units wider than the grid on every side.
pub fn showroom(count: usize) -> SceneDesc {
    grid(count, SHOWROOM_SPACING)
}

/// `builtin:assembly:COUNT`: the showroom's objects [`ASSEMBLY_SPACING`] apart.
pub fn assembly(count: usize) -> SceneDesc {
    grid(count, ASSEMBLY_SPACING)
}

/// The showroom's objects on a square grid `spacing` apart.
fn grid(count: usize, spacing: f32) -> SceneDesc {
    let cols = (count as f64).sqrt().ceil().max(1.0) as usize;
    let rows = count.div_ceil(cols);
    let at = |i: usize, n: usize| (i as f32 - (n as f32 - 1.0) / 2.0) * spacing;
    let mut objects: Vec<ObjectDesc> = (0..count)
        .map(|i| {
            let (x, z) = (at(i % cols, cols), at(i / cols, rows));
            let f = [1.0, 0.8, 1.2, 0.9, 1.1][i % 5];
            let shade = [0.35 + 0.1 * (i % 4) as f32, 0.5 - 0.05 * (i % 3) as f32, 0.3 + 0.08 * (i % 5) as f32];
            let o = ObjectDesc { moves: true, ..ObjectDesc::default() };
            match i % 4 {
                0 => ObjectDesc {
                    name: Some(format!("teapot-{i}")),
                    source: "builtin:teapot".into(),
                    resolution: Some(5),
                    stand_height: Some(0.9 * f),
                    translation: [x, 0.0, z],
                    rotation_deg: [0.0, 40.0 * i as f32, 0.0],
                    material: Some(Material::blinn_phong(shade, [0.3; 3], 20.0)),
                    ..o
                },
                1 => ObjectDesc {
                    name: Some(format!("sphere-{i}")),
                    source: "builtin:sphere".into(),
                    size: Some(0.6 * f),
                    resolution: Some(16),
                    translation: [x, 0.6 * f, z],
                    material: Some(Material::blinn_phong(shade, [0.4; 3], 40.0)),
                    ..o
                },
                2 => ObjectDesc {
                    name: Some(format!("torus-{i}")),
                    source: "builtin:torus".into(),
                    size: Some(0.6 * f),
                    resolution: Some(12),
                    translation: [x, 0.18 * f, z],
                    material: Some(Material::lambert(shade)),
                    ..o
                },
                _ => ObjectDesc {
                    name: Some(format!("box-{i}")),
                    source: "builtin:box".into(),
                    size: Some(0.9 * f),
                    resolution: Some(7),
                    translation: [x, 0.45 * f, z],
                    rotation_deg: [0.0, 25.0 * i as f32, 0.0],
                    material: Some(Material::blinn_phong(shade, [0.2; 3], 10.0)),
                    ..o
                },
            }
        })
        .collect();
    let side = cols.max(rows) as f32 * spacing + 4.0;
    objects.push(ObjectDesc {
        name: Some("ground".into()),
        source: "builtin:plane".into(),
        size: Some(side),
        resolution: Some(((side * 2.5).round() as u32).max(16)),
        material: Some(Material::lambert([0.5, 0.5, 0.5])),
        ..ObjectDesc::default()
    });
    let reach = 0.5 * side;
    SceneDesc {
        environment: EnvironmentDesc { sun_elevation_deg: 40.0, sun_azimuth_deg: 30.0, ..EnvironmentDesc::default() },
        objects,
        cameras: vec![CameraDesc {
            position: [0.0, 0.9 * reach + 2.0, 1.6 * reach + 2.0],
            target: [0.0, 0.4, 0.0],
            ..CameraDesc::default()
        }],
        precompute: None,
    }
}

/// Teapot tessellation of the `teapot` scene (quads per patch edge).
pub const TEAPOT_RESOLUTION: u32 = 16;
/// Sphere rings of the `teapot` scene.
pub const SPHERE_RINGS: u32 = 29;
/// Ground cells per edge of the `teapot` scene.
pub const TEAPOT_GROUND_CELLS: u32 = 40;
