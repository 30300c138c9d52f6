//! Assembling the mnemonic text of CPDev listing lines (`$VMSYS.MCD TON1.PT, #04,
//! #E8030000`, `$DEFAULT.ADD WN, WN, ?L?CST0224`) to instructions.
//!
//! # Operands
//!
//! - `#…` is an immediate written as its raw little-endian memory bytes
//!   (`#E8030000` = 1000, `#0100` = 1); its width must be the operand's. Where a
//!   data address is expected (CALB's first operand, `#0000`) it is a literal address,
//!   also as raw bytes. MCD takes `#count, #bytes`; MCD4A `#count4, #bytes` with the
//!   bytes padded with `FF` to a multiple of 4, as the listings show them.
//! - `:?name` is a code label, `:hhhh` a literal code address (plain hex, as in the
//!   address column).
//! - Anything else names data, resolved through a [`Resolver`].
//! - plcc's own form for MMV, which the CPDev listings never show, is
//!   `$VMSYS.MMV dst, src, #ff` with `ff` the function byte (count, bit 7 = direction).
//!
//! # Overloads of `$DEFAULT.*`
//!
//! The listing does not say which type a standard function works on; the CPDev
//! compiler picks the opcode from the declared types of the operands:
//!
//! - ADD, MUL, MAX, MIN: function byte `n<<4 | t`, `n` the number of sources, `t` the
//!   type code of the sources (`Ty`, USINT/UINT/UDINT/ULINT = BYTE/WORD/DWORD/LWORD).
//! - AND, OR: `n<<4 | l` with BOOL 0, BYTE 1, WORD 2, DWORD 3, LWORD 4; XOR the same
//!   except DWORD 4, LWORD 5.
//! - SUB, DIV, comparisons (result BOOL): `t` of the sources; MOD `0x10 | t`.
//! - SEL `dst, g, in0, in1` and MUX `dst, k, in…` (`n` = operands after `dst`): `t`
//!   of `in0`; LIMIT `dst, mn, in, mx`: `t` of `in`.
//! - NEG: SINT 1, INT 2, DINT 3, LINT 4, REAL 7, LREAL 9; NOT `0x10 |` the AND code;
//!   SHL/SHR/ROL/ROR `0x00/0x10/0x20/0x30 |` BYTE 1, WORD 2, DWORD 3, LWORD 4 of the
//!   shifted value (the count is an INT).
//! - ABS `0x10 | t`; SQRT, LN, LOG, EXP, SIN, COS, TAN, ASIN, ACOS, ATAN, TRUNC, ROUND:
//!   the REAL form, +1 for LREAL, by the type of the argument (TRUNC of a REAL into a
//!   DINT is `0634`). EXPT is not supported (its overload table is unknown).
//! - The type is taken from the first source whose type is known; when none is, from
//!   the destination (except for comparisons); a variable of unknown type (see the
//!   hidden variables below) counts by its size (1 BOOL, 2 WORD/INT, 4 DWORD/DINT, 8
//!   LWORD/LINT).
//!
//! # Scopes (as observed in every sample listing)
//!
//! - The code from a label `:?LIB.POU?INIT` or `:?LIB.POU?CODE` up to the next such
//!   label belongs to POU `LIB.POU` (other labels, `…IF?B0083`, `…FOR?C029D`, do not
//!   change the scope). Its data names are relative to an instance of that POU: any
//!   `DATA_MAP` object whose `PType` is `LIB.POU` (case-insensitive) — a program
//!   instance, an FB instance (`TON1`), or a function's call area
//!   (`?LCALL?ShipSim_LIMIT_PREC`, functions have only a `?CODE` label). A name is
//!   the path of `LName`s below the instance (`TON1.PT`, `?LCALL?X_F.EPS`), its
//!   address the sum of the relative `Addr`s (`rdlabel`).
//! - A name not found in the POU is a global variable, by `LName` or `PName`, at its
//!   absolute address: the CPDev compiler calls programs with `CALB #0000`, so
//!   program-relative and absolute addresses coincide.
//! - Before the first such label, and from a task's `?TSKSTR`/`?TSKLOOP` label on,
//!   the code is the task's: names are global `PName`s (`WWJ.OUT0`), global `LName`s,
//!   or `DATA_MAP` `PName`s, all absolute; the programs are called with `CALB #0000`.
//! - Hidden variables: the `DATA_MAP` leaves out the private variables of library
//!   FBs (TON's `stime`, TFF's `CLKp` and `M` in `blink.dcp`). Their sizes come from
//!   the MCD/FPAT that initialise them in the POU's `?INIT` code; they are placed, in
//!   that order, first-fit at their natural alignment (at most 4) into the bytes of
//!   the instance no listed variable covers, as the CPDev compiler lays instances out.

