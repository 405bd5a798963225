//! Lighting for screen space: a known strong light (the sun, split off the environment map and
//! shadowed by a shadow map, as the paper does), and the rest of the environment pre-filtered
//! to the samples' cone (for SSDO) and cosine-convolved to irradiance (for SSAO).

use crate::gbuffer::Object;
use glam::{Mat4, Vec3};
use rayon::prelude::*;
use vcut_envmap::EnvMap;
pub use vcut_envmap::sun::{Sun, split_sun};
use vcut_scene::raster::raster_triangle;

/// A function on the sphere tabulated over an octahedral map (`size × size` texels),
/// looked up bilinearly in f32: cheap enough for every sample of every pixel.
#[derive(Debug, Clone)]
pub struct Octahedral {
    size: usize,
    texels: Vec<Vec3>,
}

impl Octahedral {
    /// Unit direction of octahedral coordinates `(u, v)` ∈ [−1, 1]².
    pub fn decode(u: f32, v: f32) -> Vec3 {
        let z = 1.0 - u.abs() - v.abs();
        let (x, y) = if z < 0.0 { ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum()) } else { (u, v) };
        Vec3::new(x, y, z).normalize_or(Vec3::Z)
    }

    /// Octahedral coordinates of direction `d` (need not be unit).
    pub fn encode(d: Vec3) -> (f32, f32) {
        let a = d / (d.x.abs() + d.y.abs() + d.z.abs()).max(f32::MIN_POSITIVE);
        if a.z >= 0.0 { (a.x, a.y) } else { ((1.0 - a.y.abs()) * a.x.signum(), (1.0 - a.x.abs()) * a.y.signum()) }
    }

    /// `f` tabulated at the texel centres.
    pub fn new(size: usize, f: impl Fn(Vec3) -> Vec3 + Sync) -> Octahedral {
        let size = size.max(2);
        let texels = (0..size * size)
            .into_par_iter()
            .map(|k| {
                let (i, j) = (k % size, k / size);
                let u = (i as f32 + 0.5) / size as f32 * 2.0 - 1.0;
                let v = (j as f32 + 0.5) / size as f32 * 2.0 - 1.0;
                f(Self::decode(u, v))
            })
            .collect();
        Octahedral { size, texels }
    }

    /// Texels per side.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The texels, row-major; texel `(i, j)` holds the value at
    /// `decode((i + ½)/size·2 − 1, (j + ½)/size·2 − 1)`.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Bilinear lookup at direction `d`.
    #[inline]
    pub fn get(&self, d: Vec3) -> Vec3 {
        let (u, v) = Self::encode(d);
        let n = self.size as f32;
        let x = ((u * 0.5 + 0.5) * n - 0.5).clamp(0.0, n - 1.0);
        let y = ((v * 0.5 + 0.5) * n - 0.5).clamp(0.0, n - 1.0);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.size - 1), (y0 + 1).min(self.size - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let t = |i: usize, j: usize| self.texels[j * self.size + i];
        (t(x0, y0) * (1.0 - fx) + t(x1, y0) * fx) * (1.0 - fy) + (t(x0, y1) * (1.0 - fx) + t(x1, y1) * fx) * fy
    }
}

/// The environment (sun removed) for screen-space lighting: the mean radiance over cones of
/// the samples' solid angle, and the irradiance, each tabulated on an octahedral map.
#[derive(Debug, Clone)]
pub struct Prefiltered {
    cone: Octahedral,
    irradiance: Octahedral,
}

impl Prefiltered {
    /// `env` pre-filtered for `samples` directions per pixel: cones of solid angle 2π/samples.
    pub fn new(env: &EnvMap, samples: usize) -> Prefiltered {
        // World-space source at 128 × 64 (rotation and intensity baked in).
        let src = env.to_latlong(128, 2);
        let mut dirs = Vec::with_capacity(src.texels().len());
        let mut weights = Vec::with_capacity(src.texels().len());
        src.layout().for_each_patch(1, |_, d, w| {
            dirs.push(d);
            weights.push(w as f32);
        });
        let texels = src.texels();
        let average = |o: Vec3, weight: &dyn Fn(f32) -> f32| {
            let (mut acc, mut wsum) = (Vec3::ZERO, 0.0f32);
            for ((d, &w), c) in dirs.iter().zip(&weights).zip(texels) {
                let k = weight(o.dot(*d)) * w;
                if k > 0.0 {
                    acc += Vec3::from(*c) * k;
                    wsum += k;
                }
            }
            if wsum > 0.0 { acc / wsum } else { Vec3::ZERO }
        };
        let cos_cone = 1.0 - 1.0 / samples.max(1) as f32;
        // Cone average: mean radiance over the cone. Irradiance: E(n) = π × the cosine-weighted
        // mean over the hemisphere.
        let cone = Octahedral::new(64, |o| average(o, &|c| if c >= cos_cone { 1.0 } else { 0.0 }));
        let irradiance = Octahedral::new(32, |o| average(o, &|c| c.max(0.0)) * std::f32::consts::PI);
        Prefiltered { cone, irradiance }
    }

    /// Mean radiance of the environment over a sample's cone around `dir`.
    #[inline]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.cone.get(dir)
    }

    /// Unoccluded irradiance from the environment on a surface of normal `n`.
    #[inline]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        self.irradiance.get(n)
    }

    /// The cone-averaged radiance table and the irradiance table (for GPU implementations).
    pub fn tables(&self) -> (&Octahedral, &Octahedral) {
        (&self.cone, &self.irradiance)
    }
}

