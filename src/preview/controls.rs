//! What the preview's keys and mouse do to the scene: pure state, no window, so it is unit-tested.

use glam::Vec3;
use winit::keyboard::{Key, NamedKey};

use crate::brdf::{Analytic, Brdf, DiffuseModel, ParameterKind, ParameterValue};
use crate::scene::{Camera, Scene};

/// One user action.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Tab: select the next object.
    NextObject,
    /// 1 to 5: give the selected object this BRDF (0 lambert .. 4 cook-torrance).
    SetBrdf(usize),
    /// Up / Down: raise or lower the BRDF's main parameter (sigma, shininess or roughness), or a .brdf
    /// file's selected float parameter.
    MainParameter(i32),
    /// Left / Right: lower or raise the metalness of a Cook-Torrance material, or select a .brdf file's
    /// previous or next float parameter.
    Metalness(i32),
    /// L: turn every light's shadows off, or back to the scene's.
    ToggleShadows,
    /// B: show the selected object's BRDF lobe for the first light, or hide it.
    ToggleLobe,
    /// S: save a screenshot.
    Screenshot,
    /// R: back to the scene's camera.
    ResetCamera,
    /// Esc: quit.
    Quit,
}

/// The action of a key, as the window's keyboard events and the test scripts both deliver it.
pub fn key_action(key: &Key) -> Option<Action> {
    Some(match key {
        Key::Named(NamedKey::Tab) => Action::NextObject,
        Key::Named(NamedKey::ArrowUp) => Action::MainParameter(1),
        Key::Named(NamedKey::ArrowDown) => Action::MainParameter(-1),
        Key::Named(NamedKey::ArrowLeft) => Action::Metalness(-1),
        Key::Named(NamedKey::ArrowRight) => Action::Metalness(1),
        Key::Named(NamedKey::Escape) => Action::Quit,
        Key::Character(c) => match c.as_str() {
            "1" | "2" | "3" | "4" | "5" => Action::SetBrdf(c.parse::<usize>().ok()? - 1),
            "l" | "L" => Action::ToggleShadows,
            "b" | "B" => Action::ToggleLobe,
            "s" | "S" => Action::Screenshot,
            "r" | "R" => Action::ResetCamera,
            _ => return None,
        },
        _ => return None,
    })
}

/// One step of a test script, played one per frame: a key pressed, a drag, or the window resized.
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptStep {
    /// A key pressed, as winit reports it.
    Key(Key),
    /// A drag of [`ORBIT_STEP_PIXELS`] to the right with the button held: the camera turns about the
    /// look-at point.
    Orbit,
    /// The window resized to width x height pixels.
    Resize(u32, u32),
}

/// Parses a test script: steps separated by commas, each a key ("Tab", "Up", "Down", "Left", "Right",
/// "Esc", or one character as typed: "2", "l"), "Orbit" (a drag of [`ORBIT_STEP_PIXELS`] to the right) or
/// "resize:WxH", and any of them repeated by a count: "Orbit*100". Keys go through [`key_action`] as a real
/// key press does, so a key with no action does nothing.
///
/// # Errors
/// A message naming the entry that is none of these.
pub fn parse_script(script: &str) -> Result<Vec<ScriptStep>, String> {
    let mut steps = Vec::new();
    for entry in script.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (step, count) = match entry.rsplit_once('*') {
            Some((step, count)) => match count.parse::<usize>() {
                Ok(count) if count > 0 => (step, count),
                _ => return Err(format!("`{entry}`: the count after * is not a whole number above 0")),
            },
            None => (entry, 1),
        };
        let step = parse_step(step)?;
        steps.extend(std::iter::repeat_n(step, count));
    }
    Ok(steps)
}

/// How far one "Orbit" step of a script drags the mouse, in pixels: 5, turning the camera by 0.05 rad
/// (2.9 degrees) about the look-at point.
pub const ORBIT_STEP_PIXELS: f32 = 5.0;

fn parse_step(entry: &str) -> Result<ScriptStep, String> {
    if entry == "Orbit" {
        return Ok(ScriptStep::Orbit);
    }
    let named = match entry {
        "Tab" => Some(NamedKey::Tab),
        "Up" => Some(NamedKey::ArrowUp),
        "Down" => Some(NamedKey::ArrowDown),
        "Left" => Some(NamedKey::ArrowLeft),
        "Right" => Some(NamedKey::ArrowRight),
        "Esc" => Some(NamedKey::Escape),
        _ => None,
    };
    if let Some(named) = named {
        return Ok(ScriptStep::Key(Key::Named(named)));
    }
    if entry.chars().count() == 1 {
        return Ok(ScriptStep::Key(Key::Character(entry.into())));
    }
    let size = entry.strip_prefix("resize:").and_then(|s| s.split_once('x'));
    match size.and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?))) {
        Some((w, h)) if w > 0 && h > 0 => Ok(ScriptStep::Resize(w, h)),
        _ => Err(format!("`{entry}` is neither a key, Orbit nor resize:WIDTHxHEIGHT")),
    }
}

