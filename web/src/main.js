// The workbench page of `plcc serve` (docs/workbench.md).
import uPlot from "uplot";
import "uplot/dist/uPlot.min.css";
import "./style.css";
import { Diagram, show } from "./diagram.js";
import { LadderEdit, STANDARD_BLOCKS } from "./ldedit.js";

const $ = (id) => document.getElementById(id);

// The server's token (`plcc serve --token-file`), kept for this tab only: sent with
// every call once the user has given it.
const TOKEN_KEY = "plcc-token";

async function api(path, opts = {}) {
  const token = sessionStorage.getItem(TOKEN_KEY);
  if (token) opts = { ...opts, headers: { ...(opts.headers || {}), Authorization: `Bearer ${token}` } };
  const r = await fetch(path, opts);
  const body = await r.json().catch(() => ({ error: `${r.status} ${r.statusText}` }));
  if (r.status === 401) {
    askToken(!!token);
    throw new Error(token ? "the server refused the token: enter it again, then repeat" : "this server needs its token for that: enter it above, then repeat");
  }
  if (!r.ok) throw new Error(body.error || `${r.status}`);
  return body;
}

function askToken(wrong) {
  const form = $("token-form");
  form.hidden = false;
  form.classList.toggle("bad", wrong);
  $("token-input").value = "";
  $("token-input").focus();
}

function tokenGiven(e) {
  e.preventDefault();
  const t = $("token-input").value.trim();
  if (!t) return;
  sessionStorage.setItem(TOKEN_KEY, t);
  $("token-input").value = "";
  $("token-form").hidden = true;
  flash("token set: writes, forces and control calls now carry it");
}

const state = {
  project: null,
  vars: new Map(), // lower-case path -> {path, type}
  values: {}, // lower-case path -> value
  forced: new Set(), // lower-case paths forced from this page
  watch: [], // {path, type, trend}
  diagram: null,
  view: null, // {kind: "diagram"|"editor", pou, file}
  stream: null,
  streamKey: "",
};

function h(tag, attrs = {}, ...kids) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? "" : v);
  }
  for (const k of kids.flat()) if (k !== null && k !== undefined) e.append(k);
  return e;
}

// ---------------------------------------------------------------- project tree

function treeGroup(label, items, open = true) {
  const ul = h("ul", { role: "group" }, items);
  const head = h("button", { class: "tree-head", "aria-expanded": String(open) }, label);
  const li = h("li", { role: "treeitem", "aria-expanded": String(open), class: open ? "open" : "" }, head, ul);
  head.addEventListener("click", () => {
    const o = !li.classList.contains("open");
    li.classList.toggle("open", o);
    head.setAttribute("aria-expanded", String(o));
    li.setAttribute("aria-expanded", String(o));
  });
  return li;
}

function treeLeaf(label, badge, action, title) {
  return h(
    "li",
    { role: "treeitem" },
    h("button", { class: "tree-leaf", onclick: action, title: title || label, "aria-label": title || label }, h("span", { class: "leaf-name" }, label), badge ? h("span", { class: `badge b-${badge}` }, badge) : null)
  );
}

function renderTree() {
  const p = state.project;
  const kinds = [
    ["program", "Programs"],
    ["functionBlock", "Function blocks"],
    ["function", "Functions"],
  ];
  const groups = [];
  for (const [k, label] of kinds) {
    const pous = p.pous.filter((x) => x.kind === k);
    if (pous.length) groups.push(treeGroup(label, pous.map((x) => treeLeaf(x.name, x.lang, () => openPou(x), `${label.replace(/s$/, "")} ${x.name}, ${x.lang}`))));
  }
  if (p.types.length) groups.push(treeGroup("Data types", p.types.map((t) => treeLeaf(t.name, null, () => openFile(t.file), `data type ${t.name}`))));
  for (const c of p.configurations) {
    const res = c.resources.map((r) =>
      treeGroup(`Resource ${r.name}`, [
        ...r.tasks.map((t) =>
          treeLeaf(`${t.name}`, "task", () => openFile(c.file), `task ${t.name}, ${Object.entries(t.props).map(([k, v]) => `${k} ${v}`).join(", ")}`)
        ),
        ...r.programs.map((i) =>
          treeLeaf(`${i.name} : ${i.type}`, null, () => {
            const pou = p.pous.find((x) => x.name.toLowerCase() === i.type.toLowerCase());
            if (pou) openPou(pou);
          }, `program instance ${i.name} of ${i.type}${i.task ? " in task " + i.task : ""}`)
        ),
      ])
    );
    groups.push(treeGroup(`Configuration ${c.name}`, res));
  }
  groups.push(treeGroup("Files", p.files.map((f, i) => treeLeaf(f.name.split("/").pop(), f.lang.toUpperCase(), () => openFile(i), `file ${f.name}`)), false));
  $("tree").replaceChildren(h("ul", { class: "tree" }, groups));
}

