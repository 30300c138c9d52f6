// LD, FBD and SFC bodies drawn as SVG from the PLCopen model the server gives
// (GET /api/diagram/{pou}), with the power flow of ladder rungs lit from live values.

const SVG = "http://www.w3.org/2000/svg";

function el(tag, attrs = {}, parent) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) if (v !== undefined && v !== null) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

function text(parent, x, y, s, cls, anchor = "middle") {
  const t = el("text", { x, y, class: cls, "text-anchor": anchor }, parent);
  t.textContent = s;
  return t;
}

const KIND_NAMES = {
  leftPowerRail: "left power rail",
  rightPowerRail: "right power rail",
  contact: "contact",
  coil: "coil",
  block: "block",
  inVariable: "input variable",
  outVariable: "output variable",
  inOutVariable: "in-out variable",
  label: "label",
  jump: "jump",
  return: "return",
  connector: "connector",
  continuation: "continuation",
  comment: "comment",
  step: "step",
  transition: "transition",
  selectionDivergence: "selection divergence",
  selectionConvergence: "selection convergence",
  simultaneousDivergence: "simultaneous divergence",
  simultaneousConvergence: "simultaneous convergence",
  jumpStep: "jump to step",
  actionBlock: "action block",
};

/// What an element is, as a screen reader says it.
export function describe(e) {
  let s = KIND_NAMES[e.kind] || e.kind;
  if (e.kind === "contact") {
    s = (e.negated === "true" ? "normally closed " : "normally open ") + s;
    if (e.edge && e.edge !== "none") s = `${e.edge} edge ${s}`;
  }
  if (e.kind === "coil") {
    if (e.storage && e.storage !== "none") s = `${e.storage} ${s}`;
    if (e.negated === "true") s = `negated ${s}`;
  }
  if (e.kind === "block") return `block ${e.typeName}${e.instanceName ? " " + e.instanceName : ""}`;
  if (e.kind === "step") return `${e.initialStep === "true" ? "initial " : ""}step ${e.name}`;
  if (e.kind === "jumpStep") return `jump to step ${e.targetName}`;
  if (e.kind === "transition") return `transition ${e.condition ?? ""}`;
  if (e.kind === "label" || e.kind === "jump") return `${s} ${e.label}`;
  if (e.kind === "connector" || e.kind === "continuation") return `${s} ${e.name}`;
  if (e.text) s += ` ${e.text}`;
  return s;
}

/// A value as shown beside a variable.
export function show(v) {
  if (v === undefined || v === null) return "";
  if (typeof v === "boolean") return v ? "TRUE" : "FALSE";
  if (typeof v === "number" && !Number.isInteger(v)) return String(Math.round(v * 1000) / 1000);
  return String(v);
}

export class Diagram {
  /// model: the diagram's JSON; pathOf(name): the API path of a variable of the
  /// POU's instance, or null; onSelect(element): called when one is chosen.
  constructor(container, model, { pathOf, onSelect, problems }) {
    this.model = model;
    this.pathOf = pathOf;
    this.onSelect = onSelect;
    this.byId = new Map(model.elements.filter((e) => e.id != null).map((e) => [e.id, e]));
    this.nodes = new Map();
    this.wires = [];
    this.values = {};
    this.forced = new Set();
    let maxX = 200, maxY = 100;
    for (const e of model.elements) {
      maxX = Math.max(maxX, e.x + e.w + 120);
      maxY = Math.max(maxY, e.y + e.h + 40);
    }
    const svg = el("svg", {
      class: `diagram-svg lang-${model.lang}`,
      viewBox: `0 0 ${maxX} ${maxY}`,
      width: maxX * 1.45,
      style: `max-width: 100%; height: auto`,
      role: "group",
      "aria-label": `${model.lang} body of ${model.pou}`,
    });
    this.svg = svg;
    const wires = el("g", { class: "wires" }, svg);
    for (const e of model.elements) this.drawWires(wires, e);
    const elems = el("g", { class: "elements" }, svg);
    for (const e of model.elements) this.drawElement(elems, e, problems?.get(e.id));
    container.replaceChildren(svg);
    this.order = [...this.nodes.values()].sort((a, b) => a.e.y - b.e.y || a.e.x - b.e.x);
    svg.addEventListener("keydown", (ev) => this.key(ev));
  }

