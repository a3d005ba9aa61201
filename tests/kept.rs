//! What a renderer keeps between images (meshes, targets, shadow cube faces, scene buffers, pipelines) never
//! shows: after any sequence of changes, an image is the very bytes a new renderer makes of the same scene.

mod common;

use common::*;
use vk_render::{Renderer, RendererOptions, Scene};

/// The scene after each step of a session: a camera orbiting into views that need other shadow cube faces,
/// a light moved, a material and BRDF changed, the image resized, the sample count and the shadow filter
/// changed, a light added, shadows turned off and on.
fn session() -> Vec<(String, Scene)> {
    let bunny = asset_scene("fig5-golden-bunny.toml", &["image.width=240", "image.height=160"]);
    let mut steps = vec![("start".to_string(), bunny.clone())];
    let mut scene = bunny;
    let mut step = |name: &str, change: &dyn Fn(&mut Scene)| {
        change(&mut scene);
        steps.push((name.to_string(), scene.clone()));
    };
    step("orbit a quarter turn", &|s| s.camera.position = glam::Vec3::new(-3.0, 0.5, 3.0));
    step("orbit behind", &|s| s.camera.position = glam::Vec3::new(0.0, 1.0, 6.5));
    step("back to the start", &|s| s.camera.position = glam::Vec3::ZERO);
    step("move a light", &|s| s.lights[1].position = glam::Vec3::new(-2.0, 3.0, 2.0));
    step("another material", &|s| s.objects[0].brdf = s.objects[1].brdf.clone());
    step("resize", &|s| (s.image.width, s.image.height) = (200, 200));
    step("one sample", &|s| s.image.samples = 1);
    step("pcf", &|s| s.image.shadow_filter = vk_render::scene::ShadowFilter::Pcf);
    step("a third light", &|s| s.lights.push(s.lights[0]));
    step("shadows off", &|s| s.lights.iter_mut().for_each(|l| l.shadows = false));
    step("shadows on", &|s| s.lights.iter_mut().for_each(|l| l.shadows = true));
    steps
}

#[test]
fn a_long_lived_renderer_makes_the_bytes_of_a_new_one() {
    let mut kept = renderer();
    for (name, scene) in session() {
        let image = kept.render(&scene).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut fresh = Renderer::new(RendererOptions { validate: true, ..Default::default() }).unwrap();
        let expected = fresh.render(&scene).unwrap_or_else(|e| panic!("{name}, new renderer: {e}"));
        let differing = image.pixels.iter().zip(&expected.pixels).filter(|(a, b)| a != b).count();
        for (i, (a, b)) in image.pixels.iter().zip(&expected.pixels).enumerate().filter(|(_, (a, b))| a != b).take(5) {
            eprintln!("{name}: pixel {} {}: {a} vs {b}", i as u32 % image.width, i as u32 / image.width);
        }
        assert!(
            differing == 0 && image.width == expected.width,
            "{name}: {differing} pixels differ from a new renderer's"
        );
    }
}

#[test]
fn a_camera_crossing_a_plane_redraws_the_faces_its_shadow_needs() {
    // The sphere below the plane, the light above. Seen from above, the plane's shadow cannot be seen and
    // the cubes leave it out (src/render/occluders.rs); seen from below, it hides the sphere from the light,
    // so the faces kept from above must be drawn again with the plane.
    let sphere_below = "object.1.center=[0.0, -1.0, 1.5]".parse().unwrap();
    let above = Scene::load(&root().join("tests/scenes/sphere-shadow.toml"), &[sphere_below]).unwrap();
    let mut below = above.clone();
    (below.camera.position, below.camera.look_at) = (glam::Vec3::new(1.5, -1.2, -1.0), glam::Vec3::new(0.0, -1.0, 1.5));
    let mut kept = renderer();
    for (name, scene) in [("above", &above), ("below", &below), ("above again", &above)] {
        let image = kept.render(scene).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut fresh = Renderer::new(RendererOptions { validate: true, ..Default::default() }).unwrap();
        let expected = fresh.render(scene).unwrap_or_else(|e| panic!("{name}, new renderer: {e}"));
        let differing = image.pixels.iter().zip(&expected.pixels).filter(|(a, b)| a != b).count();
        assert_eq!(differing, 0, "{name}: {differing} pixels differ from a new renderer's");
    }
}
