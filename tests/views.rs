//! Term views (`image.view`, `--view`): the GPU's D, G, F, n . l and f_r images against the Rust mirror's
//! terms at pixels computed here by ray casting, and the views recomposing the radiance.

mod common;

use glam::Vec3;
use vk_render::brdf::{d_ggx, f_schlick, g_smith_schlick, half_vector, smith_schlick_k, Brdf};
use vk_render::scene::View;
use vk_render::{HdrImage, Scene};

/// Figure 4's half-metal gold sphere over the red plane, small, one sample a pixel (each pixel is its centre's
/// shading), the light moved aside so that the highlight is off-centre and part of the sphere is unlit.
fn gold_scene(view: View) -> Scene {
    common::asset_scene(
        "fig4-gold-metalness-0.5.toml",
        &[
            "image.width=120",
            "image.height=80",
            "image.samples=1",
            "light.0.position=[2.0, 1.5, 0.0]",
            &format!("image.view=\"{}\"", view.name()),
        ],
    )
}

/// What the test computes at a pixel of the sphere: the point's directions and the light's incident radiance.
struct SpherePixel {
    x: u32,
    y: u32,
    n: Vec3,
    wi: Vec3,
    wo: Vec3,
    incident: Vec3,
}

/// Every third pixel whose centre's ray meets the sphere well inside its silhouette and sees the light above
/// the terminator: the ray cast here, with the course's camera, independently of the GPU.
fn sphere_pixels(scene: &Scene) -> Vec<SpherePixel> {
    let (width, height) = (scene.image.width, scene.image.height);
    let camera = &scene.camera;
    let w = (camera.position - camera.look_at).normalize();
    let u = camera.up.cross(w).normalize();
    let v = w.cross(u);
    let half_height = (camera.fov_y.to_radians() * 0.5).tan();
    let half_width = half_height * width as f32 / height as f32;
    let (center, radius) = (Vec3::new(0.0, 0.0, 3.0), 1.0);
    let light = &scene.lights[0];
    let mut pixels = Vec::new();
    for y in (0..height).step_by(3) {
        for x in (0..width).step_by(3) {
            let sx = (2.0 * (x as f32 + 0.5) / width as f32 - 1.0) * half_width;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / height as f32) * half_height;
            let ray = (sx * u + sy * v - w).normalize();
            let to_center = center - camera.position;
            let along = to_center.dot(ray);
            let miss2 = to_center.length_squared() - along * along;
            if miss2 > 0.8 * radius * radius {
                continue; // outside, or near the silhouette
            }
            let p = camera.position + (along - (radius * radius - miss2).sqrt()) * ray;
            let n = (p - center).normalize();
            let to_light = light.position - p;
            let wi = to_light.normalize();
            if n.dot(wi) < 0.05 {
                continue; // unlit, or near the terminator
            }
            let incident = light.color * light.power / to_light.length_squared();
            pixels.push(SpherePixel { x, y, n, wi, wo: -ray, incident });
        }
    }
    assert!(pixels.len() > 100, "only {} pixels to check", pixels.len());
    pixels
}

fn render(view: View) -> HdrImage {
    common::render(&gold_scene(view))
}

/// The largest error of `image` against `expected` at the sphere's pixels, in units of the tolerance:
/// relative 2e-3 (the GPU's ray and point differ from this one in the last bits), absolute floor 1e-5.
fn worst_error(image: &HdrImage, scene: &Scene, expected: impl Fn(&SpherePixel) -> Vec3) -> f32 {
    sphere_pixels(scene)
        .iter()
        .map(|pixel| {
            let (got, want) = (image.at(pixel.x, pixel.y), expected(pixel));
            (got - want).abs().max_element() / (2e-3 * want.abs().max_element()).max(1e-5)
        })
        .fold(0.0, f32::max)
}

fn gold(scene: &Scene) -> Brdf {
    scene.objects[0].brdf.clone()
}

#[test]
fn every_term_view_equals_the_rust_terms() {
    let scene = gold_scene(View::Radiance);
    let Brdf::CookTorrance { f0, roughness, .. } = gold(&scene) else { panic!("the sphere is Cook-Torrance") };
    let lit = |f: Vec3, p: &SpherePixel| f * p.incident * p.n.dot(p.wi);
    type Term<'a> = &'a dyn Fn(&SpherePixel) -> Vec3;
    let terms: [(View, Term); 7] = [
        (View::D, &|p| Vec3::splat(d_ggx(p.n, half_vector(p.wi, p.wo), roughness * roughness))),
        (View::G, &|p| Vec3::splat(g_smith_schlick(p.n.dot(p.wo), p.n.dot(p.wi), smith_schlick_k(roughness)))),
        (View::F, &|p| f_schlick(p.wo.dot(half_vector(p.wi, p.wo)).clamp(0.0, 1.0), f0)),
        (View::NDotL, &|p| Vec3::splat(p.n.dot(p.wi))),
        (View::Brdf, &|p| gold(&scene).eval(p.n, p.wi, p.wo)),
        (View::Diffuse, &|p| lit(gold(&scene).eval_diffuse(p.n, p.wi, p.wo), p)),
        (View::Specular, &|p| lit(gold(&scene).eval_specular(p.n, p.wi, p.wo), p)),
    ];
    for (view, expected) in terms {
        let error = worst_error(&render(view), &scene, expected);
        assert!(error <= 1.0, "view {}: {error:.2}x the tolerance", view.name());
    }
}

