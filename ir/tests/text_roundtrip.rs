//! Round trips of the text form: `print(parse(print(m))) == print(m)`.

mod common;

use common::*;
use plcc_ir::diag::{FileId, Span};
use plcc_ir::text::{parse_module, print_function, print_module, PrintOptions};
use plcc_ir::verify::verify_module;
use plcc_ir::*;

const PLAIN: PrintOptions = PrintOptions {
    locations: false,
    canonical: false,
};
const LOCS: PrintOptions = PrintOptions::LOCATED;

#[track_caller]
fn roundtrip(m: &Module) {
    for opts in [PLAIN, LOCS] {
        let t1 = print_module(m, &opts);
        let m2 = parse_module(&t1).unwrap_or_else(|e| panic!("{e}\n{t1}"));
        let t2 = print_module(&m2, &opts);
        assert_eq!(t1, t2);
        // And once more, from the parsed module.
        let m3 = parse_module(&t2).unwrap();
        assert_eq!(m2, m3);
    }
}

#[test]
fn kitchen_sink_is_valid() {
    let m = kitchen_sink();
    if let Err(errs) = verify_module(&m) {
        let msgs: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
        panic!("{}", msgs.join("\n"));
    }
}

#[test]
fn kitchen_sink_roundtrips() {
    let m = kitchen_sink();
    roundtrip(&m);
    // Everything is live and created in layout order: the parsed module is the same.
    let m2 = parse_module(&print_module(&m, &LOCS)).unwrap();
    assert_eq!(m, m2);
    verify_module(&m2).unwrap();
}

#[test]
fn kitchen_sink_text_mentions_everything() {
    let m = kitchen_sink();
    let t = print_module(&m, &PLAIN);
    for op in UnaryOp::ALL {
        assert!(t.contains(&format!(" = {} v", op.name())), "{}", op.name());
    }
    for op in BinaryOp::ALL {
        assert!(t.contains(&format!(" = {} v", op.name())), "{}", op.name());
    }
    for op in ConvOp::ALL {
        assert!(t.contains(&format!(" = {}.", op.name())), "{}", op.name());
    }
    for cc in IntCC::ALL {
        assert!(t.contains(&format!("icmp {} ", cc.name())));
    }
    for cc in FloatCC::ALL {
        assert!(t.contains(&format!("fcmp {} ", cc.name())));
    }
    assert!(t.contains("table t0 \"I_Helper.Apply\" (i64, f32) -> i64 = [-, @helper.$x]\n"));
    assert!(t.contains("table t1 \"odd \\\"table\\\"\" () = []\n"));
    assert!(t.contains(" = call_table t0, v"));
    assert!(t.contains("    call_table t1, v"));
    for op in Intrinsic::ALL {
        assert!(
            t.contains(&format!("    {}\n", op.name()))
                || t.contains(&format!("= {}\n", op.name()))
                || t.contains(&format!("    {} v", op.name())),
            "{}",
            op.name()
        );
    }
    for role in ["in", "out", "inout", "temp", "external", "hidden", "var"] {
        assert!(t.contains(&format!("    {role} ")), "{role}");
    }
    for kind in [" fb {", " program {", " struct {", " other {"] {
        assert!(t.contains(kind), "{kind}");
    }
    for kind in [" program\n", " global at", " const\n"] {
        assert!(t.contains(kind), "{kind}");
    }
    for kind in [
        ") -> i32 function {",
        ") -> i64 helper {",
        ") fb {",
        ") program {",
        ") init {",
    ] {
        assert!(t.contains(kind), "{kind}");
    }
    for s in [
        "fconst.f32 NaN",
        "fconst.f32 -0.0",
        "fconst.f32 inf",
        "fconst.f32 -inf",
        "fconst.f32 0x7fc00001",
        "fconst.f32 0xffc00000",
        "fconst.f64 NaN",
        "fconst.f64 0x7ff8000000000001",
        "fconst.f64 0xfff8000000000000",
        "fconst.f64 5e-324",
        "fconst.f32 1e-45",
        "iconst.i64 -9223372036854775808",
        "iconst.i1 1",
        "%\"weird name!\".\"field.with.dots\"",
        "%\"weird name!\".\"ünï\"",
        "%\"weird name!\".\"\"",
        "%pkg.Inner..v",
        "%pkg.Inner..\"w.x\"",
        "ss1 = slot i32 \"tmp \\\"q\\\"\"",
        "ss0 = slot %Point \"pt\"",
        "call @helper.$x(",
        "global_addr @\"q x\"",
        "init_globals @\"globals init\"",
        "program \"fast \\\"one\\\"\" data @main body @main init @main$init interval_us 10000 priority 0",
        "file 1 \"odd \\\"name\\\"\\\\\\n.st\"",
        "array %pts = [4 x %Point] lower -2",
        "array %a0 = [10 x i16 INT] lower 1",
        "var lamp: i1 BOOL at \"%QX0.0\"",
        "hidden M: i1\n",
        "brif v",
        "jump block1(v",
        "br_table v",
    ] {
        assert!(t.contains(s), "missing {s:?} in\n{t}");
    }
    let tl = print_module(&m, &LOCS);
    assert!(tl.contains("   !0:10..20\n"));
    assert!(tl.contains("   !1:0..0\n"));
    assert!(tl.contains(") -> i32 function !0:1..999 {"));
    assert!(!t.contains("   !"));
}

