#!/usr/bin/env python3
"""Writes PLCopen TC6 XML ladder projects from a compact description of their rungs.

The ladder tests of plcc (tests/programs/ld/*.xml) were written with it, laid out the
way Beremiz exports: elements on a grid with positions and connection points, each
element's `connectionPointIn` listing the elements it is wired to. The programs
themselves are described in `scripts/ld_programs.py`, which uses this module.

Rung description (nested tuples):
    ('S', item, item, ...)            series
    ('P', branch, branch, ...)        parallel branches (joined by the next element)
    C('x'), C('x', neg=True), C('x', edge='rising')      contacts
    O('y'), O('y', neg=True), O('y', storage='set')      coils
    B('TON', 'T1', ins=[('IN', POWER), ('PT', V('T#5s'))], outs=[('Q', POWER), ('ET', V('e'))])
        a block; an input is POWER (the series' power), V(expr) (an input variable),
        RAIL (the left rail) or NET(rung) (a network from the left rail, drawn below);
        an output is POWER (continues the series), V(expr) (an output variable) or
        NET(rung) (a network starting at that output, drawn below).
    J('label'), RET, LBL('label')      jump, return, label (a label is a rung alone)
"""

import sys
from xml.sax.saxutils import escape, quoteattr

POWER = ('power',)
RAIL = ('rail',)


def V(expr, neg=False):
    return ('var', expr, neg)


def NET(net):
    return ('net', net)


def C(var, neg=False, edge='none'):
    return ('C', var, neg, edge)


def O(var, neg=False, storage='none', edge='none'):
    return ('O', var, neg, storage, edge)


def B(ty, inst=None, ins=(), outs=(), neg_in=(), neg_out=()):
    return ('B', ty, inst, list(ins), list(outs), set(neg_in), set(neg_out))


def J(label):
    return ('J', label)


RET = ('RET',)


def LBL(label):
    return ('LBL', label)


COL = 80      # grid column width
ROW = 40      # grid row height


class Body:
    def __init__(self):
        self.next_id = 1
        self.items = []        # xml text of elements
        self.left_rails = []   # (id, y list)

    def nid(self):
        i = self.next_id
        self.next_id += 1
        return i


def conn_xml(srcs, indent):
    out = []
    for (sid, param) in srcs:
        fp = f' formalParameter={quoteattr(param)}' if param else ''
        out.append(f'{indent}<connection refLocalId="{sid}"{fp}/>')
    return '\n'.join(out)


def cp_in(srcs, rel_y, indent):
    inner = conn_xml(srcs, indent + '  ')
    inner = ('\n' + inner) if inner else ''
    return (f'{indent}<connectionPointIn>\n{indent}  <relPosition x="0" y="{rel_y}"/>'
            f'{inner}\n{indent}</connectionPointIn>')


def cp_out(rel_x, rel_y, indent):
    return (f'{indent}<connectionPointOut>\n{indent}  <relPosition x="{rel_x}" y="{rel_y}"/>\n'
            f'{indent}</connectionPointOut>')


