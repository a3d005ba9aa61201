// What every page of vk-render serve and of a folder of vk-render site shares: the API's calls (or the
// folder's files in their place: site.js's SITE) and small DOM helpers.
import { SITE } from "./site.js";

// The address of a piece of a scene's data: the API's under `vk-render serve`; in a folder `vk-render site`
// wrote, the file it wrote for it (src/serve/site/mod.rs names them so), relative to the page. `kind` is the
// API's route (scenes, mesh, measured, analytic, environment, environment-albedo); a material is named by
// the number the folder's scene list gives it.
export function dataUrl(kind, scene, query = {}) {
  if (!SITE) {
    const parameters = new URLSearchParams(scene ? { scene: scene.id, ...query } : query).toString();
    return `/api/${kind}${parameters ? "?" + parameters : ""}`;
  }
  if (kind === "scenes") return "data/scenes.json";
  const folder = `data/${scene.id}/`;
  const material = () => scene.site.materials[query.material];
  switch (kind) {
    case "mesh": return `${folder}mesh-${query.object}${query.motion ? "-motion" : ""}.bin`;
    case "measured": return `${folder}measured-${material()}.bin`;
    case "analytic": return `${folder}analytic-${material()}.json`;
    case "environment": return `${folder}environment.bin`;
    case "environment-albedo": return `${folder}albedo-${material()}.json`;
    default: throw new Error(`${kind}: not in this folder`);
  }
}

// In a folder of vk-render site, what only the server does is hidden and what only such a folder says is
// shown (the pages hide it, for the server).
document.addEventListener("DOMContentLoaded", () => {
  if (!SITE) return;
  document.querySelectorAll("[data-server-only]").forEach((e) => { e.hidden = true; });
  document.querySelectorAll("[data-site-only]").forEach((e) => { e.hidden = false; });
});

// A POST of JSON to the API; the answer as a Blob, or an Error with the server's one line.
export async function postJson(path, body) {
  const response = await fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body),
  });
  if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
  return response;
}

export async function getJson(path) {
  const response = await fetch(path);
  if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
  return response.json();
}

// An element with attributes and children (strings become text: nothing is parsed as HTML).
export function el(tag, attributes, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes || {})) {
    if (key === "class") node.className = value;
    else if (key === "text") node.textContent = value;
    else node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

// A number shown to `digits` significant digits without trailing zeros.
export function shown(value, digits = 3) {
  if (typeof value !== "number") return String(value);
  return Number(value.toPrecision(digits)).toString();
}
