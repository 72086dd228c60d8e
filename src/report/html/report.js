// The run report's script (src/report/html.rs): rebuilds every cycle's state from the
// changes-only records, shows one cycle at a time, and steps with keys, clicks and the URL
// fragment. No library, no network.
"use strict";
const data = JSON.parse(document.getElementById("r-data").textContent);
const cycles = data.cycles;
const names = data.components.map(c => c.name);

// A field absent from a record means "as before": carry the last value forward.
function carried(field) {
  const out = [];
  let last = null;
  for (const c of cycles) {
    if (c[field] !== undefined) last = c[field];
    out.push(last);
  }
  return out;
}
const estimate = carried("estimate");
const belief = carried("belief");
const goals = carried("goals");
const marking = carried("marking");
const observation = carried("observation");
const hasEvents = c => (c.events && c.events.length) || (c.plant && c.plant.length);
const eventful = cycles.map((c, i) => hasEvents(c) ? i : -1).filter(i => i >= 0);
const diagnoses = cycles
  .map((c, i) => (c.events || []).some(e => e.kind === "Diagnosis") ? i : -1)
  .filter(i => i >= 0);

function clock(t) {
  const s = Math.floor(t), h = Math.floor(s / 3600), m = Math.floor(s / 60) % 60;
  return `${h}:${String(m).padStart(2, "0")}:${String(s % 60).padStart(2, "0")}`;
}
function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (cls) e.className = cls;
  return e;
}
function list(id, items, cls) {
  const ul = document.getElementById(id);
  ul.replaceChildren();
  for (const item of items) ul.appendChild(el("li", item.text ?? item, item.cls ?? cls));
  if (!items.length) ul.appendChild(el("li", "none", "none"));
}
function modeOf(component, name) {
  return data.components[component].modes.find(m => m.name === name);
}

// Marginals over the tracked states: each component's modes weighted by the states' p.
function marginals(states) {
  const total = states.reduce((s, x) => s + x.p, 0) || 1;
  return names.map(name => {
    const p = {};
    for (const s of states) p[s.modes[name]] = (p[s.modes[name]] || 0) + s.p / total;
    return Object.entries(p).sort((a, b) => b[1] - a[1]);
  });
}

function showBelief(i) {
  const states = belief[i] || [];
  const table = document.getElementById("r-states");
  table.replaceChildren();
  states.forEach((s, k) => {
    const row = table.insertRow();
    row.appendChild(el("td", s.p.toFixed(4), "p"));
    const differs = k === 0 ? [] : names.filter(n => s.modes[n] !== states[0].modes[n]);
    const text = k === 0 ? "most likely state (the schematic)" :
      differs.map(n => `${n} = ${s.modes[n]}`).join(", ");
    const shown = k === 0 ? names : differs;
    const faulty = shown.some(n => (modeOf(names.indexOf(n), s.modes[n]) || {}).fault);
    row.appendChild(el("td", text, faulty ? "fault" : undefined));
  });
  const table2 = document.getElementById("r-marginals");
  table2.replaceChildren();
  marginals(states).forEach((modes, c) => {
    const row = table2.insertRow();
    row.id = `marginal-${names[c]}`;
    row.appendChild(el("td", names[c]));
    const [top, p] = modes[0] || ["?", 0];
    const mode = modeOf(c, top);
    row.appendChild(el("td", top, mode && mode.fault ? "fault" : undefined));
    row.appendChild(el("td", p.toFixed(3), "p"));
    const bar = el("span", undefined, "bar");
    bar.style.width = `${Math.round(60 * p)}px`;
    const cell = row.insertCell();
    cell.appendChild(bar);
    const rest = modes.slice(1).filter(m => m[1] >= 0.001).map(m => `${m[0]} ${m[1].toFixed(3)}`);
    if (rest.length) cell.appendChild(el("span", " " + rest.join(", ")));
  });
}

function showSchematic(i) {
  const modes = estimate[i] || {};
  names.forEach((name, k) => {
    const node = document.getElementById(`schematic-node-${k}`);
    if (!node) return;
    const mode = modeOf(k, modes[name]);
    node.querySelector("rect").style.fill = mode ? mode.colour : "#ffffff";
    node.classList.toggle("fault", !!(mode && mode.fault));
    document.getElementById(`schematic-mode-${k}`).textContent = modes[name] || "?";
  });
}

let cursor = null;
function showCursor(i) {
  const svg = document.querySelector("#timeline > svg");
  if (!svg) return;
  if (!cursor) {
    cursor = document.createElementNS("http://www.w3.org/2000/svg", "line");
    cursor.setAttribute("class", "cursor");
    svg.appendChild(cursor);
  }
  const x = data.x[i];
  const h = svg.viewBox.baseVal.height || 2000;
  for (const [k, v] of [["x1", x], ["x2", x], ["y1", 0], ["y2", 100000 + h]]) cursor.setAttribute(k, v);
}

