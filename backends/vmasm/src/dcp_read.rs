//! Reading CPDev `.dcp` project descriptions: the XML the CPDev compiler writes beside
//! an `.xcp` code image (tasks, memory sizes, global variables, the `DATA_MAP` tree of
//! variables with their addresses, and the `MNEMONIC_MAP` listing).
//!
//! The files may start with a UTF-8 byte-order mark. Addresses are hexadecimal without
//! a prefix; `#null` stands for "no address" (array bound constants have none).

use roxmltree::{Document, Node};

/// A parsed `.dcp` project description.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dcp {
    /// `StringCompilerVersion` of `<TARGET>` (e.g. `0.4.14.71`), if present.
    pub compiler_version: Option<String>,
    /// The addressing mode, where the description says (`<TARGET Mode="mach16b">`,
    /// written by plcc; the CPDev compiler's descriptions do not say).
    pub mode: Option<crate::isa::Mode>,
    /// The tasks (`<TASKS><TASK>`), in file order.
    pub tasks: Vec<Task>,
    /// Size in bytes of the code image (`<MEMORY_MAP Type="code"><file Size>`).
    pub code_size: Option<u32>,
    /// Size in bytes of data memory (`<MEMORY_MAP Type="data"><file Size>`).
    pub data_size: Option<u32>,
    /// The global variables (`<GLOBAL><VAR>`), in file order.
    pub globals: Vec<GlobalVar>,
    /// The top-level objects of `<DATA_MAP>` (globals and tasks), with their children.
    pub data_map: Vec<DataObj>,
    /// The `<MNEMONIC_MAP>` listing: labels and instructions, source markers left out.
    pub listing: Vec<ListingLine>,
    /// The address on the listing's last line (`:01a4`), the end of the code.
    pub listing_end: Option<u32>,
}

/// A task of the project.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Task {
    /// Local name (`LName`), e.g. `TASK_LD`.
    pub name: String,
    /// Qualified name (`PName`), e.g. `Blinking_light.TASK_LD`.
    pub pname: String,
    /// The cycle in milliseconds (`Cycle`, converted from `CycleUnit` `ms` or `s`).
    pub cycle_ms: u32,
    /// `LoopType` (0: cyclic).
    pub loop_type: u32,
    /// The code address where each scan after the first starts (`BodyCodeAddres`).
    pub body_addr: u32,
}

/// A global variable (`<GLOBAL><VAR>`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GlobalVar {
    /// Local name, e.g. `ONOFF`.
    pub lname: String,
    /// Qualified name, e.g. `Blinking_light.ONOFF`.
    pub pname: String,
    /// Absolute data address.
    pub addr: u32,
    /// Size in bytes.
    pub size: u32,
    /// Type name, e.g. `BOOL`.
    pub ty: String,
    /// Qualified type name, e.g. `$DEFAULT.BOOL`.
    pub ptype: String,
}

/// An object of the `DATA_MAP` tree: a variable, an FB or program instance, an array,
/// a function's call area (`?LCALL?…`), or a task.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DataObj {
    /// `ObjType`: `VAR` or `TASK`.
    pub obj_type: String,
    /// Local name (`LName`).
    pub lname: String,
    /// Qualified path (`PName`), e.g. `Blinking_light.TASK_LD.BLINKING_LIGHT_01.TON1.PT`.
    pub pname: String,
    /// `Addr`: relative to the parent instance when `relative` (`AdrType="rdlabel"`),
    /// else absolute (`gdlabel`); `None` for `#null`.
    pub addr: Option<u32>,
    /// True when `Addr` is relative to the enclosing instance (`rdlabel`).
    pub relative: bool,
    /// `CAddr`: the absolute address (`gdlabel`) of a relative object; `None` when
    /// absent or `#null`.
    pub caddr: Option<u32>,
    /// Size in bytes.
    pub size: u32,
    /// `Type`, e.g. `TIME`, `TON`, `?P_NUMBERS?ARRAY?0298`.
    pub ty: Option<String>,
    /// `PType`, e.g. `$DEFAULT.TIME`, `IEC_61131.TON`.
    pub ptype: Option<String>,
    /// `TypeStatus`: `build-in type`, `function block`, `program`, `array`, `user function`.
    pub type_status: Option<String>,
    /// `ArrayBase` of an array (the element type name).
    pub array_base: Option<String>,
    /// The array bounds (`<DIMENSIONS><LEVEL LoBound UpBound>`), outermost first.
    pub dims: Vec<(i64, i64)>,
    /// Nested objects (instance fields, array bound constants).
    pub children: Vec<DataObj>,
}