  /// The output point of element `id` named `param` (the first if none).
  outPoint(id, param) {
    const src = this.byId.get(id);
    if (!src || !src.outs.length) return null;
    if (param) {
      const o = src.outs.find((o) => o.name && o.name.toLowerCase() === param.toLowerCase());
      if (o) return o;
    }
    return src.outs.length === 1 || !param ? src.outs[0] : null;
  }

  drawWires(g, e) {
    e.ins.forEach((pin, index) => {
      for (const c of pin.conns || []) {
        let pts = c.points.map(([x, y]) => [x, y]);
        if (pts.length < 2) {
          const o = this.outPoint(c.from, c.param ?? (e.kind === "actionBlock" ? "action" : null));
          if (!o) continue;
          const mx = (o.x + pin.x) / 2;
          pts = [[pin.x, pin.y], [mx, pin.y], [mx, o.y], [o.x, o.y]];
        }
        const path = el("polyline", { class: "wire", points: pts.map((p) => p.join(",")).join(" ") }, g);
        this.wires.push({ path, from: c.from, param: c.param, to: e.id, index });
      }
    });
  }

  drawElement(parent, e, problems) {
    const g = el("g", {
      class: `el el-${e.kind}`,
      "data-id": e.id,
      "data-kind": e.kind,
      tabindex: "0",
      role: "button",
      "aria-label": describe(e),
    }, parent);
    if (e.text && (e.kind === "contact" || e.kind === "coil" || /Variable$/.test(e.kind))) g.setAttribute("data-var", e.text);
    const { x, y, w, h } = e;
    const my = y + h / 2;
    const node = { e, g, valueText: null, pinTexts: [] };
    switch (e.kind) {
      case "leftPowerRail":
      case "rightPowerRail":
        el("rect", { x, y, width: Math.max(w, 3), height: h, class: "rail" }, g);
        break;
      case "contact": {
        const l = x + 7, r = x + w - 7;
        el("line", { x1: x, y1: my, x2: l, y2: my, class: "stroke" }, g);
        el("line", { x1: r, y1: my, x2: x + w, y2: my, class: "stroke" }, g);
        el("rect", { x: l - 1, y, width: r - l + 2, height: h, class: "hit" }, g);
        el("line", { x1: l, y1: y, x2: l, y2: y + h, class: "bar" }, g);
        el("line", { x1: r, y1: y, x2: r, y2: y + h, class: "bar" }, g);
        if (e.negated === "true") el("line", { x1: r - 1, y1: y + 2, x2: l + 1, y2: y + h - 2, class: "stroke" }, g);
        if (e.edge && e.edge !== "none") text(g, x + w / 2, my + 4, e.edge === "rising" ? "P" : "N", "mark");
        node.name = text(g, x + w / 2, y - 4, e.text, "varname");
        node.valueText = text(g, x + w / 2, y + h + 10, "", "value");
        break;
      }
      case "coil": {
        el("rect", { x: x + 3, y, width: w - 6, height: h, class: "hit" }, g);
        el("line", { x1: x, y1: my, x2: x + 5, y2: my, class: "stroke" }, g);
        el("line", { x1: x + w - 5, y1: my, x2: x + w, y2: my, class: "stroke" }, g);
        el("path", { d: `M${x + 8},${y} A10,12 0 0,0 ${x + 8},${y + h}`, class: "bar" }, g);
        el("path", { d: `M${x + w - 8},${y} A10,12 0 0,1 ${x + w - 8},${y + h}`, class: "bar" }, g);
        const mark = e.storage === "set" ? "S" : e.storage === "reset" ? "R" : e.edge === "rising" ? "P" : e.edge === "falling" ? "N" : "";
        if (mark) text(g, x + w / 2, my + 4, mark, "mark");
        if (e.negated === "true") el("line", { x1: x + w - 7, y1: y + 3, x2: x + 7, y2: y + h - 3, class: "stroke" }, g);
        node.name = text(g, x + w / 2, y - 4, e.text, "varname");
        node.valueText = text(g, x + w / 2, y + h + 10, "", "value");
        break;
      }
      case "block": {
        el("rect", { x, y, width: w, height: h, rx: 2, class: "box" }, g);
        text(g, x + w / 2, y + 13, e.typeName, "type");
        if (e.instanceName) text(g, x + w / 2, y - 4, e.instanceName, "varname");
        for (const p of e.ins) {
          el("line", { x1: p.x - 6, y1: p.y, x2: p.x, y2: p.y, class: "stroke" }, g);
          if (p.name) text(g, p.x + 4, p.y + 4, p.name, "pin", "start");
          if (p.negated) el("circle", { cx: p.x - 3, cy: p.y, r: 3, class: "neg" }, g);
        }
        for (const p of e.outs) {
          el("line", { x1: p.x, y1: p.y, x2: p.x + 6, y2: p.y, class: "stroke" }, g);
          if (p.name) text(g, p.x - 4, p.y + 4, p.name, "pin", "end");
          node.pinTexts.push({ pin: p, t: text(g, p.x + 8, p.y - 3, "", "value", "start") });
        }
        break;
      }
      case "inVariable":
      case "outVariable":
      case "inOutVariable":
        el("rect", { x, y, width: w, height: h, rx: 8, class: "box var" }, g);
        node.name = text(g, x + w / 2, my + 4, e.text, "expr");
        node.valueText = text(g, x + w / 2, y + h + 10, "", "value");
        break;
      case "connector":
      case "continuation":
        el("path", { d: e.kind === "connector" ? `M${x},${y} H${x + w - 8} L${x + w},${my} L${x + w - 8},${y + h} H${x} Z` : `M${x},${y} H${x + w} V${y + h} H${x} L${x + 8},${my} Z`, class: "box" }, g);
        text(g, x + w / 2, my + 4, e.name, "expr");
        break;
      case "label":
        text(g, x, my + 4, `${e.label}:`, "expr", "start");
        break;
      case "jump":
        el("path", { d: `M${x},${my} H${x + 12} M${x + 6},${my - 5} L${x + 12},${my} L${x + 6},${my + 5}`, class: "stroke" }, g);
        text(g, x + 16, my + 4, e.label, "expr", "start");
        break;
      case "return":
        text(g, x, my + 4, "<RETURN>", "expr", "start");
        break;
      case "comment":
        el("rect", { x, y, width: w, height: h, class: "comment" }, g);
        text(g, x + 6, y + 14, e.text || "", "commenttext", "start");
        break;
      case "step":
        el("rect", { x, y, width: w, height: h, class: "box step" }, g);
        if (e.initialStep === "true") el("rect", { x: x + 3, y: y + 3, width: w - 6, height: h - 6, class: "box step" }, g);
        text(g, x + w / 2, my + 4, e.name, "expr");
        break;
      case "transition":
        el("line", { x1: x, y1: my, x2: x + w, y2: my, class: "bar" }, g);
        el("line", { x1: x + w / 2, y1: y - 4, x2: x + w / 2, y2: y + h + 4, class: "stroke" }, g);
        if (e.condition) text(g, x + w + 6, my + 4, e.condition, "expr", "start");
        break;
      case "selectionDivergence":
      case "selectionConvergence":
        el("line", { x1: x, y1: my, x2: x + w, y2: my, class: "stroke" }, g);
        break;
      case "simultaneousDivergence":
      case "simultaneousConvergence":
        el("line", { x1: x, y1: y, x2: x + w, y2: y, class: "stroke" }, g);
        el("line", { x1: x, y1: y + 3, x2: x + w, y2: y + 3, class: "stroke" }, g);
        break;
      case "jumpStep":
        el("path", { d: `M${x},${y} L${x + w},${y} L${x + w / 2},${y + h} Z`, class: "box" }, g);
        text(g, x + w + 4, my + 4, e.targetName, "expr", "start");
        break;
      case "actionBlock": {
        const rows = e.actions || [];
        const rh = rows.length ? h / rows.length : h;
        rows.forEach((a, i) => {
          el("rect", { x, y: y + i * rh, width: 24, height: rh, class: "box" }, g);
          el("rect", { x: x + 24, y: y + i * rh, width: w - 24, height: rh, class: "box" }, g);
          text(g, x + 12, y + i * rh + rh / 2 + 4, a.qualifier, "pin");
          text(g, x + 28, y + i * rh + rh / 2 + 4, a.text || "", "pin", "start");
        });
        break;
      }
      default:
        el("rect", { x, y, width: w, height: h, class: "box" }, g);
        text(g, x + w / 2, my + 4, e.kind, "expr");
    }
    if (problems && problems.length) {
      g.classList.add(problems.some((p) => p.severity === "error") ? "has-error" : "has-warning");
      el("rect", { x: x - 4, y: y - 4, width: w + 8, height: h + 8, class: "problem" }, g);
      const msg = problems.map((p) => `${p.code}: ${p.message}`).join("\n");
      el("title", {}, g).textContent = msg;
      g.setAttribute("aria-description", msg);
    }
    g.addEventListener("click", () => this.select(node));
    g.addEventListener("keydown", (ev) => {
      if (ev.key === "Enter" || ev.key === " ") {
        ev.preventDefault();
        this.select(node);
      }
    });
    this.nodes.set(e.id ?? `k${this.nodes.size}`, node);
  }

