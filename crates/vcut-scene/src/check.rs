//! Every value of a scene file checked before anything is built: finite, of the right sign,
//! within its limits, and — for tessellations and baked maps — within the memory budget by an
//! estimate ([`crate::budget`]). Errors name the file, the table (`[environment]`, `object 2
//! ('teapot')`, `camera 0 ('main')`) and the key.

use crate::SceneError;
use crate::budget::{self, Budget};
use crate::desc::{CameraDesc, EnvironmentDesc, ObjectDesc, SceneDesc};
use crate::limits::Limit;
use glam::Vec3;
use std::path::Path;

/// The built-in shapes an object's `source` can name, with their tessellation rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    /// The Utah teapot: `resolution` quads per patch edge (32 patches).
    Teapot,
    /// A UV sphere: `resolution` rings, twice as many segments.
    Sphere,
    /// A torus: `resolution` tube segments, twice as many around the ring.
    Torus,
    /// A box: `resolution` cells per face edge.
    Box,
    /// A square plane: `resolution` cells per edge.
    Plane,
}

/// The largest mesh a built-in shape may be tessellated into (vertices before welding): beyond
/// this, 32-bit indices and every later stage's memory run out first.
pub const MAX_BUILTIN_VERTICES: u64 = 1 << 27;

/// The widest built-in map (lat-long texels across; half as many down).
pub const MAX_MAP_WIDTH: u32 = 16_384;
/// The narrowest built-in map.
pub const MIN_MAP_WIDTH: u32 = 8;

/// The target error of the light left in the cuts (`[environment] light_error`, `render
/// --light-error`, Python's `light_error`): relative, in (0, 1).
pub const LIGHT_ERROR: Limit = Limit::between(0.0, 1.0, "(relative, e.g. 0.002 for 0.2 %)");

/// How close two vertices are welded (`weld`, `inspect --weld`).
pub const WELD: Limit = Limit::at_least(0.0, "scene units");

/// A map's brightness factor (`[environment] intensity`, Python's `EnvMap.intensity`).
pub const INTENSITY: Limit = Limit::at_least(0.0, "");

/// A map's turn about the vertical (`[environment] rotation_deg`, `--env-rotation`, Python's
/// `EnvMap.set_rotation_y_degrees`).
pub const ROTATION: Limit = Limit::finite("degrees");

/// Radiance, each channel (a constant map's, Python's `EnvMap.constant`).
pub const RADIANCE: Limit = Limit::at_least(0.0, "");

impl Builtin {
    /// The names accepted in `source`.
    pub const KNOWN: &'static str = "builtin:teapot, builtin:sphere, builtin:torus, builtin:box, builtin:plane";

    /// The shape `source` names (`builtin:teapot`, ...), if it is one.
    pub fn named(source: &str) -> Option<Builtin> {
        Some(match source {
            "builtin:teapot" => Builtin::Teapot,
            "builtin:sphere" => Builtin::Sphere,
            "builtin:torus" => Builtin::Torus,
            "builtin:box" => Builtin::Box,
            "builtin:plane" => Builtin::Plane,
            _ => return None,
        })
    }

    /// The resolution used when the scene file gives none.
    pub fn default_resolution(self) -> u32 {
        match self {
            Builtin::Teapot => 12,
            Builtin::Sphere | Builtin::Torus => 32,
            Builtin::Box => 8,
            Builtin::Plane => 64,
        }
    }

    /// The smallest resolution that makes a closed (or flat) shape.
    pub fn min_resolution(self) -> u32 {
        match self {
            Builtin::Teapot | Builtin::Box | Builtin::Plane => 1,
            Builtin::Sphere => 2,
            Builtin::Torus => 3,
        }
    }

    /// The size used when the scene file gives none.
    pub fn default_size(self) -> f32 {
        match self {
            Builtin::Plane => 10.0,
            _ => 1.0,
        }
    }

    /// Vertices and triangles at resolution `r`, before welding (computed in u128, saturated
    /// to u64: no overflow at any `r`).
    pub fn counts(self, r: u32) -> (u64, u64) {
        let r = u128::from(r);
        let (v, t) = match self {
            Builtin::Teapot => (32 * (r + 1) * (r + 1), 64 * r * r),
            Builtin::Sphere => {
                let s = (2 * r).max(3);
                ((r + 1) * (s + 1), 2 * s * r)
            }
            Builtin::Torus => {
                let (nu, nv) = ((2 * r).max(3), r.max(3));
                ((nv + 1) * (nu + 1), 2 * nu * nv)
            }
            Builtin::Box => (6 * (r + 1) * (r + 1), 12 * r * r),
            Builtin::Plane => ((r + 1) * (r + 1), 2 * r * r),
        };
        let sat = |x: u128| u64::try_from(x).unwrap_or(u64::MAX);
        (sat(v), sat(t))
    }
}

