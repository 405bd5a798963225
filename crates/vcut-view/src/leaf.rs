//! The leaf viewer's state: a plant precomputed by `vcut-leaf` (LVC maps and SH transfer), the
//! editable leaf material and sun, the orbit camera, and the two-sided radiance of the last
//! frame. Every edit the leaf panel offers is a method here, so tests drive the same code.

use crate::camera::OrbitCamera;
use glam::Vec3;
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_leaf::lod::{Lod, LodParams, Selection};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::rle::RleError;
use vcut_leaf::scene::{LeafScene, Surface};
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod, TwoSided, sun_direction};

/// The cost of the last frame's parts, milliseconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LeafTimings {
    /// Decoding the sun direction's map (0 when the direction did not change).
    pub decode_ms: f64,
    /// Shading both sides of the vertices drawn.
    pub shade_ms: f64,
    /// Recomputing the vertices' scattering after a material edit.
    pub material_ms: f64,
    /// Uploading vertices to the GPU.
    pub upload_ms: f64,
    /// Drawing.
    pub draw_ms: f64,
}

/// What the leaf viewer shows.
pub struct LeafSession {
    scene: LeafScene,
    data: LeafData,
    lod: Lod,
    shader: Shader,
    base: Lighting,
    lighting: Lighting,
    env: EnvMap,
    material: LeafMaterial,
    sun: (f32, f32),
    method: SunMethod,
    /// Level of detail per leaf by screen size (else every leaf in full).
    pub lod_enabled: bool,
    /// The camera.
    pub camera: OrbitCamera,
    /// Fixed exposure, or `None` for automatic.
    pub exposure: Option<f32>,
    auto_exposure: f32,
    selection: Selection,
    radiance: Vec<TwoSided>,
    version: u64,
    dirty: bool,
    /// Cost of the last frame.
    pub timings: LeafTimings,
}

impl LeafSession {
    /// A session on `scene` with its precomputed `data` under `env` (its sun split off), seen by
    /// `camera`; the panel edits the material of the scene's first leaf object (and gives it to
    /// every leaf object).
    pub fn new(scene: LeafScene, data: LeafData, env: EnvMap, camera: OrbitCamera) -> LeafSession {
        let material = scene
            .objects()
            .iter()
            .find_map(|o| match &o.surface {
                Surface::Leaf(m) => Some((**m).clone()),
                Surface::Opaque(_) => None,
            })
            .unwrap_or_default();
        let (base, _) = Lighting::from_map(&env);
        let sun = base.sun.map_or((45.0, 0.0), |s| {
            (s.dir.y.clamp(-1.0, 1.0).asin().to_degrees(), s.dir.x.atan2(s.dir.z).to_degrees())
        });
        let lod = Lod::build(&scene, &data.transfer, &LodParams::default());
        let mut session = LeafSession {
            scene,
            data,
            lod,
            shader: Shader::new(),
            lighting: base.clone(),
            base,
            env,
            material,
            sun,
            method: SunMethod::Lvc,
            lod_enabled: false,
            camera,
            exposure: None,
            auto_exposure: 1.0,
            selection: Selection::default(),
            radiance: Vec::new(),
            version: 0,
            dirty: true,
            timings: LeafTimings::default(),
        };
        session.set_sun(sun.0, sun.1);
        session
    }

    /// The plant.
    pub fn scene(&self) -> &LeafScene {
        &self.scene
    }

    /// The environment drawn behind (the whole map, sun included).
    pub fn env(&self) -> &EnvMap {
        &self.env
    }

    /// The precomputed maps and transfer.
    pub fn data(&self) -> &LeafData {
        &self.data
    }

    /// The leaves' material.
    pub fn material(&self) -> &LeafMaterial {
        &self.material
    }

    /// Gives every leaf object `material` (R, T and gloss change at once; the bounced light keeps
    /// the precompute's parameters).
    pub fn set_material(&mut self, material: LeafMaterial) {
        let start = Instant::now();
        let names: Vec<String> = self
            .scene
            .objects()
            .iter()
            .filter(|o| matches!(o.surface, Surface::Leaf(_)))
            .map(|o| o.name.clone())
            .collect();
        for name in names {
            self.scene.set_surface(&name, Surface::Leaf(Box::new(material.clone())));
        }
        self.material = material;
        // Coarse levels average the scattering: build them again.
        self.lod = Lod::build(&self.scene, &self.data.transfer, &LodParams::default());
        self.timings.material_ms = start.elapsed().as_secs_f64() * 1e3;
        self.dirty = true;
    }

