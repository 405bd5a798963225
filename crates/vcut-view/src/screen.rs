//! The screen-space modes of a session: its objects, lighting and camera handed to the WGSL
//! passes of `vcut_ssdo::gpu` (the viewer only chooses the inputs; the passes live beside
//! their CPU twin).

use crate::gpu::{Gpu, ViewError};
use crate::session::{Mode, Session};
use vcut_ssdo::Method;
use vcut_ssdo::gpu::{GpuSsdo, SsdoFrame};

/// Builds, runs and returns the frame `session` shows in a screen-space mode (`None` in the
/// others).
pub fn session_frame(
    gpu: &Gpu,
    passes: &GpuSsdo,
    session: &mut Session,
    size: (u32, u32),
) -> Result<Option<SsdoFrame>, ViewError> {
    let method = match session.mode() {
        Mode::Ssao => Method::Ssao,
        Mode::Ssdo => Method::Ssdo,
        _ => return Ok(None),
    };
    let camera = session.camera.camera();
    let (objects, light, params) = session.screen_space_inputs();
    let frame = passes.frame(gpu, objects, light, &camera, &params, method, size)?;
    frame.run(gpu)?;
    Ok(Some(frame))
}
