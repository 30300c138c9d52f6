//! Shared helpers: building small IR modules and running them on the JIT and, as a
//! differential check, on the reference interpreter.

#![allow(dead_code)]

use plcc_ir::interp::Interp;
use plcc_ir::machine::Machine;
use plcc_ir::vars::variables;
use plcc_ir::{
    AggDef, AggId, DataDef, DataId, DataKind, ElemType, Field, FieldRole, FuncBuilder, FuncId,
    FuncKind, Function, MemType, Module, PlcValue, ProgramEntry, StructDef, StructKind, Type,
    Value,
};
use plcc_native::Jit;

/// The IEC type tests use for an IR type.
pub fn elem_of(ty: Type) -> ElemType {
    match ty {
        Type::I1 => ElemType::Bool,
        Type::I8 => ElemType::SInt,
        Type::I16 => ElemType::Int,
        Type::I32 => ElemType::DInt,
        Type::I64 => ElemType::LInt,
        Type::F32 => ElemType::Real,
        Type::F64 => ElemType::LReal,
        Type::Ptr => ElemType::Ref,
    }
}

/// A scalar field of a program instance.
pub fn field(name: &str, ty: Type) -> Field {
    Field {
        name: name.to_string(),
        ty: MemType::Scalar(ty),
        elem: Some(elem_of(ty)),
        role: FieldRole::Var,
        location: None,
    }
}

/// A field holding an aggregate.
pub fn agg_field(name: &str, agg: AggId) -> Field {
    Field {
        name: name.to_string(),
        ty: MemType::Agg(agg),
        elem: None,
        role: FieldRole::Var,
        location: None,
    }
}

/// A module under construction with one program, `main`, whose instance is a struct.
pub struct Prog {
    pub module: Module,
    pub agg: AggId,
    pub data: DataId,
}

impl Prog {
    /// A program whose instance has `fields` (scalar fields are zeroed by its init).
    pub fn new(fields: Vec<Field>) -> Prog {
        let mut module = Module::new();
        let agg = module.add_agg(AggDef::Struct(StructDef {
            name: "main".to_string(),
            kind: StructKind::Program,
            fields,
        }));
        let data = module.add_data(DataDef {
            name: "main".to_string(),
            ty: MemType::Agg(agg),
            elem: None,
            kind: DataKind::Program,
            location: None,
        });
        Prog { module, agg, data }
    }

    /// Index of a field by name.
    pub fn f(&self, name: &str) -> u32 {
        let AggDef::Struct(s) = &self.module.aggs[self.agg.index()] else {
            unreachable!()
        };
        s.fields.iter().position(|f| f.name == name).unwrap() as u32
    }

    /// Adds a function built by `body` (given the builder and the entry parameters).
    pub fn func(
        &mut self,
        name: &str,
        params: Vec<Type>,
        ret: Option<Type>,
        body: impl FnOnce(&mut FuncBuilder, Vec<Value>),
    ) -> FuncId {
        let mut f = Function::new(name, FuncKind::Function, params, ret);
        {
            let mut b = FuncBuilder::new(&mut f);
            let ps = b.params();
            body(&mut b, ps);
        }
        self.module.add_func(f)
    }

    /// Adds the body (`body` gets the builder and the instance address; a `return` is
    /// appended) and an init that stores zero in every scalar field and runs `init`.
    pub fn finish_with(
        mut self,
        body: impl FnOnce(&mut FuncBuilder, Value, AggId),
        init: impl FnOnce(&mut FuncBuilder, Value, AggId),
    ) -> Module {
        let agg = self.agg;
        let mut f = Function::new("main", FuncKind::ProgramBody, vec![Type::Ptr], None);
        {
            let mut b = FuncBuilder::new(&mut f);
            let inst = b.params()[0];
            body(&mut b, inst, agg);
            b.ret(None);
        }
        let body_id = self.module.add_func(f);
        let fields: Vec<(u32, MemType)> = match &self.module.aggs[agg.index()] {
            AggDef::Struct(s) => s
                .fields
                .iter()
                .enumerate()
                .map(|(i, f)| (i as u32, f.ty))
                .collect(),
            _ => unreachable!(),
        };
        let mut f = Function::new("main$init", FuncKind::Init, vec![Type::Ptr], None);
        {
            let mut b = FuncBuilder::new(&mut f);
            let inst = b.params()[0];
            for (i, t) in fields {
                // The IR has no null pointer: pointer fields keep the garbage.
                if let MemType::Scalar(ty) = t.filter_ptr() {
                    let z = zero(&mut b, ty);
                    let a = b.field_addr(inst, agg, i);
                    b.store(z, a);
                }
            }
            init(&mut b, inst, agg);
            b.ret(None);
        }
        let init_id = self.module.add_func(f);
        self.module.programs.push(ProgramEntry {
            name: "main".to_string(),
            data: self.data,
            body: body_id,
            init: init_id,
            interval_us: None,
            priority: None,
        });
        self.module
    }

