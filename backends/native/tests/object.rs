//! Relocatable objects and their C header.

mod common;

use common::{agg_field, field, ld, st, Prog};
use object::{Object, ObjectSymbol};
use plcc_ir::backend::{Backend, Options};
use plcc_ir::{
    AggDef, ArrayDef, BinaryOp, DataDef, DataKind, ElemType, MemType, Module, StructDef,
    StructKind, Type, UnaryOp,
};
use plcc_native::NativeBackend;
use std::process::Command;

/// A module with a program that uses the clock, division, a math helper, a nested
/// struct with awkward field names, an array and a global.
fn sample() -> Module {
    let mut p = Prog::new(vec![]);
    let inner = p.module.add_agg(AggDef::Struct(StructDef {
        name: "TON".into(),
        kind: StructKind::FunctionBlock,
        fields: vec![
            field("IN", Type::I1),
            field("PT", Type::I32),
            field("int", Type::I8),
            field("weird name$", Type::I64),
            field("f3_weird_name_", Type::I16),
        ],
    }));
    let arr = p.module.add_agg(AggDef::Array(ArrayDef {
        name: "a0".into(),
        elem: MemType::Scalar(Type::F32),
        elem_type: Some(ElemType::Real),
        len: 3,
        lower: 1,
    }));
    let g = p.module.add_data(DataDef {
        name: "gcount".into(),
        ty: MemType::Scalar(Type::I64),
        elem: Some(ElemType::LInt),
        kind: DataKind::Global,
        location: None,
    });
    if let AggDef::Struct(s) = &mut p.module.aggs[0] {
        s.fields = vec![
            field("x", Type::I32),
            field("y", Type::F32),
            agg_field("t", inner),
            agg_field("v", arr),
            field("ref", Type::Ptr),
        ];
    }
    let (fx, fy) = (p.f("x"), p.f("y"));
    p.finish(|b, inst, agg| {
        let ms = b.intrinsic(plcc_ir::Intrinsic::ClockMs, vec![]).unwrap();
        let x = ld(b, inst, agg, fx, Type::I32);
        let q = b.binary(BinaryOp::Sdiv, ms, x);
        st(b, q, inst, agg, fx);
        let y = ld(b, inst, agg, fy, Type::F32);
        let s = b.unary(UnaryOp::Sin, y);
        st(b, s, inst, agg, fy);
        let ga = b.global_addr(g);
        let gv = b.load(Type::I64, ga);
        let one = b.iconst(Type::I64, 1);
        let g1 = b.binary(BinaryOp::Iadd, gv, one);
        b.store(g1, ga);
    })
}

fn options(settings: &[(&str, &str)]) -> Options {
    Options {
        emit: None,
        settings: settings
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        sources: Vec::new(),
        output_stem: None,
    }
}

#[test]
fn object_has_the_expected_symbols() {
    let m = sample();
    let arts = NativeBackend.compile(&m, &options(&[])).unwrap();
    assert_eq!(arts.files[0].kind, "o");
    assert_eq!(arts.files[1].kind, "h");
    let obj = object::File::parse(&*arts.files[0].bytes).expect("a valid object");
    let names: Vec<String> = obj
        .symbols()
        .filter_map(|s| s.name().ok().map(|n| n.trim_start_matches('_').to_string()))
        .collect();
    for want in [
        "plcc_f_main",
        "plcc_f_main_24init",
        "plcc_data",
        "plcc_rt",
        "plcc_d_main",
        "plcc_d_gcount",
        "sinf",
    ] {
        assert!(
            names.iter().any(|n| n == want.trim_start_matches('_')),
            "missing {want} in {names:?}"
        );
    }
    // Unused helpers are not referenced.
    assert!(!names.iter().any(|n| n == "cosf"));
    // Data object symbols sit inside plcc_data at their offsets.
    let data = obj.symbols().find(|s| s.name() == Ok("plcc_data")).unwrap();
    let g = obj
        .symbols()
        .find(|s| s.name() == Ok("plcc_d_gcount"))
        .unwrap();
    let gsym = arts.symbols.iter().find(|s| s.path == "gcount").unwrap();
    assert_eq!(g.address() - data.address(), gsym.address);
    assert_eq!(gsym.size, 8);
    // Every variable has a symbol.
    assert!(arts
        .symbols
        .iter()
        .any(|s| s.path == "main.t.PT" && s.elem == ElemType::DInt));
    assert!(arts.symbols.iter().any(|s| s.path == "main.v[3]"));
    assert!(arts.summary.is_some());
}

