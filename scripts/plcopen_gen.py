"""Writes PLCopen TC6 XML files element by element, for tests/programs/plcopen/.

Unlike ld_gen.py (series-parallel rungs described as nested lists), every element is
given here by hand: its localId, its position and its connections, so that bridges,
several wires into one input, loops through blocks, chains of coils and FBD networks
can be drawn exactly. The layout follows what Beremiz / OpenPLC Editor write: a
contact or coil is 21x15 with its pins at y+8, a block's pins are 20 apart starting
30 below its top, and every wire lists its end points (sink first, as the editors
do).

    body = Body('LD')                       # or 'FBD'; Body('LD', positions=False)
    body.rail(1, 20, 20)
    body.contact(2, 'a', 1, 80, 40)         # id, variable, source(s), x, y
    body.coil(3, 'q', 2, 200, 40)
    xml = project('name', comment, [pou('name', 'program', VARS, body)])

A source is a localId, `(localId, 'PIN')` for a block output, or a list of those
(several wires into one input); `None` or `[]` leaves the input unconnected.
"""

NS = {
    '2.01': 'http://www.plcopen.org/xml/tc6_0201',
    '1.0': 'http://www.plcopen.org/xml/tc6.xsd',
}

ELEMENTARY = {
    'BOOL', 'SINT', 'INT', 'DINT', 'LINT', 'USINT', 'UINT', 'UDINT', 'ULINT', 'REAL',
    'LREAL', 'TIME', 'DATE', 'TOD', 'DT', 'STRING', 'WSTRING', 'BYTE', 'WORD', 'DWORD',
    'LWORD',
}


def type_xml(t):
    if t in ELEMENTARY:
        return f'<{t}/>'
    return f'<derived name="{t}"/>'


def sources(s):
    if s is None:
        return []
    if isinstance(s, list):
        return s
    return [s]


