//! Shadows: the rasterizer's shadow cubes against the ray tracer's shadow rays, acne, soft filtering, the
//! light limit, the Stanford bunny and a mesh of a million triangles.

mod common;

use common::*;
use glam::Vec3;
use vk_render::pictures::compare::{compare, silhouette_band};
use vk_render::pictures::output::HdrImage;
use vk_render::{reference, Scene};

/// The plane's pixels (object 0) that a light's shadows darken: radiance under half that without shadows.
fn shadow_mask(with: &HdrImage, without: &HdrImage, ids: &[Option<usize>]) -> Vec<bool> {
    with.pixels
        .iter()
        .zip(&without.pixels)
        .zip(ids)
        .map(|((a, b), id)| *id == Some(0) && a.max_element() < 0.5 * b.max_element())
        .collect()
}

fn without_shadows(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    scene.lights.iter_mut().for_each(|l| l.shadows = false);
    scene
}

/// Marks every pixel within `radius` of a change of `mask`.
fn edge_band(mask: &[bool], width: u32, height: u32, radius: u32) -> Vec<bool> {
    let ids: Vec<Option<usize>> = mask.iter().map(|&m| Some(usize::from(m))).collect();
    silhouette_band(&ids, width, height, radius)
}

#[test]
fn the_shadow_agrees_with_the_ray_tracer() {
    let scene = test_scene("sphere-shadow.toml");
    let (w, h) = (scene.image.width, scene.image.height);
    let traced = reference::render(&scene).unwrap();
    let traced_lit = reference::render(&without_shadows(&scene)).unwrap();
    let expected = shadow_mask(&traced.image, &traced_lit.image, &traced.object_ids);
    let gpu = render(&scene);
    let gpu_lit = render(&without_shadows(&scene));
    let got = shadow_mask(&gpu, &gpu_lit, &traced.object_ids);

    let intersection = expected.iter().zip(&got).filter(|(a, b)| **a && **b).count();
    let union = expected.iter().zip(&got).filter(|(a, b)| **a || **b).count();
    let iou = intersection as f64 / union as f64;
    eprintln!("shadow: {} px in the reference, {} on the GPU, IoU {iou:.4}", union, got.iter().filter(|m| **m).count());
    assert!(union > 2000, "the shadow is too small to judge: {union} px");
    assert!(iou >= 0.98, "shadow masks differ: IoU {iou:.4}");

    // No acne: away from the shadow's edge (2 px on either mask) and from silhouettes, the lit and the
    // shadowed plane match the reference within one level.
    let silhouettes = silhouette_band(&traced.object_ids, w, h, 2);
    let excluded: Vec<bool> = silhouettes
        .iter()
        .zip(edge_band(&expected, w, h, 2))
        .zip(edge_band(&got, w, h, 2))
        .map(|((a, b), c)| *a || b || c)
        .collect();
    let c = compare(&gpu.to_rgb8(&scene.image), &traced.image.to_rgb8(&scene.image), &excluded);
    eprintln!("away from shadow edges: {c}");
    assert!(c.max <= 1 && c.compared > 50_000, "{c}");
}

#[test]
fn pcf_softens_the_edge_and_hard_is_the_default() {
    let hard = test_scene("sphere-shadow.toml");
    let soft =
        Scene::load(&root().join("tests/scenes/sphere-shadow.toml"), &["image.shadow_filter=pcf".parse().unwrap()])
            .unwrap();
    assert_eq!(hard.image.shadow_filter, vk_render::scene::ShadowFilter::Hard);
    let lit = render(&without_shadows(&hard));
    // Partly lit plane pixels: between 5% and 95% of the unshadowed radiance.
    let partial = |image: &HdrImage| {
        image.pixels.iter().zip(&lit.pixels).filter(|(a, b)| b.x > 0.05 && a.x > 0.05 * b.x && a.x < 0.95 * b.x).count()
    };
    let (hard_edge, soft_edge) = (partial(&render(&hard)), partial(&render(&soft)));
    eprintln!("partly lit pixels: hard {hard_edge}, pcf {soft_edge}");
    // Hard lookups are one per pixel, so a hard edge has no partly lit pixel at all.
    assert!(soft_edge > 50 && soft_edge > 2 * hard_edge, "PCF does not soften: {soft_edge} vs {hard_edge}");
}

#[test]
fn a_light_casting_no_shadow_lights_everything() {
    let scene = test_scene("sphere-shadow.toml");
    let lit = without_shadows(&scene);
    let traced = reference::render(&lit).unwrap();
    check_against_reference("sphere-no-shadow", &lit, |c| c.max <= 1);
    assert!(traced.object_ids.contains(&Some(1)));
}

#[test]
fn a_plane_shadows_what_lies_beyond_it_for_a_camera_there_too() {
    // The sphere below the plane, the light above, the camera below: the plane hides the sphere from the
    // light, so the shadow cube must hold the plane (src/render/occluders.rs leaves a plane out only where
    // its shadow cannot be seen). Without shadows the sphere's upper right is lit.
    let overrides: Vec<_> =
        ["camera.position=[1.5, -1.2, -1.0]", "camera.look_at=[0.0, -1.0, 1.5]", "object.1.center=[0.0, -1.0, 1.5]"]
            .iter()
            .map(|o| o.parse().unwrap())
            .collect();
    let scene = Scene::load(&root().join("tests/scenes/sphere-shadow.toml"), &overrides).unwrap();
    let traced = reference::render(&scene).unwrap();
    // The sphere's pixels lit, away from its silhouette (where samples of the grey background mix in).
    let edges = silhouette_band(&traced.object_ids, scene.image.width, scene.image.height, 2);
    let sphere = |image: &HdrImage| {
        let inside = traced.object_ids.iter().zip(&edges).map(|(id, edge)| *id == Some(1) && !edge);
        image.pixels.iter().zip(inside).filter(|(p, inside)| *inside && p.max_element() > 0.01).count()
    };
    let lit_without_shadows = sphere(&render(&without_shadows(&scene)));
    assert!(lit_without_shadows > 1000, "too little of the sphere is lit to tell: {lit_without_shadows} px");
    assert_eq!(sphere(&render(&scene)), 0, "the plane does not shadow the sphere beyond it");
    let c = check_against_reference("plane-shadows-beyond", &scene, |c| c.max <= 1);
    eprintln!("a sphere in the shadow of the plane: {c}");
}

