//! `relief view`: the persistent renderer in a window. Only this module touches a window system;
//! nothing else in relief opens a window or needs a display library at run time (winit loads
//! its X11 libraries when a viewer starts).
//!
//! - [`app`]: the event loop, window, device context and frame loop;
//! - [`presenter`]: swapchain, blit of the renderer's colour target, presentation, screenshots;
//! - [`camera_rig`]: orbit and fly cameras;
//! - [`knobs`]: the method, shadow, AO, LOD and depth switches;
//! - [`controls`]: which key does what;
//! - [`overlay`]: the readout in the title.

pub mod app;
pub mod camera_rig;
pub mod controls;
pub mod knobs;
pub mod overlay;
pub mod presenter;

pub use app::{run, ViewError, ViewReport, ViewSetup};
pub use camera_rig::{CameraRig, RigMode};
pub use knobs::Knobs;
pub use presenter::{Presented, Presenter, Screenshot};
