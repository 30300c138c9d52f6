// Editing a ladder body in its PLCopen XML: the document is changed in place, so
// everything else in the file (other POUs, types, configurations, what editors keep
// in addData) is saved as it was read. Each operation keeps the undo stack (and
// clears the redo stack).

const GRID = 10;

/// The standard function blocks the editor adds: the inputs (with a literal for
/// those that need a value) and the outputs with their types; the first input takes
/// the power, the first output carries it on.
const BLOCKS = {
  TON: [[["IN"], ["PT", "T#1s"]], [["Q", "BOOL"], ["ET", "TIME"]]],
  TOF: [[["IN"], ["PT", "T#1s"]], [["Q", "BOOL"], ["ET", "TIME"]]],
  TP: [[["IN"], ["PT", "T#1s"]], [["Q", "BOOL"], ["ET", "TIME"]]],
  CTU: [[["CU"], ["R", "FALSE"], ["PV", "10"]], [["Q", "BOOL"], ["CV", "INT"]]],
  CTD: [[["CD"], ["LD", "FALSE"], ["PV", "10"]], [["Q", "BOOL"], ["CV", "INT"]]],
  R_TRIG: [[["CLK"]], [["Q", "BOOL"]]],
  F_TRIG: [[["CLK"]], [["Q", "BOOL"]]],
  SR: [[["S1"], ["R", "FALSE"]], [["Q1", "BOOL"]]],
  RS: [[["S"], ["R1", "FALSE"]], [["Q1", "BOOL"]]],
};
/// The standard functions the editor adds, called with EN and ENO (IEC 61131-3,
/// 6.6.1.7: power into EN, the function runs only when it is TRUE): the inputs
/// with their literals, and the result's type. A comparison's BOOL result carries
/// the power on (FALSE when EN is FALSE); the others pass it on through ENO and
/// write their result to a new variable.
const FUNCS = {
  ADD: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  SUB: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  MUL: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  DIV: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  MOD: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  MAX: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  MIN: [[["IN1", "0"], ["IN2", "1"]], "INT"],
  LIMIT: [[["MN", "0"], ["IN", "0"], ["MX", "100"]], "INT"],
  MOVE: [[["IN", "0"]], "INT"],
  GT: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
  GE: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
  EQ: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
  NE: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
  LT: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
  LE: [[["IN1", "0"], ["IN2", "0"]], "BOOL"],
};
/// The block types the editor offers: the standard function blocks, then the
/// standard functions.
export const STANDARD_BLOCKS = [...Object.keys(BLOCKS), ...Object.keys(FUNCS)];
/// The literal a new block's input of an elementary type gets (the others stay
/// unwired: they keep their initial value).
const DEFAULTS = {
  BOOL: "FALSE", SINT: "0", INT: "0", DINT: "0", LINT: "0", USINT: "0", UINT: "0", UDINT: "0", ULINT: "0",
  BYTE: "0", WORD: "0", DWORD: "0", LWORD: "0", REAL: "0.0", LREAL: "0.0", TIME: "T#0s",
};
const r10 = (v) => Math.round(v / GRID) * GRID;

function kids(n, name) {
  return [...n.children].filter((c) => c.localName === name);
}
function kid(n, name) {
  return kids(n, name)[0] || null;
}
function num(n, a) {
  const v = parseFloat(n?.getAttribute(a));
  return Number.isFinite(v) ? v : 0;
}

export class LadderEdit {
  /// text: the PLCopen file; pou: the POU whose LD body is edited.
  /// external: the functions and function blocks of the project's other files
  /// (see `userPous`).
  constructor(text, pou, external = []) {
    this.pou = pou;
    this.external = external;
    this.undoStack = [];
    this.redoStack = [];
    this.load(text);
  }

  load(text) {
    const doc = new DOMParser().parseFromString(text, "application/xml");
    if (doc.getElementsByTagName("parsererror").length) throw new Error("the file is not well-formed XML");
    this.doc = doc;
    const pou = [...doc.getElementsByTagNameNS("*", "pou")].find((p) => p.getAttribute("name")?.toLowerCase() === this.pou.toLowerCase());
    const body = pou && kid(pou, "body");
    this.body = body && (kid(body, "LD") || kid(body, "FBD"));
    if (!this.body) throw new Error(`${this.pou} has no LD or FBD body`);
    this.interface = kid(pou, "interface");
    this.ns = this.body.namespaceURI;
  }

