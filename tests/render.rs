//! Renders through Vulkan (validation layer on, any message fails) and checks the images.

mod common;

use common::*;
use glam::Vec3;
use vk_render::pictures::compare::Comparison;
use vk_render::pictures::output::{write_image, TexelOrder};

#[test]
fn figure_1_has_the_course_values() {
    let scene = asset_scene("fig1-lambert.toml", &[]);
    let image = render(&scene).to_rgb8(&scene.image);
    // 0.5/pi * 60/4^2 = 0.5968 -> 152; the grey background 0.5 -> 127.
    assert_eq!(image.get_pixel(300, 200).0, [152, 152, 152]);
    assert_eq!(image.get_pixel(5, 5).0, [127, 127, 127]);
    assert_eq!(image.get_pixel(595, 5).0, [127, 127, 127]);
}

#[test]
fn figure_1_matches_the_ray_traced_reference() {
    // The tessellated sphere and the infinite plane shade within one 8-bit level of exact geometry.
    let scene = asset_scene("fig1-lambert.toml", &[]);
    let c = check_against_reference("fig1-lambert", &scene, |c| c.max <= 1);
    assert!(c.compared > 200_000, "{c}");
}

#[test]
fn single_sample_matches_the_reference_too() {
    let scene = asset_scene("fig1-lambert.toml", &["image.samples=1"]);
    check_against_reference("fig1-lambert-1spp", &scene, |c| c.max <= 1);
}

#[test]
fn world_plus_x_is_on_the_left_of_the_image() {
    let scene = asset_scene("fig1-lambert.toml", &["object.0.center=[1.5, 0.0, 3.0]", "object.0.radius=0.5"]);
    let image = render(&scene).to_rgb8(&scene.image);
    // Row 190 is above the horizon, where anything but the sphere is background.
    // x = 1.5 at depth 3 is at tan = 0.5 from the axis; the half-width is tan(30 deg) * 600/400.
    let column = 300.0 - 300.0 * 0.5 / (30f32.to_radians().tan() * 1.5);
    let sphere_at = |x: u32| image.get_pixel(x, 190).0 != [127, 127, 127];
    assert!(sphere_at(column as u32), "no sphere at column {column}");
    assert!(!sphere_at(600 - column as u32), "sphere mirrored to the right");
}

#[test]
fn the_plane_reaches_the_horizon() {
    // A level camera puts the horizon on the centre line: just below it there must be plane, not background.
    let scene = asset_scene("fig1-lambert.toml", &["image.samples=1"]);
    let image = render(&scene).to_rgb8(&scene.image);
    for x in [2u32, 100, 500, 597] {
        assert_eq!(image.get_pixel(x, 199).0, [127, 127, 127], "sky at column {x}");
        assert_eq!(image.get_pixel(x, 200).0[2], 0, "plane (no blue) just below the horizon at column {x}");
    }
}

