// The check page: an image dropped or chosen. Under vk-render serve it is posted to /api/check, then its
// report's page shows; in a folder of vk-render site it is checked in this browser (siteCheck): the
// figure's renders made at `site` time (data/check/) and the student's file go to the library's check rules
// compiled to WebAssembly (static/wasm.js), and the report shows on this page. The image is sent nowhere.
import { SITE } from "./site.js";
import { el, getJson, postJson } from "./common.js";
import { showReport } from "./report.js";
import { library } from "./wasm.js";

const $ = (id) => document.getElementById(id);
let chosen = null;
// A folder's data/check/index.json: its figures and the catalogue's words for each mistake.
let checkIndex = null;
// The figure whose pictures the WebAssembly holds, and the object URLs of the report shown.
let loadedFigure = null;
let shownUrls = [];
// The last check made in this browser: its report and how long it took (the browser tests read it).
const checkPage = { last: null };

function choose(file) {
  chosen = file || null;
  $("chosen").textContent = chosen ? `${chosen.name} (${Math.round(chosen.size / 1024)} kB)` : "";
  $("submit").disabled = !chosen;
}

async function submit(event) {
  event.preventDefault();
  if (!chosen) return;
  $("submit").disabled = true;
  $("error").textContent = "";
  try {
    if (SITE) await siteCheck(chosen, checkIndex.figures.find((f) => f.id === $("scene").value));
    else await serverCheck(chosen, $("scene").value);
  } catch (error) {
    $("status").textContent = "";
    $("error").textContent = error.message;
  }
  $("submit").disabled = false;
}

async function serverCheck(file, scene) {
  const form = new FormData();
  form.append("image", file);
  if (scene) form.append("scene", scene);
  $("status").textContent = "checking: the exact image and every known mistake are rendered at your image's size...";
  const response = await fetch("/api/check", { method: "POST", body: form });
  if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
  const answer = await response.json();
  location.assign(answer.report);
}

async function fetchBytes(address) {
  const response = await fetch(address);
  if (!response.ok) throw new Error(`${address}: ${response.status} ${response.statusText}`);
  return new Uint8Array(await response.arrayBuffer());
}

// Hands the figure's pictures and objects' ids to the WebAssembly, once per figure.
async function loadFigure(wasm, figure) {
  if (loadedFigure === figure.id) return;
  loadedFigure = null;
  const begun = wasm.call("check_begin", JSON.stringify(figure));
  if (begun.error) throw new Error(`${figure.id}: ${begun.error}`);
  for (const [call, address] of [...figure.pictures.map((p) => ["check_picture", p]), ["check_objects", figure.objects]]) {
    const answer = wasm.callWithImage(call, await fetchBytes(address));
    if (answer.error) throw new Error(`${address}: ${answer.error}`);
  }
  loadedFigure = figure.id;
}

// The check of `file` against `figure` in this browser, its report shown below the form.
async function siteCheck(file, figure) {
  const started = performance.now();
  checkPage.last = null;
  const wasm = await library();
  const command = `vk-render check ${file.name} --scene ${figure.id}`;
  if (file.size > wasm.maxImageBytes) {
    throw new Error(`${file.name} is ${(file.size / 1048576).toFixed(1)} MB: this page takes images up to ${wasm.maxImageBytes / 1048576} MB`);
  }
  $("site-report").replaceChildren();
  $("status").textContent = `checking against ${figure.title}, in this browser...`;
  await loadFigure(wasm, figure);
  const answer = wasm.callWithImage("check_image", new Uint8Array(await file.arrayBuffer()));
  if (answer.size) {
    throw new Error(`Your image is ${answer.size[0]} x ${answer.size[1]}; this page checks the figures at their own size, ${figure.width} x ${figure.height}. ` +
      `At another size the exact image must be rendered: ${command}, or a course's vk-render serve.`);
  }
  if (answer.error) throw new Error(answer.error);
  for (const url of shownUrls) URL.revokeObjectURL(url);
  const difference = URL.createObjectURL(new Blob([wasm.bytes(wasm.exports.check_difference())], { type: "image/png" }));
  const yours = URL.createObjectURL(file);
  shownUrls = [difference, yours];
  const addresses = {
    yours,
    exact: figure.pictures[figure.candidates[0][1]],
    difference,
    mistake: answer.mistake_picture === null ? null : figure.pictures[answer.mistake_picture],
  };
  const report = {
    ...answer,
    mistakes: answer.mistakes.map((name) => ({ name, ...checkIndex.mistakes[name] })),
    mistake_picture: answer.mistake_picture === null ? null : answer.mistakes[0],
    scene_title: figure.title,
    scene_chosen_by_server: false,
    tells_apart: null,
    wrong_parameters: [],
  };
  const seconds = (performance.now() - started) / 1000;
  checkPage.last = { report, seconds };
  $("status").textContent = "";
  const target = $("site-report");
  showReport(target, report, (name) => addresses[name], `Checked in ${seconds.toFixed(1)} s by this browser; your image was sent nowhere.`);
  // Where vk-render check goes further than this page.
  if (report.verdict === "tie") {
    target.querySelector("#mistakes").append(el("p", { "data-needs-renderer": "tie", text: `This figure cannot tell them apart. ${command} names the practical's scene that does.` }));
  } else if (report.verdict === "unexplained") {
    target.querySelector("#mistakes").append(el("p", { "data-needs-renderer": "unexplained", text: `No known mistake explains it. ${command} (or a course's vk-render serve) goes on: it fits each object's model to your image and names the parameters that differ from the figure's.` }));
  }
}

async function start() {
  const drop = $("drop");
  drop.addEventListener("dragover", (event) => { event.preventDefault(); drop.classList.add("over"); });
  drop.addEventListener("dragleave", () => drop.classList.remove("over"));
  drop.addEventListener("drop", (event) => {
    event.preventDefault();
    drop.classList.remove("over");
    choose(event.dataTransfer.files[0]);
  });
  $("file").addEventListener("change", () => choose($("file").files[0]));
  $("form").addEventListener("submit", submit);
  try {
    if (SITE) {
      checkIndex = await getJson(`${SITE.data}check/index.json`);
      $("scene").replaceChildren(...checkIndex.figures.map((f) => el("option", { value: f.id, text: f.title })));
    } else {
      const scenes = await getJson("/api/scenes");
      for (const scene of scenes) $("scene").append(el("option", { value: scene.id, text: scene.title }));
    }
  } catch (error) {
    $("error").textContent = error.message;
  }
}

// What the browser test reads the last check by (tests/serve_browser/site_check.rs): a module's names are its own.
window.checkPage = checkPage;

start();
