//! Real-time rendering of plant leaves (Wang, Wang, Dorsey, Guo, Shum — SIGGRAPH 2005).
//!
//! Translucent, glossy leaves lit by a sharp sun and a soft sky, in two passes:
//! - [`material`]: the leaf appearance model — a two-sided slab whose diffuse reflectance and
//!   transmittance come from [`slab`] (Kubelka–Munk, stable at every extreme, with its inverse to
//!   fit measured leaves), a Torrance–Sparrow gloss per side, and the per-side parameter maps;
//! - [`lvc`]: the direct sun by light-visibility convolution over 6 × 32 × 32 sun directions,
//!   a byte per vertex and direction, re-binned per direction and run-length encoded ([`rle`]);
//! - [`prt`]: the environment and every bounce (reflected *and* transmitted) by order-5 SH
//!   precomputed radiance transfer ([`sh`]);
//! - [`shade`]: a frame — decode the sun direction's map, add the PRT pass — and the SH-only
//!   rendering it is compared with; [`reference`]: the path-traced reference; [`breakdown`]: the
//!   error per light path against it; [`image`]: pictures of two-sided leaves;
//! - [`lod`]: coarser meshes of each leaf (meshoptimizer) with Gaussian-averaged transfer, chosen
//!   per leaf by its size on screen;
//! - [`plant`]: a procedural plant of any leaf count; [`scene`]: leaves and opaque surfaces
//!   flattened for all of the above;
//! - [`store`]: the maps and the transfer saved in a `.vleaf` file (checksummed sections,
//!   atomic, resumed chunk by chunk after a kill or a full disk) and loaded instead of computed.
//!
//! # Invariants
//! R, T ≥ 0 and R + T ≤ 1 for every slab, whatever its parameters; the LVC maps decode
//! losslessly; the precomputes are deterministic whatever the thread count. This crate knows
//! nothing about visibility cuts: it shares scenes, maps and the ray tracer with them.
//!
//! # Example
//! ```
//! use vcut_leaf::{plant::{plant, PlantParams}, material::LeafMaterial, lvc::{Lvc, LvcParams}};
//! let params = PlantParams { leaves: 4, segments: [4, 2], ..PlantParams::default() };
//! let scene = plant(&params, &LeafMaterial::default()).unwrap();
//! let lvc = Lvc::compute(&scene, &LvcParams { resolution: 4, ..LvcParams::default() }, |_, _| {});
//! let mut map = vec![0u8; scene.vertex_count()];
//! lvc.decode(lvc.sun_index(glam::Vec3::Y), &mut map).unwrap();
//! assert!(lvc.compressed_bytes() <= lvc.raw_bytes());
//! ```

pub mod breakdown;
pub mod image;
pub mod lobe;
pub mod lod;
pub mod lvc;
pub mod material;
pub mod plant;
pub mod prt;
pub mod reference;
pub mod rle;
pub mod scene;
pub mod sh;
pub mod shade;
pub mod slab;
pub mod store;