  /// The file as saved: the XML declaration, then the document.
  text() {
    const s = new XMLSerializer().serializeToString(this.doc);
    return s.startsWith("<?xml") ? s : `<?xml version="1.0" encoding="utf-8"?>\n${s}`;
  }

  /// Before an edit: the text kept for undo; what was undone can no longer be
  /// redone.
  snapshot() {
    this.undoStack.push(this.text());
    if (this.undoStack.length > 100) this.undoStack.shift();
    this.redoStack = [];
  }

  undo() {
    const t = this.undoStack.pop();
    if (t === undefined) return false;
    this.redoStack.push(this.text());
    this.load(t);
    return true;
  }

  /// The last undone edit made again.
  redo() {
    const t = this.redoStack.pop();
    if (t === undefined) return false;
    this.undoStack.push(this.text());
    this.load(t);
    return true;
  }

  elements() {
    return [...this.body.children];
  }
  byId(id) {
    return this.elements().find((e) => e.getAttribute("localId") === String(id)) || null;
  }
  nextId() {
    let max = 0;
    for (const e of this.doc.getElementsByTagNameNS("*", "*")) max = Math.max(max, parseInt(e.getAttribute("localId") || "0", 10) || 0);
    return max + 1;
  }
  pos(e) {
    const p = kid(e, "position");
    return { x: num(p, "x"), y: num(p, "y") };
  }
  setPos(e, x, y) {
    let p = kid(e, "position");
    if (!p) e.prepend((p = this.make("position")));
    p.setAttribute("x", String(Math.round(x)));
    p.setAttribute("y", String(Math.round(y)));
  }
  size(e) {
    return { w: num(e, "width"), h: num(e, "height") };
  }
  make(name, attrs = {}, ...children) {
    const n = this.doc.createElementNS(this.ns, name);
    for (const [k, v] of Object.entries(attrs)) n.setAttribute(k, String(v));
    for (const c of children) n.append(typeof c === "string" ? this.doc.createTextNode(c) : c);
    return n;
  }
  point(tag, rx, ry, ...conns) {
    return this.make(tag, {}, this.make("relPosition", { x: rx, y: ry }), ...conns);
  }
  conn(ref, param) {
    const c = this.make("connection", { refLocalId: ref });
    if (param) c.setAttribute("formalParameter", param);
    return c;
  }

  /// Every input connection point of the body with its element.
  inputs() {
    const out = [];
    for (const e of this.elements()) for (const cp of e.getElementsByTagNameNS("*", "connectionPointIn")) out.push({ e, cp });
    return out;
  }

  /// The absolute place of a connection point of element e.
  abs(e, cp) {
    const p = this.pos(e);
    const r = kid(cp, "relPosition");
    return { x: p.x + num(r, "x"), y: p.y + num(r, "y") };
  }

  /// The output of element `src` a connection takes (by name, else the one nearest
  /// in height: a rail's).
  outOf(src, param, y) {
    const outs = [...src.getElementsByTagNameNS("*", "connectionPointOut")].map((cp) => {
      const v = cp.parentElement.localName === "variable" ? cp.parentElement.getAttribute("formalParameter") : cp.getAttribute("formalParameter");
      return { cp, name: v, at: this.abs(src, cp) };
    });
    if (!outs.length) return null;
    if (param) {
      const o = outs.find((o) => o.name && o.name.toLowerCase() === param.toLowerCase());
      if (o) return o.at;
    }
    return outs.reduce((a, b) => (Math.abs(b.at.y - y) < Math.abs(a.at.y - y) ? b : a)).at;
  }

