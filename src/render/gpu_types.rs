//! The forward pass's GPU data, byte for byte as `shaders/common/scene.glsl` declares it.

use glam::camera::rh::proj::vulkan;
use glam::{Mat4, Vec3, Vec4};

use super::analytic::AnalyticValues;
use super::measured::MeasuredTables;
use crate::brdf::{Brdf, DiffuseModel};
use crate::scene::{Camera, ImageSettings, Object, PointLight, Shape, View};

/// `Frame`, the forward pass's uniform block (std140; every member here is laid out as std430 would too).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GpuFrame {
    /// World to clip, column-major: reverse-Z with an infinite far plane, y flipped (see [`GpuFrame::new`]).
    pub view_projection: [[f32; 4]; 4],
    /// The camera ray through framebuffer position (x, y) is `pixel_rays * (x, y, 1, 0)`: see [`PixelRays`].
    pub pixel_rays: [[f32; 4]; 4],
    /// The eye in world space, w = 1.
    pub camera_position: [f32; 4],
    /// The image's background colour, alpha 1.
    pub background: [f32; 4],
    /// The angle a shadow-map texel subtends at the centre of a cube face: 2 / size.
    pub shadow_texel_angle: f32,
    /// The exact mode: the first sample of this pass (a pass takes `SAMPLES_PER_PASS`).
    pub environment_first_sample: u32,
    /// Padding: keeps `environment` on a 16-byte boundary.
    pub pad: [u32; 2],
    /// The environment: cos and sin of its rotation, its intensity, and 0.
    pub environment: [f32; 4],
}

/// One entry of an object's albedo table (`AlbedoEntry`, std430): the directional albedo of its diffuse
/// and of its specular lobe at one cos(theta_o).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuAlbedoEntry {
    /// rgb: the diffuse lobe's directional albedo (linear); w unused.
    pub diffuse: [f32; 4],
    /// rgb: the specular lobe's directional albedo (linear); w unused.
    pub specular: [f32; 4],
}

/// `PointLight` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuPointLight {
    /// World-space position, w = 1.
    pub position: [f32; 4],
    /// rgb = colour * power (incident radiance at distance d is radiance / d^2); w = 0.
    pub radiance: [f32; 4],
    /// x: the light's cube in the shadow cube array, or -1 for a light that casts no shadows; y: the faces
    /// of its cube that are drawn (bit i for face i).
    pub shadow: [i32; 4],
}

/// `Material` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuMaterial {
    /// Diffuse reflectance, linear rgb in `[0, 1]`; w unused.
    pub kd: [f32; 4],
    /// Phong's and Blinn-Phong's specular reflectance, linear rgb; w unused.
    pub ks: [f32; 4],
    /// Cook-Torrance's Fresnel reflectance at normal incidence, linear rgb; w unused.
    pub f0: [f32; 4],
    /// Which model: one of the `BRDF_*` ids.
    pub brdf: u32,
    /// Phong's and Blinn-Phong's exponent.
    pub shininess: f32,
    /// Oren-Nayar's sigma, the facets' slope in radians.
    pub sigma: f32,
    /// Cook-Torrance's roughness in (0, 1] (GGX's alpha is its square).
    pub roughness: f32,
    /// Cook-Torrance's metalness in `[0, 1]`.
    pub metalness: f32,
    /// Under Cook-Torrance: the diffuse lobe, [`DIFFUSE_OREN_NAYAR`] or [`DIFFUSE_LAMBERT`].
    pub diffuse: u32,
    /// Under `BRDF_MEASURED`: the material's table in the measured tables' buffer, with [`MEASURED_SAMPLED`]
    /// when the exact mode draws from its sampler.
    pub measured: u32,
    /// Under `BRDF_ANALYTIC`: the first of the material's values in the analytic values' buffer.
    pub analytic: u32,
}

/// `ObjectData` (std430).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuObject {
    /// Object to world, column-major.
    pub model: [[f32; 4]; 4],
    /// The inverse transpose of `model`, whose upper 3 x 3 transforms normals.
    pub normal_matrix: [[f32; 4]; 4],
    /// The object's material.
    pub material: GpuMaterial,
    /// x: two-sided (1 for planes and command-made triangles: the side the camera sees is shaded);
    /// y: the tangent rule, [`TANGENT_DEFAULT`] or [`TANGENT_PLANE`]; z and w unused.
    pub flags: [u32; 4],
}

