// The explore page's controls: a scene to choose, its objects, each parameter of the selected object's
// material and of the lights as a slider (or a checkbox), and the camera orbited by dragging the picture.
// Each sets the `--set` key it moves in the page's state and asks for a frame.
import { SITE } from "../site.js";
import { el, shown } from "../common.js";
import { chooseRenderer, sendState } from "./frames.js";
import { $, page } from "./state.js";
import { studies } from "./studies.js";

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

export function materialControls() {
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

export function lightControls() {
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
export function orbit(canvas) {
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

// The scene's objects to choose from, each with its material.
export function objectChoices() {
  $("object").replaceChildren(...page.scene.objects.map((o) => el("option", { value: String(o.index), text: `${o.index}: ${o.shape} (${o.material})` })));
}

export function chooseScene(id) {
  page.scene = page.scenes.find((s) => s.id === id) || page.scenes[0];
  $("scene").value = page.scene.id;
  page.set = {};
  objectChoices();
  materialControls();
  lightControls();
  studies();
  chooseRenderer();
}