#[test]
fn display_is_print_without_locations() {
    let m = kitchen_sink();
    assert_eq!(m.to_string(), print_module(&m, &PLAIN));
}

#[test]
fn empty_module() {
    let m = Module::new();
    assert_eq!(print_module(&m, &PLAIN), "");
    assert_eq!(parse_module("").unwrap(), m);
    assert_eq!(parse_module("\n ; nothing\n\n").unwrap(), m);
    roundtrip(&m);
}

/// A module whose functions have dead values, instructions and blocks (as after
/// passes): numbers are kept.
#[test]
fn gaps_in_numbering_are_kept() {
    let mut m = Module::new();
    let mut f = Function::new("f", FuncKind::Function, vec![Type::I32], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let x = b.params()[0];
        let dead_blk = b.create_block();
        let next = b.create_block();
        let p = b.block_param(next, Type::I32);
        let c = b.iconst(Type::I32, 3);
        let _unused = b.iconst(Type::I32, 4);
        let s = b.binary(BinaryOp::Iadd, x, c);
        b.jump(next, vec![s]);
        b.switch_to(dead_blk);
        b.ret(Some(x));
        b.switch_to(next);
        b.ret(Some(p));
    }
    // Remove the block from the layout and the unused constant from the entry.
    f.layout.retain(|&b| b != Block(1));
    f.blocks[0].insts.remove(1);
    m.add_func(f);
    verify_module(&m).unwrap();
    let t = print_module(&m, &PLAIN);
    assert!(t.contains("block2(v1: i32):"), "{t}");
    assert!(!t.contains("v3 ="), "{t}");
    assert!(!t.contains("block1"), "{t}");
    roundtrip(&m);
    let m2 = parse_module(&t).unwrap();
    verify_module(&m2).unwrap();
    assert_eq!(m2.funcs[0].values.len(), m.funcs[0].values.len());
}

/// The layout need not follow dominance: a value is used in a block printed before
/// the block that defines it.
#[test]
fn layout_out_of_dominance_order() {
    let mut m = Module::new();
    let mut f = Function::new(
        "f",
        FuncKind::Function,
        vec![Type::I32, Type::F64],
        Some(Type::F64),
    );
    {
        let mut b = FuncBuilder::new(&mut f);
        let p = b.params();
        let b1 = b.create_block();
        let b2 = b.create_block();
        b.jump(b1, vec![]);
        b.switch_to(b1);
        let d = b.binary(BinaryOp::Fmul, p[1], p[1]);
        let e = b.unary(UnaryOp::Fneg, d);
        let c = b.fcmp(FloatCC::Lt, e, d);
        let s = b.select(c, e, d);
        b.jump(b2, vec![]);
        b.switch_to(b2);
        let t = b.binary(BinaryOp::Fadd, s, d);
        b.ret(Some(t));
    }
    f.layout = vec![Block(0), Block(2), Block(1)];
    m.add_func(f);
    verify_module(&m).unwrap();
    let t = print_module(&m, &PLAIN);
    let use_at = t.find("fadd v5, v2").unwrap();
    let def_at = t.find("v5 = select").unwrap();
    assert!(use_at < def_at, "{t}");
    roundtrip(&m);
    let m2 = parse_module(&t).unwrap();
    verify_module(&m2).unwrap();
    let f2 = &m2.funcs[0];
    assert_eq!(f2.value_type(Value(6)), Type::F64);
    assert_eq!(f2.value_type(Value(4)), Type::I1);
}

