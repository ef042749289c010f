//! relief: a low-level Vulkan renderer for per-pixel displacement mapping.
//!
//! Layers, data flowing one way: [`heightfield`] (CPU height fields, pyramids, the exact
//! reference), [`terrain`] (height-blended layers, paper 001), [`cells`] (cubic cell complexes,
//! paper 002) and [`scene`] (glTF to plain data) know nothing of Vulkan; [`vk`] knows nothing of relief; [`render`] joins them; [`view`] puts the
//! renderer in a window.
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

pub mod bench;
pub mod cells;
pub mod heightfield;
pub mod method;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod terrain;
pub mod view;
pub mod vk;
