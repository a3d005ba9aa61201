// The explore page's renderer in the visitor's browser (WebGL2): the renderer's own shaders, translated to
// GLSL ES 3.00 when vk-render was built (GET /static/shaders.json), compiled here into programs, drawn in the
// renderer's passes (passes.js) and probes (probe.js) with what a scene's frames read (resources.js) and its
// uniform blocks (blocks.js). What the controls change is computed as the renderer computes it (math.js).
import { getJson } from "../common.js";
import { TEXTURE_UNITS } from "./bindings.js";
import { UniformBlocks } from "./blocks.js";
import { drawFrame } from "./passes.js";
import { integrateCells, probe } from "./probe.js";
import { SceneResources } from "./resources.js";

export class BrowserRenderer {
  // A renderer on `canvas`, or null with the reason when the browser cannot (no WebGL2, no float targets).
  static async create(canvas) {
    const gl = canvas.getContext("webgl2", { antialias: false, depth: false, alpha: false, preserveDrawingBuffer: false });
    if (!gl) return { renderer: null, reason: "this browser has no WebGL2" };
    if (!gl.getExtension("EXT_color_buffer_float")) return { renderer: null, reason: "this browser's WebGL2 cannot render to float targets" };
    const shaders = await getJson("static/shaders.json");
    // An environment's map and layers are read with linear filtering, as the renderer's sampler reads them.
    const filtersFloats = Boolean(gl.getExtension("OES_texture_float_linear"));
    return { renderer: new BrowserRenderer(gl, shaders, filtersFloats), reason: null };
  }

  constructor(gl, shaders, filtersFloats) {
    this.gl = gl;
    this.shaders = shaders;    // the translated shaders by entry (and a model's: resources.js's analyticSuffix)
    this.programs = new Map(); // the programs linked, by their shaders and constants
    this.blocks = new UniformBlocks(gl);
    this.resources = new SceneResources(gl, filtersFloats);
    this.targets = {};         // the passes' render targets: shadow maps, colour, depth (passes.js)
    this.shadowKey = null;     // the scene and lights the shadow maps hold
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
  // SPIRV_CROSS_CONSTANT_ID_n macros, defined before its default), linked once: its uniform blocks bound
  // (and their layouts read), its samplers given their units, and its plain uniforms' locations.
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
    const blocks = this.blocks.attach(program);
    gl.useProgram(program);
    for (const [name, unit] of Object.entries(TEXTURE_UNITS)) {
      const location = gl.getUniformLocation(program, name);
      if (location) gl.uniform1i(location, unit);
    }
    const uniform = (name) => gl.getUniformLocation(program, name);
    const entry = {
      program, blocks, object: uniform("draw.object_index"), light: uniform("draw.light_index"), face: uniform("draw.face"),
      exposure: uniform("resolve.exposure"), tonemap: uniform("resolve.tonemap"), encoding: uniform("resolve.encoding"),
      term: uniform("resolve.term"), low: uniform("resolve.low"), high: uniform("resolve.high"),
    };
    this.programs.set(key, entry);
    return entry;
  }

  // Makes program `entry` current, with the uniform blocks it reads as staged for this frame.
  use(entry) {
    this.gl.useProgram(entry.program);
    this.blocks.use(entry.blocks);
  }

  // What the scene's frames read: its meshes, tables, analytic materials' shaders and environment.
  async load(scene) {
    await this.resources.load(scene, this.shaders);
    this.shadowKey = null;
  }

  // The albedo tables that `set`'s state of `scene` needs and the page does not hold yet (a promise of them
  // all), or null (resources.js).
  missingAlbedo(scene, set) {
    return this.resources.missingAlbedo(scene, set);
  }

  // Draws `scene` with the page's overrides `set` at width x height onto the canvas; a motion frame
  // (`motion`) with the objects' lighter meshes.
  render(scene, set, width, height, motion) {
    drawFrame(this, scene, set, width, height, motion);
  }

  // f_r of object `index`'s material at each pair [wi, wo] of `pairs` (probe.js).
  probe(scene, set, index, pairs) {
    return probe(this, scene, set, index, pairs);
  }

  // The integrals of f_r cos θi of object `index`'s material over `count` cells (probe.js).
  integrateCells(scene, set, index, cells, count) {
    return integrateCells(this, scene, set, index, cells, count);
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