impl DataObj {
    /// The absolute address: `CAddr`, or `Addr` of an absolute object.
    pub fn abs_addr(&self) -> Option<u32> {
        self.caddr.or(if self.relative { None } else { self.addr })
    }

    /// This object and all objects below it, depth first.
    pub fn walk(&self) -> Vec<&DataObj> {
        let mut out = vec![self];
        for c in &self.children {
            out.extend(c.walk());
        }
        out
    }
}

/// One line of the `MNEMONIC_MAP` listing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ListingLine {
    /// The code address.
    pub addr: u32,
    /// The encoded bytes (empty for a label line). Hex columns the listing wraps onto
    /// continuation lines (`…`) are joined.
    pub bytes: Vec<u8>,
    /// The hex column as written (groups separated by spaces; wrapped parts joined).
    pub hex: String,
    /// The mnemonic text (`$VMSYS.MCD TON1.PT, #04, #E8030000`) or the label
    /// (`:?IEC_61131.TON?CODE`), trimmed.
    pub text: String,
}

impl ListingLine {
    /// The label name (with its leading `:`) if this is a label line.
    pub fn label(&self) -> Option<&str> {
        if self.bytes.is_empty() && self.text.starts_with(':') {
            Some(&self.text)
        } else {
            None
        }
    }
}

/// What `Dcp::find_var` returns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VarLoc {
    /// Absolute data address.
    pub addr: u32,
    /// Size in bytes.
    pub size: u32,
    /// Type name (`INT`, `TIME`, an FB name, or an array's element type when the path
    /// names an array element).
    pub ty: String,
}

fn hex_u32(s: &str) -> Result<Option<u32>, String> {
    let s = s.trim();
    if s == "#null" || s.is_empty() {
        return Ok(None);
    }
    u32::from_str_radix(s, 16)
        .map(Some)
        .map_err(|_| format!("bad hex address `{s}`"))
}

fn dec_u32(s: &str, what: &str) -> Result<u32, String> {
    s.trim().parse().map_err(|_| format!("bad {what} `{s}`"))
}

fn attr<'a>(n: Node<'a, 'a>, name: &str) -> Result<&'a str, String> {
    n.attribute(name)
        .ok_or_else(|| format!("<{}> without {name}", n.tag_name().name()))
}

fn child<'a, 'i>(n: Node<'a, 'i>, name: &str) -> impl Iterator<Item = Node<'a, 'i>> + use<'a, 'i> {
    let name = name.to_string();
    n.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == name)
}

fn parse_obj(n: Node) -> Result<DataObj, String> {
    let addr_attr = n.attribute("Addr").unwrap_or("#null");
    let mut dims = Vec::new();
    for d in child(n, "DIMENSIONS") {
        for l in child(d, "LEVEL") {
            let b = |k: &str| -> Result<i64, String> {
                attr(l, k)?.trim().parse().map_err(|_| format!("bad {k}"))
            };
            dims.push((b("LoBound")?, b("UpBound")?));
        }
    }
    let mut children = Vec::new();
    for c in child(n, "OBJ") {
        children.push(parse_obj(c)?);
    }
    let own = |k: &str| n.attribute(k).map(str::to_string);
    Ok(DataObj {
        obj_type: n.attribute("ObjType").unwrap_or("VAR").to_string(),
        lname: attr(n, "LName")?.to_string(),
        pname: n.attribute("PName").unwrap_or_default().to_string(),
        addr: hex_u32(addr_attr)?,
        relative: n.attribute("AdrType") == Some("rdlabel"),
        caddr: match n.attribute("CAddr") {
            Some(s) => hex_u32(s)?,
            None => None,
        },
        size: match n.attribute("Size") {
            Some(s) => dec_u32(s, "Size")?,
            None => 0,
        },
        ty: own("Type"),
        ptype: own("PType"),
        type_status: own("TypeStatus"),
        array_base: own("ArrayBase"),
        dims,
        children,
    })
}

