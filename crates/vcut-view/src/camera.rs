//! The viewer's orbit camera and picking rays.

use glam::{Mat4, Vec3};
pub use vcut_rays::{ray_plane, ray_triangle};
use vcut_scene::Camera;

/// A camera orbiting a target point: yaw and pitch around the world's +Y, and a distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at and orbited around.
    pub target: Vec3,
    /// Rotation around +Y, radians (0: the eye on +Z of the target).
    pub yaw: f32,
    /// Elevation, radians, within ±89°.
    pub pitch: f32,
    /// Eye-to-target distance.
    pub distance: f32,
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
}

const MAX_PITCH: f32 = 89.0 * std::f32::consts::PI / 180.0;

impl OrbitCamera {
    /// The orbit that reproduces `camera` (its up vector becomes +Y).
    pub fn from_camera(camera: &Camera) -> OrbitCamera {
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-4);
        let d = offset / distance;
        OrbitCamera {
            target: camera.target,
            yaw: d.x.atan2(d.z),
            pitch: d.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH),
            distance,
            fov_y_deg: camera.fov_y_deg,
        }
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance
    }

    /// As a scene camera (what the CPU renderer takes).
    pub fn camera(&self) -> Camera {
        Camera {
            name: "viewer".into(),
            position: self.eye(),
            target: self.target,
            up: Vec3::Y,
            fov_y_deg: self.fov_y_deg,
        }
    }

    /// Orbits by `dx`, `dy` radians (yaw, pitch).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx;
        self.pitch = (self.pitch + dy).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Pans the target by a fraction `dx`, `dy` of the view's height at the target.
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let forward = (self.target - self.eye()).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        let scale = 2.0 * self.distance * (self.fov_y_deg.to_radians() * 0.5).tan();
        self.target += (-right * dx + up * dy) * scale;
    }

    /// Moves toward the target by `factor` (< 1: closer).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(1e-3, 1e6);
        }
    }

    /// The view-projection matrix for an image of `aspect` = width / height, exactly as the
    /// CPU renderer builds it.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        vcut_shade::image::view_projection(&self.camera(), aspect)
    }

    /// The world-space ray through pixel position (`x`, `y`) (pixels from the top left) of a
    /// `width × height` image: origin and unit direction.
    pub fn ray(&self, x: f32, y: f32, width: f32, height: f32) -> (Vec3, Vec3) {
        let inv = self.view_projection(width / height.max(1.0)).inverse();
        let ndc = Vec3::new(x / width.max(1.0) * 2.0 - 1.0, 1.0 - y / height.max(1.0) * 2.0, 1.0);
        let far = inv.project_point3(ndc);
        let eye = self.eye();
        (eye, (far - eye).normalize_or_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_round_trips_a_scene_camera() {
        let cam = Camera {
            name: "c".into(),
            position: Vec3::new(1.0, 2.0, 6.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            up: Vec3::Y,
            fov_y_deg: 35.0,
        };
        let orbit = OrbitCamera::from_camera(&cam);
        assert!((orbit.eye() - cam.position).length() < 1e-5, "{:?}", orbit.eye());
        let vp = orbit.view_projection(1.5);
        let cpu = vcut_shade::image::view_projection(&cam, 1.5);
        assert!(vp.abs_diff_eq(cpu, 1e-4));
    }

    #[test]
    fn the_centre_ray_hits_the_target_and_picks_a_facing_triangle() {
        let cam = Camera {
            name: "c".into(),
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 40.0,
        };
        let orbit = OrbitCamera::from_camera(&cam);
        let (o, d) = orbit.ray(320.0, 240.0, 640.0, 480.0);
        assert!((d - Vec3::NEG_Z).length() < 1e-4);
        let t = ray_triangle(o, d, Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
        assert!((t.unwrap() - 5.0).abs() < 1e-4);
        // A ray off to the side misses.
        let (o, d) = orbit.ray(10.0, 10.0, 640.0, 480.0);
        assert!(ray_triangle(o, d, Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::Y).is_none());
        assert_eq!(ray_plane(o, d, Vec3::new(0.0, -1.0, 0.0), Vec3::Y), None, "a ray upward never meets the floor");
        let (o, d) = orbit.ray(10.0, 470.0, 640.0, 480.0);
        let p = ray_plane(o, d, Vec3::new(0.0, -1.0, 0.0), Vec3::Y).unwrap();
        assert!((p.y + 1.0).abs() < 1e-4 && p.x < 0.0, "{p}");
    }

    #[test]
    fn pitch_stays_off_the_poles() {
        let mut orbit = OrbitCamera { target: Vec3::ZERO, yaw: 0.0, pitch: 0.0, distance: 3.0, fov_y_deg: 40.0 };
        orbit.orbit(0.3, 10.0);
        assert!(orbit.pitch <= MAX_PITCH);
        let e = orbit.eye();
        assert!(e.is_finite() && (e.length() - 3.0).abs() < 1e-4);
        orbit.zoom(0.5);
        assert!((orbit.eye().length() - 1.5).abs() < 1e-4);
        orbit.zoom(f32::NAN);
        assert!((orbit.distance - 1.5).abs() < 1e-6);
    }
}
