// The renderer's passes, drawn by WebGL2 with the renderer's own shaders (src/render/passes.rs): each
// shadow-casting light's cube (six layers of a float array texture), the forward pass into a float target at
// one sample a pixel, and the resolve to the course's 8-bit levels on the canvas. The uniform blocks they
// read are staged here, member by member (blocks.js), as src/render/gpu_types.rs writes them.
import { TEXTURE_UNITS } from "./bindings.js";
import { cubeFaceViews, frameData, scale, sceneState } from "./math.js";
import { analyticSuffix } from "./resources.js";

// shadow.frag's FAR_AWAY: what a shadow texel holds where nothing is.
const FAR_AWAY = 3.0e38;

// The Lights block (GpuPointLight::new): position, colour * power, and the light's cube (every face drawn).
function stageLights(renderer, state, shadows) {
  renderer.blocks.stage("Lights", (data) => {
    let cube = 0;
    state.lights.forEach((light, k) => {
      data.set(`lights[${k}].position`, [...light.position, 1]);
      data.set(`lights[${k}].radiance`, [...scale(light.color, light.power), 0]);
      data.set(`lights[${k}].shadow`, shadows[k] ? [cube++, 63, 0, 0] : [-1, 0, 0, 0]);
    });
  });
}

// The analytic materials' values one after the other (AnalyticValues::write): where each one's begin.
function stageAnalytic(renderer, state) {
  const values = [];
  const firsts = {};
  for (const [name, material] of Object.entries(state.materials)) {
    if (!material.analytic_values) continue;
    firsts[name] = values.length;
    values.push(...material.analytic_values);
  }
  renderer.blocks.stage("AnalyticParameters", (data) => { if (values.length) data.set("analytic_values[0]", values); });
  return firsts;
}

// Every object's ObjectData (GpuObject), one range each; an analytic material's `analytic` where its values
// begin. With the analytic values: the blocks a probe of a material reads.
export function stageObjects(renderer, scene, state) {
  const firsts = stageAnalytic(renderer, state);
  const slots = renderer.resources.tableSlots;
  renderer.blocks.stage("Objects", (data) => scene.browser.objects.forEach((object, k) => {
    const m = state.materials[object.material];
    const set = (member, values) => data.set(`objects[0].${member}`, values, k);
    set("model", object.model);
    set("normal_matrix", object.normal_matrix);
    for (const colour of ["kd", "ks", "f0"]) set(`material.${colour}`, m[colour]);
    for (const value of ["brdf", "shininess", "sigma", "roughness", "metalness", "diffuse"]) set(`material.${value}`, [m[value]]);
    set("material.measured", [slots[object.material] || 0]);
    set("material.analytic", [firsts[object.material] || 0]);
    set("flags", object.flags);
  }), scene.browser.objects.length);
}

// Every object's albedo table (the latest its material has), one range each: entries of two vec4 as the
// server's table lists them (Renderer::albedo_table).
function stageAlbedo(renderer, scene) {
  const tables = renderer.resources.albedoTables;
  renderer.blocks.stage("EnvironmentAlbedo", (data) => scene.browser.objects.forEach((object, k) => {
    const held = tables.get(object.material);
    if (!held || !held.table) return;
    for (let entry = 0; entry < held.table.length / 8; entry++) {
      data.set(`environment_albedo[${entry}].diffuse`, held.table.subarray(8 * entry, 8 * entry + 4), k);
      data.set(`environment_albedo[${entry}].specular`, held.table.subarray(8 * entry + 4, 8 * entry + 8), k);
    }
  }), scene.browser.objects.length);
}

// The Frame block (GpuFrame::new) for the camera of `state` at width x height.
function stageFrame(renderer, scene, state, width, height) {
  const browser = scene.browser;
  const camera = frameData(state.camera, width, height, browser.near);
  renderer.blocks.stage("Frame", (data) => {
    data.set("view_projection", camera.view_projection);
    data.set("pixel_rays", camera.pixel_rays);
    data.set("camera_position", camera.camera_position);
    data.set("background", browser.background);
    data.set("shadow_texel_angle", [2 / browser.shadow_map_size]);
    data.set("environment", browser.environment ? browser.environment.frame : [1, 0, 0, 0]);
  });
}

// Binds object `index`'s ranges of the objects' block and, under an environment, of the albedo tables'.
export function bindObject(renderer, scene, index) {
  renderer.blocks.bindRange("Objects", index);
  if (scene.browser.environment) renderer.blocks.bindRange("EnvironmentAlbedo", index);
}

// Draws object `index`: its mesh, or for a motion frame its lighter one where it has one.
function drawMesh(renderer, scene, index, motion) {
  const gl = renderer.gl;
  const mesh = renderer.resources.mesh(scene, index, motion);
  bindObject(renderer, scene, index);
  gl.bindVertexArray(mesh.vertexArray);
  gl.drawElements(gl.TRIANGLES, mesh.count, gl.UNSIGNED_INT, 0);
  gl.bindVertexArray(null);
}

