//! Modules: aggregate types, data objects, functions and the programs to run.

use crate::entities::{AggId, DataId, FuncId, TableId};
use crate::function::Function;
use crate::types::{ElemType, MemType, Type};

/// What a struct stands for in the source.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum StructKind {
    /// The variables of a PROGRAM.
    Program,
    /// The variables of a FUNCTION_BLOCK (an instance).
    FunctionBlock,
    /// A user STRUCT type.
    Struct,
    /// Anything else the front end needs (for example a FUNCTION's output buffer).
    Other,
}

impl StructKind {
    /// The keyword of the text form.
    pub fn name(self) -> &'static str {
        match self {
            StructKind::Program => "program",
            StructKind::FunctionBlock => "fb",
            StructKind::Struct => "struct",
            StructKind::Other => "other",
        }
    }

    /// Parses a keyword of the text form.
    pub fn from_name(s: &str) -> Option<StructKind> {
        Some(match s {
            "program" => StructKind::Program,
            "fb" => StructKind::FunctionBlock,
            "struct" => StructKind::Struct,
            "other" => StructKind::Other,
            _ => return None,
        })
    }
}

/// How a field is declared in its POU; the runner lists variables by it.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum FieldRole {
    /// `VAR` (or a struct field).
    Var,
    /// `VAR_INPUT`
    Input,
    /// `VAR_OUTPUT`
    Output,
    /// `VAR_IN_OUT` (the field holds the address of the argument).
    InOut,
    /// `VAR_TEMP`
    Temp,
    /// `VAR_EXTERNAL` (the field holds the address of the global).
    External,
    /// State a front end added that the user did not declare.
    Hidden,
}

impl FieldRole {
    /// The keyword of the text form.
    pub fn name(self) -> &'static str {
        match self {
            FieldRole::Var => "var",
            FieldRole::Input => "in",
            FieldRole::Output => "out",
            FieldRole::InOut => "inout",
            FieldRole::Temp => "temp",
            FieldRole::External => "external",
            FieldRole::Hidden => "hidden",
        }
    }

    /// Parses a keyword of the text form.
    pub fn from_name(s: &str) -> Option<FieldRole> {
        Some(match s {
            "var" => FieldRole::Var,
            "in" => FieldRole::Input,
            "out" => FieldRole::Output,
            "inout" => FieldRole::InOut,
            "temp" => FieldRole::Temp,
            "external" => FieldRole::External,
            "hidden" => FieldRole::Hidden,
            _ => return None,
        })
    }
}

/// A field of a struct.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The source name (as declared; paths compare it case-insensitively).
    pub name: String,
    /// What it holds.
    pub ty: MemType,
    /// For a scalar, its IEC type (how the runner shows it).
    pub elem: Option<ElemType>,
    /// How it was declared.
    pub role: FieldRole,
    /// `AT %IX0.0`: its located address, as written.
    pub location: Option<String>,
}

/// A struct: program or FB instance variables, or a user STRUCT.
#[derive(Clone, Debug, PartialEq)]
pub struct StructDef {
    /// Unique name within the module's aggregates (the POU or type name).
    pub name: String,
    /// What it stands for.
    pub kind: StructKind,
    /// The fields in declaration order.
    pub fields: Vec<Field>,
}

/// An array of `len` elements; the source indexes it from `lower`.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayDef {
    /// Unique name within the module's aggregates.
    pub name: String,
    /// Element type.
    pub elem: MemType,
    /// For scalar elements, their IEC type.
    pub elem_type: Option<ElemType>,
    /// Number of elements.
    pub len: u32,
    /// The source index of element 0 (for paths such as `main.a[3]`).
    pub lower: i64,
}

/// A struct or an array type.
#[derive(Clone, Debug, PartialEq)]
pub enum AggDef {
    /// A struct.
    Struct(StructDef),
    /// An array.
    Array(ArrayDef),
}

impl AggDef {
    /// The aggregate's unique name.
    pub fn name(&self) -> &str {
        match self {
            AggDef::Struct(s) => &s.name,
            AggDef::Array(a) => &a.name,
        }
    }
}

/// What a data object is.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum DataKind {
    /// The instance of a PROGRAM.
    Program,
    /// A global variable (`VAR_GLOBAL`).
    Global,
    /// Read-only data (constant tables).
    Constant,
}