// ------------------------------------------------------------------- diagrams

function instanceOf(pouName) {
  const i = state.project.instances.find((x) => x.pou.toLowerCase() === pouName.toLowerCase());
  return i ? i.name : null;
}

function pathFinder(pouName) {
  const inst = instanceOf(pouName);
  return (name) => {
    const n = name.trim().toLowerCase();
    for (const c of inst ? [`${inst.toLowerCase()}.${n}`, n] : [n]) {
      const v = state.vars.get(c);
      if (v) return v.path;
    }
    return null;
  };
}

async function openPou(pou) {
  if (!pou.graphical) return openFile(pou.file, pou.from);
  $("view-title").textContent = `${pou.name} — ${pou.lang}`;
  state.edit = null;
  const model = await api(`/api/diagram/${encodeURIComponent(pou.name)}`);
  const text = (await api(`/api/files/${model.file}`)).text;
  state.view = { kind: "diagram", pou: pou.name, file: model.file, lang: model.lang, text };
  showPane("diagram");
  $("ld-tools").hidden = model.lang !== "LD";
  setEditing(false);
  await renderDiagram(model, text);
}

/// The rung checks of a PLCopen text, by element, for POU `pou`.
async function rungChecks(text, pou) {
  const problems = new Map();
  const f = state.project.files[state.view.file];
  const r = await api(`/api/check?file=${encodeURIComponent(f.name)}`, { method: "POST", body: text });
  for (const d of r.diagnostics) {
    const m = d.message.match(/localId (\d+)/);
    if (m && d.message.toLowerCase().includes(`\`${pou.toLowerCase()}\``)) {
      const id = Number(m[1]);
      if (!problems.has(id)) problems.set(id, []);
      problems.get(id).push(d);
    }
  }
  return { problems, r };
}

async function renderDiagram(model, text, select) {
  let problems = new Map();
  let summary = "";
  // The keyboard stays on the diagram when it is drawn again (after an undo).
  const hadFocus = $("diagram").contains(document.activeElement);
  try {
    const c = await rungChecks(text, model.pou);
    problems = c.problems;
    const first = c.r.diagnostics[0];
    summary = c.r.errors ? `${c.r.errors} error(s)` : `${c.r.diagnostics.length} warning(s)`;
    if (first) summary += ` — ${first.code}: ${first.message}`;
  } catch (e) {
    summary = e.message;
  }
  state.diagram = new Diagram($("diagram"), model, {
    pathOf: pathFinder(model.pou),
    onSelect: (e) => {
      state.selected = e.id;
      inspect(e);
    },
    problems,
  });
  state.diagram.update(state.values, state.forced);
  flash(`${model.elements.length} elements · ${summary}`, summary.includes("error"));
  const n = select != null ? state.diagram.nodes.get(Number(select)) : null;
  if (n) state.diagram.select(n);
  else if (hadFocus) $("diagram").querySelector(".el[tabindex]")?.focus();
  resubscribe();
}

// ------------------------------------------------------------ ladder editing

function setEditing(on) {
  $("ld-tools").classList.toggle("editing", on);
  $("ld-edit").setAttribute("aria-pressed", String(on));
  $("diagram").classList.toggle("editing", on);
  if (on && !state.edit) {
    // The functions and function blocks of the project's other files, with their
    // pins, can go into a rung too.
    const external = state.project.pous
      .filter((p) => p.pins && p.file !== state.view.file)
      .map((p) => ({ name: p.name, kind: p.kind, inputs: p.pins.inputs, outputs: p.pins.outputs, result: p.pins.result }));
    state.edit = new LadderEdit(state.view.text, state.view.pou, external);
    // The block types: the standard FBs and functions, then the project's own.
    const list = $("ld-block-types");
    list.replaceChildren(...STANDARD_BLOCKS.map((n) => h("option", { value: n })), ...state.edit.userBlocks().map((n) => h("option", { value: n, class: "user" })));
  }
}