  select(node) {
    for (const n of this.nodes.values()) n.g.classList.toggle("selected", n === node);
    node.g.focus();
    this.onSelect?.(node.e);
  }

  /// Arrow keys move between elements: left and right along the rung, up and down
  /// to the nearest element above or below.
  key(ev) {
    const cur = [...this.nodes.values()].find((n) => n.g === document.activeElement);
    if (!cur || !["ArrowLeft", "ArrowRight", "ArrowUp", "ArrowDown", "Home", "End"].includes(ev.key)) return;
    ev.preventDefault();
    const c = { x: cur.e.x + cur.e.w / 2, y: cur.e.y + cur.e.h / 2 };
    let best = null, bestD = Infinity;
    if (ev.key === "Home" || ev.key === "End") {
      best = ev.key === "Home" ? this.order[0] : this.order[this.order.length - 1];
    } else {
      for (const n of this.nodes.values()) {
        if (n === cur) continue;
        const p = { x: n.e.x + n.e.w / 2, y: n.e.y + n.e.h / 2 };
        const dx = p.x - c.x, dy = p.y - c.y;
        const ok = { ArrowLeft: dx < -1, ArrowRight: dx > 1, ArrowUp: dy < -1, ArrowDown: dy > 1 }[ev.key];
        if (!ok) continue;
        const d = ev.key === "ArrowLeft" || ev.key === "ArrowRight" ? Math.abs(dx) + 3 * Math.abs(dy) : Math.abs(dy) + 3 * Math.abs(dx);
        if (d < bestD) (bestD = d), (best = n);
      }
    }
    if (best) best.g.focus();
  }

