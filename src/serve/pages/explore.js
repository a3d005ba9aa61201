// The explore page (explore.html): the controls of a scene's material, light and camera, its frames
// (explore/frames.js: the visitor's browser's where it can, else the server's), the studies of its material
// beside it, and the editor of a student's own BRDF (explore/editor.js).
import { dataUrl, el, getJson, postJson } from "./common.js";
import { editor, editorFile, registerStudentShaders, startEditor, studentStudies } from "./explore/editor.js";
import { BrowserRenderer } from "./renderer/renderer.js";
import { cubeFaceViews, frameData } from "./renderer/math.js";
import { chooseScene, materialControls, orbit } from "./explore/controls.js";
import { browserPixels, chooseRenderer, drawInBrowser, sendState, useServer } from "./explore/frames.js";
import { $, page, pictureSize, request, showError, studentModelShown } from "./explore/state.js";
import { siteStudies, studies } from "./explore/studies.js";

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

// What the browser test and `make bench-serve` drive the page by (tests/serve_browser.rs), and a visitor's
// console may too: a module's names are its own.
Object.assign(window, { page, chooseScene, pictureSize, browserPixels, drawInBrowser, sendState, frameData, cubeFaceViews, siteStudies,
  editor, editorFile, studentStudies });

startEditor();
start();