  /// Wires whose ends moved get new points (kept where both ends are where they were).
  reroute() {
    for (const { e, cp } of this.inputs()) {
      const to = this.abs(e, cp);
      for (const c of kids(cp, "connection")) {
        const src = this.byId(c.getAttribute("refLocalId"));
        if (!src) continue;
        const from = this.outOf(src, c.getAttribute("formalParameter"), to.y);
        if (!from) continue;
        const pts = kids(c, "position").map((p) => ({ x: num(p, "x"), y: num(p, "y") }));
        const same = (a, b) => a && Math.abs(a.x - b.x) < 0.5 && Math.abs(a.y - b.y) < 0.5;
        if (pts.length >= 2 && same(pts[0], to) && same(pts[pts.length - 1], from)) continue;
        for (const p of kids(c, "position")) p.remove();
        let route = [to, from];
        if (Math.abs(to.y - from.y) >= 0.5) {
          const mx = Math.round(from.x + Math.max(GRID, (to.x - from.x) / 2));
          route = [to, { x: mx, y: to.y }, { x: mx, y: from.y }, from];
        }
        for (const p of route) c.append(this.make("position", { x: Math.round(p.x), y: Math.round(p.y) }));
      }
    }
  }

  /// The elements fed, directly or not, by element `id`.
  downstream(id) {
    const seen = new Set();
    const walk = (ref) => {
      for (const { e, cp } of this.inputs()) {
        const lid = e.getAttribute("localId");
        if (seen.has(lid)) continue;
        if (kids(cp, "connection").some((c) => c.getAttribute("refLocalId") === String(ref))) {
          seen.add(lid);
          walk(lid);
        }
      }
    };
    walk(id);
    return [...seen].map((i) => this.byId(i)).filter(Boolean);
  }

  rails() {
    return {
      left: this.elements().find((e) => e.localName === "leftPowerRail"),
      right: this.elements().find((e) => e.localName === "rightPowerRail"),
    };
  }

  /// Moves the right rail right when an element comes near it.
  roomOnTheRight() {
    const { right } = this.rails();
    if (!right) return;
    const rx = this.pos(right).x;
    let max = 0;
    for (const e of this.elements()) if (e !== right && e.localName !== "comment") max = Math.max(max, this.pos(e).x + this.size(e).w);
    if (max + 20 > rx) this.setPos(right, r10(max + 40), this.pos(right).y);
  }

  newContact(x, y, variable, conns) {
    const id = this.nextId();
    const e = this.make(
      "contact",
      { localId: id, negated: "false", edge: "none", width: 21, height: 20 },
      this.make("position", { x, y }),
      this.point("connectionPointIn", 0, 10, ...conns),
      this.point("connectionPointOut", 21, 10),
      this.make("variable", {}, variable)
    );
    return e;
  }

  newCoil(x, y, variable, conns) {
    const id = this.nextId();
    return this.make(
      "coil",
      { localId: id, negated: "false", storage: "none", edge: "none", width: 21, height: 20 },
      this.make("position", { x, y }),
      this.point("connectionPointIn", 0, 10, ...conns),
      this.point("connectionPointOut", 21, 10),
      this.make("variable", {}, variable)
    );
  }

  /// Moves what element `id` feeds, with the literals and variables attached to
  /// the blocks among it, right until all of it starts at `x` or further.
  makeRoomAfter(id, x) {
    const moving = new Set();
    const own = new Set(this.attached(this.byId(id)));
    for (const d of this.downstream(id)) {
      if (d.localName === "rightPowerRail" || own.has(d)) continue;
      moving.add(d);
      for (const a of this.attached(d)) moving.add(a);
    }
    if (!moving.size) return;
    const first = Math.min(...[...moving].map((d) => this.pos(d).x));
    const dx = Math.max(0, r10(x - first + 5));
    for (const d of moving) this.setPos(d, this.pos(d).x + dx, this.pos(d).y);
  }

  /// A contact or coil put in series after element `id` (a contact or coil): what
  /// was fed by it is fed by the new one. Returns the new element's id.
  insertAfter(id, kind) {
    const e = this.byId(id);
    if (!e || !["contact", "coil"].includes(e.localName)) throw new Error("select a contact or a coil to put an element after it");
    this.snapshot();
    const { x, y } = this.pos(e);
    const { w } = this.size(e);
    // Room for the new element: what follows moves right as far as needed.
    const nx = r10(x + w + 30);
    this.makeRoomAfter(id, nx + 21 + 30);
    const variable = kid(e, "variable")?.textContent.trim() || this.boolVar(kind === "coil");
    const ne = kind === "coil" ? this.newCoil(nx, y, variable, []) : this.newContact(nx, y, variable, []);
    const nid = ne.getAttribute("localId");
    for (const { cp } of this.inputs())
      for (const c of kids(cp, "connection")) if (c.getAttribute("refLocalId") === String(id)) c.setAttribute("refLocalId", nid);
    kid(ne, "connectionPointIn").append(this.conn(id));
    e.after(ne);
    this.roomOnTheRight();
    this.reroute();
    return nid;
  }