  /// The paths of the variables the diagram shows live.
  variables() {
    const out = new Set();
    for (const e of this.model.elements) {
      for (const p of this.elementPaths(e)) if (p) out.add(p);
    }
    return [...out];
  }

  elementPaths(e) {
    if (e.text && (e.kind === "contact" || e.kind === "coil" || /Variable$/.test(e.kind))) return [this.pathOf(e.text)];
    if (e.kind === "block" && e.instanceName) return e.outs.map((o) => this.pathOf(`${e.instanceName}.${o.name}`));
    if (e.kind === "step" && e.name) return [this.pathOf(`${e.name}.X`)];
    return [];
  }

  value(name) {
    const p = this.pathOf(name);
    return p ? this.values[p.toLowerCase()] : undefined;
  }

  /// The power (or boolean value) on output `param` of element `id`; undefined
  /// when unknown.
  power(id, param, seen = new Set()) {
    const key = `${id}/${param ?? ""}`;
    if (seen.has(key)) return undefined;
    seen.add(key);
    const e = this.byId.get(id);
    if (!e) return undefined;
    const input = (i = 0) => this.inPower(e, i, seen);
    switch (e.kind) {
      case "leftPowerRail":
        return true;
      case "contact": {
        const v = this.value(e.text);
        const pin = input();
        if (typeof v !== "boolean" || pin === undefined) return pin === false ? false : undefined;
        return pin && (e.negated === "true" ? !v : v);
      }
      case "coil":
        return input();
      case "inVariable": {
        if (/^true$/i.test(e.text)) return true;
        if (/^false$/i.test(e.text)) return false;
        const v = this.value(e.text);
        return typeof v === "boolean" ? (e.negated === "true" ? !v : v) : undefined;
      }
      case "block": {
        if (e.instanceName) {
          const o = param ? e.outs.find((o) => o.name?.toLowerCase() === param.toLowerCase()) : e.outs[0];
          const v = o ? this.value(`${e.instanceName}.${o.name}`) : undefined;
          if (typeof v === "boolean") return o.negated ? !v : v;
        }
        const en = e.ins.findIndex((p) => p.name?.toUpperCase() === "EN");
        if (en >= 0 && param && param.toUpperCase() === "ENO") return input(en);
        return undefined;
      }
      case "continuation": {
        const c = this.model.elements.find((x) => x.kind === "connector" && x.name?.toLowerCase() === e.name?.toLowerCase());
        return c ? this.inPower(c, 0, seen) : undefined;
      }
      default:
        return undefined;
    }
  }