    /// Rays per shadow-edge vertex toward the true sun when the sun moves
    /// ([`Shader::edge_rays`]).
    pub fn edge_rays(&self) -> u32 {
        self.shader.edge_rays()
    }

    /// Sets [`LeafSession::edge_rays`] (0: the maps around the sun blended only).
    pub fn set_edge_rays(&mut self, rays: u32) {
        self.shader.set_edge_rays(rays);
        self.dirty = true;
    }

    /// Vertices the last sun map cast edge rays for ([`Shader::edge_vertices`]).
    pub fn edge_vertices(&self) -> usize {
        self.shader.edge_vertices()
    }

    /// The sun's elevation and azimuth, degrees.
    pub fn sun(&self) -> (f32, f32) {
        self.sun
    }

    /// Moves the sun (its irradiance kept).
    pub fn set_sun(&mut self, elevation_deg: f32, azimuth_deg: f32) {
        self.sun = (elevation_deg, azimuth_deg);
        self.lighting = self.base.with_sun_dir(sun_direction(elevation_deg, azimuth_deg));
        self.dirty = true;
    }

    /// How the sun is lit.
    pub fn method(&self) -> SunMethod {
        self.method
    }

    /// The two passes, or SH alone.
    pub fn set_method(&mut self, method: SunMethod) {
        self.method = method;
        self.dirty = true;
    }

    /// Marks the frame for re-shading (after a camera move: gloss depends on the view).
    pub fn touch(&mut self) {
        self.dirty = true;
    }

    /// Leaves drawn at each level of detail in the last frame.
    pub fn leaves_per_level(&self) -> &[usize] {
        &self.selection.leaves_per_level
    }

    /// Re-shades when something changed: decodes the sun direction's map if it changed, picks
    /// each leaf's level (when enabled), shades both sides of every vertex drawn.
    pub fn update(&mut self, height_px: u32) -> Result<bool, RleError> {
        if !self.dirty {
            return Ok(false);
        }
        let eye = self.camera.eye();
        let start = Instant::now();
        let decoded = self.shader.prepare(&self.scene, &self.data.lvc, &self.lighting)?;
        self.timings.decode_ms = if decoded { start.elapsed().as_secs_f64() * 1e3 } else { 0.0 };
        let start = Instant::now();
        let force = (!self.lod_enabled).then_some(0);
        self.selection =
            self.lod.select(&self.scene, &self.data.transfer, eye, self.camera.fov_y_deg, height_px, force);
        let mut out = Vec::new();
        self.shader.shade_lod(&self.scene, &self.data, &self.selection, &self.lighting, self.method, eye, &mut out);
        self.radiance.resize(self.scene.vertex_count(), [Vec3::ZERO; 2]);
        for (k, &v) in self.selection.vertices.iter().enumerate() {
            self.radiance[v as usize] = out[k];
        }
        self.timings.shade_ms = start.elapsed().as_secs_f64() * 1e3;
        let small = vcut_leaf::image::render_triangles(
            &self.scene,
            &self.selection.triangles,
            &self.radiance,
            &self.camera.camera(),
            (160, 90),
            None,
        );
        let image = vcut_shade::image::Image {
            width: small.width as u32,
            height: small.height as u32,
            rgb: small.rgb,
            covered: small.covered,
        };
        self.auto_exposure = vcut_shade::image::auto_exposure(&image);
        self.version += 1;
        self.dirty = false;
        Ok(true)
    }

    /// Per vertex, both sides' radiance toward the eye (vertices not drawn hold stale values).
    pub fn radiance(&self) -> &[TwoSided] {
        &self.radiance
    }

    /// The triangles drawn (scene vertex indices).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.selection.triangles
    }

    /// Bumped by every re-shade.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// The exposure used: the fixed one, or the automatic one of the last frame.
    pub fn exposure_in_use(&self) -> f32 {
        self.exposure.unwrap_or(self.auto_exposure)
    }

    /// What the renderer draws: the plant's positions, both sides' radiance, the triangles
    /// drawn, the version of the last re-shade.
    pub fn mesh(&self) -> crate::render::LeafMesh<'_> {
        crate::render::LeafMesh {
            positions: self.scene.positions(),
            radiance: &self.radiance,
            triangles: &self.selection.triangles,
            version: self.version,
            env: &self.env,
        }
    }

    /// How its frame is shown in `viewport` (radiance, at the exposure in use).
    pub fn shown(&self, viewport: crate::render::Viewport) -> crate::render::Shown<'_> {
        crate::render::Shown {
            env: &self.env,
            camera: &self.camera,
            exposure: self.exposure_in_use(),
            radiance: true,
            viewport,
        }
    }
}