use crate::dcp_read::{DataObj, Dcp, ListingLine};
use crate::isa::{self, op, Inst, Kind, Mode, Opcode, Operand, Ty};
use std::collections::HashMap;
use std::sync::OnceLock;

/// A data symbol: where a name lives and what it holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DataSym {
    /// The address the operand encodes (relative in a POU's code, absolute in the task's).
    pub addr: u32,
    /// The IEC type name (`INT`, `TIME`, an FB or array type name), if known.
    pub ty: Option<String>,
    /// Size in bytes.
    pub size: u32,
}

/// Looks up the names in mnemonic text.
pub trait Resolver {
    /// The data symbol of a name (`TON1.PT`, `?L?CST0224`).
    fn data(&self, name: &str) -> Option<DataSym>;
    /// The address of a code label, given without its `:` (`?IEC_61131.TON?CODE`).
    fn label(&self, name: &str) -> Option<u32>;
}

/// Which names the code at some point of a listing sees.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Scope {
    /// The task code: the global initialisers and the `TSKSTR`/`TSKLOOP` part.
    Task,
    /// The code of a POU (`LIB.POU`, as in its `?INIT`/`?CODE` labels).
    Pou(String),
}

/// The scope a label starts: `Some(Pou)` for `?LIB.POU?INIT`/`?CODE`, `Some(Task)`
/// for `?…?TSKSTR`/`?TSKLOOP`, `None` for labels inside a POU. The leading `:` is
/// optional.
pub fn label_scope(label: &str) -> Option<Scope> {
    let l = label.strip_prefix(':').unwrap_or(label).strip_prefix('?')?;
    let (head, tail) = l.rsplit_once('?')?;
    match tail.to_ascii_uppercase().as_str() {
        "INIT" | "CODE" => Some(Scope::Pou(head.to_string())),
        "TSKSTR" | "TSKLOOP" => Some(Scope::Task),
        _ => None,
    }
}

/// One name of a scope.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The name as written in the listings (`TON1.PT`).
    pub path: String,
    /// The symbol.
    pub sym: DataSym,
    /// True for an instance, call area or array (an object with fields).
    pub aggregate: bool,
    /// Nesting depth below the scope (0: a direct field).
    pub depth: usize,
    /// True for a hidden variable placed by inference (not in the `DATA_MAP`).
    pub inferred: bool,
}

/// The names of one scope.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// The entries, in `DATA_MAP` order (inferred ones last).
    pub entries: Vec<Entry>,
    by_name: HashMap<String, usize>,
}

impl Table {
    fn push(&mut self, e: Entry) {
        self.by_name
            .entry(e.path.to_ascii_uppercase())
            .or_insert(self.entries.len());
        self.entries.push(e);
    }

    /// The entry of a name (case-insensitive).
    pub fn get(&self, name: &str) -> Option<&Entry> {
        self.by_name
            .get(&name.to_ascii_uppercase())
            .map(|&i| &self.entries[i])
    }

    /// The entries at an address.
    pub fn at(&self, addr: u32) -> impl Iterator<Item = &Entry> {
        self.entries.iter().filter(move |e| e.sym.addr == addr)
    }

    fn add_fields(&mut self, obj: &DataObj, prefix: &str, base: u32, depth: usize) {
        for c in &obj.children {
            let Some(a) = c.addr else { continue };
            let path = if prefix.is_empty() {
                c.lname.clone()
            } else {
                format!("{prefix}.{}", c.lname)
            };
            let addr = base.wrapping_add(a);
            self.push(Entry {
                path: path.clone(),
                sym: DataSym {
                    addr,
                    ty: c.ty.clone(),
                    size: c.size,
                },
                aggregate: c.children.iter().any(|k| k.addr.is_some()) || !c.dims.is_empty(),
                depth,
                inferred: false,
            });
            self.add_fields(c, &path, addr, depth + 1);
        }
    }
}

/// The symbols of a `.dcp`: a table per POU, the globals, the task scope, and the
/// labels of its listing. See the module documentation for the rules.
#[derive(Clone, Debug, Default)]
pub struct Symbols {
    /// Names of each POU's code, by upper-cased POU name.
    pub pous: HashMap<String, Table>,
    /// The global variables by `LName`, then by `PName` (absolute addresses).
    pub globals: Table,
    /// Names of the task code: global `PName`s and `LName`s, then `DATA_MAP` `PName`s.
    pub task: Table,
    /// The listing's labels (without `:`) and addresses, in listing order.
    pub labels: Vec<(String, u32)>,
    label_map: HashMap<String, u32>,
    /// Where scopes start: the address of each scope-changing label, in listing order.
    pub marks: Vec<(u32, Scope)>,
}