#[test]
fn a_bigger_shadow_map_moves_the_edge_less() {
    // The edge's error shrinks with the texel: each size, set explicitly, must be worse than the next one
    // up. Were shadow_map_size ignored, the three would be equal.
    let with_size = |size: u32| {
        let size = format!("image.shadow_map_size={size}").parse().unwrap();
        Scene::load(&root().join("tests/scenes/sphere-shadow.toml"), &[size]).unwrap()
    };
    let scene = with_size(1024);
    let traced = reference::render(&scene).unwrap();
    let expected = traced.image.to_rgb8(&scene.image);
    let everything = vec![false; expected.len() / 3];
    let error = |size: u32| {
        let c = compare(&render(&with_size(size)).to_rgb8(&scene.image), &expected, &everything);
        eprintln!("{size} texels: {c}");
        c.fraction_over_3
    };
    let (coarse, medium, fine) = (error(64), error(256), error(1024));
    assert!(coarse > medium && medium > fine, "64: {coarse}, 256: {medium}, 1024: {fine} (fractions over 3 levels)");
}

#[test]
fn the_bunny_loads_with_its_triangles_and_stands_upright_in_frame() {
    let mesh = vk_render::mesh::load_obj(std::path::Path::new(vk_render::scene::BUNNY_PATH)).unwrap();
    assert_eq!(mesh.triangle_count(), 69_666);
    assert_eq!(mesh.vertices.len(), 34_835);
    let scene = asset_scene("fig5-golden-bunny.toml", &[]);
    let traced = reference::render(&scene).unwrap();
    let (w, h) = (scene.image.width, scene.image.height);
    let bunny: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| traced.object_ids[(y * w + x) as usize] == Some(0))
        .collect();
    // In frame: a good part of the image, touching no border.
    assert!(bunny.len() as f64 > 0.05 * f64::from(w * h), "{} bunny pixels", bunny.len());
    assert!(bunny.iter().all(|&(x, y)| x > 0 && y > 0 && x < w - 1 && y < h - 1), "the bunny leaves the frame");
    // Upright: the placed mesh's highest points are its ears, at the back-top, and it rests on the plane.
    let placed = &vk_render::mesh::place_objects(&scene).unwrap()[0];
    let world: Vec<Vec3> = placed
        .mesh
        .vertices
        .iter()
        .map(|v| placed.model.transform_point3(Vec3::from_slice(&v.position[..3])))
        .collect();
    let (low, high) = world.iter().fold((f32::MAX, f32::MIN), |(l, h), p| (l.min(p.y), h.max(p.y)));
    let plane_y = match scene.objects[1].shape {
        vk_render::scene::Shape::Plane { point, .. } => point.y,
        _ => panic!("object 1 is the plane"),
    };
    assert!((low - plane_y).abs() < 0.02, "the bunny floats or sinks: lowest point {low}, plane {plane_y}");
    // The bunny's body is wider at the bottom than at the top: more vertices in its lower half.
    let middle = 0.5 * (low + high);
    let lower = world.iter().filter(|p| p.y < middle).count();
    assert!(lower > world.len() / 2, "upside down? {lower} of {} vertices in the lower half", world.len());
    // The GPU's image of the golden bunny with its shadow agrees with the ray tracer's.
    let c = check_against_reference("fig5-golden-bunny", &scene, acceptable);
    eprintln!("golden bunny: {c}");
}

#[test]
fn a_mesh_of_a_million_triangles_renders() {
    let folder = temp_dir();
    let mesh = vk_render::mesh::uv_sphere(1000, 501);
    assert!(mesh.triangle_count() >= 1_000_000, "{}", mesh.triangle_count());
    let mut obj = String::with_capacity(60_000_000);
    for v in &mesh.vertices {
        obj += &format!(
            "v {} {} {}\nvn {} {} {}\n",
            v.position[0], v.position[1], v.position[2], v.normal[0], v.normal[1], v.normal[2]
        );
    }
    for t in mesh.indices.chunks(3) {
        let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
        obj += &format!("f {a}//{a} {b}//{b} {c}//{c}\n");
    }
    std::fs::write(folder.path().join("million.obj"), obj).unwrap();
    let base = std::fs::read_to_string(root().join("tests/scenes/sphere-shadow.toml")).unwrap();
    let text = base.replace(
        "shape = \"sphere\"\ncenter = [0.0, 1.0, 1.5]\nradius = 0.6",
        "shape = \"mesh\"\npath = \"million.obj\"\nscale = 0.6\ntranslate = [0.0, 1.0, 1.5]",
    );
    assert_ne!(text, base);
    let path = folder.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path, &[]).unwrap();
    let c = check_against_reference("million-triangles", &scene, |c| acceptable(c) && c.mean_abs < 0.05);
    eprintln!("a million triangles: {c}");
}