  /// The functions and function blocks of this file a rung can hold, with their
  /// pins: `{ name, kind, inputs: [[name, type]], outputs: [[name, type]], result }`.
  ownPous() {
    const typeOf = (t) => {
      const e = t?.firstElementChild;
      if (!e) return "";
      return e.localName === "derived" ? e.getAttribute("name") || "" : e.localName.toUpperCase();
    };
    return [...this.doc.getElementsByTagNameNS("*", "pou")]
      .filter((p) => ["function", "functionBlock"].includes(p.getAttribute("pouType")))
      .map((p) => {
        const iface = kid(p, "interface");
        const vars = (section) => (iface ? kids(iface, section).flatMap((b) => kids(b, "variable").map((v) => [v.getAttribute("name"), typeOf(kid(v, "type"))])) : []);
        return {
          name: p.getAttribute("name"),
          kind: p.getAttribute("pouType"),
          inputs: vars("inputVars"),
          outputs: vars("outputVars"),
          result: iface ? typeOf(kid(iface, "returnType")) || null : null,
        };
      });
  }

  /// The functions and function blocks a rung can hold besides the standard ones:
  /// this file's, then those of the project's other files (`external`, in the same
  /// shape, from the server's project).
  userPous() {
    const own = this.ownPous();
    const seen = new Set(own.map((p) => p.name.toLowerCase()));
    return [...own, ...this.external.filter((p) => !seen.has(p.name.toLowerCase()))];
  }

  /// The names of `userPous`.
  userBlocks() {
    return this.userPous().map((p) => p.name);
  }

  /// The pins of a block type: the inputs (name, and the literal a new block gets
  /// on it, none on the first, which takes the power), the outputs with their
  /// types, which output carries the power on (`flow`), and whether it is a
  /// function (no instance). A standard FB's pins from the table; a function's
  /// with EN and ENO; a function block of the project's with its own pins when its
  /// first input and one output are BOOL, else with EN and ENO.
  blockPins(type) {
    const T = type.trim().toUpperCase();
    const std = BLOCKS[T];
    if (std) return { name: T, fn: false, ins: std[0], outs: std[1], flow: 0 };
    const withEn = (name, fn, ins, outs, result) => {
      const o = [["ENO", "BOOL"], ...(fn ? [["OUT", result]] : []), ...outs];
      return { name, fn, ins: [["EN"], ...ins], outs: o, flow: fn && (result || "").toUpperCase() === "BOOL" ? 1 : 0 };
    };
    const f = FUNCS[T];
    if (f) return withEn(T, true, f[0], [], f[1]);
    const pou = this.userPous().find((p) => p.name.toLowerCase() === type.trim().toLowerCase());
    if (!pou) {
      const other = [...this.doc.getElementsByTagNameNS("*", "pou")].find((p) => p.getAttribute("name")?.toLowerCase() === type.trim().toLowerCase());
      const why = other ? ` (${other.getAttribute("name")} is a ${other.getAttribute("pouType")}: only functions and function blocks go into a rung)` : "";
      throw new Error(`blocks: ${[...STANDARD_BLOCKS, ...this.userBlocks()].join(", ")}${why}`);
    }
    const up = (t) => (t || "").toUpperCase();
    const ins = pou.inputs.map(([n, t]) => [n, DEFAULTS[up(t)]]);
    if (pou.kind === "function") {
      if (!pou.result) throw new Error(`${pou.name} has no result type: it cannot be a block`);
      return withEn(pou.name, true, ins, pou.outputs, pou.result);
    }
    const flow = pou.outputs.findIndex(([, t]) => up(t) === "BOOL");
    if (ins.length && up(pou.inputs[0][1]) === "BOOL" && flow >= 0) return { name: pou.name, fn: false, ins: ins.map(([n, l], i) => [n, i ? l : undefined]), outs: pou.outputs, flow };
    return withEn(pou.name, false, ins, pou.outputs, null);
  }

