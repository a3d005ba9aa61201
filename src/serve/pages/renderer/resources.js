// What a scene's frames read besides its uniforms, fetched from the server (or a folder of vk-render site)
// and held while the scene is shown: its meshes as vertex arrays, its measured materials' tables, its
// analytic materials' shaders, its environment's textures and its materials' albedo tables.
import { SITE } from "../site.js";
import { dataUrl } from "../common.js";
import { TEXTURE_UNITS } from "./bindings.js";
import { sceneState } from "./math.js";

// brdf/measured.glsl's MEASURED_TEXTURE_WIDTH: texels a row of the measured tables' texture, one entry each.
const MEASURED_TEXTURE_WIDTH = 2048;

// The suffix of an analytic material's shaders' names (SceneResources.loadAnalytic); none for another.
export const analyticSuffix = (scene, name) => (scene.browser.materials[name].analytic_values ? `@${scene.id}/${name}` : "");

// Where the server hands out the mesh of `scene`'s object `index` (the key its vertex array is kept by).
// (`motion`: its lighter mesh, for the motion frames).
const meshUrl = (scene, index, motion) => dataUrl("mesh", scene, motion ? { object: index, motion: true } : { object: index });

export class SceneResources {
  // `filtersFloats`: whether this browser's WebGL2 reads float textures linearly (OES_texture_float_linear),
  // which an environment needs.
  constructor(gl, filtersFloats) {
    this.gl = gl;
    this.filtersFloats = filtersFloats;
    this.meshes = new Map();
    this.tables = null;       // the measured tables' texture and the scene and materials it holds
    this.tableSlots = {};     // each measured material's place among the tables
    this.environment = null;  // the environment's textures and its scene
    this.albedoTables = new Map();
  }

