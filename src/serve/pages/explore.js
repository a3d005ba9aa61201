// The explore page: the controls of a scene's material, light and camera, and its frames: rendered in the
// visitor's browser (WebGL2, webgl.js) where the browser and the scene allow, every frame then the exact one;
// otherwise the server's over a WebSocket (motion frames while a control moves, then the exact still frame).
"use strict";

const page = {
  scenes: [],
  scene: null,     // the chosen scene's description (GET /api/scenes)
  set: {},         // the overrides the controls made, by `--set` key
  socket: null,
  sent: 0,         // states sent
  pending: null,   // the header of the frame whose PNG comes next
  frames: [],      // when the frames of the last second were shown, for the rate shown
  browser: null,   // the browser's renderer (webgl.js), or null
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
};

const $ = (id) => document.getElementById(id);

function showError(message) {
  $("error").textContent = message || "";
}

// The picture's size: the scene's own, scaled down to fit the page's column (at most 1280 pixels wide).
function pictureSize() {
  const scene = page.scene;
  const room = Math.min(1280, Math.max(64, $("frame").parentElement.clientWidth));
  const scale = Math.min(1, room / scene.width);
  return [Math.max(16, Math.round(scene.width * scale)), Math.max(16, Math.round(scene.height * scale))];
}

function request() {
  const [width, height] = pictureSize();
  return { scene: page.scene.id, set: page.set, width, height };
}

// The page's state changed: its frame, in the browser (a motion frame at the next animation frame, the
// still frame once the controls rest; `still`: at once, a scene's first) or from the server.
function sendState(still) {
  if (page.mode === "browser") {
    page.sent += 1;
    clearTimeout(page.restTimer);
    if (still === true) drawInBrowser(false);
    else {
      if (!page.drawing) {
        page.drawing = true;
        requestAnimationFrame(() => drawInBrowser(true));
      }
      page.restTimer = setTimeout(() => drawInBrowser(false), SETTLE_MS);
    }
    studiesLater();
    return;
  }
  if (SITE) return;  // no server: nothing draws it (useServer said why)
  if (!page.socket) connect();
  if (page.socket.readyState !== WebSocket.OPEN) return;
  page.sent += 1;
  sendOnSocket(false);
  studiesLater();
}

// Sends the page's state on the socket (the server's frames, or its still frame: `still`), noting which.
function sendOnSocket(still) {
  page.socketSent += 1;
  page.socketStates.set(page.socketSent, page.sent);
  page.socket.send(JSON.stringify({ ...request(), ...(still ? { still: true } : {}) }));
}

// Whether the browser's frames of this scene are not its exact image: an environment's light that `render`
// integrates exactly (the browser draws its fast mode). Its still frame is then the server's, if there is one.
function notExact() {
  const environment = page.scene.browser.environment;
  return Boolean(environment && !environment.fast);
}
function stillFromServer() {
  return !SITE && notExact();
}

// How long the controls rest before the still frame is drawn or asked for (the server's SETTLE,
// src/serve/explore.rs).
const SETTLE_MS = 150;
// A motion frame's size, a fraction of the picture's: the server's motion frames' (src/render/interactive.rs,
// MOTION_SCALE), scaled up to the picture by the page, and drawn with the objects' lighter meshes
// (src/mesh/motion.rs). A CPU's WebGL (SwiftShader) shades a pixel of the bunny's one-pixel triangles several
// times over (2 x 2 quads) and sets up each of its triangles: half the size, a third of the shading.
const MOTION_SCALE = 2;
// How often the status line is written while a control moves (the page's layout costs a frame's tenth).
const MOTION_STATUS_MS = 250;