  /// A block in series after element `id` (a contact or coil): its first input
  /// takes what the element gave, its power output feeds what the element fed; its
  /// other inputs get literals (`T#1s`, `10`) or stay open. A function block gets
  /// an instance declared in the POU's local variables; a function's result, when
  /// it does not carry the power, goes to a new local variable.
  insertBlock(id, type) {
    const e = this.byId(id);
    const { name: T, fn, ins, outs, flow } = this.blockPins(type);
    if (!e || !["contact", "coil"].includes(e.localName)) throw new Error("select a contact or a coil to put a block after it");
    this.snapshot();
    const { x, y } = this.pos(e);
    const { w, h } = this.size(e);
    const my = y + h / 2;
    const bw = 80;
    const bh = Math.max(ins.length, outs.length) * 40 + 20;
    const nx = r10(x + w + 40);
    const by = my - 30;
    // Beyond the block and, for a function, the variable its result goes to.
    this.makeRoomAfter(id, nx + bw + (fn ? 130 : 40));
    // Room below for the block's other pins.
    this.makeRoomBelow(y + h, Math.max(0, r10(bh - 40)));
    const instance = fn ? null : this.freeName(T);
    const bid = this.nextId();
    const attrs = { localId: bid, typeName: T, width: bw, height: bh };
    if (instance) attrs.instanceName = instance;
    const block = this.make("block", attrs, this.make("position", { x: nx, y: by }));
    const inputs = this.make("inputVariables");
    ins.forEach(([name], i) => {
      const cp = this.point("connectionPointIn", 0, 30 + 40 * i);
      if (i === 0) cp.append(this.conn(id));
      inputs.append(this.make("variable", { formalParameter: name }, cp));
    });
    const outputs = this.make("outputVariables");
    outs.forEach(([name], i) => outputs.append(this.make("variable", { formalParameter: name }, this.point("connectionPointOut", bw, 30 + 40 * i))));
    block.append(inputs, this.make("inOutVariables"), outputs);
    for (const { cp } of this.inputs())
      for (const c of kids(cp, "connection"))
        if (c.getAttribute("refLocalId") === String(id)) {
          c.setAttribute("refLocalId", String(bid));
          c.setAttribute("formalParameter", outs[flow][0]);
        }
    e.after(block);
    // Literals on the other inputs that need a value.
    let last = block;
    ins.forEach(([name, literal], i) => {
      if (i === 0 || !literal) return;
      const vid = this.nextId();
      const vw = 60;
      const v = this.make(
        "inVariable",
        { localId: vid, negated: "false", width: vw, height: 20 },
        this.make("position", { x: nx - vw - 20, y: by + 30 + 40 * i - 10 }),
        this.point("connectionPointOut", vw, 10),
        this.make("expression", {}, literal)
      );
      last.after(v);
      last = v;
      const cp = [...kids(kid(block, "inputVariables"), "variable")][i];
      kid(cp, "connectionPointIn").append(this.conn(vid));
    });
    if (instance) this.declare(instance, T);
    // A function's result that does not carry the power is kept in a variable.
    if (fn && flow !== 1) this.outputTo(block, "OUT");
    this.roomOnTheRight();
    this.reroute();
    return bid;
  }

  /// An output variable for the first output of block `id` that nothing takes
  /// yet (other than the one carrying the power and ENO): a new local variable of
  /// the output's type is declared and written there. Returns its id.
  addOutput(id) {
    const b = this.byId(id);
    if (!b || b.localName !== "block") throw new Error("select a block to wire one of its outputs");
    const { outs, flow } = this.blockPins(b.getAttribute("typeName") || "");
    const taken = new Set();
    for (const { cp } of this.inputs())
      for (const c of kids(cp, "connection")) if (c.getAttribute("refLocalId") === String(id)) taken.add((c.getAttribute("formalParameter") || "").toLowerCase());
    const free = outs.filter(([n], i) => i !== flow && n.toUpperCase() !== "ENO" && !taken.has(n.toLowerCase()));
    if (!free.length) throw new Error(`every output of ${b.getAttribute("typeName")} is wired already`);
    this.snapshot();
    // Room right of the block for the variable.
    this.makeRoomAfter(id, this.pos(b).x + this.size(b).w + 130);
    const vid = this.outputTo(b, free[0][0]);
    this.roomOnTheRight();
    this.reroute();
    return vid;
  }

