// The explore page's renderer in the visitor's browser (WebGL2): the renderer's own shaders, translated to
// GLSL ES 3.00 when vk-render was built (GET /static/shaders.json), drawn in the renderer's passes: each
// shadow-casting light's cube (six layers of a float array texture), the forward pass into a float target
// at one sample a pixel, and the resolve to the course's 8-bit levels on the canvas. What the controls change
// is computed here as the renderer computes it; each function below names the Rust it mirrors, and the
// browser test holds the frame and shadow views it makes to the server's (tests/serve_browser.rs).
"use strict";

// common/environment.glsl's ALBEDO_TABLE_SIZE: entries of a material's albedo table, each two vec4.
const ALBEDO_TABLE_SIZE = 32;
// The uniform blocks' bindings, and their sizes in bytes (std140 as shaders/common/scene.glsl declares them).
const BLOCKS = {
  Frame: [0, 192], Lights: [1, 16 * 48], Objects: [2, 224], ShadowViews: [3, 96 * 64], AnalyticParameters: [4, 1024 * 16],
  EnvironmentAlbedo: [5, ALBEDO_TABLE_SIZE * 32],
};
// shadow.frag's FAR_AWAY: what a shadow texel holds where nothing is.
const FAR_AWAY = 3.0e38;
// brdf/measured.glsl's MEASURED_TEXTURE_WIDTH: texels a row of the measured tables' texture, one entry each.
const MEASURED_TEXTURE_WIDTH = 2048;

// ---- The renderer's host-side math (src/render/gpu_types.rs, src/render/shadow.rs, glam's cameras) ----

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const normalize = (a) => scale(a, 1 / Math.sqrt(dot(a, a)));

// Column-major 4 x 4 product a * b.
function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let sum = 0;
      for (let k = 0; k < 4; k++) sum += a[4 * k + r] * b[4 * c + k];
      out[4 * c + r] = sum;
    }
  }
  return out;
}

// glam's camera::rh::view::look_at_mat4: world to a right-handed view looking down -z.
function lookAt(eye, center, up) {
  const f = normalize(sub(center, eye));
  const s = normalize(cross(f, up));
  const u = cross(s, f);
  return [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1];
}

// glam's perspective_infinite_reverse: depth near / distance; Vulkan's (flipY, GpuFrame::new) turns y over.
function perspectiveInfiniteReverse(fovY, aspect, near, flipY) {
  const f = 1 / Math.tan(0.5 * fovY);
  return [f / aspect, 0, 0, 0, 0, flipY ? -f : f, 0, 0, 0, 0, 0, -1, 0, 0, near, 0];
}

// PixelRays::new: the camera's ray through framebuffer position (x, y) is pixel_rays * (x, y, 1, 0).
function pixelRays(camera, width, height) {
  const w = normalize(sub(camera.position, camera.look_at));
  const u = normalize(cross(camera.up, w));
  const v = cross(w, u);
  const halfHeight = Math.tan((camera.fov_y * Math.PI) / 180 * 0.5);
  const halfWidth = (halfHeight * width) / height;
  const corner = sub(sub(scale(v, halfHeight), scale(u, halfWidth)), w);
  return [...scale(u, (2 * halfWidth) / width), 0, ...scale(v, (-2 * halfHeight) / height), 0, ...corner, 0, 0, 0, 0, 0];
}

// GpuFrame::new's matrices for the camera and the image's size.
function frameData(camera, width, height, near) {
  const projection = perspectiveInfiniteReverse((camera.fov_y * Math.PI) / 180, width / height, near, true);
  return {
    view_projection: multiply(projection, lookAt(camera.position, camera.look_at, camera.up)),
    pixel_rays: pixelRays(camera, width, height),
    camera_position: [...camera.position, 1],
  };
}

// cube_face_views (src/render/shadow.rs): each face of a light's cube, in Vulkan's order, y up.
function cubeFaceViews(light, near) {
  const projection = perspectiveInfiniteReverse(Math.PI / 2, 1, near, false);
  const faces = [[[1, 0, 0], [0, -1, 0]], [[-1, 0, 0], [0, -1, 0]], [[0, 1, 0], [0, 0, 1]],
    [[0, -1, 0], [0, 0, -1]], [[0, 0, 1], [0, -1, 0]], [[0, 0, -1], [0, -1, 0]]];
  return faces.map(([forward, up]) => multiply(projection, lookAt(light, [0, 1, 2].map((k) => light[k] + forward[k]), up)));
}

