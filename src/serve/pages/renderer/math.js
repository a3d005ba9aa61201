// The renderer's host-side math, mirrored (src/render/gpu_types.rs, src/render/shadow.rs, glam's cameras), and
// a scene's state under the page's overrides: each function names the Rust it mirrors, and the browser test
// holds the frame and shadow views it makes to the server's (tests/serve_browser.rs).

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
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
export function frameData(camera, width, height, near) {
  const projection = perspectiveInfiniteReverse((camera.fov_y * Math.PI) / 180, width / height, near, true);
  return {
    view_projection: multiply(projection, lookAt(camera.position, camera.look_at, camera.up)),
    pixel_rays: pixelRays(camera, width, height),
    camera_position: [...camera.position, 1],
  };
}

// cube_face_views (src/render/shadow.rs): each face of a light's cube, in Vulkan's order, y up.
export function cubeFaceViews(light, near) {
  const projection = perspectiveInfiniteReverse(Math.PI / 2, 1, near, false);
  const faces = [[[1, 0, 0], [0, -1, 0]], [[-1, 0, 0], [0, -1, 0]], [[0, 1, 0], [0, 0, 1]],
    [[0, -1, 0], [0, 0, -1]], [[0, 0, 1], [0, -1, 0]], [[0, 0, -1], [0, -1, 0]]];
  return faces.map(([forward, up]) => multiply(projection, lookAt(light, [0, 1, 2].map((k) => light[k] + forward[k]), up)));
}

// The camera, lights and materials of `scene` (GET /api/scenes) with `set` applied, as Scene::parse applies
// the same keys: a material's parameters by name, a light's power and position, the camera's position.
export function sceneState(scene, set) {
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