class Layout:
    """Places a rung's elements on the grid and writes them."""

    def __init__(self, body, top):
        self.b = body
        self.top = top           # y of row 0
        self.max_row = 0
        self.rail_id = None      # set by the caller

    def y(self, row):
        return self.top + row * ROW

    def x(self, col):
        return 60 + col * COL

    def place(self, net, col, row, srcs):
        """Places `net` at (col, row) fed by `srcs` ([(id, param)]); returns
        (outputs, width in columns, height in rows)."""
        self.max_row = max(self.max_row, row)
        kind = net[0]
        I = '            '
        if kind == 'S':
            w = 0
            h = 1
            cur = srcs
            for item in net[1:]:
                cur, iw, ih = self.place(item, col + w, row, cur)
                w += iw
                h = max(h, ih)
            return cur, w, h
        if kind == 'P':
            outs = []
            w = 0
            h = 0
            for br in net[1:]:
                o, bw, bh = self.place(br, col, row + h, srcs)
                outs += o
                w = max(w, bw)
                h += bh
            return outs, w, h
        if kind == 'C':
            _, var, neg, edge = net
            i = self.b.nid()
            neg_a = 'true' if neg else 'false'
            self.b.items.append(
                f'{I}<contact localId="{i}" negated="{neg_a}" edge="{edge}" width="21" height="20">\n'
                f'{I}  <position x="{self.x(col)}" y="{self.y(row)}"/>\n'
                f'{cp_in(srcs, 10, I + "  ")}\n{cp_out(21, 10, I + "  ")}\n'
                f'{I}  <variable>{escape(var)}</variable>\n{I}</contact>')
            return [(i, None)], 1, 1
        if kind == 'O':
            _, var, neg, storage, edge = net
            i = self.b.nid()
            neg_a = 'true' if neg else 'false'
            self.b.items.append(
                f'{I}<coil localId="{i}" negated="{neg_a}" storage="{storage}" edge="{edge}" width="21" height="20">\n'
                f'{I}  <position x="{self.x(col)}" y="{self.y(row)}"/>\n'
                f'{cp_in(srcs, 10, I + "  ")}\n{cp_out(21, 10, I + "  ")}\n'
                f'{I}  <variable>{escape(var)}</variable>\n{I}</coil>')
            return [(i, None)], 1, 1
        if kind == 'J':
            i = self.b.nid()
            self.b.items.append(
                f'{I}<jump localId="{i}" label={quoteattr(net[1])} width="40" height="20">\n'
                f'{I}  <position x="{self.x(col)}" y="{self.y(row)}"/>\n'
                f'{cp_in(srcs, 10, I + "  ")}\n{I}</jump>')
            return [], 1, 1
        if kind == 'RET':
            i = self.b.nid()
            self.b.items.append(
                f'{I}<return localId="{i}" width="40" height="20">\n'
                f'{I}  <position x="{self.x(col)}" y="{self.y(row)}"/>\n'
                f'{cp_in(srcs, 10, I + "  ")}\n{I}</return>')
            return [], 1, 1
        if kind == 'B':
            return self.block(net, col, row, srcs)
        raise ValueError(kind)

    def block(self, net, col, row, srcs):
        _, ty, inst, ins, outs, neg_in, neg_out = net
        I = '            '
        n = max(len(ins), len(outs), 1)
        # The block takes two columns; its variables one column each side.
        bx = self.x(col + 1)
        by = self.y(row) + 10 - 30
        bid = self.b.nid()
        in_xml = []
        extra_rows = n
        below = row + n   # where sub-networks go
        for k, (port, src) in enumerate(ins):
            py = self.y(row + k) + 10
            if src == POWER:
                s = srcs
            elif src == RAIL:
                s = [(self.rail_id, None)]
            elif src[0] == 'var':
                vid = self.b.nid()
                neg_a = 'true' if src[2] else 'false'
                self.b.items.append(
                    f'{I}<inVariable localId="{vid}" negated="{neg_a}" width="60" height="20">\n'
                    f'{I}  <position x="{self.x(col)}" y="{py - 10}"/>\n'
                    f'{cp_out(60, 10, I + "  ")}\n'
                    f'{I}  <expression>{escape(src[1])}</expression>\n{I}</inVariable>')
                s = [(vid, None)]
            elif src[0] == 'net':
                # A network from the left rail on the rows below, wired to this input.
                o, w, h = self.place(src[1], 0, below, [(self.rail_id, None)])
                below += h
                s = o
            elif src[0] == 'ref':
                s = src[1]
            else:
                raise ValueError(src)
            neg_a = ' negated="true"' if port in neg_in else ''
            in_xml.append(
                f'{I}    <variable formalParameter="{port}"{neg_a}>\n'
                f'{cp_in(s, 30 + 40 * k, I + "      ")}\n{I}    </variable>')
        out_xml = []
        results = []
        for k, (port, dst) in enumerate(outs):
            neg_a = ' negated="true"' if port in neg_out else ''
            out_xml.append(
                f'{I}    <variable formalParameter="{port}"{neg_a}>\n'
                f'{cp_out(80, 30 + 40 * k, I + "      ")}\n{I}    </variable>')
            py = self.y(row + k) + 10
            if dst == POWER:
                results.append((bid, port))
            elif dst is None:
                pass
            elif dst[0] == 'var':
                vid = self.b.nid()
                neg_a = 'true' if dst[2] else 'false'
                self.b.items.append(
                    f'{I}<outVariable localId="{vid}" negated="{neg_a}" width="60" height="20">\n'
                    f'{I}  <position x="{self.x(col + 3)}" y="{py - 10}"/>\n'
                    f'{cp_in([(bid, port)], 10, I + "  ")}\n'
                    f'{I}  <expression>{escape(dst[1])}</expression>\n{I}</outVariable>')
            elif dst[0] == 'net':
                o, w, h = self.place(dst[1], col + 3, row + k, [(bid, port)])
                # The network's ends go to the right rail.
                self.ends += o
            else:
                raise ValueError(dst)
        inst_a = f' instanceName={quoteattr(inst)}' if inst else ''
        self.b.items.append(
            f'{I}<block localId="{bid}" typeName={quoteattr(ty)}{inst_a} width="80" height="{40 * n + 20}">\n'
            f'{I}  <position x="{bx}" y="{by}"/>\n'
            f'{I}  <inputVariables>\n' + '\n'.join(in_xml) + f'\n{I}  </inputVariables>\n'
            f'{I}  <inOutVariables/>\n'
            f'{I}  <outputVariables>\n' + '\n'.join(out_xml) + f'\n{I}  </outputVariables>\n'
            f'{I}</block>')
        return results, 4, max(n, below - row)