impl Symbols {
    /// Builds the symbols of a project description.
    pub fn from_dcp(dcp: &Dcp) -> Symbols {
        let mut s = Symbols::default();
        let global = |path: &str, g: &crate::dcp_read::GlobalVar, depth: usize| Entry {
            path: path.to_string(),
            sym: DataSym {
                addr: g.addr,
                ty: Some(g.ty.clone()),
                size: g.size,
            },
            aggregate: false,
            depth,
            inferred: false,
        };
        for g in &dcp.globals {
            s.globals.push(global(&g.lname, g, 0));
            s.task.push(global(&g.pname, g, 0));
        }
        for g in &dcp.globals {
            s.globals.push(global(&g.pname, g, 1));
            s.task.push(global(&g.lname, g, 1));
        }
        let objs = dcp.objects();
        for o in &objs {
            if let (Some(a), false) = (o.abs_addr(), o.pname.is_empty()) {
                s.task.push(Entry {
                    path: o.pname.clone(),
                    sym: DataSym {
                        addr: a,
                        ty: o.ty.clone(),
                        size: o.size,
                    },
                    aggregate: !o.children.is_empty(),
                    depth: 2,
                    inferred: false,
                });
            }
        }
        // One instance of each POU type.
        let mut inst_of: HashMap<String, &DataObj> = HashMap::new();
        for o in &objs {
            let Some(pt) = &o.ptype else { continue };
            let status = o.type_status.as_deref().unwrap_or("");
            if matches!(status, "program" | "function block" | "user function")
                || (!o.children.is_empty() && o.dims.is_empty())
            {
                inst_of.entry(pt.to_ascii_uppercase()).or_insert(o);
            }
        }
        for (pou, o) in &inst_of {
            let mut t = Table::default();
            t.add_fields(o, "", 0, 0);
            s.pous.insert(pou.clone(), t);
        }
        for l in &dcp.listing {
            if let Some(name) = l.label() {
                let name = name.trim_start_matches(':');
                s.labels.push((name.to_string(), l.addr));
                s.label_map
                    .entry(name.to_ascii_uppercase())
                    .or_insert(l.addr);
                if let Some(sc) = label_scope(name) {
                    s.marks.push((l.addr, sc));
                }
            }
        }
        s.infer_hidden(dcp, &inst_of);
        s
    }

    /// Places the variables a POU's `?INIT` initialises but the `DATA_MAP` omits.
    fn infer_hidden(&mut self, dcp: &Dcp, inst_of: &HashMap<String, &DataObj>) {
        let mut wanted: HashMap<String, Vec<(String, u32)>> = HashMap::new();
        let mut scope: Option<String> = None;
        for l in &dcp.listing {
            if let Some(name) = l.label() {
                let n = name.trim_start_matches(':');
                match label_scope(n) {
                    Some(Scope::Pou(p)) if n.to_ascii_uppercase().ends_with("?INIT") => {
                        scope = Some(p.to_ascii_uppercase())
                    }
                    Some(_) => scope = None,
                    None => {}
                }
                continue;
            }
            let Some(pou) = &scope else { continue };
            let Some((mn, ops)) = split_text(&l.text) else {
                continue;
            };
            let size = match (mn.to_ascii_uppercase().as_str(), ops.as_slice()) {
                ("$VMSYS.MCD" | "$VMSYS.MCD4A", [_, n, _]) => raw_hex(n).ok().map(|b| le(&b)),
                ("$VMSYS.FPAT" | "$VMSYS.FPAT4A", [_, _, n]) => raw_hex(n).ok().map(|b| le(&b)),
                _ => None,
            };
            let (Some(size), Some(dst)) = (size, ops.first()) else {
                continue;
            };
            let known = self.pous.get(pou).is_some_and(|t| t.get(dst).is_some())
                || self.globals.get(dst).is_some();
            if !known && !dst.contains('.') && !dst.starts_with('#') {
                let list = wanted.entry(pou.clone()).or_default();
                if !list.iter().any(|(n, _)| n.eq_ignore_ascii_case(dst)) {
                    list.push((dst.to_string(), size));
                }
            }
        }
        for (pou, list) in wanted {
            let (Some(obj), Some(table)) = (inst_of.get(&pou), self.pous.get_mut(&pou)) else {
                continue;
            };
            let total = obj.size as usize;
            let mut used = vec![false; total];
            let mut mark = |a: u32, n: u32| {
                for u in used.iter_mut().skip(a as usize).take(n as usize) {
                    *u = true;
                }
            };
            for e in table.entries.iter().filter(|e| e.depth == 0) {
                mark(e.sym.addr, e.sym.size);
            }
            if obj.type_status.as_deref() == Some("program") {
                for g in &dcp.globals {
                    mark(g.addr, g.size);
                }
            }
            for (name, size) in list {
                let n = size as usize;
                let align = n.clamp(1, 4).next_power_of_two().min(4);
                let fits =
                    |a: usize, used: &[bool]| a + n <= total && used[a..a + n].iter().all(|u| !u);
                let at = (0..total)
                    .step_by(align)
                    .find(|&a| fits(a, &used))
                    .or_else(|| (0..total).find(|&a| fits(a, &used)));
                let Some(at) = at else { continue };
                for u in &mut used[at..at + n] {
                    *u = true;
                }
                table.push(Entry {
                    path: name,
                    sym: DataSym {
                        addr: at as u32,
                        ty: None,
                        size,
                    },
                    aggregate: false,
                    depth: 0,
                    inferred: true,
                });
            }
        }
    }