impl DataKind {
    /// The keyword of the text form.
    pub fn name(self) -> &'static str {
        match self {
            DataKind::Program => "program",
            DataKind::Global => "global",
            DataKind::Constant => "const",
        }
    }

    /// Parses a keyword of the text form.
    pub fn from_name(s: &str) -> Option<DataKind> {
        Some(match s {
            "program" => DataKind::Program,
            "global" => DataKind::Global,
            "const" => DataKind::Constant,
            _ => return None,
        })
    }
}

/// A statically allocated object.
#[derive(Clone, Debug, PartialEq)]
pub struct DataDef {
    /// Unique name among data objects (the program instance or global's name).
    pub name: String,
    /// What it holds.
    pub ty: MemType,
    /// For a scalar, its IEC type.
    pub elem: Option<ElemType>,
    /// What it is.
    pub kind: DataKind,
    /// `AT %...` location of a located global.
    pub location: Option<String>,
}

/// A PROGRAM instance the scan runs: its memory, its body and its cold-start code.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramEntry {
    /// The instance name (paths start with it: `main.count`); it is also the name
    /// of its data object, which is how paths find the memory.
    pub name: String,
    /// Its variables.
    pub data: DataId,
    /// `body(instance: ptr)`, run once per scan.
    pub body: FuncId,
    /// `init(instance: ptr)`, run at cold start.
    pub init: FuncId,
    /// The task's cycle time, if a configuration gives one (microseconds: a task may
    /// run every 0.5 ms although TIME counts whole milliseconds).
    pub interval_us: Option<u64>,
    /// The task's priority (0 is the most urgent), if a configuration gives one.
    pub priority: Option<u32>,
}

/// A CONFIGURATION's names as the source spells them, and what each of its RESOURCEs
/// holds: a backend that writes source for a runtime names its files and variables
/// after them (the C target's `Config0.c`, `RES0__INSTANCE0`, `CONFIG0__G1`). The
/// scan itself does not depend on it: the program entries say what runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Configuration {
    /// The configuration's name.
    pub name: String,
    /// Its resources, in declaration order.
    pub resources: Vec<Resource>,
}

/// A RESOURCE of a [`Configuration`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Resource {
    /// The resource's name (`RESOURCE` for the tasks and programs written directly in
    /// the configuration, as matiec names them).
    pub name: String,
    /// The instance names of the program entries configured in it, as declared.
    pub programs: Vec<String>,
    /// The names of the globals declared in it (fields of the module's
    /// [`globals`](Module::globals)); the other globals are the configuration's.
    pub globals: Vec<String>,
}

/// A function table: the callees of a call bound at run time (`call_table`), such as
/// the implementations of one method of an interface, one per class.
///
/// Every entry that is `Some` has exactly the table's signature (the verifier checks
/// it); a `None` entry (a class that does not implement the method) and an index past
/// the end are not undefined: `call_table` then raises the fault flag and gives a zero
/// result.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// A name for listings and diagnostics (`I_Shape.Area`); need not be unique.
    pub name: String,
    /// The parameter types of every entry.
    pub params: Vec<Type>,
    /// The result type of every entry, if they return a value.
    pub result: Option<Type>,
    /// The functions, by index.
    pub entries: Vec<Option<FuncId>>,
}

/// A whole program ready for a backend.
///
/// Cold start calls `init_globals` (if any) and then every program's `init` with the
/// address of its data; every scan calls every program's `body` in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Module {
    /// Source file names, indexed by [`crate::diag::FileId`].
    pub files: Vec<String>,
    /// Struct and array types.
    pub aggs: Vec<AggDef>,
    /// Data objects.
    pub data: Vec<DataDef>,
    /// Functions.
    pub funcs: Vec<Function>,
    /// Function tables, for calls bound at run time.
    pub tables: Vec<Table>,
    /// The programs the scan runs, in order.
    pub programs: Vec<ProgramEntry>,
    /// `() -> ()` that initialises the globals at cold start.
    pub init_globals: Option<FuncId>,
    /// The data object that holds the `VAR_GLOBAL`s, one field per global (a backend
    /// may give each global a variable of its own).
    pub globals: Option<DataId>,
    /// The configuration the program entries come from, if the source has one.
    pub configuration: Option<Configuration>,
    /// True if pointers may hold addresses no data object or live slot has (CODESYS
    /// pointer arithmetic, `inttoptr`, or the address of a temporary kept past its
    /// call): a machine that cannot check every access refuses to run such a module.
    pub unchecked_pointers: bool,
}

impl Module {
    /// An empty module.
    pub fn new() -> Module {
        Module::default()
    }