// The browser's frame of the latest state: while a control moves (`motion`), at half the picture's size and
// scaled up; otherwise the still frame, at the picture's size: the exact image, or (see stillFromServer) the
// environment's fast mode until the server's still frame comes.
function drawInBrowser(motion) {
  page.drawing = false;
  if (page.mode !== "browser") return;
  const [width, height] = pictureSize();
  const scale = motion ? MOTION_SCALE : 1;
  // An environment's albedo tables of materials that moved come from the server: the still frame is drawn
  // again when they are here (meanwhile with the last ones).
  const missing = page.browser.missingAlbedo(page.scene, page.set);
  const state = page.sent;
  if (missing) {
    missing.then(() => { if (page.sent === state && !motion) drawInBrowser(false); },
      (error) => useServer(`its albedo tables did not come (${error.message})`));
  }
  try {
    page.browser.render(page.scene, page.set, Math.ceil(width / scale), Math.ceil(height / scale), motion);
  } catch (error) {
    useServer(`your browser could not draw it (${error.message})`);
    return;
  }
  const canvas = $("gl");
  canvas.style.width = `${width}px`;
  if (page.firstFrame === undefined) page.firstFrame = performance.now();
  $("frame").hidden = true;
  canvas.hidden = false;
  canvas.dataset.frame = motion ? "motion" : "still";
  canvas.dataset.scene = page.scene.id;
  if (!missing && !motion) canvas.dataset.state = String(state);
  const rate = framesThisSecond();
  const now = performance.now();
  if (motion && now - page.statusShown < MOTION_STATUS_MS) return;
  page.statusShown = now;
  const size = motion ? `${Math.ceil(width / scale)} x ${Math.ceil(height / scale)} scaled up` : `${width} x ${height}`;
  if (stillFromServer()) {
    $("status").textContent = `rendered by your browser (WebGL2), the environment's fast mode, ${size}, ${rate} frames/s; the exact image from the server once the controls rest`;
    if (!missing && !motion) askServerStill();
  } else if (notExact()) {
    $("status").textContent = `rendered by your browser (WebGL2), the environment's fast mode, ${size}, ${rate} frames/s; the exact image is vk-render render's`;
  } else {
    $("status").textContent = motion
      ? `moving: rendered by your browser (WebGL2), ${size}, ${rate} frames/s`
      : `rendered by your browser (WebGL2): the exact image, ${size}`;
  }
}

// Asks the server for the still frame of the latest state (the browser draws this scene's motion frames).
function askServerStill() {
  if (page.mode !== "browser" || !stillFromServer()) return;
  if (!page.socket) return connect();  // its opening asks
  if (page.socket.readyState === WebSocket.OPEN) sendOnSocket(true);
}

// Counts a frame shown now; the frames shown in the last second.
function framesThisSecond() {
  const now = performance.now();
  page.frames = page.frames.filter((t) => now - t < 1000).concat([now]);
  return page.frames.length;
}

// The browser's frame drawn now and its pixels read back (rows from the top, RGBA): for the browser test.
function browserPixels() {
  drawInBrowser(false);
  return page.browser.pixels();
}

// The server renders this scene's frames, for `why`; a folder of vk-render site has none, and says so, as
// for a student's own model, which only this browser has.
function useServer(why) {
  const student = studentModelShown();
  if (SITE || student) {
    page.mode = "none";
    $("gl").hidden = true;
    $("frame").hidden = false;
    $("status").textContent = student
      ? `your browser cannot draw your model now: ${why}; vk-render render can (download your .brdf)`
      : `this page cannot draw it: ${why}; vk-render render and vk-render serve can`;
    return;
  }
  page.mode = "server";
  page.serverReason = why;
  $("gl").hidden = true;
  $("frame").hidden = false;
  $("frame").dataset.frame = "none";
  $("status").textContent = `the server's frames: ${why}`;
  if (!page.socket) connect();
  else sendState();
}

// Who renders the chosen scene: the browser when it can draw it, the server otherwise.
async function chooseRenderer() {
  const scene = page.scene;
  if (!page.browser) return useServer(page.noBrowser);
  if (scene.browser.unsupported) return useServer(`your browser does not draw ${scene.browser.unsupported} yet`);
  try {
    await page.browser.load(scene);
  } catch (error) {
    return useServer(`its meshes did not load (${error.message})`);
  }
  if (page.scene !== scene) return;
  page.mode = "browser";
  page.loaded = scene;
  $("frame").hidden = true;
  $("gl").hidden = false;
  sendState(true);
}