    /// The scope of the code at a listing address: the one the last scope-changing
    /// label at or before it started (the task's before any).
    pub fn scope_at(&self, addr: u32) -> Scope {
        self.marks
            .iter()
            .rev()
            .find(|(a, _)| *a <= addr)
            .map_or(Scope::Task, |(_, s)| s.clone())
    }

    /// The address of a label of the listing (without `:`, case-insensitive).
    pub fn label(&self, name: &str) -> Option<u32> {
        self.label_map
            .get(&name.trim_start_matches(':').to_ascii_uppercase())
            .copied()
    }

    /// Looks a data name up in a scope (see the module documentation).
    pub fn data(&self, scope: &Scope, name: &str) -> Option<&Entry> {
        match scope {
            Scope::Task => self.task.get(name),
            Scope::Pou(p) => self
                .pous
                .get(&p.to_ascii_uppercase())
                .and_then(|t| t.get(name))
                .or_else(|| self.globals.get(name)),
        }
    }

    /// A resolver for the code of a scope, with the listing's labels.
    pub fn resolver<'a>(&'a self, scope: &Scope) -> ScopeResolver<'a> {
        ScopeResolver {
            syms: self,
            scope: scope.clone(),
            labels: None,
        }
    }

    /// A resolver for the code of a scope, with the given labels (upper-cased names
    /// without `:`).
    pub fn resolver_with<'a>(
        &'a self,
        scope: &Scope,
        labels: &'a HashMap<String, u32>,
    ) -> ScopeResolver<'a> {
        ScopeResolver {
            syms: self,
            scope: scope.clone(),
            labels: Some(labels),
        }
    }
}

/// A [`Resolver`] over [`Symbols`] in one scope.
#[derive(Clone, Debug)]
pub struct ScopeResolver<'a> {
    syms: &'a Symbols,
    scope: Scope,
    labels: Option<&'a HashMap<String, u32>>,
}

impl Resolver for ScopeResolver<'_> {
    fn data(&self, name: &str) -> Option<DataSym> {
        self.syms.data(&self.scope, name).map(|e| e.sym.clone())
    }

    fn label(&self, name: &str) -> Option<u32> {
        match self.labels {
            Some(m) => m
                .get(&name.trim_start_matches(':').to_ascii_uppercase())
                .copied(),
            None => self.syms.label(name),
        }
    }
}

/// Splits mnemonic text into the mnemonic and its operands.
pub fn split_text(text: &str) -> Option<(&str, Vec<&str>)> {
    let text = text.trim();
    if text.is_empty() {
        return None;
    }
    let (mn, rest) = text.split_once(char::is_whitespace).unwrap_or((text, ""));
    let rest = rest.trim();
    let ops = if rest.is_empty() {
        Vec::new()
    } else {
        rest.split(',').map(str::trim).collect()
    };
    Some((mn, ops))
}

/// The bytes written after `#` (hex digit pairs, in memory order).
fn raw_hex(s: &str) -> Result<Vec<u8>, String> {
    let h = s
        .strip_prefix('#')
        .ok_or_else(|| format!("`{s}` is not an immediate"))?;
    if h.is_empty() || !h.len().is_multiple_of(2) || !h.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!("bad immediate `{s}`"));
    }
    Ok((0..h.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&h[i..i + 2], 16).unwrap_or(0))
        .collect())
}

