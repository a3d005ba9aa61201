//! Renders through Vulkan (validation layer on, any message fails) and checks the images.

mod common;

use common::*;
use glam::Vec3;
use vk_render::compare::Comparison;
use vk_render::output::write_image;

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
    let band = vk_render::compare::silhouette_band(&reference.object_ids, 600, 400, 2);
    let gpu = render(&mesh_scene).to_rgb8(&mesh_scene.image);
    let c = vk_render::compare::compare(&gpu, &reference.image.to_rgb8(&sphere_scene.image), &band);
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