#[test]
fn the_same_scene_gives_the_same_bytes() {
    let scene = asset_scene("fig1-lambert.toml", &[]);
    let first = render(&scene);
    let second = render(&scene);
    assert!(first
        .pixels
        .iter()
        .zip(&second.pixels)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
}

#[test]
fn the_resolve_pass_writes_the_hosts_levels() {
    // PNGs and the preview's frames take the course's output transform from the resolve pass
    // (shaders/resolve.comp), in every texel order: byte for byte what the host's encoding of the radiance
    // gives, at any exposure (far above 1 saturates) and sample count; the other transforms and the term
    // views are encoded by the host. Caught when broken on purpose: rounding instead of truncating, the
    // exposure left out, the clamp left out, B and R not swapped. (One sample in place of the mean is
    // caught by a_sphere_covers_and_shades_the_exact_sphere_at_every_sample.)
    let cases: [(&str, &[&str]); 9] = [
        ("fig1-lambert.toml", &[]),
        // 35 pixels: the last four-pixel texel of the levels holds three.
        ("fig1-lambert.toml", &["image.width=7", "image.height=5"]),
        ("fig1-lambert.toml", &["image.exposure=2.7"]),
        ("fig1-lambert.toml", &["image.exposure=0.37", "image.samples=1"]),
        ("fig4-gold-metalness-0.5.toml", &["image.exposure=1.3"]),
        ("fig5-golden-bunny.toml", &["image.width=300", "image.height=200"]),
        ("fig6-blinn-phong.toml", &["image.exposure=13"]),
        ("fig3-plastic-s-32.toml", &["image.encoding=\"srgb\"", "image.tonemap=\"aces\""]),
        ("fig3-plastic-s-32.toml", &["image.view=\"specular\""]),
    ];
    for (file, overrides) in cases {
        let scene = asset_scene(file, overrides);
        let expected = render(&scene).to_rgb8(&scene.image);
        for order in [TexelOrder::Rgb, TexelOrder::Rgba, TexelOrder::Bgra] {
            let mut texels = vec![0; expected.as_raw().len() / 3 * order.bytes()];
            renderer().render_texels(&scene, order, &mut texels).expect("render with no validation message");
            let differ = expected.pixels().zip(texels.chunks_exact(order.bytes())).filter(|(rgb, texel)| {
                let [r, g, b] = rgb.0;
                match order {
                    TexelOrder::Rgb => texel[..] != [r, g, b],
                    TexelOrder::Rgba => texel[..] != [r, g, b, 255],
                    TexelOrder::Bgra => texel[..] != [b, g, r, 255],
                }
            });
            assert_eq!(differ.count(), 0, "{file} {overrides:?} in {order:?}: pixels differ from the host's encoding");
        }
    }
}

#[test]
fn nine_coloured_lights_add_up() {
    // Nine lights (more than the eight promised) of different colours: the image of all of them is the
    // sum of the images of each alone, in the float output.
    let colours = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 1.0],
        [1.0, 0.0, 1.0],
        [0.5, 0.5, 0.5],
        [1.0, 0.5, 0.2],
        [0.2, 0.5, 1.0],
    ];
    let mut text = String::from("[image]\nwidth = 160\nheight = 120\nbackground = 0.0\n");
    for (i, c) in colours.iter().enumerate() {
        let angle = i as f32 * 0.7;
        text += &format!(
            "[[light]]\nposition = [{}, {}, {}]\ncolor = {c:?}\npower = {}\n",
            3.0 * angle.cos(),
            1.0 + (i % 3) as f32,
            3.0 + 3.0 * angle.sin(),
            5.0 + i as f32
        );
    }
    text += "[material.m]\nbrdf = \"lambert\"\nkd = 0.8\n\
             [[object]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 3.0]\nradius = 1.0\nmaterial = \"m\"\n\
             [[object]]\nshape = \"plane\"\npoint = [0.0, -1.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nmaterial = \"m\"\n";
    let all = scene_from_text("nine-lights", &text);
    let together = render(&all);
    let mut sum = vec![Vec3::ZERO; together.pixels.len()];
    for i in 0..colours.len() {
        let mut alone = all.clone();
        alone.lights = vec![all.lights[i]];
        for (s, p) in sum.iter_mut().zip(render(&alone).pixels) {
            *s += p;
        }
    }
    for (i, (a, b)) in together.pixels.iter().zip(&sum).enumerate() {
        assert!((*a - *b).abs().max_element() <= 1e-4 * a.max_element().max(1.0), "pixel {i}: {a} != {b}");
    }
}