async function editOp(op) {
  const ed = state.edit;
  if (!ed) return;
  const sel = state.selected;
  let next = sel;
  try {
    switch (op) {
      case "contact":
        next = ed.insertAfter(sel, "contact");
        break;
      case "coil":
        next = ed.insertAfter(sel, "coil");
        break;
      case "branch":
        next = ed.addBranch(sel);
        break;
      case "rung":
        next = ed.addRung();
        break;
      case "block":
        next = ed.insertBlock(sel, $("ld-block").value.trim());
        break;
      case "output":
        next = ed.addOutput(sel);
        break;
      case "cycle":
        ed.cycle(sel);
        break;
      case "delete":
        next = ed.remove(sel);
        break;
      case "undo":
        if (!ed.undo()) return flash("nothing to undo");
        break;
      case "redo":
        if (!ed.redo()) return flash("nothing to redo");
        break;
      case "var":
        ed.setVariable(sel, $("ld-var").value);
        break;
      case "save":
        return saveXml();
      case "apply":
        return applyXml();
    }
  } catch (e) {
    return flash(e.message, true);
  }
  await redraw(next);
}

/// The edited text drawn again, with element `select` selected.
async function redraw(select) {
  const text = state.edit.text();
  state.view.text = text;
  const model = await api(`/api/diagram/${encodeURIComponent(state.view.pou)}`, { method: "POST", body: text });
  await renderDiagram(model, text, select);
}

/// Moves the selected element by (dx, dy).
async function moveSelected(dx, dy) {
  try {
    state.edit.move(state.selected, dx, dy);
  } catch (e) {
    return flash(e.message, true);
  }
  await redraw(state.selected);
}

/// Dragging an element with the mouse while editing moves it (on the grid) when
/// the button is let go.
function dragToMove(svgHost) {
  let drag = null;
  svgHost.addEventListener("pointerdown", (ev) => {
    if (!state.edit || !$("ld-tools").classList.contains("editing") || ev.button !== 0) return;
    const g = ev.target.closest(".el");
    const node = g && [...state.diagram.nodes.entries()].find(([, n]) => n.g === g);
    if (!node || /PowerRail$/.test(node[1].e.kind)) return;
    const svg = g.ownerSVGElement;
    drag = { id: node[0], g, svg, x: ev.clientX, y: ev.clientY, moved: false };
    g.setPointerCapture?.(ev.pointerId);
  });
  const scale = (d) => {
    const m = d.svg.getScreenCTM();
    return m && m.a ? 1 / m.a : 1;
  };
  svgHost.addEventListener("pointermove", (ev) => {
    if (!drag) return;
    const k = scale(drag);
    const dx = (ev.clientX - drag.x) * k, dy = (ev.clientY - drag.y) * k;
    if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
    if (drag.moved) drag.g.setAttribute("transform", `translate(${dx},${dy})`);
  });
  const end = async (ev) => {
    const d = drag;
    drag = null;
    if (!d || !d.moved) return;
    const k = scale(d);
    state.selected = d.id;
    await moveSelected((ev.clientX - d.x) * k, (ev.clientY - d.y) * k);
  };
  svgHost.addEventListener("pointerup", end);
  svgHost.addEventListener("pointercancel", () => {
    drag?.g.removeAttribute("transform");
    drag = null;
  });
}

/// Downloads `text` under the name of the project's file `index`.
function download(index, text, type) {
  const name = state.project.files[index].name.split("/").pop();
  const a = h("a", { href: URL.createObjectURL(new Blob([text], { type })), download: name });
  document.body.append(a);
  a.click();
  a.remove();
  flash(`saved as ${name}`);
}

function saveXml() {
  const text = state.edit ? state.edit.text() : state.view.text;
  download(state.view.file, text, "application/xml");
  state.saved = text;
}

/// Loads the project with `text` in place of its file `index` into the running PLC
/// (an online change); the project tree follows.
async function apply(index, text) {
  const name = state.project.files[index].name;
  try {
    const r = await api(`/api/program?file=${encodeURIComponent(name)}`, { method: "POST", body: text });
    flash(`loaded into the PLC: ${r.kept} variable(s) kept`);
  } catch (e) {
    flash(e.message.split("\n")[0], true);
    return;
  }
  const [project, vars] = await Promise.all([api("/api/project"), api("/api/vars")]);
  state.project = project;
  state.vars.clear();
  for (const v of vars) state.vars.set(v.path.toLowerCase(), v);
  $("var-list").replaceChildren(...vars.map((v) => h("option", { value: v.path })));
  renderTree();
}