/// Checks one table's keys, naming the file and the table in its errors.
struct Table<'a> {
    file: &'a Path,
    name: String,
}

impl Table<'_> {
    fn bad(&self, key: &str, value: impl std::fmt::Debug, reason: impl Into<String>) -> SceneError {
        SceneError::Value {
            path: self.file.into(),
            table: self.name.clone(),
            key: key.into(),
            value: format!("{value:?}"),
            reason: reason.into(),
        }
    }

    /// `v` within `limit` ([`crate::limits`], the one check of a number users give).
    fn limit(&self, key: &str, v: f32, limit: Limit) -> Result<(), SceneError> {
        limit.check(f64::from(v)).map(|_| ()).map_err(|reason| self.bad(key, v, reason))
    }

    fn finite3(&self, key: &str, v: [f32; 3]) -> Result<(), SceneError> {
        if v.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(self.bad(key, v, "must be three finite numbers")) }
    }

    fn positive(&self, key: &str, v: f32) -> Result<(), SceneError> {
        self.limit(key, v, Limit::above(0.0, ""))
    }

    /// Adds `bytes` to what the scene takes so far, failing over the budget.
    fn spend(
        &self,
        key: &str,
        value: impl std::fmt::Debug,
        what: &str,
        bytes: u64,
        spent: &mut u64,
        budget: &Budget,
    ) -> Result<(), SceneError> {
        let total = spent.saturating_add(bytes);
        if total > budget.max_bytes {
            let so_far =
                if *spent > 0 { format!(" (the scene so far {})", budget::human(*spent)) } else { String::new() };
            return Err(self.bad(
                key,
                value,
                format!(
                    "{what} would take about {}{so_far}, more than the {} of memory available",
                    budget::human(bytes),
                    budget::human(budget.max_bytes)
                ),
            ));
        }
        *spent = total;
        Ok(())
    }
}

impl EnvironmentDesc {
    /// Checks every key; adds a built-in map's baking memory to `spent`.
    pub fn check(&self, file: &Path, budget: &Budget, spent: &mut u64) -> Result<(), SceneError> {
        let t = Table { file, name: "[environment]".into() };
        if self.source.trim().is_empty() {
            return Err(t.bad(
                "source",
                &self.source,
                "must name a map: builtin:sky, builtin:studio, builtin:constant or a file",
            ));
        }
        t.limit("rotation_deg", self.rotation_deg, ROTATION)?;
        t.limit("intensity", self.intensity, INTENSITY)?;
        if !(MIN_MAP_WIDTH..=MAX_MAP_WIDTH).contains(&self.resolution) {
            return Err(t.bad(
                "resolution",
                self.resolution,
                format!("must lie in [{MIN_MAP_WIDTH}, {MAX_MAP_WIDTH}] texels across"),
            ));
        }
        t.limit("sun_elevation_deg", self.sun_elevation_deg, Limit::within(-90.0, 90.0, "degrees"))?;
        t.limit("sun_azimuth_deg", self.sun_azimuth_deg, Limit::finite("degrees"))?;
        // The range Preetham et al.'s fit was made for.
        t.limit("turbidity", self.turbidity, Limit::within(1.7, 10.0, ""))?;
        t.limit("sun_diameter_deg", self.sun_diameter_deg, Limit::above_up_to(0.0, 45.0, "degrees"))?;
        t.limit("sun_to_zenith", self.sun_to_zenith, Limit::within(1e-6, 1e9, ""))?;
        t.limit("lux_scale", self.lux_scale, Limit::at_least(0.0, "map units per lux"))?;
        if let Some(e) = self.light_error {
            LIGHT_ERROR.check(e).map_err(|reason| t.bad("light_error", e, reason))?;
        }
        if matches!(self.source.as_str(), "builtin:sky" | "builtin:studio") {
            let w = u64::from(self.resolution);
            t.spend("resolution", self.resolution, "baking the map", budget::map_bytes(w * (w / 2)), spent, budget)?;
        }
        Ok(())
    }
}

impl ObjectDesc {
    /// The table name in errors: `object 2 ('teapot')`.
    pub fn table_name(&self, index: usize) -> String {
        format!("object {index} ('{}')", self.name.as_deref().unwrap_or(&self.source))
    }

