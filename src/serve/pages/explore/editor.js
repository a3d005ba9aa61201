// The explore page's editor of a student's own BRDF: a BRDF Explorer `.brdf` file written here (from an
// example), opened or dropped; read and wrapped by the library's own code (static/vk-render.wasm: the crate
// brdf-file, which the renderer reads `.brdf` files with), put into the translated forward passes' templates
// (static/brdf-templates.json) and compiled by this browser's WebGL2, then drawn on the selected object.
// Nothing is sent anywhere: the text stays in this browser's storage, and downloads as a file that
// `vk-render render` renders.
import { el, getJson } from "../common.js";
import { library } from "../wasm.js";
import { analyticSuffix } from "../renderer/resources.js";
import { drawAlbedo, drawLobe } from "./charts.js";
import { chooseScene, materialControls, objectChoices } from "./controls.js";
import { chooseRenderer } from "./frames.js";
import { $, browserHoldsScene, isStudentMaterial, page } from "./state.js";
import { browserAlbedo, browserLobe } from "./studies.js";

// Where this browser keeps the text.
const EDITOR_STORAGE = "vk-render.brdf";
// The line of a template that the model's GLSL replaces (build/webgl.rs: TEMPLATE_HOOK).
const TEMPLATE_HOOK = "// ANALYTIC_BRDF_HOOK";
// src/render/gpu_types.rs's BRDF_ANALYTIC: an analytic model's Material.brdf.
const ANALYTIC_BRDF_ID = 6;
// The name the student's material takes in the scene (with a number per compile: the shaders' name).
const STUDENT_MATERIAL = "your-brdf";
// The example the editor starts from.
const EXAMPLE_BRDF = `analytic
# Your own BRDF, in BRDF Explorer's format: its parameters (each one a
# slider), then a GLSL ES 3.00 function that returns f_r, without the
# cosine, for the light's direction L and the view V at a surface of
# normal N and tangents X and Y (unit vectors, away from the surface).
# Write 2.0, not 2: GLSL ES makes no integer a float.

::begin parameters
color kd 0.5 0.12 0.1
color ks 0.04 0.04 0.04
float shininess 1 1000 64
::end parameters

::begin shader
const float PI = 3.14159265358979;

// Lambert, plus a normalised Blinn-Phong lobe.
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    vec3 H = normalize(L + V);
    float lobe = (shininess + 8.0) / (8.0 * PI) * pow(max(dot(N, H), 0.0), shininess);
    return kd / PI + ks * lobe;
}
::end shader
`;

export const editor = {
  reader: null,     // the WebAssembly library (WasmLibrary), once loaded
  templates: null,  // the analytic templates by entry, once fetched
  model: null,      // the model drawn now: what read_brdf answered, with its shaders
  serial: 0,        // models compiled so far: each one's shaders have a name of their own
  fileName: "my.brdf",
  saveTimer: null,
};

function editorStatus(message) {
  $("editor-status").textContent = message;
}

// Shows a mistake: at its line of the text (selected in the editor) where it has one.
function editorError(line, message) {
  $("editor-error").textContent = message ? (line ? `line ${line}: ${message}` : message) : "";
  if (!line) return;
  const text = $("editor-text");
  const lines = text.value.split("\n");
  const start = lines.slice(0, line - 1).reduce((sum, l) => sum + l.length + 1, 0);
  text.setSelectionRange(start, start + (lines[line - 1] || "").length);
}

// The editor's text as the file it downloads.
export function editorFile() {
  return $("editor-text").value;
}

