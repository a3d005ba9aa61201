//! The output transform of SCENE_FORMAT (exposure, tonemap, clamp, encoding) and PNG/EXR files.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::error::{Error, Result};
use crate::scene::{Encoding, ImageSettings, Tonemap, View};

/// A linear HDR image: RGB radiance per pixel, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGB values (a radiance, or the term a view shows), row by row: see [`HdrImage::at`].
    pub pixels: Vec<Vec3>,
}

impl HdrImage {
    /// The radiance at pixel (x, y), x from the left and y from the top.
    pub fn at(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The scale a term view of this image is written with (None for a radiance).
    pub fn term_scale(&self, view: View) -> Option<TermScale> {
        TermScale::of(view, self.pixels.iter().flat_map(|c| c.to_array()))
    }

    /// The image after the whole output transform, as 8-bit RGB; a term view by its [`TermScale`].
    pub fn to_rgb8(&self, settings: &ImageSettings) -> image::RgbImage {
        let channels = self.pixels.iter().flat_map(|c| c.to_array());
        let bytes = match self.term_scale(settings.view) {
            None => {
                channels.map(|c| encode(tonemap(c * settings.exposure, settings.tonemap), settings.encoding)).collect()
            }
            Some(scale) => channels.map(|c| scale.level(c)).collect(),
        };
        image::RgbImage::from_raw(self.width, self.height, bytes).expect("one RGB triple per pixel")
    }

    /// The linear image as written to `.exr` files: a radiance after exposure, a term view as it is.
    pub fn exposed(&self, settings: &ImageSettings) -> image::Rgb32FImage {
        let exposure = if settings.view.is_radiance() { settings.exposure } else { 1.0 };
        let data = self.pixels.iter().flat_map(|c| (*c * exposure).to_array()).collect();
        image::Rgb32FImage::from_raw(self.width, self.height, data).expect("one RGB triple per pixel")
    }
}

/// How a term view (not a radiance) becomes 8-bit levels: linearly, without tone map, level = 255 x (value -
/// low) / (high - low), truncated and clamped. The normal's components span [-1, 1]; every other term
/// [0, the larger of 1 and the image's largest value], so that terms within [0, 1] (n . l, G, F) read
/// directly and the others (D, f_r) fill the range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TermScale {
    /// The view it scales.
    pub view: View,
    /// The value written as level 0.
    pub low: f32,
    /// The value written as level 255.
    pub high: f32,
}

impl TermScale {
    /// The scale of `view` for an image of these channel values; `None` for a radiance (the scene's output
    /// transform applies).
    pub fn of(view: View, channels: impl Iterator<Item = f32>) -> Option<Self> {
        match view {
            _ if view.is_radiance() => None,
            View::Normal => Some(Self { view, low: -1.0, high: 1.0 }),
            _ => {
                let largest = channels.filter(|c| c.is_finite()).fold(1.0f32, f32::max);
                Some(Self { view, low: 0.0, high: largest })
            }
        }
    }

    /// One channel's 8-bit level.
    pub fn level(&self, value: f32) -> u8 {
        encode((value - self.low) / (self.high - self.low), Encoding::Linear)
    }

    /// The scale in one line, for the user: `view d: PNG level = 255 x value / 12.7 ...`.
    pub fn describe(&self) -> String {
        let span = if self.low == 0.0 { format!("value / {}", self.high) } else { "(value + 1) / 2".to_string() };
        format!(
            "view {}: PNG level = 255 x {span}, linear, no tone map (an .exr holds the values themselves)",
            self.view.name()
        )
    }
}

/// How encoded pixels are laid out: 3 bytes (RGB, a PNG's), or 4 with alpha 255 in a window's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelOrder {
    /// 3 bytes: R, G, B (a PNG's).
    Rgb,
    /// 4 bytes: R, G, B, 255.
    Rgba,
    /// 4 bytes: B, G, R, 255 (a `B8G8R8A8` swapchain's).
    Bgra,
}