    /// Checks every key of object `index`; adds a built-in shape's tessellation memory to
    /// `spent`.
    pub fn check(&self, file: &Path, index: usize, budget: &Budget, spent: &mut u64) -> Result<(), SceneError> {
        let t = Table { file, name: self.table_name(index) };
        if self.source.trim().is_empty() {
            return Err(t.bad("source", &self.source, format!("must name a mesh file or one of {}", Builtin::KNOWN)));
        }
        let builtin = Builtin::named(&self.source);
        match builtin {
            Some(b) => {
                let r = self.resolution.unwrap_or(b.default_resolution());
                if r < b.min_resolution() {
                    return Err(t.bad("resolution", r, format!("must be at least {}", b.min_resolution())));
                }
                let (vertices, triangles) = b.counts(r);
                if vertices > MAX_BUILTIN_VERTICES {
                    return Err(t.bad(
                        "resolution",
                        r,
                        format!("makes {vertices} vertices, above the limit of {MAX_BUILTIN_VERTICES}"),
                    ));
                }
                t.spend("resolution", r, "tessellating", budget::mesh_bytes(vertices, triangles), spent, budget)?;
                if let Some(s) = self.size {
                    t.positive("size", s)?;
                }
            }
            None if self.source.starts_with("builtin:") => {
                return Err(SceneError::UnknownBuiltin { name: self.source.clone(), known: Builtin::KNOWN });
            }
            None => {
                for (key, given) in [("resolution", self.resolution.is_some()), ("size", self.size.is_some())] {
                    if given {
                        return Err(t.bad(key, &self.source, "applies to built-in shapes only, not to a mesh file"));
                    }
                }
            }
        }
        if let Some(h) = self.stand_height {
            t.positive("stand_height", h)?;
        }
        t.finite3("translation", self.translation)?;
        t.finite3("rotation_deg", self.rotation_deg)?;
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(t.bad("scale", self.scale, "must be a finite number above 0 (mirroring is not supported)"));
        }
        if let Some(w) = self.weld {
            t.limit("weld", w, WELD)?;
        }
        if let Some(m) = &self.material {
            m.validate().map_err(|e| t.bad("material", m.model, e.to_string()))?;
        }
        if self.instances.len() > crate::desc::MAX_INSTANCES {
            return Err(t.bad(
                "instances",
                self.instances.len(),
                format!("places more than {} copies", crate::desc::MAX_INSTANCES),
            ));
        }
        for (k, offset) in self.instances.iter().enumerate() {
            t.finite3(&format!("instances[{k}]"), *offset)?;
        }
        if let (Some(b), n) = (builtin, self.instances.len())
            && n > 1
        {
            let (vertices, triangles) = b.counts(self.resolution.unwrap_or(b.default_resolution()));
            let copies = budget::mesh_bytes(vertices, triangles).saturating_mul(n as u64 - 1);
            t.spend("instances", n, "the copies", copies, spent, budget)?;
        }
        Ok(())
    }
}

impl CameraDesc {
    /// Checks every key of camera `index`.
    pub fn check(&self, file: &Path, index: usize) -> Result<(), SceneError> {
        let t = Table { file, name: format!("camera {index} ('{}')", self.name) };
        t.finite3("position", self.position)?;
        t.finite3("target", self.target)?;
        t.finite3("up", self.up)?;
        let dir = Vec3::from(self.target) - Vec3::from(self.position);
        if !(dir.length() > 0.0 && dir.is_finite()) {
            return Err(t.bad("target", self.target, "must differ from position"));
        }
        let side = dir.normalize().cross(Vec3::from(self.up));
        if side.length().is_nan() || side.length() <= 1e-6 {
            return Err(t.bad("up", self.up, "must be non-zero and not along the view direction"));
        }
        t.limit("fov_y_deg", self.fov_y_deg, Limit::between(0.0, 180.0, "degrees"))?;
        Ok(())
    }
}

impl SceneDesc {
    /// Checks every value of the description (see the module docs) against `budget`; returns
    /// the estimated peak bytes of building its built-in shapes and maps.
    pub fn check(&self, file: &Path, budget: &Budget) -> Result<u64, SceneError> {
        let mut spent = 0u64;
        self.environment.check(file, budget, &mut spent)?;
        for (i, o) in self.objects.iter().enumerate() {
            o.check(file, i, budget, &mut spent)?;
        }
        for (i, c) in self.cameras.iter().enumerate() {
            c.check(file, i)?;
        }
        Ok(spent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_counts_match_the_builders() {
        for (b, r) in [(Builtin::Teapot, 3), (Builtin::Box, 4), (Builtin::Plane, 5)] {
            let mesh = match b {
                Builtin::Teapot => crate::teapot::teapot(r).unwrap().0,
                Builtin::Box => crate::shapes::cuboid(Vec3::ONE, r).unwrap(),
                _ => crate::shapes::plane(1.0, r).unwrap(),
            };
            let (v, t) = b.counts(r);
            // Welding and dropped degenerate triangles only ever remove.
            assert!(mesh.vertex_count() as u64 <= v && mesh.triangle_count() as u64 <= t, "{b:?}");
        }
        let (v, t) = Builtin::Plane.counts(5);
        assert_eq!((v, t), (36, 50));
        assert_eq!(Builtin::Teapot.counts(u32::MAX), (u64::MAX, u64::MAX));
        assert_eq!(Builtin::Sphere.counts(2), (3 * 5, 16));
    }
}