  inPower(e, i, seen) {
    const pin = e.ins[i];
    if (!pin || !pin.conns?.length) return undefined;
    let any = false, unknown = false;
    for (const c of pin.conns) {
      const p = this.power(c.from, c.param, new Set(seen));
      if (p === true) any = true;
      else if (p === undefined) unknown = true;
    }
    return any ? true : unknown ? undefined : false;
  }

  /// Shows live values: values maps lower-case paths to JSON values.
  update(values, forced) {
    this.values = values;
    this.forced = forced || new Set();
    const ld = this.model.lang === "LD" || this.model.lang === "FBD";
    for (const w of this.wires) {
      const p = ld ? this.power(w.from, w.param) : undefined;
      w.path.classList.toggle("on", p === true);
    }
    for (const n of this.nodes.values()) {
      const e = n.e;
      const paths = this.elementPaths(e);
      const v = paths[0] ? values[paths[0].toLowerCase()] : undefined;
      let on = false;
      if (e.kind === "contact") on = ld && this.power(e.id) === true;
      else if (e.kind === "coil" || e.kind === "step") on = v === true;
      else if (e.kind === "leftPowerRail") on = true;
      n.g.classList.toggle("on", on);
      n.g.classList.toggle("forced", !!paths[0] && this.forced.has(paths[0].toLowerCase()));
      if (n.valueText) n.valueText.textContent = typeof v === "boolean" || v === undefined ? "" : show(v);
      n.pinTexts.forEach(({ pin, t }, k) => {
        const pv = paths[k] ? values[paths[k].toLowerCase()] : undefined;
        t.textContent = typeof pv === "boolean" ? "" : show(pv);
        t.parentNode && t.parentNode.classList.toggle(`pin-on-${k}`, pv === true);
      });
      const label = describe(e) + (v !== undefined ? `, ${show(v)}` : "") + (n.g.classList.contains("forced") ? ", forced" : "");
      n.g.setAttribute("aria-label", label);
    }
  }
}
