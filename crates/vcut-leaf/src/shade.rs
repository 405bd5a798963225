//! Two-pass shading (the paper's eq. 9): the direct sun from the decoded LVC map of the current
//! sun direction, plus everything else — the environment, direct and bounced, and the bounced part
//! of the sunlight — through the PRT transfer vectors. Per vertex both sides are shaded toward the
//! eye, so an image can show whichever side faces it.
//!
//! For comparison, [`SunMethod::ShOnly`] sends the sun through the SH transfer too (no LVC): the
//! low-frequency rendering whose lost shadow detail the paper's Fig. 8 shows.

use crate::lobe::LobeVisibility;
use crate::lvc::{Content, Lvc};
use crate::material::Scatter;
use crate::prt::Transfer;
use crate::rle::RleError;
use crate::scene::LeafScene;
use crate::sh::{COEFFS, ShRgb, project_delta, project_env};
use glam::{Vec3, Vec3A};
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;
use vcut_envmap::sun::split_sun;

/// A distant disk light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunLight {
    /// Unit direction toward the sun.
    pub dir: Vec3,
    /// Irradiance at normal incidence (∫ over the disk of L dω), RGB.
    pub irradiance: Vec3,
}

/// Unit direction toward a sun at `elevation_deg` above the horizon and `azimuth_deg` from +Z
/// toward +X (the built-in sky's convention).
pub fn sun_direction(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// The sun at `hours` of a day whose sun rises at 6 in the east (+X), culminates at 60° in the
/// south (+Z) at 12 and sets at 18 in the west: (elevation, azimuth) in degrees.
pub fn sun_at(hours: f32) -> (f32, f32) {
    let t = (hours - 6.0) / 12.0 * PI;
    let elevation = (60.0f32.to_radians().sin() * t.sin()).clamp(-1.0, 1.0).asin().to_degrees();
    (elevation, 90.0 + (hours - 6.0) / 12.0 * 180.0)
}

/// The lighting of a frame: the environment without its sun in SH, and the sun.
#[derive(Debug, Clone)]
pub struct Lighting {
    /// SH coefficients of the environment (sun removed).
    pub env: ShRgb,
    /// The sun, if any.
    pub sun: Option<SunLight>,
    /// The sun's SH coefficients (a δ of its irradiance).
    pub sun_sh: ShRgb,
}

impl Lighting {
    /// Lighting from a map without a sun in it and a separate sun.
    pub fn new(env_without_sun: &EnvMap, sun: Option<SunLight>) -> Lighting {
        let env = project_env(env_without_sun);
        let sun_sh = sun.map_or([Vec3::ZERO; COEFFS], |s| project_delta(s.dir, s.irradiance));
        Lighting { env, sun, sun_sh }
    }

    /// Lighting from a map with a sun in it: the sun is split off (its power kept) and treated
    /// as the disk light; a map without a sun is all environment.
    pub fn from_map(env: &EnvMap) -> (Lighting, EnvMap) {
        let (sun, rest) = split_sun(env);
        let sun = sun.map(|s| SunLight { dir: s.dir, irradiance: s.irradiance });
        (Lighting::new(&rest, sun), rest)
    }

    /// The same lighting with the sun moved to unit direction `dir` (its irradiance kept).
    pub fn with_sun_dir(&self, dir: Vec3) -> Lighting {
        let sun = self.sun.map(|s| SunLight { dir: dir.normalize(), ..s });
        let sun_sh = sun.map_or([Vec3::ZERO; COEFFS], |s| project_delta(s.dir, s.irradiance));
        Lighting { env: self.env, sun, sun_sh }
    }
}

/// The glossy reflection of SH lighting (the paper's BRDF vector b(v)), per surface: the lobe
/// taken as a Phong lobe around the mirror direction of exponent n = (2/m² − 2)/4 (Beckmann's
/// Blinn–Phong equivalent, moved from the half vector to the mirror direction), whose SH
/// convolution weights g_l = (n+1)∫₀¹ μⁿ P_l(μ) dμ filter the light, scaled by the gloss's
/// directional albedo A(n·v, m) (tabulated by importance sampling the Beckmann distribution) and
/// by the share of the side's sky left unoccluded.
struct GlossTables {
    /// A(μ_v, m): rows of m, columns of μ_v.
    albedo: Vec<f32>,
    /// The cosine and sine of the lobe centre's tilt (the BRDF × cosine-weighted mean direction's
    /// angle from the normal, toward the mirror direction), each laid out as `albedo` and
    /// interpolated apart, so a frame needs no trigonometry.
    tilt: [Vec<f32>; 2],
    /// g_l per m row.
    bands: Vec<[f32; 5]>,
    /// Per m row, the hemispherical albedo 2∫A(μ)μ dμ: what the gloss reflects of light from
    /// every direction (the bounces' gloss, [`gloss_reflectance`]).
    hemispherical: Vec<f32>,
}

const GLOSS_MU: usize = 32;
const GLOSS_M: usize = 24;

fn gloss_m(k: usize) -> f32 {
    0.02 + (1.0 - 0.02) * k as f32 / (GLOSS_M - 1) as f32
}

impl GlossTables {
    fn get() -> &'static GlossTables {
        static TABLES: std::sync::OnceLock<GlossTables> = std::sync::OnceLock::new();
        TABLES.get_or_init(GlossTables::build)
    }

    fn build() -> GlossTables {
        use crate::material::{CUTICLE_IOR, fresnel_dielectric};
        let mut albedo = Vec::with_capacity(GLOSS_M * GLOSS_MU);
        let mut tilt = [Vec::with_capacity(GLOSS_M * GLOSS_MU), Vec::with_capacity(GLOSS_M * GLOSS_MU)];
        let mut bands = Vec::with_capacity(GLOSS_M);
        let strata = 24;
        for k in 0..GLOSS_M {
            let m = gloss_m(k);
            for j in 0..GLOSS_MU {
                let nv = ((j as f32 + 0.5) / GLOSS_MU as f32).max(1e-3);
                let v = Vec3::new((1.0 - nv * nv).sqrt(), nv, 0.0);
                let mut sum = 0.0f64;
                let mut centre = glam::DVec2::ZERO;
                for a in 0..strata {
                    for b in 0..strata {
                        let (u1, u2) = ((a as f32 + 0.5) / strata as f32, (b as f32 + 0.5) / strata as f32);
                        let tan2 = -m * m * (1.0 - u1).ln();
                        let ch = 1.0 / (1.0 + tan2).sqrt();
                        let sh = (1.0 - ch * ch).max(0.0).sqrt();
                        let phi = 2.0 * PI * u2;
                        let h = Vec3::new(sh * phi.cos(), ch, sh * phi.sin());
                        let vh = v.dot(h);
                        let l = 2.0 * vh * h - v;
                        if l.y <= 0.0 || vh <= 0.0 {
                            continue;
                        }
                        let g = (2.0 * ch * nv / vh).min(2.0 * ch * l.y / vh).min(1.0);
                        let w = f64::from(g * fresnel_dielectric(vh, CUTICLE_IOR) * vh / (ch * nv));
                        sum += w;
                        centre += w * glam::DVec2::new(f64::from(l.x), f64::from(l.y));
                    }
                }
                albedo.push((sum / (strata * strata) as f64) as f32);
                // The mirror direction lies toward −x: the tilt is positive toward it.
                let angle = (-centre.x).atan2(centre.y.max(1e-12));
                tilt[0].push(angle.cos() as f32);
                tilt[1].push(angle.sin() as f32);
            }
            let n = ((2.0 / (m * m) - 2.0) / 4.0).max(0.0);
            let mom = |k: f32| (n + 1.0) / (n + k + 1.0);
            bands.push([
                1.0,
                mom(1.0),
                (3.0 * mom(2.0) - 1.0) / 2.0,
                (5.0 * mom(3.0) - 3.0 * mom(1.0)) / 2.0,
                (35.0 * mom(4.0) - 30.0 * mom(2.0) + 3.0) / 8.0,
            ]);
        }
        let hemispherical = albedo
            .chunks(GLOSS_MU)
            .map(|row| {
                let mu = |j: usize| (j as f32 + 0.5) / GLOSS_MU as f32;
                row.iter().enumerate().map(|(j, a)| 2.0 * a * mu(j) / GLOSS_MU as f32).sum()
            })
            .collect();
        GlossTables { albedo, tilt, bands, hemispherical }
    }

    /// Directional albedo, band weights and the lobe centre's tilt (cosine, sine) for roughness
    /// `m` and cosine `nv`.
    fn lookup(&self, m: f32, nv: f32) -> (f32, [f32; 5], [f32; 2]) {
        let (k0, k1, f) = m_rows(m);
        let y = (nv * GLOSS_MU as f32 - 0.5).clamp(0.0, (GLOSS_MU - 1) as f32);
        let j0 = y.floor() as usize;
        let j1 = (j0 + 1).min(GLOSS_MU - 1);
        let g = y - j0 as f32;
        let at = |t: &[f32], k: usize| t[k * GLOSS_MU + j0] * (1.0 - g) + t[k * GLOSS_MU + j1] * g;
        let albedo = at(&self.albedo, k0) * (1.0 - f) + at(&self.albedo, k1) * f;
        let tilt = self.tilt.each_ref().map(|t| at(t, k0) * (1.0 - f) + at(t, k1) * f);
        let mut bands = [0.0; 5];
        for (l, b) in bands.iter_mut().enumerate() {
            *b = self.bands[k0][l] * (1.0 - f) + self.bands[k1][l] * f;
        }
        (albedo, bands, tilt)
    }
}