// The float depth buffer of a target of width x height (one kept, made anew when the size changes).
function depthBuffer(renderer, width, height) {
  const gl = renderer.gl;
  const depth = renderer.targets.depth;
  if (depth && depth.width === width && depth.height === height) return depth.renderbuffer;
  if (depth) gl.deleteRenderbuffer(depth.renderbuffer);
  const renderbuffer = gl.createRenderbuffer();
  gl.bindRenderbuffer(gl.RENDERBUFFER, renderbuffer);
  gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT32F, width, height);
  renderer.targets.depth = { renderbuffer, width, height };
  return renderbuffer;
}

// Every shadow-casting light's cube, each face a layer (6 cube + face) of one R32F array texture (drawn
// with the lighter meshes for a motion frame).
function drawShadows(renderer, scene, state, motion) {
  const gl = renderer.gl;
  const targets = renderer.targets;
  const size = scene.browser.shadow_map_size;
  const casting = scene.browser.shadows.map((s, k) => (s ? k : -1)).filter((k) => k >= 0);
  const layers = Math.max(1, 6 * casting.length);
  if (!targets.shadowMaps || targets.shadowMaps.size !== size || targets.shadowMaps.layers !== layers) {
    if (targets.shadowMaps) gl.deleteTexture(targets.shadowMaps.texture);
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
    gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.R32F, size, size, layers);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D_ARRAY, p, gl.NEAREST);
    targets.shadowMaps = { texture, size, layers };
  }
  const views = new Float32Array(16 * layers);
  casting.forEach((k, cube) => cubeFaceViews(state.lights[k].position, scene.browser.near).forEach((m, face) => views.set(m, 16 * (6 * cube + face))));
  renderer.blocks.stage("ShadowViews", (data) => data.set("shadow_views[0]", views));
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depthBuffer(renderer, size, size));
  gl.viewport(0, 0, size, size);
  casting.forEach((k, cube) => {
    for (let face = 0; face < 6; face++) {
      gl.framebufferTextureLayer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, targets.shadowMaps.texture, 0, 6 * cube + face);
      gl.clearBufferfv(gl.COLOR, 0, [FAR_AWAY, 0, 0, 0]);
      gl.clearBufferfv(gl.DEPTH, 0, [0]);
      scene.browser.objects.forEach((object, index) => {
        if (!object.casts_shadow) return;
        const entry = renderer.program("shadow.vert", object.sphere ? "shadow_sphere.frag" : "shadow.frag", {});
        renderer.use(entry);
        gl.uniform1ui(entry.object, 0);
        gl.uniform1ui(entry.light, k);
        gl.uniform1ui(entry.face, face);
        drawMesh(renderer, scene, index, motion);
      });
    }
  });
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  gl.deleteFramebuffer(framebuffer);
}

// Whether `object`'s back faces can be culled seen from `eye` (GpuMesh::hides_back_faces): its mesh is
// closed and wound outwards, and the eye is outside its bounding box (in its own space: the inverse of its
// model matrix is the transpose of its normal matrix), so every back face lies behind a front face. A CPU
// rasterizer spends on back faces what it spends on front faces.
function hidesBackFaces(object, eye) {
  if (!object.closed) return false;
  const n = object.normal_matrix;
  const local = [0, 1, 2].map((r) => n[4 * r] * eye[0] + n[4 * r + 1] * eye[1] + n[4 * r + 2] * eye[2] + n[4 * r + 3]);
  const [least, greatest] = object.bounds;
  return !local.every((v, k) => v >= least[k] && v <= greatest[k]);
}

// The forward pass's program of `object` (PipelineKey::for_object's constants: BRDF, shadow filter, lights,
// diffuse lobe, view; a view other than the radiance drawn by the TERM_VIEWS variant, as the renderer draws
// it; an environment's light in its fast mode, ENVIRONMENT 2, by the WITH_ENVIRONMENT variants).
function forwardProgram(renderer, scene, state, object) {
  const browser = scene.browser;
  const material = state.materials[object.material];
  const constants = { 0: `${material.brdf}u`, 1: `${browser.shadow_filter}u`, 2: `${state.lights.length}u`, 3: `${material.diffuse}u`, 4: `${browser.view}u` };
  if (browser.environment) constants[5] = "2u";
  const variant = (browser.environment ? "+WITH_ENVIRONMENT" : "") + (browser.view === 0 ? "" : "+TERM_VIEWS");
  const model = analyticSuffix(scene, object.material);
  return object.sphere
    ? renderer.program("forward_sphere.vert", `forward_sphere.frag${variant}${model}`, constants)
    : renderer.program("forward.vert", `forward.frag${variant}${model}`, constants);
}

// The float target of the forward pass at width x height (one kept, made anew when the size changes).
function colourTarget(renderer, width, height) {
  const gl = renderer.gl;
  const colour = renderer.targets.colour;
  if (colour && colour.width === width && colour.height === height) return colour.texture;
  if (colour) gl.deleteTexture(colour.texture);
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
  for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
  renderer.targets.colour = { texture, width, height };
  return texture;
}