/// In [`GpuMaterial::measured`], beside the table's place: the exact mode draws from the table's sampler
/// (`MEASURED_SAMPLED` of `shaders/brdf/measured.glsl`).
pub const MEASURED_SAMPLED: u32 = 1 << 31;

/// The BRDF ids of `shaders/common/brdf.glsl`: this one [`Brdf::Lambert`].
pub const BRDF_LAMBERT: u32 = 0;
/// [`Brdf::OrenNayar`].
pub const BRDF_OREN_NAYAR: u32 = 1;
/// [`Brdf::Phong`].
pub const BRDF_PHONG: u32 = 2;
/// [`Brdf::BlinnPhong`].
pub const BRDF_BLINN_PHONG: u32 = 3;
/// [`Brdf::CookTorrance`].
pub const BRDF_COOK_TORRANCE: u32 = 4;
/// [`Brdf::Measured`]: the material's table is in the measured tables' buffer.
pub const BRDF_MEASURED: u32 = 5;
/// [`Brdf::Analytic`]: a user's `.brdf` model, its values in the analytic values' buffer.
pub const BRDF_ANALYTIC: u32 = 6;
/// [`Brdf::Measured`] of an anisotropic RGL file: its floats in the measured tables' buffer
/// (`shaders/brdf/rgl.glsl`).
pub const BRDF_RGL: u32 = 7;
/// The diffuse ids under a Cook-Torrance lobe: this one [`DiffuseModel::OrenNayar`] (the default).
pub const DIFFUSE_OREN_NAYAR: u32 = 0;
/// [`DiffuseModel::Lambert`].
pub const DIFFUSE_LAMBERT: u32 = 1;

/// The camera rays of an image, unnormalized, as a linear function of the framebuffer position (x right,
/// y down, pixel centres at +0.5): the same rays as the CPU reference's through pixel centres, and through
/// any sample position.
#[derive(Clone, Copy, Debug)]
pub struct PixelRays {
    /// The ray's change per unit of x (right along the image).
    pub per_x: Vec3,
    /// The ray's change per unit of y (down the image).
    pub per_y: Vec3,
    /// The ray through the framebuffer's corner (0, 0).
    pub corner: Vec3,
}

impl PixelRays {
    /// The course's camera frame (w backwards, u right, v up) over an image of `width` x `height`.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let w = (camera.position - camera.look_at).normalize();
        let u = camera.up.cross(w).normalize();
        let v = w.cross(u);
        let half_height = (camera.fov_y.to_radians() * 0.5).tan();
        let half_width = half_height * width as f32 / height as f32;
        Self {
            per_x: u * (2.0 * half_width / width as f32),
            per_y: v * (-2.0 * half_height / height as f32),
            corner: -half_width * u + half_height * v - w,
        }
    }

    /// The unit ray through framebuffer position (x, y).
    pub fn at(&self, x: f32, y: f32) -> Vec3 {
        (self.corner + x * self.per_x + y * self.per_y).normalize()
    }
}

impl GpuFrame {
    /// The camera's view-projection for the image.
    ///
    /// Reverse-Z with an infinite far plane: depth is near / distance, 1 at the near plane and 0 at infinity,
    /// so the plane's vertices at infinity land exactly on the far end and float depth keeps its precision.
    /// glam's Vulkan projection also flips y, Vulkan's clip space having y pointing down the image.
    pub fn new(camera: &Camera, image: &ImageSettings, near: f32) -> Self {
        let aspect = image.width as f32 / image.height as f32;
        let projection = vulkan::perspective_infinite_reverse(camera.fov_y.to_radians(), aspect, near);
        let rays = PixelRays::new(camera, image.width, image.height);
        Self {
            view_projection: (projection * camera.view()).to_cols_array_2d(),
            pixel_rays: [rays.per_x.extend(0.0), rays.per_y.extend(0.0), rays.corner.extend(0.0), glam::Vec4::ZERO]
                .map(|c| c.to_array()),
            camera_position: camera.position.extend(1.0).into(),
            // A term view shows 0 where no object is seen: the background is a radiance.
            background: if image.view == View::Radiance { image.background.extend(1.0) } else { Vec4::W }.into(),
            shadow_texel_angle: 2.0 / image.shadow_map_size as f32,
            environment_first_sample: 0,
            pad: [0; 2],
            environment: [1.0, 0.0, 0.0, 0.0],
        }
    }
}