// Reads, wraps and compiles the editor's text, and draws it on the selected object in place of its material.
async function drawStudentModel() {
  editorError(0, "");
  saveStudentText();
  const scene = page.scene;
  if (!scene) return;
  if (!page.browser) return editorError(0, `your browser cannot draw it: ${page.noBrowser}`);
  if (scene.browser.environment) {
    return editorError(0, "your model is drawn under point lights: choose a scene without an environment (its fast mode needs the material's albedo table, which vk-render makes)");
  }
  try {
    if (!editor.reader) editor.reader = await library();
    if (!editor.templates) editor.templates = await getJson("static/brdf-templates.json");
  } catch (error) {
    return editorError(0, `the editor could not start: ${error.message}`);
  }
  let read;
  try {
    read = editor.reader.call("read_brdf", editorFile());
  } catch (error) {
    return editorError(0, error.message);
  }
  if (read.error) return editorError(read.error.line, read.error.message);
  const shaders = {};
  // (A function, so that no `$` of the text is taken for a replacement pattern.)
  for (const [entry, template] of Object.entries(editor.templates)) shaders[entry] = template.replace(TEMPLATE_HOOK, () => read.glsl);
  const log = compileLog(page.browser.gl, shaders["forward_sphere.frag"]);
  if (log !== null) {
    const error = editor.reader.call("read_compiler_log", log);
    return editorError(error.line, error.message);
  }
  // One model at a time: the one drawn before, its shaders and programs go.
  if (editor.model && page.browser) page.browser.forget(analyticSuffix(scene, editor.model.name));
  editor.serial += 1;
  editor.model = { ...read, shaders, name: `${STUDENT_MATERIAL}-${editor.serial}` };
  const object = Number($("object").value);
  page.scene = withStudentModel(scene, object, editor.model);
  registerStudentShaders(page.browser);
  objectChoices();
  $("object").value = String(object);
  materialControls();
  editorStatus(`${editor.fileName}: compiled by your browser, drawn on object ${object}` +
    (read.warnings.length ? `; ${read.warnings.join("; ")}` : ""));
  // Its frame, then its lobe (sendState's studies, once the scene is loaded).
  chooseRenderer();
}

// The student's model studied by this browser: its lobe (f_r cos θo in the plane of incidence, by the
// probe pass) and its albedo, drawn; and said where its loops were stopped.
export function studentStudies() {
  const index = page.scene.objects.findIndex((object) => isStudentMaterial(object.material));
  if (index < 0 || !browserHoldsScene()) return;
  let lobe;
  try {
    lobe = browserLobe(index);
  } catch (error) {
    return editorError(0, `its lobe: ${error.message}`);
  }
  editor.lobe = lobe;
  $("editor-lobe").parentElement.hidden = false;
  drawLobe($("editor-lobe"), lobe);
  saidStopped(lobe.stopped);
  studentAlbedo(index);
}

// Says whether the model's loops were stopped by the page's guard (in its lobe or its albedo).
function saidStopped(stopped) {
  $("editor-error").textContent = stopped
    ? `its loops ran past ${STOPPED_STEPS} steps in one evaluation (a loop that never ends?): the page stopped them, and draws 0 there`
    : "";
}

// The student's model's directional albedo, computed by this browser (browserAlbedo), drawn with its bound.
async function studentAlbedo(index) {
  const scene = page.scene;
  $("editor-albedo-status").textContent = "its directional albedo: integrating...";
  let albedo;
  try {
    albedo = await browserAlbedo(index);
  } catch (error) {
    if (page.scene === scene) editorError(0, `its albedo: ${error.message}`);
    return;
  }
  if (!albedo || page.scene !== scene) return;
  editor.albedo = albedo;
  drawAlbedo($("editor-albedo"), albedo);
  $("editor-albedo-status").textContent = `its directional albedo at ${albedo.theta_o.length} angles, in ${albedo.rounds} rounds of cells`;
  if (albedo.stopped) saidStopped(true);
}

// crates/brdf-file's WEBGL_MAX_LOOP_STEPS: the steps the loops of a model may take in one evaluation.
const STOPPED_STEPS = 4096;


// The compiler's log of a fragment shader that does not compile; null when it does.
function compileLog(gl, text) {
  const shader = gl.createShader(gl.FRAGMENT_SHADER);
  gl.shaderSource(shader, text);
  gl.compileShader(shader);
  const log = gl.getShaderParameter(shader, gl.COMPILE_STATUS) ? null : gl.getShaderInfoLog(shader) || "it does not compile";
  gl.deleteShader(shader);
  return log;
}

