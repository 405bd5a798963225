//! What the window reads of a frame while its worker may hold it: each object's mesh, name,
//! material, motion and the translation and turn it is drawn at, and the lighting facts the panel shows.
//! A session keeps this beside its [`vcut_shade::BackgroundFrame`], so drawing, picking and the
//! panel never wait for a merge: a dragged object is drawn where the pointer put it at once,
//! with the last shading until the new one arrives.

use glam::Vec3;
use vcut_scene::texture::Texture;
use vcut_scene::{Material, Mesh, Motion};
use vcut_shade::{Frame, LightChoice};

/// One object as the window shows it.
#[derive(Debug, Clone)]
pub struct ShownObject {
    /// Its name.
    pub name: String,
    /// Its mesh at rest (before any turn).
    pub mesh: Mesh,
    /// Its BRDF parameters (as last edited).
    pub material: Material,
    /// Its albedo texture, if any.
    pub texture: Option<Texture>,
    /// Its mean diffuse albedo (`vcut_shade::FrameObject::mean_albedo`).
    pub albedo: Vec3,
    /// Whether it may move.
    pub motion: Motion,
    /// Where it is drawn: the translation last asked for (the frame's, once its moves are done).
    pub translation: Vec3,
    /// The translation the frame's cuts are merged at now (the shading's).
    pub placed: Vec3,
    /// Where it is drawn turned: its yaw about +Y (radians) through `centre`, as last asked for
    /// (the frame's, once its turns are done; `vcut_shade::Frame::turn`).
    pub yaw: f32,
    /// The yaw the frame's cuts are merged at now.
    pub placed_yaw: f32,
    /// What it turns about: the vertical through this point (its bounding-sphere centre at rest).
    pub centre: Vec3,
}

impl ShownObject {
    /// Its mesh turned as it is drawn (at no translation): normals too, for the screen-space
    /// modes.
    pub fn turned_mesh(&self) -> std::borrow::Cow<'_, Mesh> {
        if self.yaw == 0.0 {
            return std::borrow::Cow::Borrowed(&self.mesh);
        }
        let mut mesh = self.mesh.clone();
        mesh.transform(
            glam::Mat4::from_translation(self.centre)
                * glam::Mat4::from_rotation_y(self.yaw)
                * glam::Mat4::from_translation(-self.centre),
        );
        std::borrow::Cow::Owned(mesh)
    }

    /// Its vertex positions where it is drawn: turned, then translated.
    pub fn positions(&self) -> Vec<Vec3> {
        let turn = glam::Quat::from_rotation_y(self.yaw);
        let turned = |p: Vec3| if self.yaw == 0.0 { p } else { turn * (p - self.centre) + self.centre };
        self.mesh.positions().iter().map(|&p| turned(p) + self.translation).collect()
    }
}

/// The lighting facts the panel shows, as of the last lighting or settings change.
#[derive(Debug, Clone, Default)]
pub struct ShownLight {
    /// Why the sun's leaves are those.
    pub choice: LightChoice,
    /// Leaves cast by rays.
    pub sun_leaves: usize,
    /// The direction tree's leaves.
    pub directions: usize,
    /// The target error of the light left in the cuts (`vcut_shade::SunRays::target`).
    pub target: f64,
}

/// Every object of `frame` as shown, at the frame's translations.
pub(crate) fn objects_of(frame: &Frame) -> Vec<ShownObject> {
    (0..frame.object_count())
        .map(|o| {
            let object = frame.object(o);
            ShownObject {
                name: object.name.to_string(),
                mesh: object.rest_mesh().clone(),
                material: *object.material,
                texture: object.textures.base_colour.clone(),
                albedo: object.mean_albedo(),
                motion: object.motion,
                translation: object.translation,
                placed: object.translation,
                yaw: object.yaw,
                placed_yaw: object.yaw,
                centre: object.turn_centre(),
            }
        })
        .collect()
}

/// The lighting facts of `frame`.
pub(crate) fn light_of(frame: &Frame) -> ShownLight {
    ShownLight {
        choice: frame.light_choice().clone(),
        sun_leaves: frame.stats().sun_leaves,
        directions: frame.tree().leaf_count(),
        target: frame.sun_rays().target,
    }
}