fn le(b: &[u8]) -> u32 {
    b.iter()
        .take(4)
        .rev()
        .fold(0u32, |acc, &x| acc << 8 | x as u32)
}

/// Opcodes by mnemonic, per mode.
fn by_name(mode: Mode) -> &'static HashMap<&'static str, Vec<Opcode>> {
    static TABLES: [OnceLock<HashMap<&'static str, Vec<Opcode>>>; 3] =
        [OnceLock::new(), OnceLock::new(), OnceLock::new()];
    let i = Mode::ALL.iter().position(|&m| m == mode).unwrap_or(0);
    TABLES[i].get_or_init(|| {
        let mut m: HashMap<&'static str, Vec<Opcode>> = HashMap::new();
        for x in 0..=u16::MAX {
            if let Some((name, _)) = isa::shape(Opcode(x), mode) {
                m.entry(name).or_default().push(Opcode(x));
            }
        }
        m
    })
}

/// A parsed operand.
enum Arg {
    Hex(Vec<u8>),
    Code(u32),
    Name(DataSym),
}

impl Arg {
    fn ty(&self) -> Option<Ty> {
        match self {
            Arg::Name(s) => s.ty.as_deref().and_then(Ty::from_name),
            _ => None,
        }
    }

    fn size(&self) -> Option<u32> {
        match self {
            Arg::Name(s) => Some(s.size),
            _ => None,
        }
    }
}

/// How the overloaded groups number their types.
#[derive(Copy, Clone, PartialEq)]
enum Coding {
    /// `Ty` codes.
    Plain,
    /// BOOL 0, BYTE 1, WORD 2, DWORD 3, LWORD 4.
    Logic,
    /// XOR: BOOL 0, BYTE 1, WORD 2, DWORD 4, LWORD 5.
    Xor,
    /// NEG: SINT 1, INT 2, DINT 3, LINT 4, REAL 7, LREAL 9.
    Neg,
    /// REAL 0, LREAL 1.
    Float,
}

fn code_of(t: Ty, c: Coding) -> Option<u8> {
    use Ty::*;
    match c {
        Coding::Plain => Some(t as u8),
        Coding::Logic => match t {
            Bool => Some(0),
            Byte => Some(1),
            Word => Some(2),
            Dword => Some(3),
            Lword => Some(4),
            _ => None,
        },
        Coding::Xor => match t {
            Bool => Some(0),
            Byte => Some(1),
            Word => Some(2),
            Dword => Some(4),
            Lword => Some(5),
            _ => None,
        },
        Coding::Neg => match t {
            Sint => Some(1),
            Int => Some(2),
            Dint => Some(3),
            Lint => Some(4),
            Real => Some(7),
            Lreal => Some(9),
            _ => None,
        },
        Coding::Float => match t {
            Real => Some(0),
            Lreal => Some(1),
            _ => None,
        },
    }
}

/// The type of an operand of unknown type, by its size.
fn ty_by_size(size: u32, c: Coding) -> Option<Ty> {
    let logic = matches!(c, Coding::Logic | Coding::Xor);
    Some(match size {
        1 if logic => Ty::Bool,
        1 => Ty::Sint,
        2 if logic => Ty::Word,
        2 => Ty::Int,
        4 if logic => Ty::Dword,
        4 => Ty::Dint,
        8 if logic => Ty::Lword,
        8 => Ty::Lint,
        _ => return None,
    })
}

/// Picks the type of an overloaded operation: the first of `srcs` with a known
/// type, else `dst`, else by size in the same order.
fn pick_ty(args: &[Arg], srcs: &[usize], dst: Option<usize>, c: Coding) -> Option<Ty> {
    let order: Vec<usize> = srcs.iter().copied().chain(dst).collect();
    order
        .iter()
        .find_map(|&i| args.get(i).and_then(Arg::ty))
        .or_else(|| {
            order.iter().find_map(|&i| {
                args.get(i)
                    .and_then(Arg::size)
                    .and_then(|s| ty_by_size(s, c))
            })
        })
}

/// Chooses the opcode of an overloaded `$DEFAULT.*` mnemonic.
fn overload(mn: &str, args: &[Arg], cands: &[Opcode], mode: Mode) -> Result<Opcode, String> {
    let n = args.len();
    let group = cands[0].group();
    let fname = mn.rsplit('.').next().unwrap_or(mn).to_ascii_uppercase();
    let all_src: Vec<usize> = (1..n).collect();
    let no_ty = || format!("{mn}: cannot tell the operand type");
    let ty = |srcs: &[usize], dst: bool, c: Coding| -> Result<(Ty, u8), String> {
        let t = pick_ty(args, srcs, if dst { Some(0) } else { None }, c).ok_or_else(no_ty)?;
        let code = code_of(t, c).ok_or_else(|| format!("{mn} has no {} form", t.name()))?;
        Ok((t, code))
    };
    use op::group as g;
    let variadic = |c: Coding| -> Result<Opcode, String> {
        let count = n
            .checked_sub(1)
            .filter(|&k| (2..=15).contains(&k))
            .ok_or_else(|| format!("{mn}: bad operand count"))?;
        let (_, code) = ty(&all_src, true, c)?;
        Ok(Opcode::new(group, (count as u8) << 4 | code))
    };
    let f = match group {
        g::ADD | g::MUL | g::MAX | g::MIN => return variadic(Coding::Plain),
        g::AND | g::OR => return variadic(Coding::Logic),
        g::XOR => return variadic(Coding::Xor),
        g::MUX => {
            let count = n
                .checked_sub(1)
                .filter(|&k| (2..=15).contains(&k))
                .ok_or_else(|| format!("{mn}: bad operand count"))?;
            let (_, code) = ty(&(2..n).collect::<Vec<_>>(), true, Coding::Plain)?;
            return Ok(Opcode::new(group, (count as u8) << 4 | code));
        }
        g::SUB | g::DIV => {
            let (_, code) = ty(&all_src, true, Coding::Plain)?;
            if fname == "MOD" {
                0x10 | code
            } else {
                code
            }
        }
        g::GT..=g::NE => ty(&all_src, false, Coding::Plain)?.1,
        g::SEL => ty(&[2, 3], true, Coding::Plain)?.1,
        g::LIMIT => ty(&[2, 1, 3], true, Coding::Plain)?.1,
        g::NEG if fname == "NEG" => ty(&all_src, true, Coding::Neg)?.1,
        g::NEG => 0x10 | ty(&all_src, true, Coding::Logic)?.1,
        g::SHIFT => {
            let base = match fname.as_str() {
                "SHL" => 0x00,
                "SHR" => 0x10,
                "ROL" => 0x20,
                _ => 0x30,
            };
            base | ty(&[1], true, Coding::Logic)?.1
        }
        g::MATH if fname == "ABS" => 0x10 | ty(&all_src, true, Coding::Plain)?.1,
        g::MATH if fname == "EXPT" => {
            return Err(format!("{mn}: the EXPT overloads are not known"))
        }
        g::MATH => {
            let even = cands.iter().map(|o| o.func()).min().unwrap_or(0);
            even + ty(&all_src, true, Coding::Float)?.1
        }
        _ => return Err(format!("{mn}: no rule to choose among its opcodes")),
    };
    let o = Opcode::new(group, f);
    if cands.contains(&o) && isa::shape(o, mode).is_some() {
        Ok(o)
    } else {
        Err(format!("{mn}: no opcode {o} for these operand types"))
    }
}

fn parse_arg(s: &str, r: &dyn Resolver) -> Result<Arg, String> {
    if s.starts_with('#') {
        return raw_hex(s).map(Arg::Hex);
    }
    if let Some(l) = s.strip_prefix(':') {
        if l.starts_with('?') {
            return r
                .label(l)
                .map(Arg::Code)
                .ok_or_else(|| format!("unknown label `{s}`"));
        }
        return u32::from_str_radix(l, 16)
            .map(Arg::Code)
            .map_err(|_| format!("bad code address `{s}`"));
    }
    if s.is_empty() {
        return Err("an empty operand".into());
    }
    r.data(s)
        .map(Arg::Name)
        .ok_or_else(|| format!("unknown name `{s}`"))
}

/// Assembles the mnemonic text of one listing line into an instruction.
pub fn assemble(text: &str, mode: Mode, r: &dyn Resolver) -> Result<Inst, String> {
    let (mn, ops) = split_text(text).ok_or("empty line")?;
    let args = ops
        .iter()
        .map(|s| parse_arg(s, r))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| format!("{text}: {e}"))?;
    let err = |m: String| format!("{text}: {m}");
    let upper = mn.to_ascii_uppercase();
    let table = by_name(mode);
    let key = table
        .keys()
        .find(|k| k.eq_ignore_ascii_case(&upper))
        .ok_or_else(|| err(format!("unknown mnemonic in mode {}", mode.name())))?;
    let cands = &table[key];
    let (opcode, args) = if upper == "$VMSYS.MMV" {
        let [.., Arg::Hex(f)] = args.as_slice() else {
            return Err(err("MMV takes `dst, src, #ff`".into()));
        };
        let [f] = f.as_slice() else {
            return Err(err("MMV's function byte is one byte".into()));
        };
        let o = Opcode::new(op::group::MMV, *f);
        isa::shape(o, mode).ok_or_else(|| err(format!("no opcode {o}")))?;
        let mut args = args;
        args.pop();
        (o, args)
    } else if cands.len() == 1 {
        (cands[0], args)
    } else {
        (overload(mn, &args, cands, mode).map_err(&err)?, args)
    };
    let (_, kinds) = isa::shape(opcode, mode).ok_or_else(|| err(format!("no opcode {opcode}")))?;
    let mut it = args.into_iter();
    let mut operands = Vec::with_capacity(kinds.len());
    let a = mode.addr_bytes();
    let imm = |b: Vec<u8>, w: usize, what: &str| -> Result<u32, String> {
        if b.len() == w {
            Ok(le(&b))
        } else {
            Err(format!("{what} takes {w} byte(s), not {}", b.len()))
        }
    };
    for k in kinds {
        let next = it.next().ok_or_else(|| err("too few operands".into()))?;
        let o = match (k, next) {
            (Kind::Data, Arg::Name(d)) => Operand::Data(d.addr),
            (Kind::Data, Arg::Hex(b)) => {
                Operand::Data(imm(b, a, "a literal address").map_err(&err)?)
            }
            (Kind::Code, Arg::Code(c)) => Operand::Code(c),
            (Kind::Byte, Arg::Hex(b)) => Operand::Imm(imm(b, 1, "the operand").map_err(&err)?),
            (Kind::Word, Arg::Hex(b)) => Operand::Imm(imm(b, 2, "the operand").map_err(&err)?),
            (Kind::Dword, Arg::Hex(b)) => Operand::Imm(imm(b, 4, "the operand").map_err(&err)?),
            (Kind::Bytes | Kind::Bytes4A, Arg::Hex(count)) => {
                let w = if k == Kind::Bytes { 1 } else { 4 };
                let n = imm(count, w, "the count").map_err(&err)? as usize;
                let Some(Arg::Hex(data)) = it.next() else {
                    return Err(err("the bytes are missing".into()));
                };
                let want = if k == Kind::Bytes { n } else { isa::padded4(n) };
                if data.len() != want {
                    return Err(err(format!("{} bytes given, {want} expected", data.len())));
                }
                if data[n..].iter().any(|&p| p != isa::MCD4A_PAD) {
                    return Err(err("padding other than FF".into()));
                }
                Operand::Bytes(data[..n].to_vec())
            }
            (k, _) => return Err(err(format!("an operand does not fit {k:?}"))),
        };
        operands.push(o);
    }
    if it.next().is_some() {
        return Err(err("too many operands".into()));
    }
    Ok(Inst::new(opcode, operands))
}