impl TexelOrder {
    /// Bytes a pixel.
    pub fn bytes(self) -> usize {
        match self {
            TexelOrder::Rgb => 3,
            TexelOrder::Rgba | TexelOrder::Bgra => 4,
        }
    }
}

/// Writes `linear` (four native-endian f32 a pixel, alpha unread) after the whole output transform into
/// `texels`, laid out as `order` says: per channel exactly what [`HdrImage::to_rgb8`] computes.
pub fn encode_texels(linear: &[u8], settings: &ImageSettings, order: TexelOrder, texels: &mut [u8]) {
    let channels = linear.chunks_exact(16).flat_map(|pixel| (0..3).map(|c| f32_at(&pixel[4 * c..])));
    if let Some(scale) = TermScale::of(settings.view, channels) {
        return encode_each(linear, order, texels, |c| scale.level(c));
    }
    let exposure = settings.exposure;
    // One loop per curve and encoding, so that each is compiled with its transform inlined (the preview
    // encodes every frame: a match per channel took 2.5 ms of a 13 ms frame).
    use {Encoding::*, Tonemap::*};
    match (settings.tonemap, settings.encoding) {
        (Clamp, Linear) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Clamp), Linear)),
        (Clamp, Srgb) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Clamp), Srgb)),
        (Reinhard, Linear) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Reinhard), Linear)),
        (Reinhard, Srgb) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Reinhard), Srgb)),
        (Aces, Linear) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Aces), Linear)),
        (Aces, Srgb) => encode_each(linear, order, texels, |c| encode(tonemap(c * exposure, Aces), Srgb)),
    }
}

#[inline(always)]
fn encode_each(linear: &[u8], order: TexelOrder, texels: &mut [u8], channel: impl Fn(f32) -> u8) {
    let (red, blue) = match order {
        TexelOrder::Rgb | TexelOrder::Rgba => (0, 2),
        TexelOrder::Bgra => (2, 0),
    };
    for (pixel, texel) in linear.chunks_exact(16).zip(texels.chunks_exact_mut(order.bytes())) {
        texel[red] = channel(f32_at(&pixel[0..4]));
        texel[1] = channel(f32_at(&pixel[4..8]));
        texel[blue] = channel(f32_at(&pixel[8..12]));
        if let Some(alpha) = texel.get_mut(3) {
            *alpha = 255;
        }
    }
}

/// The native-endian f32 at the start of `bytes`.
fn f32_at(bytes: &[u8]) -> f32 {
    f32::from_ne_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])
}

/// The tone curve, per channel, applied after exposure.
pub fn tonemap(c: f32, curve: Tonemap) -> f32 {
    match curve {
        Tonemap::Clamp => c,
        Tonemap::Reinhard => c / (1.0 + c),
        // Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
        Tonemap::Aces => c * (2.51 * c + 0.03) / (c * (2.43 * c + 0.59) + 0.14),
    }
}

/// Clamps to [0, 1] and encodes one channel to 8 bits. NaN becomes 0 rather than poisoning the image.
pub fn encode(c: f32, encoding: Encoding) -> u8 {
    let v = transfer(c, encoding) * 255.0;
    match encoding {
        // The course: x255 and truncate, no gamma.
        Encoding::Linear => v as u8,
        // Rounded to nearest.
        Encoding::Srgb => v.round() as u8,
    }
}

/// One channel clamped to [0, 1] and through the encoding's transfer function, before it is made 8 bits.
fn transfer(c: f32, encoding: Encoding) -> f32 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    match encoding {
        Encoding::Linear => c,
        // IEC 61966-2-1.
        Encoding::Srgb => {
            if c <= 0.003_130_8 {
                12.92 * c
            } else {
                1.055 * c.powf(1.0 / 2.4) - 0.055
            }
        }
    }
}

