//! Screen-space directional occlusion (Ritschel, Grosch, Seidel 2009) and SSAO beside it, on
//! the CPU: the far "speed" end of the trade — no precomputation, fully dynamic geometry.
//!
//! 1. [`gbuffer::GBuffer`]: per pixel the nearest surface and the next one behind it (depth
//!    peeling, one pass), each with position, normal, albedo and view depth.
//! 2. [`light`]: the sun split off the environment map (a known strong light, shadowed by a
//!    [`light::ShadowMap`] as the paper does) and the rest pre-filtered to the samples' cone.
//! 3. [`samples::SampleSets`]: M Halton (2, 3, 5) sets of N points in the unit half-ball, one per
//!    pixel by a 4 × 4 interleaved pattern.
//! 4. [`ssdo::render`]: per pixel N samples at distances λ ∈ (0, r_max] in the normal's
//!    hemisphere, each projected into the image and occluded when the stored surface there is
//!    nearer the camera (within a depth limit, or — peeled — between the first and second
//!    layer). SSDO: L_dir = Σ ρ/π L_in(ω_i) V_i cos θ_i Δω, Δω = 2π/N, plus the sun; then
//!    L_ind = Σ ρ/π L_pixel (1 − V_i) A_s cos θ_s cos θ_r / d², A_s = π r_max²/N, d² clamped
//!    below at r_max²/2 (so the N patches never subtend more than 2π), back-facing senders
//!    ignored. SSAO: ρ/π E_env(n) · (visible share, cosine-weighted), plus the sun.
//!    Both are blurred by the geometry-aware separable [`ssdo::blur`].
//! 5. [`reference::reference`]: ray-traced direct light with visibility plus one diffuse
//!    bounce, to measure them against.
//!
//! With the feature `gpu`, `gpu::GpuSsdo` runs the same passes as WGSL on any wgpu adapter
//! (lavapipe and llvmpipe included) over the same inputs, so the two images can be compared.

pub mod gbuffer;
#[cfg(feature = "gpu")]
pub mod gpu;
#[cfg(feature = "gpu")]
pub mod gpu_timing;
pub mod light;
pub mod reference;
pub mod samples;
pub mod ssdo;

pub use gbuffer::{GBuffer, Object, Surface};
pub use light::{Prefiltered, ShadowMap, Sun, split_sun};
pub use reference::{ReferenceParams, reference, rel_l2};
pub use samples::SampleSets;
pub use ssdo::{Lighting, Method, Output, Params, render};