/// What gloss `g` reflects of light arriving from every direction alike, per channel: ρ_s times
/// its hemispherical albedo. Light passed on by a glossy leaf leaves it in every direction its
/// lobe spreads it; [`crate::prt`]'s bounces carry it as if diffuse.
pub fn gloss_reflectance(g: &crate::material::Gloss) -> Vec3 {
    if g.rho_s == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let t = GlossTables::get();
    let (k0, k1, f) = m_rows(g.roughness);
    g.rho_s * (t.hemispherical[k0] * (1.0 - f) + t.hemispherical[k1] * f)
}

/// The gloss tables' rows around roughness `m` and the fraction of the way to the second.
fn m_rows(m: f32) -> (usize, usize, f32) {
    let x = ((m - 0.02) / (1.0 - 0.02) * (GLOSS_M - 1) as f32).clamp(0.0, (GLOSS_M - 1) as f32);
    let k0 = x.floor() as usize;
    (k0, (k0 + 1).min(GLOSS_M - 1), x - k0 as f32)
}

/// How the sun's direct light is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SunMethod {
    /// From the LVC map (the paper's two passes).
    Lvc,
    /// Through the SH transfer like the environment (what SH alone can do).
    ShOnly,
}

/// What the two passes read: the LVC maps and the transfer vectors of one scene.
#[derive(Debug, Clone)]
pub struct LeafData {
    /// The sun's light-visibility convolution maps.
    pub lvc: Lvc,
    /// The SH transfer vectors.
    pub transfer: Transfer,
    /// Per vertex, how open a gloss lobe is toward any direction (from `lvc`; `None` when the
    /// maps lack directions).
    pub lobe: Option<LobeVisibility>,
}