// Draws `scene` with the page's overrides `set` at width x height onto the canvas; a motion frame
// (`motion`) with the objects' lighter meshes.
export function drawFrame(renderer, scene, set, width, height, motion) {
  const gl = renderer.gl;
  const canvas = gl.canvas;
  if (canvas.width !== width || canvas.height !== height) [canvas.width, canvas.height] = [width, height];
  const state = sceneState(scene, set);
  const browser = scene.browser;
  const resources = renderer.resources;
  gl.enable(gl.DEPTH_TEST);
  gl.depthFunc(gl.GEQUAL);  // reverse-Z, as the renderer's GREATER_OR_EQUAL (src/render/passes.rs)
  gl.disable(gl.CULL_FACE);
  // Meshes are wound counter-clockwise seen from outside; through the camera's y-flipped projection they
  // are clockwise in GL's window coordinates (PassView::front_face finds Vulkan's counter-clockwise, whose
  // area has the opposite sign to GL's).
  gl.frontFace(gl.CW);
  gl.cullFace(gl.BACK);
  stageLights(renderer, state, browser.shadows);
  stageObjects(renderer, scene, state);
  if (browser.environment) stageAlbedo(renderer, scene);
  // The shadow cubes, drawn again when a light moves, or for a still frame where a motion frame drew them.
  const shadowKey = JSON.stringify([scene.id, state.lights.map((l) => l.position)]);
  if (shadowKey !== renderer.shadowKey || (!motion && renderer.shadowsOfMotion)) {
    renderer.shadowsOfMotion = Boolean(motion);
    drawShadows(renderer, scene, state, renderer.shadowsOfMotion);
    renderer.shadowKey = shadowKey;
  }
  stageFrame(renderer, scene, state, width, height);
  // The forward pass into a float target, one sample a pixel.
  const colour = colourTarget(renderer, width, height);
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, colour, 0);
  gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depthBuffer(renderer, width, height));
  gl.viewport(0, 0, width, height);
  gl.clearBufferfv(gl.COLOR, 0, browser.background);
  gl.clearBufferfv(gl.DEPTH, 0, [0]);
  gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.measured_tables);
  gl.bindTexture(gl.TEXTURE_2D, resources.tables ? resources.tables.texture : null);
  if (browser.environment) {
    gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.environment_map);
    gl.bindTexture(gl.TEXTURE_2D, resources.environment.map);
    gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.environment_prefiltered);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, resources.environment.layers);
  }
  gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.shadow_maps);
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, renderer.targets.shadowMaps.texture);
  // A visible environment is the background (background.frag's WITH_ENVIRONMENT variant, ENVIRONMENT 1),
  // drawn first and under everything.
  if (browser.environment && browser.environment.visible) {
    gl.disable(gl.DEPTH_TEST);
    renderer.use(renderer.program("background.vert", "background.frag+WITH_ENVIRONMENT", { 5: "1u" }));
    gl.bindVertexArray(renderer.emptyVertexArray);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
    gl.enable(gl.DEPTH_TEST);
  }
  browser.objects.forEach((object, index) => {
    const entry = forwardProgram(renderer, scene, state, object);
    renderer.use(entry);
    gl.uniform1ui(entry.object, 0);
    if (hidesBackFaces(object, state.camera.position)) gl.enable(gl.CULL_FACE);
    else gl.disable(gl.CULL_FACE);
    drawMesh(renderer, scene, index, motion);
  });
  gl.disable(gl.CULL_FACE);
  // A term's scale (TermScale::of): the normal's [-1, 1]; any other term's [0, the larger of 1 and the
  // image's largest finite value], read back from the float target.
  let [low, high] = [0, 1];
  if (browser.term && browser.view === 1) low = -1;
  else if (browser.term) {
    const values = new Float32Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.FLOAT, values);
    for (let i = 0; i < values.length; i++) if (i % 4 !== 3 && Number.isFinite(values[i]) && values[i] > high) high = values[i];
  }
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  gl.deleteFramebuffer(framebuffer);
  resolve(renderer, browser, colour, low, high);
}

// The resolve of the float target `colour` onto the canvas: exposure, tone curve and encoding, or a term's
// scale from `low` to `high`.
function resolve(renderer, browser, colour, low, high) {
  const gl = renderer.gl;
  gl.disable(gl.DEPTH_TEST);
  const entry = renderer.program("background.vert", "web/resolve.frag", {});
  renderer.use(entry);
  gl.uniform1f(entry.exposure, browser.exposure);
  gl.uniform1ui(entry.tonemap, browser.tonemap);
  gl.uniform1ui(entry.encoding, browser.encoding);
  gl.uniform1ui(entry.term, browser.term ? 1 : 0);
  gl.uniform1f(entry.low, low);
  gl.uniform1f(entry.high, Math.fround(high));
  gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.colour);
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, null);
  gl.bindTexture(gl.TEXTURE_2D, colour);
  gl.bindVertexArray(renderer.emptyVertexArray);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  gl.bindVertexArray(null);
}
