//! The check of a student's image in the browser: a `vk-render site` folder's check page hands over a
//! figure's renders (the exact image and each mistake's, made at `site` time: src/serve/site/check.rs) and
//! the student's file; the verdict, the mistakes, the statistics and the map of differences come from the
//! rules `vk-render check` decides by (crates/check-rules), so that the page and the program cannot differ
//! by a rule. The image stays in this page's memory.
//!
//! One check at a time: [`check_begin`] with the figure's list of candidates, [`check_picture`] for each of
//! its pictures in order, [`check_objects`] with its objects' ids, then [`check_image`] with the student's
//! file and, for its map of differences, [`check_difference`].

use std::cell::RefCell;
use std::io::Cursor;

use check_rules::{decode_image, rank, regions, DifferenceMap, RegionStatistics, Statistics};
use image::RgbImage;
use serde_json::{json, Value};

use crate::{answer, input_bytes, input_text, OUTPUT};

/// The largest image file the page takes: 16 MiB, as `vk-render serve` takes (the page refuses a larger one
/// before reading it).
pub const MAX_IMAGE_BYTES: usize = 16 << 20;

/// The most candidates a figure lists (the catalogue has 18 mistakes).
const MAX_CANDIDATES: usize = 256;

#[derive(Default)]
struct Session {
    /// The figure's size: every picture's, and the only size its check decides at.
    size: (u32, u32),
    /// Each candidate: its mistake's name (None: the exact image, first) and its picture.
    candidates: Vec<(Option<String>, usize)>,
    pictures: Vec<RgbImage>,
    object_ids: Vec<Option<usize>>,
    /// The last check's map of differences, as a PNG.
    difference: Vec<u8>,
}

impl Session {
    /// How many pictures the figure's candidates name (numbered from 0).
    fn pictures_named(&self) -> usize {
        self.candidates.iter().map(|c| c.1).max().map_or(0, |k| k + 1)
    }
}

thread_local! {
    static SESSION: RefCell<Session> = RefCell::new(Session::default());
}

/// Starts a check for the input's `length` bytes of JSON, a figure as the site's `data/check/index.json`
/// lists it (`width`, `height`, `candidates`: `[name or null, picture]` each, the exact image first):
/// answers `{"pictures": how many to hand over}` or `{"error"}`.
#[no_mangle]
pub extern "C" fn check_begin(length: usize) -> usize {
    answer(&begin(&input_text(length)).unwrap_or_else(|error| json!({ "error": error })))
}

/// Takes the input's `length` bytes as the figure's next picture (a PNG of its size): answers
/// `{"pictures": how many taken}` or `{"error"}`.
#[no_mangle]
pub extern "C" fn check_picture(length: usize) -> usize {
    answer(&input_bytes(length, picture).unwrap_or_else(|error| json!({ "error": error })))
}

/// Takes the input's `length` bytes as the figure's objects' ids (a PNG of its size, grey level k + 1 for
/// object k, 0 the background): answers `{"objects": true}` or `{"error"}`.
#[no_mangle]
pub extern "C" fn check_objects(length: usize) -> usize {
    answer(&input_bytes(length, objects).unwrap_or_else(|error| json!({ "error": error })))
}

/// Checks the input's `length` bytes, the student's PNG or JPEG: answers the check (see [`check`]) or
/// `{"error"}`, with `"size": [width, height]` when it is an image of another size than the figure's.
#[no_mangle]
pub extern "C" fn check_image(length: usize) -> usize {
    answer(&input_bytes(length, check).unwrap_or_else(|error| error))
}

/// The last check's map of differences, a PNG, into the output: its length (0 before a check).
#[no_mangle]
pub extern "C" fn check_difference() -> usize {
    SESSION.with_borrow(|session| {
        OUTPUT.with_borrow_mut(|output| {
            output.clone_from(&session.difference);
            output.len()
        })
    })
}

/// [`MAX_IMAGE_BYTES`], for the page to refuse a file before reading it.
#[no_mangle]
pub extern "C" fn max_image_bytes() -> usize {
    MAX_IMAGE_BYTES
}