  // The scene's meshes (GET /api/mesh), each as a vertex array: position (4 floats), normal (3), tangent (3);
  // and the lighter ones of the motion frames, where an object has one; then its tables, its analytic
  // materials' shaders (into `shaders`) and its environment.
  async load(scene, shaders) {
    const gl = this.gl;
    const urls = scene.objects.flatMap((object, k) =>
      [meshUrl(scene, object.index, false)].concat(scene.browser.objects[k].motion_mesh ? [meshUrl(scene, object.index, true)] : []));
    for (const url of urls) {
      if (this.meshes.has(url)) continue;
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
      const bytes = await response.arrayBuffer();
      const [vertices, indices] = new Uint32Array(bytes, 0, 2);
      const vertexArray = gl.createVertexArray();
      gl.bindVertexArray(vertexArray);
      const vertexBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, vertexBuffer);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(bytes, 8, vertices * 10), gl.STATIC_DRAW);
      [[0, 4, 0], [1, 3, 16], [2, 3, 28]].forEach(([location, size, offset]) => {
        gl.enableVertexAttribArray(location);
        gl.vertexAttribPointer(location, size, gl.FLOAT, false, 40, offset);
      });
      const indexBuffer = gl.createBuffer();
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indexBuffer);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(bytes, 8 + vertices * 40, indices), gl.STATIC_DRAW);
      gl.bindVertexArray(null);
      this.meshes.set(url, { vertexArray, count: indices });
    }
    await this.loadTables(scene);
    await this.loadAnalytic(scene, shaders);
    await this.loadEnvironment(scene);
  }

  // The vertex array of `scene`'s object `index` (for a motion frame, its lighter mesh where it has one).
  mesh(scene, index, motion) {
    return this.meshes.get(meshUrl(scene, index, motion && scene.browser.objects[index].motion_mesh));
  }

  // The scene's environment (GET /api/environment): its map (unit 2) and its prefiltered layers (unit 3),
  // float textures read linearly, wrapping in u and clamped in v as the renderer's sampler reads them; and
  // every material's albedo table at the scene's own values.
  async loadEnvironment(scene) {
    if (!scene.browser.environment) return;
    if (!this.filtersFloats) throw new Error("this browser's WebGL2 cannot filter float textures (OES_texture_float_linear)");
    const gl = this.gl;
    if (!this.environment || this.environment.scene !== scene.id) {
      const url = dataUrl("environment", scene);
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
      const bytes = await response.arrayBuffer();
      const [width, height, layerWidth, layerHeight, layers] = new Uint32Array(bytes, 0, 5);
      const texture = (target, unit, upload) => {
        const t = gl.createTexture();
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(target, t);
        upload();
        for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(target, p, gl.LINEAR);
        gl.texParameteri(target, gl.TEXTURE_WRAP_S, gl.REPEAT);
        gl.texParameteri(target, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
        gl.texParameteri(target, gl.TEXTURE_WRAP_R, gl.CLAMP_TO_EDGE);
        gl.activeTexture(gl.TEXTURE0);
        return t;
      };
      const mapTexels = new Float32Array(bytes, 20, width * height * 3);
      const layerTexels = new Float32Array(bytes, 20 + mapTexels.byteLength, layerWidth * layerHeight * layers * 3);
      if (this.environment) [this.environment.map, this.environment.layers].forEach((t) => gl.deleteTexture(t));
      this.environment = {
        scene: scene.id,
        map: texture(gl.TEXTURE_2D, TEXTURE_UNITS.environment_map, () => gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, width, height, 0, gl.RGB, gl.FLOAT, mapTexels)),
        layers: texture(gl.TEXTURE_2D_ARRAY, TEXTURE_UNITS.environment_prefiltered, () => gl.texImage3D(gl.TEXTURE_2D_ARRAY, 0, gl.RGB32F, layerWidth, layerHeight, layers, 0, gl.RGB, gl.FLOAT, layerTexels)),
      };
    }
    const wanted = this.missingAlbedo(scene, {});
    if (wanted) await wanted;
  }

  // The albedo tables of the materials of `set`'s state that the page does not hold yet, asked of the server
  // (POST /api/environment-albedo: Renderer::albedo_table, which the renderer's fast mode reads): a promise
  // of them all, or null when every table is held. A frame drawn meanwhile reads the last table that came.
  missingAlbedo(scene, set) {
    if (!scene.browser.environment) return null;
    const state = sceneState(scene, set);
    const pending = [];
    for (const name of new Set(scene.browser.objects.map((o) => o.material))) {
      const key = JSON.stringify([scene.id, state.materials[name]]);
      const held = this.albedoTables.get(name) || { key: null, table: null, asked: null };
      if (held.key === key) continue;
      if (!held.asked || held.asked.key !== key) {
        const promise = this.fetchAlbedo(scene, name, set).then(async (response) => {
          const now = this.albedoTables.get(name);
          Object.assign(now, { key, table: new Float32Array((await response.json()).table) });
          if (now.asked && now.asked.key === key) now.asked = null;
        });
        held.asked = { key, promise };
        this.albedoTables.set(name, held);
      }
      pending.push(held.asked.promise);
    }
    return pending.length ? Promise.all(pending) : null;
  }

  // Material `name`'s albedo table in `set`'s state: the server's (POST /api/environment-albedo); in a folder
  // of vk-render site, the one it wrote of the scene's own values, which is all it has.
  async fetchAlbedo(scene, name, set) {
    let url = "/api/environment-albedo";
    let response;
    if (SITE) {
      if (Object.keys(set).some((key) => key.startsWith(`material.${name}.`))) {
        throw new Error("a moved material's albedo table is the server's (vk-render serve)");
      }
      url = dataUrl("environment-albedo", scene, { material: name });
      response = await fetch(url);
    } else {
      response = await fetch(url, { method: "POST", body: JSON.stringify({ scene: scene.id, material: name, set }) });
    }
    if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
    return response;
  }

  // The scene's analytic materials' shaders (GET /api/analytic: the forward entries with the material's
  // model, translated on the server), each kept as `ENTRY@SCENE/MATERIAL` beside the renderer's.
  async loadAnalytic(scene, shaders) {
    for (const [name, material] of Object.entries(scene.browser.materials)) {
      if (!material.analytic_values || shaders[`forward.frag${analyticSuffix(scene, name)}`]) continue;
      const url = dataUrl("analytic", scene, { material: name });
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
      for (const [entry, text] of Object.entries(await response.json())) shaders[entry + analyticSuffix(scene, name)] = text;
    }
  }

  // The scene's measured materials' tables (GET /api/measured), one after the other in one RGB32F texture
  // (unit 1), each material's `measured` its table's place, as the renderer's buffer holds them.
  async loadTables(scene) {
    const gl = this.gl;
    const names = Object.keys(scene.browser.materials).filter((name) => scene.browser.materials[name].measured_table);
    this.tableSlots = {};
    if (names.length === 0) return;
    const key = `${scene.id}|${names.join(",")}`;
    if (this.tables && this.tables.key === key) {
      names.forEach((name, slot) => { this.tableSlots[name] = slot; });
      return;
    }
    const tables = [];
    for (const name of names) {
      const url = dataUrl("measured", scene, { material: name });
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
      tables.push(new Float32Array(await response.arrayBuffer()));
    }
    const entries = tables.reduce((sum, t) => sum + t.length / 3, 0);
    const height = Math.ceil(entries / MEASURED_TEXTURE_WIDTH);
    const texels = new Float32Array(MEASURED_TEXTURE_WIDTH * height * 3);
    let offset = 0;
    tables.forEach((table, slot) => {
      texels.set(table, offset);
      offset += table.length;
      this.tableSlots[names[slot]] = slot;
    });
    if (this.tables) gl.deleteTexture(this.tables.texture);
    const texture = gl.createTexture();
    gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.measured_tables);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, MEASURED_TEXTURE_WIDTH, height, 0, gl.RGB, gl.FLOAT, texels);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    gl.activeTexture(gl.TEXTURE0);
    this.tables = { texture, key };
  }
}
