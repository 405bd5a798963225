//! The sun as a known strong light: found in a map, split off with its power kept exactly; or
//! added to a map as a disk ([`EnvMap::with_suns`]).
//!
//! Screen-space occlusion shadow-maps it and the leaf renderer convolves it with visibility; both
//! need the rest of the map without it.

use crate::procedural::{cone_solid_angle, disk_shares};
use crate::{EnvMap, Layout, layout, luminance};
use glam::Vec3;

/// A distant light of small extent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sun {
    /// Unit direction toward the sun (world).
    pub dir: Vec3,
    /// Irradiance at normal incidence, ∫ over the disk of L dω (RGB).
    pub irradiance: Vec3,
}

/// Half-angle around the brightest texel searched for the sun's texels.
const SUN_SEARCH_DEG: f32 = 4.0;
/// A texel belongs to the sun when its luminance exceeds this multiple of the map's median.
const SUN_OVER_MEDIAN: f32 = 50.0;
/// A sun holding less than this share of the map's power is left in the map.
const SUN_MIN_SHARE: f64 = 0.02;

/// Splits `env` into a sun (texels near the brightest one that exceed 50× the median luminance,
/// when they hold at least 2 % of the power) and the rest, where the sun's texels take the mean
/// of the ring just outside them. Without such a sun the map comes back whole.
pub fn split_sun(env: &EnvMap) -> (Option<Sun>, EnvMap) {
    let layout = env.layout();
    let texels = env.texels();
    let mut dirs = vec![Vec3::ZERO; texels.len()];
    let mut omega = vec![0.0f64; texels.len()];
    layout.for_each_patch(1, |t, d, w| {
        dirs[t] = d;
        omega[t] = w;
    });
    let lum: Vec<f32> = texels.iter().map(|&c| luminance(c)).collect();
    let Some((peak, _)) = lum.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) else {
        return (None, env.clone());
    };
    let mut sorted = lum.clone();
    sorted.sort_by(f32::total_cmp);
    let median = sorted[sorted.len() / 2];
    let cos_search = SUN_SEARCH_DEG.to_radians().cos();
    let cos_ring = (2.0 * SUN_SEARCH_DEG).to_radians().cos();
    let near: Vec<usize> = (0..texels.len()).filter(|&t| dirs[t].dot(dirs[peak]) >= cos_ring).collect();
    let is_sun =
        |t: usize| dirs[t].dot(dirs[peak]) >= cos_search && lum[t] > SUN_OVER_MEDIAN * median.max(f32::MIN_POSITIVE);
    let sun_texels: Vec<usize> = near.iter().copied().filter(|&t| is_sun(t)).collect();
    let ring: Vec<usize> = near.iter().copied().filter(|&t| !is_sun(t)).collect();
    let (mut fill, mut fill_w) = (glam::DVec3::ZERO, 0.0);
    for &t in &ring {
        fill += glam::DVec3::from(texels[t].map(f64::from)) * omega[t];
        fill_w += omega[t];
    }
    let fill = if fill_w > 0.0 { fill / fill_w } else { glam::DVec3::ZERO };
    let (mut power, mut centroid) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for &t in &sun_texels {
        let excess = (glam::DVec3::from(texels[t].map(f64::from)) - fill).max(glam::DVec3::ZERO) * omega[t];
        power += excess;
        centroid += dirs[t].as_dvec3() * (excess.x * 0.2126 + excess.y * 0.7152 + excess.z * 0.0722);
    }
    let total: f64 = lum.iter().zip(&omega).map(|(&l, &w)| f64::from(l) * w).sum();
    let sun_lum = power.x * 0.2126 + power.y * 0.7152 + power.z * 0.0722;
    if sun_texels.is_empty() || total <= 0.0 || sun_lum < SUN_MIN_SHARE * total {
        return (None, env.clone());
    }
    let mut rest = texels.to_vec();
    for &t in &sun_texels {
        rest[t] = fill.as_vec3().to_array();
    }
    let Ok((mut residual, _)) =
        EnvMap::new(layout, rest, format!("{} (sun removed)", env.source()), Default::default())
    else {
        return (None, env.clone());
    };
    residual.set_rotation(env.rotation());
    residual.set_intensity(env.intensity());
    let dir = env.rotation() * centroid.as_vec3().normalize_or(dirs[peak]);
    (Some(Sun { dir, irradiance: power.as_vec3() * env.intensity() }), residual)
}