impl GpuPointLight {
    /// A light whose shadow cube is `shadow`'s slot in the cube array, with the faces drawn, if it casts
    /// shadows.
    pub fn new(light: &PointLight, shadow: Option<(usize, [bool; 6])>) -> Self {
        let (slot, faces) = match shadow {
            Some((slot, seen)) => (slot as i32, (0..6).filter(|&f| seen[f]).map(|f| 1 << f).sum()),
            None => (-1, 0),
        };
        Self {
            position: light.position.extend(1.0).into(),
            radiance: (light.color * light.power).extend(0.0).into(),
            shadow: [slot, faces, 0, 0],
        }
    }
}

/// The id of `brdf` in `shaders/common/brdf.glsl`.
pub fn brdf_id(brdf: &Brdf) -> u32 {
    match brdf {
        Brdf::Lambert { .. } => BRDF_LAMBERT,
        Brdf::OrenNayar { .. } => BRDF_OREN_NAYAR,
        Brdf::Phong { .. } => BRDF_PHONG,
        Brdf::BlinnPhong { .. } => BRDF_BLINN_PHONG,
        Brdf::CookTorrance { .. } => BRDF_COOK_TORRANCE,
        Brdf::Measured(m) if m.table().anisotropic().is_some() => BRDF_RGL,
        Brdf::Measured(_) => BRDF_MEASURED,
        Brdf::Analytic(_) => BRDF_ANALYTIC,
    }
}

/// What the shaders read of a material besides its own fields: the measured tables and the analytic
/// materials' values, each material's at its place.
#[derive(Clone, Copy)]
pub struct MaterialData<'a> {
    /// The measured tables, where [`GpuMaterial::measured`] points.
    pub measured: &'a MeasuredTables,
    /// The analytic materials' values, where [`GpuMaterial::analytic`] points.
    pub analytic: &'a AnalyticValues,
}

/// The tangent rules of `shaders/common/scene.glsl` (an object's `flags.y`): this one the vertices' tangents
/// where they have them, else `default_tangent`.
pub const TANGENT_DEFAULT: u32 = 0;
/// A plane's: the world's +x projected on it (`plane_tangent`).
pub const TANGENT_PLANE: u32 = 1;

/// The id of `brdf`'s diffuse lobe under a Cook-Torrance lobe (`DIFFUSE_*` of `shaders/brdf/cook_torrance.glsl`;
/// unread by the other models, 0).
pub fn diffuse_id(brdf: &Brdf) -> u32 {
    match brdf {
        Brdf::CookTorrance { diffuse: DiffuseModel::Lambert, .. } => DIFFUSE_LAMBERT,
        _ => DIFFUSE_OREN_NAYAR,
    }
}

impl GpuMaterial {
    /// `brdf`'s material, its measured table or analytic values (if any) at their places in `data`.
    pub fn new(brdf: &Brdf, data: MaterialData) -> Self {
        let base = GpuMaterial { brdf: brdf_id(brdf), ..GpuMaterial::default() };
        match *brdf {
            Brdf::Measured(ref table) => GpuMaterial {
                measured: data.measured.slot(table) | if table.sampled() { MEASURED_SAMPLED } else { 0 },
                ..base
            },
            Brdf::Analytic(ref material) => GpuMaterial { analytic: data.analytic.first(material), ..base },
            _ => Self::of_parameters(brdf),
        }
    }

    /// The material of one of the course's models, whose parameters are all its data (a measured or an
    /// analytic material's data lie elsewhere: only its id is set).
    pub fn of_parameters(brdf: &Brdf) -> Self {
        let rgb = |v: Vec3| v.extend(0.0).to_array();
        let base = GpuMaterial { brdf: brdf_id(brdf), ..GpuMaterial::default() };
        match *brdf {
            Brdf::Lambert { kd } => GpuMaterial { kd: rgb(kd), ..base },
            Brdf::OrenNayar { kd, sigma } => GpuMaterial { kd: rgb(kd), sigma, ..base },
            Brdf::Phong { kd, ks, shininess } => GpuMaterial { kd: rgb(kd), ks: rgb(ks), shininess, ..base },
            Brdf::BlinnPhong { kd, ks, shininess } => GpuMaterial { kd: rgb(kd), ks: rgb(ks), shininess, ..base },
            Brdf::CookTorrance { kd, f0, roughness, metalness, .. } => GpuMaterial {
                brdf: BRDF_COOK_TORRANCE,
                kd: rgb(kd),
                f0: rgb(f0),
                roughness,
                metalness,
                diffuse: diffuse_id(brdf),
                ..base
            },
            Brdf::Measured(_) | Brdf::Analytic(_) => base,
        }
    }
}