/// A linear radiance channel after the whole output transform, in 8-bit levels but not yet rounded to one:
/// how far apart two radiances land in the image.
pub fn level(c: f32, settings: &ImageSettings) -> f32 {
    255.0 * transfer(tonemap(c * settings.exposure, settings.tonemap), settings.encoding)
}

/// How many 8-bit levels of an image made with `settings` a radiance `mean` moves by when it grows by
/// `error` (a standard error): the largest channel's.
pub fn levels_moved(mean: Vec3, error: Vec3, settings: &ImageSettings) -> f32 {
    (0..3).map(|c| level(mean[c] + error[c], settings) - level(mean[c], settings)).fold(0.0, f32::max)
}

/// The 99th percentile of `values` (reordered), 0 for none.
pub fn percentile_99(values: &mut [f32]) -> f32 {
    if values.is_empty() {
        return 0.0;
    }
    let at = ((values.len() - 1) as f64 * 0.99).round() as usize;
    *values.select_nth_unstable_by(at, f32::total_cmp).1
}

/// The kinds of file an image can be written to, by the output path's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// 8-bit RGB after the whole output transform.
    Png,
    /// 32-bit float linear RGB after exposure, before tonemap and encoding.
    Exr,
}

impl OutputFormat {
    /// Checks an output path before any rendering: a known extension and an existing folder.
    ///
    /// # Errors
    /// `Error::Output` naming the path when the extension is not .png/.exr or its folder does not exist.
    pub fn for_path(path: &Path) -> Result<OutputFormat> {
        let error = |message: String| Error::Output { path: path.to_path_buf(), message };
        let format = match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => OutputFormat::Png,
            Some("exr") => OutputFormat::Exr,
            _ => return Err(error("unsupported output file type (expected a .png or .exr path)".into())),
        };
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if !folder.is_dir() {
            return Err(error(format!("the folder {} does not exist", folder.display())));
        }
        Ok(format)
    }
}

/// Writes the image to `path` (PNG or EXR by extension) through a temporary file in the same folder, so
/// that a failure never leaves a partial image behind.
///
/// # Errors
/// `Error::Output` naming the path when the file cannot be encoded or written.
pub fn write_image(hdr: &HdrImage, settings: &ImageSettings, path: &Path) -> Result<()> {
    match OutputFormat::for_path(path)? {
        OutputFormat::Png => write_png(&hdr.to_rgb8(settings), path),
        OutputFormat::Exr => {
            write_encoded(path, |bytes| hdr.exposed(settings).write_to(bytes, image::ImageFormat::OpenExr))
        }
    }
}

/// Writes an 8-bit image as a PNG, through a temporary file as [`write_image`] does, with the fast deflate
/// level every PNG of vk-render has (a sweep's tile took 4.4 ms to encode at the balanced level, on the
/// core that lavapipe's second thread wants; the pixels are the same at any level).
///
/// # Errors
/// `Error::Output` naming the path when the file cannot be encoded or written.
pub fn write_png(image: &image::RgbImage, path: &Path) -> Result<()> {
    write_png_rows(path, image.dimensions(), |band| band(image))
}

/// Encodes into memory, then writes a temporary file beside `path` and renames it into place.
fn write_encoded(
    path: &Path,
    encode: impl FnOnce(&mut std::io::Cursor<Vec<u8>>) -> image::ImageResult<()>,
) -> Result<()> {
    write_file(path, &encoded(path, encode)?)
}

fn encoded(
    path: &Path,
    encode: impl FnOnce(&mut std::io::Cursor<Vec<u8>>) -> image::ImageResult<()>,
) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    encode(&mut bytes)
        .map_err(|e| Error::Output { path: path.to_path_buf(), message: format!("cannot encode the image: {e}") })?;
    Ok(bytes.into_inner())
}

/// Writes `bytes` to a temporary file beside `path` (`NAME.partial-PID`) and renames it into place, so that a
/// failure never leaves a partial file behind: see [`PartialFile`].
///
/// # Errors
/// `Error::Output` naming the path when the file cannot be written.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut file = PartialFile::create(path)?;
    std::io::Write::write_all(&mut file, bytes).map_err(|e| write_error(path, &e))?;
    file.commit()
}

