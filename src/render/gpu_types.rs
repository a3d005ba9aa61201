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
    use std::collections::HashMap;
    use std::mem::{offset_of, size_of};

    use super::*;
    use crate::vulkan::{ShaderCompiler, ShaderSources};

    /// What the compiled GLSL says of its structs: each member's byte offset by struct and member name, and
    /// the array stride of each runtime array by its element's struct name. Read from the SPIR-V's own
    /// decorations (the compiler keeps names: it generates debug information).
    struct SpirvLayouts {
        offsets: HashMap<(String, String), u32>,
        strides: HashMap<String, u32>,
    }

    fn spirv_layouts(spirv: &[u32]) -> SpirvLayouts {
        const OP_NAME: u32 = 5;
        const OP_MEMBER_NAME: u32 = 6;
        const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
        const OP_DECORATE: u32 = 71;
        const OP_MEMBER_DECORATE: u32 = 72;
        const DECORATION_ARRAY_STRIDE: u32 = 6;
        const DECORATION_OFFSET: u32 = 35;
        let text = |words: &[u32]| -> String {
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).take_while(|&b| b != 0).collect();
            String::from_utf8(bytes).unwrap()
        };
        let (mut names, mut member_names, mut element_of) = (HashMap::new(), HashMap::new(), HashMap::new());
        let (mut member_offsets, mut array_strides) = (Vec::new(), Vec::new());
        let mut at = 5; // past the header
        while at < spirv.len() {
            let (count, opcode) = ((spirv[at] >> 16) as usize, spirv[at] & 0xffff);
            let operands = &spirv[at + 1..at + count];
            match opcode {
                OP_NAME => drop(names.insert(operands[0], text(&operands[1..]))),
                OP_MEMBER_NAME => drop(member_names.insert((operands[0], operands[1]), text(&operands[2..]))),
                OP_TYPE_RUNTIME_ARRAY => drop(element_of.insert(operands[0], operands[1])),
                OP_MEMBER_DECORATE if operands[2] == DECORATION_OFFSET => {
                    member_offsets.push((operands[0], operands[1], operands[3]));
                }
                OP_DECORATE if operands[1] == DECORATION_ARRAY_STRIDE => array_strides.push((operands[0], operands[2])),
                _ => {}
            }
            at += count;
        }
        let offsets = member_offsets
            .into_iter()
            .map(|(id, member, offset)| ((names[&id].clone(), member_names[&(id, member)].clone()), offset))
            .collect();
        let strides = array_strides
            .into_iter()
            .filter_map(|(id, stride)| Some((names.get(element_of.get(&id)?)?.clone(), stride)))
            .collect();
        SpirvLayouts { offsets, strides }
    }

    /// Asserts that every member of the GLSL struct `glsl` is at the offset `rust` gives for it, and that
    /// the struct has no member `rust` leaves out.
    fn assert_offsets(layouts: &SpirvLayouts, glsl: &str, rust: &[(&str, usize)]) {
        let members: HashMap<&str, u32> =
            layouts.offsets.iter().filter(|((s, _), _)| s == glsl).map(|((_, m), &o)| (m.as_str(), o)).collect();
        assert_eq!(members.len(), rust.len(), "{glsl}: the GLSL has members {members:?}");
        for &(member, offset) in rust {
            assert_eq!(members.get(member).map(|&o| o as usize), Some(offset), "{glsl}.{member}");
        }
    }

    #[test]
    fn field_offsets_match_the_glsl_layouts() {
        let compiler = ShaderCompiler::new(ShaderSources::default()).unwrap();
        let layouts = spirv_layouts(&compiler.compile("forward.frag").unwrap());
        assert_offsets(
            &layouts,
            "Frame",
            &[
                ("view_projection", offset_of!(GpuFrame, view_projection)),
                ("camera_position", offset_of!(GpuFrame, camera_position)),
                ("light_count", offset_of!(GpuFrame, light_count)),
                ("shadow_texel_angle", offset_of!(GpuFrame, shadow_texel_angle)),
                ("shadow_filter", offset_of!(GpuFrame, shadow_filter)),
            ],
        );
        assert_offsets(
            &layouts,
            "PointLight",
            &[
                ("position", offset_of!(GpuPointLight, position)),
                ("radiance", offset_of!(GpuPointLight, radiance)),
                ("shadow", offset_of!(GpuPointLight, shadow)),
            ],
        );
        assert_offsets(
            &layouts,
            "Material",
            &[
                ("kd", offset_of!(GpuMaterial, kd)),
                ("ks", offset_of!(GpuMaterial, ks)),
                ("f0", offset_of!(GpuMaterial, f0)),
                ("brdf", offset_of!(GpuMaterial, brdf)),
                ("shininess", offset_of!(GpuMaterial, shininess)),
                ("sigma", offset_of!(GpuMaterial, sigma)),
                ("roughness", offset_of!(GpuMaterial, roughness)),
                ("metalness", offset_of!(GpuMaterial, metalness)),
                ("diffuse", offset_of!(GpuMaterial, diffuse)),
                ("pad0", offset_of!(GpuMaterial, pad)),
                ("pad1", offset_of!(GpuMaterial, pad) + 4),
            ],
        );
        assert_offsets(
            &layouts,
            "ObjectData",
            &[
                ("model", offset_of!(GpuObject, model)),
                ("normal_matrix", offset_of!(GpuObject, normal_matrix)),
                ("material", offset_of!(GpuObject, material)),
                ("flags", offset_of!(GpuObject, flags)),
            ],
        );
        // The storage buffers' arrays step by the Rust structs' sizes.
        assert_eq!(layouts.strides.get("PointLight"), Some(&(size_of::<GpuPointLight>() as u32)));
        assert_eq!(layouts.strides.get("ObjectData"), Some(&(size_of::<GpuObject>() as u32)));
    }

    #[test]
    fn a_moved_glsl_member_is_caught() {
        // The check itself can fail: swap two members of Material in the GLSL.
        let material = include_str!("../../shaders/common/material.glsl");
        let swapped = material.replace("float shininess;\n    float sigma;", "float sigma;\n    float shininess;");
        assert_ne!(swapped, material);
        let sources = ShaderSources::default().with_file("common/material.glsl", swapped);
        let compiler = ShaderCompiler::new(sources).unwrap();
        let layouts = spirv_layouts(&compiler.compile("forward.frag").unwrap());
        let shininess = layouts.offsets[&("Material".to_string(), "shininess".to_string())];
        assert_ne!(shininess as usize, offset_of!(GpuMaterial, shininess));
    }
}