let current = 0;
function show(i) {
  current = Math.max(0, Math.min(cycles.length - 1, i));
  const c = cycles[current];
  if (!c) return;
  document.getElementById("r-cycle").textContent =
    `Cycle ${c.cycle} · t = ${clock(c.time)} (${c.time} s) · ${current + 1} of ${cycles.length}`;
  showBelief(current);
  showSchematic(current);
  list("r-goals", goals[current] || []);
  list("r-marking", marking[current] || []);
  const events = c.events || [];
  const why = events.filter(e => e.kind === "CommandIssued" || e.kind === "Waiting")
    .map(e => `${e.kind === "Waiting" ? "waiting: " : ""}${e.text}`);
  list("r-commands", (c.command || []).map(a => `μ: ${a}`).concat(why));
  list("r-events", events.map(e => ({ text: `${e.kind}: ${e.text}`, cls: e.kind })));
  list("r-plant", (c.plant || []).map(p => ({
    text: `${p.rule} (${p.kind}${p.fault ? ", injected fault" : ""})`, cls: p.fault ? "fault" : undefined })));
  list("r-observation", (observation[current] || []).map(o => `${o.variable} = ${JSON.stringify(o.value)}`));
  showCursor(current);
}

function after(indices, i) { return indices.find(k => k > i); }
function before(indices, i) { return [...indices].reverse().find(k => k < i); }
function key(name) {
  const moves = {
    ArrowRight: () => after(eventful, current), n: () => after(eventful, current),
    ArrowLeft: () => before(eventful, current), p: () => before(eventful, current),
    ArrowDown: () => current + 1, j: () => current + 1,
    ArrowUp: () => current - 1, k: () => current - 1,
    f: () => after(diagnoses, current),
    Home: () => 0, End: () => cycles.length - 1,
  };
  const move = moves[name];
  if (!move) return false;
  const next = move();
  if (next !== undefined) show(next);
  return true;
}
document.addEventListener("keydown", e => { if (key(e.key)) e.preventDefault(); });

// The timeline: wheel zooms around the pointer, drag pans, click goes to the nearest cycle.
(function timeline() {
  const svg = document.querySelector("#timeline > svg");
  if (!svg) return;
  const full = svg.viewBox.baseVal;
  const home = [full.x, full.y, full.width, full.height];
  let view = home.slice();
  const apply = () => svg.setAttribute("viewBox", view.join(" "));
  const toSvg = e => {
    const p = svg.createSVGPoint();
    p.x = e.clientX; p.y = e.clientY;
    return p.matrixTransform(svg.getScreenCTM().inverse());
  };
  svg.addEventListener("wheel", e => {
    e.preventDefault();
    const at = toSvg(e), f = e.deltaY < 0 ? 0.8 : 1.25;
    const w = Math.min(home[2], Math.max(50, view[2] * f));
    view[0] = Math.max(home[0], Math.min(home[0] + home[2] - w, at.x - (at.x - view[0]) * w / view[2]));
    view[2] = w;
    apply();
  }, { passive: false });
  let drag = null;
  svg.addEventListener("mousedown", e => { drag = { x: e.clientX, view0: view[0], moved: false }; });
  window.addEventListener("mousemove", e => {
    if (!drag) return;
    const dx = (e.clientX - drag.x) * view[2] / svg.clientWidth;
    if (Math.abs(e.clientX - drag.x) > 3) drag.moved = true;
    view[0] = Math.max(home[0], Math.min(home[0] + home[2] - view[2], drag.view0 - dx));
    apply();
  });
  window.addEventListener("mouseup", e => {
    if (drag && !drag.moved) {
      const x = toSvg(e).x;
      let best = 0;
      data.x.forEach((cx, i) => { if (Math.abs(cx - x) < Math.abs(data.x[best] - x)) best = i; });
      show(best);
    }
    drag = null;
  });
  svg.addEventListener("dblclick", () => { view = home.slice(); apply(); });
})();

(function verdicts() {
  const box = document.getElementById("r-verdicts");
  for (const v of data.verdicts) box.appendChild(el("span", v.label, `verdict ${v.holds ? "ok" : "failed"}`));
})();

// The fragment: `#cycle=N` goes to a cycle, `#keys=f,n` plays keys as if pressed.
function fromFragment() {
  const params = new URLSearchParams(location.hash.slice(1));
  if (params.has("r-cycle")) show(Number(params.get("r-cycle")) || 0);
  for (const name of (params.get("keys") || "").split(",").filter(Boolean)) {
    document.dispatchEvent(new KeyboardEvent("keydown", { key: name }));
  }
}
show(0);
fromFragment();
window.addEventListener("hashchange", fromFragment);