/// An orthographic depth map from the sun over the scene's bounding sphere.
#[derive(Debug, Clone)]
pub struct ShadowMap {
    view: Mat4,
    size: usize,
    half: f32,
    depth: Vec<f32>,
    bias: f32,
}

impl ShadowMap {
    /// A `size × size` map of `objects` seen from direction `sun` (toward the sun).
    pub fn new(objects: &[Object], sun: Vec3, size: usize) -> ShadowMap {
        let points = objects.iter().flat_map(|o| o.positions.iter().copied());
        let b = vcut_scene::Bounds::of_points(points);
        let radius = b.radius.max(1e-6);
        let up = if sun.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
        let eye = b.center + sun * radius * 2.0;
        let view = glam::camera::rh::view::look_at_mat4(eye, b.center, up);
        let size = size.max(1);
        let mut depth = vec![f32::INFINITY; size * size];
        let to_map = |p: Vec3| map_coords(view, radius, size, p);
        for o in objects {
            let mapped: Vec<Vec3> = o.positions.iter().map(|&p| to_map(p)).collect();
            for t in &o.triangles {
                let s = t.map(|i| mapped[i as usize]);
                raster_triangle(s, size, size, |k, b0, b1, b2| {
                    let z = b0 * s[0].z + b1 * s[1].z + b2 * s[2].z;
                    if z < depth[k] {
                        depth[k] = z;
                    }
                });
            }
        }
        // Two texels of slope: enough bias for surfaces up to ~60° from the sun.
        let bias = 2.0 * (2.0 * radius / size as f32) * 1.7;
        ShadowMap { view, size, half: radius, depth, bias }
    }

    /// The map's view matrix (world to sun view, looking along −sun).
    pub fn view(&self) -> Mat4 {
        self.view
    }

    /// Half the side of the square the map covers (the scene's bounding radius).
    pub fn half(&self) -> f32 {
        self.half
    }

    /// Texels per side.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Depth bias of the comparison.
    pub fn bias(&self) -> f32 {
        self.bias
    }

    /// Stored depth per texel, row-major (∞ where nothing was drawn).
    pub fn depths(&self) -> &[f32] {
        &self.depth
    }

    /// Share of `p` lit by the sun, 3 × 3 percentage-closer filtered.
    pub fn lit(&self, p: Vec3) -> f32 {
        let Vec3 { x, y, z } = map_coords(self.view, self.half, self.size, p);
        let (mut lit, mut n) = (0.0, 0.0);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                let (px, py) = (x.floor() as i64 + dx, y.floor() as i64 + dy);
                n += 1.0;
                if px < 0 || py < 0 || px >= self.size as i64 || py >= self.size as i64 {
                    lit += 1.0;
                    continue;
                }
                if z <= self.depth[py as usize * self.size + px as usize] + self.bias {
                    lit += 1.0;
                }
            }
        }
        lit / n
    }
}

/// Shadow-map coordinates of world point `p`: texel x, y (from the top left) and the depth
/// along the sun's view (−z of `view`).
#[inline]
pub fn map_coords(view: Mat4, half: f32, size: usize, p: Vec3) -> Vec3 {
    let v = view.transform_point3(p);
    Vec3::new((v.x / half * 0.5 + 0.5) * size as f32, (0.5 - v.y / half * 0.5) * size as f32, -v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedral_coordinates_round_trip_and_tables_interpolate() {
        for d in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.8, -0.5).normalize(), Vec3::new(-0.6, 0.1, 0.7)] {
            let (u, v) = Octahedral::encode(d);
            assert!((Octahedral::decode(u, v) - d.normalize()).length() < 1e-5, "{d}");
        }
        // A linear function of the direction comes back within the table's resolution.
        let t = Octahedral::new(64, |d| Vec3::splat(d.y + 1.0));
        for d in [Vec3::Y, -Vec3::Y, Vec3::new(0.5, 0.5, -0.7).normalize()] {
            assert!((t.get(d).x - (d.y + 1.0)).abs() < 0.03, "{d}: {}", t.get(d));
        }
    }

    #[test]
    fn prefiltering_keeps_a_constant_map_and_its_irradiance() {
        let p = Prefiltered::new(&EnvMap::constant([2.0, 1.0, 0.5]), 16);
        for d in [Vec3::Y, Vec3::X, Vec3::new(0.3, -0.8, 0.5).normalize()] {
            assert!((p.radiance(d) - Vec3::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-3);
            let e = p.irradiance(d);
            let want = Vec3::new(2.0, 1.0, 0.5) * std::f32::consts::PI;
            assert!((e - want).abs().max_element() < 0.01 * want.max_element(), "{e} vs {want}");
        }
    }

    #[test]
    fn a_shadow_map_shadows_below_a_blocker_only() {
        let quad = |y: f32, half: f32| Object {
            positions: vec![
                Vec3::new(-half, y, -half),
                Vec3::new(half, y, -half),
                Vec3::new(half, y, half),
                Vec3::new(-half, y, half),
            ],
            normals: vec![Vec3::Y; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            albedo: Vec3::ONE,
        };
        let objects = [quad(0.0, 2.0), quad(1.0, 0.5)];
        let map = ShadowMap::new(&objects, Vec3::Y, 256);
        assert_eq!(map.lit(Vec3::new(0.0, 0.0, 0.0)), 0.0, "under the blocker");
        assert_eq!(map.lit(Vec3::new(1.5, 0.0, 1.5)), 1.0, "in the open");
        assert_eq!(map.lit(Vec3::new(0.0, 1.0, 0.0)), 1.0, "the blocker itself");
    }
}
