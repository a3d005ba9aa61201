// The check page: an image dropped or chosen, posted to /api/check, then its report's page.
"use strict";

const $ = (id) => document.getElementById(id);
let chosen = null;

function choose(file) {
  chosen = file || null;
  $("chosen").textContent = chosen ? `${chosen.name} (${Math.round(chosen.size / 1024)} kB)` : "";
  $("submit").disabled = !chosen;
}

async function submit(event) {
  event.preventDefault();
  if (!chosen) return;
  const form = new FormData();
  form.append("image", chosen);
  const scene = $("scene").value;
  if (scene) form.append("scene", scene);
  $("submit").disabled = true;
  $("error").textContent = "";
  $("status").textContent = "checking: the exact image and every known mistake are rendered at your image's size...";
  try {
    const response = await fetch("/api/check", { method: "POST", body: form });
    if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
    const answer = await response.json();
    location.assign(answer.report);
  } catch (error) {
    $("status").textContent = "";
    $("error").textContent = error.message;
    $("submit").disabled = false;
  }
}

async function start() {
  if (SITE) return;  // a folder of vk-render site: no server to check with (the page says so)
  const drop = $("drop");
  drop.addEventListener("dragover", (event) => { event.preventDefault(); drop.classList.add("over"); });
  drop.addEventListener("dragleave", () => drop.classList.remove("over"));
  drop.addEventListener("drop", (event) => {
    event.preventDefault();
    drop.classList.remove("over");
    choose(event.dataTransfer.files[0]);
  });
  $("file").addEventListener("change", () => choose($("file").files[0]));
  $("form").addEventListener("submit", submit);
  try {
    const scenes = await getJson("/api/scenes");
    for (const scene of scenes) $("scene").append(el("option", { value: scene.id, text: scene.title }));
  } catch (error) {
    $("error").textContent = error.message;
  }
}

start();