impl EnvMap {
    /// This map with `suns` added as disks of angular diameter `diameter_deg` (a glTF scene's
    /// directional lights, `KHR_lights_punctual`): each a disk of uniform radiance `E / Ω`
    /// around its direction, `E` its irradiance at normal incidence and `Ω = 2π(1 − cos r)` the
    /// disk's solid angle, spread over the texels it covers as the built-in sky's sun is
    /// ([`crate::procedural`]), so the map's power grows by exactly `E` and the renderers see a
    /// small bright source like any other. A lat-long map at least `width` texels across gets
    /// them in place (in map space: the map's rotation turns them back to their world
    /// directions, and its intensity scales them as it scales the rest); a cube map or a narrower
    /// map is first resampled to a `width × width/2` lat-long map so the disks have texels to
    /// land in. No sun: the map unchanged.
    pub fn with_suns(self, suns: &[Sun], diameter_deg: f32, width: u32) -> EnvMap {
        if suns.is_empty() {
            return self;
        }
        let reconstruction = self.reconstruction;
        let narrow = match self.layout {
            Layout::LatLong { width: w, .. } => w < width,
            Layout::Cube { .. } => true,
        };
        let (mut map, scale) = if narrow {
            // Resampling bakes rotation and intensity in: the suns take the intensity as a factor.
            (self.to_latlong(width, 4), self.intensity)
        } else {
            (self, 1.0)
        };
        let Layout::LatLong { width: w, height: h } = map.layout else { return map };
        for sun in suns {
            let axis = map.rotation.inverse() * sun.dir.normalize_or(Vec3::Y);
            let r = 0.5 * f64::from(diameter_deg.max(1e-4)).to_radians();
            let omega = cone_solid_angle(r);
            for (t, share) in disk_shares(map.layout, axis, r) {
                let row = (t / w as usize) as f64;
                let texel = layout::latlong_solid_angle(
                    0.0,
                    1.0 / f64::from(w),
                    row / f64::from(h),
                    (row + 1.0) / f64::from(h),
                );
                let add = share / (omega * texel) * f64::from(scale);
                for (c, e) in map.texels[t].iter_mut().zip(sun.irradiance.to_array()) {
                    *c += (f64::from(e.max(0.0)) * add) as f32;
                }
            }
        }
        map.source = format!("{} with {} sun(s)", map.source, suns.len());
        // Reconstructed as before (the result is lat-long): the means follow the new texels.
        map.with_reconstruction(reconstruction).expect("a lat-long map")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::PreethamSky;

    #[test]
    fn the_sky_sun_is_found_with_its_power_and_direction() {
        let sky = PreethamSky::default();
        let map = sky.bake(512);
        let (sun, rest) = split_sun(&map);
        let sun = sun.expect("a 10^5 sun is found");
        assert!(sun.dir.dot(sky.sun_dir.normalize()) > 0.9995, "{} vs {}", sun.dir, sky.sun_dir);
        let total = map.total_power();
        let left = rest.total_power();
        // What left the map is the sun's power, within 1 %.
        for c in 0..3 {
            let taken = total[c] - left[c];
            assert!((taken - f64::from(sun.irradiance[c])).abs() < 0.01 * taken, "channel {c}");
        }
        assert!(left[1] < 0.8 * total[1], "the sun held a large share: {} of {}", left[1], total[1]);
        // A constant map has no sun.
        assert!(split_sun(&EnvMap::constant([1.0; 3])).0.is_none());
    }

    #[test]
    fn a_sun_adds_its_irradiance_as_power_where_it_points() {
        let base = EnvMap::constant([0.5, 0.5, 0.5]);
        let sun = Sun { dir: Vec3::new(1.0, 2.0, 0.5).normalize(), irradiance: Vec3::new(3.0, 2.0, 1.0) };
        let lit = base.clone().with_suns(&[sun], 0.53, 256);
        assert_eq!(lit.layout(), Layout::LatLong { width: 256, height: 128 });
        let (before, after) = (base.total_power(), lit.total_power());
        for c in 0..3 {
            let added = after[c] - before[c];
            let want = f64::from(sun.irradiance[c]);
            assert!((added - want).abs() < 1e-4 * want, "channel {c}: added {added}, want {want}");
        }
        // All of it within a few texels of its direction.
        let near = lit.integrate_cone(sun.dir, 3f32.to_radians());
        let plain = base.to_latlong(256, 4).integrate_cone(sun.dir, 3f32.to_radians());
        assert!((near[0] - plain[0] - 3.0).abs() < 1e-3, "{near:?} {plain:?}");
        // A rotated map keeps the sun at its world direction; intensity scales it.
        let mut turned = EnvMap::constant([0.0; 3]).to_latlong(128, 1);
        turned.set_rotation_y_degrees(70.0);
        turned.set_intensity(2.0);
        let lit = turned.with_suns(&[sun], 0.53, 128);
        let near = lit.integrate_cone(sun.dir, 4f32.to_radians());
        assert!((near[1] - 2.0 * 2.0).abs() < 1e-3, "{near:?}");
        assert_eq!(EnvMap::constant([1.0; 3]).with_suns(&[], 0.53, 64).texels(), EnvMap::constant([1.0; 3]).texels());
    }
}