#[test]
fn the_views_recompose_the_radiance() {
    let scene = gold_scene(View::Radiance);
    let radiance = render(View::Radiance);
    let (brdf, n_dot_l) = (render(View::Brdf), render(View::NDotL));
    // One light: radiance = f_r * (n . l) * the light's incident radiance, where the light is seen.
    let error = worst_error(&radiance, &scene, |p| brdf.at(p.x, p.y) * n_dot_l.at(p.x, p.y) * p.incident);
    assert!(error <= 1.0, "f_r x n.l x incident is {error:.2}x the tolerance from the radiance");
    // Wherever an object is seen, shadows and the plane included: radiance = diffuse + specular (the lobes'
    // views have no background: it is neither lobe's).
    let (diffuse, specular) = (render(View::Diffuse), render(View::Specular));
    let mut objects_seen = 0;
    for (k, pixel) in radiance.pixels.iter().enumerate() {
        let sum = diffuse.pixels[k] + specular.pixels[k];
        if *pixel == scene.image.background && sum == Vec3::ZERO {
            continue;
        }
        objects_seen += 1;
        assert!(
            (*pixel - sum).abs().max_element() <= 1e-5 * pixel.max_element().max(1.0),
            "pixel {k}: {pixel} vs {sum}"
        );
    }
    assert!(objects_seen > 4000, "only {objects_seen} pixels see an object");
    assert!(specular.pixels.iter().any(|c| c.max_element() > 1.0), "the highlight is in the specular view");
}

#[test]
fn a_g_without_its_four_fails_the_g_view() {
    // The views' test must see a real mistake in the GLSL: G = (n.wo)(n.wi) V, the 4 forgotten.
    let mut renderer = common::mutant_renderer(
        "brdf/cook_torrance.glsl",
        "return 4.0 * NoV * NoL * v_smith_schlick",
        "return NoV * NoL * v_smith_schlick",
    );
    let scene = gold_scene(View::G);
    let Brdf::CookTorrance { roughness, .. } = gold(&scene) else { panic!("the sphere is Cook-Torrance") };
    let image = renderer.render(&scene).unwrap();
    let error = worst_error(&image, &scene, |p| {
        Vec3::splat(g_smith_schlick(p.n.dot(p.wo), p.n.dot(p.wi), smith_schlick_k(roughness)))
    });
    assert!(error > 100.0, "the broken G went unnoticed ({error:.2}x the tolerance)");
}

#[test]
fn term_views_have_no_background_and_the_normal_view_holds_the_normal() {
    let scene = gold_scene(View::Normal);
    let normals = render(View::Normal);
    let error = worst_error(&normals, &scene, |p| p.n);
    assert!(error <= 1.0, "normal view: {error:.2}x the tolerance");
    let d = render(View::D);
    assert_eq!(d.at(0, 0), Vec3::ZERO, "a term view's background is 0, not the scene's grey");
    assert_eq!(d.at(60, 79), Vec3::ZERO, "the Lambert plane has no D");
}

#[test]
fn brdf_diffuse_and_specular_add_up_in_the_rust_mirror() {
    let scene = gold_scene(View::Radiance);
    for pixel in sphere_pixels(&scene) {
        for brdf in scene.materials.values() {
            let sum = brdf.eval_diffuse(pixel.n, pixel.wi, pixel.wo) + brdf.eval_specular(pixel.n, pixel.wi, pixel.wo);
            let whole = brdf.eval(pixel.n, pixel.wi, pixel.wo);
            assert!((sum - whole).abs().max_element() <= 1e-6 * whole.max_element().max(1.0), "{brdf:?}");
        }
    }
}

/// A renderer asked for more pipelines than it keeps destroys the least recently used ones and builds them
/// again when asked: its images are unchanged and its count stays bounded (a server's memory).
#[test]
fn pipelines_past_the_bound_are_destroyed_and_rebuilt_unchanged() {
    let mut renderer =
        vk_render::Renderer::new(vk_render::RendererOptions { validate: true, ..Default::default() }).unwrap();
    renderer.keep_pipelines(3);
    let first = renderer.render_rgb8(&gold_scene(View::Radiance)).unwrap();
    for view in View::ALL {
        renderer.render_picture(&gold_scene(view)).unwrap();
        assert!(renderer.pipelines_kept() <= 3, "{} pipelines kept", renderer.pipelines_kept());
    }
    assert!(
        renderer.render_rgb8(&gold_scene(View::Radiance)).unwrap() == first,
        "a rebuilt pipeline renders otherwise"
    );
    assert!(renderer.take_validation_messages().is_empty());
}
