// The explore page's frames: drawn by the visitor's browser (WebGL2, renderer/) where the browser and the scene
// allow, every frame then the exact one; otherwise the server's over a WebSocket (motion frames while a
// control moves, then the exact still frame).
import { SITE } from "../site.js";
import { $, notExact, page, pictureSize, request, showError, stillFromServer, studentModelShown } from "./state.js";
import { studiesLater } from "./studies.js";

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

// The page's state changed: its frame, in the browser (a motion frame at the next animation frame, the
// still frame once the controls rest; `still`: at once, a scene's first) or from the server.
export function sendState(still) {
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

// The browser's frame of the latest state: while a control moves (`motion`), at half the picture's size and
// scaled up; otherwise the still frame, at the picture's size: the exact image, or (see stillFromServer) the
// environment's fast mode until the server's still frame comes.
export function drawInBrowser(motion) {
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
export function browserPixels() {
  drawInBrowser(false);
  return page.browser.pixels();
}

// The server renders this scene's frames, for `why`; a folder of vk-render site has none, and says so, as
// for a student's own model, which only this browser has.
export function useServer(why) {
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
export async function chooseRenderer() {
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