  /// An output variable right of `block` at its pin `pin`, holding a new local
  /// variable of the pin's type. Returns its id.
  outputTo(block, pin) {
    const { outs } = this.blockPins(block.getAttribute("typeName") || "");
    const type = outs.find(([n]) => n.toLowerCase() === pin.toLowerCase())?.[1];
    if (!type) throw new Error(`the type of ${pin} is not known: wire it in the text editor`);
    const cp = [...kids(kid(block, "outputVariables"), "variable")].find((v) => (v.getAttribute("formalParameter") || "").toLowerCase() === pin.toLowerCase());
    const at = this.abs(block, kid(cp, "connectionPointOut"));
    const name = this.freeName(`${block.getAttribute("instanceName") || block.getAttribute("typeName")}_${pin}`, false);
    this.declare(name, type);
    const vid = this.nextId();
    const v = this.make(
      "outVariable",
      { localId: vid, negated: "false", width: 80, height: 20 },
      this.make("position", { x: r10(at.x + 30), y: at.y - 10 }),
      this.point("connectionPointIn", 0, 10, this.conn(block.getAttribute("localId"), pin)),
      this.make("expression", {}, name)
    );
    block.after(v);
    return vid;
  }

  /// Moves element `id` by (dx, dy), on the grid; a block takes along the literals
  /// and output variables wired to it alone. Rails stay.
  move(id, dx, dy) {
    const e = this.byId(id);
    if (!e || e.localName.endsWith("PowerRail")) throw new Error("select an element other than a rail to move it");
    dx = r10(dx);
    dy = r10(dy);
    if (!dx && !dy) return id;
    this.snapshot();
    for (const m of [e, ...this.attached(e)]) {
      const p = this.pos(m);
      this.setPos(m, Math.max(0, p.x + dx), Math.max(0, p.y + dy));
    }
    this.roomOnTheRight();
    this.reroute();
    return id;
  }

  /// The literals that feed only block `e` and the output variables it alone feeds.
  attached(e) {
    if (!e || e.localName !== "block") return [];
    const id = e.getAttribute("localId");
    const feeds = (f) => this.inputs().some(({ e: o, cp }) => o !== e && kids(cp, "connection").some((c) => c.getAttribute("refLocalId") === f.getAttribute("localId")));
    const literals = [...e.getElementsByTagNameNS("*", "connection")]
      .map((c) => this.byId(c.getAttribute("refLocalId")))
      .filter((f) => f && f.localName === "inVariable" && !feeds(f));
    const outs = this.elements().filter((o) => {
      if (o.localName !== "outVariable") return false;
      const cs = [...o.getElementsByTagNameNS("*", "connection")];
      return cs.length > 0 && cs.every((c) => c.getAttribute("refLocalId") === id);
    });
    return [...literals, ...outs];
  }

  /// A name for a new variable: `TON0`, `TON1`...; with `numbered` false, `base`
  /// itself while it is free.
  freeName(base, numbered = true) {
    const used = new Set([...this.doc.getElementsByTagNameNS("*", "variable")].map((v) => (v.getAttribute("name") || "").toLowerCase()));
    if (!numbered && !used.has(base.toLowerCase())) return base;
    for (let i = numbered ? 0 : 1; ; i++) if (!used.has(`${base}${i}`.toLowerCase())) return `${base}${i}`;
  }

  /// Declares a local variable of an elementary type or a derived one (an FB
  /// instance).
  declare(name, type) {
    if (!this.interface) throw new Error("the POU has no interface to declare the variable in");
    let locals = kid(this.interface, "localVars");
    if (!locals) this.interface.append((locals = this.make("localVars")));
    const T = type.toUpperCase();
    const ty = T in DEFAULTS || ["LTIME", "DATE", "TOD", "DT"].includes(T) ? this.make(T) : T === "STRING" || T === "WSTRING" ? this.make(T.toLowerCase()) : this.make("derived", { name: type });
    locals.append(this.make("variable", { name }, this.make("type", {}, ty)));
  }

