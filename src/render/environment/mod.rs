//! Image-based light on the GPU: an environment's irradiance map, its specular map prefiltered
//! per roughness and the BRDF table of the split sum, built by compute kernels once per renderer
//! and read by every drawing pass (`shaders/include/environment_light.glsl`).

mod background_pass;
mod environment_kernels;
mod environment_light;
mod environment_plan;

pub use background_pass::BackgroundPass;
pub(in crate::render) use environment_light::stand_in_binds;
pub use environment_light::{BakedEnvironment, EnvironmentLight};
pub use environment_plan::EnvironmentPlan;
