//! Variables used in place and values computed straight into variables.

use super::*;

/// Variables used in place: a load whose value is used only in its block before
/// anything may write the variable reads the variable itself (no copy), and a value
/// computed by one VM instruction and then only stored to a variable is computed
/// straight into it. This is what makes `x := x + 1` one `ADD x, x, ?L?CST`.
impl Fx<'_, '_> {
    /// Where an instruction may write memory other than its result's home.
    pub(super) fn writes(&mut self, data: &InstData) -> Option<Option<(u32, u32)>> {
        match data {
            InstData::Store { value, addr } => {
                let n = self.size(self.vty(*value));
                match self.class_of(*addr) {
                    PtrClass::Rel(o) => Some(Some((o, n))),
                    _ => Some(None),
                }
            }
            // A fill writes elements from its address on (`isel/fill.rs`).
            InstData::Call { .. }
            | InstData::CallTable { .. }
            | InstData::Intrinsic {
                op: Intrinsic::Fill,
                ..
            } => Some(None),
            _ => None,
        }
    }

    pub(super) fn overlaps(a: (u32, u32), b: (u32, u32)) -> bool {
        a.0 < b.0 + b.1 && b.0 < a.0 + a.1
    }

    pub(super) fn single_vm_inst(&self, data: &InstData) -> bool {
        match data {
            InstData::Binary { op, .. } => matches!(
                op,
                BinaryOp::Iadd
                    | BinaryOp::Isub
                    | BinaryOp::Imul
                    | BinaryOp::Band
                    | BinaryOp::Bor
                    | BinaryOp::Bxor
                    | BinaryOp::Fadd
                    | BinaryOp::Fsub
                    | BinaryOp::Fmul
                    | BinaryOp::Fdiv
            ),
            InstData::Unary { op, .. } => !matches!(
                op,
                UnaryOp::Fnearest | UnaryOp::Ftrunc | UnaryOp::Ffloor | UnaryOp::Fceil
            ),
            InstData::Icmp { .. } | InstData::Fcmp { .. } | InstData::Select { .. } => true,
            InstData::Load { .. } => true,
            InstData::Convert { op, .. } => matches!(
                op,
                ConvOp::Itrunc | ConvOp::Bitcast | ConvOp::Fpromote | ConvOp::Fdemote
            ),
            _ => false,
        }
    }

    pub(super) fn plan_in_place(&mut self) {
        let f = self.f;
        let layout = f.layout.clone();
        for b in layout {
            let insts = f.block(b).insts.clone();
            // Uses of each value within this block, by position.
            let mut local_uses: FxHashMap<Value, Vec<usize>> = FxHashMap::default();
            for (p, &i) in insts.iter().enumerate() {
                f.inst(i)
                    .for_each_arg(|v| local_uses.entry(v).or_default().push(p));
                if let Some(&v) = self.late_use.get(&i) {
                    local_uses.entry(v).or_default().push(p);
                }
            }
            // Loads read in place.
            for (p, &i) in insts.iter().enumerate() {
                let InstData::Load { ty, addr } = f.inst(i) else {
                    continue;
                };
                let Some(v) = f.result(i) else { continue };
                let PtrClass::Rel(o) = self.class_of(*addr) else {
                    continue;
                };
                let n = self.size(*ty);
                let total = self.uses[v.index()].len();
                let Some(local) = local_uses.get(&v) else {
                    continue;
                };
                if local.len() != total || total == 0 {
                    continue;
                }
                let last = *local.iter().max().expect("a use");
                let mut ok = true;
                for &j in &insts[p + 1..last] {
                    let d = f.inst(j).clone();
                    match self.writes(&d) {
                        Some(Some(w)) if Self::overlaps(w, (o, n)) => ok = false,
                        Some(None) => ok = false,
                        _ => {}
                    }
                    if !ok {
                        break;
                    }
                }
                if ok {
                    self.homes[v.index()] = Some(o);
                }
            }
            // Values computed straight into the variable they are stored to.
            for (p, &i) in insts.iter().enumerate() {
                let InstData::Store { value, addr } = f.inst(i).clone() else {
                    continue;
                };
                let PtrClass::Rel(o) = self.class_of(addr) else {
                    continue;
                };
                if self.homes[value.index()].is_some() || self.uses[value.index()].len() != 1 {
                    continue;
                }
                let ValueDef::Result(def) = f.value_def(value) else {
                    continue;
                };
                let Some(dp) = insts.iter().position(|&x| x == def) else {
                    continue;
                };
                let data = f.inst(def).clone();
                if !self.single_vm_inst(&data) {
                    continue;
                }
                let n = self.size(self.vty(value));
                let mut ok = true;
                for &j in &insts[dp + 1..p] {
                    let d = f.inst(j).clone();
                    match self.writes(&d) {
                        Some(Some(w)) if Self::overlaps(w, (o, n)) => ok = false,
                        Some(None) => ok = false,
                        _ => {}
                    }
                    if let InstData::Load { addr, ty } = &d {
                        match self.class_of(*addr) {
                            PtrClass::Rel(q) if Self::overlaps((q, self.size(*ty)), (o, n)) => {
                                ok = false
                            }
                            PtrClass::Rel(_) | PtrClass::Abs(_) => {}
                            _ => ok = false,
                        }
                    }
                    let homes = &self.homes;
                    let size = |t: Type| self.cx.layout.scalar_size(t);
                    d.for_each_arg(|u| {
                        if let Some(h) = homes[u.index()] {
                            if Self::overlaps((h, size(f.value_type(u))), (o, n)) {
                                ok = false;
                            }
                        }
                    });
                    if !ok {
                        break;
                    }
                }
                if ok {
                    self.homes[value.index()] = Some(o);
                }
            }
        }
    }
}