function connect() {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  const socket = new WebSocket(`${scheme}//${location.host}/api/explore`);
  socket.binaryType = "blob";
  page.socketSent = 0;
  page.socketStates = new Map();
  socket.onopen = () => {
    if (page.mode === "server") {
      $("status").textContent = "connected";
      sendState();
    } else askServerStill();
  };
  socket.onclose = (event) => {
    page.socket = null;
    if (page.mode !== "server") return;
    $("status").textContent = `disconnected${event.reason ? ": " + event.reason : ""}; reconnecting...`;
    setTimeout(() => { if (!page.socket && page.mode === "server") connect(); }, 1000);
  };
  socket.onmessage = async (event) => {
    if (typeof event.data === "string") {
      const message = JSON.parse(event.data);
      if (message.error) showError(message.error);
      else page.pending = message;
      return;
    }
    const header = page.pending;
    page.pending = null;
    if (!header) return;
    // The page's state the frame is of; the messages before it will have no frame (a message's motion and
    // still frames come in its order).
    for (const number of page.socketStates.keys()) if (number < header.state) page.socketStates.delete(number);
    header.state = page.socketStates.get(header.state);
    if (page.mode === "browser" && !(header.kind === "still" && header.state === page.sent && stillFromServer())) return;
    const bitmap = await createImageBitmap(event.data);
    if (page.mode === "browser" && header.state !== page.sent) return;  // the controls moved meanwhile
    if (page.mode === "browser") {
      $("gl").hidden = true;
      $("frame").hidden = false;
    }
    draw(header, bitmap);
  };
  page.socket = socket;
}

// Draws a frame: a motion frame scaled up to the picture's size, the still frame pixel for pixel.
function draw(header, bitmap) {
  const canvas = $("frame");
  const [width, height] = header.kind === "still" ? [header.width, header.height] : pictureSize();
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  const context = canvas.getContext("2d");
  context.imageSmoothingEnabled = header.kind !== "still";
  context.drawImage(bitmap, 0, 0, width, height);
  canvas.dataset.frame = header.kind;
  canvas.dataset.state = String(header.state);
  const rate = framesThisSecond();
  $("status").textContent = (header.kind === "still"
    ? `still: the exact image, ${header.width} x ${header.height}`
    : `moving: ${rate} frames/s at ${header.width} x ${header.height}, scaled up`) +
    (page.mode === "browser"
      ? " (from the server, which integrates the environment's light exactly; your browser draws its fast mode while the controls move)"
      : ` (the server's frames: ${page.serverReason})`);
  if (header.kind === "still") showError("");
}

// One slider (or checkbox) for a parameter of the scene description.
function control(parameter, component, label) {
  const value = component === null ? parameter.value : parameter.value[component];
  const key = parameter.key;
  const row = el("label", { class: "control" }, label);
  if (parameter.kind === "bool") {
    const box = el("input", { type: "checkbox" });
    box.checked = Boolean(value);
    box.addEventListener("change", () => { page.set[key] = box.checked; sendState(); });
    row.append(box, el("output"));
    return row;
  }
  const log = parameter.log;
  const [min, max] = [parameter.min ?? Math.min(0, value), parameter.max ?? Math.max(1, 2 * value)];
  const toSlider = (v) => (log ? Math.log(Math.max(v, min)) : v);
  const fromSlider = (s) => (log ? Math.exp(s) : s);
  const slider = el("input", {
    type: "range",
    min: String(toSlider(min)),
    max: String(toSlider(max)),
    step: String((toSlider(max) - toSlider(min)) / 1000),
    "data-key": key,
    "data-component": component === null ? "" : String(component),
  });
  slider.value = String(toSlider(value));
  const output = el("output", { text: shown(value) });
  slider.addEventListener("input", () => {
    const v = Number(fromSlider(Number(slider.value)).toPrecision(4));
    output.textContent = shown(v);
    if (component === null) page.set[key] = v;
    else {
      const current = Array.isArray(page.set[key]) ? page.set[key] : parameter.value.slice();
      current[component] = v;
      page.set[key] = current;
    }
    sendState();
  });
  row.append(slider, output);
  return row;
}