/// Writes a UV sphere as an OBJ (with or without its exact normals), renders it in place of Figure 1's
/// sphere, checks it against the reference tracing the same mesh (within one level), and returns its
/// comparison with the ray-traced exact sphere.
fn obj_sphere_against_the_reference(name: &str, segments: u32, rings: u32, with_normals: bool) -> Comparison {
    let folder = temp_dir();
    let mesh = vk_render::mesh::uv_sphere(segments, rings);
    let mut obj = String::new();
    for v in &mesh.vertices {
        obj += &format!("v {} {} {}\n", v.position[0], v.position[1], v.position[2]);
        if with_normals {
            obj += &format!("vn {} {} {}\n", v.normal[0], v.normal[1], v.normal[2]);
        }
    }
    for t in mesh.indices.chunks(3) {
        let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
        obj += &if with_normals { format!("f {a}//{a} {b}//{b} {c}//{c}\n") } else { format!("f {a} {b} {c}\n") };
    }
    std::fs::write(folder.path().join("ball.obj"), obj).unwrap();
    // Rotated and scaled so that the transform is exercised (a sphere of radius 2 is a sphere still), and
    // clear of the plane, where the facets would decide which surface is in front.
    let base = std::fs::read_to_string(root().join("assets/scenes/fig1-lambert.toml")).unwrap();
    let text = base.replace(
        "shape = \"sphere\"\ncenter = [0.0, 0.0, 3.0]\nradius = 1.0",
        "shape = \"mesh\"\npath = \"ball.obj\"\nscale = 2.0\ntranslate = [0.0, 0.5, 4.5]\nrotate = [90.0, 30.0, 0.0]",
    );
    assert_ne!(text, base);
    let scene_path = folder.path().join("scene.toml");
    std::fs::write(&scene_path, text).unwrap();
    let mesh_scene = vk_render::Scene::load(&scene_path, &[]).unwrap();
    let sphere_scene = asset_scene("fig1-lambert.toml", &["object.0.radius=2.0", "object.0.center=[0.0, 0.5, 4.5]"]);
    let reference = vk_render::reference::render(&sphere_scene).unwrap();
    let band = vk_render::pictures::compare::silhouette_band(&reference.object_ids, 600, 400, 2);
    let gpu = render(&mesh_scene).to_rgb8(&mesh_scene.image);
    let c = vk_render::pictures::compare::compare(&gpu, &reference.image.to_rgb8(&sphere_scene.image), &band);
    eprintln!("{name}: {c}");
    // The reference traces the same triangles with parry3d and interpolates the same normals.
    let c_mesh = check_against_reference(name, &mesh_scene, |c| c.max <= 1);
    eprintln!("{name} against the reference's own mesh: {c_mesh}");
    c
}

#[test]
fn a_fine_obj_sphere_shades_within_one_level_of_an_exact_sphere() {
    // A 256 x 128 UV sphere drawn as a mesh: interpolated normals over chords 7.5e-5 radii deep.
    let c = obj_sphere_against_the_reference("256x128 sphere", 256, 128, true);
    assert!(c.max <= 1, "{c}");
}

#[test]
fn an_obj_without_normals_gets_smooth_normals() {
    // Positions and faces only: the computed smooth normals must shade a coarser sphere almost exactly.
    let c = obj_sphere_against_the_reference("128x64 sphere, computed normals", 128, 64, false);
    assert!(c.max <= 2 && c.mean_abs < 0.1, "{c}");
}

#[test]
fn exr_output_holds_the_linear_image_after_exposure() {
    let scene = asset_scene("fig1-lambert.toml", &["image.width=60", "image.height=40", "image.exposure=2.0"]);
    let image = render(&scene);
    let folder = temp_dir();
    let path = folder.path().join("fig1.exr");
    write_image(&image, &scene.image, &path).unwrap();
    let read = image::open(&path).unwrap().into_rgb32f();
    assert_eq!(read.dimensions(), (60, 40));
    for (x, y) in [(30, 20), (1, 1), (30, 39)] {
        let expected = image.at(x, y) * 2.0;
        let got = Vec3::from(read.get_pixel(x, y).0);
        assert!((got - expected).abs().max_element() < 1e-6, "({x},{y}): {got} != {expected}");
    }
}

