//! The `view` section: what a renderer needs of the scene besides its objects — its cameras and
//! its light-error target — so that a `.vcuts` file renders from any folder and on another
//! machine without its scene file. A built-in map travels here as the description that bakes it
//! again (a few hundred bytes instead of megabytes of texels); a map from a file travels
//! embedded in the `environment` section.
//!
//! TOML text: `light_error = REL` when the scene set one; an `[environment]` table with the
//! scene file's keys when the map is built in; then one `[[camera]]` table per camera with the
//! scene file's keys (`name`, `position`, `target`, `up`, `fov_y_deg`). Every value is checked
//! on reading as a scene file's is.

use crate::file::{SectionId, Sections};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::Path;
use vcut_scene::desc::{CameraDesc, EnvironmentDesc};
use vcut_scene::{Budget, Camera, Scene};

/// The scene's cameras, light-error target and, when built in, its map's description.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct View {
    /// The cameras, the default view first.
    pub cameras: Vec<Camera>,
    /// `[environment] light_error`, when the scene set one.
    pub light_error: Option<f64>,
    /// The built-in map's description ([`Scene::environment_recipe`]); `None` when the map
    /// came from a file (then embedded in the `environment` section).
    pub environment: Option<EnvironmentDesc>,
}

/// Why a `view` section could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ViewError {
    /// Not the TOML this module writes.
    #[error("{0}")]
    Toml(String),
    /// A value out of range (the message names the camera and key, as a scene file's would).
    #[error("{0}")]
    Value(String),
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Text {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    light_error: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    environment: Option<EnvironmentDesc>,
    #[serde(default)]
    camera: Vec<CameraDesc>,
}

/// The sections a precompute writes of `scene` besides its objects, so its file renders without
/// the scene file: the `view` (cameras, light-error target, a built-in map's description) and,
/// for a map from a file, the map itself (`environment`).
pub fn scene_sections(scene: &Scene) -> Vec<(SectionId, Vec<u8>)> {
    let view = View::of(scene);
    let mut out = vec![(SectionId::view(), view.text().into_bytes())];
    if view.environment.is_none() {
        out.push((SectionId::environment(), vcut_envmap::embed::encode(&scene.environment)));
    }
    out
}

impl View {
    /// The view of `scene`.
    pub fn of(scene: &Scene) -> View {
        View {
            cameras: scene.cameras.clone(),
            light_error: scene.light_error,
            environment: scene.environment_recipe.clone(),
        }
    }

    /// The section's text.
    pub fn text(&self) -> String {
        let camera = self
            .cameras
            .iter()
            .map(|c| CameraDesc {
                name: c.name.clone(),
                position: c.position.to_array(),
                target: c.target.to_array(),
                up: c.up.to_array(),
                fov_y_deg: c.fov_y_deg,
            })
            .collect();
        let environment = self.environment.clone();
        toml::to_string(&Text { light_error: self.light_error, environment, camera }).unwrap_or_default()
    }

    /// Reads what [`View::text`] wrote, checking every value.
    pub fn parse(text: &str) -> Result<View, ViewError> {
        let t: Text = toml::from_str(text).map_err(|e| ViewError::Toml(e.message().to_string()))?;
        let here = Path::new("view");
        for (i, c) in t.camera.iter().enumerate() {
            c.check(here, i).map_err(|e| ViewError::Value(e.to_string()))?;
        }
        if let Some(e) = t.light_error {
            vcut_scene::check::LIGHT_ERROR
                .check(e)
                .map_err(|reason| ViewError::Value(format!("light_error = {e}: {reason}")))?;
        }
        if let Some(env) = &t.environment {
            if !env.source.starts_with("builtin:") {
                return Err(ViewError::Value(format!(
                    "[environment] source = '{}': only a built-in map is recorded by its description",
                    env.source
                )));
            }
            // Checked against every byte (not the memory free now): baking is the reader's step.
            env.check(here, &Budget::bytes(u64::MAX), &mut 0).map_err(|e| ViewError::Value(e.to_string()))?;
        }
        let cameras = t
            .camera
            .into_iter()
            .map(|c| Camera {
                name: c.name,
                position: Vec3::from(c.position),
                target: Vec3::from(c.target),
                up: Vec3::from(c.up),
                fov_y_deg: c.fov_y_deg,
            })
            .collect();
        Ok(View { cameras, light_error: t.light_error, environment: t.environment })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_round_trip_and_bad_values_are_refused_by_key() {
        let view = View {
            cameras: vec![
                Camera {
                    name: "main \"quoted\"".into(),
                    position: Vec3::new(1.0, 2.5, -3.25),
                    target: Vec3::new(0.1, 0.2, 0.3),
                    up: Vec3::Y,
                    fov_y_deg: 18.0123,
                },
                Camera { name: "b".into(), position: Vec3::Z, target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 40.0 },
            ],
            light_error: Some(0.002),
            environment: Some(EnvironmentDesc {
                sun_elevation_deg: 12.5,
                resolution: 256,
                ..EnvironmentDesc::builtin("builtin:sky").unwrap()
            }),
        };
        assert_eq!(View::parse(&view.text()).unwrap(), view);
        assert_eq!(View::parse(&View::default().text()).unwrap(), View::default());
        let bad = view.text().replace("fov_y_deg = 40.0", "fov_y_deg = 400.0");
        let e = View::parse(&bad).unwrap_err().to_string();
        assert!(e.contains("camera 1 ('b')") && e.contains("fov_y_deg"), "{e}");
        let e = View::parse("light_error = 3.0\n").unwrap_err().to_string();
        assert!(e.contains("light_error"), "{e}");
        assert!(View::parse("colour = 1\n").is_err());
        let e = View::parse(&view.text().replace("turbidity = 3.0", "turbidity = 30.0")).unwrap_err().to_string();
        assert!(e.contains("turbidity"), "{e}");
        let e = View::parse("[environment]\nsource = \"sky.exr\"\n").unwrap_err().to_string();
        assert!(e.contains("built-in"), "{e}");
    }
}