// `scene` with object `index` made of the student's model at its defaults, as the server describes an
// analytic material (description.rs, browser.rs): its controls, and its values as the renderer's buffer holds them.
// The objects of a model drawn before take the new one, which replaces it (and the page's overrides of it go).
function withStudentModel(scene, index, model) {
  const derived = JSON.parse(JSON.stringify(scene));
  const name = model.name;
  for (const [old, material] of Object.entries(scene.materials)) {
    if (!material.student) continue;
    delete derived.materials[old];
    delete derived.browser.materials[old];
    for (const key of Object.keys(page.set)) if (key.startsWith(`material.${old}.`)) delete page.set[key];
    derived.objects.forEach((object, k) => {
      if (object.material !== old) return;
      object.material = name;
      derived.browser.objects[k].material = name;
    });
  }
  derived.materials[name] = {
    model: "analytic",
    file: editor.fileName,
    student: true,
    parameters: model.parameters.map((p) => ({ ...p, key: `material.${name}.params.${p.name}` })),
  };
  const zero = [0, 0, 0, 0];
  derived.browser.materials[name] = {
    kd: zero, ks: zero, f0: zero, brdf: ANALYTIC_BRDF_ID, shininess: 0, sigma: 0, roughness: 0, metalness: 0,
    diffuse: 0, measured_table: false, analytic_values: model.values, analytic_offsets: model.offsets,
  };
  derived.objects[index].material = name;
  derived.browser.objects[index].material = name;
  return derived;
}

// The student's shaders beside the renderer's, under the names the renderer looks for (analyticSuffix).
export function registerStudentShaders(renderer) {
  if (!renderer || !editor.model || !page.scene.materials[editor.model.name]) return;
  for (const [entry, text] of Object.entries(editor.model.shaders)) {
    renderer.shaders[entry + analyticSuffix(page.scene, editor.model.name)] = text;
  }
}

// Reads a file opened or dropped into the editor: refused unread past the reader's limit.
async function openStudentFile(file) {
  editorError(0, "");
  const limit = editor.reader ? editor.reader.maxBytes : 256 * 1024;
  if (file.size > limit) return editorError(0, `${file.name} is ${file.size} bytes: the editor takes a .brdf file of at most ${limit}`);
  let text;
  try {
    text = await file.text();
  } catch (error) {
    return editorError(0, `${file.name}: ${error.message}`);
  }
  editor.fileName = file.name;
  $("editor-text").value = text;
  saveStudentText();
  drawStudentModel();
}

function saveStudentText() {
  try {
    localStorage.setItem(EDITOR_STORAGE, JSON.stringify({ name: editor.fileName, text: editorFile() }));
  } catch (error) {
    editorStatus(`this browser did not keep your text (${error.message})`);
  }
}

function downloadStudentFile() {
  const link = el("a", { href: URL.createObjectURL(new Blob([editorFile()], { type: "text/plain" })), download: editor.fileName });
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(link.href), 1000);
}

export function startEditor() {
  page.studentStudies = studentStudies;
  const text = $("editor-text");
  let kept = null;
  try {
    kept = JSON.parse(localStorage.getItem(EDITOR_STORAGE) || "null");
  } catch (error) {
    kept = null;
  }
  text.value = kept && typeof kept.text === "string" ? kept.text : EXAMPLE_BRDF;
  if (kept && typeof kept.name === "string") editor.fileName = kept.name;
  text.addEventListener("input", () => {
    clearTimeout(editor.saveTimer);
    editor.saveTimer = setTimeout(saveStudentText, 300);
  });
  text.addEventListener("keydown", (event) => {
    if (event.key === "Enter" && (event.ctrlKey || event.metaKey)) {
      event.preventDefault();
      drawStudentModel();
    }
  });
  text.addEventListener("dragover", (event) => { event.preventDefault(); text.classList.add("over"); });
  text.addEventListener("dragleave", () => text.classList.remove("over"));
  text.addEventListener("drop", (event) => {
    event.preventDefault();
    text.classList.remove("over");
    const file = event.dataTransfer.files[0];
    if (file) openStudentFile(file);
  });
  $("editor-file").addEventListener("change", (event) => {
    const file = event.target.files[0];
    event.target.value = "";
    if (file) openStudentFile(file);
  });
  $("editor-apply").addEventListener("click", drawStudentModel);
  $("editor-download").addEventListener("click", downloadStudentFile);
  $("editor-example").addEventListener("click", () => {
    text.value = EXAMPLE_BRDF;
    editor.fileName = "my.brdf";
    saveStudentText();
  });
  $("editor-off").addEventListener("click", () => { editorStatus(""); editorError(0, ""); chooseScene(page.scene.id); });
}