    /// [`Prog::finish_with`] with no extra init.
    pub fn finish(self, body: impl FnOnce(&mut FuncBuilder, Value, AggId)) -> Module {
        self.finish_with(body, |_, _, _| {})
    }
}

trait FilterPtr {
    fn filter_ptr(self) -> MemType;
}

impl FilterPtr for MemType {
    /// Pointers become an aggregate type, so the caller skips them.
    fn filter_ptr(self) -> MemType {
        match self {
            MemType::Scalar(Type::Ptr) => MemType::Agg(AggId::new(u32::MAX as usize)),
            t => t,
        }
    }
}

/// A zero of any scalar type but `ptr`.
pub fn zero(b: &mut FuncBuilder, ty: Type) -> Value {
    match ty {
        Type::F32 | Type::F64 => b.fconst(ty, 0.0),
        _ => b.iconst(ty, 0),
    }
}

/// `load.ty field`
pub fn ld(b: &mut FuncBuilder, inst: Value, agg: AggId, field: u32, ty: Type) -> Value {
    let a = b.field_addr(inst, agg, field);
    b.load(ty, a)
}

/// `store v, field`
pub fn st(b: &mut FuncBuilder, v: Value, inst: Value, agg: AggId, field: u32) {
    let a = b.field_addr(inst, agg, field);
    b.store(v, a);
}

/// The JIT and the interpreter running one module in lockstep; every read and the
/// fault flag are compared.
pub struct Pair {
    pub module: Module,
    pub jit: Jit,
    pub interp: Interp,
}

impl Pair {
    pub fn new(module: Module) -> Pair {
        let jit = Jit::new(&module).unwrap_or_else(|e| {
            panic!(
                "JIT compile failed: {}",
                e.iter()
                    .map(|d| format!("{d} {:?}", d.notes))
                    .collect::<Vec<_>>()
                    .join("\n")
            )
        });
        let interp = Interp::new(&module).expect("interpreter accepts the module");
        let mut p = Pair {
            module,
            jit,
            interp,
        };
        p.cold_start();
        p
    }

    pub fn cold_start(&mut self) {
        self.jit.cold_start().unwrap();
        self.interp.cold_start().unwrap();
        self.compare_all();
    }

    pub fn scan(&mut self) {
        self.jit.scan().unwrap();
        self.interp.scan().expect("interpreter scan");
    }

    pub fn set_clock_us(&mut self, us: i64) {
        self.jit.set_clock_us(us);
        self.interp.set_clock_us(us);
    }

    pub fn write(&mut self, path: &str, v: PlcValue) {
        self.jit.write(path, v).unwrap();
        self.interp.write(path, v).unwrap();
    }

    /// Reads a variable from both machines; they must agree.
    pub fn read(&self, path: &str) -> PlcValue {
        let a = self.jit.read(path).unwrap();
        let b = self.interp.read(path).unwrap();
        assert_eq!(a, b, "{path}: JIT {a} vs interpreter {b}");
        a
    }

    pub fn fault(&self) -> bool {
        let (a, b) = (self.jit.fault(), self.interp.fault());
        assert_eq!(a, b, "fault flag: JIT {a} vs interpreter {b}");
        a
    }

    pub fn clear_fault(&mut self) {
        self.jit.clear_fault();
        self.interp.clear_fault();
    }

    /// Every variable of every data object agrees.
    pub fn compare_all(&self) {
        for i in 0..self.module.data.len() {
            for v in variables(&self.module, DataId::new(i)) {
                self.read(&v.path);
            }
        }
        self.fault();
    }
}

/// A value of an IR type from raw bits.
pub fn val(ty: Type, bits: u64) -> PlcValue {
    PlcValue::from_bits(elem_of(ty), bits)
}
