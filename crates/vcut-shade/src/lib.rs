//! Run-time shading from precomputed visibility cuts.
//!
//! - [`brdf`]: Lambert, normalised Blinn-Phong and Phong, and GGX, evaluated at run time from a
//!   `vcut_scene::Material` (never precomputed: materials are edited live).
//! - [`frame::Frame`]: the scene at run time — per vertex the SVC × the interpolated fields of
//!   the objects that can move relative to it, merged (`vcut-merge`) and cached; moves re-merge
//!   only the vertices whose field inputs changed; B = Σ_k v_k f_r(ω_k, ω_o) l_k with l_k from
//!   the light tree at the merged node's level-order index.
//! - [`sun`]: the sun's few leaves of the light cast by rays at run time instead of carried by
//!   the cuts (the default): exact sun shadows, the sky from the cuts.
//! - [`reference`]: the exact-direction reference and its error metrics.
//! - [`image`]: a headless rasteriser of per-vertex radiance, linear EXR, tone-mapped PNG
//!   (ACES filmic, Narkowicz's fit), and the whole scene as a PLY mesh.
//!
//! # Invariants
//! Merged cuts depend only on translations: moving an object back restores them bit for bit, and
//! BRDF, camera and lighting edits never merge. No GPU: images are rasterised on the CPU.
//!
//! # Example
//! ```no_run
//! use vcut_data::Precomputed;
//! use vcut_shade::frame::Frame;
//! let mut data = Precomputed::open(std::path::Path::new("target/vcuts/teapot-fast.vcuts")).unwrap();
//! let sky = vcut_envmap::procedural::PreethamSky::default().bake(512);
//! let mut frame = Frame::open(&mut data, &sky, &vcut_shade::FrameSettings::default(), None).unwrap();
//! let teapot = frame.object_index("teapot").unwrap();
//! frame.translate(teapot, glam::Vec3::new(1.0, 0.0, 0.0)).unwrap();
//! let radiance = frame.shade(glam::Vec3::new(5.0, 6.0, 10.0));
//! ```

pub mod brdf;
pub mod flat;
pub mod frame;
pub mod glb;
pub mod image;
pub mod measure;
pub mod passes;
pub mod reference;
pub mod sun;

#[cfg(feature = "clap")]
pub use frame::FrameArgs;
pub use frame::{
    BackgroundFrame, BackgroundShading, BackgroundStats, CutFailure, DragStats, FIELD_REACH, FieldReach, FinishedJob,
    FlatEdges, Frame, FrameCaches, FrameError, FrameJob, FrameMemory, FrameObject, FrameSettings, FrameStats,
    INTERACTIVE_EDGE_SHARE, LightChoice, MergeAlgorithm, MoveTiming, Parts, REFINE_REACH, RefineStats, Refinement,
    SettingError, TurnRefusal, Turned,
};
pub use sun::SunRays;
