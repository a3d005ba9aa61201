// The renderer's probes in the browser: a material's f_r at given pairs of directions (shaders/web/probe.frag:
// brdf_probe.comp's work) and the integrals of f_r cos θi over cells of the hemisphere (shaders/web/albedo.frag:
// brdf_albedo.comp's cell integral), each drawn as a full-screen triangle into float targets.
import { TEXTURE_UNITS } from "./bindings.js";
import { sceneState } from "./math.js";
import { bindObject, stageObjects } from "./passes.js";
import { analyticSuffix } from "./resources.js";

// The albedo probe's draws: at most ALBEDO_ROWS rows of ALBEDO_WIDTH cells each (each cell 225 evaluations of
// the model), so that one draw stays short on a software GPU.
const ALBEDO_WIDTH = 1024;
const ALBEDO_ROWS = 16;

// f_r of object `index`'s material (the page's overrides `set` applied) at each pair [wi, wo] of `pairs`
// (n = +z, X = +x, as the probe's frame), by the probe pass (shaders/web/probe.frag: brdf_probe.comp's
// work): [r, g, b, stopped] each, `stopped` 1 where an analytic model's loops were stopped by their guard.
export function probe(renderer, scene, set, index, pairs) {
  const count = pairs.length;
  const directions = new Float32Array(8 * count);
  pairs.forEach(([wi, wo], k) => {
    directions.set([...wi, 0], 4 * k);
    directions.set([...wo, 0], 4 * (count + k));
  });
  const [values] = runProbe(renderer, scene, set, index, "web/probe.frag", { data: directions, width: count, height: 2 }, count, 1, 1);
  return pairs.map((_, k) => Array.from(values.subarray(4 * k, 4 * k + 4)));
}

// The integrals of f_r cos θi of object `index`'s material (the page's overrides `set` applied) over
// `count` cells of the hemisphere, by the albedo probe (shaders/web/albedo.frag: brdf_albedo.comp's cell
// integral), `cells` holding each one's bounds and wo (8 floats: crates/cubature's cells, as the WebAssembly
// writes them): the Kronrod estimates (RGBA each, alpha 1 where an analytic model's loops were stopped), then
// the Gauss ones, in one array; drawn ALBEDO_ROWS rows of ALBEDO_WIDTH cells at a time.
export function integrateCells(renderer, scene, set, index, cells, count) {
  const estimates = new Float32Array(8 * count);
  const perDraw = ALBEDO_WIDTH * ALBEDO_ROWS;
  for (let first = 0; first < count; first += perDraw) {
    const n = Math.min(perDraw, count - first);
    const width = Math.min(n, ALBEDO_WIDTH);
    const height = Math.ceil(n / width);
    const data = new Float32Array(8 * width * height);
    data.set(cells.subarray(8 * first, 8 * (first + n)));
    const [kronrod, gauss] = runProbe(renderer, scene, set, index, "web/albedo.frag", { data, width: 2 * width, height }, width, height, 2);
    estimates.set(kronrod.subarray(0, 4 * n), 4 * first);
    estimates.set(gauss.subarray(0, 4 * n), 4 * (count + first));
  }
  return estimates;
}

// Draws the probe entry `entry` (web/probe.frag, web/albedo.frag) for object `index`'s material with the
// page's overrides `set` into `targets` float targets of width × height, its input (RGBA floats, `input.width`
// × `input.height`) on the probes' texture unit: each target's pixels (RGBA floats, rows from the bottom).
function runProbe(renderer, scene, set, index, entry, input, width, height, targets) {
  const gl = renderer.gl;
  const state = sceneState(scene, set);
  stageObjects(renderer, scene, state);
  const texture = (w, h, data) => {
    const made = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, made);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, data);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    return made;
  };
  gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.probe_directions);
  const inputTexture = texture(input.width, input.height, input.data);
  gl.activeTexture(gl.TEXTURE0);
  const outputs = [...Array(targets).keys()].map(() => texture(width, height, null));
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  const attachments = outputs.map((output, k) => {
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + k, gl.TEXTURE_2D, output, 0);
    return gl.COLOR_ATTACHMENT0 + k;
  });
  gl.drawBuffers(attachments);
  gl.viewport(0, 0, width, height);
  gl.disable(gl.DEPTH_TEST);
  gl.disable(gl.CULL_FACE);
  gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.measured_tables);
  gl.bindTexture(gl.TEXTURE_2D, renderer.resources.tables ? renderer.resources.tables.texture : null);
  gl.activeTexture(gl.TEXTURE0);
  const object = scene.browser.objects[index];
  const material = state.materials[object.material];
  // The material's constants, as the forward pass has them (the BRDF and its diffuse lobe).
  const program = renderer.program("background.vert", `${entry}${analyticSuffix(scene, object.material)}`, { 0: `${material.brdf}u`, 3: `${material.diffuse}u` });
  renderer.use(program);
  bindObject(renderer, scene, index);
  gl.uniform1ui(program.object, 0);
  gl.bindVertexArray(renderer.emptyVertexArray);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  gl.bindVertexArray(null);
  const values = attachments.map((attachment) => {
    const pixels = new Float32Array(4 * width * height);
    gl.readBuffer(attachment);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.FLOAT, pixels);
    return pixels;
  });
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  gl.deleteFramebuffer(framebuffer);
  gl.deleteTexture(inputTexture);
  for (const output of outputs) gl.deleteTexture(output);
  return values;
}