class Body:
    """A graphical body: its elements in document order."""

    def __init__(self, lang, positions=True):
        self.lang = lang
        self.positions = positions
        self.elems = []
        self.by_id = {}

    def _add(self, el):
        assert el['id'] not in self.by_id, f"localId {el['id']} used twice"
        self.elems.append(el)
        self.by_id[el['id']] = el
        return el

    # ------------------------------------------------------------ elements

    def rail(self, id, x, y):
        return self._add(dict(kind='leftPowerRail', id=id, x=x, y=y, w=3, h=0))

    def right_rail(self, id, x, y, srcs):
        return self._add(dict(kind='rightPowerRail', id=id, x=x, y=y, w=3, h=0,
                              srcs=sources(srcs)))

    def contact(self, id, var, src, x, y, neg=False, edge=None, order=None):
        return self._add(dict(kind='contact', id=id, var=var, src=sources(src), x=x, y=y,
                              w=21, h=15, neg=neg, edge=edge, order=order))

    def coil(self, id, var, src, x, y, neg=False, storage=None, edge=None, order=None):
        return self._add(dict(kind='coil', id=id, var=var, src=sources(src), x=x, y=y,
                              w=21, h=15, neg=neg, storage=storage, edge=edge, order=order))

    def block(self, id, ty, x, y, ins, outs, inst=None, order=None, w=None):
        """`ins`: [(pin, sources) or (pin, sources, {'neg': True, 'edge': 'rising'})];
        `outs`: [pin or (pin, {'neg': True, 'edge': 'falling'})]."""
        ins = [(p[0], sources(p[1]), p[2] if len(p) > 2 else {}) for p in ins]
        outs = [(p, {}) if isinstance(p, str) else p for p in outs]
        if w is None:
            w = max(60, 10 * len(ty) + 20, 10 * len(inst or '') + 10)
        h = 40 + 20 * max(len(ins), len(outs))
        return self._add(dict(kind='block', id=id, ty=ty, inst=inst, x=x, y=y, w=w, h=h,
                              ins=ins, outs=outs, order=order))

    def invar(self, id, expr, x, y, neg=False):
        return self._add(dict(kind='inVariable', id=id, expr=expr, x=x, y=y,
                              w=max(30, 8 * len(expr) + 10), h=25, neg=neg))

    def outvar(self, id, expr, src, x, y, order=None, neg=False):
        return self._add(dict(kind='outVariable', id=id, expr=expr, src=sources(src),
                              x=x, y=y, w=max(30, 8 * len(expr) + 10), h=25, order=order,
                              neg=neg))

    def inoutvar(self, id, expr, src, x, y, order=None):
        return self._add(dict(kind='inOutVariable', id=id, expr=expr, src=sources(src),
                              x=x, y=y, w=max(30, 8 * len(expr) + 10), h=25, order=order))

    def connector(self, id, name, src, x, y):
        return self._add(dict(kind='connector', id=id, name=name, src=sources(src), x=x, y=y,
                              w=60, h=20))

    def continuation(self, id, name, x, y):
        return self._add(dict(kind='continuation', id=id, name=name, x=x, y=y, w=60, h=20))

    def jump(self, id, label, src, x, y):
        return self._add(dict(kind='jump', id=id, label=label, src=sources(src), x=x, y=y,
                              w=12, h=13))

    def label(self, id, label, x, y):
        return self._add(dict(kind='label', id=id, label=label, x=x, y=y, w=60, h=20))

    def ret(self, id, src, x, y):
        return self._add(dict(kind='return', id=id, src=sources(src), x=x, y=y, w=50, h=20))

    def comment(self, id, text, x, y):
        return self._add(dict(kind='comment', id=id, text=text, x=x, y=y, w=300, h=40))

    # ------------------------------------------------------------ geometry

    def out_point(self, s, at_y=None):
        """The absolute point of output `s` (a source)."""
        if isinstance(s, tuple):
            el, pin = self.by_id[s[0]], s[1]
        else:
            el, pin = self.by_id[s], None
        k = el['kind']
        if k == 'leftPowerRail':
            return (el['x'] + 3, at_y)
        if k == 'block':
            names = [p for p, _ in el['outs']]
            if pin is None:
                pin = [n for n in names if n != 'ENO'][0]
            i = names.index(pin)
            return (el['x'] + el['w'], el['y'] + 30 + 20 * i)
        if k in ('contact', 'coil'):
            return (el['x'] + 21, el['y'] + 8)
        if k in ('inVariable', 'inOutVariable'):
            return (el['x'] + el['w'], el['y'] + 12)
        if k == 'continuation':
            return (el['x'] + 60, el['y'] + 10)
        raise ValueError(f"no output on {k} {el['id']}")

    def in_point(self, el, port=0):
        k = el['kind']
        if k == 'block':
            return (el['x'], el['y'] + 30 + 20 * port)
        if k in ('contact', 'coil'):
            return (el['x'], el['y'] + 8)
        if k in ('outVariable', 'inOutVariable'):
            return (el['x'], el['y'] + 12)
        if k == 'connector':
            return (el['x'], el['y'] + 10)
        if k in ('jump', 'return'):
            return (el['x'], el['y'] + 8)
        if k == 'rightPowerRail':
            return (el['x'], None)
        raise ValueError(k)

    # ------------------------------------------------------------ writing

    def _pos(self, el, ind):
        if not self.positions:
            return ''
        return f'{ind}<position x="{el["x"]}" y="{el["y"]}"/>\n'

    def _conns(self, el, srcs, port, ind):
        """A `connectionPointIn` with its connections."""
        sx, sy = self.in_point(el, port)
        rel_y = (sy - el['y']) if sy is not None else 0
        out = f'{ind}<connectionPointIn>\n{ind}  <relPosition x="0" y="{rel_y}"/>\n'
        for s in srcs:
            ref, pin = (s if isinstance(s, tuple) else (s, None))
            src_el = self.by_id[ref]
            if pin is None and src_el['kind'] == 'block':
                pin = [n for n, _ in src_el['outs'] if n != 'ENO'][0]
            fp = f' formalParameter="{pin}"' if pin else ''
            if self.positions:
                y = sy
                if y is None:  # right rail: the point of the source
                    y = self.out_point(s, 0)[1]
                ox, oy = self.out_point(s, y)
                out += (f'{ind}  <connection refLocalId="{ref}"{fp}>\n'
                        f'{ind}    <position x="{sx}" y="{y}"/>\n'
                        f'{ind}    <position x="{ox}" y="{oy}"/>\n'
                        f'{ind}  </connection>\n')
            else:
                out += f'{ind}  <connection refLocalId="{ref}"{fp}/>\n'
        return out + f'{ind}</connectionPointIn>\n'

    def _out(self, rel_x, rel_y, ind, fp=None):
        f = f' formalParameter="{fp}"' if fp is not None else ''
        return (f'{ind}<connectionPointOut{f}>\n{ind}  <relPosition x="{rel_x}" y="{rel_y}"/>\n'
                f'{ind}</connectionPointOut>\n')

    def _rail_points(self, rail):
        """The heights (relative) at which elements are wired to a left rail."""
        ys = []
        for el in self.elems:
            if el['kind'] == 'block':
                for i, (_, srcs, _) in enumerate(el['ins']):
                    if rail['id'] in [s if not isinstance(s, tuple) else s[0] for s in srcs]:
                        ys.append(self.in_point(el, i)[1])
            elif rail['id'] in [s if not isinstance(s, tuple) else s[0]
                                for s in el.get('src', [])]:
                ys.append(self.in_point(el)[1])
        return sorted(set(ys))

    def xml(self, ind):
        i2 = ind + '  '
        i3 = i2 + '  '
        parts = []
        for el in self.elems:
            k = el['kind']
            head = f'{ind}<{k} localId="{el["id"]}" height="{el["h"]}" width="{el["w"]}"'
            if k == 'leftPowerRail':
                ys = self._rail_points(el)
                h = (max(ys) - el['y'] + 20) if ys else 40
                s = f'{ind}<{k} localId="{el["id"]}" height="{h}" width="3">\n'
                s += self._pos(el, i2)
                for y in (ys or [el['y'] + 20]):
                    s += self._out(3, y - el['y'], i2, fp='')
                s += f'{ind}</{k}>\n'
            elif k == 'rightPowerRail':
                s = head + '>\n' + self._pos(el, i2)
                for src in el['srcs']:
                    s += self._conns(el, [src], 0, i2)
                s += f'{ind}</{k}>\n'
            elif k in ('contact', 'coil'):
                attrs = f' negated="{str(el["neg"]).lower()}"'
                if k == 'coil':
                    attrs += f' storage="{el["storage"] or "none"}"'
                attrs += f' edge="{el["edge"] or "none"}"'
                if el['order']:
                    attrs += f' executionOrderId="{el["order"]}"'
                s = head + attrs + '>\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2)
                s += self._out(21, 8, i2)
                s += f'{i2}<variable>{el["var"]}</variable>\n{ind}</{k}>\n'
            elif k == 'block':
                inst = f' instanceName="{el["inst"]}"' if el['inst'] else ''
                order = f' executionOrderId="{el["order"] or 0}"'
                s = (f'{ind}<block localId="{el["id"]}" typeName="{el["ty"]}"{inst}{order} '
                     f'height="{el["h"]}" width="{el["w"]}">\n')
                s += self._pos(el, i2)
                s += f'{i2}<inputVariables>\n'
                for port, (pin, srcs, mods) in enumerate(el['ins']):
                    m = ''
                    if mods.get('neg'):
                        m += ' negated="true"'
                    if mods.get('edge'):
                        m += f' edge="{mods["edge"]}"'
                    s += f'{i3}<variable formalParameter="{pin}"{m}>\n'
                    if srcs:
                        s += self._conns(el, srcs, port, i3 + '  ')
                    else:
                        s += (f'{i3}  <connectionPointIn>\n{i3}    <relPosition x="0" '
                              f'y="{30 + 20 * port}"/>\n{i3}  </connectionPointIn>\n')
                    s += f'{i3}</variable>\n'
                s += f'{i2}</inputVariables>\n{i2}<inOutVariables/>\n{i2}<outputVariables>\n'
                for j, (pin, mods) in enumerate(el['outs']):
                    m = ''
                    if mods.get('neg'):
                        m += ' negated="true"'
                    if mods.get('edge'):
                        m += f' edge="{mods["edge"]}"'
                    s += f'{i3}<variable formalParameter="{pin}"{m}>\n'
                    s += self._out(el['w'], 30 + 20 * j, i3 + '  ')
                    s += f'{i3}</variable>\n'
                s += f'{i2}</outputVariables>\n{ind}</block>\n'
            elif k == 'inVariable':
                s = head + f' negated="{str(el["neg"]).lower()}">\n' + self._pos(el, i2)
                s += self._out(el['w'], 12, i2)
                s += f'{i2}<expression>{el["expr"]}</expression>\n{ind}</{k}>\n'
            elif k == 'outVariable':
                order = f' executionOrderId="{el["order"]}"' if el['order'] else ''
                s = head + f' negated="{str(el["neg"]).lower()}"{order}>\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2)
                s += f'{i2}<expression>{el["expr"]}</expression>\n{ind}</{k}>\n'
            elif k == 'inOutVariable':
                order = f' executionOrderId="{el["order"]}"' if el['order'] else ''
                s = head + f' negatedOut="false" negatedIn="false"{order}>\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2)
                s += self._out(el['w'], 12, i2)
                s += f'{i2}<expression>{el["expr"]}</expression>\n{ind}</{k}>\n'
            elif k == 'connector':
                s = head + f' name="{el["name"]}">\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2) + f'{ind}</{k}>\n'
            elif k == 'continuation':
                s = head + f' name="{el["name"]}">\n' + self._pos(el, i2)
                s += self._out(60, 10, i2) + f'{ind}</{k}>\n'
            elif k == 'jump':
                s = head + f' label="{el["label"]}">\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2) + f'{ind}</{k}>\n'
            elif k == 'label':
                s = head + f' label="{el["label"]}">\n' + self._pos(el, i2) + f'{ind}</{k}>\n'
            elif k == 'return':
                s = head + '>\n' + self._pos(el, i2)
                s += self._conns(el, el['src'], 0, i2) + f'{ind}</{k}>\n'
            elif k == 'comment':
                s = (head + '>\n' + self._pos(el, i2) + f'{i2}<content>\n'
                     f'{i2}  <xhtml:p><![CDATA[{el["text"]}]]></xhtml:p>\n'
                     f'{i2}</content>\n{ind}</{k}>\n')
            else:
                raise ValueError(k)
            parts.append(s)
        return ''.join(parts)


