// A check's report: the verdict, the mistakes named and explained, the statistics, and the pictures: yours
// beside the exact one, the difference as a heat map (viridis: it reads in grey and for colour-blind
// readers) and a magnifier on the worst region. The server's report page (/reports/ID) shows a report the
// API kept; a site's check page (check.js) one its WebAssembly made, with the same showReport.
import { el, getJson, shown } from "./common.js";

function verdictLine(report) {
  if (report.matches) return "matches: your image is the exact one within the tolerance";
  if (report.verdict === "mistake") return `differs: ${report.mistakes[0].name}`;
  if (report.verdict === "tie") return `differs: one of ${report.mistakes.map((m) => m.name).join(", ")}`;
  if (report.verdict === "matches") return "within the tolerance, but a known mistake explains it better";
  return "differs: no known mistake explains it";
}

function mistakes(report) {
  const list = el("section", { id: "mistakes" });
  for (const m of report.mistakes) {
    list.append(el("div", { class: "mistake", "data-mistake": m.name },
      el("h3", { text: m.name }),
      el("p", { text: m.explanation }),
      el("p", {}, "It should be ", el("code", { text: m.should_be }), "; your image suggests ", el("code", { text: m.looks_like }), ".")));
  }
  if (report.verdict === "tie" && report.tells_apart) {
    list.append(el("p", { text: `The practical's scene that tells them apart: ${report.tells_apart}. Render yours of it and check it.` }));
  }
  for (const w of report.wrong_parameters) {
    const fitted = Object.entries(w.fitted).map(([k, v]) => `${k} = ${v.map((x) => shown(x)).join(", ")}`).join("; ");
    const given = Object.entries(w.scene).map(([k, v]) => `${k} = ${v.map((x) => shown(x)).join(", ")}`).join("; ");
    list.append(el("div", { class: "mistake", "data-wrong-parameters": String(w.object) },
      el("h3", { text: `object ${w.object} (${w.material}, ${w.model}): other parameters` }),
      el("p", { text: `Your image matches the correct ${w.model} with ${fitted}; the scene says ${given} (fitted within ${shown(w.residual_levels)} levels, the scene's parameters ${shown(w.scene_levels)}).` })));
  }
  return list;
}

function statistics(report) {
  const s = report.statistics;
  const rows = [el("tr", {}, ...["", "rms", "mean", "p99", "over"].map((h) => el("th", { text: h })))];
  const row = (name, stats) => el("tr", {}, el("td", { text: name }), ...[stats.rms, stats.mean, stats.p99].map((v) => el("td", { text: shown(v) })), el("td", { text: `${shown(100 * stats.over)}%` }));
  rows.push(row("whole image", s));
  for (const r of report.regions) rows.push(row(`${r.object === null ? "background" : "object " + r.object} ${r.part}`, r));
  return el("table", { id: "statistics" }, ...rows);
}

function figure(picture, name, caption, ...below) {
  return el("figure", {}, el("img", { src: picture(name), alt: caption, "data-picture": name }), el("figcaption", { text: caption }), ...below);
}

// The worst region of each picture, magnified four times; moving over your image moves it.
function magnifier(report, picture) {
  const region = report.worst_region;
  const canvases = ["yours", "exact", "difference"].map((name) => {
    const canvas = el("canvas", { width: String(region.width), height: String(region.height), "data-magnified": name });
    const image = new Image();
    image.src = picture(name);
    canvas.image = image;
    return canvas;
  });
  const captioned = canvases.map((canvas) => el("figure", {}, canvas, el("figcaption", { text: canvas.dataset.magnified })));
  const paint = (x, y) => {
    for (const canvas of canvases) {
      const context = canvas.getContext("2d");
      context.imageSmoothingEnabled = false;
      context.drawImage(canvas.image, x, y, region.width, region.height, 0, 0, region.width, region.height);
    }
  };
  Promise.all(canvases.map((c) => c.image.decode())).then(() => paint(region.x, region.y)).catch(() => {});
  const box = el("section", {}, el("h2", { text: "Magnified: where the differences are worst (move over your image to look elsewhere)" }), el("div", { class: "magnifier" }, ...captioned));
  box.follow = (img) => img.addEventListener("mousemove", (event) => {
    const bounds = img.getBoundingClientRect();
    const x = Math.round(((event.clientX - bounds.left) / bounds.width) * report.width - region.width / 2);
    const y = Math.round(((event.clientY - bounds.top) / bounds.height) * report.height - region.height / 2);
    paint(Math.max(0, Math.min(report.width - region.width, x)), Math.max(0, Math.min(report.height - region.height, y)));
  });
  return box;
}

// The report into `target`: `picture(name)` the address of each picture ("yours", "exact", "difference",
// and "mistake" where report.mistake_picture names one), `closing` its last line.
export function showReport(target, report, picture, closing) {
  const verdict = el("p", { id: "verdict", class: `verdict ${report.matches ? "matches" : "differs"}`, "data-verdict": report.verdict, text: verdictLine(report) });
  const against = `${report.width} x ${report.height} against ${report.scene_title}${report.scene_chosen_by_server ? " (the closest figure)" : ""}`;
  const bar = el("div", { class: "colour-bar" }, el("span", { text: "0" }), el("span", { class: "ramp" }), el("span", { text: `${report.difference_scale} levels` }));
  const pictures = el("div", { class: "pictures" }, figure(picture, "yours", "yours"), figure(picture, "exact", "exact"), figure(picture, "difference", "|yours - exact|, the largest channel's difference", bar));
  if (report.mistake_picture) pictures.append(figure(picture, "mistake", `the exact image with ${report.mistake_picture}`));
  const zoom = magnifier(report, picture);
  target.replaceChildren(
    verdict,
    el("p", { class: "muted", text: against }),
    mistakes(report),
    el("h2", { text: "Pictures" }), pictures, zoom,
    el("h2", { text: "Differences, in 8-bit levels" }), statistics(report),
    el("p", { class: "muted", text: closing }));
  zoom.follow(pictures.querySelector("img"));
}

// The server's report page: the report of the address's id.
async function loadReport() {
  const $ = (id) => document.getElementById(id);
  const id = location.pathname.split("/").pop();
  let report;
  try {
    report = await getJson(`/api/reports/${id}`);
  } catch (error) {
    $("status").textContent = "";
    $("error").textContent = error.message;
    return;
  }
  const minutes = Math.round(report.expires_in_seconds / 60);
  showReport($("report"), report, (name) => `/api/reports/${id}/${name}.png`, `This report and your image are kept ${minutes} minutes at this address, then forgotten.`);
}

if (document.body.dataset.page === "report") loadReport();
