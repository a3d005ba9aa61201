//! What `vk-render render` writes to a PNG, as pixels: the one function the command line and the Python
//! package share, so that both give the same bytes.

use crate::error::Result;
use crate::pictures::output::TermScale;
use crate::scene::Scene;

use super::Renderer;

/// A PNG's pixels of a scene, and for a term view the scale its levels were written with.
pub struct Picture {
    /// The 8-bit RGB pixels, as the PNG holds them.
    pub pixels: image::RgbImage,
    /// For a term view, the scale its levels were written with; `None` for a radiance.
    pub scale: Option<TermScale>,
}

impl Renderer {
    /// The scene after the whole output transform, as 8-bit RGB: a radiance through the texel path of
    /// [`Renderer::render_rgb8`], a term view by its [`TermScale`] (which depends on the whole image).
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn render_picture(&mut self, scene: &Scene) -> Result<Picture> {
        if scene.image.view.is_radiance() {
            return Ok(Picture { pixels: self.render_rgb8(scene)?, scale: None });
        }
        let image = self.render(scene)?;
        Ok(Picture { scale: image.term_scale(scene.image.view), pixels: image.to_rgb8(&scene.image) })
    }
}