function materialControls() {
  const box = $("material");
  box.replaceChildren(el("legend", { text: "Material" }));
  const object = page.scene.objects[Number($("object").value)];
  if (!object) return;
  const material = page.scene.materials[object.material];
  box.append(el("p", { class: "muted", text: `${object.material}: ${material.model}${material.file ? " (" + material.file + ")" : ""}` }));
  if (material.parameters.length === 0) box.append(el("p", { class: "muted", text: "a measured material: no parameter" }));
  for (const parameter of material.parameters) {
    if (parameter.kind === "colour") {
      ["r", "g", "b"].forEach((c, k) => box.append(control(parameter, k, `${parameter.name}.${c}`)));
    } else {
      box.append(control(parameter, null, parameter.name));
    }
  }
  // Under an environment the fast mode reads the material's albedo table, which the server makes as the
  // material moves; a folder of vk-render site holds the scene's own.
  if (SITE && page.scene.browser.environment && material.parameters.length > 0) {
    box.querySelectorAll("input").forEach((input) => { input.disabled = true; });
    box.append(el("p", { class: "muted", text: "under an environment, the material moves on vk-render serve (its albedo table is the server's)" }));
  }
}

function lightControls() {
  const box = $("light");
  box.replaceChildren(el("legend", { text: "Light" }));
  for (const light of page.scene.lights) {
    const power = { key: `light.${light.index}.power`, kind: "number", value: light.power, min: 0, max: Math.max(1, light.power * 4), log: false };
    box.append(control(power, null, `${light.index}: power`));
    const reach = Math.max(5, ...light.position.map(Math.abs)) * 2;
    const position = { key: `light.${light.index}.position`, kind: "colour", value: light.position, min: -reach, max: reach, log: false };
    ["x", "y", "z"].forEach((c, k) => box.append(control(position, k, `${light.index}: ${c}`)));
  }
  if (page.scene.lights.length === 0) box.append(el("p", { class: "muted", text: "lit by its environment" }));
}

// Dragging the picture (a mouse's or a finger's) orbits the camera about what it looks at.
function orbit(canvas) {
  let last = null;
  canvas.addEventListener("pointerdown", (event) => {
    last = [event.clientX, event.clientY];
    canvas.setPointerCapture(event.pointerId);
    canvas.classList.add("dragging");
  });
  const release = () => { last = null; canvas.classList.remove("dragging"); };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("pointermove", (event) => {
    if (!last) return;
    const [dx, dy] = [event.clientX - last[0], event.clientY - last[1]];
    last = [event.clientX, event.clientY];
    const camera = page.scene.camera;
    const position = page.set["camera.position"] || camera.position;
    const target = camera.look_at;
    const offset = position.map((p, k) => p - target[k]);
    const radius = Math.hypot(...offset);
    let azimuth = Math.atan2(offset[0], offset[2]) - dx * 0.01;
    let elevation = Math.asin(offset[1] / radius) + dy * 0.01;
    elevation = Math.max(-1.5, Math.min(1.5, elevation));
    const moved = [
      target[0] + radius * Math.cos(elevation) * Math.sin(azimuth),
      target[1] + radius * Math.sin(elevation),
      target[2] + radius * Math.cos(elevation) * Math.cos(azimuth),
    ].map((v) => Number(v.toPrecision(6)));
    page.set["camera.position"] = moved;
    sendState();
  });
}

// The lobe's incidence and angles: the page's lobe (explore.js) at θi 30°, θo every half degree from -90 to
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