/// A camera orbiting the scene's look-at point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// From the look-at point to the camera, in world units.
    pub distance: f32,
    /// Radians about the up axis (+y), from +z.
    pub yaw: f32,
    /// Radians above the horizontal plane, kept within +-1.5 so that up never meets the view direction.
    pub pitch: f32,
}

impl Orbit {
    /// The orbit that puts the camera where the scene has it.
    pub fn from_camera(camera: &Camera) -> Self {
        let offset = camera.position - camera.look_at;
        let distance = offset.length();
        Self { distance, yaw: offset.x.atan2(offset.z), pitch: (offset.y / distance).clamp(-1.0, 1.0).asin() }
    }

    /// Turns by a mouse drag of (dx, dy) pixels.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.01;
        self.pitch = (self.pitch + dy * 0.01).clamp(-1.5, 1.5);
    }

    /// Moves closer (positive lines) or farther.
    pub fn zoom(&mut self, lines: f32) {
        self.distance = (self.distance * 0.9f32.powf(lines)).max(1e-3);
    }

    /// The camera position for this orbit around `target`.
    pub fn position(&self, target: Vec3) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }
}

/// The preview's state: the selected object, the orbit and the scene as the user changed it.
pub struct Controls {
    /// The object the keys change: its index in the scene's objects.
    pub selected: usize,
    /// The camera's orbit about the scene's look-at point.
    pub orbit: Orbit,
    /// The scene file's shadows flags, restored when L is pressed again.
    scene_shadows: Option<Vec<bool>>,
    /// Whether the selected object's lobe is shown (B).
    pub show_lobe: bool,
    /// Which float parameter of a .brdf file Up and Down step (Left and Right choose), counted among its
    /// float parameters.
    pub analytic_parameter: usize,
}

impl Controls {
    /// Controls starting on the scene's own camera.
    pub fn new(scene: &Scene) -> Self {
        Self {
            selected: 0,
            orbit: Orbit::from_camera(&scene.camera),
            scene_shadows: None,
            show_lobe: false,
            analytic_parameter: 0,
        }
    }

    /// Applies an action to the scene (actions that are not about the scene do nothing here).
    pub fn apply(&mut self, action: Action, scene: &mut Scene, original_camera: &Camera) {
        let count = scene.objects.len();
        match action {
            Action::NextObject if count > 0 => {
                self.selected = (self.selected + 1) % count;
                self.analytic_parameter = 0;
            }
            Action::SetBrdf(index) => {
                if let Some(object) = scene.objects.get_mut(self.selected) {
                    object.brdf = switch_brdf(&object.brdf, index);
                }
            }
            Action::MainParameter(step) => {
                if let Some(object) = scene.objects.get_mut(self.selected) {
                    object.brdf = match &object.brdf {
                        Brdf::Analytic(material) => Brdf::Analytic(step_float(material, self.analytic_parameter, step)),
                        other => change_main_parameter(other.clone(), step),
                    };
                }
            }
            Action::Metalness(step) => {
                if let Some(object) = scene.objects.get_mut(self.selected) {
                    if let Brdf::Analytic(material) = &object.brdf {
                        let floats = float_parameters(material).len();
                        if floats > 0 {
                            self.analytic_parameter =
                                (self.analytic_parameter as i64 + i64::from(step)).rem_euclid(floats as i64) as usize;
                        }
                    }
                    if let Brdf::CookTorrance { ref mut metalness, .. } = object.brdf {
                        *metalness = (*metalness + 0.1 * step as f32).clamp(0.0, 1.0);
                    }
                }
            }
            Action::ToggleShadows => match self.scene_shadows.take() {
                Some(flags) => scene.lights.iter_mut().zip(flags).for_each(|(light, on)| light.shadows = on),
                None => {
                    self.scene_shadows = Some(scene.lights.iter().map(|l| l.shadows).collect());
                    scene.lights.iter_mut().for_each(|light| light.shadows = false);
                }
            },
            Action::ResetCamera => self.orbit = Orbit::from_camera(original_camera),
            Action::ToggleLobe => self.show_lobe = !self.show_lobe,
            _ => {}
        }
        self.selected = self.selected.min(count.saturating_sub(1));
        scene.camera.position = self.orbit.position(scene.camera.look_at);
    }

