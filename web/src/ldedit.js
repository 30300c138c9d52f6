// Editing a ladder body in its PLCopen XML: the document is changed in place, so
// everything else in the file (other POUs, types, configurations, what editors keep
// in addData) is saved as it was read. Each operation keeps the undo stack (and
// clears the redo stack).

const GRID = 10;

/// The standard function blocks the editor adds: the inputs (with a literal for
/// those that need a value) and the outputs; the first input takes the power.
const BLOCKS = {
  TON: [[["IN"], ["PT", "T#1s"]], ["Q", "ET"]],
  TOF: [[["IN"], ["PT", "T#1s"]], ["Q", "ET"]],
  TP: [[["IN"], ["PT", "T#1s"]], ["Q", "ET"]],
  CTU: [[["CU"], ["R", "FALSE"], ["PV", "10"]], ["Q", "CV"]],
  CTD: [[["CD"], ["LD", "FALSE"], ["PV", "10"]], ["Q", "CV"]],
  R_TRIG: [[["CLK"]], ["Q"]],
  F_TRIG: [[["CLK"]], ["Q"]],
  SR: [[["S1"], ["R", "FALSE"]], ["Q1"]],
  RS: [[["S"], ["R1", "FALSE"]], ["Q1"]],
};
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
  constructor(text, pou) {
    this.pou = pou;
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
    const after = this.downstream(id).filter((d) => d.localName !== "rightPowerRail");
    const first = Math.min(...after.map((d) => this.pos(d).x));
    const dx = after.length ? Math.max(0, r10(nx + 21 + 30 - first + 5)) : 0;
    for (const d of after) this.setPos(d, this.pos(d).x + dx, this.pos(d).y);
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

  /// A function block in series after element `id` (a contact or coil): its first
  /// input takes what the element gave, its first output feeds what the element fed;
  /// its other inputs get literals (`T#1s`, `10`) or stay open; an instance is
  /// declared in the POU's local variables.
  /// The function blocks of this file (`pouType="functionBlock"`) a rung can hold:
  /// their names.
  userBlocks() {
    return [...this.doc.getElementsByTagNameNS("*", "pou")].filter((p) => p.getAttribute("pouType") === "functionBlock").map((p) => p.getAttribute("name"));
  }

  /// The pins of a block type: the inputs (name, and the literal a new block gets
  /// on it, none on the first, which takes the power), the outputs, and which
  /// output carries the power on. A standard FB's from the table; a function
  /// block of this file's from its interface: its first input and one of its
  /// outputs must be BOOL.
  blockPins(type) {
    const std = BLOCKS[type.toUpperCase()];
    if (std) return { name: type.toUpperCase(), ins: std[0], outs: std[1], flow: 0 };
    const pou = [...this.doc.getElementsByTagNameNS("*", "pou")].find((p) => p.getAttribute("name")?.toLowerCase() === type.toLowerCase());
    if (!pou || pou.getAttribute("pouType") !== "functionBlock") {
      const user = this.userBlocks();
      throw new Error(`blocks: ${[...Object.keys(BLOCKS), ...user].join(", ")}${pou ? ` (${type} is a ${pou.getAttribute("pouType")}: not yet in a rung)` : ""}`);
    }
    const vars = (section) => {
      const iface = kid(pou, "interface");
      const block = iface && kid(iface, section);
      return block ? kids(block, "variable").map((v) => [v.getAttribute("name"), kid(v, "type")?.firstElementChild?.localName || ""]) : [];
    };
    const ins = vars("inputVars");
    const outs = vars("outputVars");
    const name = pou.getAttribute("name");
    if (!ins.length || ins[0][1] !== "BOOL") throw new Error(`${name}'s first input is not BOOL: it cannot take the power of a rung`);
    const flow = outs.findIndex(([, t]) => t === "BOOL");
    if (flow < 0) throw new Error(`${name} has no BOOL output to carry the power on`);
    return { name, ins: ins.map(([n, t], i) => [n, i ? DEFAULTS[t] : undefined]), outs: outs.map(([n]) => n), flow };
  }

  insertBlock(id, type) {
    const e = this.byId(id);
    const { name: T, ins, outs, flow } = this.blockPins(type);
    if (!e || !["contact", "coil"].includes(e.localName)) throw new Error("select a contact or a coil to put a block after it");
    this.snapshot();
    const { x, y } = this.pos(e);
    const { w, h } = this.size(e);
    const my = y + h / 2;
    const bw = 80;
    const bh = Math.max(ins.length, outs.length) * 40 + 20;
    const nx = r10(x + w + 40);
    const by = my - 30;
    const after = this.downstream(id).filter((d) => d.localName !== "rightPowerRail");
    const first = Math.min(...after.map((d) => this.pos(d).x));
    const dx = after.length ? Math.max(0, r10(nx + bw + 40 - first + 5)) : 0;
    for (const d of after) this.setPos(d, this.pos(d).x + dx, this.pos(d).y);
    // Room below for the block's other pins.
    this.makeRoomBelow(y + h, Math.max(0, r10(bh - 40)));
    const instance = this.freeName(T);
    const bid = this.nextId();
    const block = this.make("block", { localId: bid, typeName: T, instanceName: instance, width: bw, height: bh }, this.make("position", { x: nx, y: by }));
    const inputs = this.make("inputVariables");
    ins.forEach(([name], i) => {
      const cp = this.point("connectionPointIn", 0, 30 + 40 * i);
      if (i === 0) cp.append(this.conn(id));
      inputs.append(this.make("variable", { formalParameter: name }, cp));
    });
    const outputs = this.make("outputVariables");
    outs.forEach((name, i) => outputs.append(this.make("variable", { formalParameter: name }, this.point("connectionPointOut", bw, 30 + 40 * i))));
    block.append(inputs, this.make("inOutVariables"), outputs);
    for (const { cp } of this.inputs())
      for (const c of kids(cp, "connection"))
        if (c.getAttribute("refLocalId") === String(id)) {
          c.setAttribute("refLocalId", String(bid));
          c.setAttribute("formalParameter", outs[flow]);
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
    this.declare(instance, T);
    this.roomOnTheRight();
    this.reroute();
    return bid;
  }

  /// A name for a new instance: `TON0`, `TON1`...
  freeName(type) {
    const used = new Set([...this.doc.getElementsByTagNameNS("*", "variable")].map((v) => (v.getAttribute("name") || "").toLowerCase()));
    for (let i = 0; ; i++) if (!used.has(`${type}${i}`.toLowerCase())) return `${type}${i}`;
  }

  /// Declares a local variable of a derived type (an FB instance).
  declare(name, type) {
    if (!this.interface) throw new Error("the POU has no interface to declare the instance in");
    let locals = kid(this.interface, "localVars");
    if (!locals) this.interface.append((locals = this.make("localVars")));
    locals.append(this.make("variable", { name }, this.make("type", {}, this.make("derived", { name: type }))));
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

  /// Everything below `y` moved down by `dy`; the rails grow.
  makeRoomBelow(y, dy) {
    for (const e of this.elements()) {
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
    const feeds = (f) => this.inputs().some(({ e: o, cp }) => o !== e && kids(cp, "connection").some((c) => c.getAttribute("refLocalId") === f.getAttribute("localId")));
    const literals =
      e.localName === "block"
        ? [...e.getElementsByTagNameNS("*", "connection")]
            .map((c) => this.byId(c.getAttribute("refLocalId")))
            .filter((f) => f && f.localName === "inVariable" && !feeds(f))
        : [];
    for (const { e: owner, cp } of this.inputs()) {
      if (owner === e) continue;
      const cs = kids(cp, "connection");
      if (!cs.some((c) => c.getAttribute("refLocalId") === String(id))) continue;
      for (const c of cs) if (c.getAttribute("refLocalId") === String(id)) c.remove();
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

  /// Sets the variable of a contact or coil, or the expression of a variable.
  setVariable(id, name) {
    const e = this.byId(id);
    const t = e && (kid(e, "variable") || kid(e, "expression"));
    if (!t) throw new Error("select a contact, a coil or a variable to name its variable");
    if (!/^[A-Za-z_%][A-Za-z0-9_.%#[\]]*$/.test(name.trim())) throw new Error(`\`${name}\` is not a variable`);
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