fn begin(text: &str) -> Result<Value, String> {
    let figure: Value = serde_json::from_str(text).map_err(|e| format!("the figure is not JSON: {e}"))?;
    let side = |key: &str| {
        figure[key]
            .as_u64()
            .and_then(|v| u32::try_from(v).ok())
            .filter(|v| (1..=16384).contains(v))
            .ok_or_else(|| format!("the figure's `{key}` is not a size in pixels"))
    };
    let size = (side("width")?, side("height")?);
    let listed = figure["candidates"].as_array().ok_or("the figure has no `candidates`")?;
    if listed.is_empty() || listed.len() > MAX_CANDIDATES {
        return Err(format!("the figure lists {} candidates (1 to {MAX_CANDIDATES})", listed.len()));
    }
    let mut candidates = Vec::with_capacity(listed.len());
    for (k, candidate) in listed.iter().enumerate() {
        let name = match &candidate[0] {
            Value::Null => None,
            Value::String(name) => Some(name.clone()),
            _ => return Err(format!("candidate {k}: its first item is a mistake's name or null")),
        };
        let picture = candidate[1].as_u64().and_then(|p| usize::try_from(p).ok()).filter(|&p| p < MAX_CANDIDATES);
        let picture = picture.ok_or_else(|| format!("candidate {k}: its second item is a picture's number"))?;
        if (k == 0) != name.is_none() {
            return Err("the exact image (null) is the first candidate, and only the first".into());
        }
        candidates.push((name, picture));
    }
    SESSION.with_borrow_mut(|session| {
        *session = Session { size, candidates, ..Session::default() };
        Ok(json!({ "pictures": session.pictures_named() }))
    })
}

