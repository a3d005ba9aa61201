// The explore page's state: the scene chosen, the overrides its controls made, who draws its frames, and
// what the page's parts ask of it. Every part of the page (frames.js, controls.js, studies.js, editor.js)
// reads and writes this one object.
import { SITE } from "../site.js";

export const page = {
  scenes: [],
  scene: null,     // the chosen scene's description (GET /api/scenes)
  set: {},         // the overrides the controls made, by `--set` key
  socket: null,
  sent: 0,         // states sent
  pending: null,   // the header of the frame whose PNG comes next
  frames: [],      // when the frames of the last second were shown, for the rate shown
  browser: null,   // the browser's renderer (renderer/renderer.js), or null
  noBrowser: "",   // why there is none
  mode: "server",  // who renders this scene's frames: "browser" or "server"
  drawing: false,  // a browser frame is asked for the next animation frame
  serverReason: "", // why the server renders this scene's frames
  firstFrame: undefined,  // when the browser drew its first frame, in ms since the page opened (make bench-serve)
  socketSent: 0,   // messages sent on the socket, which numbers its frames so
  socketStates: new Map(), // the page's state (page.sent) of each message sent on the socket, until its frames come
  restTimer: null, // draws the browser's still frame once the controls rest
  loaded: null,    // the scene whose meshes, tables and shaders the browser's renderer holds
  statusShown: 0,  // when the status line was last written
  studentStudies: null,  // the editor's studies of the student's own model (editor.js), once it is on the page
};

export const $ = (id) => document.getElementById(id);

export function showError(message) {
  $("error").textContent = message || "";
}

// The picture's size: the scene's own, scaled down to fit the page's column (at most 1280 pixels wide).
export function pictureSize() {
  const scene = page.scene;
  const room = Math.min(1280, Math.max(64, $("frame").parentElement.clientWidth));
  const scale = Math.min(1, room / scene.width);
  return [Math.max(16, Math.round(scene.width * scale)), Math.max(16, Math.round(scene.height * scale))];
}

export function request() {
  const [width, height] = pictureSize();
  return { scene: page.scene.id, set: page.set, width, height };
}

// Whether the browser's frames of this scene are not its exact image: an environment's light that `render`
// integrates exactly (the browser draws its fast mode). Its still frame is then the server's, if there is one.
export function notExact() {
  const environment = page.scene.browser.environment;
  return Boolean(environment && !environment.fast);
}
export function stillFromServer() {
  return !SITE && notExact();
}

// Whether the browser draws the page's scene, its data loaded (a scene just chosen is still loading).
export function browserHoldsScene() {
  return page.mode === "browser" && Boolean(page.browser) && page.loaded === page.scene;
}

// Whether an object of the page's scene is made of the student's own model.
export function studentModelShown() {
  return Boolean(page.scene && page.scene.objects.some((object) => isStudentMaterial(object.material)));
}

// Whether `material` of the page's scene is the student's own model (editor.js).
export function isStudentMaterial(material) {
  return Boolean(page.scene && page.scene.materials[material] && page.scene.materials[material].student);
}