impl LeafData {
    /// The data of `lvc` and `transfer`, with the lobe visibility derived from the maps.
    pub fn new(lvc: Lvc, transfer: Transfer) -> Result<LeafData, RleError> {
        let lobe = LobeVisibility::from_lvc(&lvc)?;
        Ok(LeafData { lvc, transfer, lobe })
    }
}

/// Shades frames, keeping the map of the last sun direction.
#[derive(Debug)]
pub struct Shader {
    map: Vec<u8>,
    /// The sun direction the map was made for.
    map_sun: Option<Vec3>,
    edge_rays: u32,
    edge_vertices: usize,
}

impl Default for Shader {
    fn default() -> Shader {
        Shader { map: Vec::new(), map_sun: None, edge_rays: 4, edge_vertices: 0 }
    }
}

/// Rays over the sun's disk (Vogel's spiral, area-uniform) toward its true direction: a first
/// look, and [`PENUMBRA_FACTOR`] times as many where the first look is split.
struct DiskRays {
    dir: Vec3,
    rays: Vec<Vec3>,
    fine: Vec<Vec3>,
}

/// A vertex whose first rays over the sun's disk disagree lies in the penumbra; it casts this
/// many times as many rays again (a denser spiral of its own) and takes their share.
pub const PENUMBRA_FACTOR: u32 = 4;