// ---- The scene's state: its description with the page's overrides (the `--set` keys the controls make) ----

// The camera, lights and materials of `scene` (GET /api/scenes) with `set` applied, as Scene::parse applies
// the same keys: a material's parameters by name, a light's power and position, the camera's position.
function sceneState(scene, set) {
  const value = (key, base) => (key in set ? set[key] : base);
  const camera = { ...scene.camera, position: value("camera.position", scene.camera.position) };
  const lights = scene.lights.map((light) => ({
    position: value(`light.${light.index}.position`, light.position),
    power: value(`light.${light.index}.power`, light.power),
    color: light.color,
  }));
  const materials = {};
  for (const [name, base] of Object.entries(scene.browser.materials)) {
    const material = { ...base };
    if (base.analytic_values) material.analytic_values = [...base.analytic_values];
    for (const parameter of scene.materials[name].parameters) {
      if (!(parameter.key in set)) continue;
      const v = set[parameter.key];
      if (base.analytic_offsets) {
        // An analytic value as Analytic::floats lays it: a bool as 0 or 1, a colour's three components.
        const floats = Array.isArray(v) ? v : parameter.kind === "colour" ? [v, v, v] : [Number(v)];
        material.analytic_values.splice(base.analytic_offsets[parameter.name], floats.length, ...floats);
      } else {
        material[parameter.name] = Array.isArray(v) ? [...v, 0] : typeof v === "number" && ["kd", "ks", "f0"].includes(parameter.name) ? [v, v, v, 0] : v;
      }
    }
    materials[name] = material;
  }
  return { camera, lights, materials };
}

// ---- WebGL2 ----

// The suffix of an analytic material's shaders' names (BrowserRenderer.loadAnalytic); none for another.
const analyticSuffix = (scene, name) => (scene.browser.materials[name].analytic_values ? `@${scene.id}/${name}` : "");

// The texture units of the shaders' samplers (the resolve's colour shares the shadow cubes' unit).
const TEXTURE_UNITS = { shadow_maps: 0, measured_tables: 1, environment_map: 2, environment_prefiltered: 3, colour: 0, probe_directions: 4, albedo_cells: 4 };

// The albedo probe's draws: at most ALBEDO_ROWS rows of ALBEDO_WIDTH cells each (each cell 225 evaluations of
// the model), so that one draw stays short on a software GPU.
const ALBEDO_WIDTH = 1024;
const ALBEDO_ROWS = 16;

// Where the server hands out the mesh of `scene`'s object `index` (the key its vertex array is kept by).
// (`motion`: its lighter mesh, for the motion frames).
const meshUrl = (scene, index, motion) => dataUrl("mesh", scene, motion ? { object: index, motion: true } : { object: index });

class BrowserRenderer {
  // A renderer on `canvas`, or null with the reason when the browser cannot (no WebGL2, no float targets).
  static async create(canvas) {
    const gl = canvas.getContext("webgl2", { antialias: false, depth: false, alpha: false, preserveDrawingBuffer: false });
    if (!gl) return { renderer: null, reason: "this browser has no WebGL2" };
    if (!gl.getExtension("EXT_color_buffer_float")) return { renderer: null, reason: "this browser's WebGL2 cannot render to float targets" };
    const shaders = await getJson("static/shaders.json");
    const renderer = new BrowserRenderer(gl, shaders);
    // An environment's map and layers are read with linear filtering, as the renderer's sampler reads them.
    renderer.filtersFloats = Boolean(gl.getExtension("OES_texture_float_linear"));
    return { renderer, reason: null };
  }

