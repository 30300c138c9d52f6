//! Program instances and helper functions the front end adds to the module.

use super::Lowerer;
use crate::ast::PouKind;
use crate::codes;
use crate::types::PouId;
use plcc_ir::{BinaryOp, FuncBuilder, FuncId, FuncKind, Function, IntCC, ProgramEntry, Type};

impl Lowerer<'_> {
    /// Creates a data object and a program entry for every PROGRAM to run: the ones
    /// named in the options, or all of them but a library's.
    pub(super) fn instantiate_programs(&mut self, opts: &super::LowerOptions) {
        if let Some(c) = self.configuration(&opts.library) {
            self.instantiate_configuration(c, &opts.programs);
            return;
        }
        let mut chosen = Vec::new();
        if opts.programs.is_empty() {
            for (i, p) in self.pous.iter().enumerate() {
                if p.kind == PouKind::Program
                    && self.used[i]
                    && Some(PouId(i as u32)) != self.globals_pou
                    && !opts.library.contains(&self.units[p.unit as usize].file)
                {
                    chosen.push(i);
                }
            }
        } else {
            for name in &opts.programs {
                let found = self.pous.iter().enumerate().position(|(i, p)| {
                    p.kind == PouKind::Program
                        && self.used[i]
                        && p.display.eq_ignore_ascii_case(name)
                });
                match found {
                    Some(i) => chosen.push(i),
                    None => self.diags.push(plcc_ir::diag::Diagnostic::error_nowhere(
                        codes::E_NO_PROGRAM,
                        format!("there is no PROGRAM named `{name}`"),
                    )),
                }
            }
        }
        for i in chosen {
            let ir = &self.ir[i];
            let (Some(_), Some(body), Some(init)) = (ir.agg, ir.body, ir.init) else {
                continue;
            };
            let name = self.pous[i].display.clone();
            let Some(data) = self.program_data(&name, PouId(i as u32)) else {
                continue;
            };
            self.module.programs.push(ProgramEntry {
                name,
                data,
                body,
                init,
                interval_us: None,
                priority: None,
            });
        }
    }

    /// `ipow(base: T, exp: i64) -> T`: integer power by repeated squaring, wrapping
    /// like multiplication. A negative exponent gives `1/base**n` truncated: 1 for a
    /// base of 1, ±1 for -1, else 0.
    pub(super) fn ipow_helper(&mut self, t: Type) -> FuncId {
        let name = format!("__ipow_{t}");
        if let Some(&f) = self.helpers.get(&name) {
            return f;
        }
        let mut func = Function::new(name.clone(), FuncKind::Helper, vec![t, Type::I64], Some(t));
        {
            let mut b = FuncBuilder::new(&mut func);
            let p = b.params();
            let (base, exp) = (p[0], p[1]);
            let zero64 = b.iconst(Type::I64, 0);
            let neg = b.icmp(IntCC::Slt, exp, zero64);
            let negative = b.create_block();
            let positive = b.create_block();
            b.brif(neg, negative, vec![], positive, vec![]);

            b.switch_to(negative);
            let one = b.iconst(t, 1);
            let minus_one = b.iconst(t, -1);
            let zero = b.iconst(t, 0);
            let is_one = b.icmp(IntCC::Eq, base, one);
            let is_m1 = b.icmp(IntCC::Eq, base, minus_one);
            let one64 = b.iconst(Type::I64, 1);
            let odd_bit = b.binary(BinaryOp::Band, exp, one64);
            let odd = b.icmp(IntCC::Ne, odd_bit, zero64);
            let m1_result = b.select(odd, minus_one, one);
            let r1 = b.select(is_m1, m1_result, zero);
            let r = b.select(is_one, one, r1);
            b.ret(Some(r));

            b.switch_to(positive);
            let header = b.create_block();
            let body = b.create_block();
            let done = b.create_block();
            let acc = b.block_param(header, t);
            let bb = b.block_param(header, t);
            let e = b.block_param(header, Type::I64);
            let one = b.iconst(t, 1);
            b.jump(header, vec![one, base, exp]);
            b.switch_to(header);
            let more = b.icmp(IntCC::Ne, e, zero64);
            b.brif(more, body, vec![], done, vec![]);
            b.switch_to(body);
            let one64 = b.iconst(Type::I64, 1);
            let bit = b.binary(BinaryOp::Band, e, one64);
            let set = b.icmp(IntCC::Ne, bit, zero64);
            let prod = b.binary(BinaryOp::Imul, acc, bb);
            let acc2 = b.select(set, prod, acc);
            let sq = b.binary(BinaryOp::Imul, bb, bb);
            let e2 = b.binary(BinaryOp::Ushr, e, one64);
            b.jump(header, vec![acc2, sq, e2]);
            b.switch_to(done);
            b.ret(Some(acc));
        }
        let f = self.module.add_func(func);
        self.helpers.insert(name, f);
        f
    }
}