/// Decodes a PNG or JPEG of exactly `size` within the memory it needs; `what` names it in errors.
fn decode_sized(bytes: &[u8], size: (u32, u32), what: &str) -> Result<RgbImage, Value> {
    let found = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .ok()
        .and_then(|reader| reader.into_dimensions().ok())
        .ok_or_else(|| json!({ "error": format!("{what}: not a PNG or JPEG image vk-render can read") }))?;
    if found != size {
        let message = format!("{what} is {} x {}, the figure {} x {}", found.0, found.1, size.0, size.1);
        return Err(json!({ "error": message, "size": [found.0, found.1] }));
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(size.0);
    limits.max_image_height = Some(size.1);
    limits.max_alloc = Some(u64::from(size.0) * u64::from(size.1) * 4 * 3);
    decode_image(bytes, limits).map_err(|e| json!({ "error": format!("{what}: {e}") }))
}

fn message(error: Value) -> String {
    error["error"].as_str().unwrap_or_default().to_string()
}

fn picture(bytes: &[u8]) -> Result<Value, String> {
    SESSION.with_borrow_mut(|session| {
        let wanted = session.pictures_named();
        if session.pictures.len() >= wanted {
            return Err(format!("the figure has {wanted} pictures, all taken (check_begin starts a check)"));
        }
        let what = format!("picture {}", session.pictures.len());
        session.pictures.push(decode_sized(bytes, session.size, &what).map_err(message)?);
        Ok(json!({ "pictures": session.pictures.len() }))
    })
}

fn objects(bytes: &[u8]) -> Result<Value, String> {
    SESSION.with_borrow_mut(|session| {
        let ids = decode_sized(bytes, session.size, "the objects' ids").map_err(message)?;
        session.object_ids = ids.pixels().map(|p| p.0[0].checked_sub(1).map(usize::from)).collect();
        Ok(json!({ "objects": true }))
    })
}

/// The check of the student's image, in the words of `vk-render check`'s JSON (`vk_render.check`'s
/// summary): `matches`, `verdict`, `mistakes` (their names), `statistics`, `regions` (when the objects'
/// ids were handed over), and for the page's report `width`, `height`, `difference_scale`,
/// `worst_region`, `mistake_picture` (the diagnosed mistake's picture's number, or null) and `ranking`
/// (every candidate's name and distance, best first).
fn check(bytes: &[u8]) -> Result<Value, Value> {
    SESSION.with_borrow_mut(|session| {
        if session.candidates.is_empty() || session.pictures.len() != session.pictures_named() {
            return Err(json!({ "error": "the figure's pictures were not all handed over (check_picture)" }));
        }
        let mine = decode_sized(bytes, session.size, "your image")?;
        let labelled: Vec<(Option<usize>, &RgbImage)> = session
            .candidates
            .iter()
            .enumerate()
            .map(|(k, (name, picture))| (name.as_ref().map(|_| k), &session.pictures[*picture]))
            .collect();
        let ranked = rank(&mine, &labelled);
        let verdict = ranked.verdict();
        let name = |k: usize| session.candidates[k].0.clone();
        let exact = &session.pictures[session.candidates[0].1];
        let found_regions: Vec<RegionStatistics> =
            if session.object_ids.len() == (session.size.0 * session.size.1) as usize {
                regions(&mine, exact, &session.object_ids).iter().map(RegionStatistics::from).collect()
            } else {
                Vec::new()
            };
        let map = DifferenceMap::of(&mine, exact);
        let (x, y, side) = map.worst_region();
        session.difference.clear();
        map.heat_map()
            .write_to(&mut Cursor::new(&mut session.difference), image::ImageFormat::Png)
            .map_err(|e| json!({ "error": format!("the map of differences: {e}") }))?;
        Ok(json!({
            "matches": ranked.against_exact.matches() && verdict == check_rules::Verdict::Matches,
            "verdict": verdict.word(),
            "mistakes": verdict.mistakes().iter().map(|&k| name(k)).collect::<Vec<_>>(),
            "statistics": Statistics::from(&ranked.against_exact),
            "regions": found_regions,
            "width": mine.width(),
            "height": mine.height(),
            "difference_scale": map.scale(),
            "worst_region": { "x": x, "y": y, "width": side, "height": side },
            "mistake_picture": verdict.mistakes().first().map(|&k| session.candidates[k].1),
            "ranking": ranked.ranking.iter().map(|(k, d)| json!([k.and_then(name), d])).collect::<Vec<_>>(),
        }))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 40 x 30 picture: a gradient, `shift` levels brighter on a block in its middle.
    fn picture_of(shift: i16) -> RgbImage {
        RgbImage::from_fn(40, 30, |x, y| {
            let lifted = if (10..30).contains(&x) && (8..22).contains(&y) { shift } else { 0 };
            let v = ((60 + x + y) as i16 + lifted).clamp(0, 255) as u8;
            image::Rgb([v, v / 2, 255 - v])
        })
    }

    fn encoded(image: &RgbImage, format: image::ImageFormat) -> Vec<u8> {
        let mut bytes = Vec::new();
        image.write_to(&mut Cursor::new(&mut bytes), format).unwrap();
        bytes
    }

    /// A figure of three candidates on two pictures (two mistakes alike), and its objects' ids: the left
    /// half the background, the right half object 0.
    fn begin_figure() {
        let figure = r#"{"width": 40, "height": 30,
            "candidates": [[null, 0], ["darker", 1], ["brighter", 2], ["also-none", 0]]}"#;
        assert_eq!(begin(figure).unwrap(), json!({ "pictures": 3 }));
        for shift in [0, -30, 30] {
            picture(&encoded(&picture_of(shift), image::ImageFormat::Png)).unwrap();
        }
        let ids = RgbImage::from_fn(40, 30, |x, _| image::Rgb([u8::from(x >= 20); 3]));
        objects(&encoded(&ids, image::ImageFormat::Png)).unwrap();
    }

    #[test]
    fn a_mistakes_jpeg_is_diagnosed_and_the_exact_image_matches() {
        begin_figure();
        let darker = check(&encoded(&picture_of(-29), image::ImageFormat::Jpeg)).unwrap();
        assert_eq!((darker["verdict"].as_str(), &darker["mistakes"]), (Some("mistake"), &json!(["darker"])));
        assert_eq!(darker["mistake_picture"], 1);
        assert_eq!(darker["matches"], false);
        assert_eq!(darker["ranking"][0][0], "darker");
        // Regions of both the background and the object.
        let parts: Vec<&Value> = darker["regions"].as_array().unwrap().iter().map(|r| &r["object"]).collect();
        assert!(parts.contains(&&Value::Null) && parts.contains(&&json!(0)), "{parts:?}");
        let exact = check(&encoded(&picture_of(0), image::ImageFormat::Png)).unwrap();
        assert_eq!((exact["verdict"].as_str(), exact["matches"].as_bool()), (Some("matches"), Some(true)));
        assert_eq!(exact["statistics"]["rms"], 0.0);
        assert_eq!(exact["mistake_picture"], Value::Null);
        // The map of differences of the last check: a PNG of the figure's size.
        let length = check_difference();
        let map = OUTPUT.with_borrow(|output| image::load_from_memory(&output[..length]).unwrap());
        assert_eq!((map.width(), map.height()), (40, 30));
    }

    #[test]
    fn another_size_a_text_and_missing_pictures_are_answered_with_an_error() {
        begin_figure();
        let small = check(&encoded(&RgbImage::new(20, 10), image::ImageFormat::Png)).unwrap_err();
        assert_eq!(small["size"], json!([20, 10]));
        assert!(small["error"].as_str().unwrap().contains("20 x 10, the figure 40 x 30"), "{small}");
        let text = check(b"GIF89a, or so it says").unwrap_err();
        assert!(text["error"].as_str().unwrap().contains("not a PNG or JPEG"), "{text}");
        assert!(picture(&encoded(&picture_of(0), image::ImageFormat::Png)).unwrap_err().contains("all taken"));
        begin(r#"{"width": 40, "height": 30, "candidates": [[null, 0], ["darker", 1]]}"#).unwrap();
        assert!(check(&encoded(&picture_of(0), image::ImageFormat::Png)).is_err());
        assert!(begin(r#"{"width": 40, "height": 30, "candidates": [["darker", 0]]}"#).is_err());
        assert!(begin(r#"{"width": 0, "height": 30, "candidates": [[null, 0]]}"#).is_err());
        assert!(begin("not JSON").unwrap_err().contains("not JSON"));
    }
}