    /// The window title: the selected object, its BRDF and parameters, and the frame time.
    pub fn title(&self, scene: &Scene, frame_ms: f64) -> String {
        let Some(object) = scene.objects.get(self.selected) else {
            return format!("vk-render: no object - {frame_ms:.1} ms");
        };
        let shape = object.shape.kind();
        format!(
            "vk-render: object {}/{} ({shape}, material {}): {} - {frame_ms:.1} ms",
            self.selected + 1,
            scene.objects.len(),
            object.material,
            match &object.brdf {
                Brdf::Analytic(material) => describe_selected(material, self.analytic_parameter),
                other => describe(other),
            }
        )
    }
}

/// The names of a .brdf file's float parameters, the ones the keys step, in the file's order.
fn float_parameters(material: &Analytic) -> Vec<String> {
    material
        .values()
        .filter(|(p, _)| matches!(p.kind, ParameterKind::Float { .. }))
        .map(|(p, _)| p.name.clone())
        .collect()
}

/// `material` with its `index`-th float parameter moved by `step` twentieths of its range, within the range.
fn step_float(material: &Analytic, index: usize, step: i32) -> Analytic {
    let names = float_parameters(material);
    let Some(name) = names.get(index) else { return material.clone() };
    let (Some(parameter), Some(ParameterValue::Float(value))) =
        (material.model().parameter(name), material.value(name))
    else {
        return material.clone();
    };
    let ParameterKind::Float { min, max, .. } = parameter.kind else { return material.clone() };
    let moved = (value + (max - min) / 20.0 * step as f32).clamp(min, max);
    material.clone().with(name, ParameterValue::Float(moved)).unwrap_or_else(|_| material.clone())
}

/// A .brdf material's file and float parameters, the one the keys step in brackets:
/// `ward.brdf [alpha_x 0.10] alpha_y 0.35 (Up/Down step it, Left/Right choose)`.
fn describe_selected(material: &Analytic, index: usize) -> String {
    let names = float_parameters(material);
    let mut text = material.model().name();
    for (i, name) in names.iter().enumerate() {
        let Some(ParameterValue::Float(value)) = material.value(name) else { continue };
        if i == index {
            text.push_str(&format!(" [{name} {value:.3}]"));
        } else {
            text.push_str(&format!(" {name} {value:.3}"));
        }
    }
    if !names.is_empty() {
        text.push_str(" (Up/Down step it, Left/Right choose)");
    }
    text
}

/// The BRDF's name and parameters, e.g. "oren-nayar sigma 0.30".
pub fn describe(brdf: &Brdf) -> String {
    match *brdf {
        Brdf::Lambert { .. } => "lambert".into(),
        Brdf::OrenNayar { sigma, .. } => format!("oren-nayar sigma {sigma:.2}"),
        Brdf::Phong { shininess, .. } => format!("phong shininess {shininess:.0}"),
        Brdf::BlinnPhong { shininess, .. } => format!("blinn-phong shininess {shininess:.0}"),
        Brdf::CookTorrance { roughness, metalness, .. } => {
            format!("cook-torrance roughness {roughness:.2} metalness {metalness:.1}")
        }
        Brdf::Measured(_) | Brdf::Analytic(_) => crate::analysis::describe(brdf),
    }
}

/// The kd every model has.
fn diffuse_colour(brdf: &Brdf) -> Vec3 {
    match *brdf {
        Brdf::Lambert { kd }
        | Brdf::OrenNayar { kd, .. }
        | Brdf::Phong { kd, .. }
        | Brdf::BlinnPhong { kd, .. }
        | Brdf::CookTorrance { kd, .. } => kd,
        // pi f_r away from any highlight (wi and wo 60 degrees from n, a quarter turn apart): about the
        // reflectance of the measurement's diffuse part.
        Brdf::Measured(ref table) => {
            let (wi, wo) = (Vec3::new(0.866, 0.0, 0.5), Vec3::new(0.0, 0.866, 0.5));
            (std::f32::consts::PI * table.eval(Vec3::Z, Vec3::X, wi, wo)).clamp(Vec3::ZERO, Vec3::ONE)
        }
        // The file's first colour, which is most often its diffuse one; a grey where it has none.
        Brdf::Analytic(ref material) => material
            .values()
            .find_map(|(_, value)| match value {
                crate::brdf::ParameterValue::Color(c) => Some(c.clamp(Vec3::ZERO, Vec3::ONE)),
                _ => None,
            })
            .unwrap_or(Vec3::splat(0.5)),
    }
}