/// Parses the text of `<MNEMONIC_MAP>`: label and instruction lines, without the
/// `;;;;;` / `;!!!!` source markers; the last line (`:01a4` alone) gives the end.
pub fn parse_listing(text: &str) -> Result<(Vec<ListingLine>, Option<u32>), String> {
    let mut out: Vec<ListingLine> = Vec::new();
    let mut end = None;
    for (no, raw) in text.lines().enumerate() {
        let line = raw.trim_end();
        if line.is_empty() || line.starts_with(';') {
            continue;
        }
        let err = |m: &str| format!("MNEMONIC_MAP line {}: {m}: `{line}`", no + 1);
        let Some(rest) = line.strip_prefix(':') else {
            return Err(err("does not start with `:`"));
        };
        let mut parts = rest.splitn(3, '|');
        let addr_s = parts.next().unwrap_or_default();
        let addr = u32::from_str_radix(addr_s.trim(), 16).map_err(|_| err("bad address"))?;
        let (Some(hex), Some(txt)) = (parts.next(), parts.next()) else {
            // The final line holds only the end address.
            end = Some(addr);
            continue;
        };
        let hex = hex.trim();
        let txt = txt.trim();
        // A hex column too wide for the listing goes on with `…` on the next line,
        // which has the same address and no text.
        if let Some(prev) = out.last_mut() {
            if prev.hex.ends_with('…') && prev.addr == addr && txt.is_empty() {
                prev.hex.pop();
                prev.hex.push_str(hex);
                prev.bytes = hex_bytes(&prev.hex).map_err(|m| err(&m))?;
                continue;
            }
        }
        if let Some(prev) = out.last() {
            if prev.hex.ends_with('…') {
                return Err(err("the hex of the previous line is cut off"));
            }
        }
        if txt.is_empty() {
            return Err(err("no mnemonic"));
        }
        // The bytes of a cut-off hex column are filled in when its rest is joined.
        let bytes = if hex.ends_with('…') {
            Vec::new()
        } else {
            hex_bytes(hex).map_err(|m| err(&m))?
        };
        if bytes.is_empty() && !txt.starts_with(':') && !hex.ends_with('…') {
            return Err(err("an instruction without bytes"));
        }
        out.push(ListingLine {
            addr,
            bytes,
            hex: hex.to_string(),
            text: txt.to_string(),
        });
    }
    if let Some(l) = out.last() {
        if l.hex.ends_with('…') {
            return Err(format!("MNEMONIC_MAP: the hex of `{}` is cut off", l.text));
        }
    }
    Ok((out, end))
}

fn hex_bytes(s: &str) -> Result<Vec<u8>, String> {
    let digits: Vec<u8> = s.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    if !digits.len().is_multiple_of(2) {
        return Err(format!("odd number of hex digits in `{s}`"));
    }
    digits
        .chunks(2)
        .map(|c| {
            std::str::from_utf8(c)
                .ok()
                .and_then(|t| u8::from_str_radix(t, 16).ok())
                .ok_or_else(|| format!("bad hex `{s}`"))
        })
        .collect()
}

/// Parses the text of a `.dcp` file (a leading byte-order mark is allowed).
pub fn parse(text: &str) -> Result<Dcp, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let doc = Document::parse(text).map_err(|e| format!("dcp: {e}"))?;
    let root = doc.root_element();
    let target = if root.tag_name().name() == "TARGET" {
        root
    } else {
        child(root, "TARGET").next().ok_or("dcp: no <TARGET>")?
    };
    let mut dcp = Dcp {
        compiler_version: target
            .attribute("StringCompilerVersion")
            .map(str::to_string),
        mode: target.attribute("Mode").and_then(crate::isa::Mode::parse),
        ..Dcp::default()
    };
    for g in child(target, "GLOBAL") {
        for v in child(g, "VAR") {
            dcp.globals.push(GlobalVar {
                lname: attr(v, "LName")?.to_string(),
                pname: attr(v, "PName")?.to_string(),
                addr: hex_u32(attr(v, "Addr")?)?.ok_or("global without address")?,
                size: dec_u32(attr(v, "Size")?, "Size")?,
                ty: attr(v, "Type")?.to_string(),
                ptype: v.attribute("PType").unwrap_or_default().to_string(),
            });
        }
    }
    for ts in child(target, "TASKS") {
        for t in child(ts, "TASK") {
            let cycle = dec_u32(t.attribute("Cycle").unwrap_or("0"), "Cycle")?;
            let cycle_ms = match t.attribute("CycleUnit").unwrap_or("ms") {
                "s" => cycle.saturating_mul(1000),
                _ => cycle,
            };
            dcp.tasks.push(Task {
                name: attr(t, "LName")?.to_string(),
                pname: t.attribute("PName").unwrap_or_default().to_string(),
                cycle_ms,
                loop_type: dec_u32(t.attribute("LoopType").unwrap_or("0"), "LoopType")?,
                body_addr: hex_u32(attr(t, "BodyCodeAddres")?)?.unwrap_or(0),
            });
        }
    }
    for m in child(target, "MEMORY_MAP") {
        let size = match child(m, "file").next().and_then(|f| f.attribute("Size")) {
            Some(s) => Some(dec_u32(s, "Size")?),
            None => None,
        };
        match m.attribute("Type") {
            Some("code") => dcp.code_size = size,
            Some("data") => dcp.data_size = size,
            _ => {}
        }
    }
    if let Some(mm) = child(target, "MNEMONIC_MAP").next() {
        let text: String = mm.children().filter_map(|c| c.text()).collect();
        let (listing, end) = parse_listing(&text)?;
        dcp.listing = listing;
        dcp.listing_end = end;
    }
    for dm in child(target, "DATA_MAP") {
        for o in child(dm, "OBJ") {
            dcp.data_map.push(parse_obj(o)?);
        }
    }
    Ok(dcp)
}