function applyXml() {
  return apply(state.view.file, state.edit ? state.edit.text() : state.view.text);
}

const EDIT_KEYS = { c: "contact", o: "coil", b: "branch", r: "rung", k: "cycle", l: "block", u: "output", Delete: "delete" };
const MOVES = { ArrowLeft: [-10, 0], ArrowRight: [10, 0], ArrowUp: [0, -10], ArrowDown: [0, 10] };

function editKeys(ev) {
  if (!state.edit || !$("ld-tools").classList.contains("editing")) return;
  if (ev.target.closest && ev.target.closest("input, form")) return;
  if ((ev.ctrlKey || ev.metaKey) && (ev.key === "y" || (ev.key.toLowerCase() === "z" && ev.shiftKey))) {
    ev.preventDefault();
    return editOp("redo");
  }
  if ((ev.ctrlKey || ev.metaKey) && ev.key === "z") {
    ev.preventDefault();
    return editOp("undo");
  }
  if (ev.key === "v") {
    ev.preventDefault();
    return $("ld-var").focus();
  }
  // Shift+arrow moves the selected element a grid step.
  if (ev.shiftKey && MOVES[ev.key] && state.selected != null) {
    ev.preventDefault();
    ev.stopPropagation();
    return moveSelected(...MOVES[ev.key]);
  }
  const op = !ev.ctrlKey && !ev.altKey && EDIT_KEYS[ev.key];
  if (op) {
    ev.preventDefault();
    editOp(op);
  }
}

function inspect(e) {
  if (state.edit) $("ld-var").value = e.text || "";
  const box = $("inspector");
  const names = [];
  if (e.text && (e.kind === "contact" || e.kind === "coil" || /Variable$/.test(e.kind))) names.push(e.text);
  if (e.kind === "block" && e.instanceName) for (const o of e.outs) names.push(`${e.instanceName}.${o.name}`);
  const pathOf = pathFinder(state.view.pou);
  const rows = names
    .map((n) => pathOf(n))
    .filter(Boolean)
    .map((p) => {
      const v = state.vars.get(p.toLowerCase());
      const bool = v.type === "BOOL";
      const input = bool ? null : h("input", { class: "force-value", "aria-label": `value to force ${p} to`, size: 8 });
      return h(
        "div",
        { class: "insp-row" },
        h("code", {}, p),
        h("span", { class: "insp-value", "data-path": p.toLowerCase() }, show(state.values[p.toLowerCase()])),
        bool ? h("button", { onclick: () => force(p, true), "aria-label": `Force ${p} TRUE` }, "Force TRUE") : input,
        bool ? h("button", { onclick: () => force(p, false), "aria-label": `Force ${p} FALSE` }, "Force FALSE") : h("button", { onclick: () => force(p, parseValue(input.value, v.type)), "aria-label": `Force ${p}` }, "Force"),
        h("button", { onclick: () => unforce(p), "aria-label": `Unforce ${p}` }, "Unforce"),
        h("button", { onclick: () => addWatch(p), "aria-label": `Watch ${p}` }, "Watch")
      );
    });
  box.replaceChildren(h("strong", {}, e.kind === "block" ? `${e.typeName} ${e.instanceName || ""}` : `${e.kind} ${e.text || e.name || ""}`), ...rows);
  box.hidden = false;
}

// --------------------------------------------------------------------- editor

let editor = null;

/// The diagnostics of a file's text as the editor shows them.
async function check(fileName, text, len) {
  let r;
  try {
    r = await api(`/api/check?file=${encodeURIComponent(fileName)}`, { method: "POST", body: text });
  } catch (e) {
    $("view-info").textContent = e.message;
    return [];
  }
  const first = r.diagnostics.find((d) => d.here) || r.diagnostics[0];
  $("view-info").textContent =
    (r.ok ? `checked: no errors, ${r.diagnostics.length} warning(s)` : `checked: ${r.errors} error(s)`) +
    (first ? ` — ${first.code}${first.line ? " line " + first.line : ""}: ${first.message}` : "");
  return r.diagnostics
    .filter((d) => d.here)
    .map((d) => ({
      from: Math.min(d.from, len),
      to: Math.min(Math.max(d.to, d.from), len),
      severity: d.severity,
      message: `${d.code}: ${d.message}${d.label ? " (" + d.label + ")" : ""}${d.notes.length ? "\n" + d.notes.join("\n") : ""}`,
    }));
}