/// Assembles one line and encodes it.
pub fn assemble_bytes(text: &str, mode: Mode, r: &dyn Resolver) -> Result<Vec<u8>, String> {
    let i = assemble(text, mode, r)?;
    let mut v = Vec::new();
    i.encode(mode, &mut v);
    Ok(v)
}

/// A listing assembled from its mnemonic text.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Assembled {
    /// The code image.
    pub code: Vec<u8>,
    /// For each listing line, the address it was placed at.
    pub addrs: Vec<u32>,
    /// The labels (without `:`) and the addresses they got, in listing order.
    pub labels: Vec<(String, u32)>,
}

/// Assembles a whole listing from its text only (labels and mnemonics; the address
/// and hex columns are ignored), in two passes, starting at code address 0. Scopes
/// follow the labels as the module documentation describes.
pub fn assemble_listing(
    lines: &[ListingLine],
    mode: Mode,
    syms: &Symbols,
) -> Result<Assembled, String> {
    let mut labels: HashMap<String, u32> = HashMap::new();
    let mut out = Assembled::default();
    for pass in 0..2 {
        let mut pc = 0u32;
        let mut scope = Scope::Task;
        out = Assembled::default();
        let placeholder = PlaceholderLabels {
            syms,
            scope: Scope::Task,
        };
        for l in lines {
            out.addrs.push(pc);
            if let Some(name) = l.label() {
                let name = name.trim_start_matches(':');
                if pass == 0 {
                    labels.entry(name.to_ascii_uppercase()).or_insert(pc);
                }
                out.labels.push((name.to_string(), pc));
                if let Some(s) = label_scope(name) {
                    scope = s;
                }
                continue;
            }
            let inst = if pass == 0 {
                let r = PlaceholderLabels {
                    scope: scope.clone(),
                    ..placeholder.clone()
                };
                assemble(&l.text, mode, &r)
            } else {
                assemble(&l.text, mode, &syms.resolver_with(&scope, &labels))
            }
            .map_err(|e| format!("line at {:04x}: {e}", l.addr))?;
            let before = out.code.len();
            inst.encode(mode, &mut out.code);
            pc += (out.code.len() - before) as u32;
        }
    }
    Ok(out)
}