#[test]
fn print_function_alone() {
    let m = kitchen_sink();
    let t = print_function(&m, &m.funcs[1], &PLAIN);
    assert_eq!(
        t,
        "func @helper.$x(i64, f32) -> i64 helper {\nblock0(v0: i64, v1: f32):\n    return v0\n}\n"
    );
}

#[test]
fn exact_layout_of_the_text() {
    let mut m = Module::new();
    m.files.push("a.st".into());
    let s = m.add_agg(AggDef::Struct(StructDef {
        name: "S".into(),
        kind: StructKind::Struct,
        fields: vec![field(
            "a",
            FieldRole::Var,
            scalar(Type::I32),
            Some(ElemType::DInt),
        )],
    }));
    let d = m.add_data(DataDef {
        name: "d".into(),
        ty: MemType::Agg(s),
        elem: None,
        kind: DataKind::Global,
        location: None,
    });
    let mut f = Function::new("f", FuncKind::Init, vec![], None);
    {
        let mut b = FuncBuilder::new(&mut f);
        b.slot("x", scalar(Type::I8));
        b.set_span(Some(Span::new(FileId(0), 3, 9)));
        let a = b.global_addr(d);
        let fa = b.field_addr(a, s, 0);
        let one = b.iconst(Type::I32, 1);
        b.store(one, fa);
        let nb = b.create_block();
        b.jump(nb, vec![]);
        b.switch_to(nb);
        b.ret(None);
    }
    let fid = m.add_func(f);
    m.init_globals = Some(fid);
    let want = "\
file 0 \"a.st\"

struct %S struct {
    var a: i32 DINT
}

data @d: %S global

func @f() init {
    ss0 = slot i8 \"x\"
block0:
    v0 = global_addr @d   !0:3..9
    v1 = field_addr v0, %S.a   !0:3..9
    v2 = iconst.i32 1   !0:3..9
    store v2, v1   !0:3..9
    jump block1   !0:3..9

block1:
    return   !0:3..9
}

init_globals @f
";
    assert_eq!(print_module(&m, &LOCS), want);
    assert_eq!(parse_module(want).unwrap(), m);
}

