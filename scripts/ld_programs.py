#!/usr/bin/env python3
"""The ladder test programs of tests/programs/ld/, described rung by rung.

    python3 scripts/ld_programs.py [tests/programs/ld]

writes NAME.xml for every program below (and the ladder example of examples/) (PLCopen TC6 XML, laid out as Beremiz
lays out a ladder). The scenarios (NAME.expect) and the IL twins (NAME.il) beside
them are written by hand, not generated: the twins are the IL a person writes for
the same logic, and tests/ld_equivalence.rs checks that both give the same IR.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ld_gen import B, C, J, LBL, NET, O, POWER, RAIL, RET, V, pou_xml, project  # noqa: E402

PROGRAMS = {}
EXAMPLES = {}


def program(name, version, comment, pous, **kw):
    PROGRAMS[name] = project(name, pous, version=version, comment=comment, **kw)


def example(name, version, comment, pous, **kw):
    EXAMPLES[name] = project(name, pous, version=version, comment=comment, **kw)


def bools(names):
    return [(n, 'BOOL') for n in names.split()]


# ---------------------------------------------------------------- motor start/stop
program('motor_start_stop', '2.01', '''
Motor start/stop with a seal-in contact, a normally closed stop button, an overload
that latches a fault, and a reset that clears it once the overload is gone. The
buttons and outputs are located I/O.''', [pou_xml('motor_start_stop', 'program', {
    'inputVars': [('start', 'BOOL', None, '%IX0.0'), ('stop', 'BOOL', None, '%IX0.1'),
                  ('overload', 'BOOL', None, '%IX0.2'), ('reset', 'BOOL', None, '%IX0.3')],
    'outputVars': [('run', 'BOOL', None, '%QX0.0'), ('lamp', 'BOOL', None, '%QX0.1'),
                   ('fault_lamp', 'BOOL', None, '%QX0.2')],
    'localVars': bools('fault'),
}, [
    ('S', ('P', C('start'), C('run')), C('stop', neg=True), C('fault', neg=True), O('run')),
    ('S', C('overload'), O('fault', storage='set')),
    ('S', C('reset'), C('overload', neg=True), O('fault', storage='reset')),
    ('S', C('run'), O('lamp')),
    ('S', C('fault'), O('fault_lamp')),
])])

# ---------------------------------------------------------------- traffic light
program('traffic_light', '2.01', '''
Traffic light with three on-delay timers: red 3 s, green 2 s, yellow 1 s, each phase
handing over to the next with set and reset coils; all lamps off when disabled.''', [
    pou_xml('traffic_light', 'program', {
        'inputVars': bools('enable'),
        'outputVars': bools('red yellow green'),
        'localVars': [('T_red', 'TON'), ('T_green', 'TON'), ('T_yellow', 'TON'),
                      ('red_time', 'TIME')],
    }, [
        ('S', C('enable'), C('red'),
         B('TON', 'T_red', ins=[('IN', POWER), ('PT', V('T#3s'))],
           outs=[('Q', POWER), ('ET', V('red_time'))]),
         ('P', O('green', storage='set'), O('red', storage='reset'))),
        ('S', C('enable'), C('green'),
         B('TON', 'T_green', ins=[('IN', POWER), ('PT', V('T#2s'))], outs=[('Q', POWER), ('ET', None)]),
         ('P', O('yellow', storage='set'), O('green', storage='reset'))),
        ('S', C('enable'), C('yellow'),
         B('TON', 'T_yellow', ins=[('IN', POWER), ('PT', V('T#1s'))], outs=[('Q', POWER), ('ET', None)]),
         ('P', O('red', storage='set'), O('yellow', storage='reset'))),
        ('S', C('enable'), C('red', neg=True), C('green', neg=True), C('yellow', neg=True),
         O('red', storage='set')),
        ('S', C('enable', neg=True),
         ('P', O('red', storage='reset'), O('green', storage='reset'), O('yellow', storage='reset'))),
    ])])

# ---------------------------------------------------------------- counter with reset
program('counter_reset', '1.0', '''
Counter with reset: a rising-edge contact counts pulses into a CTU (preset 5, reset
from its own network); a full count adds a batch (ADD with EN/ENO); a comparison
block enabled from the rail flags counts above 2.''', [pou_xml('counter_reset', 'program', {
    'inputVars': bools('pulse reset'),
    'outputVars': [('done', 'BOOL'), ('count', 'INT'), ('batches', 'INT'), ('added', 'BOOL'),
                   ('over2', 'BOOL')],
    'localVars': [('C1', 'CTU')],
}, [
    ('S', C('pulse', edge='rising'),
     B('CTU', 'C1', ins=[('CU', POWER), ('R', NET(('S', C('reset')))), ('PV', V('5'))],
       outs=[('Q', POWER), ('CV', V('count'))]),
     O('done')),
    ('S', C('done'),
     B('ADD', None, ins=[('EN', POWER), ('IN1', V('batches')), ('IN2', V('1'))],
       outs=[('ENO', POWER), ('OUT', V('batches'))]),
     O('added')),
    ('S', B('GT', None, ins=[('EN', RAIL), ('IN1', V('count')), ('IN2', V('2'))],
            outs=[('ENO', None), ('OUT', POWER)]),
     O('over2')),
])])

# ---------------------------------------------------------------- set / reset coils
program('set_reset', '2.01', '''
Set and reset coils: a latch set by one button and reset by another (the reset rung
comes later, so it wins when both are pressed), a lamp and a negated coil that follow
the latch, and a flag of both buttons pressed, cleared when both are released.''', [
    pou_xml('set_reset', 'program', {
        'inputVars': bools('set_pb reset_pb'),
        'outputVars': bools('latch lamp lamp_off conflict'),
    }, [
        ('S', C('set_pb'), O('latch', storage='set')),
        ('S', C('reset_pb'), O('latch', storage='reset')),
        ('S', C('latch'), ('P', O('lamp'), O('lamp_off', neg=True))),
        ('S', C('set_pb'), C('reset_pb'), O('conflict', storage='set')),
        ('S', C('conflict'), C('set_pb', neg=True), C('reset_pb', neg=True),
         O('conflict', storage='reset')),
    ])])

# ---------------------------------------------------------------- edge contacts
program('edge_contacts', '1.0', '''
Rising and falling contacts: one-scan pulses on each edge of a button, counted with
ADD blocks, and a rising contact behind an enable contact (its edge detector runs
every scan, enabled or not, so an edge seen while disabled is not seen again).''', [
    pou_xml('edge_contacts', 'program', {
        'inputVars': bools('btn enable'),
        'outputVars': [('rise_pulse', 'BOOL'), ('fall_pulse', 'BOOL'), ('gated', 'BOOL'),
                       ('rises', 'INT'), ('falls', 'INT')],
    }, [
        ('S', C('btn', edge='rising'), O('rise_pulse')),
        ('S', C('btn', edge='falling'), O('fall_pulse')),
        ('S', C('rise_pulse'),
         B('ADD', None, ins=[('EN', POWER), ('IN1', V('rises')), ('IN2', V('1'))],
           outs=[('ENO', None), ('OUT', V('rises'))])),
        ('S', C('fall_pulse'),
         B('ADD', None, ins=[('EN', POWER), ('IN1', V('falls')), ('IN2', V('1'))],
           outs=[('ENO', None), ('OUT', V('falls'))])),
        ('S', C('enable'), C('btn', edge='rising'), O('gated')),
    ])])

# ---------------------------------------------------------------- output trees
program('output_tree', '2.01', '''
Several coils on one rung: a fork into three branches after two contacts (the power
at the fork is kept in a temporary), a coil then a contact on the same line, and a
fork of a single contact (read again).''', [pou_xml('output_tree', 'program', {
    'inputVars': bools('a b c d'),
    'outputVars': bools('x y z p q r s'),
}, [
    ('S', C('a'), C('b'), ('P', ('S', C('c'), O('x')), ('S', C('d'), O('y')), O('z'))),
    ('S', C('a'), ('P', O('p'), ('S', C('b', neg=True), O('q')))),
    ('S', C('x'), ('P', ('S', C('y'), O('r')), ('S', C('z'), O('s')))),
])])

# ---------------------------------------------------------------- nested parallels
program('nested_parallel', '2.01', '''
Series and parallel connections nested: the seed's example ((x0 AND x1) OR x2 OR x3)
AND x5, a parallel block inside a branch of another, and two parallel blocks in
series.''', [pou_xml('nested_parallel', 'program', {
    'inputVars': bools('x0 x1 x2 x3 x5 a b c d e f g h i j'),
    'outputVars': bools('y1 v w'),
}, [
    ('S', ('P', ('S', C('x0'), C('x1')), C('x2'), C('x3')), C('x5'), O('y1')),
    ('S', ('P', ('S', C('a'), ('P', C('b'), ('S', C('c'), C('d')))), C('e')),
     C('f', neg=True), O('v')),
    ('S', ('P', C('g'), C('h')), ('P', C('i'), C('j')), O('w')),
])])

# ---------------------------------------------------------------- star-delta
program('star_delta', '2.01', '''
Star-delta starter: the main contactor seals in; a 2 s on-delay switches from star to
delta, each interlocked by a normally closed contact on the other (the rungs run top
to bottom, so delta sees star already off in the scan of the switch-over).''', [
    pou_xml('star_delta', 'program', {
        'inputVars': bools('start stop'),
        'outputVars': bools('main_k star_k delta_k'),
        'localVars': [('T1', 'TON'), ('switched', 'BOOL')],
    }, [
        ('S', ('P', C('start'), C('main_k')), C('stop', neg=True), O('main_k')),
        ('S', C('main_k'),
         B('TON', 'T1', ins=[('IN', POWER), ('PT', V('T#2s'))], outs=[('Q', POWER), ('ET', None)]),
         O('switched')),
        ('S', C('main_k'), C('switched', neg=True), C('delta_k', neg=True), O('star_k')),
        ('S', C('main_k'), C('switched'), C('star_k', neg=True), O('delta_k')),
    ])])

# ---------------------------------------------------------------- jumps and labels
program('jumps', '1.0', '''
A jump over two rungs: while bypass is on, the rungs between the jump and its label do
not run, so their coil keeps its value and the counter stands still.''', [
    pou_xml('jumps', 'program', {
        'inputVars': bools('bypass a'),
        'outputVars': [('x', 'BOOL'), ('z', 'BOOL'), ('count', 'INT')],
    }, [
        ('S', C('bypass'), J('skip')),
        ('S', C('a'), O('x')),
        ('S', C('a'),
         B('ADD', None, ins=[('EN', POWER), ('IN1', V('count')), ('IN2', V('1'))],
           outs=[('ENO', None), ('OUT', V('count'))])),
        LBL('skip'),
        ('S', C('x'), O('z')),
    ])])

# ---------------------------------------------------------------- a FUNCTION in ladder
program('function_ld', '2.01', '''
A FUNCTION written in ladder: GE and LE blocks in series (the first one's result is
the second one's EN), their result on a coil named after the function. The program
calls it as a block and drives two coils from it.''', [
    pou_xml('in_range', 'function', {
        'inputVars': [('x', 'INT'), ('lo', 'INT'), ('hi', 'INT')],
    }, [
        ('S', B('GE', None, ins=[('EN', RAIL), ('IN1', V('x')), ('IN2', V('lo'))],
                outs=[('ENO', None), ('OUT', POWER)]),
         B('LE', None, ins=[('EN', POWER), ('IN1', V('x')), ('IN2', V('hi'))],
           outs=[('ENO', None), ('OUT', POWER)]),
         O('in_range')),
    ], ret='BOOL'),
    pou_xml('function_ld', 'program', {
        'inputVars': [('level', 'INT')],
        'outputVars': bools('ok alarm'),
    }, [
        ('S', B('in_range', None, ins=[('x', V('level')), ('lo', V('10')), ('hi', V('90'))],
                outs=[('OUT', POWER)]),
         O('ok')),
        ('S', C('ok', neg=True), O('alarm')),
    ]),
], program='function_ld')

# ---------------------------------------------------------------- a FUNCTION_BLOCK in ladder
program('fb_ld', '2.01', '''
A FUNCTION_BLOCK written in ladder (a debounce: an on-delay timer whose preset is an
input of the block), used by the program through two instances with different
presets.''', [
    pou_xml('debounce', 'functionBlock', {
        'inputVars': [('raw', 'BOOL'), ('delay', 'TIME', 'T#50ms')],
        'outputVars': bools('clean'),
        'localVars': [('t', 'TON')],
    }, [
        ('S', C('raw'),
         B('TON', 't', ins=[('IN', POWER), ('PT', V('delay'))], outs=[('Q', POWER), ('ET', None)]),
         O('clean')),
    ]),
    pou_xml('fb_ld', 'program', {
        'inputVars': bools('in1 in2'),
        'outputVars': bools('out1 out2'),
        'localVars': [('d1', 'debounce'), ('d2', 'debounce')],
    }, [
        ('S', C('in1'), B('debounce', 'd1', ins=[('raw', POWER)], outs=[('clean', POWER)]),
         O('out1')),
        ('S', C('in2'),
         B('debounce', 'd2', ins=[('raw', POWER), ('delay', V('T#100ms'))], outs=[('clean', POWER)]),
         O('out2')),
    ]),
], program='fb_ld')

# ---------------------------------------------------------------- comparison blocks
program('compare_blocks', '1.0', '''
Comparison blocks enabled from the left rail drive the power flow: GT in series with a
contact, LT and GE setting and resetting a refill request (hysteresis), EQ on its own
coil.''', [pou_xml('compare_blocks', 'program', {
    'inputVars': [('level', 'INT'), ('pump_ok', 'BOOL')],
    'outputVars': bools('high_alarm refill equal_50'),
}, [
    ('S', B('GT', None, ins=[('EN', RAIL), ('IN1', V('level')), ('IN2', V('80'))],
            outs=[('ENO', None), ('OUT', POWER)]),
     C('pump_ok'), O('high_alarm')),
    ('S', B('LT', None, ins=[('EN', RAIL), ('IN1', V('level')), ('IN2', V('20'))],
            outs=[('ENO', None), ('OUT', POWER)]),
     O('refill', storage='set')),
    ('S', B('GE', None, ins=[('EN', RAIL), ('IN1', V('level')), ('IN2', V('60'))],
            outs=[('ENO', None), ('OUT', POWER)]),
     O('refill', storage='reset')),
    ('S', B('EQ', None, ins=[('EN', RAIL), ('IN1', V('level')), ('IN2', V('50'))],
            outs=[('ENO', None), ('OUT', POWER)]),
     O('equal_50')),
])])

# ---------------------------------------------------------------- LD, ST and IL in one file
program('mixed_bodies', '1.0', '''
Ladder, Structured Text and Instruction List in one file: a FUNCTION in ST (a 2-out-of-3
vote), a FUNCTION_BLOCK in IL (a latch), a ladder PROGRAM using both and a global of the
configuration, a data type (a subrange with an initial value) from the file's
dataTypes.''', [
    pou_xml('majority', 'function', {'inputVars': bools('a b c')}, ret='BOOL',
            st='majority := (a AND b) OR (a AND c) OR (b AND c);'),
    pou_xml('latch', 'functionBlock', {'inputVars': bools('s r'), 'outputVars': bools('q')},
            il='LD s\n        S q\n        LD r\n        R q'),
    pou_xml('mixed_bodies', 'program', {
        'inputVars': [('x', 'BOOL'), ('y', 'BOOL'), ('z', 'BOOL'), ('clear', 'BOOL'),
                      ('level', 'INT')],
        'outputVars': bools('vote held above'),
        'localVars': [('L1', 'latch'), ('sp', 'Percent')],
        'externalVars': bools('g_enable g_out'),
    }, [
        ('S', B('majority', None, ins=[('a', V('x')), ('b', V('y')), ('c', V('z'))],
                outs=[('OUT', POWER)]),
         O('vote')),
        ('S', C('vote'), B('latch', 'L1', ins=[('s', POWER), ('r', NET(('S', C('clear'))))],
                           outs=[('q', POWER)]),
         O('held')),
        ('S', C('held'), C('g_enable'), O('g_out')),
        ('S', B('GT', None, ins=[('EN', RAIL), ('IN1', V('level')), ('IN2', V('sp'))],
                outs=[('ENO', None), ('OUT', POWER)]),
         O('above')),
    ]),
], program='mixed_bodies', globals_=[('g_enable', 'BOOL', 'TRUE'), ('g_out', 'BOOL')],
    types='''
      <dataType name="Percent">
        <baseType>
          <subrangeSigned>
            <range lower="0" upper="100"/>
            <baseType><INT/></baseType>
          </subrangeSigned>
        </baseType>
        <initialValue><simpleValue value="50"/></initialValue>
      </dataType>
    ''')

# ---------------------------------------------------------------- TOF and TP
program('timers_tof_tp', '2.01', '''
Off-delay and pulse timers: a fan runs on for 500 ms after its motor stops (TOF); a horn
sounds for exactly 300 ms when its button is pressed, however long it is held (TP).''', [
    pou_xml('timers_tof_tp', 'program', {
        'inputVars': bools('motor horn_btn'),
        'outputVars': bools('fan horn'),
        'localVars': [('T_fan', 'TOF'), ('T_horn', 'TP')],
    }, [
        ('S', C('motor'),
         B('TOF', 'T_fan', ins=[('IN', POWER), ('PT', V('T#500ms'))], outs=[('Q', POWER), ('ET', None)]),
         O('fan')),
        ('S', C('horn_btn'),
         B('TP', 'T_horn', ins=[('IN', POWER), ('PT', V('T#300ms'))], outs=[('Q', POWER), ('ET', None)]),
         O('horn')),
    ])])

# ---------------------------------------------------------------- CTUD
program('updown_counter', '2.01', '''
An up/down counter with four power inputs from four networks (count up, count down,
reset, load the preset) and two power outputs (at the preset, at zero), its count
on an output variable.''', [pou_xml('updown_counter', 'program', {
    'inputVars': bools('up down reset load'),
    'outputVars': [('at_max', 'BOOL'), ('at_zero', 'BOOL'), ('count', 'INT')],
    'localVars': [('C', 'CTUD')],
}, [
    ('S', C('up'),
     B('CTUD', 'C', ins=[('CU', POWER), ('CD', NET(('S', C('down')))), ('R', NET(('S', C('reset')))),
                         ('LD', NET(('S', C('load')))), ('PV', V('3'))],
       outs=[('QU', POWER), ('QD', NET(('S', O('at_zero')))), ('CV', V('count'))]),
     O('at_max')),
])])

# ---------------------------------------------------------------- SR and RS
program('bistables', '1.0', '''
The bistable function blocks: SR (set dominant) and RS (reset dominant), each driven
by two contacts, their outputs on coils.''', [pou_xml('bistables', 'program', {
    'inputVars': bools('set1 reset1 set2 reset2'),
    'outputVars': bools('q_sr q_rs'),
    'localVars': [('L_sr', 'SR'), ('L_rs', 'RS')],
}, [
    ('S', C('set1'), B('SR', 'L_sr', ins=[('S1', POWER), ('R', NET(('S', C('reset1'))))],
                       outs=[('Q1', POWER)]),
     O('q_sr')),
    ('S', C('set2'), B('RS', 'L_rs', ins=[('S', POWER), ('R1', NET(('S', C('reset2'))))],
                       outs=[('Q1', POWER)]),
     O('q_rs')),
])])

# ---------------------------------------------------------------- coils in series
program('coil_chain', '2.01', '''
Coils in series: a coil passes its power on, so contacts after it see the power
before them ANDed with their own; a negated coil writes the inverse and passes the
power on unchanged; a set coil in the middle of a line.''', [pou_xml('coil_chain', 'program', {
    'inputVars': bools('a b c'),
    'outputVars': bools('x y z m n'),
}, [
    ('S', C('a'), O('x'), C('b'), O('y', neg=True), C('c'), O('z')),
    ('S', C('b'), O('m', storage='set'), C('c', neg=True), O('n')),
    ('S', C('c', neg=True), C('b', neg=True), O('m', storage='reset')),
])])

# ---------------------------------------------------------------- reads and writes in a rung
program('rung_order', '2.01', '''
A rung that writes a variable it also reads: every contact reads its variable once,
when it is evaluated, so a coil that resets the variable later in the rung does not
change what the rung's other outputs see (the reading is carried in the current
result, or saved before the coil when the coil is on another branch).''', [
    pou_xml('rung_order', 'program', {
        'inputVars': bools('e d'),
        'outputVars': bools('a c k w v u'),
    }, [
        ('S', C('a'), ('P', O('a', storage='reset'), O('w'))),
        ('S', C('c'), ('P', O('c', storage='reset'), ('S', C('d'), O('v')))),
        ('S', ('P', C('k'), ('S', C('e'), O('k', storage='reset'))), O('u')),
    ])])

# ---------------------------------------------------------------- blinker
program('blinker', '1.0', '''
A blinker from two on-delay timers, each one's output feeding the other's input (one
through a normally closed contact on `T2.Q`): off 300 ms, on 200 ms, while enabled.''', [
    pou_xml('blinker', 'program', {
        'inputVars': bools('enable'),
        'outputVars': bools('lamp'),
        'localVars': [('T1', 'TON'), ('T2', 'TON'), ('restart', 'BOOL')],
    }, [
        ('S', C('enable'), C('T2.Q', neg=True),
         B('TON', 'T1', ins=[('IN', POWER), ('PT', V('T#300ms'))], outs=[('Q', POWER), ('ET', None)]),
         O('lamp')),
        ('S', C('lamp'),
         B('TON', 'T2', ins=[('IN', POWER), ('PT', V('T#200ms'))], outs=[('Q', POWER), ('ET', None)]),
         O('restart')),
    ])])

# ---------------------------------------------------------------- alarm with acknowledgement
program('alarm_ack', '2.01', '''
An alarm latched on the rising edge of its sensor, acknowledged by a button: the horn
sounds until the acknowledgement, the lamp flashes with a clock bit until then and is
steady after; the alarm clears once acknowledged and the sensor is back to normal.''', [
    pou_xml('alarm_ack', 'program', {
        'inputVars': bools('sensor ack flash'),
        'outputVars': bools('alarm acked horn lamp'),
    }, [
        ('S', C('sensor', edge='rising'), ('P', O('alarm', storage='set'), O('acked', storage='reset'))),
        ('S', C('alarm'), C('ack'), O('acked', storage='set')),
        ('S', C('acked'), C('sensor', neg=True), O('alarm', storage='reset')),
        ('S', C('alarm'), C('acked', neg=True), O('horn')),
        ('S', C('alarm'), ('P', ('S', C('acked', neg=True), C('flash')), C('acked')), O('lamp')),
    ])])

# ---------------------------------------------------------------- tank filling
program('tank_fill', '1.0', '''
Tank filling with two level switches: in automatic mode the pump starts at the low
switch and stops at the high one (or when automatic is switched off); the inlet valve
follows the pump; both switches on at once is a sensor fault.''', [
    pou_xml('tank_fill', 'program', {
        'inputVars': bools('low_sw high_sw auto'),
        'outputVars': bools('pump valve_open sensor_fault'),
    }, [
        ('S', C('auto'), C('low_sw'), O('pump', storage='set')),
        ('S', ('P', C('high_sw'), C('auto', neg=True)), O('pump', storage='reset')),
        ('S', C('pump'), O('valve_open')),
        ('S', C('high_sw'), C('low_sw'), O('sensor_fault')),
    ])])

# ---------------------------------------------------------------- EN/ENO chains
program('enable_chain', '2.01', '''
Function blocks with EN/ENO in a chain: two MOVE blocks, the ENO of the first enabling
the second and the ENO of the second on a coil; an ADD enabled by a normally closed
contact. A block whose EN is off does not run: its output variables keep their
values.''', [pou_xml('enable_chain', 'program', {
    'inputVars': bools('go'),
    'outputVars': [('a', 'INT'), ('b', 'INT'), ('c', 'INT'), ('done', 'BOOL')],
}, [
    ('S', C('go'),
     B('MOVE', None, ins=[('EN', POWER), ('IN', V('a'))], outs=[('ENO', POWER), ('OUT', V('b'))]),
     B('MOVE', None, ins=[('EN', POWER), ('IN', V('b'))], outs=[('ENO', POWER), ('OUT', V('c'))]),
     O('done')),
    ('S', C('go', neg=True),
     B('ADD', None, ins=[('EN', POWER), ('IN1', V('a')), ('IN2', V('1'))],
       outs=[('ENO', None), ('OUT', V('a'))])),
])])

# ---------------------------------------------------------------- RETURN in a function
program('return_function', '2.01', '''
A ladder FUNCTION with a conditional RETURN: it moves its first input to its result,
returns unless `use_b`, and then moves its second input. The program calls it with a
block wired to variables only, and shows the selection on a coil.''', [
    pou_xml('pick', 'function', {
        'inputVars': [('a', 'INT'), ('b', 'INT'), ('use_b', 'BOOL')],
    }, [
        ('S', B('MOVE', None, ins=[('EN', RAIL), ('IN', V('a'))], outs=[('ENO', None), ('OUT', V('pick'))])),
        ('S', C('use_b', neg=True), RET),
        ('S', B('MOVE', None, ins=[('EN', RAIL), ('IN', V('b'))], outs=[('ENO', None), ('OUT', V('pick'))])),
    ], ret='INT'),
    pou_xml('return_function', 'program', {
        'inputVars': [('x', 'INT'), ('y', 'INT'), ('sel', 'BOOL')],
        'outputVars': [('result', 'INT'), ('sel_lamp', 'BOOL')],
    }, [
        ('S', B('pick', None, ins=[('a', V('x')), ('b', V('y')), ('use_b', V('sel'))],
                outs=[('OUT', V('result'))])),
        ('S', C('sel'), O('sel_lamp')),
    ]),
], program='return_function')

# ---------------------------------------------------------------- conveyor
program('conveyor', '1.0', '''
A conveyor with located I/O: the belt seals in until stop or a full batch; a CTU counts
parts passing the sensor while the belt runs (reset by the start button) and reports
the count; a full batch latches a flag.''', [pou_xml('conveyor', 'program', {
    'inputVars': [('start_pb', 'BOOL', None, '%IX0.0'), ('stop_pb', 'BOOL', None, '%IX0.1'),
                  ('part_sensor', 'BOOL', None, '%IX0.2')],
    'outputVars': [('belt', 'BOOL', None, '%QX0.0'), ('full', 'BOOL', None, '%QX0.1')],
    'localVars': [('cnt', 'CTU'), ('parts', 'INT'), ('batch_done', 'BOOL')],
}, [
    ('S', ('P', C('start_pb'), C('belt')), C('stop_pb', neg=True), C('full', neg=True), O('belt')),
    ('S', C('belt'), C('part_sensor'),
     B('CTU', 'cnt', ins=[('CU', POWER), ('R', NET(('S', C('start_pb')))), ('PV', V('4'))],
       outs=[('Q', POWER), ('CV', V('parts'))]),
     O('full')),
    ('S', C('full'), O('batch_done', storage='set')),
])])


# ---------------------------------------------------------------- the example
example('pump_station', '2.01', '''
A sump pump: it starts at the high level switch and runs until the level is below the
low switch, but at least 5 s once started; the high switch on for 10 s raises an
alarm. (plcc draws it with its option emit ld-text, and shows its IL with emit il.)''', [
    pou_xml('pump_station', 'program', {
        'inputVars': [('high_sw', 'BOOL', None, '%IX0.0'), ('low_sw', 'BOOL', None, '%IX0.1')],
        'outputVars': [('pump', 'BOOL', None, '%QX0.0'), ('alarm', 'BOOL', None, '%QX0.1')],
        'localVars': [('T_min', 'TON'), ('T_alarm', 'TON'), ('min_done', 'BOOL')],
    }, [
        ('S', ('P', C('high_sw'), C('pump')), ('P', C('low_sw', neg=True), C('min_done', neg=True)),
         O('pump')),
        ('S', C('pump'),
         B('TON', 'T_min', ins=[('IN', POWER), ('PT', V('T#5s'))], outs=[('Q', POWER), ('ET', None)]),
         O('min_done')),
        ('S', C('high_sw'),
         B('TON', 'T_alarm', ins=[('IN', POWER), ('PT', V('T#10s'))], outs=[('Q', POWER), ('ET', None)]),
         O('alarm')),
    ])])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, '..', 'tests', 'programs', 'ld')
    os.makedirs(out, exist_ok=True)
    for name, text in PROGRAMS.items():
        with open(os.path.join(out, name + '.xml'), 'w') as f:
            f.write(text)
    print(f'{len(PROGRAMS)} programs written to {out}')
    examples = os.path.join(here, '..', 'examples')
    for name, text in EXAMPLES.items():
        with open(os.path.join(examples, name + '.xml'), 'w') as f:
            f.write(text)
    print(f'{len(EXAMPLES)} examples written to {examples}')


if __name__ == '__main__':
    main()