  /// A contact parallel to contact `id` (an OR branch), below it.
  addBranch(id) {
    const e = this.byId(id);
    if (!e || e.localName !== "contact") throw new Error("select a contact to put a branch beside it");
    this.snapshot();
    const { x, y } = this.pos(e);
    const { h } = this.size(e);
    this.makeRoomBelow(y + h, 40);
    const conns = kids(kid(e, "connectionPointIn"), "connection").map((c) => this.conn(c.getAttribute("refLocalId"), c.getAttribute("formalParameter")));
    const ne = this.newContact(x, y + 40, kid(e, "variable")?.textContent.trim() || this.boolVar(false), conns);
    const nid = ne.getAttribute("localId");
    for (const { cp } of this.inputs()) {
      const cs = kids(cp, "connection");
      if (cs.some((c) => c.getAttribute("refLocalId") === String(id))) cp.append(this.conn(nid));
    }
    e.after(ne);
    this.reroute();
    return nid;
  }

  /// Everything below `y` moved down by `dy`, except the literals and variables
  /// attached to a block that stays; the rails grow.
  makeRoomBelow(y, dy) {
    const stays = new Set();
    for (const b of this.elements()) if (b.localName === "block" && this.pos(b).y <= y) for (const a of this.attached(b)) stays.add(a);
    for (const e of this.elements()) {
      if (stays.has(e)) continue;
      const kind = e.localName;
      if (kind === "leftPowerRail" || kind === "rightPowerRail") {
        const p = this.pos(e);
        e.setAttribute("height", String(num(e, "height") + dy));
        for (const cp of [...kids(e, "connectionPointOut"), ...kids(e, "connectionPointIn")]) {
          const r = kid(cp, "relPosition");
          if (p.y + num(r, "y") > y) r.setAttribute("y", String(num(r, "y") + dy));
        }
      } else if (this.pos(e).y > y) this.setPos(e, this.pos(e).x, this.pos(e).y + dy);
    }
  }

  /// A BOOL variable of the interface for a new element (an output for a coil).
  boolVar(output) {
    const groups = this.interface ? [...this.interface.children] : [];
    const order = output ? ["outputVars", "localVars", "inputVars"] : ["inputVars", "localVars", "outputVars"];
    for (const g of order)
      for (const grp of groups.filter((x) => x.localName === g))
        for (const v of kids(grp, "variable")) if (v.getElementsByTagNameNS("*", "BOOL").length) return v.getAttribute("name");
    return "TRUE";
  }

  /// A new rung at the bottom: a contact and a coil between the rails.
  addRung() {
    const { left, right } = this.rails();
    if (!left || !right) throw new Error("the body has no power rails");
    this.snapshot();
    let bottom = 0;
    for (const e of this.elements()) if (e !== left && e !== right) bottom = Math.max(bottom, this.pos(e).y + this.size(e).h);
    const y = r10(bottom + 40);
    const lp = this.pos(left), rp = this.pos(right);
    const grow = (rail) => {
      const need = y + 40 - this.pos(rail).y;
      if (num(rail, "height") < need) rail.setAttribute("height", String(need));
    };
    grow(left);
    grow(right);
    left.append(this.point("connectionPointOut", num(left, "width") || 3, y + 10 - lp.y));
    kids(left, "connectionPointOut").at(-1).setAttribute("formalParameter", "");
    const contact = this.newContact(r10(lp.x + 40), y, this.boolVar(false), [this.conn(left.getAttribute("localId"))]);
    right.before(contact);
    const coil = this.newCoil(r10(rp.x - 60), y, this.boolVar(true), [this.conn(contact.getAttribute("localId"))]);
    right.before(coil);
    right.append(this.point("connectionPointIn", 0, y + 10 - rp.y, this.conn(coil.getAttribute("localId"))));
    this.reroute();
    return contact.getAttribute("localId");
  }

