// The explore page's charts of a material, drawn on canvases as `vk-render plot` draws them: its lobe in the
// plane of incidence and its directional albedo.
import { shown } from "../common.js";

// The lobe's polar plot (luminance, Rec. 709's weights as `vk-render plot lobe`'s) on `canvas`: the surface,
// the incident direction, and the curve scaled to its largest value. `lobe`: its θi, its θo (degrees) and
// f_r cos θo per channel at each (studies.js: browserLobe).
export function drawLobe(canvas, { theta_i: thetaI, theta_o: angles, values }) {
  const context = canvas.getContext("2d");
  const [width, height] = [canvas.width, canvas.height];
  context.clearRect(0, 0, width, height);
  const luminance = values.map(([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b);
  const finite = luminance.filter((v) => Number.isFinite(v));
  const largest = Math.max(1e-30, ...finite.map(Math.abs));
  const [cx, cy, radius] = [width / 2, height - 16, Math.min(width / 2, height - 24) - 8];
  // As `vk-render plot lobe` draws it: θo negative on the side of wi, on the left.
  const at = (theta, r) => [cx + Math.sin((theta * Math.PI) / 180) * r * radius, cy - Math.cos((theta * Math.PI) / 180) * r * radius];
  context.strokeStyle = "#d0d4d9";
  context.lineWidth = 1;
  for (const r of [0.25, 0.5, 0.75, 1]) {
    context.beginPath();
    context.arc(cx, cy, r * radius, Math.PI, 2 * Math.PI);
    context.stroke();
  }
  context.beginPath();
  context.moveTo(cx - radius - 4, cy);
  context.lineTo(cx + radius + 4, cy);
  context.stroke();
  context.strokeStyle = "#5f6368";
  context.setLineDash([4, 4]);
  context.beginPath();
  context.moveTo(cx, cy);
  context.lineTo(...at(-thetaI, 1));
  context.stroke();
  context.setLineDash([]);
  context.strokeStyle = "#1f5fa8";
  context.lineWidth = 2;
  context.beginPath();
  angles.forEach((theta, k) => {
    const v = Number.isFinite(luminance[k]) ? Math.max(luminance[k], 0) / largest : 0;
    const [x, y] = at(theta, v);
    if (k === 0) context.moveTo(x, y);
    else context.lineTo(x, y);
  });
  context.stroke();
  context.fillStyle = "#5f6368";
  context.font = "12px system-ui, sans-serif";
  context.fillText(`f_r cos θo, luminance; θi ${thetaI}° (dashed); largest ${shown(largest)}`, 8, 14);
}

// The directional albedo's chart on `canvas` (what `vk-render plot albedo` draws, per channel): ρ against θo,
// from 0 to the larger of 1 and its largest value, and the bound on its error.
export function drawAlbedo(canvas, albedo) {
  const context = canvas.getContext("2d");
  const [width, height] = [canvas.width, canvas.height];
  context.clearRect(0, 0, width, height);
  const top = Math.max(1, ...albedo.albedo.flat().filter(Number.isFinite));
  const [left, right, upper, lower] = [36, width - 10, 24, height - 22];
  const at = (theta, rho) => [left + ((right - left) * theta) / 90, lower - ((lower - upper) * rho) / top];
  context.strokeStyle = "#d0d4d9";
  context.fillStyle = "#5f6368";
  context.font = "11px system-ui, sans-serif";
  context.lineWidth = 1;
  for (const rho of [0, 0.25, 0.5, 0.75, 1].map((f) => f * top)) {
    const [, y] = at(0, rho);
    context.beginPath();
    context.moveTo(left, y);
    context.lineTo(right, y);
    context.stroke();
    context.fillText(shown(rho, 2), 4, y + 4);
  }
  for (const theta of [0, 30, 60, 90]) context.fillText(`${theta}°`, at(theta, 0)[0] - (theta === 90 ? 18 : 6), height - 6);
  context.lineWidth = 2;
  ["#c5221f", "#188038", "#1a5fb4"].forEach((colour, channel) => {
    context.strokeStyle = colour;
    context.beginPath();
    albedo.theta_o.forEach((theta, k) => {
      const [x, y] = at(theta, Number.isFinite(albedo.albedo[k][channel]) ? albedo.albedo[k][channel] : 0);
      if (k === 0) context.moveTo(x, y);
      else context.lineTo(x, y);
    });
    context.stroke();
  });
  context.fillStyle = "#5f6368";
  context.font = "12px system-ui, sans-serif";
  context.fillText(`ρ(θo), R G B; error bound ${shown(Math.max(...albedo.bound), 2)}`, 8, 14);
}
