//! The viewer's errors. The device itself is [`vcut_gpu::Gpu`] (re-exported here): what an
//! adapter lacks or refuses comes back as a [`GpuError`] naming the adapter, never a panic.

pub use vcut_gpu::{Gpu, GpuError};

/// Why the viewer could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ViewError {
    /// The GPU device: no adapter, a refused device, a missing capability, a failed operation
    /// or read-back.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// No window system to open a window on.
    #[error(
        "cannot open a window ({0}): no display. Run under a desktop session or Xvfb \
         (`Xvfb :99 & DISPLAY=:99 cargo xtask view …`), or render without a window with \
         `cargo xtask view FILE --screenshot out.png`"
    )]
    NoDisplay(String),
    /// A window or surface error.
    #[error("window: {0}")]
    Window(String),
    /// The leaf session's light-visibility maps could not be decoded.
    #[error("decoding the leaves' light-visibility maps: {0}")]
    Leaves(#[from] vcut_leaf::rle::RleError),
    /// Writing an image.
    #[error(transparent)]
    Image(#[from] vcut_shade::image::ImageError),
}