#[test]
fn objects_for_other_targets() {
    let m = sample();
    for triple in [
        "aarch64-unknown-linux-gnu",
        "x86_64-pc-windows-msvc",
        "aarch64-apple-darwin",
        "riscv64gc-unknown-linux-gnu",
        "s390x-unknown-linux-gnu",
    ] {
        let arts = NativeBackend
            .compile(&m, &options(&[("triple", triple)]))
            .unwrap_or_else(|e| panic!("{triple}: {e:?}"));
        let obj = object::File::parse(&*arts.files[0].bytes).expect("a valid object");
        assert!(
            obj.symbols()
                .any(|s| s.name().is_ok_and(|n| n.ends_with("plcc_f_main"))),
            "{triple}"
        );
    }
}

#[test]
fn bad_targets_and_settings_are_diagnostics() {
    let m = sample();
    for (k, v, code) in [
        ("triple", "not-a-triple-at-all", "E8001"),
        ("triple", "armv7-unknown-linux-gnueabihf", "E8001"),
        ("triple", "i686-unknown-linux-gnu", "E8001"),
        ("opt_level", "fast", "E8002"),
        ("colour", "blue", "E8002"),
    ] {
        let e = NativeBackend.compile(&m, &options(&[(k, v)])).unwrap_err();
        assert_eq!(e[0].code, code, "{k}={v}: {}", e[0]);
    }
    for c in plcc_native::CODES {
        assert!(c.code.starts_with("E80") && !c.explanation.is_empty());
    }
}

