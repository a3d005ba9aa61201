//! vk-render: classic BRDFs rendered through a real Vulkan rasterizer, offscreen, on lavapipe or any GPU.
//!
//! The pieces, in the order a render uses them: [`scene`] reads and validates a scene file (no GPU
//! types), [`mesh`] builds the geometry, [`render`] draws it with Vulkan through the owners of
//! [`vulkan`], and [`pictures::output`] applies the output transform and writes PNG or EXR files. [`brdf`] is the
//! Rust mirror of the GLSL reflectance models in `shaders/brdf/`.

#![deny(missing_docs)]

pub mod analysis;
pub mod brdf;
pub mod check;
pub mod environment;
pub mod error;
pub mod export;
pub mod files;
pub mod interrupt;
pub mod mesh;
pub mod parallel;
pub mod pictures;
#[cfg(feature = "preview")]
pub mod preview;
pub mod reference;
pub mod render;
pub mod scene;
pub mod vulkan;

pub use error::{Error, Result};
pub use pictures::output::HdrImage;
pub use render::{Renderer, RendererOptions};
pub use scene::{Override, Scene};
