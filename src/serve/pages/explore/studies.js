// The studies of the selected object's material beside its picture: its lobe and its directional albedo,
// the server's plots (POST /api/lobe, /api/albedo) or, in a folder of vk-render site and for a student's own
// model, computed by this browser (the renderer's probe pass; the library's cubature as WebAssembly).
import { SITE } from "../site.js";
import { postJson } from "../common.js";
import { library } from "../wasm.js";
import { drawAlbedo, drawLobe } from "./charts.js";
import { $, browserHoldsScene, isStudentMaterial, page, showError, studentModelShown } from "./state.js";

// The lobe's incidence and angles: the page's lobe at θi 30°, θo every half degree from -90 to
// 90 (src/analysis/lobe.rs: LOBE_STEP_DEGREES), negative on the side of wi.
const LOBE_THETA_I = 30;
const LOBE_ANGLES = [...Array(361).keys()].map((k) => -90 + 0.5 * k);

// The directions of the lobe's cut in the plane of incidence: wi, and wo at each of LOBE_ANGLES (degrees),
// as src/analysis/lobe.rs's cut_directions makes them (n = +z, wi at +x).
function lobeDirections(thetaI) {
  const radians = (degrees) => (degrees * Math.PI) / 180;
  const wi = [Math.sin(radians(thetaI)), 0, Math.cos(radians(thetaI))];
  return LOBE_ANGLES.map((theta) => [wi, [-Math.sin(radians(theta)), 0, Math.cos(radians(theta))]]);
}

// The directional albedo of object `index`'s material with the page's overrides at ALBEDO_ANGLES, computed
// by this browser (WasmLibrary.albedo: the library's cubature, this browser's albedo probe); null when a
// later one started meanwhile. The last one asked is kept: asked again (the editor's and the studies' column
// of the same model), it is not integrated twice.
let albedoAsked = null;
export function browserAlbedo(index) {
  const state = studiedState(index);
  const key = JSON.stringify(state);
  if (albedoAsked && albedoAsked.key === key && albedoAsked.renderer === page.browser) return albedoAsked.promise;
  const [renderer, scene] = [page.browser, page.scene];
  const promise = library().then((wasm) => wasm.albedo(renderer, scene, state.set, index, ALBEDO_ANGLES));
  albedoAsked = { key, renderer, promise };
  promise.catch(() => { if (albedoAsked && albedoAsked.promise === promise) albedoAsked = null; });
  return promise;
}

// The lobe of object `index`'s material with the page's overrides, computed by this browser's probe pass
// (renderer/probe.js): f_r cos θo per channel at each of LOBE_ANGLES, and whether an analytic model's loops
// were stopped there (a student's model: editor.js).
export function browserLobe(index) {
  const values = page.browser.probe(page.scene, page.set, index, lobeDirections(LOBE_THETA_I));
  const lobe = values.map(([r, g, b], k) => {
    const cosine = Math.max(Math.cos((LOBE_ANGLES[k] * Math.PI) / 180), 0);
    return [r * cosine, g * cosine, b * cosine];
  });
  return { theta_i: LOBE_THETA_I, theta_o: LOBE_ANGLES, values: lobe, stopped: values.some((v) => v[3] !== 0) };
}

// A folder of vk-render site: the selected object's lobe and albedo, computed by this browser (the server's
// plots are the server's).
export async function siteStudies() {
  const index = Number($("object").value);
  if (!browserHoldsScene() || !page.scene.objects[index]) return;
  try {
    page.lobe = browserLobe(index);
  } catch (error) {
    return showError(`the lobe: ${error.message}`);
  }
  drawLobe($("browser-lobe"), page.lobe);
  const scene = page.scene;
  try {
    const albedo = await browserAlbedo(index);
    if (!albedo || page.scene !== scene) return;
    page.albedo = albedo;
    drawAlbedo($("browser-albedo"), albedo);
  } catch (error) {
    if (page.scene === scene) showError(`the albedo: ${error.message}`);
  }
}

// The outgoing angles of the page's albedo chart, in degrees.
const ALBEDO_ANGLES = [...Array(18).keys()].map((k) => 5 * k).concat([89]);

let studiesTimer = null;
let studiesAsked = 0;
let studied = null;  // the material state the lobe and the albedo shown are of
export function studiesLater() {
  clearTimeout(studiesTimer);
  studiesTimer = setTimeout(studies, 250);
}

// Object `index`'s material (the selected object's by default) and the overrides that change it (the lobe
// and the albedo depend on these alone: moving the camera or a light asks the server for nothing).
function studiedState(index = Number($("object").value)) {
  const object = page.scene.objects[index];
  if (!object) return null;
  const prefix = `material.${object.material}.`;
  const set = Object.fromEntries(Object.entries(page.set).filter(([key]) => key.startsWith(prefix)));
  return { scene: page.scene.id, material: object.material, set };
}

// The lobe and the albedo of the selected object's material with the current overrides, unless shown.
export async function studies() {
  // A student's model is studied by the browser (the server never sees it).
  if (studentModelShown() && page.studentStudies) page.studentStudies();
  const object = page.scene.objects[Number($("object").value)];
  if (SITE) return siteStudies();
  if (object && isStudentMaterial(object.material)) return;  // the server never sees a student's model
  const body = studiedState();
  if (!body || JSON.stringify(body) === studied) return;
  studied = JSON.stringify(body);
  const asked = ++studiesAsked;
  for (const [id, path] of [["lobe", "/api/lobe?format=svg"], ["albedo", "/api/albedo?format=svg"]]) {
    try {
      // The albedo every 5 degrees (and at 89): a fifth of the default's 90 angles' work on the server, so
      // that a class's rests keep within what its workers do (make bench-serve).
      const request = id === "albedo" ? { ...body, theta_o: ALBEDO_ANGLES } : body;
      const blob = await (await postJson(path, request)).blob();
      if (asked !== studiesAsked) return;
      const image = $(id);
      if (image.src) URL.revokeObjectURL(image.src);
      image.src = URL.createObjectURL(blob);
    } catch (error) {
      studied = null;
      showError(`${id}: ${error.message}`);
    }
  }
}