/// A file written under a temporary name beside its final path (`NAME.partial-PID`) and renamed into place
/// by [`PartialFile::commit`]. Dropped uncommitted (an error on the way), the temporary file is removed; on
/// SIGINT or SIGTERM [`remove_partial_files`] removes it; what a SIGKILL leaves is removed by the next write
/// to the same path.
pub struct PartialFile {
    path: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
    registered: Partial,
}

impl PartialFile {
    /// Creates the temporary file for `path`, first removing what killed processes left beside it.
    ///
    /// # Errors
    /// `Error::Output` naming the path when the file cannot be created.
    pub fn create(path: &Path) -> Result<Self> {
        remove_abandoned_partial_files(path);
        let registered = Partial::new(temporary_path(path));
        let file = std::fs::File::create(&registered.0).map_err(|e| write_error(path, &e))?;
        Ok(Self { path: path.to_path_buf(), file: Some(std::io::BufWriter::new(file)), registered })
    }

    /// Flushes the file and renames it into place.
    ///
    /// # Errors
    /// `Error::Output` naming the final path.
    pub fn commit(mut self) -> Result<()> {
        let file = self.file.take().ok_or_else(|| write_error(&self.path, &std::io::ErrorKind::Other.into()))?;
        file.into_inner().map_err(|e| write_error(&self.path, e.error()))?.sync_data().ok();
        pause_for_tests();
        std::fs::rename(&self.registered.0, &self.path).map_err(|e| write_error(&self.path, &e))
    }
}

impl std::io::Write for PartialFile {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.file.as_mut().ok_or(std::io::ErrorKind::Other)?.write(bytes)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().ok_or(std::io::ErrorKind::Other)?.flush()
    }
}

impl Drop for PartialFile {
    fn drop(&mut self) {
        // Committed, the temporary name is gone and this fails harmlessly.
        self.file = None;
        let _ = std::fs::remove_file(&self.registered.0);
    }
}

fn write_error(path: &Path, e: &std::io::Error) -> Error {
    Error::Output { path: path.to_path_buf(), message: format!("cannot write the file: {e}") }
}

/// Writes the 8-bit RGB PNG of `width` x `height` at `path` row by row, as `produce` hands over bands of
/// whole rows (a contact sheet made band by band holds one band at a time), through a [`PartialFile`]:
/// nothing is left at `path` unless `produce` succeeds and its bands fill the image.
///
/// # Errors
/// What `produce` returns, or `Error::Output` naming the path.
pub fn write_png_rows(
    path: &Path,
    size: (u32, u32),
    produce: impl FnOnce(&mut dyn FnMut(&image::RgbImage) -> Result<()>) -> Result<()>,
) -> Result<()> {
    let mut file = PartialFile::create(path)?;
    encode_png_rows(&mut file, path, size, produce)?;
    file.commit()
}

/// The bytes of the PNG [`write_png`] writes for `image` (the server answers with them).
///
/// # Errors
/// `Error::Output` when the image cannot be encoded (it is empty).
pub fn png_bytes(image: &image::RgbImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    encode_png_rows(&mut bytes, Path::new("<PNG in memory>"), image.dimensions(), |band| band(image))?;
    Ok(bytes)
}

