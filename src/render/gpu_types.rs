//! The forward pass's GPU data, byte for byte as `shaders/common/scene.glsl` declares it.

use glam::camera::rh::proj::vulkan;
use glam::{Mat4, Vec3};

use crate::brdf::{Brdf, DiffuseModel};
use crate::scene::{Camera, ImageSettings, Object, PointLight, ShadowFilter, Shape};

/// `Frame` (std140).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GpuFrame {
    pub view_projection: [[f32; 4]; 4],
    pub camera_position: [f32; 4],
    pub light_count: u32,
    /// The angle a shadow-map texel subtends at the centre of a cube face: 2 / size.
    pub shadow_texel_angle: f32,
    /// 0: hard shadows, 1: PCF.
    pub shadow_filter: u32,
    pub pad: u32,
}

/// `PointLight` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuPointLight {
    pub position: [f32; 4],
    pub radiance: [f32; 4],
    /// x: the light's cube in the shadow cube array, or -1 for a light that casts no shadows.
    pub shadow: [i32; 4],
}

/// `Material` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuMaterial {
    pub kd: [f32; 4],
    pub ks: [f32; 4],
    pub f0: [f32; 4],
    pub brdf: u32,
    pub shininess: f32,
    pub sigma: f32,
    pub roughness: f32,
    pub metalness: f32,
    pub diffuse: u32,
    pub pad: [u32; 2],
}

/// `ObjectData` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuObject {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
    pub material: GpuMaterial,
    pub flags: [u32; 4],
}

/// The BRDF ids of `shaders/common/brdf.glsl`.
pub const BRDF_LAMBERT: u32 = 0;
pub const BRDF_OREN_NAYAR: u32 = 1;
pub const BRDF_PHONG: u32 = 2;
pub const BRDF_BLINN_PHONG: u32 = 3;
pub const BRDF_COOK_TORRANCE: u32 = 4;
/// The diffuse ids under a Cook-Torrance lobe.
pub const DIFFUSE_OREN_NAYAR: u32 = 0;
pub const DIFFUSE_LAMBERT: u32 = 1;

impl GpuFrame {
    /// The camera's view-projection for an image of `aspect` = width / height.
    ///
    /// Reverse-Z with an infinite far plane: depth is near / distance, 1 at the near plane and 0 at infinity,
    /// so the plane's vertices at infinity land exactly on the far end and float depth keeps its precision.
    /// glam's Vulkan projection also flips y, Vulkan's clip space having y pointing down the image.
    pub fn new(camera: &Camera, aspect: f32, image: &ImageSettings, light_count: usize, near: f32) -> Self {
        let projection = vulkan::perspective_infinite_reverse(camera.fov_y.to_radians(), aspect, near);
        Self {
            view_projection: (projection * camera.view()).to_cols_array_2d(),
            camera_position: camera.position.extend(1.0).into(),
            light_count: light_count as u32,
            shadow_texel_angle: 2.0 / image.shadow_map_size as f32,
            shadow_filter: match image.shadow_filter {
                ShadowFilter::Hard => 0,
                ShadowFilter::Pcf => 1,
            },
            pad: 0,
        }
    }
}

impl GpuPointLight {
    /// A light whose shadow cube is `shadow_slot` in the cube array, if it casts shadows.
    pub fn new(light: &PointLight, shadow_slot: Option<usize>) -> Self {
        Self {
            position: light.position.extend(1.0).into(),
            radiance: (light.color * light.power).extend(0.0).into(),
            shadow: [shadow_slot.map_or(-1, |slot| slot as i32), 0, 0, 0],
        }
    }
}

impl From<&Brdf> for GpuMaterial {
    fn from(brdf: &Brdf) -> Self {
        let rgb = |v: Vec3| v.extend(0.0).to_array();
        let base = GpuMaterial::default();
        match *brdf {
            Brdf::Lambert { kd } => GpuMaterial { brdf: BRDF_LAMBERT, kd: rgb(kd), ..base },
            Brdf::OrenNayar { kd, sigma } => GpuMaterial { brdf: BRDF_OREN_NAYAR, kd: rgb(kd), sigma, ..base },
            Brdf::Phong { kd, ks, shininess } => {
                GpuMaterial { brdf: BRDF_PHONG, kd: rgb(kd), ks: rgb(ks), shininess, ..base }
            }
            Brdf::BlinnPhong { kd, ks, shininess } => {
                GpuMaterial { brdf: BRDF_BLINN_PHONG, kd: rgb(kd), ks: rgb(ks), shininess, ..base }
            }
            Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse } => GpuMaterial {
                brdf: BRDF_COOK_TORRANCE,
                kd: rgb(kd),
                f0: rgb(f0),
                roughness,
                metalness,
                diffuse: match diffuse {
                    DiffuseModel::OrenNayar => DIFFUSE_OREN_NAYAR,
                    DiffuseModel::Lambert => DIFFUSE_LAMBERT,
                },
                ..base
            },
        }
    }
}

impl GpuObject {
    /// An object placed by `model`.
    pub fn new(object: &Object, model: Mat4) -> Self {
        let two_sided = matches!(object.shape, Shape::Plane { .. });
        let exact_sphere = matches!(object.shape, Shape::Sphere { .. });
        Self {
            model: model.to_cols_array_2d(),
            normal_matrix: model.inverse().transpose().to_cols_array_2d(),
            material: GpuMaterial::from(&object.brdf),
            flags: [u32::from(two_sided), u32::from(exact_sphere), 0, 0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_match_the_glsl_layouts() {
        // std140 Frame: mat4 (64) + vec4 (16) + uint padded to 16.
        assert_eq!(std::mem::size_of::<GpuFrame>(), 96);
        assert_eq!(std::mem::size_of::<GpuPointLight>(), 48);
        // std430 Material: 3 vec4 (48) + 8 scalars (32).
        assert_eq!(std::mem::size_of::<GpuMaterial>(), 80);
        assert_eq!(std::mem::size_of::<GpuObject>(), 64 + 64 + 80 + 16);
    }
}