impl DiskRays {
    fn new(dir: Vec3, diameter_deg: f32, count: u32) -> DiskRays {
        let radius = (diameter_deg * 0.5).to_radians().max(0.0);
        let spiral = |n: u32| crate::lvc::disk_directions(dir, radius, n).collect();
        DiskRays { dir, rays: spiral(count), fine: spiral(count * PENUMBRA_FACTOR) }
    }

    /// Vertex `v`'s map byte toward the sun: the share of the rays that reach it (times the
    /// cosine when the maps bake it in).
    fn byte(&self, scene: &LeafScene, v: usize, content: Content) -> u8 {
        let (p, nrm) = (scene.positions()[v], scene.normals()[v]);
        let side = if nrm.dot(self.dir) >= 0.0 { nrm } else { -nrm };
        let origin = p + side * scene.ray_offset();
        let open =
            |rays: &[Vec3]| rays.iter().filter(|&&d| !scene.occluder().occluded(origin, d, f32::INFINITY)).count();
        let first = open(&self.rays);
        let mut share = if first == 0 || first == self.rays.len() {
            first as f32 / self.rays.len() as f32
        } else {
            open(&self.fine) as f32 / self.fine.len() as f32
        };
        if content == Content::CosineBaked {
            share *= nrm.dot(self.dir).abs();
        }
        (share.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// Per vertex, the radiance leaving side 0 and side 1 toward the eye.
pub type TwoSided = [Vec3; 2];

impl Shader {
    /// A shader with no map decoded yet.
    pub fn new() -> Shader {
        Shader::default()
    }

    /// Makes the map of `lighting`'s sun direction unless it is the one already made: the
    /// decoded maps of the computed directions around it blended by angle
    /// ([`Lvc::sun_weights`]), so shadows move with the sun between the cube's directions;
    /// then every vertex where a shadow edge passes — the maps around the sun disagree there
    /// (a blend is a guess), or its triangle's bytes do (a map samples one direction per texel,
    /// so a vertex in the penumbra reads all or nothing) — casts [`Shader::edge_rays`] rays over
    /// the sun's disk in its true direction, [`PENUMBRA_FACTOR`] times as many more where those
    /// disagree, and takes the share that reach it. Returns whether it made a map.
    pub fn prepare(&mut self, scene: &LeafScene, lvc: &Lvc, lighting: &Lighting) -> Result<bool, RleError> {
        let Some(sun) = lighting.sun else { return Ok(false) };
        if self.map_sun == Some(sun.dir) {
            return Ok(false);
        }
        let n = lvc.vertex_count();
        self.map_sun = None;
        self.map.resize(n, 0);
        self.edge_vertices = 0;
        let weights = lvc.sun_weights(sun.dir);
        // Vertices where a shadow edge passes: the maps around the sun disagree there.
        let mut edge = vec![false; n];
        if let [(j, _)] = weights[..] {
            lvc.decode(j, &mut self.map)?;
        } else {
            let mut sum = vec![0.0f32; n];
            let (mut lo, mut hi) = (vec![u8::MAX; n], vec![0u8; n]);
            for &(j, w) in &weights {
                lvc.decode(j, &mut self.map)?;
                for (v, &m) in self.map.iter().enumerate() {
                    sum[v] += w * f32::from(m);
                    lo[v] = lo[v].min(m);
                    hi[v] = hi[v].max(m);
                }
            }
            for (m, acc) in self.map.iter_mut().zip(&sum) {
                *m = acc.round().clamp(0.0, 255.0) as u8;
            }
            for (e, (l, h)) in edge.iter_mut().zip(lo.iter().zip(&hi)) {
                *e = l != h;
            }
        }
        if self.edge_rays > 0 && scene.vertex_count() == n {
            // ... or a triangle's vertices disagree: the edge crosses the triangle, and a vertex
            // in its penumbra sees part of the disk, which a map's one direction per texel
            // cannot tell from all or nothing.
            for t in scene.triangles() {
                let [a, b, c] = t.map(|v| v as usize);
                if self.map[a] != self.map[b] || self.map[b] != self.map[c] {
                    (edge[a], edge[b], edge[c]) = (true, true, true);
                }
            }
            let edges: Vec<usize> = (0..n).filter(|&v| edge[v]).collect();
            let disk = DiskRays::new(sun.dir, lvc.params().sun_diameter_deg, self.edge_rays);
            let content = lvc.params().content;
            let seen: Vec<u8> = edges.par_iter().with_min_len(256).map(|&v| disk.byte(scene, v, content)).collect();
            for (&v, b) in edges.iter().zip(seen) {
                self.map[v] = b;
            }
            self.edge_vertices = edges.len();
        }
        self.map_sun = Some(sun.dir);
        Ok(true)
    }

    /// A shader casting `rays` rays per shadow-edge vertex when it makes a sun map (0: the maps
    /// around the sun blended only).
    pub fn with_edge_rays(rays: u32) -> Shader {
        Shader { edge_rays: rays, ..Shader::default() }
    }

    /// Rays per shadow-edge vertex when a sun map is made (default 4; 0: the blend alone).
    pub fn edge_rays(&self) -> u32 {
        self.edge_rays
    }

    /// Sets [`Shader::edge_rays`]; the next [`Shader::prepare`] makes its map again.
    pub fn set_edge_rays(&mut self, rays: u32) {
        if rays != self.edge_rays {
            self.edge_rays = rays;
            self.map_sun = None;
        }
    }

    /// Vertices the last map cast rays for (its shadow edges).
    pub fn edge_vertices(&self) -> usize {
        self.edge_vertices
    }

    /// The sun map the last [`Shader::prepare`] made (a byte per vertex), if any.
    pub fn sun_map(&self) -> Option<&[u8]> {
        self.map_sun.map(|_| &self.map[..])
    }

    fn context<'a>(
        &'a self,
        scene: &'a LeafScene,
        data: &'a LeafData,
        lighting: &Lighting,
        method: SunMethod,
        eye: Vec3,
    ) -> FrameContext<'a> {
        let lvc = &data.lvc;
        let map = match (method, lighting.sun) {
            (SunMethod::Lvc, Some(sun)) if self.map_sun == Some(sun.dir) => Some((&self.map[..], lvc.params().content)),
            _ => None,
        };
        // Light through the direct transfer, and through the indirect one.
        let mut through_direct = [Vec3A::ZERO; COEFFS];
        let mut through_indirect = [Vec3A::ZERO; COEFFS];
        for i in 0..COEFFS {
            through_indirect[i] = Vec3A::from(lighting.env[i] + lighting.sun_sh[i]);
            through_direct[i] = match method {
                SunMethod::Lvc => Vec3A::from(lighting.env[i]),
                SunMethod::ShOnly => through_indirect[i],
            };
        }
        FrameContext {
            scene,
            through_direct,
            through_indirect,
            map,
            sun: lighting.sun.filter(|_| map.is_some()),
            tables: GlossTables::get(),
            lobe: data.lobe.as_ref(),
            sky_share: 1.0 / (PI * crate::sh::basis(Vec3::Y)[0]),
            eye,
        }
    }

    /// Shades every vertex of `scene` seen from `eye` into `out`. With [`SunMethod::Lvc`], call
    /// [`Shader::prepare`] first (a frame whose map is missing gets no direct sun).
    pub fn shade(
        &self,
        scene: &LeafScene,
        data: &LeafData,
        lighting: &Lighting,
        method: SunMethod,
        eye: Vec3,
        out: &mut Vec<TwoSided>,
    ) {
        let ctx = self.context(scene, data, lighting, method, eye);
        let t = &data.transfer;
        out.resize(scene.vertex_count(), [Vec3::ZERO; 2]);
        out.par_iter_mut().enumerate().with_min_len(1024).for_each(|(v, o)| {
            *o = ctx.vertex(v, &t.direct[v], &t.indirect[v], &scene.scatter()[v]);
        });
    }

    /// Shades the vertices a level-of-detail selection keeps (`out[k]` for `selection`'s k-th
    /// vertex), with their averaged transfer.
    #[allow(clippy::too_many_arguments)] // `shade`'s arguments and the selection
    pub fn shade_lod(
        &self,
        scene: &LeafScene,
        data: &LeafData,
        selection: &crate::lod::Selection,
        lighting: &Lighting,
        method: SunMethod,
        eye: Vec3,
        out: &mut Vec<TwoSided>,
    ) {
        let ctx = self.context(scene, data, lighting, method, eye);
        out.resize(selection.vertices.len(), [Vec3::ZERO; 2]);
        out.par_iter_mut().enumerate().with_min_len(1024).for_each(|(k, o)| {
            let (v, direct, indirect, scatter) = selection.vertex(k);
            *o = ctx.vertex(v, direct, indirect, scatter);
        });
    }
}

/// The SH band of each coefficient.
const BAND: [usize; COEFFS] = [0, 1, 1, 1, 2, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4];

/// The share of a gloss lobe around the mirror direction that the side's rays found open: the
/// lobe-filtered band-limited visibility × cosine the direct transfer `t` holds (its SH
/// coefficients; `yb` is the basis at the mirror direction times the lobe's band weights), over
/// the same for an open side — whose projection is zonal around the normal (`cos_nm` =
/// n·mirror). `None` where the open side's filtered cosine is too small to divide by.
fn lobe_visibility(t: &[f32; COEFFS], yb: &[f32; COEFFS], cos_nm: f32, bands: &[f32; 5]) -> Option<f32> {
    // 2π∫₀¹ μ P_l(μ) dμ: the clamped cosine's zonal coefficients, times (2l + 1)/(4π).
    const COSINE: [f32; 5] = [PI, 2.0 * PI / 3.0, PI / 4.0, 0.0, -PI / 24.0];
    let c = cos_nm;
    let legendre = [
        1.0,
        c,
        (3.0 * c * c - 1.0) / 2.0,
        (5.0 * c * c * c - 3.0 * c) / 2.0,
        (35.0 * c * c * c * c - 30.0 * c * c + 3.0) / 8.0,
    ];
    let mut open = 0.0;
    for l in 0..5 {
        open += bands[l] * COSINE[l] * (2 * l + 1) as f32 / (4.0 * PI) * legendre[l];
    }
    let seen: f32 = t.iter().zip(yb).map(|(t, yb)| t * yb).sum();
    (open > 0.02).then(|| (seen / open).clamp(0.0, 1.0))
}

/// What every vertex of one frame shares.
struct FrameContext<'a> {
    scene: &'a LeafScene,
    through_direct: [Vec3A; COEFFS],
    through_indirect: [Vec3A; COEFFS],
    map: Option<(&'a [u8], Content)>,
    sun: Option<SunLight>,
    tables: &'static GlossTables,
    lobe: Option<&'a LobeVisibility>,
    sky_share: f32,
    eye: Vec3,
}

impl FrameContext<'_> {
    /// Both sides of vertex `v` with transfer `direct`, `indirect` and scattering `s`.
    fn vertex(&self, v: usize, direct: &[[f32; COEFFS]; 2], indirect: &[[Vec3; COEFFS]; 2], s: &Scatter) -> TwoSided {
        let scene = self.scene;
        let (through_direct, through_indirect) = (&self.through_direct, &self.through_indirect);
        let (tables, sky_share, eye) = (self.tables, self.sky_share, self.eye);
        let (p, nrm) = (scene.positions()[v], scene.normals()[v]);
        // Irradiance per side: what arrives unscattered (the environment through the direct
        // transfer) and what other surfaces pass on.
        let (mut e, mut e_ind) = ([Vec3A::ZERO; 2], [Vec3A::ZERO; 2]);
        for side in 0..2 {
            let (d, ind) = (&direct[side], &indirect[side]);
            let (mut a, mut b) = (Vec3A::ZERO, Vec3A::ZERO);
            for i in 0..COEFFS {
                a += through_direct[i] * d[i];
                b += through_indirect[i] * Vec3A::from(ind[i]);
            }
            e_ind[side] = b.max(Vec3A::ZERO);
            e[side] = (a + b).max(Vec3A::ZERO);
        }
        let e = e.map(Vec3::from);
        let view = (eye - p).normalize_or_zero();
        let mut radiance = [s.r[0] / PI * e[0] + s.t / PI * e[1], s.r[1] / PI * e[1] + s.t / PI * e[0]];
        // Gloss of the SH light, toward the eye mirrored into each side: the lobe's open part
        // reflects the environment, its occluded part the light other surfaces pass on.
        for (side, rad) in radiance.iter_mut().enumerate() {
            let g = s.gloss[side];
            if g.rho_s == Vec3::ZERO {
                continue;
            }
            let ns = if side == 0 { nrm } else { -nrm };
            let vs = if ns.dot(view) > 0.0 { view } else { (view - 2.0 * ns.dot(view) * ns).normalize_or(ns) };
            let nv = ns.dot(vs).max(1e-3);
            let (albedo, bands, tilt) = tables.lookup(g.roughness, nv);
            let mirror = 2.0 * nv * ns - vs;
            // The basis at the mirror direction filtered by the lobe's band weights.
            let y = crate::sh::basis(mirror);
            let yb: [f32; COEFFS] = std::array::from_fn(|i| y[i] * bands[BAND[i]]);
            let mut filtered = Vec3A::ZERO;
            for (t, yb) in through_direct.iter().zip(&yb) {
                filtered += *t * *yb;
            }
            let open = (direct[side][0] * sky_share).clamp(0.0, 1.0);
            // How open the lobe is: the LVC-derived table at the lobe's centre (its cosine-weighted
            // mean direction, tilted from the mirror direction toward the normal), else the SH.
            let visible = match self.lobe {
                Some(table) => {
                    let along = (mirror - ns * ns.dot(mirror)).normalize_or_zero();
                    table.at(v, (ns * tilt[0] + along * tilt[1]).normalize_or(ns))
                }
                None => lobe_visibility(&direct[side], &yb, ns.dot(mirror), &bands).unwrap_or(open),
            };
            // The occluders' mean radiance: the bounced irradiance over the occluded part of the
            // cosine-weighted hemisphere.
            let occluded = Vec3::from(e_ind[side]) / (PI * (1.0 - open).max(0.05));
            let lobe = visible * Vec3::from(filtered.max(Vec3A::ZERO)) + (1.0 - visible) * occluded;
            *rad += g.rho_s * albedo * lobe;
        }
        if let (Some(sun), Some((map, content))) = (self.sun, self.map) {
            let cos = nrm.dot(sun.dir);
            let q = f32::from(map[v]) / 255.0;
            let vis = match content {
                Content::Visibility => q * cos.abs(),
                Content::CosineBaked => q,
            };
            if vis > 0.0 {
                let lit = usize::from(cos < 0.0);
                let irr = sun.irradiance * vis;
                let ns = if lit == 0 { nrm } else { -nrm };
                // The lit side reflects (diffuse + gloss toward the eye); the other transmits.
                let v_lit = if ns.dot(view) > 0.0 { view } else { view - 2.0 * ns.dot(view) * ns };
                radiance[lit] += (s.r[lit] / PI + s.gloss[lit].eval(ns, sun.dir, v_lit)) * irr;
                radiance[1 - lit] += s.t / PI * irr;
            }
        }
        radiance
    }
}
