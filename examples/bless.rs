//! `make bless`: rewrites the golden images of tests/golden/ from lavapipe's renders, on purpose (review the
//! images in the diff before committing them). The golden images are lavapipe's: the tests hold any lavapipe
//! to them strictly, and other devices to a tolerance that still sees a missing highlight.

#[path = "../tests/common/golden.rs"]
mod golden;

use vk_render::{Renderer, RendererOptions};

fn main() -> anyhow::Result<()> {
    let options = RendererOptions { device: Some("llvmpipe".into()), validate: true, ..Default::default() };
    let mut renderer = Renderer::new(options)?;
    let folder = golden::folder();
    std::fs::create_dir_all(&folder)?;
    for (name, scene) in golden::cases() {
        let image = renderer.render(&scene)?.to_rgb8(&scene.image);
        vk_render::pictures::output::write_png(&image, &folder.join(&name))?;
        println!("blessed tests/golden/{name}");
    }
    println!("on {} ({})", renderer.device_info().name, renderer.device_info().driver);
    Ok(())
}