async function openFile(index, at) {
  const [f, cm] = await Promise.all([api(`/api/files/${index}`), import("/assets/editor.js")]);
  $("view-title").textContent = f.name;
  showPane("editor");
  state.view = { kind: "editor", file: index };
  state.diagram = null;
  editor = cm.show(editor, $("editor"), f.text, f.lang, (text, len) => check(f.name, text, len), at);
  resubscribe();
}

/// The editor's Save (download) and Apply (online change) buttons.
function editorOp(op) {
  if (!editor || state.view?.kind !== "editor") return;
  const text = editor.state.doc.toString();
  const f = state.project.files[state.view.file];
  if (op === "save") return download(state.view.file, text, f.lang === "xml" ? "application/xml" : "text/plain");
  if (op === "apply") return apply(state.view.file, text);
}

function showPane(which) {
  $("diagram").hidden = which !== "diagram";
  if (which !== "diagram") $("ld-tools").hidden = true;
  $("ed-tools").hidden = which !== "editor";
  $("editor").hidden = which !== "editor";
  $("inspector").hidden = true;
}

// ---------------------------------------------------------- values and forces

function parseValue(s, type) {
  s = s.trim();
  if (type === "BOOL") return /^(true|1)$/i.test(s);
  if (/^(TIME|LTIME|DATE|TOD|DT|TIME_OF_DAY|DATE_AND_TIME|STRING|WSTRING)/.test(type)) return s;
  const n = Number(s);
  return Number.isNaN(n) ? s : n;
}

async function force(path, value) {
  try {
    await api(`/api/force/${encodeURIComponent(path)}`, { method: "POST", body: JSON.stringify({ value }) });
    state.forced.add(path.toLowerCase());
    flash(`${path} forced to ${show(value)}`);
  } catch (e) {
    flash(e.message, true);
  }
  renderValues();
  pollStatus();
}

async function unforce(path) {
  try {
    await api(`/api/force/${encodeURIComponent(path)}`, { method: "DELETE" });
    state.forced.delete(path.toLowerCase());
    flash(`${path} released`);
  } catch (e) {
    flash(e.message, true);
  }
  renderValues();
  pollStatus();
}

function flash(msg, bad) {
  const s = $("view-info");
  s.textContent = msg;
  s.classList.toggle("bad", !!bad);
}

function resubscribe() {
  const paths = new Set(state.watch.map((w) => w.path));
  if (state.diagram) for (const p of state.diagram.variables()) paths.add(p);
  const key = [...paths].sort().join(",");
  if (key === state.streamKey) return;
  state.streamKey = key;
  if (state.stream) state.stream.close();
  state.stream = null;
  if (!paths.size) return;
  const es = new EventSource(`/api/stream?vars=${[...paths].map(encodeURIComponent).join(",")}`);
  es.onmessage = (ev) => {
    const d = JSON.parse(ev.data);
    for (const [k, v] of Object.entries(d.values)) state.values[k.toLowerCase()] = v;
    renderValues();
  };
  state.stream = es;
}

function renderValues() {
  if (state.diagram) state.diagram.update(state.values, state.forced);
  for (const w of state.watch) {
    const row = w.row;
    row.querySelector(".w-value").textContent = show(state.values[w.path.toLowerCase()]);
    row.classList.toggle("forced", state.forced.has(w.path.toLowerCase()));
  }
  for (const s of document.querySelectorAll(".insp-value")) s.textContent = show(state.values[s.dataset.path]);
}

// ---------------------------------------------------------------- watch table

