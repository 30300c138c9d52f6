//! Calls bound at run time as compare chains of direct calls, for backends whose
//! machine has no call to a computed address that suits them (the PIC16's CALL and
//! GOTO take an immediate address; its computed jumps through PCL would not let the
//! backend's analyses see the callees).
//!
//! Every `v = call_table t, i(args)` becomes, in place:
//!
//! ```text
//!     c0 = icmp eq i, k0          ; k0, k1, …: the entries that are not empty
//!     brif c0, call0, next0       ; (and that the index's type can reach)
//! next0:
//!     c1 = icmp eq i, k1
//!     brif c1, call1, fault
//! call0:
//!     r0 = call @f0(args)
//!     jump join(r0)
//! call1: …
//! fault:
//!     raise_fault
//!     jump join(0)
//! join(v):                        ; the rest of the block
//! ```
//!
//! so every callee is a direct call and the backend's call graph, stack depth and
//! frame overlays see each of them (the chain itself uses no stack). The result keeps
//! its value number as `join`'s parameter. Equality at the index's own width reads the
//! index unsigned, as `call_table` does.

use crate::entities::{Block, FuncId, Inst, Value};
use crate::function::{Function, ValueDef};
use crate::inst::{BlockCall, InstData, IntCC, Intrinsic};
use crate::module::{Module, Table};
use crate::types::Type;

/// Lowers every `call_table` of `module`; true if there was one.
pub fn run(module: &mut Module) -> bool {
    let tables = std::mem::take(&mut module.tables);
    let mut changed = false;
    for f in &mut module.funcs {
        changed |= lower_function(f, &tables);
    }
    module.tables = tables;
    changed
}

/// Lowers the `call_table`s of one function (`tables` are its module's).
pub fn lower_function(f: &mut Function, tables: &[Table]) -> bool {
    let sites: Vec<(Block, Inst)> = f
        .inst_iter()
        .filter(|&(_, i)| matches!(f.inst(i), InstData::CallTable { .. }))
        .collect();
    // Last first: splitting a block leaves the earlier sites where they were recorded.
    for &(b, i) in sites.iter().rev() {
        lower_site(f, tables, b, i);
    }
    !sites.is_empty()
}

fn lower_site(f: &mut Function, tables: &[Table], b: Block, inst: Inst) {
    let InstData::CallTable { table, index, args } = f.inst(inst).clone() else {
        return;
    };
    let tab = &tables[table.index()];
    let span = f.spans[inst.index()];
    let result = f.result(inst);
    let ity = f.value_type(index);
    let reach = match ity.bits() {
        64 => u64::MAX,
        w => (1u64 << w) - 1,
    };

    // Split: the instructions after the call go to `join`, whose parameter the result
    // becomes.
    let pos = f.blocks[b.index()]
        .insts
        .iter()
        .position(|&i| i == inst)
        .expect("the call in its block");
    let rest = f.blocks[b.index()].insts.split_off(pos + 1);
    f.blocks[b.index()].insts.pop();
    let join = f.create_block();
    f.blocks[join.index()].insts = rest;
    if let Some(r) = result {
        f.values[r.index()].def = ValueDef::Param(join, 0);
        f.blocks[join.index()].params.push(r);
        f.results[inst.index()] = None;
    }

    let push = |f: &mut Function, blk: Block, data: InstData, ty: Option<Type>| {
        let i = f.create_inst(data, ty, span);
        f.blocks[blk.index()].insts.push(i);
        f.result(i)
    };
    let cases: Vec<(u64, FuncId)> = tab
        .entries
        .iter()
        .enumerate()
        .filter_map(|(k, e)| e.map(|g| (k as u64, g)))
        .filter(|&(k, _)| k <= reach)
        .collect();
    let mut new_blocks = Vec::new();
    let fault = f.create_block();
    let mut at = b;
    let mut calls = Vec::new();
    for (n, &(k, g)) in cases.iter().enumerate() {
        let imm = ity.canon_int(k as i64);
        let kv = push(f, at, InstData::Iconst { ty: ity, imm }, Some(ity)).expect("a constant");
        let c = push(
            f,
            at,
            InstData::Icmp {
                cond: IntCC::Eq,
                args: [index, kv],
            },
            Some(Type::I1),
        )
        .expect("a condition");
        let call = f.create_block();
        let next = if n + 1 < cases.len() {
            f.create_block()
        } else {
            fault
        };
        push(
            f,
            at,
            InstData::Brif {
                cond: c,
                then_dest: Box::new(BlockCall::new(call, Vec::new())),
                else_dest: Box::new(BlockCall::new(next, Vec::new())),
            },
            None,
        );
        calls.push((call, g));
        if next != fault {
            new_blocks.push(next);
        }
        at = next;
    }
    if cases.is_empty() {
        push(
            f,
            b,
            InstData::Jump {
                dest: BlockCall::new(fault, Vec::new()),
            },
            None,
        );
    }
    for &(call, g) in &calls {
        let r = push(
            f,
            call,
            InstData::Call {
                func: g,
                args: args.clone(),
            },
            tab.result,
        );
        push(
            f,
            call,
            InstData::Jump {
                dest: BlockCall::new(join, r.into_iter().collect()),
            },
            None,
        );
        new_blocks.push(call);
    }
    push(
        f,
        fault,
        InstData::Intrinsic {
            op: Intrinsic::RaiseFault,
            args: Vec::new(),
        },
        None,
    );
    let zero: Option<Value> = tab.result.map(|t| {
        let data = if t.is_float() {
            InstData::Fconst { ty: t, bits: 0 }
        } else {
            InstData::Iconst { ty: t, imm: 0 }
        };
        push(f, fault, data, Some(t)).expect("a constant")
    });
    push(
        f,
        fault,
        InstData::Jump {
            dest: BlockCall::new(join, zero.into_iter().collect()),
        },
        None,
    );
    new_blocks.push(fault);
    new_blocks.push(join);
    let at = f
        .layout
        .iter()
        .position(|&x| x == b)
        .expect("the block in the layout");
    f.layout.splice(at + 1..at + 1, new_blocks);
}