def vars_xml(group, vs, ind):
    """`vs`: [(name, type) or (name, type, initial value)]."""
    s = f'{ind}<{group}>\n'
    for v in vs:
        name, t = v[0], v[1]
        init = v[2] if len(v) > 2 else None
        s += f'{ind}  <variable name="{name}">\n{ind}    <type>{type_xml(t)}</type>\n'
        if init is not None:
            s += (f'{ind}    <initialValue><simpleValue value="{init}"/></initialValue>\n')
        s += f'{ind}  </variable>\n'
    return s + f'{ind}</{group}>\n'


GROUPS = ['returnType', 'inputVars', 'outputVars', 'inOutVars', 'externalVars',
          'localVars', 'tempVars']


def pou(name, kind, interface, body):
    """`interface`: {'inputVars': [...], 'localVars': [...], 'returnType': 'INT'}; `body` a
    Body, or ('ST', text)."""
    ind = '      '
    s = f'{ind}<pou name="{name}" pouType="{kind}">\n{ind}  <interface>\n'
    for g in GROUPS:
        if g not in interface:
            continue
        if g == 'returnType':
            s += f'{ind}    <returnType>{type_xml(interface[g])}</returnType>\n'
        else:
            s += vars_xml(g, interface[g], ind + '    ')
    s += f'{ind}  </interface>\n{ind}  <body>\n'
    if isinstance(body, tuple):
        lang, text = body
        s += (f'{ind}    <{lang}>\n{ind}      <xhtml:p><![CDATA[{text}]]></xhtml:p>\n'
              f'{ind}    </{lang}>\n')
    else:
        s += f'{ind}    <{body.lang}>\n' + body.xml(ind + '      ') + f'{ind}    </{body.lang}>\n'
    s += f'{ind}  </body>\n{ind}</pou>\n'
    return s