/// The first pass's resolver: real data names, every label at 0.
#[derive(Clone)]
struct PlaceholderLabels<'a> {
    syms: &'a Symbols,
    scope: Scope,
}

impl Resolver for PlaceholderLabels<'_> {
    fn data(&self, name: &str) -> Option<DataSym> {
        self.syms.data(&self.scope, name).map(|e| e.sym.clone())
    }

    fn label(&self, _: &str) -> Option<u32> {
        Some(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct R;
    impl Resolver for R {
        fn data(&self, name: &str) -> Option<DataSym> {
            let (addr, ty, size) = match name {
                "WN" => (0x98, "INT", 2),
                "?L?CST0224" => (0xC2, "INT", 2),
                "F" => (0x0C, "DWORD", 4),
                "R" => (0x10, "REAL", 4),
                "LR" => (0x20, "LREAL", 8),
                "B" => (0x04, "BOOL", 1),
                "TON1.PT" => (0x0C, "TIME", 4),
                "TON1" => (0x08, "TON", 20),
                _ => return None,
            };
            Some(DataSym {
                addr,
                ty: Some(ty.into()),
                size,
            })
        }
        fn label(&self, name: &str) -> Option<u32> {
            (name == "?IEC_61131.TON?CODE").then_some(0x3D)
        }
    }

    fn hex(text: &str, mode: Mode) -> String {
        assemble_bytes(text, mode, &R)
            .unwrap()
            .iter()
            .map(|b| format!("{b:02X}"))
            .collect()
    }

    #[test]
    fn assembles_listing_lines() {
        assert_eq!(
            hex("$DEFAULT.ADD WN, WN, ?L?CST0224", Mode::M16),
            "012298009800C200"
        );
        assert_eq!(
            hex("$VMSYS.MCD TON1.PT, #04, #E8030000", Mode::M16),
            "1C150C0004E8030000"
        );
        assert_eq!(
            hex("$VMSYS.CALB TON1, :?IEC_61131.TON?CODE", Mode::M16),
            "1C1608003D00"
        );
        assert_eq!(hex("$VMSYS.CALB #0000, :0010", Mode::M16), "1C1600001000");
        assert_eq!(hex("$DEFAULT.XOR F, F, F", Mode::M16), "0A240C000C000C00");
        assert_eq!(hex("$DEFAULT.NEG R, R", Mode::M16), "050710001000");
        assert_eq!(hex("$DEFAULT.NOT F, F", Mode::M16), "05130C000C00");
        assert_eq!(hex("$DEFAULT.SHR F, F, WN", Mode::M16), "0B130C000C009800");
        assert_eq!(hex("$DEFAULT.SQRT LR, LR", Mode::M16), "062120002000");
        assert_eq!(
            hex("$DEFAULT.GT B, R, R", Mode::M16),
            "100904001000 1000".replace(' ', "")
        );
        assert_eq!(
            hex("$VMSYS.MCD4A F, #02000000, #0100FFFF", Mode::M32A),
            "1C3700000C000000020000000100FFFF"
        );
        assert_eq!(hex("$VMSYS.MMV F, R, #84", Mode::M16), "07840C001000");
        assert!(assemble("$VMSYS.MCD4A F, #02000000, #0100FF00", Mode::M32A, &R).is_err());
        assert!(assemble("$VMSYS.MCD F, #02, #01", Mode::M16, &R).is_err());
        assert!(assemble("$VMSYS.DPRDL4A F, R, #01000000", Mode::M32A, &R).is_err());
        assert!(assemble("$DEFAULT.ADD B, NOPE, B", Mode::M16, &R).is_err());
        assert!(assemble("$DEFAULT.AND R, R, R", Mode::M16, &R).is_err());
    }

    #[test]
    fn label_scopes() {
        assert_eq!(
            label_scope(":?IEC_61131.TON?CODE"),
            Some(Scope::Pou("IEC_61131.TON".into()))
        );
        assert_eq!(label_scope("?B.P?INIT"), Some(Scope::Pou("B.P".into())));
        assert_eq!(label_scope(":?B.T?TSKLOOP"), Some(Scope::Task));
        assert_eq!(label_scope(":?IEC_61131.TONIF?B0083"), None);
    }
}