/// Another model with the same kd and the course's parameters: sigma 0.3; the plastic's ks 0.3 and
/// shininess 32; Cook-Torrance with F0 = kd, roughness 0.3, metalness 0.5 and the Oren-Nayar diffuse lobe.
/// Choosing the model the object already has keeps its parameters.
pub fn switch_brdf(brdf: &Brdf, index: usize) -> Brdf {
    let kd = diffuse_colour(brdf);
    let ks = Vec3::splat(0.3);
    let wanted = ["lambert", "oren-nayar", "phong", "blinn-phong", "cook-torrance"].get(index).copied();
    if wanted == Some(brdf.name()) {
        return brdf.clone();
    }
    match index {
        1 => Brdf::OrenNayar { kd, sigma: 0.3 },
        2 => Brdf::Phong { kd, ks, shininess: 32.0 },
        3 => Brdf::BlinnPhong { kd, ks, shininess: 32.0 },
        4 => Brdf::CookTorrance { kd, f0: kd, roughness: 0.3, metalness: 0.5, diffuse: DiffuseModel::OrenNayar },
        _ => Brdf::Lambert { kd },
    }
}

/// Sigma by 0.1 (from 0), shininess doubled or halved (from 1), roughness by 0.05 (within 0.05 and 1).
pub fn change_main_parameter(brdf: Brdf, step: i32) -> Brdf {
    let up = step > 0;
    match brdf {
        Brdf::OrenNayar { kd, sigma } => Brdf::OrenNayar { kd, sigma: (sigma + 0.1 * step as f32).max(0.0) },
        Brdf::Phong { kd, ks, shininess } => Brdf::Phong { kd, ks, shininess: scale_shininess(shininess, up) },
        Brdf::BlinnPhong { kd, ks, shininess } => {
            Brdf::BlinnPhong { kd, ks, shininess: scale_shininess(shininess, up) }
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse } => Brdf::CookTorrance {
            kd,
            f0,
            roughness: (roughness + 0.05 * step as f32).clamp(0.05, 1.0),
            metalness,
            diffuse,
        },
        // No parameter to change.
        unchanged @ (Brdf::Lambert { .. } | Brdf::Measured(_) | Brdf::Analytic(_)) => unchanged,
    }
}