def project(name, comment, pous, version='2.01', tasks=None, program=None,
            config_globals=None, resource_globals=None, free_instances=None):
    """The whole file. `tasks`: [(task name, interval, priority, [(instance, type)])];
    by default one task `task0` of T#10ms running `instance0` of `program` (or `name`).
    `free_instances`: [(instance, type)] in the resource without a task."""
    ns = NS[version]
    inst_attr = 'typeName' if version == '2.01' else 'type'
    if tasks is None:
        tasks = [('task0', 'T#10ms', 0, [('instance0', program or name)])]
    head = "<?xml version='1.0' encoding='utf-8'?>\n"
    if comment:
        head += '<!--\n' + comment.strip('\n') + '\n-->\n'
    res = '        <resource name="resource1">\n'
    for tname, interval, prio, insts in tasks:
        res += f'          <task name="{tname}" priority="{prio}" interval="{interval}">\n'
        for iname, ty in insts:
            res += f'            <pouInstance name="{iname}" {inst_attr}="{ty}"/>\n'
        res += '          </task>\n'
    if resource_globals:
        res += vars_xml('globalVars', resource_globals, '          ')
    for iname, ty in free_instances or []:
        res += f'          <pouInstance name="{iname}" {inst_attr}="{ty}"/>\n'
    res += '        </resource>\n'
    if config_globals:
        res += vars_xml('globalVars', config_globals, '        ')
    return f'''{head}<project xmlns="{ns}" xmlns:xhtml="http://www.w3.org/1999/xhtml" xmlns:xsd="http://www.w3.org/2001/XMLSchema">
  <fileHeader companyName="plcc" productName="plcc PLCopen tests" productVersion="1" creationDateTime="2026-12-02T10:00:00"/>
  <contentHeader name="{name}" modificationDateTime="2026-12-02T10:00:00">
    <coordinateInfo>
      <fbd><scaling x="10" y="10"/></fbd>
      <ld><scaling x="10" y="10"/></ld>
      <sfc><scaling x="10" y="10"/></sfc>
    </coordinateInfo>
  </contentHeader>
  <types>
    <dataTypes/>
    <pous>
{''.join(pous)}    </pous>
  </types>
  <instances>
    <configurations>
      <configuration name="config">
{res}      </configuration>
    </configurations>
  </instances>
</project>
'''
