// The uniform blocks of the renderer's shaders (shaders/common/scene.glsl) and their buffers. Nothing here
// knows an offset: each block's layout is read from the first linked program that declares it (std140, so
// every member of a declared block is active and the layout is the same in every program), and a frame's
// contents are set member by member, by name, then written when a program that reads them is used.

import { BLOCK_BINDINGS as BINDINGS } from "./bindings.js";

// The GL types of the members written as integers (the rest are floats and float vectors and matrices).
const SIGNED = new Set([0x1404, 0x8b53, 0x8b54, 0x8b55]);  // INT, INT_VEC2, INT_VEC3, INT_VEC4
const UNSIGNED = new Set([0x1405, 0x8dc6, 0x8dc7, 0x8dc8]);  // UNSIGNED_INT, UNSIGNED_INT_VEC2, _VEC3, _VEC4

// Block `index` of `program` (named `name`): its size in bytes and each member's offset and type, by its
// name inside the block ("view_projection", "lights[3].radiance", "objects[0].material.kd"; an array of
// plain values by its first element, "shadow_views[0]", its elements one after the other).
function readLayout(gl, program, index, name) {
  const size = gl.getActiveUniformBlockParameter(program, index, gl.UNIFORM_BLOCK_DATA_SIZE);
  const uniforms = gl.getActiveUniformBlockParameter(program, index, gl.UNIFORM_BLOCK_ACTIVE_UNIFORM_INDICES);
  const offsets = gl.getActiveUniforms(program, uniforms, gl.UNIFORM_OFFSET);
  const members = new Map();
  uniforms.forEach((uniform, k) => {
    const info = gl.getActiveUniform(program, uniform);
    const member = info.name.startsWith(`${name}.`) ? info.name.slice(name.length + 1) : info.name;
    members.set(member, { offset: offsets[k], type: info.type });
  });
  return { size, members };
}

// A block's contents for `count` ranges (one an object for Objects and EnvironmentAlbedo, each at an
// aligned place), set member by member.
class BlockData {
  constructor(name, layout, stride, count) {
    this.name = name;
    this.layout = layout;
    this.stride = stride;
    this.bytes = new ArrayBuffer(stride * (count - 1) + layout.size);
  }

  // Sets `member` of range `range` to `values` (numbers, as the member's type stores them).
  set(member, values, range = 0) {
    const found = this.layout.members.get(member);
    if (!found) throw new Error(`the uniform block ${this.name} has no member ${member}`);
    const View = SIGNED.has(found.type) ? Int32Array : UNSIGNED.has(found.type) ? Uint32Array : Float32Array;
    new View(this.bytes, this.stride * range + found.offset, values.length).set(values);
  }
}

export class UniformBlocks {
  constructor(gl) {
    this.gl = gl;
    this.alignment = gl.getParameter(gl.UNIFORM_BUFFER_OFFSET_ALIGNMENT);
    this.layouts = new Map();
    this.buffers = new Map();  // by block: { buffer, stride }
    this.staged = new Map();   // by block: the contents set for the frame, not written yet
  }

  // Binds the blocks that `program` declares to their points, reads the layouts of those not seen before,
  // and returns their names.
  attach(program) {
    const gl = this.gl;
    const names = [];
    for (let index = 0; index < gl.getProgramParameter(program, gl.ACTIVE_UNIFORM_BLOCKS); index++) {
      const name = gl.getActiveUniformBlockName(program, index);
      if (!(name in BINDINGS)) throw new Error(`a uniform block ${name} that the renderer does not know`);
      gl.uniformBlockBinding(program, index, BINDINGS[name]);
      if (!this.layouts.has(name)) this.layouts.set(name, readLayout(gl, program, index, name));
      names.push(name);
    }
    return names;
  }

  // Block `name`'s contents for the frame, `count` ranges of it, set by `fill(data)` (data.set(member,
  // values, range)) once a program that declares the block is used.
  stage(name, fill, count = 1) {
    this.staged.set(name, { fill, count });
  }

  // Writes the staged contents of `blocks` (a program's, as attach named them) and binds them whole.
  use(blocks) {
    const gl = this.gl;
    for (const name of blocks) {
      const staged = this.staged.get(name);
      if (!staged) continue;
      this.staged.delete(name);
      const layout = this.layouts.get(name);
      const stride = Math.ceil(layout.size / this.alignment) * this.alignment;
      const data = new BlockData(name, layout, stride, staged.count);
      staged.fill(data);
      let held = this.buffers.get(name);
      if (!held) {
        held = { buffer: gl.createBuffer() };
        this.buffers.set(name, held);
      }
      held.stride = stride;
      gl.bindBuffer(gl.UNIFORM_BUFFER, held.buffer);
      gl.bufferData(gl.UNIFORM_BUFFER, data.bytes, gl.DYNAMIC_DRAW);
      gl.bindBufferRange(gl.UNIFORM_BUFFER, BINDINGS[name], held.buffer, 0, layout.size);
    }
  }

  // Binds range `range` of block `name` (an object's ObjectData, or its albedo table).
  bindRange(name, range) {
    const held = this.buffers.get(name);
    if (!held) return;
    const gl = this.gl;
    gl.bindBufferRange(gl.UNIFORM_BUFFER, BINDINGS[name], held.buffer, held.stride * range, this.layouts.get(name).size);
  }
}