/// The example of docs/ir.md, completed with the declarations it refers to.
#[test]
fn parses_the_documented_example() {
    let text = r#"
; comment to end of line
file 0 "examples/traffic_light.st"

struct %TON fb {
    in IN: i1 BOOL
    in PT: i32 TIME
    out Q: i1 BOOL
    out ET: i32 TIME
    hidden start: i32 TIME
    var inner: %R_TRIG
    var lamp: i1 BOOL at "%QX0.0"
}
struct %R_TRIG fb {
    in CLK: i1 BOOL
    out Q: i1 BOOL
}
struct %main program {
    var t: %TON
}
array %a0 = [10 x i16 INT] lower 1
array %grid = [3 x %a0] lower 0

data @main: %main program
data @g: i32 DINT global at "%MD2"

func @add3(i32, i32, i32) -> i32 function {
    ss0 = slot i32 "tmp"
block0(v0: i32, v1: i32, v2: i32):
    v3 = iadd v0, v1
    v4 = iadd v3, v2   !0:120..131
    return v4
}

func @main(ptr) program {
block0(v0: ptr):
    return
}

func @main$init(ptr) init {
block0(v0: ptr):
    return
}

func @globals$init() init {
block0:
    return
}

program "main" data @main body @main init @main$init
init_globals @globals$init
"#;
    let m = parse_module(text).unwrap();
    verify_module(&m).unwrap();
    assert_eq!(m.files, vec!["examples/traffic_light.st".to_string()]);
    assert_eq!(m.aggs.len(), 5);
    let AggDef::Struct(ton) = &m.aggs[0] else {
        panic!()
    };
    assert_eq!(ton.kind, StructKind::FunctionBlock);
    assert_eq!(ton.fields.len(), 7);
    assert_eq!(ton.fields[5].ty, MemType::Agg(AggId(1)));
    assert_eq!(ton.fields[6].location.as_deref(), Some("%QX0.0"));
    assert_eq!(ton.fields[1].elem, Some(ElemType::Time));
    let AggDef::Array(grid) = &m.aggs[4] else {
        panic!()
    };
    assert_eq!(
        (grid.len, grid.lower, grid.elem),
        (3, 0, MemType::Agg(AggId(3)))
    );
    assert_eq!(m.data[1].location.as_deref(), Some("%MD2"));
    let add3 = &m.funcs[0];
    assert_eq!(add3.params, vec![Type::I32; 3]);
    assert_eq!(add3.ret, Some(Type::I32));
    assert_eq!(add3.slots[0].name, "tmp");
    assert_eq!(add3.spans[1], Some(Span::new(FileId(0), 120, 131)));
    assert_eq!(add3.spans[0], None);
    assert_eq!(
        add3.insts[1],
        InstData::Binary {
            op: BinaryOp::Iadd,
            args: [Value(3), Value(2)]
        }
    );
    assert_eq!(m.programs[0].body, FuncId(1));
    assert_eq!(m.programs[0].init, FuncId(2));
    assert_eq!(m.init_globals, Some(FuncId(3)));
}

/// Everything may be referred to before it is declared, numbers need not be dense or
/// in order, and the text may be sloppy with blank lines and comments.
#[test]
fn forward_references_and_sparse_numbers() {
    let text = r#"
program "p" data @inst body @body init @init ; a comment
init_globals @gi

func @body(ptr) program {
block7(v10: ptr):            ; entry
    v3 = call @sq(v12)
    jump block2(v3)
block2(v40: i32):
    v41 = field_addr v10, %P.x
    store v40, v41
    v12 = load.i32 v41
    return
}

func @sq(i32) -> i32 function {
block0(v5: i32):
    v6 = imul v5, v5
    return v6
}

func @init(ptr) init {
block0(v0: ptr):
    return
}
func @gi() init {
block0:
    v1 = global_addr @inst
    return
}
data @inst: %P program
struct %P program {
    var x: i32 DINT
}
"#;
    let m = parse_module(text).unwrap();
    // v12 is used in block7 before block2 defines it: SSA dominance fails, but the
    // text parses; the verifier reports the use.
    let errs = verify_module(&m).unwrap_err();
    assert_eq!(errs.len(), 1, "{errs:?}");
    assert!(
        errs[0].message.contains("v12 is defined in block2"),
        "{}",
        errs[0]
    );
    let body = &m.funcs[0];
    assert_eq!(body.layout, vec![Block(7), Block(2)]);
    assert_eq!(body.value_type(Value(3)), Type::I32);
    assert_eq!(body.value_type(Value(12)), Type::I32);
    assert_eq!(body.values.len(), 42);
    // Unused numbers are parameters of one dead block.
    assert_eq!(body.blocks.len(), 9);
    assert!(!body.layout.contains(&Block(8)));
    // Printing keeps the numbers.
    let t = print_module(&m, &PLAIN);
    assert!(
        t.contains("block7(v10: ptr):\n    v3 = call @sq(v12)\n    jump block2(v3)\n"),
        "{t}"
    );
    assert_eq!(print_module(&parse_module(&t).unwrap(), &PLAIN), t);
}