def body_xml(rungs):
    """The <LD> body of a list of rungs."""
    b = Body()
    rail = b.nid()
    rail_ys = []
    right = []
    top = 40
    labels = []
    for r in rungs:
        if r[0] == 'LBL':
            i = b.nid()
            b.items.append(
                f'            <label localId="{i}" label={quoteattr(r[1])} width="60" height="20">\n'
                f'              <position x="60" y="{top}"/>\n            </label>')
            top += ROW
            continue
        lay = Layout(b, top)
        lay.rail_id = rail
        lay.ends = []
        outs, w, h = lay.place(r, 0, 0, [(rail, None)])
        right += outs + lay.ends
        rail_ys.append(top + 10)
        top = lay.y(max(lay.max_row, h - 1) + 1) + 20
    I = '            '
    rail_xml = (f'{I}<leftPowerRail localId="{rail}" width="3" height="{top}">\n'
                f'{I}  <position x="20" y="20"/>\n' +
                '\n'.join(f'{I}  <connectionPointOut formalParameter="">\n{I}    <relPosition x="3" y="{y - 20}"/>\n{I}  </connectionPointOut>'
                          for y in rail_ys) +
                f'\n{I}</leftPowerRail>')
    rid = b.nid()
    right_xml = (f'{I}<rightPowerRail localId="{rid}" width="3" height="{top}">\n'
                 f'{I}  <position x="900" y="20"/>\n' +
                 '\n'.join(cp_in([s], 10, I + '  ') for s in right) +
                 f'\n{I}</rightPowerRail>')
    return '\n'.join([rail_xml] + b.items + [right_xml])


TYPE_TAGS = {'STRING': '<string/>', 'WSTRING': '<wstring/>'}


def type_xml(t):
    if t.upper() in TYPE_TAGS:
        return TYPE_TAGS[t.upper()]
    if t.isupper() and t.replace('_', '').isalnum():
        return f'<{t}/>'
    return f'<derived name={quoteattr(t)}/>'


