// What every page of vk-render serve shares: the API's calls and small DOM helpers.
"use strict";

// A POST of JSON to the API; the answer as a Blob, or an Error with the server's one line.
async function postJson(path, body) {
  const response = await fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body),
  });
  if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
  return response;
}

async function getJson(path) {
  const response = await fetch(path);
  if (!response.ok) throw new Error((await response.text()).trim() || response.statusText);
  return response.json();
}

// An element with attributes and children (strings become text: nothing is parsed as HTML).
function el(tag, attributes, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes || {})) {
    if (key === "class") node.className = value;
    else if (key === "text") node.textContent = value;
    else node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

// A number shown to `digits` significant digits without trailing zeros.
function shown(value, digits = 3) {
  if (typeof value !== "number") return String(value);
  return Number(value.toPrecision(digits)).toString();
}
