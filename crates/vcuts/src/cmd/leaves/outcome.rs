//! What `vcuts leaves` reports: the plant, its leaf data and how the estimate compared, a
//! frame's costs, the images, the levels of detail and the reference's errors.

use super::data::{AgainstOutcome, LeafEstimateOutcome, Precomputed, StoreOutcome};
use super::frame::{FrameFigures, LodOutcome};
use super::plant::PlantArgs;
use glam::Vec3;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};
use std::path::PathBuf;
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::scene::LeafScene;

/// Everything `vcuts leaves` measured and wrote, in the order it happens.
#[derive(Debug, Clone, Serialize)]
pub struct LeavesOutcome {
    /// The plant, its material and the sun.
    #[serde(flatten)]
    pub plant: PlantOutcome,
    /// The leaf data's estimate (when computed, or a dry run's).
    #[serde(flatten)]
    pub estimate: Option<LeafEstimateOutcome>,
    /// How the estimate compared (when computed).
    #[serde(flatten)]
    pub against: Option<AgainstOutcome>,
    /// Where the leaf data is and what was done to get it.
    #[serde(flatten)]
    pub store: Option<StoreOutcome>,
    /// The leaf data's times and sizes.
    #[serde(flatten)]
    pub data: Option<DataOutcome>,
    /// A frame's costs.
    #[serde(flatten)]
    pub frame: Option<FrameFigures>,
    /// Vertices whose sun comes from rays (a shadow edge between the maps).
    pub sun_edge_vertices: Option<usize>,
    /// The two passes' image.
    pub png_lvc_prt: Option<PathBuf>,
    /// The SH-only image.
    pub png_sh_only: Option<PathBuf>,
    /// The levels of detail.
    #[serde(flatten)]
    pub lod: Option<LodOutcome>,
    /// The reference's errors.
    #[serde(flatten)]
    pub reference: Option<ReferenceOutcome>,
    /// The reference's image (when it covers every vertex).
    pub png_reference: Option<PathBuf>,
}

impl LeavesOutcome {
    /// The outcome so far: the plant.
    pub fn new(plant: PlantOutcome) -> LeavesOutcome {
        LeavesOutcome {
            plant,
            estimate: None,
            against: None,
            store: None,
            data: None,
            frame: None,
            sun_edge_vertices: None,
            png_lvc_prt: None,
            png_sh_only: None,
            lod: None,
            reference: None,
            png_reference: None,
        }
    }

    /// The leaf data's figures: estimate, store, times and sizes.
    pub fn data(&mut self, pre: &Precomputed) {
        if let Some((e, a)) = &pre.estimate {
            (self.estimate, self.against) = (Some(e.clone()), Some(a.clone()));
        }
        self.store = Some(StoreOutcome::of(pre));
        let lvc = &pre.data.lvc;
        self.data = Some(DataOutcome {
            lvc_s: pre.seconds.0,
            lvc_raw_bytes: lvc.raw_bytes() as u64,
            lvc_rle_bytes: lvc.compressed_bytes() as u64,
            rle_ratio: lvc.raw_bytes() as f64 / lvc.compressed_bytes().max(1) as f64,
            prt_s: pre.seconds.1,
            transfer_bytes: pre.data.transfer.bytes() as u64,
        });
    }
}

/// The plant, its leaf material and the sun.
#[derive(Debug, Clone, Serialize)]
pub struct PlantOutcome {
    /// Its source.
    pub plant: String,
    /// Its vertices.
    pub vertices: usize,
    /// Its triangles.
    pub triangles: usize,
    /// The leaves' absorption (per mm).
    pub leaf_sigma_a: [f32; 3],
    /// The leaves' scattering (per mm).
    pub leaf_sigma_s: [f32; 3],
    /// The leaves' thickness.
    pub leaf_thickness_mm: f32,
    /// Seconds to build or load it.
    pub scene_s: f64,
    /// The sun's direction.
    pub sun_dir: [f32; 3],
}

impl PlantOutcome {
    /// The keys of the plant `args` name, built as `scene` with `material` in `scene_s`, lit
    /// by a sun from `sun_dir`.
    pub fn of(args: &PlantArgs, scene: &LeafScene, material: &LeafMaterial, scene_s: f64, sun_dir: Vec3) -> Self {
        PlantOutcome {
            plant: args.plant.to_string(),
            vertices: scene.vertex_count(),
            triangles: scene.triangles().len(),
            leaf_sigma_a: material.sigma_a.to_array(),
            leaf_sigma_s: material.sigma_s.to_array(),
            leaf_thickness_mm: material.thickness,
            scene_s,
            sun_dir: sun_dir.to_array(),
        }
    }
}

/// The leaf data's times and sizes.
#[derive(Debug, Clone, Serialize)]
pub struct DataOutcome {
    /// Seconds of the maps (0 when loaded).
    pub lvc_s: f64,
    /// The maps' bytes uncompressed.
    pub lvc_raw_bytes: u64,
    /// The maps' bytes run-length coded.
    pub lvc_rle_bytes: u64,
    /// Their ratio.
    pub rle_ratio: f64,
    /// Seconds of the transfer (0 when loaded).
    pub prt_s: f64,
    /// The transfer's bytes.
    pub transfer_bytes: u64,
}

/// The path-traced reference and the renderer's errors against it.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceOutcome {
    /// Seconds to trace it.
    pub reference_s: f64,
    /// Vertices it covers.
    pub reference_vertices: usize,
    /// Its own noise (relative L2).
    pub reference_noise_rel_l2: f64,
    /// The two passes against it.
    pub rel_l2_lvc_prt: f64,
    /// The SH alone against it.
    pub rel_l2_sh_only: f64,
    /// The same per object: `rel_l2_lvc_prt_<object>`, `rel_l2_sh_only_<object>`.
    #[serde(flatten)]
    pub per_object: Named,
    /// Per light path (`--breakdown`): `breakdown_<part>_rel_l2`, `…_share_of_whole`,
    /// `…_weight`.
    #[serde(flatten)]
    pub breakdown: Named,
}

impl ReferenceOutcome {
    /// A reference traced in `seconds` at `vertices` vertices with `noise`; errors to fill.
    pub fn new(seconds: f64, vertices: usize, noise: f64) -> ReferenceOutcome {
        ReferenceOutcome {
            reference_s: seconds,
            reference_vertices: vertices,
            reference_noise_rel_l2: noise,
            rel_l2_lvc_prt: f64::NAN,
            rel_l2_sh_only: f64::NAN,
            per_object: Named::default(),
            breakdown: Named::default(),
        }
    }
}

/// Figures under names made from what they measure (an object's, a light path's).
#[derive(Debug, Clone, Default)]
pub struct Named(pub Vec<(String, f64)>);

impl Serialize for Named {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}