impl GpuObject {
    /// An object placed by `model`, its material's data in `data`.
    pub fn new(object: &Object, model: Mat4, data: MaterialData) -> Self {
        Self { material: GpuMaterial::new(&object.brdf, data), ..Self::placed(object, model) }
    }

    /// An object placed by `model`, its material left default: its matrices and flags.
    pub fn placed(object: &Object, model: Mat4) -> Self {
        let two_sided = matches!(object.shape, Shape::Plane { .. } | Shape::Triangles(_));
        let tangent = if matches!(object.shape, Shape::Plane { .. }) { TANGENT_PLANE } else { TANGENT_DEFAULT };
        Self {
            model: model.to_cols_array_2d(),
            normal_matrix: model.inverse().transpose().to_cols_array_2d(),
            material: GpuMaterial::default(),
            flags: [u32::from(two_sided), tangent, 0, 0],
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
        let layouts = spirv_layouts(&compiler.compile("forward_sphere.frag+WITH_ENVIRONMENT").unwrap());
        assert_offsets(
            &layouts,
            "Frame",
            &[
                ("view_projection", offset_of!(GpuFrame, view_projection)),
                ("pixel_rays", offset_of!(GpuFrame, pixel_rays)),
                ("camera_position", offset_of!(GpuFrame, camera_position)),
                ("background", offset_of!(GpuFrame, background)),
                ("shadow_texel_angle", offset_of!(GpuFrame, shadow_texel_angle)),
                ("environment_first_sample", offset_of!(GpuFrame, environment_first_sample)),
                ("pad0", offset_of!(GpuFrame, pad)),
                ("pad1", offset_of!(GpuFrame, pad) + 4),
                ("environment", offset_of!(GpuFrame, environment)),
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
                ("measured", offset_of!(GpuMaterial, measured)),
                ("analytic", offset_of!(GpuMaterial, analytic)),
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
        assert_offsets(
            &layouts,
            "AlbedoEntry",
            &[("diffuse", offset_of!(GpuAlbedoEntry, diffuse)), ("specular", offset_of!(GpuAlbedoEntry, specular))],
        );
        // The storage buffers' arrays step by the Rust structs' sizes.
        assert_eq!(layouts.strides.get("PointLight"), Some(&(size_of::<GpuPointLight>() as u32)));
        assert_eq!(layouts.strides.get("ObjectData"), Some(&(size_of::<GpuObject>() as u32)));
        assert_eq!(layouts.strides.get("AlbedoEntry"), Some(&(size_of::<GpuAlbedoEntry>() as u32)));
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

    #[test]
    fn pixel_rays_are_the_reference_cameras_rays() {
        // The reference's rays (src/reference/mod.rs), written out: through pixel centres of a 600 x 400 image.
        let camera = Camera {
            position: Vec3::new(1.0, 2.0, -3.0),
            look_at: Vec3::new(0.5, -0.2, 4.0),
            up: Vec3::Y,
            fov_y: 50.0,
        };
        let (width, height) = (600.0_f32, 400.0_f32);
        let w = (camera.position - camera.look_at).normalize();
        let u = camera.up.cross(w).normalize();
        let v = w.cross(u);
        let half_height = (camera.fov_y.to_radians() * 0.5).tan();
        let half_width = half_height * width / height;
        let rays = PixelRays::new(&camera, 600, 400);
        for (x, y) in [(0.0, 0.0), (599.0, 0.0), (0.0, 399.0), (300.0, 200.0), (123.0, 321.0)] {
            let sx = (2.0 * (x + 0.5) / width - 1.0) * half_width;
            let sy = (1.0 - 2.0 * (y + 0.5) / height) * half_height;
            let reference = (sx * u + sy * v - w).normalize();
            let ray = rays.at(x + 0.5, y + 0.5);
            assert!(ray.abs_diff_eq(reference, 1e-6), "pixel ({x}, {y}): {ray} != {reference}");
        }
        // Row 0 is the top of the image: its rays point more upwards than the bottom row's.
        assert!(rays.at(300.0, 0.5).dot(v) > rays.at(300.0, 399.5).dot(v));
    }
}