def vars_xml(section, decls, indent):
    """decls: [(name, type, init, address)]"""
    if not decls:
        return ''
    out = [f'{indent}<{section}>']
    for d in decls:
        name, ty = d[0], d[1]
        init = d[2] if len(d) > 2 else None
        addr = d[3] if len(d) > 3 else None
        a = f' address={quoteattr(addr)}' if addr else ''
        iv = (f'<initialValue><simpleValue value={quoteattr(init)}/></initialValue>'
              if init is not None else '')
        out.append(f'{indent}  <variable name={quoteattr(name)}{a}><type>{type_xml(ty)}</type>{iv}</variable>')
    out.append(f'{indent}</{section}>')
    return '\n'.join(out)


def pou_xml(name, kind, iface, rungs=None, st=None, il=None, ret=None):
    I = '      '
    parts = [f'{I}<pou name={quoteattr(name)} pouType="{kind}">', f'{I}  <interface>']
    if ret:
        parts.append(f'{I}    <returnType>{type_xml(ret)}</returnType>')
    for section in ['inputVars', 'outputVars', 'inOutVars', 'localVars', 'tempVars', 'externalVars']:
        if section in iface:
            parts.append(vars_xml(section, iface[section], I + '    '))
    parts.append(f'{I}  </interface>')
    parts.append(f'{I}  <body>')
    if rungs is not None:
        parts.append(f'{I}    <LD>\n{body_xml(rungs)}\n{I}    </LD>')
    elif st is not None:
        parts.append(f'{I}    <ST>\n{I}      <xhtml:p><![CDATA[{st}]]></xhtml:p>\n{I}    </ST>')
    elif il is not None:
        parts.append(f'{I}    <IL>\n{I}      <xhtml:p><![CDATA[{il}]]></xhtml:p>\n{I}    </IL>')
    parts.append(f'{I}  </body>')
    parts.append(f'{I}</pou>')
    return '\n'.join(parts)


NS = {
    '2.01': 'http://www.plcopen.org/xml/tc6_0201',
    '1.0': 'http://www.plcopen.org/xml/tc6.xsd',
}


def project(name, pous, version='2.01', program=None, interval='T#10ms', globals_=None,
            comment=None, types=''):
    """The whole file. `comment` goes in an XML comment after the declaration;
    `types` is the raw XML of `<dataType>` elements."""
    ns = NS[version]
    inst_attr = 'typeName' if version == '2.01' else 'type'
    head = "<?xml version='1.0' encoding='utf-8'?>\n"
    if comment:
        head += '<!--\n' + comment.strip('\n') + '\n-->\n'
    g = ''
    if globals_:
        g = '\n' + vars_xml('globalVars', globals_, '        ')
    prog = program or name
    return f'''{head}<project xmlns="{ns}" xmlns:xhtml="http://www.w3.org/1999/xhtml" xmlns:xsd="http://www.w3.org/2001/XMLSchema">
  <fileHeader companyName="plcc" productName="plcc ladder tests" productVersion="1" creationDateTime="2024-05-01T10:00:00"/>
  <contentHeader name="{name}" modificationDateTime="2024-05-01T10:00:00">
    <coordinateInfo>
      <fbd><scaling x="10" y="10"/></fbd>
      <ld><scaling x="10" y="10"/></ld>
      <sfc><scaling x="10" y="10"/></sfc>
    </coordinateInfo>
  </contentHeader>
  <types>
    <dataTypes>{types}</dataTypes>
    <pous>
{chr(10).join(pous)}
    </pous>
  </types>
  <instances>
    <configurations>
      <configuration name="config">
        <resource name="resource1">
          <task name="cyclic" priority="0" interval="{interval}">
            <pouInstance name="instance0" {inst_attr}="{prog}"/>
          </task>
        </resource>{g}
      </configuration>
    </configurations>
  </instances>
</project>
'''


if __name__ == '__main__':
    sys.exit('import this module from a description script')