#[test]
fn header_compiles_with_gcc() {
    let m = sample();
    let arts = NativeBackend.compile(&m, &options(&[])).unwrap();
    let header = String::from_utf8(arts.files[1].bytes.clone()).unwrap();
    assert!(header.contains("struct plcc_s_TON"));
    assert!(header.contains("void plcc_f_main(void *instance);"));
    assert!(header.contains("extern plcc_runtime plcc_rt;"));
    if Command::new("gcc").arg("--version").output().is_err() {
        eprintln!("gcc is not installed: skipping the C compile of the header");
        return;
    }
    let dir = std::env::temp_dir().join(format!("plcc-native-h-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let h = dir.join("prog.h");
    std::fs::write(&h, &header).unwrap();
    let c = dir.join("use.c");
    std::fs::write(
        &c,
        "#include \"prog.h\"\nint main(void) { plcc_cold_start(); plcc_set_clock_us(1500); \
         plcc_scan(); return plcc_d_main.t.PT + (int)plcc_rt.fault + (int)plcc_d_gcount; }\n",
    )
    .unwrap();
    for std in ["-std=c11", "-std=gnu17"] {
        let out = Command::new("gcc")
            .args(["-fsyntax-only", "-Wall", "-Wextra", std])
            .arg(&c)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "gcc {std}: {}\n{header}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // Link and run it for real on x86_64 Linux: the object plus the header's
    // inline runtime, compared with the JIT.
    if cfg!(all(target_arch = "x86_64", target_os = "linux")) {
        let o = dir.join("prog.o");
        std::fs::write(&o, &arts.files[0].bytes).unwrap();
        let exe = dir.join("prog");
        let main = dir.join("main.c");
        std::fs::write(
            &main,
            "#include <stdio.h>\n#include <string.h>\n#include \"prog.h\"\n\
             int main(void) { memset(plcc_data, 0xA5, PLCC_DATA_SIZE); plcc_cold_start();\n\
             plcc_d_gcount = 0; plcc_d_main.x = 7; plcc_d_main.y = 0.5f; plcc_set_clock_us(1500000); plcc_scan();\n\
             printf(\"%d %a %lld %d\\n\", plcc_d_main.x, plcc_d_main.y, (long long)plcc_d_gcount, plcc_rt.fault);\n\
             plcc_d_main.x = 0; plcc_scan();\n\
             printf(\"%d %d\\n\", plcc_d_main.x, plcc_rt.fault); return 0; }\n",
        )
        .unwrap();
        let out = Command::new("gcc")
            .arg(&main)
            .arg(&o)
            .args(["-lm", "-o"])
            .arg(&exe)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "link: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let out = Command::new(&exe).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let want = format!("{} {} 1 0\n0 1\n", 1500 / 7, c_hex_float(0.5f32.sin()));
        assert_eq!(text, want);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `printf("%a", (double)x)` as glibc writes it.
fn c_hex_float(x: f32) -> String {
    let d = x as f64;
    let bits = d.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let mant = bits & ((1u64 << 52) - 1);
    let mut hex = format!("{mant:013x}");
    while hex.ends_with('0') {
        hex.pop();
    }
    let sign = if d < 0.0 { "-" } else { "" };
    if hex.is_empty() {
        format!("{sign}0x1p{exp:+}")
    } else {
        format!("{sign}0x1.{hex}p{exp:+}")
    }
}

#[test]
fn many_functions_compile_in_parallel_into_an_object_and_the_jit() {
    // Enough functions for the worker threads to kick in.
    let mut p = Prog::new(vec![field("x", Type::I32), field("r", Type::F64)]);
    let mut fs = Vec::new();
    for k in 0..100 {
        let prev = fs.last().copied();
        fs.push(p.func(
            &format!("f{k}"),
            vec![Type::I32],
            Some(Type::I32),
            |b, ps| {
                let c = b.iconst(Type::I32, k + 1);
                let q = b.binary(BinaryOp::Sdiv, ps[0], c);
                let r = match prev {
                    Some(f) => b.call(f, Some(Type::I32), vec![q]).unwrap(),
                    None => q,
                };
                let s = b.binary(BinaryOp::Iadd, r, ps[0]);
                b.ret(Some(s));
            },
        ));
    }
    let last = *fs.last().unwrap();
    let (fx, fr) = (p.f("x"), p.f("r"));
    let m = p.finish(|b, inst, agg| {
        let x = ld(b, inst, agg, fx, Type::I32);
        let y = b.call(last, Some(Type::I32), vec![x]).unwrap();
        st(b, y, inst, agg, fx);
        let f = b.convert(plcc_ir::ConvOp::SiToF, Type::F64, y);
        let c = b.unary(UnaryOp::Cos, f);
        st(b, c, inst, agg, fr);
    });
    let mut first: Option<Vec<u8>> = None;
    for threads in ["1", "2", "3", "2"] {
        let arts = NativeBackend
            .compile(&m, &options(&[("threads", threads)]))
            .unwrap();
        // The same bytes however many threads compiled them.
        match &first {
            None => first = Some(arts.files[0].bytes.clone()),
            Some(f) => assert!(
                *f == arts.files[0].bytes,
                "object differs with {threads} threads"
            ),
        }
        let obj = object::File::parse(&*arts.files[0].bytes).unwrap();
        for k in [0, 50, 99] {
            let name = format!("plcc_f_f{k}");
            assert!(
                obj.symbols().any(|s| s.name() == Ok(name.as_str())),
                "{name}"
            );
        }
    }
    let mut pair = common::Pair::new(m);
    pair.write(
        "main.x",
        plcc_ir::PlcValue::from_i64(ElemType::DInt, 1_000_000),
    );
    pair.scan();
    pair.scan();
    pair.compare_all();
}