#[cfg(test)]
mod tests {
    use crate::interp::Interp;
    use crate::machine::Machine;
    use crate::text::parse_module;
    use crate::verify::verify_module;

    /// Every index of an i8 (and some of an i64) gives the same result and fault as the
    /// `call_table` it replaces.
    #[test]
    fn the_chain_calls_what_the_table_calls() {
        let text = r#"
struct %m program {
    in i: i8 SINT
    in j: i64 LINT
    out r: i32 DINT
    out s: f32 REAL
}
data @m: %m program
table t0 "T" (i32) -> i32 = [@a, -, @b, @a]
table t1 "U" () -> f32 = [-, @c]
table t2 "V" () = []
func @a(i32) -> i32 function {
block0(v0: i32):
    v1 = iconst.i32 5
    v2 = iadd v0, v1
    return v2
}
func @b(i32) -> i32 function {
block0(v0: i32):
    v1 = ineg v0
    return v1
}
func @c() -> f32 function {
block0:
    v0 = fconst.f32 2.5
    return v0
}
func @body(ptr) program {
block0(v0: ptr):
    v1 = field_addr v0, %m.i
    v2 = load.i8 v1
    v3 = sext.i32 v2
    v4 = call_table t0, v2(v3)
    v5 = field_addr v0, %m.r
    store v4, v5
    v6 = field_addr v0, %m.j
    v7 = load.i64 v6
    v8 = call_table t1, v7()
    v9 = field_addr v0, %m.s
    store v8, v9
    call_table t2, v2()
    return
}
func @init(ptr) init {
block0(v0: ptr):
    v1 = iconst.i8 0
    v2 = field_addr v0, %m.i
    store v1, v2
    v3 = iconst.i64 0
    v4 = field_addr v0, %m.j
    store v3, v4
    return
}
program "m" data @m body @body init @init
"#;
        let m = parse_module(text).unwrap();
        verify_module(&m).unwrap();
        let mut lowered = m.clone();
        assert!(super::run(&mut lowered));
        verify_module(&lowered).unwrap();
        assert!(lowered.funcs.iter().all(|f| f
            .inst_iter()
            .all(|(_, i)| !matches!(f.inst(i), crate::InstData::CallTable { .. }))));
        let mut a = Interp::new(&m).unwrap();
        let mut b = Interp::new(&lowered).unwrap();
        a.cold_start().unwrap();
        b.cold_start().unwrap();
        for i in -128i64..128 {
            let j = [i, 1, 1 << 40, -1][(i & 3) as usize];
            for it in [&mut a, &mut b] {
                it.write("m.i", crate::PlcValue::from_i64(crate::ElemType::SInt, i))
                    .unwrap();
                it.write("m.j", crate::PlcValue::from_i64(crate::ElemType::LInt, j))
                    .unwrap();
                it.clear_fault();
                it.scan().unwrap();
            }
            for p in ["m.r", "m.s"] {
                assert_eq!(a.read(p).unwrap(), b.read(p).unwrap(), "{p} at i = {i}");
            }
            assert_eq!(a.fault(), b.fault(), "i = {i}");
        }
    }
}