  constructor(gl, shaders) {
    this.gl = gl;
    this.shaders = shaders;
    this.programs = new Map();
    this.meshes = new Map();
    this.blocks = {};
    // One buffer a block, but the objects': theirs are ranges of one buffer (writeObjects, bindObject).
    for (const [name, [binding, size]] of Object.entries(BLOCKS).filter(([name]) => name !== "Objects")) {
      const buffer = gl.createBuffer();
      gl.bindBuffer(gl.UNIFORM_BUFFER, buffer);
      gl.bufferData(gl.UNIFORM_BUFFER, size, gl.DYNAMIC_DRAW);
      this.blocks[name] = { buffer, binding, size };
    }
    const alignment = gl.getParameter(gl.UNIFORM_BUFFER_OFFSET_ALIGNMENT);
    this.objectStride = Math.ceil(BLOCKS.Objects[1] / alignment) * alignment;
    this.objects = gl.createBuffer();
    this.albedoStride = Math.ceil(BLOCKS.EnvironmentAlbedo[1] / alignment) * alignment;
    this.albedoBuffer = gl.createBuffer();
    this.albedoTables = new Map();
    this.shadowKey = null;
    this.emptyVertexArray = gl.createVertexArray();
  }

  // Forgets the shaders whose names end with `suffix` (a model's: analyticSuffix), and their programs.
  forget(suffix) {
    for (const name of Object.keys(this.shaders)) if (name.endsWith(suffix)) delete this.shaders[name];
    for (const [key, entry] of this.programs) {
      if (!key.split("|")[1].endsWith(suffix)) continue;
      this.gl.deleteProgram(entry.program);
      this.programs.delete(key);
    }
  }