    /// A copy whose functions have no bodies (each keeps its name, kind, signature
    /// and span): for a caller that gives the module to a machine and keeps its
    /// data, types, programs and names.
    pub fn clone_declarations(&self) -> Module {
        let funcs = self
            .funcs
            .iter()
            .map(|f| {
                let mut shell = Function::new(f.name.clone(), f.kind, f.params.clone(), f.ret);
                shell.span = f.span;
                shell
            })
            .collect();
        Module {
            files: self.files.clone(),
            aggs: self.aggs.clone(),
            data: self.data.clone(),
            funcs,
            tables: self.tables.clone(),
            programs: self.programs.clone(),
            init_globals: self.init_globals,
            globals: self.globals,
            configuration: self.configuration.clone(),
            unchecked_pointers: self.unchecked_pointers,
        }
    }

    /// Adds an aggregate type.
    pub fn add_agg(&mut self, def: AggDef) -> AggId {
        self.aggs.push(def);
        AggId::new(self.aggs.len() - 1)
    }

    /// Adds a data object.
    pub fn add_data(&mut self, def: DataDef) -> DataId {
        self.data.push(def);
        DataId::new(self.data.len() - 1)
    }

    /// Adds a function.
    pub fn add_func(&mut self, func: Function) -> FuncId {
        self.funcs.push(func);
        FuncId::new(self.funcs.len() - 1)
    }

    /// Adds a function table.
    pub fn add_table(&mut self, table: Table) -> TableId {
        self.tables.push(table);
        TableId::new(self.tables.len() - 1)
    }

    /// A function table.
    pub fn table(&self, id: TableId) -> &Table {
        &self.tables[id.index()]
    }

    /// An aggregate's definition.
    pub fn agg(&self, id: AggId) -> &AggDef {
        &self.aggs[id.index()]
    }

    /// A struct's definition (panics if `id` is an array: callers check types first).
    pub fn struct_def(&self, id: AggId) -> &StructDef {
        match &self.aggs[id.index()] {
            AggDef::Struct(s) => s,
            AggDef::Array(a) => panic!("aggregate {} is an array, not a struct", a.name),
        }
    }

    /// An array's definition (panics if `id` is a struct).
    pub fn array_def(&self, id: AggId) -> &ArrayDef {
        match &self.aggs[id.index()] {
            AggDef::Array(a) => a,
            AggDef::Struct(s) => panic!("aggregate {} is a struct, not an array", s.name),
        }
    }

    /// A function.
    pub fn func(&self, id: FuncId) -> &Function {
        &self.funcs[id.index()]
    }

    /// A function, for rewriting.
    pub fn func_mut(&mut self, id: FuncId) -> &mut Function {
        &mut self.funcs[id.index()]
    }

    /// Looks a function up by name.
    pub fn func_by_name(&self, name: &str) -> Option<FuncId> {
        self.funcs
            .iter()
            .position(|f| f.name == name)
            .map(FuncId::new)
    }

    /// Looks a data object up by name (case-insensitive, as IEC names).
    pub fn data_by_name(&self, name: &str) -> Option<DataId> {
        self.data
            .iter()
            .position(|d| d.name.eq_ignore_ascii_case(name))
            .map(DataId::new)
    }

    /// Looks a program entry up by instance name (case-insensitive).
    pub fn program(&self, name: &str) -> Option<&ProgramEntry> {
        self.programs
            .iter()
            .find(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// The common tick of the configuration's tasks: the greatest common divisor of
    /// their intervals (µs), as matiec's `common_ticktime__`; `None` when no program
    /// has a task with an interval. A scan every tick runs each task exactly when due.
    pub fn task_tick_us(&self) -> Option<u64> {
        fn gcd(a: u64, b: u64) -> u64 {
            if b == 0 {
                a
            } else {
                gcd(b, a % b)
            }
        }
        self.programs
            .iter()
            .filter_map(|p| p.interval_us)
            .filter(|&i| i > 0)
            .reduce(gcd)
    }

    /// The program entry named `name`, else the only instance of the PROGRAM type
    /// `name` (a configuration names its instances: `PROGRAM inst WITH t : name`).
    pub fn program_or_instance_of(&self, name: &str) -> Option<&ProgramEntry> {
        if let Some(p) = self.program(name) {
            return Some(p);
        }
        let mut of_type = self.programs.iter().filter(|p| {
            matches!(self.data[p.data.index()].ty, MemType::Agg(a) if self.agg(a).name().eq_ignore_ascii_case(name))
        });
        match (of_type.next(), of_type.next()) {
            (Some(p), None) => Some(p),
            _ => None,
        }
    }
}