  /// Deletes a contact, coil, variable or block; what it fed is fed by what fed it
  /// (a contact or coil in series), or loses the connection (a parallel branch, the
  /// others).
  remove(id) {
    const e = this.byId(id);
    if (!e || e.localName.endsWith("PowerRail")) throw new Error("select an element other than a rail to delete it");
    this.snapshot();
    // A contact, coil or block in series is bridged from its (first) input; the
    // literals that fed only a block go with it.
    const through = ["contact", "coil", "block"].includes(e.localName);
    const firstIn = e.getElementsByTagNameNS("*", "connectionPointIn")[0];
    const sources = through && firstIn ? kids(firstIn, "connection").map((c) => [c.getAttribute("refLocalId"), c.getAttribute("formalParameter")]) : [];
    const literals = this.attached(e);
    // Only what took a block's power output is bridged; what took its other
    // outputs loses the connection.
    const flowPin = e.localName === "block" ? this.flowPin(e) : null;
    for (const { e: owner, cp } of this.inputs()) {
      if (owner === e) continue;
      const cs = kids(cp, "connection").filter((c) => c.getAttribute("refLocalId") === String(id));
      if (!cs.length) continue;
      const carried = !flowPin || cs.some((c) => (c.getAttribute("formalParameter") || "").toLowerCase() === flowPin);
      for (const c of cs) c.remove();
      if (!carried) continue;
      // What fed the element feeds what it fed, unless that already reaches it
      // another way (the element was a parallel branch: a wire there would be a
      // short circuit around the other branches).
      for (const [ref, param] of sources) {
        const present = kids(cp, "connection").some((c) => c.getAttribute("refLocalId") === ref && (c.getAttribute("formalParameter") || null) === (param || null));
        if (!present && !this.downstream(ref).includes(owner)) cp.append(this.conn(ref, param));
      }
      if (!kids(cp, "connection").length && owner.localName === "rightPowerRail") cp.remove();
    }
    e.remove();
    for (const f of literals) f.remove();
    this.reroute();
    return sources.length ? sources[0][0] : null;
  }

  /// The name (lower case) of the output of block `e` that carries the power: its
  /// type's, else its first output's.
  flowPin(e) {
    try {
      const { outs, flow } = this.blockPins(e.getAttribute("typeName") || "");
      return outs[flow][0].toLowerCase();
    } catch {
      const o = e.getElementsByTagNameNS("*", "outputVariables")[0];
      return (o && kids(o, "variable")[0]?.getAttribute("formalParameter")?.toLowerCase()) || "";
    }
  }

  /// Sets the variable of a contact or coil, or the expression of a variable.
  setVariable(id, name) {
    const e = this.byId(id);
    const t = e && (kid(e, "variable") || kid(e, "expression"));
    if (!t) throw new Error("select a contact, a coil or a variable to name its variable");
    const variable = /^[A-Za-z_%][A-Za-z0-9_.%#[\]]*$/.test(name.trim());
    // An input variable of a block may hold a literal: 5, -2, 1.5, 16#FF, INT#3.
    const literal = t.localName === "expression" && /^[+-]?[0-9][0-9A-Za-z_.#+-]*$/.test(name.trim());
    if (!variable && !literal) throw new Error(`\`${name}\` is not a ${t.localName === "expression" ? "variable or literal" : "variable"}`);
    this.snapshot();
    t.textContent = name.trim();
  }

  /// Cycles a contact through normally open, normally closed, rising and falling
  /// edges; a coil through plain, negated, set and reset.
  cycle(id) {
    const e = this.byId(id);
    if (!e || !["contact", "coil"].includes(e.localName)) throw new Error("select a contact or a coil to change its kind");
    this.snapshot();
    const get = (a, d) => e.getAttribute(a) || d;
    if (e.localName === "contact") {
      const states = [["false", "none"], ["true", "none"], ["false", "rising"], ["false", "falling"]];
      const i = states.findIndex(([n, ed]) => n === get("negated", "false") && ed === get("edge", "none"));
      const [n, ed] = states[(i + 1) % states.length];
      e.setAttribute("negated", n);
      e.setAttribute("edge", ed);
    } else {
      const states = [["false", "none"], ["true", "none"], ["false", "set"], ["false", "reset"]];
      const i = states.findIndex(([n, s]) => n === get("negated", "false") && s === get("storage", "none"));
      const [n, s] = states[(i + 1) % states.length];
      e.setAttribute("negated", n);
      e.setAttribute("storage", s);
    }
  }
}