  // The program of a vertex and a fragment shader with its specialization constants (SPIRV-Cross's
  // SPIRV_CROSS_CONSTANT_ID_n macros, defined before its default), compiled once.
  program(vertex, fragment, constants) {
    const key = `${vertex}|${fragment}|${JSON.stringify(constants)}`;
    if (this.programs.has(key)) return this.programs.get(key);
    const gl = this.gl;
    const defines = Object.entries(constants).map(([id, v]) => `#define SPIRV_CROSS_CONSTANT_ID_${id} ${v}\n`).join("");
    const compile = (type, name) => {
      const text = this.shaders[name];
      if (!text) throw new Error(`no translated shader ${name}`);
      const shader = gl.createShader(type);
      gl.shaderSource(shader, text.replace(/^(#version 300 es\n)/, `$1${defines}`));
      gl.compileShader(shader);
      if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(`${name}: ${gl.getShaderInfoLog(shader)}`);
      return shader;
    };
    const program = gl.createProgram();
    const stages = [compile(gl.VERTEX_SHADER, vertex), compile(gl.FRAGMENT_SHADER, fragment)];
    for (const shader of stages) gl.attachShader(program, shader);
    gl.bindAttribLocation(program, 0, "in_position");
    gl.bindAttribLocation(program, 1, "in_normal");
    gl.bindAttribLocation(program, 2, "in_tangent");
    gl.linkProgram(program);
    // The shaders go with the program (deleted once it is: forget).
    for (const shader of stages) gl.deleteShader(shader);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(`${vertex} + ${fragment}: ${gl.getProgramInfoLog(program)}`);
    for (const [name, [binding]] of Object.entries(BLOCKS)) {
      const index = gl.getUniformBlockIndex(program, name);
      if (index !== gl.INVALID_INDEX) gl.uniformBlockBinding(program, index, binding);
    }
    gl.useProgram(program);
    for (const [name, unit] of Object.entries(TEXTURE_UNITS)) {
      const location = gl.getUniformLocation(program, name);
      if (location) gl.uniform1i(location, unit);
    }
    const uniform = (name) => gl.getUniformLocation(program, name);
    const entry = {
      program, object: uniform("draw.object_index"), light: uniform("draw.light_index"), face: uniform("draw.face"),
      exposure: uniform("resolve.exposure"), tonemap: uniform("resolve.tonemap"), encoding: uniform("resolve.encoding"),
      term: uniform("resolve.term"), low: uniform("resolve.low"), high: uniform("resolve.high"),
    };
    this.programs.set(key, entry);
    return entry;
  }

  // The scene's meshes (GET /api/mesh), each as a vertex array: position (4 floats), normal (3), tangent (3);
  // and the lighter ones of the motion frames, where an object has one.
  async load(scene) {
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
    await this.loadAnalytic(scene);
    await this.loadEnvironment(scene);
    this.shadowKey = null;
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

  // Every object's albedo table (the latest its material has), each at its aligned place in one buffer.
  writeAlbedo(scene) {
    const gl = this.gl;
    const data = new Float32Array((this.albedoStride / 4) * scene.browser.objects.length);
    scene.browser.objects.forEach((object, k) => {
      const held = this.albedoTables.get(object.material);
      if (held && held.table) data.set(held.table, (this.albedoStride / 4) * k);
    });
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.albedoBuffer);
    gl.bufferData(gl.UNIFORM_BUFFER, data, gl.DYNAMIC_DRAW);
  }

  // The scene's analytic materials' shaders (GET /api/analytic: the forward entries with the material's
  // model, translated on the server), each kept as `ENTRY@SCENE/MATERIAL` beside the renderer's.
  async loadAnalytic(scene) {
    for (const [name, material] of Object.entries(scene.browser.materials)) {
      if (!material.analytic_values || this.shaders[`forward.frag${analyticSuffix(scene, name)}`]) continue;
      const url = dataUrl("analytic", scene, { material: name });
      const response = await fetch(url);
      if (!response.ok) throw new Error(`${url}: ${(await response.text()).trim()}`);
      for (const [entry, text] of Object.entries(await response.json())) this.shaders[entry + analyticSuffix(scene, name)] = text;
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
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, MEASURED_TEXTURE_WIDTH, height, 0, gl.RGB, gl.FLOAT, texels);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    gl.activeTexture(gl.TEXTURE0);
    this.tables = { texture, key };
  }


  write(block, floats) {
    const gl = this.gl;
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.blocks[block].buffer);
    gl.bufferSubData(gl.UNIFORM_BUFFER, 0, floats);
    gl.bindBufferBase(gl.UNIFORM_BUFFER, this.blocks[block].binding, this.blocks[block].buffer);
  }

  // The Lights block (GpuPointLight::new): position, colour * power, and the light's cube (every face drawn).
  writeLights(state, shadows) {
    const data = new ArrayBuffer(BLOCKS.Lights[1]);
    const floats = new Float32Array(data);
    const ints = new Int32Array(data);
    let cube = 0;
    state.lights.forEach((light, k) => {
      floats.set([...light.position, 1], 12 * k);
      floats.set([...scale(light.color, light.power), 0], 12 * k + 4);
      ints.set(shadows[k] ? [cube++, 63, 0, 0] : [-1, 0, 0, 0], 12 * k + 8);
    });
    this.write("Lights", new Uint8Array(data));
  }

  // The analytic materials' values one after the other (AnalyticValues::write), and where each one's begin.
  writeAnalytic(state) {
    const values = [];
    const firsts = {};
    for (const [name, material] of Object.entries(state.materials)) {
      if (!material.analytic_values) continue;
      firsts[name] = values.length;
      values.push(...material.analytic_values);
    }
    this.write("AnalyticParameters", new Float32Array(values.length ? values : [0]));
    return firsts;
  }

  // Every object's ObjectData (GpuObject), each at its aligned place in one buffer; an analytic material's
  // `analytic` where its values begin (`firsts`).
  writeObjects(scene, state, firsts) {
    const gl = this.gl;
    const data = new ArrayBuffer(this.objectStride * scene.browser.objects.length);
    scene.browser.objects.forEach((object, k) => {
      const base = this.objectStride * k;
      const floats = new Float32Array(data, base, 56);
      const uints = new Uint32Array(data, base, 56);
      const m = state.materials[object.material];
      floats.set(object.model, 0);
      floats.set(object.normal_matrix, 16);
      floats.set(m.kd, 32);
      floats.set(m.ks, 36);
      floats.set(m.f0, 40);
      uints[44] = m.brdf;
      floats.set([m.shininess, m.sigma, m.roughness, m.metalness], 45);
      uints.set([m.diffuse, this.tableSlots[object.material] || 0, firsts[object.material] || 0], 49);
      uints.set(object.flags, 52);
    });
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.objects);
    gl.bufferData(gl.UNIFORM_BUFFER, data, gl.DYNAMIC_DRAW);
  }

  // Binds object `k`'s ranges of the objects' buffer and, under an environment, of the albedo tables'.
  bindObject(scene, k) {
    const gl = this.gl;
    gl.bindBufferRange(gl.UNIFORM_BUFFER, BLOCKS.Objects[0], this.objects, this.objectStride * k, BLOCKS.Objects[1]);
    if (scene.browser.environment) gl.bindBufferRange(gl.UNIFORM_BUFFER, BLOCKS.EnvironmentAlbedo[0], this.albedoBuffer, this.albedoStride * k, BLOCKS.EnvironmentAlbedo[1]);
  }

  // The float depth buffer of a target of width x height (one kept, made anew when the size changes).
  depthBuffer(width, height) {
    const gl = this.gl;
    if (this.depth && this.depth.width === width && this.depth.height === height) return this.depth.renderbuffer;
    if (this.depth) gl.deleteRenderbuffer(this.depth.renderbuffer);
    const renderbuffer = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, renderbuffer);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT32F, width, height);
    this.depth = { renderbuffer, width, height };
    return renderbuffer;
  }

  // Every shadow-casting light's cube, each face a layer (6 cube + face) of one R32F array texture (drawn
  // with the lighter meshes for a motion frame).
  drawShadows(scene, state, motion) {
    const gl = this.gl;
    const size = scene.browser.shadow_map_size;
    const casting = scene.browser.shadows.map((s, k) => (s ? k : -1)).filter((k) => k >= 0);
    const layers = Math.max(1, 6 * casting.length);
    if (!this.shadowMaps || this.shadowMaps.size !== size || this.shadowMaps.layers !== layers) {
      if (this.shadowMaps) gl.deleteTexture(this.shadowMaps.texture);
      const texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
      gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.R32F, size, size, layers);
      for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D_ARRAY, p, gl.NEAREST);
      this.shadowMaps = { texture, size, layers };
    }
    const views = new Float32Array(BLOCKS.ShadowViews[1] / 4);
    casting.forEach((k, cube) => cubeFaceViews(state.lights[k].position, scene.browser.near).forEach((m, face) => views.set(m, 16 * (6 * cube + face))));
    this.write("ShadowViews", views);
    const framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, this.depthBuffer(size, size));
    gl.viewport(0, 0, size, size);
    casting.forEach((k, cube) => {
      for (let face = 0; face < 6; face++) {
        gl.framebufferTextureLayer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, this.shadowMaps.texture, 0, 6 * cube + face);
        gl.clearBufferfv(gl.COLOR, 0, [FAR_AWAY, 0, 0, 0]);
        gl.clearBufferfv(gl.DEPTH, 0, [0]);
        scene.browser.objects.forEach((object, index) => {
          if (!object.casts_shadow) return;
          const entry = this.program("shadow.vert", object.sphere ? "shadow_sphere.frag" : "shadow.frag", {});
          gl.useProgram(entry.program);
          gl.uniform1ui(entry.object, 0);
          gl.uniform1ui(entry.light, k);
          gl.uniform1ui(entry.face, face);
          this.drawMesh(scene, index, motion);
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
  hidesBackFaces(object, eye) {
    if (!object.closed) return false;
    const n = object.normal_matrix;
    const local = [0, 1, 2].map((r) => n[4 * r] * eye[0] + n[4 * r + 1] * eye[1] + n[4 * r + 2] * eye[2] + n[4 * r + 3]);
    const [least, greatest] = object.bounds;
    return !local.every((v, k) => v >= least[k] && v <= greatest[k]);
  }

  // Draws object `index`: its mesh, or for a motion frame its lighter one where it has one.
  drawMesh(scene, index, motion) {
    const gl = this.gl;
    const mesh = this.meshes.get(meshUrl(scene, index, motion && scene.browser.objects[index].motion_mesh));
    this.bindObject(scene, index);
    gl.bindVertexArray(mesh.vertexArray);
    gl.drawElements(gl.TRIANGLES, mesh.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
  }

  // Draws `scene` with the page's overrides `set` at width x height onto the canvas; a motion frame
  // (`motion`) with the objects' lighter meshes.
  render(scene, set, width, height, motion) {
    const gl = this.gl;
    const canvas = gl.canvas;
    if (canvas.width !== width || canvas.height !== height) [canvas.width, canvas.height] = [width, height];
    const state = sceneState(scene, set);
    const browser = scene.browser;
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.GEQUAL);  // reverse-Z, as the renderer's GREATER_OR_EQUAL (src/render/passes.rs)
    gl.disable(gl.CULL_FACE);
    // Meshes are wound counter-clockwise seen from outside; through the camera's y-flipped projection they
    // are clockwise in GL's window coordinates (PassView::front_face finds Vulkan's counter-clockwise, whose
    // area has the opposite sign to GL's).
    gl.frontFace(gl.CW);
    gl.cullFace(gl.BACK);
    this.writeLights(state, browser.shadows);
    this.writeObjects(scene, state, this.writeAnalytic(state));
    if (browser.environment) this.writeAlbedo(scene);
    // The shadow cubes, drawn again when a light moves, or for a still frame where a motion frame drew them.
    const shadowKey = JSON.stringify([scene.id, state.lights.map((l) => l.position)]);
    if (shadowKey !== this.shadowKey || (!motion && this.shadowsOfMotion)) {
      this.shadowsOfMotion = Boolean(motion);
      this.drawShadows(scene, state, this.shadowsOfMotion);
      this.shadowKey = shadowKey;
    }
    // The frame (GpuFrame::new).
    const frame = new ArrayBuffer(BLOCKS.Frame[1]);
    const f = new Float32Array(frame);
    const camera = frameData(state.camera, width, height, browser.near);
    f.set(camera.view_projection, 0);
    f.set(camera.pixel_rays, 16);
    f.set(camera.camera_position, 32);
    f.set(browser.background, 36);
    f[40] = 2 / browser.shadow_map_size;
    f.set(browser.environment ? browser.environment.frame : [1, 0, 0, 0], 44);
    this.write("Frame", new Uint8Array(frame));
    // The forward pass into a float target, one sample a pixel.
    if (!this.colour || this.colour.width !== width || this.colour.height !== height) {
      if (this.colour) gl.deleteTexture(this.colour.texture);
      const texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
      for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
      this.colour = { texture, width, height };
    }
    const framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.colour.texture, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, this.depthBuffer(width, height));
    gl.viewport(0, 0, width, height);
    gl.clearBufferfv(gl.COLOR, 0, browser.background);
    gl.clearBufferfv(gl.DEPTH, 0, [0]);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.tables ? this.tables.texture : null);
    if (browser.environment) {
      gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.environment_map);
      gl.bindTexture(gl.TEXTURE_2D, this.environment.map);
      gl.activeTexture(gl.TEXTURE0 + TEXTURE_UNITS.environment_prefiltered);
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.environment.layers);
    }
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.shadowMaps.texture);
    // A visible environment is the background (background.frag's WITH_ENVIRONMENT variant, ENVIRONMENT 1),
    // drawn first and under everything.
    if (browser.environment && browser.environment.visible) {
      gl.disable(gl.DEPTH_TEST);
      gl.useProgram(this.program("background.vert", "background.frag+WITH_ENVIRONMENT", { 5: "1u" }).program);
      gl.bindVertexArray(this.emptyVertexArray);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.bindVertexArray(null);
      gl.enable(gl.DEPTH_TEST);
    }
    browser.objects.forEach((object, index) => {
      const material = state.materials[object.material];
      // The pipeline's constants (PipelineKey::for_object): BRDF, shadow filter, lights, diffuse lobe, view;
      // a view other than the radiance is drawn by the TERM_VIEWS variant, as the renderer draws it.
      // An environment's light in its fast mode (ENVIRONMENT 2), by the WITH_ENVIRONMENT variants.
      const constants = { 0: `${material.brdf}u`, 1: `${browser.shadow_filter}u`, 2: `${state.lights.length}u`, 3: `${material.diffuse}u`, 4: `${browser.view}u` };
      if (browser.environment) constants[5] = "2u";
      const variant = (browser.environment ? "+WITH_ENVIRONMENT" : "") + (browser.view === 0 ? "" : "+TERM_VIEWS");
      const model = analyticSuffix(scene, object.material);
      const entry = object.sphere
        ? this.program("forward_sphere.vert", `forward_sphere.frag${variant}${model}`, constants)
        : this.program("forward.vert", `forward.frag${variant}${model}`, constants);
      gl.useProgram(entry.program);
      gl.uniform1ui(entry.object, 0);
      if (this.hidesBackFaces(object, state.camera.position)) gl.enable(gl.CULL_FACE);
      else gl.disable(gl.CULL_FACE);
      this.drawMesh(scene, index, motion);
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
    // The resolve onto the canvas.
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteFramebuffer(framebuffer);
    gl.disable(gl.DEPTH_TEST);
    const resolve = this.program("background.vert", "web/resolve.frag", {});
    gl.useProgram(resolve.program);
    gl.uniform1f(resolve.exposure, browser.exposure);
    gl.uniform1ui(resolve.tonemap, browser.tonemap);
    gl.uniform1ui(resolve.encoding, browser.encoding);
    gl.uniform1ui(resolve.term, browser.term ? 1 : 0);
    gl.uniform1f(resolve.low, low);
    gl.uniform1f(resolve.high, Math.fround(high));
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, null);
    gl.bindTexture(gl.TEXTURE_2D, this.colour.texture);
    gl.bindVertexArray(this.emptyVertexArray);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
  }

  // f_r of object `index`'s material (the page's overrides `set` applied) at each pair [wi, wo] of `pairs`
  // (n = +z, X = +x, as the probe's frame), by the probe pass (shaders/web/probe.frag: brdf_probe.comp's
  // work): [r, g, b, stopped] each, `stopped` 1 where an analytic model's loops were stopped by their guard.
  probe(scene, set, index, pairs) {
    const count = pairs.length;
    const directions = new Float32Array(8 * count);
    pairs.forEach(([wi, wo], k) => {
      directions.set([...wi, 0], 4 * k);
      directions.set([...wo, 0], 4 * (count + k));
    });
    const [values] = this.runProbe(scene, set, index, "web/probe.frag", { data: directions, width: count, height: 2 }, count, 1, 1);
    return pairs.map((_, k) => Array.from(values.subarray(4 * k, 4 * k + 4)));
  }

  // The integrals of f_r cos θi of object `index`'s material (the page's overrides `set` applied) over
  // `count` cells of the hemisphere, by the albedo probe (shaders/web/albedo.frag: brdf_albedo.comp's cell
  // integral), `cells` holding each one's bounds and wo (8 floats: crates/cubature's cells, as the WebAssembly
  // writes them): the Kronrod estimates (RGBA each, alpha 1 where an analytic model's loops were stopped), then
  // the Gauss ones, in one array; drawn ALBEDO_ROWS rows of ALBEDO_WIDTH cells at a time.
  integrateCells(scene, set, index, cells, count) {
    const estimates = new Float32Array(8 * count);
    const perDraw = ALBEDO_WIDTH * ALBEDO_ROWS;
    for (let first = 0; first < count; first += perDraw) {
      const n = Math.min(perDraw, count - first);
      const width = Math.min(n, ALBEDO_WIDTH);
      const height = Math.ceil(n / width);
      const data = new Float32Array(8 * width * height);
      data.set(cells.subarray(8 * first, 8 * (first + n)));
      const [kronrod, gauss] = this.runProbe(scene, set, index, "web/albedo.frag", { data, width: 2 * width, height }, width, height, 2);
      estimates.set(kronrod.subarray(0, 4 * n), 4 * first);
      estimates.set(gauss.subarray(0, 4 * n), 4 * (count + first));
    }
    return estimates;
  }

  // Draws the probe entry `entry` (web/probe.frag, web/albedo.frag) for object `index`'s material with the
  // page's overrides `set` into `targets` float targets of width × height, its input (RGBA floats, `input.width`
  // × `input.height`) on the probes' texture unit: each target's pixels (RGBA floats, rows from the bottom).
  runProbe(scene, set, index, entry, input, width, height, targets) {
    const gl = this.gl;
    const state = sceneState(scene, set);
    this.writeObjects(scene, state, this.writeAnalytic(state));
    this.bindObject(scene, index);
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
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.tables ? this.tables.texture : null);
    const object = scene.browser.objects[index];
    const material = state.materials[object.material];
    // The material's constants, as the forward pass has them (the BRDF and its diffuse lobe).
    const program = this.program("background.vert", `${entry}${analyticSuffix(scene, object.material)}`, { 0: `${material.brdf}u`, 3: `${material.diffuse}u` });
    gl.useProgram(program.program);
    gl.uniform1ui(program.object, 0);
    gl.bindVertexArray(this.emptyVertexArray);
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

  // The canvas's pixels as the image's rows from the top (R, G, B, A each), read before it is shown.
  pixels() {
    const gl = this.gl;
    const [width, height] = [gl.canvas.width, gl.canvas.height];
    const bottomUp = new Uint8Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, bottomUp);
    const rows = new Uint8Array(bottomUp.length);
    for (let y = 0; y < height; y++) rows.set(bottomUp.subarray((height - 1 - y) * width * 4, (height - y) * width * 4), y * width * 4);
    return rows;
  }
}