#[test]
fn type_inference_through_long_reverse_chains() {
    // Block k defines v(k) from v(k+1), which block k+1 defines: every use is printed
    // before its definition, 2000 deep. The entry block is printed first.
    let n = 2000;
    let mut text = format!("func @f(i64) -> i64 function {{\nblock{n}(v0: i64):\n    v{n} = bnot v0\n    jump block{}\n", n - 1);
    text.push_str("block1:\n    v1 = iadd v2, v2\n    return v1\n");
    for k in 2..n {
        text.push_str(&format!(
            "block{k}:\n    v{k} = iadd v{}, v{}\n    jump block{}\n",
            k + 1,
            k + 1,
            k - 1
        ));
    }
    text.push_str("}\n");
    let m = parse_module(&text).unwrap();
    verify_module(&m).unwrap();
    assert!(m.funcs[0].values.iter().all(|v| v.ty == Type::I64));
}

#[test]
fn select_and_binary_fall_back_to_the_other_operand() {
    // v2's first operand depends on v2 itself (invalid SSA), the second gives its type.
    let text =
        "func @f(i8) -> i8 function {\nblock0(v0: i8):\n    v2 = iadd v2, v0\n    return v2\n}\n";
    let m = parse_module(text).unwrap();
    assert_eq!(m.funcs[0].value_type(Value(2)), Type::I8);
    assert!(verify_module(&m).is_err());
}

#[test]
fn big_module_roundtrips_quickly() {
    let mut m = Module::new();
    let mut f = Function::new("big", FuncKind::Function, vec![Type::I32], Some(Type::I32));
    {
        let mut b = FuncBuilder::new(&mut f);
        let mut acc = b.params()[0];
        for k in 0..20_000 {
            let c = b.iconst(Type::I32, k);
            acc = b.binary(BinaryOp::Iadd, acc, c);
            if k % 100 == 0 {
                let nb = b.create_block();
                let p = b.block_param(nb, Type::I32);
                b.jump(nb, vec![acc]);
                b.switch_to(nb);
                acc = p;
            }
        }
        b.ret(Some(acc));
    }
    m.add_func(f);
    let start = std::time::Instant::now();
    let t = print_module(&m, &PLAIN);
    let m2 = parse_module(&t).unwrap();
    assert_eq!(print_module(&m2, &PLAIN), t);
    verify_module(&m2).unwrap();
    assert!(start.elapsed().as_secs() < 20);
}

/// `inline_c` (C code of a pragma, for the `c` target) prints, parses back and
/// verifies; its struct must be a struct and its data a pointer; the interpreter
/// refuses to run it.
#[test]
fn inline_c_roundtrips_and_only_the_c_target_takes_it() {
    let text = "struct %m program {\n    var n: i16 INT\n}\n\ndata @m: %m program\n\n\
                func @m(ptr) program {\nblock0(v0: ptr):\n    \
                inline_c %m, v0, \"{ __SET_VAR(data__->,N,,\\\"x\\\\n\\\"[0]); }\"\n    return\n}\n\n\
                func @m$init(ptr) init {\nblock0(v0: ptr):\n    return\n}\n\n\
                program \"m\" data @m body @m init @m$init\n";
    let m = parse_module(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    verify_module(&m).unwrap();
    roundtrip(&m);
    let InstData::InlineC { code, .. } = m.funcs[0].inst(m.funcs[0].inst_iter().next().unwrap().1)
    else {
        panic!("an inline_c first")
    };
    assert_eq!(&**code, "{ __SET_VAR(data__->,N,,\"x\\n\"[0]); }");
    let bad = text.replace(
        "inline_c %m, v0,",
        "v1 = iconst.i16 0\n    inline_c %m, v1,",
    );
    let errs = verify_module(&parse_module(&bad).unwrap()).unwrap_err();
    assert!(
        errs.iter().any(|e| e.to_string().contains("is not a ptr")),
        "{errs:?}"
    );
    use plcc_ir::machine::Machine;
    let refused = plcc_ir::interp::Interp::new(&m)
        .map_err(|e| e.to_string())
        .and_then(|mut i| {
            i.cold_start().map_err(|e| e.to_string())?;
            i.scan().map_err(|e| e.to_string())
        });
    let err = refused.expect_err("the interpreter refuses");
    assert!(err.contains("inline C"), "{err}");
}
