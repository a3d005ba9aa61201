// The library's own code in the browser, as WebAssembly (static/vk-render.wasm, built from crates/web/ by build.rs):
// what the explore page's editor and a site's check page call.

// The library's code compiled to WebAssembly (crates/web/src/lib.rs): the `.brdf` reader, a text in and a JSON
// answer out, the albedo's cubature (crates/cubature) and the check's rules (crates/check-rules), an image
// file in. Loaded once, at its first use (library()).
class WasmLibrary {
  static async load() {
    const response = await fetch("static/vk-render.wasm");
    if (!response.ok) throw new Error(`static/vk-render.wasm: ${response.status} ${response.statusText}`);
    const { instance } = await WebAssembly.instantiate(await response.arrayBuffer(), {});
    return new WasmLibrary(instance.exports);
  }

  constructor(exports) {
    this.exports = exports;
    this.maxBytes = exports.max_text_bytes();
    this.maxImageBytes = exports.max_image_bytes();
    this.albedoRuns = 0;
  }

  // `read_brdf`, `read_compiler_log`, `albedo_start` or `check_begin` of `text`.
  call(name, text) {
    const bytes = new TextEncoder().encode(text);
    const at = this.exports.input(bytes.length);
    if (at === 0) throw new Error(`the text is ${bytes.length} bytes: the editor takes at most ${this.maxBytes}`);
    new Uint8Array(this.exports.memory.buffer, at, bytes.length).set(bytes);
    return this.answer(this.exports[name](bytes.length));
  }

  // `check_picture`, `check_objects` or `check_image` of an image file's `bytes` (a Uint8Array).
  callWithImage(name, bytes) {
    const at = this.exports.image_input(bytes.length);
    if (at === 0) throw new Error(`the file is ${bytes.length} bytes: this page takes at most ${this.maxImageBytes}`);
    new Uint8Array(this.exports.memory.buffer, at, bytes.length).set(bytes);
    return this.answer(this.exports[name](bytes.length));
  }

  // The bytes of the output's `length` (a binary answer: check_difference's PNG), copied out.
  bytes(length) {
    return new Uint8Array(this.exports.memory.buffer, this.exports.output(), length).slice();
  }

  // The JSON answer of `length` bytes that a call left.
  answer(length) {
    return JSON.parse(new TextDecoder().decode(new Uint8Array(this.exports.memory.buffer, this.exports.output(), length)));
  }

  // The directional albedo of object `index`'s material (the page's overrides `set` applied) at each of
  // `angles` (degrees): the library's cubature, as `vk-render plot albedo` runs it, its cells integrated by
  // this browser's albedo probe (BrowserRenderer.integrateCells). {theta_o, albedo: [[r, g, b]...], bound:
  // [...], rounds, stopped}; null when a later albedo started meanwhile (one cubature at a time).
  async albedo(renderer, scene, set, index, angles) {
    const run = ++this.albedoRuns;
    let answer = this.call("albedo_start", JSON.stringify({ theta_o: angles }));
    let stopped = false;
    while (!answer.error && answer.pending > 0) {
      const count = answer.pending;
      const cells = new Float32Array(this.exports.memory.buffer, this.exports.albedo_cells(), 8 * count).slice();
      const estimates = renderer.integrateCells(scene, set, index, cells, count);
      for (let k = 0; k < count && !stopped; k++) stopped = estimates[4 * k + 3] !== 0;
      const at = this.exports.albedo_estimates(count);
      if (at === 0) throw new Error(`the albedo's ${count} cells were not the ones pending`);
      new Float32Array(this.exports.memory.buffer, at, 8 * count).set(estimates);
      answer = this.answer(this.exports.albedo_take());
      // The page answers between rounds; a newer albedo takes the WebAssembly's cubature over.
      await new Promise((resolve) => setTimeout(resolve));
      if (run !== this.albedoRuns) return null;
    }
    if (answer.error) throw new Error(answer.error);
    return { ...this.answer(this.exports.albedo_result()), stopped };
  }
}

// The WebAssembly library, loaded at the first call.
let wasmLibrary = null;
export function library() {
  if (!wasmLibrary) wasmLibrary = WasmLibrary.load().catch((error) => { wasmLibrary = null; throw error; });
  return wasmLibrary;
}