function addWatch(name) {
  const v = state.vars.get(name.trim().toLowerCase());
  if (!v) return flash(`no variable \`${name}\`: GET /api/vars lists them`, true);
  if (state.watch.some((w) => w.path === v.path)) return;
  const w = { path: v.path, type: v.type, trend: v.type !== "STRING" && !/^(TIME|DATE|TOD|DT|STRING|WSTRING)/.test(v.type) };
  const input = h("input", { class: "force-value", size: 6, "aria-label": `value to force ${v.path} to`, placeholder: v.type === "BOOL" ? "TRUE" : "" });
  const trend = h("input", { type: "checkbox", "aria-label": `Trend ${v.path}`, class: "w-trend" });
  trend.checked = w.trend;
  trend.addEventListener("change", () => {
    w.trend = trend.checked;
    rebuildTrend();
  });
  w.row = h(
    "tr",
    { "data-path": v.path },
    h("th", { scope: "row" }, h("code", {}, v.path), h("small", {}, ` ${v.type}`)),
    h("td", { class: "w-value", "aria-live": "off" }, ""),
    h(
      "td",
      { class: "w-force" },
      input,
      h("button", { class: "w-force-btn", onclick: () => force(v.path, parseValue(input.value || (v.type === "BOOL" ? "TRUE" : "0"), v.type)), "aria-label": `Force ${v.path}` }, "F"),
      h("button", { onclick: () => unforce(v.path), "aria-label": `Unforce ${v.path}` }, "U")
    ),
    h("td", {}, trend),
    h("td", {}, h("button", { onclick: () => removeWatch(w), "aria-label": `Remove ${v.path} from the watch table` }, "×"))
  );
  state.watch.push(w);
  $("watch-body").append(w.row);
  rebuildTrend();
  resubscribe();
  renderValues();
}

function removeWatch(w) {
  state.watch = state.watch.filter((x) => x !== w);
  w.row.remove();
  rebuildTrend();
  resubscribe();
}

// ---------------------------------------------------------------------- trend

const trend = { plot: null, t: [], series: new Map(), t0: performance.now() };
const COLOURS = ["#0a7d32", "#1f6fd1", "#c2410c", "#7c3aed", "#be123c", "#0e7490"];
const POINTS = 300;

function numeric(v) {
  if (typeof v === "boolean") return v ? 1 : 0;
  return typeof v === "number" ? v : null;
}

function rebuildTrend() {
  const chosen = state.watch.filter((w) => w.trend).map((w) => w.path);
  for (const p of chosen) if (!trend.series.has(p)) trend.series.set(p, trend.t.map(() => null));
  for (const p of [...trend.series.keys()]) if (!chosen.includes(p)) trend.series.delete(p);
  const el = $("trend");
  if (trend.plot) trend.plot.destroy();
  trend.plot = null;
  el.replaceChildren();
  if (!chosen.length) {
    el.append(h("p", { class: "hint" }, "Tick Trend in the watch table to plot a variable."));
    return;
  }
  const width = Math.max(260, el.clientWidth || 300);
  trend.plot = new uPlot(
    {
      width,
      height: 200,
      legend: { show: true, live: false },
      cursor: { show: false },
      scales: { x: { time: false } },
      axes: [{ label: "s", size: 30 }, { size: 46 }],
      series: [{ label: "time (s)" }, ...chosen.map((p, i) => ({ label: p, stroke: COLOURS[i % COLOURS.length], width: 2, points: { show: false }, paths: uPlot.paths.stepped({ align: 1 }) }))],
    },
    [trend.t, ...chosen.map((p) => trend.series.get(p))],
    el
  );
}

function sampleTrend() {
  if (!trend.series.size) return;
  trend.t.push((performance.now() - trend.t0) / 1000);
  for (const [p, arr] of trend.series) arr.push(numeric(state.values[p.toLowerCase()]));
  if (trend.t.length > POINTS) {
    trend.t.shift();
    for (const arr of trend.series.values()) arr.shift();
  }
  if (trend.plot) trend.plot.setData([trend.t, ...[...trend.series.keys()].map((p) => trend.series.get(p))]);
}

// --------------------------------------------------------------------- status

async function pollStatus() {
  try {
    const s = await api("/api/status");
    const st = $("state");
    st.textContent = s.state + (s.fault ? " · fault" : "");
    st.className = `state s-${s.state}`;
    const f = (x) => (x === null || x === undefined ? "–" : Math.round(x));
    $("status").replaceChildren(
      h("span", {}, `target ${s.target}`),
      h("span", {}, `cycle ${s.cycle_us / 1000} ms`),
      h("span", { id: "scans" }, `scans ${s.scans}`),
      h("span", {}, `exec ${f(s.exec_us.mean)}/${f(s.exec_us.max)} µs (mean/max)`),
      h("span", {}, `lateness p99 ${f(s.lateness_us.p99)} µs`),
      h("span", {}, `overruns ${s.overruns}`),
      h("span", {}, `forced ${s.forced}`),
      ...(s.error ? [h("span", { class: "bad" }, s.error)] : [])
    );
  } catch (e) {
    $("state").textContent = "disconnected";
    $("state").className = "state s-error";
  }
}