impl Dcp {
    /// Reads and parses a `.dcp` file.
    pub fn read(path: &std::path::Path) -> Result<Dcp, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let text = String::from_utf8(bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Every `DATA_MAP` object, depth first.
    pub fn objects(&self) -> Vec<&DataObj> {
        self.data_map.iter().flat_map(|o| o.walk()).collect()
    }

    /// Finds a variable by its `PName` path, ignoring case: the full path
    /// (`benchmark1.TASK.PERFECT_NUMBERS_01.I`), or a tail of it that names one
    /// variable only (`PERFECT_NUMBERS_01.I`, `I`), or a global's `PName`/`LName`.
    /// A final `[i]` (or `[i, j]`) selects an array element using the array's bounds.
    /// Returns the absolute address, size and type name.
    pub fn find_var(&self, path: &str) -> Option<VarLoc> {
        let path = path.trim();
        let (base, index) = match path.strip_suffix(']').and_then(|p| p.split_once('[')) {
            Some((b, i)) => (b.trim(), Some(i)),
            None => (path, None),
        };
        let obj = self.find_obj(base);
        let loc = match obj {
            Some(o) => VarLoc {
                addr: o.abs_addr()?,
                size: o.size,
                ty: o.ty.clone().unwrap_or_default(),
            },
            None => {
                let g = self.globals.iter().find(|g| {
                    g.pname.eq_ignore_ascii_case(base) || g.lname.eq_ignore_ascii_case(base)
                })?;
                VarLoc {
                    addr: g.addr,
                    size: g.size,
                    ty: g.ty.clone(),
                }
            }
        };
        let Some(index) = index else { return Some(loc) };
        let o = obj?;
        if o.dims.is_empty() {
            return None;
        }
        let idx: Vec<i64> = index
            .split(',')
            .map(|s| s.trim().parse().ok())
            .collect::<Option<_>>()?;
        if idx.len() != o.dims.len() {
            return None;
        }
        let count: i64 = o.dims.iter().map(|(lo, hi)| hi - lo + 1).product();
        if count <= 0 || o.size as i64 % count != 0 {
            return None;
        }
        let elem = o.size as i64 / count;
        let mut linear = 0i64;
        for (&i, &(lo, hi)) in idx.iter().zip(&o.dims) {
            if i < lo || i > hi {
                return None;
            }
            linear = linear * (hi - lo + 1) + (i - lo);
        }
        Some(VarLoc {
            addr: loc.addr + (linear * elem) as u32,
            size: elem as u32,
            ty: o.array_base.clone().unwrap_or_default(),
        })
    }

    fn find_obj(&self, path: &str) -> Option<&DataObj> {
        let objs = self.objects();
        if let Some(o) = objs.iter().find(|o| o.pname.eq_ignore_ascii_case(path)) {
            return Some(o);
        }
        let tail = format!(".{}", path.to_ascii_uppercase());
        let mut hits = objs
            .iter()
            .filter(|o| o.pname.to_ascii_uppercase().ends_with(&tail) && o.abs_addr().is_some());
        let first = hits.next()?;
        match hits.next() {
            None => Some(first),
            Some(_) => None,
        }
    }

    /// The labels of the listing with their addresses, in listing order (a label the
    /// listing repeats appears twice).
    pub fn labels(&self) -> Vec<(u32, &str)> {
        self.listing
            .iter()
            .filter_map(|l| Some((l.addr, l.label()?)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "\u{feff}<?xml version=\"1.0\" encoding=\"utf-8\"?>
<CPDEV version=\"1.0\"><TARGET StringCompilerVersion=\"0.4.14.71\">
<GLOBAL><VAR LName=\"ONOFF\" PName=\"B.ONOFF\" Addr=\"0000\" AdrType=\"gdlabel\" Size=\"1\" Type=\"BOOL\" PType=\"$DEFAULT.BOOL\" /></GLOBAL>
<TASKS><TASK LName=\"T\" PName=\"B.T\" LoopType=\"0\" Cycle=\"50\" CycleUnit=\"ms\" BodyCodeAddres=\"0019\" /></TASKS>
<MEMORY_MAP Type=\"code\"><file LoadAddr=\"0\" Size=\"420\">b.xcp</file></MEMORY_MAP>
<MEMORY_MAP Type=\"data\"><file LoadAddr=\"0\" Size=\"65\">#dummy</file></MEMORY_MAP>
<MNEMONIC_MAP Type=\"code\">
:0000| 1C15 0000 01 01                   | $VMSYS.MCD B.ONOFF, #01, #01   
:0006|                                   | :?B.T?TSKSTR
;;;;;|                                   | {B:4!46!1066}
;!!!!|                                   | \u{25a0}x := a &lt; b\u{25a0};
:0006| 1C370000 50000000 02000000 0000F\u{2026} | $VMSYS.MCD4A I, #02000000, #0000FFFF
:0006| FFF                               |
:0016 
</MNEMONIC_MAP>
<DATA_MAP><OBJ ObjType=\"TASK\" LName=\"T\" PName=\"B.T\" Addr=\"0000\" AdrType=\"gdlabel\" Size=\"55\">
<OBJ ObjType=\"VAR\" LName=\"A\" PName=\"B.T.P.A\" Addr=\"0010\" AdrType=\"rdlabel\" CAddr=\"0010\" CAdrType=\"gdlabel\" Size=\"8\" Type=\"?A?ARRAY\" ArrayBase=\"INT\">
<DIMENSIONS><LEVEL No=\"0\" LoBound=\"1\" UpBound=\"4\" /></DIMENSIONS>
<OBJ ObjType=\"VAR\" LName=\"LOW\" PName=\"B.T.P.A.LOW\" Addr=\"#null\" AdrType=\"rdlabel\" CAddr=\"#null\" Size=\"2\" Type=\"INT\" />
</OBJ></OBJ></DATA_MAP></TARGET></CPDEV>";

    #[test]
    fn parses_a_small_description() {
        let d = parse(SMALL).unwrap();
        assert_eq!(d.tasks[0].cycle_ms, 50);
        assert_eq!(d.tasks[0].body_addr, 0x19);
        assert_eq!((d.code_size, d.data_size), (Some(420), Some(65)));
        assert_eq!(d.globals[0].pname, "B.ONOFF");
        assert_eq!(d.listing.len(), 3);
        assert_eq!(d.listing[0].bytes, [0x1C, 0x15, 0, 0, 1, 1]);
        assert_eq!(d.listing[1].label(), Some(":?B.T?TSKSTR"));
        assert_eq!(d.listing[2].bytes.len(), 16);
        assert_eq!(d.listing[2].hex, "1C370000 50000000 02000000 0000FFFF");
        assert_eq!(d.listing_end, Some(0x16));
        let a = &d.data_map[0].children[0];
        assert_eq!(
            (a.addr, a.relative, a.dims.clone()),
            (Some(0x10), true, vec![(1, 4)])
        );
        assert_eq!(a.children[0].addr, None);
        assert_eq!(
            d.find_var("b.t.p.a[3]"),
            Some(VarLoc {
                addr: 0x14,
                size: 2,
                ty: "INT".into()
            })
        );
        assert_eq!(d.find_var("P.A").map(|v| v.size), Some(8));
        assert_eq!(d.find_var("onoff").map(|v| v.addr), Some(0));
        assert_eq!(d.find_var("a[5]"), None);
    }
}
