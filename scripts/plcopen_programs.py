#!/usr/bin/env python3
"""The PLCopen test programs of tests/programs/plcopen/, drawn element by element.

    python3 scripts/plcopen_programs.py [tests/programs/plcopen]

writes NAME.xml for every program below (LD and FBD bodies, configurations with
several tasks), laid out as Beremiz / OpenPLC Editor lay them out. The scenarios
(NAME.expect) beside them are written by hand, each with the computation of its
expected values from the diagram's meaning under IEC 61131-3: every element is
evaluated once per scan, in data-flow order, networks top to bottom; the power on
an input is the OR of its wires; a coil passes its power on.

These programs have no IL twin (tests/programs/ld/ keeps its twins): e2e.rs runs
them on every machine like any other program under tests/programs/.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plcopen_gen import Body, pou, project  # noqa: E402

PROGRAMS = {}


def program(name, comment, pous, **kw):
    PROGRAMS[name] = project(name, comment, pous, **kw)


def bools(names):
    return [(n, 'BOOL') for n in names.split()]


def ints(names):
    return [(n, 'INT') for n in names.split()]


# ================================================================ LD

# ---------------------------------------------------------------- bridge
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'a', 1, 80, 40)
b.contact(3, 'b', 1, 80, 120)
b.contact(4, 'e', 2, 160, 80)          # the bridge: from a's side down to d
b.contact(5, 'c', 2, 240, 40)
b.contact(6, 'd', [3, 4], 240, 120)    # two sources (b, e) ...
b.coil(7, 'q1', [5, 6], 360, 40)       # ... and two sinks (q1, q2)
b.coil(8, 'q2', 6, 360, 120)
b.right_rail(9, 440, 20, [7, 8])
program('ld_bridge', '''
A bridge (not a series-parallel network): contact e joins the output of a to the
input of d, and d has two sources (b, e) and two sinks (q1, q2). Power flows only
from left to right along the wires, never backwards through e.''',
        [pou('ld_bridge', 'program', {'localVars': bools('a b c d e q1 q2')}, b)])

# ---------------------------------------------------------------- coils on the rail
b = Body('LD')
b.rail(1, 20, 20)
b.coil(2, 'on', 1, 300, 40)
b.coil(3, 'off', 1, 300, 80, neg=True)
b.coil(4, 'st', 1, 300, 120, storage='set')
b.coil(5, 'rs', 1, 300, 160, storage='reset')
b.contact(7, 'a', 1, 80, 240)
b.coil(6, 'q2', [1, 7], 300, 200)      # the rail in parallel with a
b.contact(8, 'c', [1, 7], 200, 280)    # c fed by the rail and by a
b.coil(9, 'q3', 8, 300, 280)
b.right_rail(10, 400, 20, [2, 3, 4, 5, 6, 9])
program('ld_rail_coils', '''
Coils wired straight to the left rail: a plain coil is TRUE on every scan, a negated
one FALSE, a set coil sets, a reset coil resets. A coil fed by the rail and by a
contact is always TRUE; a contact fed by the rail and by a contact passes its own
variable.''', [pou('ld_rail_coils', 'program', {
    'localVars': bools('a c on off st rs q2 q3')}, b)])

# ---------------------------------------------------------------- coil chains, one wire
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'a', 1, 60, 40)
b.coil(3, 'x', 2, 120, 40)
b.contact(4, 'b', 3, 180, 40)
b.coil(5, 'y', 4, 240, 40)
b.coil(6, 'z', 5, 300, 40)
b.contact(7, 'a', 1, 60, 100)
b.coil(8, 'n', 7, 120, 100, neg=True)
b.contact(9, 'h', 8, 180, 100)
b.coil(10, 'w', 9, 240, 100)
b.contact(11, 'a', 1, 60, 160)
b.coil(12, 'k', 11, 120, 160)
b.contact(13, 'k', 12, 180, 160)       # reads k after the coil before it wrote it
b.coil(14, 'r', 13, 240, 160)
b.right_rail(15, 360, 20, [6, 10, 14])
program('ld_coil_chain', '''
Coils in series, each with one incoming wire: a coil passes its power on to the
contacts and coils after it; a negated coil writes the inverse but passes on its
power unchanged; a contact after a coil of its own variable reads the value the coil
has just written (the coil is evaluated first).''', [pou('ld_coil_chain', 'program', {
    'localVars': bools('a b h x y z n w k r')}, b)])

# ---------------------------------------------------------------- coil chains, two wires
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'f', 1, 60, 40)
b.contact(3, 'g', 1, 60, 80)
b.coil(4, 'q2', [2, 3], 140, 40)       # two incoming wires
b.coil(5, 'q3', 4, 220, 40)
b.contact(6, 'h', 4, 220, 80)
b.coil(7, 'q4', 6, 300, 80)
b.contact(8, 'f', 1, 60, 140)
b.contact(9, 'g', 1, 60, 180)
b.contact(10, 'h', 1, 60, 220)
b.coil(11, 'm', [8, 9, 10], 140, 140)  # three incoming wires
b.contact(12, 'g', 11, 220, 140, neg=True)
b.coil(13, 'q5', 12, 300, 140)
b.right_rail(14, 380, 20, [5, 7, 13])
program('ld_coil_chain_or', '''
Coils in series whose coil has several incoming wires: the power it passes on is
the OR of its wires (the power on its input), the same value it writes.''',
        [pou('ld_coil_chain_or', 'program', {'localVars': bools('f g h q2 q3 q4 m q5')}, b)])

# ---------------------------------------------------------------- contacts with no input
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'a', None, 80, 40)        # <connectionPointIn/> without a connection
b.coil(3, 'q', 2, 200, 40)
b.contact(4, 'b', None, 80, 100)
b.contact(5, 'c', 4, 140, 100)
b.coil(6, 'r', 5, 200, 100)
b.contact(7, 'd', 1, 80, 160)
b.coil(8, 's', 7, 200, 160)
b.right_rail(9, 280, 20, [3, 6, 8])
program('ld_unconnected_contact', '''
Contacts whose connectionPointIn lists no connection: the contact takes the left
rail (a warning says so), so it passes its own variable.''',
        [pou('ld_unconnected_contact', 'program', {'localVars': bools('a b c d q r s')}, b)])

# ---------------------------------------------------------------- edge contacts, two coils
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'btn', 1, 60, 40, edge='rising')
b.coil(3, 'p1', 2, 200, 40)
b.coil(4, 'btn', 2, 200, 80, storage='reset')   # clears the contact's variable
b.coil(5, 'p2', 2, 200, 120)
b.contact(6, 'sw', 1, 60, 180, edge='falling')
b.coil(7, 'f1', 6, 140, 180)
b.coil(8, 'f2', 7, 200, 180)
b.right_rail(9, 280, 20, [3, 4, 5, 8])
program('ld_edge_two_coils', '''
A rising contact feeding three coils in parallel, one of which resets the contact's
own variable: the contact is evaluated once, so both pulse coils see the same pulse.
A falling contact feeding two coils in series: both see the same pulse.''',
        [pou('ld_edge_two_coils', 'program', {'localVars': bools('btn sw p1 p2 f1 f2')}, b)])

# ---------------------------------------------------------------- coil modifiers
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 's', 1, 60, 40)
b.coil(3, 'm', 2, 200, 40, storage='set')
b.contact(4, 'r', 1, 60, 80)
b.coil(5, 'm', 4, 200, 80, storage='reset')
b.contact(6, 'a', 1, 60, 120)
b.coil(7, 'n', 6, 200, 120, neg=True)
b.contact(8, 'a', 1, 60, 160)
b.coil(9, 'pr', 8, 200, 160, edge='rising')
b.contact(10, 'a', 1, 60, 200)
b.coil(11, 'pf', 10, 200, 200, edge='falling')
b.right_rail(12, 280, 20, [3, 5, 7, 9, 11])
program('ld_coil_modifiers', '''
Set, reset, negated, rising and falling coils, each in its own rung; the reset rung
is below the set rung, so it wins when both are powered.''',
        [pou('ld_coil_modifiers', 'program', {'localVars': bools('s r a m n pr pf')}, b)])

# ---------------------------------------------------------------- TON in a rung
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'start', 1, 60, 50)
b.invar(3, 'T#30ms', 60, 90)
b.block(4, 'TON', 160, 20, [('IN', 2), ('PT', 3)], ['Q', 'ET'], inst='T1')
b.coil(5, 'done', (4, 'Q'), 300, 42)
b.outvar(6, 'et', (4, 'ET'), 300, 80)
b.right_rail(7, 380, 20, [5])
program('ld_ton_rung', '''
An on-delay timer in a rung: IN from a contact, PT from a literal, Q to a coil, ET to
an output variable.''', [pou('ld_ton_rung', 'program', {
    'localVars': [('start', 'BOOL'), ('done', 'BOOL'), ('et', 'TIME'), ('T1', 'TON')]}, b)])

# ---------------------------------------------------------------- CTU with EN
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'enable', 1, 60, 50)
b.contact(3, 'pulse', 1, 60, 70)
b.contact(4, 'reset', 1, 60, 90)
b.invar(5, '3', 100, 110)
b.block(6, 'CTU', 160, 20, [('EN', 2), ('CU', 3), ('R', 4), ('PV', 5)],
        ['ENO', 'Q', 'CV'], inst='C1')
b.coil(7, 'ran', (6, 'ENO'), 300, 42)
b.coil(8, 'done', (6, 'Q'), 300, 62)
b.outvar(9, 'count', (6, 'CV'), 300, 80)
b.right_rail(10, 380, 20, [7, 8])
program('ld_ctu_en', '''
An up counter with EN in a rung: while EN is FALSE the instance is not called (its
outputs and its edge memory of CU keep their values, ENO is FALSE), so a CU that rose
while disabled counts when EN comes back. A coil on ENO.''', [pou('ld_ctu_en', 'program', {
    'localVars': bools('enable pulse reset ran done') + [('count', 'INT'), ('C1', 'CTU')]}, b)])

# ---------------------------------------------------------------- ADD with EN
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'inc', 1, 60, 50)
b.invar(3, 'total', 60, 70)
b.invar(4, '5', 60, 90)
b.block(5, 'ADD', 160, 20, [('EN', 2), ('IN1', 3), ('IN2', 4)], ['ENO', 'OUT'])
b.coil(6, 'added', (5, 'ENO'), 300, 42)
b.outvar(7, 'total', (5, 'OUT'), 300, 60)
b.right_rail(8, 380, 20, [6])
program('ld_add_en', '''
ADD with its EN wired from a contact: the output variable is written only when the
function ran; a coil on ENO.''', [pou('ld_add_en', 'program', {
    'localVars': bools('inc added') + ints('total')}, b)])

# ---------------------------------------------------------------- feedback through blocks
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 's', 1, 60, 50)
b.block(3, 'SR', 160, 20, [('S1', 2), ('R', (3, 'Q1'), {'neg': True})], ['Q1'], inst='SR0')
b.coil(4, 'q', (3, 'Q1'), 300, 42)
b.invar(5, '1', 60, 170)
b.block(6, 'ADD', 160, 120, [('EN', 1), ('IN1', 5), ('IN2', (6, 'OUT'))], ['ENO', 'OUT'])
b.coil(7, 'tick', (6, 'ENO'), 300, 142)
b.outvar(8, 'n', (6, 'OUT'), 300, 160)
b.right_rail(9, 380, 20, [4, 7])
program('ld_block_feedback', '''
Feedback through blocks in LD: SR0's Q1 wired back, negated, to its own R (R reads
the previous scan's Q1); ADD's OUT wired back to its own IN2, enabled from the rail,
adds 1 on every scan.''', [pou('ld_block_feedback', 'program', {
    'localVars': bools('s q tick') + ints('n') + [('SR0', 'SR')]}, b)])

# ---------------------------------------------------------------- jumps (TC6 1.0)
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'skip', 1, 60, 40)
b.jump(3, 'L1', 2, 200, 40)
b.contact(4, 'a', 1, 60, 100)
b.coil(5, 'x', 4, 200, 100)
b.invar(6, 'cnt', 60, 180)
b.invar(7, '1', 60, 200)
b.block(8, 'ADD', 120, 140, [('EN', 1), ('IN1', 6), ('IN2', 7)], ['ENO', 'OUT'])
b.outvar(9, 'cnt', (8, 'OUT'), 240, 180)
b.label(10, 'L1', 20, 260)
b.contact(11, 'a', 1, 60, 300)
b.coil(12, 'z', 11, 200, 300)
b.right_rail(13, 280, 20, [5, 12])
program('ld_jump', '''
A jump over two rungs to a label (TC6 1.0 namespace): while skip is on, the rungs
between the jump and the label do not run.''', [pou('ld_jump', 'program', {
    'localVars': bools('skip a x z') + ints('cnt')}, b)], version='1.0')

# ---------------------------------------------------------------- return (no positions)
b = Body('LD', positions=False)
b.rail(1, 0, 0)
b.contact(2, 'a', 1, 0, 0)
b.coil(3, 'x', 2, 0, 0)
b.contact(4, 'stop', 1, 0, 0)
b.ret(5, 4, 0, 0)
b.invar(6, 'cnt', 0, 0)
b.invar(7, '1', 0, 0)
b.block(8, 'ADD', 0, 0, [('EN', 1), ('IN1', 6), ('IN2', 7)], ['ENO', 'OUT'])
b.outvar(9, 'cnt', (8, 'OUT'), 0, 0)
b.contact(10, 'a', 1, 0, 0)
b.coil(11, 'y', 10, 0, 0)
program('ld_return', '''
A RETURN in a rung, in a file without positions (the rungs run in document order):
while stop is on, the rungs after the return do not run.''', [pou('ld_return', 'program', {
    'localVars': bools('a stop x y') + ints('cnt')}, b)])

# ---------------------------------------------------------------- connectors in LD
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'a', 1, 60, 40)
b.contact(3, 'b', 2, 120, 40)
b.connector(4, 'AB', 3, 200, 38)
b.continuation(5, 'AB', 20, 100)
b.contact(6, 'c', 5, 120, 102)
b.coil(7, 'x', 6, 240, 102)
b.continuation(8, 'AB', 20, 160)
b.coil(9, 'y', 8, 240, 162)
b.contact(10, 'c', 1, 60, 220)
b.contact(11, 'd', 1, 60, 260)
b.connector(12, 'CD', [10, 11], 200, 218)
b.continuation(13, 'CD', 20, 320)
b.coil(14, 'w', 13, 240, 322)
b.right_rail(15, 320, 20, [7, 9, 14])
program('ld_connectors', '''
Connectors and continuations in LD: the power reaching connector AB (a AND b) goes on
from two continuations; connector CD is fed by two wires (c OR d).''',
        [pou('ld_connectors', 'program', {'localVars': bools('a b c d x y w')}, b)])

# ---------------------------------------------------------------- rung order by position
b = Body('LD')
b.rail(1, 20, 20)
# written bottom-up in the document; the positions put them top-down W, A, B, C
b.contact(2, 'n', 1, 60, 220)
b.coil(3, 'p', 2, 200, 220)          # C
b.contact(4, 'm', 1, 60, 160)
b.coil(5, 'n', 4, 200, 160)          # B
b.contact(6, 'a', 1, 60, 100)
b.coil(7, 'm', 6, 200, 100)          # A
b.contact(8, 'p', 1, 60, 40)
b.coil(9, 'w', 8, 200, 40)           # W, the top rung, reads p written by C below
b.right_rail(10, 280, 20, [3, 5, 7, 9])
program('ld_rung_order', '''
Rungs run top to bottom by position, whatever their order in the file (here the
reverse): a rung reading a coil of a rung above sees this scan's value, a rung
reading a coil of a rung below sees the previous scan's.''',
        [pou('ld_rung_order', 'program', {'localVars': bools('a m n p w')}, b)])

# ---------------------------------------------------------------- TON read by a contact
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'start', 1, 60, 50)
b.invar(3, 'T#30ms', 60, 70)
b.block(4, 'TON', 160, 20, [('IN', 2), ('PT', 3)], ['Q', 'ET'], inst='T0')
b.contact(5, 'T0.Q', 1, 60, 140)
b.coil(6, 'lamp', 5, 200, 140)
b.contact(7, 'T0.Q', 1, 60, 180, neg=True)
b.coil(8, 'idle', 7, 200, 180)
b.right_rail(9, 300, 20, [(4, 'Q'), 6, 8])
program('ld_ton_contact', '''
A TON in the top rung with nothing wired to its outputs but the right rail; the rungs
below read it through contacts `T0.Q`. The top rung runs first, so lamp follows T0.Q
in the same scan.''', [pou('ld_ton_contact', 'program', {
    'localVars': bools('start lamp idle') + [('T0', 'TON')]}, b)])

# ---------------------------------------------------------------- executionOrderId in LD
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'en', 1, 60, 40, order=1)
b.contact(3, 'v', 2, 140, 40, order=4)      # drawn on top, but runs after coil v
b.coil(4, 'w', 3, 240, 40, order=5)
b.contact(5, 'a', 2, 140, 100, order=2)
b.coil(6, 'v', 5, 240, 100, order=3)
b.right_rail(7, 320, 20, [4, 6])
program('ld_exec_order', '''
executionOrderId in an LD rung: the two branches after en are independent, and the
ids make the lower branch (a, coil v) run before the upper one (contact v, coil w),
so w sees this scan's v.''',
        [pou('ld_exec_order', 'program', {'localVars': bools('en a v w')}, b)])


# ================================================================ FBD

# ---------------------------------------------------------------- arithmetic
b = Body('FBD')
b.invar(1, 'a', 20, 40)
b.invar(2, 'b', 20, 80)
b.block(3, 'ADD', 100, 20, [('IN1', 1), ('IN2', 2)], ['OUT'])
b.invar(4, 'c', 100, 110)
b.block(5, 'MUL', 200, 20, [('IN1', (3, 'OUT')), ('IN2', 4)], ['OUT'])
b.invar(6, '7', 200, 110)
b.block(7, 'SUB', 300, 20, [('IN1', (5, 'OUT')), ('IN2', 6)], ['OUT'])
b.outvar(8, 'r1', (7, 'OUT'), 420, 40)
b.invar(9, '2', 300, 150)
b.block(10, 'DIV', 420, 100, [('IN1', (7, 'OUT')), ('IN2', 9)], ['OUT'])
b.outvar(11, 'r2', (10, 'OUT'), 520, 120)
b.invar(12, 'a', 20, 220)
b.invar(13, 'b', 20, 250)
b.invar(14, 'c', 20, 280)
b.block(15, 'ADD', 100, 200, [('IN1', 12), ('IN2', 13), ('IN3', 14)], ['OUT'])
b.outvar(16, 'r3', (15, 'OUT'), 220, 220)
b.invar(17, 'a', 20, 340)
b.invar(18, '4', 20, 370)
b.block(19, 'MOD', 100, 320, [('IN1', 17), ('IN2', 18)], ['OUT'])
b.outvar(20, 'r4', (19, 'OUT'), 220, 340)
program('fbd_arith', '''
Arithmetic functions in FBD: a chain ADD -> MUL -> SUB, its result also divided by 2
(DIV truncates toward zero), an ADD with three inputs, MOD.''',
        [pou('fbd_arith', 'program', {'localVars': ints('a b c r1 r2 r3 r4')}, b)])

# ---------------------------------------------------------------- selection
b = Body('FBD')
b.invar(1, 'g', 20, 40)
b.invar(2, 'x', 20, 60)
b.invar(3, 'lo', 20, 80)
b.block(4, 'SEL', 100, 20, [('G', 1), ('IN0', 2), ('IN1', 3)], ['OUT'])
b.outvar(5, 'y_sel', (4, 'OUT'), 220, 40)
b.invar(6, 'lo', 20, 140)
b.invar(7, 'x', 20, 160)
b.invar(8, 'hi', 20, 180)
b.block(9, 'LIMIT', 100, 120, [('MN', 6), ('IN', 7), ('MX', 8)], ['OUT'])
b.outvar(10, 'y_lim', (9, 'OUT'), 220, 140)
b.invar(11, 'x', 20, 240)
b.invar(12, 'lo', 20, 260)
b.invar(13, 'hi', 20, 280)
b.block(14, 'MAX', 100, 220, [('IN1', 11), ('IN2', 12), ('IN3', 13)], ['OUT'])
b.outvar(15, 'y_max', (14, 'OUT'), 220, 240)
b.invar(16, 'x', 20, 340)
b.invar(17, 'hi', 20, 360)
b.block(18, 'MIN', 100, 320, [('IN1', 16), ('IN2', 17)], ['OUT'])
b.outvar(19, 'y_min', (18, 'OUT'), 220, 340)
b.invar(20, 'k', 20, 420)
b.invar(21, 'x', 20, 440)
b.invar(22, 'lo', 20, 460)
b.invar(23, 'hi', 20, 480)
b.block(24, 'MUX', 100, 400, [('K', 20), ('IN0', 21), ('IN1', 22), ('IN2', 23)], ['OUT'])
b.outvar(25, 'y_mux', (24, 'OUT'), 220, 420)
program('fbd_select', '''
Selection functions in FBD: SEL, LIMIT, MAX with three inputs, MIN, MUX.''',
        [pou('fbd_select', 'program', {'localVars': [
            ('g', 'BOOL'), ('x', 'INT'), ('lo', 'INT', '10'), ('hi', 'INT', '100'),
            ('k', 'INT')] + ints('y_sel y_lim y_max y_min y_mux')}, b)])

# ---------------------------------------------------------------- comparisons and logic
b = Body('FBD')
b.invar(1, 'x', 20, 40)
b.invar(2, 'y', 20, 60)
b.block(3, 'GT', 100, 20, [('IN1', 1), ('IN2', 2)], ['OUT'])
b.outvar(4, 'o_gt', (3, 'OUT'), 340, 20)
b.invar(5, 'b', 100, 100)
b.block(6, 'AND', 200, 60, [('IN1', (3, 'OUT')), ('IN2', 5)], ['OUT'])
b.outvar(7, 'o_and', (6, 'OUT'), 340, 80)
b.block(8, 'XOR', 200, 130, [('IN1', (3, 'OUT')), ('IN2', 5)], ['OUT'])
b.outvar(9, 'o_xor', (8, 'OUT'), 340, 150)
b.invar(10, 'x', 20, 240)
b.invar(11, 'y', 20, 260)
b.block(12, 'EQ', 100, 220, [('IN1', 10), ('IN2', 11)], ['OUT'])
b.outvar(13, 'o_eq', (12, 'OUT'), 340, 220)
b.block(14, 'OR', 200, 240, [('IN1', (12, 'OUT')), ('IN2', 5), ('IN3', (3, 'OUT'))], ['OUT'])
b.outvar(15, 'o_or', (14, 'OUT'), 340, 270)
b.block(16, 'NOT', 200, 340, [('IN', 5)], ['OUT'])
b.outvar(17, 'o_not', (16, 'OUT'), 340, 370)
b.invar(18, 'x', 20, 440)
b.invar(19, 'y', 20, 460)
b.block(20, 'NE', 100, 420, [('IN1', 18), ('IN2', 19)], ['OUT'])
b.outvar(21, 'o_ne', (20, 'OUT'), 340, 440)
b.invar(22, 'x', 20, 520)
b.invar(23, 'y', 20, 540)
b.block(24, 'LE', 100, 500, [('IN1', 22), ('IN2', 23)], ['OUT'])
b.outvar(25, 'o_le', (24, 'OUT'), 340, 520)
program('fbd_logic', '''
Comparisons and Boolean functions in FBD: GT, EQ, NE, LE; AND, XOR and a
three-input OR fed by comparison outputs; NOT. One input variable (b) and one
comparison output (GT) each feed several blocks.''', [pou('fbd_logic', 'program', {
    'localVars': ints('x y') + bools('b o_gt o_eq o_and o_or o_not o_xor o_ne o_le')}, b)])

# ---------------------------------------------------------------- conversions
b = Body('FBD')
b.invar(1, 'i', 20, 40)
b.block(2, 'INT_TO_REAL', 80, 20, [('IN', 1)], ['OUT'])
b.invar(3, 'k', 80, 90)
b.block(4, 'MUL', 230, 20, [('IN1', (2, 'OUT')), ('IN2', 3)], ['OUT'])
b.outvar(5, 'o_real', (4, 'OUT'), 460, 40)
b.block(6, 'REAL_TO_INT', 320, 80, [('IN', (4, 'OUT'))], ['OUT'])
b.outvar(7, 'o_int', (6, 'OUT'), 460, 110)
program('fbd_convert', '''
Type conversions in FBD: INT_TO_REAL, a REAL product, REAL_TO_INT (rounds to the
nearest integer).''', [pou('fbd_convert', 'program', {
    'localVars': [('i', 'INT'), ('k', 'REAL', '2.25'), ('o_real', 'REAL'), ('o_int', 'INT')]}, b)])

# ---------------------------------------------------------------- timers
b = Body('FBD')
b.invar(1, 'go', 20, 40)
b.invar(2, 'T#30ms', 20, 60)
b.block(3, 'TON', 120, 20, [('IN', 1), ('PT', 2)], ['Q', 'ET'], inst='T1')
b.outvar(4, 'qon', (3, 'Q'), 240, 40)
b.outvar(5, 'eton', (3, 'ET'), 240, 60)
b.invar(6, 'go', 20, 140)
b.invar(7, 'T#20ms', 20, 160)
b.block(8, 'TOF', 120, 120, [('IN', 6), ('PT', 7)], ['Q', 'ET'], inst='T2')
b.outvar(9, 'qoff', (8, 'Q'), 240, 140)
b.invar(10, 'go', 20, 240)
b.invar(11, 'T#20ms', 20, 260)
b.block(12, 'TP', 120, 220, [('IN', 10), ('PT', 11)], ['Q', 'ET'], inst='T3')
b.outvar(13, 'qp', (12, 'Q'), 240, 240)
program('fbd_timers', '''
The timers in FBD: TON, TOF and TP on one input, with literal preset times.''',
        [pou('fbd_timers', 'program', {'localVars': bools('go qon qoff qp') + [
            ('eton', 'TIME'), ('T1', 'TON'), ('T2', 'TOF'), ('T3', 'TP')]}, b)])

# ---------------------------------------------------------------- counters
b = Body('FBD')
b.invar(1, 'up', 20, 40)
b.invar(2, 'rst', 20, 60)
b.invar(3, '3', 20, 80)
b.block(4, 'CTU', 120, 20, [('CU', 1, {'edge': 'rising'}), ('R', 2, {'edge': 'rising'}),
                             ('PV', 3)], ['Q', 'CV'], inst='C1')
b.outvar(5, 'cu_q', (4, 'Q'), 240, 40)
b.outvar(6, 'cu_cv', (4, 'CV'), 240, 60)
b.invar(7, 'down', 20, 160)
b.invar(8, 'ld', 20, 180)
b.invar(9, '2', 20, 200)
b.block(10, 'CTD', 120, 140, [('CD', 7), ('LD', 8), ('PV', 9)], ['Q', 'CV'], inst='C2')
b.outvar(11, 'cd_q', (10, 'Q'), 240, 160)
b.outvar(12, 'cd_cv', (10, 'CV'), 240, 180)
b.invar(13, 'up', 20, 280)
b.invar(14, 'down', 20, 300)
b.invar(15, 'rst', 20, 320)
b.invar(16, 'ld', 20, 340)
b.invar(17, '2', 20, 360)
b.block(18, 'CTUD', 120, 260, [('CU', 13), ('CD', 14), ('R', 15), ('LD', 16), ('PV', 17)],
        ['QU', 'QD', 'CV'], inst='C3')
b.outvar(19, 'qu', (18, 'QU'), 240, 280)
b.outvar(20, 'qd', (18, 'QD'), 240, 300)
b.outvar(21, 'cud_cv', (18, 'CV'), 240, 320)
program('fbd_counters', '''
The counters in FBD: CTU with rising-edge pins on CU and on R (R resets on the edge
of rst only), CTD, CTUD.''', [pou('fbd_counters', 'program', {
    'localVars': bools('up down rst ld cu_q cd_q qu qd') + ints('cu_cv cd_cv cud_cv')
    + [('C1', 'CTU'), ('C2', 'CTD'), ('C3', 'CTUD')]}, b)])

# ---------------------------------------------------------------- bistables and triggers
b = Body('FBD')
b.invar(1, 's', 20, 40)
b.invar(2, 'r', 20, 60)
b.block(3, 'SR', 120, 20, [('S1', 1), ('R', 2)], ['Q1'], inst='SR0')
b.outvar(4, 'qsr', (3, 'Q1'), 240, 40)
b.invar(5, 's', 20, 140)
b.invar(6, 'r', 20, 160)
b.block(7, 'RS', 120, 120, [('S', 5), ('R1', 6)], ['Q1'], inst='RS0')
b.outvar(8, 'qrs', (7, 'Q1'), 240, 140)
b.invar(9, 's', 20, 240)
b.block(10, 'R_TRIG', 120, 220, [('CLK', 9)], ['Q'], inst='RT')
b.outvar(11, 'rise', (10, 'Q'), 240, 240)
b.invar(12, 's', 20, 320)
b.block(13, 'F_TRIG', 120, 300, [('CLK', 12)], ['Q'], inst='FT')
b.outvar(14, 'fall', (13, 'Q'), 240, 320)
program('fbd_bistables', '''
SR (set dominant), RS (reset dominant), R_TRIG and F_TRIG in FBD, on the same two
inputs.''', [pou('fbd_bistables', 'program', {
    'localVars': bools('s r qsr qrs rise fall')
    + [('SR0', 'SR'), ('RS0', 'RS'), ('RT', 'R_TRIG'), ('FT', 'F_TRIG')]}, b)])

# ---------------------------------------------------------------- pin modifiers
b = Body('FBD')
b.invar(1, 'a', 20, 40)
b.invar(2, 'b', 20, 60)
b.block(3, 'AND', 100, 20, [('IN1', 1), ('IN2', 2, {'neg': True})], ['OUT'])
b.outvar(4, 'x1', (3, 'OUT'), 220, 40)
b.invar(5, 'a', 20, 140)
b.invar(6, 'b', 20, 160)
b.block(7, 'OR', 100, 120, [('IN1', 5), ('IN2', 6)], [('OUT', {'neg': True})])
b.outvar(8, 'x2', (7, 'OUT'), 220, 140)
b.invar(9, 'a', 20, 240)
b.invar(10, 'b', 20, 260)
b.block(11, 'AND', 100, 220, [('IN1', 9), ('IN2', 10)], [('OUT', {'edge': 'rising'})])
b.outvar(12, 'p1', (11, 'OUT'), 220, 230)
b.outvar(13, 'p2', (11, 'OUT'), 220, 260)
b.invar(14, 'a', 20, 340, neg=True)
b.outvar(15, 'x3', 14, 220, 340)
program('fbd_pins', '''
Negated and edge pins in FBD: a negated input, a negated output, a rising edge on a
block output feeding two variables (one detector: both get the same pulse), and a
negated input variable.''', [pou('fbd_pins', 'program', {
    'localVars': bools('a b x1 x2 x3 p1 p2')}, b)])

# ---------------------------------------------------------------- connectors (no positions)
b = Body('FBD', positions=False)
b.invar(1, 'a', 0, 0)
b.invar(2, 'b', 0, 0)
b.block(3, 'ADD', 0, 0, [('IN1', 1), ('IN2', 2)], ['OUT'])
b.connector(4, 'SUM', (3, 'OUT'), 0, 0)
b.continuation(5, 'SUM', 0, 0)
b.invar(6, 'c', 0, 0)
b.block(7, 'MUL', 0, 0, [('IN1', 5), ('IN2', 6)], ['OUT'])
b.outvar(8, 's1', (7, 'OUT'), 0, 0)
b.continuation(9, 'SUM', 0, 0)
b.invar(10, '10', 0, 0)
b.block(11, 'GT', 0, 0, [('IN1', 9), ('IN2', 10)], ['OUT'])
b.outvar(12, 'big', (11, 'OUT'), 0, 0)
b.continuation(13, 'SUM', 0, 0)
b.outvar(14, 's2', 13, 0, 0)
program('fbd_connectors', '''
A connector and three continuations in FBD, in a file without positions: the sum
a + b goes on to a product, a comparison and a variable.''',
        [pou('fbd_connectors', 'program', {'localVars': ints('a b c s1 s2') + bools('big')}, b)])

# ---------------------------------------------------------------- unwired function inputs
b = Body('FBD')
b.invar(1, 'x', 20, 60)
b.invar(2, 'hi', 20, 80)
b.block(3, 'LIMIT', 100, 20, [('MN', None), ('IN', 1), ('MX', 2)], ['OUT'])
b.outvar(4, 'lim', (3, 'OUT'), 220, 40)
b.invar(5, 'x', 20, 160)
b.invar(6, 'hi', 20, 180)
b.block(7, 'SEL', 100, 120, [('G', None), ('IN0', 5), ('IN1', 6)], ['OUT'])
b.outvar(8, 'y_sel', (7, 'OUT'), 220, 140)
b.invar(9, 'x', 20, 240)
b.block(10, 'ADD', 100, 220, [('IN1', 9), ('IN2', None)], ['OUT'])
b.outvar(11, 'y', (10, 'OUT'), 220, 240)
program('fbd_unwired_input', '''
Function inputs left unwired take their type's default: LIMIT with MN unwired limits
to [0, MX]; SEL with G unwired selects IN0; ADD with IN2 unwired adds 0.''',
        [pou('fbd_unwired_input', 'program', {'localVars': [
            ('x', 'INT'), ('hi', 'INT', '100')] + ints('lim y_sel y')}, b)])

# ---------------------------------------------------------------- EN / ENO on functions
b = Body('FBD')
b.invar(1, 'en', 20, 40)
b.invar(2, 'a', 20, 60)
b.invar(3, 'b', 20, 80)
b.block(4, 'ADD', 100, 20, [('EN', 1), ('IN1', 2), ('IN2', 3)], ['ENO', 'OUT'])
b.outvar(5, 's', (4, 'OUT'), 360, 140)
b.invar(6, '2', 100, 120)
b.block(7, 'MUL', 220, 20, [('EN', (4, 'ENO')), ('IN1', (4, 'OUT')), ('IN2', 6)],
        ['ENO', 'OUT'])
b.outvar(8, 'p', (7, 'OUT'), 360, 60)
program('fbd_en_eno', '''
EN/ENO on functions in FBD: ADD enabled by en, its ENO enabling MUL. A variable fed
by a function whose EN is FALSE is not written.''',
        [pou('fbd_en_eno', 'program', {'localVars': bools('en') + ints('a b s p')}, b)])

# ---------------------------------------------------------------- feedback
b = Body('FBD')
b.invar(1, 'inc', 20, 40)
b.block(2, 'ADD', 100, 20, [('IN1', 1), ('IN2', (2, 'OUT'))], ['OUT'])
b.outvar(3, 'n', (2, 'OUT'), 220, 40)
b.invar(4, 'T#30ms', 20, 160)
b.block(5, 'TON', 120, 120, [('IN', (5, 'Q'), {'neg': True}), ('PT', 4)], ['Q', 'ET'],
        inst='T0')
b.outvar(6, 'osc', (5, 'Q'), 240, 140)
program('fbd_feedback', '''
Feedback in FBD: ADD's output wired back to its own IN2 (adds inc on every scan);
a TON whose Q is wired back, negated, to its own IN (a pulse every 5 scans).''',
        [pou('fbd_feedback', 'program', {'localVars': [
            ('inc', 'INT', '1'), ('n', 'INT'), ('osc', 'BOOL'), ('T0', 'TON')]}, b)])

# ---------------------------------------------------------------- a loop of two blocks
b = Body('FBD')
b.invar(1, '1', 20, 40)
b.block(2, 'ADD', 100, 20, [('IN1', 1), ('IN2', (4, 'OUT'))], ['OUT'], order=2)
b.outvar(3, 'a_out', (2, 'OUT'), 360, 20)
b.block(4, 'MUL', 220, 80, [('IN1', (2, 'OUT')), ('IN2', 5)], ['OUT'], order=1)
b.invar(5, '2', 120, 140)
b.outvar(6, 'b_out', (4, 'OUT'), 360, 100)
program('fbd_loop_order', '''
A loop of two blocks, ADD -> MUL -> ADD, with executionOrderIds that make MUL (drawn
below and to the right) run first: MUL reads ADD's output of the previous scan.''',
        [pou('fbd_loop_order', 'program', {'localVars': ints('a_out b_out')}, b)])

# ---------------------------------------------------------------- executionOrderId
b = Body('FBD')
b.invar(1, 'k', 20, 40)
b.invar(2, 'y', 20, 80)
b.block(3, 'ADD', 120, 20, [('IN1', 1), ('IN2', 2)], ['OUT'], order=3)
b.outvar(4, 'x', (3, 'OUT'), 240, 40, order=4)
b.invar(5, 'x', 20, 180)
b.block(6, 'ADD', 120, 140, [('IN1', 1), ('IN2', 5)], ['OUT'], order=1)
b.outvar(7, 'y', (6, 'OUT'), 240, 160, order=2)
program('fbd_exec_order', '''
executionOrderId in one FBD network (two chains sharing the input variable k): the
lower chain (y := k + x) has the smaller ids, so it runs first, and the upper chain
(x := k + y) reads the y of this scan.''', [pou('fbd_exec_order', 'program', {
    'localVars': [('k', 'INT', '1')] + ints('x y')}, b)])

# ---------------------------------------------------------------- inOutVariable
b = Body('FBD')
b.invar(1, 'a', 20, 40)
b.invar(2, '1', 20, 60)
b.block(3, 'ADD', 100, 20, [('IN1', 1), ('IN2', 2)], ['OUT'])
b.inoutvar(4, 'm', (3, 'OUT'), 200, 40)
b.invar(5, '2', 200, 80)
b.block(6, 'MUL', 280, 20, [('IN1', 4), ('IN2', 5)], ['OUT'])
b.outvar(7, 'r', (6, 'OUT'), 400, 40)
b.invar(8, '1', 20, 180)
b.block(9, 'ADD', 100, 140, [('IN1', 10), ('IN2', 8)], ['OUT'])
b.inoutvar(10, 'cnt', (9, 'OUT'), 200, 160)
program('fbd_inout_var', '''
inOutVariable in FBD: m is written from ADD and read by MUL after it; cnt is written
from an ADD that reads cnt itself through the same element (counts every scan).''',
        [pou('fbd_inout_var', 'program', {'localVars': ints('a m r cnt')}, b)])

# ---------------------------------------------------------------- user FUNCTIONs
f1 = Body('FBD', positions=False)
f1.invar(1, 'x', 0, 0)
f1.invar(2, 'k', 0, 0)
f1.block(3, 'MUL', 0, 0, [('IN1', 1), ('IN2', 2)], ['OUT'])
f1.invar(4, '1', 0, 0)
f1.block(5, 'ADD', 0, 0, [('IN1', (3, 'OUT')), ('IN2', 4)], ['OUT'])
f1.outvar(6, 'SCALE3', (5, 'OUT'), 0, 0)
f2 = Body('FBD', positions=False)
f2.invar(1, 'v', 0, 0)
f2.invar(2, 'lo', 0, 0)
f2.block(3, 'GE', 0, 0, [('IN1', 1), ('IN2', 2)], ['OUT'])
f2.invar(4, 'v', 0, 0)
f2.invar(5, 'hi', 0, 0)
f2.block(6, 'LE', 0, 0, [('IN1', 4), ('IN2', 5)], ['OUT'])
f2.block(7, 'AND', 0, 0, [('IN1', (3, 'OUT')), ('IN2', (6, 'OUT'))], ['OUT'])
f2.outvar(8, 'IN_RANGE', (7, 'OUT'), 0, 0)
b = Body('FBD')
b.invar(1, 'a', 20, 40)
b.invar(2, 'kk', 20, 60)
b.block(3, 'SCALE3', 100, 20, [('x', 1), ('k', 2)], ['OUT'])
b.outvar(4, 'r', (3, 'OUT'), 360, 40)
b.invar(5, '0', 120, 100)
b.invar(6, '20', 120, 120)
b.block(7, 'IN_RANGE', 220, 60, [('v', (3, 'OUT')), ('lo', 5), ('hi', 6)], ['OUT'])
b.outvar(8, 'ok', (7, 'OUT'), 360, 90)
program('fbd_user_function', '''
User FUNCTIONs with FBD bodies (without positions) called from an FBD program:
SCALE3(x, k) = x * k + 1, IN_RANGE(v, lo, hi) = v >= lo AND v <= hi. A function's
result is the output variable named after it.''', [
    pou('SCALE3', 'function', {'returnType': 'INT', 'inputVars': ints('x k')}, f1),
    pou('IN_RANGE', 'function', {'returnType': 'BOOL', 'inputVars': ints('v lo hi')}, f2),
    pou('fbd_user_function', 'program', {'localVars': ints('a kk r') + bools('ok')}, b)])

# ---------------------------------------------------------------- user FUNCTION_BLOCK
f = Body('FBD')
f.invar(1, 'x', 20, 40)
f.block(2, 'R_TRIG', 100, 20, [('CLK', 1)], ['Q'], inst='RT')
f.outvar(3, 'hit', (2, 'Q'), 420, 20)
f.invar(4, '0', 100, 100)
f.invar(5, 'step', 100, 120)
f.block(6, 'SEL', 200, 60, [('G', (2, 'Q')), ('IN0', 4), ('IN1', 5)], ['OUT'])
f.invar(7, 'n', 200, 160)
f.block(8, 'ADD', 300, 80, [('IN1', 7), ('IN2', (6, 'OUT'))], ['OUT'])
f.outvar(9, 'n', (8, 'OUT'), 420, 110)
b = Body('FBD')
b.invar(1, 'a', 20, 40)
b.invar(2, '1', 20, 60)
b.block(3, 'EDGE_COUNT', 100, 20, [('x', 1), ('step', 2)], ['n', 'hit'], inst='C1')
b.outvar(4, 'n1', (3, 'n'), 260, 40)
b.outvar(5, 'h1', (3, 'hit'), 260, 60)
b.invar(6, 'b', 20, 140)
b.invar(7, '10', 20, 160)
b.block(8, 'EDGE_COUNT', 100, 120, [('x', 6), ('step', 7)], ['n', 'hit'], inst='C2')
b.outvar(9, 'n2', (8, 'n'), 260, 140)
program('fbd_user_fb', '''
A user FUNCTION_BLOCK with an FBD body (an R_TRIG instance inside, SEL, ADD) counting
rising edges of x by step, used twice from an FBD program.''', [
    pou('EDGE_COUNT', 'functionBlock', {
        'inputVars': [('x', 'BOOL'), ('step', 'INT')],
        'outputVars': [('n', 'INT'), ('hit', 'BOOL')],
        'localVars': [('RT', 'R_TRIG')]}, f),
    pou('fbd_user_fb', 'program', {'localVars': bools('a b h1') + ints('n1 n2') + [
        ('C1', 'EDGE_COUNT'), ('C2', 'EDGE_COUNT')]}, b)])


# ================================================================ configurations

# ---------------------------------------------------------------- two tasks, one program
b = Body('FBD')
b.invar(1, 'n', 20, 40)
b.invar(2, '1', 20, 60)
b.block(3, 'ADD', 100, 20, [('IN1', 1), ('IN2', 2)], ['OUT'])
b.outvar(4, 'n', (3, 'OUT'), 220, 40)
b.invar(5, 'TRUE', 20, 140)
b.invar(6, 'T#90ms', 20, 160)
b.block(7, 'TON', 100, 120, [('IN', 5), ('PT', 6)], ['Q', 'ET'], inst='T1')
b.outvar(8, 'done', (7, 'Q'), 220, 140)
b.outvar(9, 'et', (7, 'ET'), 220, 160)
program('cfg_two_tasks', '''
Two tasks of 10 ms and 30 ms, each running an instance of the same program (a scan
counter and a 90 ms on-delay started at the first run): with a base tick of 10 ms
(the GCD of the intervals) the slow instance runs every 3rd tick, and its timer sees
30 ms pass between its runs.''', [pou('counter_prog', 'program', {
    'localVars': [('n', 'INT'), ('done', 'BOOL'), ('et', 'TIME'), ('T1', 'TON')]}, b)],
        tasks=[('fast', 'T#10ms', 0, [('fast', 'counter_prog')]),
               ('slow', 'T#30ms', 1, [('slow', 'counter_prog')])])

# ---------------------------------------------------------------- globals, a free instance
p = Body('FBD')
p.invar(1, 'g_count', 20, 40)
p.invar(2, '1', 20, 60)
p.block(3, 'ADD', 100, 20, [('IN1', 1), ('IN2', 2)], ['OUT'])
p.outvar(4, 'g_count', (3, 'OUT'), 220, 40)
c = Body('FBD')
c.invar(1, 'g_count', 20, 40)
c.outvar(2, 'snap', 1, 160, 40)
c.invar(3, 'runs', 20, 100)
c.invar(4, '1', 20, 120)
c.block(5, 'ADD', 100, 80, [('IN1', 3), ('IN2', 4)], ['OUT'])
c.outvar(6, 'runs', (5, 'OUT'), 220, 100)
c.invar(7, 'r_flag', 20, 180)
c.block(8, 'NOT', 100, 160, [('IN', 7)], ['OUT'])
c.outvar(9, 'r_flag', (8, 'OUT'), 220, 180)
w = Body('FBD')
w.invar(1, 'g_count', 20, 40)
w.outvar(2, 'w', 1, 160, 40)
program('cfg_globals', '''
A configuration global written by a program of a 10 ms task and read by a program of
a 20 ms task (declared after it, with a lower priority: it runs after the writer in
the ticks where both run) and by a program instance with no task (runs every tick,
after the tasks' programs); a resource global toggled by the 20 ms program.''', [
    pou('producer', 'program', {'externalVars': [('g_count', 'INT')]}, p),
    pou('consumer', 'program', {'externalVars': [('g_count', 'INT'), ('r_flag', 'BOOL')],
                                'localVars': ints('snap runs')}, c),
    pou('watcher', 'program', {'externalVars': [('g_count', 'INT')],
                               'localVars': ints('w')}, w)],
        tasks=[('fast', 'T#10ms', 0, [('prod', 'producer')]),
               ('slow', 'T#20ms', 1, [('cons', 'consumer')])],
        free_instances=[('watch', 'watcher')],
        config_globals=[('g_count', 'INT')], resource_globals=[('r_flag', 'BOOL')])

# ---------------------------------------------------------------- TC6 1.0 configuration
b = Body('LD')
b.rail(1, 20, 20)
b.contact(2, 'x', 1, 60, 40, neg=True)
b.coil(3, 'x', 2, 200, 40)
b.invar(4, 'cnt', 60, 120)
b.invar(5, '1', 60, 140)
b.block(6, 'ADD', 120, 80, [('EN', 1), ('IN1', 4), ('IN2', 5)], ['ENO', 'OUT'])
b.outvar(7, 'cnt', (6, 'OUT'), 240, 120)
b.right_rail(8, 280, 20, [3])
program('cfg_old_namespace', '''
A configuration in the TC6 1.0 namespace (tasks with the old interval format, 10 ms
and 30 ms): two instances of a ladder program that toggles x and counts its runs.''',
        [pou('toggler', 'program', {'localVars': bools('x') + ints('cnt')}, b)],
        version='1.0',
        tasks=[('fast', '00:00:00.010000', 0, [('f', 'toggler')]),
               ('slow', '00:00:00.030000', 1, [('s', 'toggler')])])

# ================================================================ once disagreements
# Programs whose hand-computed scenarios plcc did not pass at first (a loop cut
# against executionOrderId, ids across networks, a variable on ENO); fixed since.

# ---------------------------------------------------------------- ids across networks
b = Body('FBD')
b.invar(1, 'k', 20, 40)
b.invar(2, 'y', 20, 80)
b.block(3, 'ADD', 120, 20, [('IN1', 1), ('IN2', 2)], ['OUT'], order=3)
b.outvar(4, 'x', (3, 'OUT'), 240, 40, order=4)
b.invar(5, 'k', 20, 160)
b.invar(6, 'x', 20, 180)
b.block(7, 'ADD', 120, 140, [('IN1', 5), ('IN2', 6)], ['OUT'], order=1)
b.outvar(8, 'y', (7, 'OUT'), 240, 160, order=2)
program('fbd_exec_order_networks', '''
executionOrderId across two FBD networks: the lower network (y := k + x) has ids 1
and 2, the upper one (x := k + y) ids 3 and 4, so the lower one runs first.''',
        [pou('fbd_exec_order_networks', 'program', {
            'localVars': [('k', 'INT', '1')] + ints('x y')}, b)])

# ---------------------------------------------------------------- a variable on ENO
b = Body('FBD')
b.invar(1, 'en', 20, 40)
b.invar(2, 'a', 20, 60)
b.invar(3, 'b', 20, 80)
b.block(4, 'ADD', 100, 20, [('EN', 1), ('IN1', 2), ('IN2', 3)], ['ENO', 'OUT'])
b.outvar(5, 'ok', (4, 'ENO'), 240, 40)
b.outvar(6, 's', (4, 'OUT'), 240, 60)
program('fbd_eno_variable', '''
A variable wired to the ENO of a function: it takes ENO's value, FALSE when EN is
FALSE (the function's result variable is not written then).''',
        [pou('fbd_eno_variable', 'program', {
            'localVars': bools('en ok') + ints('a b s')}, b)])


if __name__ == '__main__':
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), '..', 'tests', 'programs', 'plcopen')
    os.makedirs(out, exist_ok=True)
    for name, text in PROGRAMS.items():
        with open(os.path.join(out, name + '.xml'), 'w') as f:
            f.write(text)
    print(f'{len(PROGRAMS)} programs written to {out}')