async function control(what) {
  try {
    await api(`/api/${what}`, { method: "POST" });
  } catch (e) {
    flash(e.message, true);
  }
  pollStatus();
}

// ---------------------------------------------------------------------- build

async function buildFor(target) {
  const out = $("build-out");
  out.replaceChildren(h("p", { class: "hint" }, `building for ${target}…`));
  let q = `target=${encodeURIComponent(target)}`;
  // The target's settings, as `-s` takes them: `pin.%IX0.0=RA2 mode=32`.
  for (const kv of $("build-settings").value.trim().split(/\s+/).filter(Boolean)) q += `&set=${encodeURIComponent(kv)}`;
  let body = "";
  if (state.edit) {
    q += `&file=${encodeURIComponent(state.project.files[state.view.file].name)}`;
    body = state.edit.text();
  }
  let r;
  try {
    r = await api(`/api/build?${q}`, { method: "POST", body });
  } catch (e) {
    return out.replaceChildren(h("pre", {}, e.message));
  }
  if (!r.ok) return out.replaceChildren(h("p", {}, `${target}: does not build`), h("pre", {}, r.errors));
  const links = r.files.map((f) => {
    const bytes = Uint8Array.from(atob(f.base64), (c) => c.charCodeAt(0));
    const url = URL.createObjectURL(new Blob([bytes], { type: "application/octet-stream" }));
    return h("li", {}, h("a", { href: url, download: f.name, "aria-label": `Download ${f.name}, ${f.size} bytes` }, f.name), h("small", {}, ` ${f.size} B`));
  });
  out.replaceChildren(
    h("p", { class: "summary" }, `${r.target}: ${r.summary || "built"}${r.warnings ? `, ${r.warnings} warning(s)` : ""}`),
    h("ul", { "aria-label": "Files built" }, links)
  );
}

// ----------------------------------------------------------------------- start

async function main() {
  $("btn-start").onclick = () => control("start");
  $("btn-stop").onclick = () => control("stop");
  $("btn-restart").onclick = () => control("restart?mode=cold");
  $("ld-edit").onclick = () => setEditing(!$("ld-tools").classList.contains("editing"));
  for (const b of document.querySelectorAll("#ld-tools [data-op]")) b.onclick = () => editOp(b.dataset.op);
  $("ld-block-form").addEventListener("submit", (e) => {
    e.preventDefault();
    editOp("block");
  });
  $("ld-var-form").addEventListener("submit", (e) => {
    e.preventDefault();
    editOp("var");
  });
  $("diagram").addEventListener("keydown", editKeys, true);
  dragToMove($("diagram"));
  $("build-form").addEventListener("submit", (e) => {
    e.preventDefault();
    buildFor($("build-target").value);
  });
  $("token-form").addEventListener("submit", tokenGiven);
  for (const b of document.querySelectorAll("#ed-tools [data-op]")) b.addEventListener("click", () => editorOp(b.dataset.op));
  $("watch-add").addEventListener("submit", (e) => {
    e.preventDefault();
    addWatch($("watch-input").value);
    $("watch-input").value = "";
  });
  const [project, vars] = await Promise.all([api("/api/project"), api("/api/vars")]);
  state.project = project;
  for (const v of vars) state.vars.set(v.path.toLowerCase(), v);
  $("var-list").replaceChildren(...vars.map((v) => h("option", { value: v.path })));
  renderTree();
  rebuildTrend();
  pollStatus();
  setInterval(pollStatus, 1000);
  setInterval(sampleTrend, 200);
  // The first graphical POU that runs, else the first POU.
  const running = project.pous.filter((p) => p.graphical && instanceOf(p.name));
  const first = running[0] || project.pous.find((p) => p.graphical) || project.pous[0];
  if (first) await openPou(first);
  document.body.dataset.ready = "true";
}

window.plccWorkbench = {
  state,
  trend: (path) => trend.series.get(path) || trend.series.get([...trend.series.keys()].find((k) => k.toLowerCase() === path.toLowerCase())) || [],
  editor: () => editor,
  ladder: () => state.edit,
  addWatch,
  force,
  unforce,
};

main().catch((e) => {
  $("view-info").textContent = `cannot load the project: ${e.message}`;
});