// The lobe's polar plot (luminance, Rec. 709's weights as `vk-render plot lobe`'s) on `canvas`: the surface,
// the incident direction, and the curve scaled to its largest value.
function drawLobe(canvas, lobe) {
  const context = canvas.getContext("2d");
  const [width, height] = [canvas.width, canvas.height];
  context.clearRect(0, 0, width, height);
  const luminance = lobe.map(([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b);
  const finite = luminance.filter((v) => Number.isFinite(v));
  const largest = Math.max(1e-30, ...finite.map(Math.abs));
  const [cx, cy, radius] = [width / 2, height - 16, Math.min(width / 2, height - 24) - 8];
  // As `vk-render plot lobe` draws it: θo negative on the side of wi, on the left.
  const at = (theta, r) => [cx + Math.sin((theta * Math.PI) / 180) * r * radius, cy - Math.cos((theta * Math.PI) / 180) * r * radius];
  context.strokeStyle = "#d0d4d9";
  context.lineWidth = 1;
  for (const r of [0.25, 0.5, 0.75, 1]) {
    context.beginPath();
    context.arc(cx, cy, r * radius, Math.PI, 2 * Math.PI);
    context.stroke();
  }
  context.beginPath();
  context.moveTo(cx - radius - 4, cy);
  context.lineTo(cx + radius + 4, cy);
  context.stroke();
  context.strokeStyle = "#5f6368";
  context.setLineDash([4, 4]);
  context.beginPath();
  context.moveTo(cx, cy);
  context.lineTo(...at(-LOBE_THETA_I, 1));
  context.stroke();
  context.setLineDash([]);
  context.strokeStyle = "#1f5fa8";
  context.lineWidth = 2;
  context.beginPath();
  LOBE_ANGLES.forEach((theta, k) => {
    const v = Number.isFinite(luminance[k]) ? Math.max(luminance[k], 0) / largest : 0;
    const [x, y] = at(theta, v);
    if (k === 0) context.moveTo(x, y);
    else context.lineTo(x, y);
  });
  context.stroke();
  context.fillStyle = "#5f6368";
  context.font = "12px system-ui, sans-serif";
  context.fillText(`f_r cos θo, luminance; θi ${LOBE_THETA_I}° (dashed); largest ${shown(largest)}`, 8, 14);
}

// The directional albedo's chart on `canvas` (what `vk-render plot albedo` draws, per channel): ρ against θo,
// from 0 to the larger of 1 and its largest value, and the bound on its error.
function drawAlbedo(canvas, albedo) {
  const context = canvas.getContext("2d");
  const [width, height] = [canvas.width, canvas.height];
  context.clearRect(0, 0, width, height);
  const top = Math.max(1, ...albedo.albedo.flat().filter(Number.isFinite));
  const [left, right, upper, lower] = [36, width - 10, 24, height - 22];
  const at = (theta, rho) => [left + ((right - left) * theta) / 90, lower - ((lower - upper) * rho) / top];
  context.strokeStyle = "#d0d4d9";
  context.fillStyle = "#5f6368";
  context.font = "11px system-ui, sans-serif";
  context.lineWidth = 1;
  for (const rho of [0, 0.25, 0.5, 0.75, 1].map((f) => f * top)) {
    const [, y] = at(0, rho);
    context.beginPath();
    context.moveTo(left, y);
    context.lineTo(right, y);
    context.stroke();
    context.fillText(shown(rho, 2), 4, y + 4);
  }
  for (const theta of [0, 30, 60, 90]) context.fillText(`${theta}°`, at(theta, 0)[0] - (theta === 90 ? 18 : 6), height - 6);
  context.lineWidth = 2;
  ["#c5221f", "#188038", "#1a5fb4"].forEach((colour, channel) => {
    context.strokeStyle = colour;
    context.beginPath();
    albedo.theta_o.forEach((theta, k) => {
      const [x, y] = at(theta, Number.isFinite(albedo.albedo[k][channel]) ? albedo.albedo[k][channel] : 0);
      if (k === 0) context.moveTo(x, y);
      else context.lineTo(x, y);
    });
    context.stroke();
  });
  context.fillStyle = "#5f6368";
  context.font = "12px system-ui, sans-serif";
  context.fillText(`ρ(θo), R G B; error bound ${shown(Math.max(...albedo.bound), 2)}`, 8, 14);
}

// The directional albedo of object `index`'s material with the page's overrides at ALBEDO_ANGLES, computed
// by this browser (WasmLibrary.albedo: the library's cubature, this browser's albedo probe); null when a
// later one started meanwhile. The last one asked is kept: asked again (the editor's and the studies' column
// of the same model), it is not integrated twice.
let albedoAsked = null;
function browserAlbedo(index) {
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
// (webgl.js: probe): f_r cos θo per channel at each of LOBE_ANGLES, and whether an analytic model's loops
// were stopped there (a student's model: editor.js).
function browserLobe(index) {
  const values = page.browser.probe(page.scene, page.set, index, lobeDirections(LOBE_THETA_I));
  const lobe = values.map(([r, g, b], k) => {
    const cosine = Math.max(Math.cos((LOBE_ANGLES[k] * Math.PI) / 180), 0);
    return [r * cosine, g * cosine, b * cosine];
  });
  return { theta_i: LOBE_THETA_I, theta_o: LOBE_ANGLES, values: lobe, stopped: values.some((v) => v[3] !== 0) };
}

// Whether the browser draws the page's scene, its data loaded (a scene just chosen is still loading).
function browserHoldsScene() {
  return page.mode === "browser" && Boolean(page.browser) && page.loaded === page.scene;
}

// A folder of vk-render site: the selected object's lobe and albedo, computed by this browser (the server's
// plots are the server's).
async function siteStudies() {
  const index = Number($("object").value);
  if (!browserHoldsScene() || !page.scene.objects[index]) return;
  try {
    page.lobe = browserLobe(index);
  } catch (error) {
    return showError(`the lobe: ${error.message}`);
  }
  drawLobe($("browser-lobe"), page.lobe.values);
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
function studiesLater() {
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

// Whether an object of the page's scene is made of the student's own model (editor.js).
function studentModelShown() {
  return Boolean(page.scene && page.scene.objects.some((object) => isStudentMaterial(object.material)));
}

// The lobe and the albedo of the selected object's material with the current overrides, unless shown.
async function studies() {
  // A student's model is studied by the browser (the server never sees it).
  if (studentModelShown()) studentStudies();
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

// The scene's objects to choose from, each with its material.
function objectChoices() {
  $("object").replaceChildren(...page.scene.objects.map((o) => el("option", { value: String(o.index), text: `${o.index}: ${o.shape} (${o.material})` })));
}

function chooseScene(id) {
  page.scene = page.scenes.find((s) => s.id === id) || page.scenes[0];
  $("scene").value = page.scene.id;
  page.set = {};
  objectChoices();
  materialControls();
  lightControls();
  studies();
  chooseRenderer();
}

async function download() {
  if (studentModelShown()) return showError("your own model is in your browser alone: download the .brdf (the editor), and name it in a scene file");
  try {
    const blob = await (await postJson("/api/scene-file", request())).blob();
    const link = el("a", { href: URL.createObjectURL(blob), download: `${page.scene.id}.toml` });
    document.body.append(link);
    link.click();
    link.remove();
  } catch (error) {
    showError(error.message);
  }
}

async function start() {
  try {
    page.scenes = await getJson(dataUrl("scenes"));
  } catch (error) {
    showError(error.message);
    return;
  }
  const select = $("scene");
  select.replaceChildren(...page.scenes.map((s) => el("option", { value: s.id, text: s.title })));
  const wanted = new URLSearchParams(location.search).get("scene");
  if (wanted && page.scenes.some((s) => s.id === wanted)) select.value = wanted;
  select.addEventListener("change", () => chooseScene(select.value));
  $("object").addEventListener("change", () => { materialControls(); studies(); });
  $("reset").addEventListener("click", () => chooseScene(page.scene.id));
  $("download").addEventListener("click", download);
  orbit($("frame"));
  orbit($("gl"));
  await makeBrowserRenderer();
  // A lost WebGL context (the browser reclaims it, a driver resets): the server's frames until it is back.
  $("gl").addEventListener("webglcontextlost", (event) => {
    event.preventDefault();  // asks the browser to restore it
    page.browser = null;
    page.noBrowser = "the browser's WebGL context was lost";
    useServer(page.noBrowser);
  });
  $("gl").addEventListener("webglcontextrestored", async () => {
    await makeBrowserRenderer();
    chooseRenderer();
  });
  chooseScene(select.value);
}

// The browser's renderer on the page's WebGL canvas, or none and why (page.noBrowser).
async function makeBrowserRenderer() {
  const made = await BrowserRenderer.create($("gl")).catch((error) => ({ renderer: null, reason: error.message }));
  page.browser = made.renderer;
  page.noBrowser = made.reason;
  registerStudentShaders(page.browser);
}

start();
