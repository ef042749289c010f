#![doc = include_str!("guide.md")]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]
#![deny(clippy::undocumented_unsafe_blocks)]

#[macro_use]
mod setters;

#[cfg(feature = "bench")]
pub mod bench;
pub mod cells;
pub mod displaced_reference;
pub mod environment;
pub mod geometry;
pub mod heightfield;
pub mod method;
pub mod render;
pub mod scene;
pub mod shader_library;
pub mod shaders;
pub mod shadow_reference;
pub mod shells;
pub mod srgb;
pub mod terrain;
#[cfg(feature = "window")]
pub mod view;
pub mod vk;