/// Vulkan's standard locations of 4 samples within a pixel.
const FOUR_SAMPLES: [(f64, f64); 4] = [(0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875)];

#[test]
fn a_sphere_covers_and_shades_the_exact_sphere_at_every_sample() {
    // A white Lambert sphere lit from the camera (so that every point the camera sees is lit) over black:
    // a pixel holds (covered samples / 4) * the radiance where the pixel centre's ray meets the sphere (the
    // first sample's that meets it when it misses), computed here in f64 from the camera's rays. The sphere is
    // drawn as a 960-triangle mesh standing up to 2% of its radius outside it: none of that shows.
    let text = r#"
        [image]
        width = 160
        height = 120
        samples = 4
        background = [0.0, 0.0, 0.0]
        [camera]
        position = [0.0, 0.0, 0.0]
        look_at = [0.0, 0.0, 1.0]
        up = [0.0, 1.0, 0.0]
        fov_y = 60.0
        [[light]]
        type = "point"
        position = [0.0, 0.0, 0.0]
        color = [1.0, 1.0, 1.0]
        power = 10.0
        shadows = false
        [material.white]
        brdf = "lambert"
        kd = [1.0, 1.0, 1.0]
        [[object]]
        shape = "sphere"
        center = [0.4, -0.3, 4.0]
        radius = 1.3
        material = "white"
    "#;
    let scene = scene_from_text("exact-sphere.toml", text);
    let image = render(&scene);
    let rays = vk_render::render::gpu_types::PixelRays::new(&scene.camera, 160, 120);
    let (center, radius) = (glam::DVec3::new(0.4, -0.3, 4.0), 1.3);
    // The distance to the sphere along the unit ray through framebuffer position (x, y), and whether the ray
    // passes so close to the silhouette (within 1e-4 radii) that f32 may decide either way.
    let hit = |x: f64, y: f64| {
        let d = (rays.corner.as_dvec3() + x * rays.per_x.as_dvec3() + y * rays.per_y.as_dvec3()).normalize();
        let b = d.dot(center);
        let discriminant = b * b - (center.length_squared() - radius * radius);
        let ambiguous = discriminant.abs() < 2e-4 * radius * radius;
        ((discriminant >= 0.0).then(|| (b - discriminant.sqrt(), d)), ambiguous)
    };
    let (mut edge_pixels, mut checked) = (0, 0);
    for y in 0..120 {
        for x in 0..160 {
            let samples: Vec<_> =
                FOUR_SAMPLES.iter().map(|(sx, sy)| hit(f64::from(x) + sx, f64::from(y) + sy)).collect();
            let (centre, centre_ambiguous) = hit(f64::from(x) + 0.5, f64::from(y) + 0.5);
            if centre_ambiguous || samples.iter().any(|(_, ambiguous)| *ambiguous) {
                continue;
            }
            let covered: Vec<_> = samples.iter().filter_map(|(h, _)| *h).collect();
            let expected = match centre.or(covered.first().copied()) {
                Some((t, d)) if !covered.is_empty() => {
                    // Lambert 1/pi, radiance 10 / t^2, cos = n . -d with the light at the eye.
                    let n = (t * d - center) / radius;
                    let radiance = 10.0 / (t * t) * n.dot(-d) / std::f64::consts::PI;
                    radiance * covered.len() as f64 / 4.0
                }
                _ => 0.0,
            };
            let got = f64::from(image.at(x, y).x);
            assert!(
                (got - expected).abs() <= 1e-4 * expected + 1e-5,
                "pixel ({x}, {y}): {got}, expected {expected} ({} of 4 samples covered)",
                covered.len()
            );
            checked += 1;
            edge_pixels += usize::from(!covered.is_empty() && covered.len() < 4);
        }
    }
    assert!(checked > 19_000 && edge_pixels > 100, "{checked} pixels checked, {edge_pixels} on the silhouette");
}