fn scale_shininess(shininess: f32, up: bool) -> f32 {
    if up {
        (shininess * 2.0).max(1.0)
    } else {
        (shininess / 2.0).max(1.0)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// The actions of a script of keys, through the keyboard's mapping.
    fn key_actions(script: &str) -> Vec<Action> {
        let keys = parse_script(script).unwrap().into_iter();
        keys.map(|step| match step {
            ScriptStep::Key(key) => key_action(&key).unwrap_or_else(|| panic!("{key:?} has no action")),
            ScriptStep::Orbit | ScriptStep::Resize(..) => panic!("not a key in {script}"),
        })
        .collect()
    }

    fn figure_1() -> Scene {
        let text = include_str!("../../assets/scenes/fig1-lambert.toml");
        Scene::parse(text, Path::new("fig1.toml"), &[]).unwrap()
    }

    #[test]
    fn up_and_down_step_a_brdf_files_chosen_float_parameter_within_its_range() {
        let ward = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/brdfs/ward.brdf");
        let text = format!(
            "[material.m]\nbrdf = \"analytic\"\nfile = {:?}\nparams = {{ alpha_x = 0.96 }}\n[[object]]\nshape = \
             \"sphere\"\ncenter = [0, 0, 3]\nradius = 1.0\nmaterial = \"m\"\n",
            ward.display().to_string()
        );
        let mut scene = Scene::parse(&text, Path::new("ward.toml"), &[]).unwrap();
        let camera = scene.camera;
        let mut controls = Controls::new(&scene);
        let value = |scene: &Scene, name: &str| match &scene.objects[0].brdf {
            Brdf::Analytic(m) => match m.value(name) {
                Some(ParameterValue::Float(v)) => v,
                other => panic!("{name}: {other:?}"),
            },
            _ => panic!("not analytic"),
        };
        // alpha_x's range is [0.01, 1]: a step is 0.0495, and the top of the range holds.
        controls.apply(Action::MainParameter(1), &mut scene, &camera);
        assert_eq!(value(&scene, "alpha_x"), 1.0);
        controls.apply(Action::MainParameter(-1), &mut scene, &camera);
        assert!((value(&scene, "alpha_x") - (1.0 - 0.0495)).abs() < 1e-6);
        // Right chooses the next float parameter, alpha_y (the colours are not stepped).
        controls.apply(Action::Metalness(1), &mut scene, &camera);
        controls.apply(Action::MainParameter(-1), &mut scene, &camera);
        assert!((value(&scene, "alpha_y") - (0.15 - 0.0495)).abs() < 1e-6);
        let title = controls.title(&scene, 1.0);
        assert!(title.contains("ward.brdf alpha_x 0.95") && title.contains(" [alpha_y 0.10"), "{title}");
        // Left from the first wraps round to the last.
        controls.apply(Action::Metalness(-1), &mut scene, &camera);
        controls.apply(Action::Metalness(-1), &mut scene, &camera);
        assert_eq!(controls.analytic_parameter, 1);
    }

    #[test]
    fn keys_switch_the_selected_objects_brdf_and_its_parameters() {
        let mut scene = figure_1();
        let camera = scene.camera;
        let mut controls = Controls::new(&scene);
        for action in key_actions("2, Up, Up") {
            controls.apply(action, &mut scene, &camera);
        }
        assert!(matches!(scene.objects[0].brdf, Brdf::OrenNayar { sigma, .. } if (sigma - 0.5).abs() < 1e-6));
        assert_eq!(scene.objects[1].brdf, figure_1().objects[1].brdf, "the plane is not selected");
        for action in key_actions("Tab,5,Right,Right,Down") {
            controls.apply(action, &mut scene, &camera);
        }
        assert_eq!(controls.selected, 1);
        let Brdf::CookTorrance { roughness, metalness, kd, f0, .. } = scene.objects[1].brdf else {
            panic!("{:?}", scene.objects[1].brdf)
        };
        assert!((roughness - 0.25).abs() < 1e-6 && (metalness - 0.7).abs() < 1e-6);
        assert_eq!((kd, f0), (Vec3::X, Vec3::X), "kd kept, F0 = kd");
        assert!(controls
            .title(&scene, 12.34)
            .contains("object 2/2 (plane, material red): cook-torrance roughness 0.25 metalness 0.7 - 12.3 ms"));
    }

    #[test]
    fn shadows_toggle_off_and_back() {
        let mut scene = figure_1();
        let camera = scene.camera;
        let mut controls = Controls::new(&scene);
        controls.apply(Action::ToggleShadows, &mut scene, &camera);
        assert!(!scene.lights[0].shadows);
        controls.apply(Action::ToggleShadows, &mut scene, &camera);
        assert!(scene.lights[0].shadows);
    }

    #[test]
    fn the_orbit_starts_on_the_scene_camera_and_resets_to_it() {
        let mut scene = figure_1();
        let camera = scene.camera;
        let mut controls = Controls::new(&scene);
        assert!(controls.orbit.position(camera.look_at).abs_diff_eq(camera.position, 1e-5));
        controls.orbit.drag(120.0, -40.0);
        controls.orbit.zoom(2.0);
        controls.apply(Action::NextObject, &mut scene, &camera);
        assert!(!scene.camera.position.abs_diff_eq(camera.position, 1e-3));
        assert!(((scene.camera.position - camera.look_at).length() - 0.81).abs() < 1e-4, "zoomed by 0.9^2");
        controls.apply(Action::ResetCamera, &mut scene, &camera);
        assert!(scene.camera.position.abs_diff_eq(camera.position, 1e-5));
    }

    #[test]
    fn scripts_parse_or_name_the_bad_entry() {
        assert_eq!(
            parse_script("Tab, 3 ,resize:200x150,Esc,6").unwrap(),
            vec![
                ScriptStep::Key(Key::Named(NamedKey::Tab)),
                ScriptStep::Key(Key::Character("3".into())),
                ScriptStep::Resize(200, 150),
                ScriptStep::Key(Key::Named(NamedKey::Escape)),
                ScriptStep::Key(Key::Character("6".into())),
            ]
        );
        assert_eq!(key_action(&Key::Character("6".into())), None, "6 is a key with no action");
        assert_eq!(key_actions("Tab, 3, l, S, r, Esc, Left"), {
            use Action::*;
            vec![NextObject, SetBrdf(2), ToggleShadows, Screenshot, ResetCamera, Quit, Metalness(-1)]
        });
        assert!(parse_script("Tab,Foo").unwrap_err().contains("`Foo`"));
        assert_eq!(parse_script("Orbit*3,Tab").unwrap().len(), 4);
        assert_eq!(parse_script("Orbit").unwrap(), vec![ScriptStep::Orbit]);
        assert!(parse_script("Orbit*0").unwrap_err().contains("`Orbit*0`"));
        assert!(parse_script("Orbit*x").is_err());
        assert!(parse_script("resize:0x10").is_err());
    }
}