/// The encoder of every PNG vk-render writes, into `out` (errors name `path`).
fn encode_png_rows(
    out: &mut impl std::io::Write,
    path: &Path,
    (width, height): (u32, u32),
    produce: impl FnOnce(&mut dyn FnMut(&image::RgbImage) -> Result<()>) -> Result<()>,
) -> Result<()> {
    let encoding = |e: png::EncodingError| Error::Output {
        path: path.to_path_buf(),
        message: format!("cannot encode the image: {e}"),
    };
    let mut encoder = png::Encoder::new(out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    // Paeth on every row rather than Fast's adaptive choice per row: files of the same size (Figure 1:
    // 50.4 against 50.9 kB; Figure 3's sheet 209 against 211 kB) in three quarters of the time (0.47
    // against 0.63 ms; 2.1 against 3.0 ms), which a sweep pays twice an image (its tile and its sheet).
    encoder.set_filter(png::Filter::Paeth);
    let mut writer = encoder.write_header().map_err(encoding)?;
    let mut rows = writer.stream_writer().map_err(encoding)?;
    produce(&mut |band: &image::RgbImage| {
        use std::io::Write;
        rows.write_all(band.as_raw()).map_err(|e| write_error(path, &e))
    })?;
    rows.finish().map_err(encoding)?;
    writer.finish().map_err(encoding)
}

/// The temporary files being written now, for [`remove_partial_files`].
static PARTIAL_FILES: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn partial_files() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PARTIAL_FILES.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A temporary file registered for removal on a signal while it is written.
struct Partial(PathBuf);

impl Partial {
    fn new(path: PathBuf) -> Self {
        partial_files().push(path.clone());
        Self(path)
    }
}

impl Drop for Partial {
    fn drop(&mut self) {
        partial_files().retain(|p| *p != self.0);
    }
}

/// Removes every temporary file being written (a signal handler's last act): returns how many.
pub fn remove_partial_files() -> usize {
    partial_files().iter().filter(|path| std::fs::remove_file(path).is_ok()).count()
}

/// Removes the temporary files beside `path` that a process no longer running left (a SIGKILL cannot be
/// caught): `NAME.partial-PID` whose PID has no /proc entry.
fn remove_abandoned_partial_files(path: &Path) {
    let (Some(folder), Some(name)) = (path.parent(), path.file_name()) else { return };
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    let prefix = format!("{}.partial-", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let pid = file.strip_prefix(&prefix).and_then(|pid| pid.parse::<u32>().ok());
        if pid.is_some_and(|pid| pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// A test hook: VK_RENDER_TEST_WRITE_PAUSE_MS holds each write between its temporary file and the rename,
/// so that a test can signal the process while a partial file exists.
fn pause_for_tests() {
    if let Some(ms) = std::env::var("VK_RENDER_TEST_WRITE_PAUSE_MS").ok().and_then(|v| v.parse().ok()) {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
}

fn temporary_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".partial-{}", std::process::id()));
    path.with_file_name(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_encoding_truncates_like_the_course() {
        assert_eq!(encode(0.5, Encoding::Linear), 127); // the grey background
        assert_eq!(encode(0.596_831, Encoding::Linear), 152); // Figure 1's sphere centre
        assert_eq!(encode(1.7, Encoding::Linear), 255);
        assert_eq!(encode(-0.2, Encoding::Linear), 0);
        assert_eq!(encode(f32::NAN, Encoding::Linear), 0);
    }

    #[test]
    fn srgb_encoding_rounds_through_the_transfer_function() {
        assert_eq!(encode(0.0, Encoding::Srgb), 0);
        assert_eq!(encode(1.0, Encoding::Srgb), 255);
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357 -> 187.52 -> 188
        assert_eq!(encode(0.5, Encoding::Srgb), 188);
        // linear segment: 12.92 * 0.002 = 0.02584 -> 6.59 -> 7
        assert_eq!(encode(0.002, Encoding::Srgb), 7);
    }

    #[test]
    fn tonemaps_by_hand() {
        assert_eq!(tonemap(3.0, Tonemap::Clamp), 3.0);
        assert_eq!(tonemap(1.0, Tonemap::Reinhard), 0.5);
        // 1 * (2.51 + 0.03) / (2.43 + 0.59 + 0.14) = 2.54 / 3.16 = 0.803797
        assert!((tonemap(1.0, Tonemap::Aces) - 0.803_797).abs() < 1e-6);
    }

    #[test]
    fn exposure_comes_before_the_tonemap() {
        let settings = ImageSettings {
            width: 1,
            height: 1,
            samples: 1,
            background: Vec3::ZERO,
            tonemap: Tonemap::Reinhard,
            exposure: 2.0,
            encoding: Encoding::Linear,
            shadow_map_size: 16,
            shadow_filter: crate::scene::ShadowFilter::Hard,
            view: View::Radiance,
        };
        let hdr = HdrImage { width: 1, height: 1, pixels: vec![Vec3::new(0.5, 1.0, 0.0)] };
        // 0.5 * 2 = 1 -> 0.5 -> 127; 1 * 2 = 2 -> 2/3 -> 170
        assert_eq!(hdr.to_rgb8(&settings).into_raw(), vec![127, 170, 0]);
    }

    #[test]
    fn term_views_are_scaled_linearly_by_hand() {
        let normal = TermScale::of(View::Normal, [0.3f32].into_iter()).unwrap();
        assert_eq!([-1.0, 0.0, 1.0].map(|n| normal.level(n)), [0, 127, 255]);
        // D up to 12 (and a NaN, ignored): 255 x 6 / 12 = 127.5 -> 127; F within [0, 1] reads directly.
        let d = TermScale::of(View::D, [0.5, 12.0, f32::NAN].into_iter()).unwrap();
        assert_eq!((d.high, d.level(6.0), d.level(12.0)), (12.0, 127, 255));
        let f = TermScale::of(View::F, [0.2f32, 0.9].into_iter()).unwrap();
        assert_eq!((f.high, f.level(0.5)), (1.0, 127));
        assert!(d.describe().starts_with("view d: PNG level = 255 x value / 12,"), "{}", d.describe());
        assert_eq!(TermScale::of(View::Diffuse, [3.0f32].into_iter()), None, "a radiance: the output transform");
    }

    #[test]
    fn texels_hold_what_to_rgb8_holds_for_every_curve_and_encoding() {
        let pixels: Vec<Vec3> = (0..300)
            .map(|i| Vec3::new(i as f32 * 0.0071, (i as f32 * 0.37).sin() * 2.0, [f32::NAN, -1.0, 0.3][i % 3]))
            .collect();
        let mut linear = Vec::new();
        for p in &pixels {
            for c in [p.x, p.y, p.z, 1.0] {
                linear.extend(c.to_ne_bytes());
            }
        }
        let image = HdrImage { width: 300, height: 1, pixels };
        let transforms = [Tonemap::Clamp, Tonemap::Reinhard, Tonemap::Aces]
            .into_iter()
            .flat_map(|tonemap| [Encoding::Linear, Encoding::Srgb].map(|encoding| (tonemap, encoding, View::Radiance)))
            .chain([View::Normal, View::D, View::Specular].map(|view| (Tonemap::Clamp, Encoding::Linear, view)));
        for (tonemap, encoding, view) in transforms {
            {
                let settings = ImageSettings {
                    width: 300,
                    height: 1,
                    samples: 1,
                    background: Vec3::ZERO,
                    tonemap,
                    exposure: 1.3,
                    encoding,
                    shadow_map_size: 1,
                    shadow_filter: crate::scene::ShadowFilter::Hard,
                    view,
                };
                let rgb = image.to_rgb8(&settings);
                for (order, [r, b]) in [(TexelOrder::Rgba, [0, 2]), (TexelOrder::Bgra, [2, 0])] {
                    let mut texels = vec![0; 300 * 4];
                    encode_texels(&linear, &settings, order, &mut texels);
                    for (texel, p) in texels.chunks_exact(4).zip(rgb.pixels()) {
                        assert_eq!([texel[r], texel[1], texel[b], texel[3]], [p.0[0], p.0[1], p.0[2], 255]);
                    }
                }
                let mut texels = vec![0; 300 * 3];
                encode_texels(&linear, &settings, TexelOrder::Rgb, &mut texels);
                assert_eq!(texels, rgb.into_raw());
            }
        }
    }
}
