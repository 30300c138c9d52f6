//! What runs: configurations with their resources, tasks and program instances, the
//! global variables of each level, and what CODESYS-based editors keep in
//! `<addData>` (applications, global variable lists, POUs). Also the dialect the
//! file's header implies.

use super::*;

/// The editors built on CODESYS, as their `fileHeader` names them (lowercase).
const CODESYS_EDITORS: [&str; 5] = ["codesys", "e!cockpit", "twincat", "3s-smart", "3s - smart"];

/// The namespace of CODESYS's vendor data (`<data name="...">` in `<addData>`).
const CODESYS_DATA: &str = "http://www.3s-software.com/plcopenxml/";

impl Reader<'_, '_> {
    /// `<instances>` and the project's `<addData>`: configurations, global variable
    /// lists, CODESYS applications, and the POUs kept there (added to `p.pous`).
    pub(super) fn instances(&mut self, root: Node, p: &mut Project) {
        if let Some(cs) = kid(root, "instances").and_then(|i| kid(i, "configurations")) {
            for c in kids(cs, "configuration") {
                if let Some(x) = self.config(c, &mut p.pous) {
                    p.configs.push(x);
                }
            }
        }
        // CODESYS: a project's global variable lists and POUs outside any
        // application.
        for g in add_data(root, "globalvars").flat_map(|d| kids(d, "globalVars")) {
            let groups = self.global_vars(g);
            p.globals.extend(groups);
        }
        self.add_data_pous(root, &mut p.pous);
        self.add_data_interfaces(root, &mut p.interfaces);
        // Those of the resources (of configurations and applications).
        for r in root
            .descendants()
            .filter(|d| d.is_element() && d.tag_name().name() == "resource")
        {
            self.add_data_interfaces(r, &mut p.interfaces);
        }
        // CODESYS and TwinCAT "application" exports: the application is a resource
        // with no configuration around it; it becomes one of the same name, unless
        // it has nothing to run or declare.
        for r in add_data(root, "application").flat_map(|d| kids(d, "resource")) {
            let Some(res) = self.resource(r, &mut p.pous) else {
                continue;
            };
            if res.tasks.is_empty() && res.instances.is_empty() {
                p.globals.extend(res.globals);
            } else {
                p.configs.push(Config {
                    name: res.name.clone(),
                    globals: Vec::new(),
                    resources: vec![res],
                });
            }
        }
    }

    /// The POUs CODESYS keeps in the `<addData>` of `n` (`<data name=".../pou">`).
    fn add_data_pous(&mut self, n: Node, pous: &mut Vec<Pou>) {
        for pou in add_data(n, "pou").flat_map(|d| kids(d, "pou")) {
            if let Some(x) = self.pou(pou) {
                pous.push(x);
            }
        }
    }

    /// `<configuration>`; the POUs kept in its resources go to `pous`.
    fn config(&mut self, c: Node, pous: &mut Vec<Pou>) -> Option<Config> {
        let name = self.need_attr(c, "name")?;
        let globals = kids(c, "globalVars")
            .flat_map(|g| self.global_vars(g))
            .collect();
        let resources = kids(c, "resource")
            .filter_map(|r| self.resource(r, pous))
            .collect();
        Some(Config {
            name,
            globals,
            resources,
        })
    }

    /// `<resource>`: its globals, tasks and program instances; the POUs CODESYS
    /// keeps in its `<addData>` go to `pous`.
    fn resource(&mut self, r: Node, pous: &mut Vec<Pou>) -> Option<Resource> {
        let name = self.need_attr(r, "name")?;
        let globals = kids(r, "globalVars")
            .flat_map(|g| self.global_vars(g))
            .collect();
        let tasks = kids(r, "task").filter_map(|t| self.task(t)).collect();
        let instances = kids(r, "pouInstance")
            .filter_map(|i| self.instance(i))
            .collect();
        self.add_data_pous(r, pous);
        Some(Resource {
            name,
            globals,
            tasks,
            instances,
        })
    }

    /// `<task name="..." interval="..." priority="..." single="...">` and the
    /// program instances it runs.
    fn task(&mut self, t: Node) -> Option<Task> {
        let name = self.need_attr(t, "name")?;
        let mut interval = self.attr(t, "interval").filter(|i| !i.value.is_empty());
        if interval
            .as_ref()
            .is_none_or(|i| duration_ms(&i.value) == Some(0.0))
        {
            if let Some(s) = self.task_settings(t) {
                interval = Some(s);
            }
        }
        let single = self.attr(t, "single").filter(|s| !s.value.is_empty());
        if let Some(s) = &single {
            if s.value.starts_with('[') {
                self.error(
                    codes::E_UNSUPPORTED,
                    format!(
                        "not supported yet: a task triggered by several variables (`single=\"{}\"`)",
                        s.value
                    ),
                    s.range.clone(),
                );
            }
        }
        let instances = kids(t, "pouInstance")
            .filter_map(|i| self.instance(i))
            .collect();
        Some(Task {
            name,
            interval,
            priority: self.attr(t, "priority"),
            single,
            instances,
        })
    }

    /// The interval of a cyclic task in CODESYS's task settings (`<addData>`), for a
    /// task whose `interval` is missing or zero: TwinCAT's exports write `PT0S` there
    /// and the true interval in the settings (`Interval="10000" IntervalUnit="us"`;
    /// CODESYS writes `Interval="t#50ms"`).
    fn task_settings(&self, t: Node) -> Option<Text> {
        let s = add_data(t, "tasksettings")
            .flat_map(|d| kids(d, "TaskSettings"))
            .next()?;
        if s.attribute("KindOfTask") != Some("Cyclic") {
            return None;
        }
        let iv = self.attr(s, "Interval")?;
        if iv.value.contains('#') {
            return Some(iv);
        }
        let number = !iv.value.is_empty()
            && iv
                .value
                .bytes()
                .all(|b| b.is_ascii_digit() || b == b'.' || b == b'_');
        let unit = s
            .attribute("IntervalUnit")
            .unwrap_or("ms")
            .to_ascii_lowercase();
        if !number || !matches!(unit.as_str(), "ns" | "us" | "ms" | "s" | "m" | "h") {
            return None;
        }
        Some(Text {
            value: format!("T#{}{unit}", iv.value),
            range: iv.range,
            exact: Vec::new(),
        })
    }

    /// `<pouInstance name="..." typeName="...">`. CODESYS writes `typeName=""` for a
    /// PROGRAM that a task calls directly: the instance is the PROGRAM of its name.
    fn instance(&mut self, i: Node) -> Option<Instance> {
        let name = self.need_attr(i, "name")?;
        // `typeName` in TC6 2.01, `type` in 1.0.
        let type_name = match self.attr(i, "typeName").or_else(|| self.attr(i, "type")) {
            Some(t) if !t.value.is_empty() => t,
            Some(_) => name.clone(),
            None => {
                self.error(
                    codes::LD_BAD_PROJECT,
                    "`<pouInstance>` needs a `typeName` attribute",
                    self.qname(i),
                );
                return None;
            }
        };
        Some(Instance { name, type_name })
    }
}

/// The dialect of the editor that wrote the file: CODESYS's for CODESYS and the
/// editors built on it (WAGO e!COCKPIT, Beckhoff TwinCAT), told by the `fileHeader`'s
/// company or product name, or by CODESYS's vendor data in the project's
/// `<addData>`; IEC 61131-3 for any other (Beremiz, OpenPLC...).
pub(super) fn dialect(root: Node) -> Dialect {
    let header = kid(root, "fileHeader").is_some_and(|h| {
        ["companyName", "productName"]
            .iter()
            .filter_map(|a| h.attribute(*a))
            .any(|v| {
                let v = v.to_ascii_lowercase();
                CODESYS_EDITORS.iter().any(|k| v.contains(k))
            })
    });
    let data = [Some(root), kid(root, "contentHeader")]
        .into_iter()
        .flatten()
        .flat_map(|n| kids(n, "addData"))
        .flat_map(|a| kids(a, "data"))
        .any(|d| {
            d.attribute("name")
                .is_some_and(|n| n.starts_with(CODESYS_DATA))
        });
    if header || data {
        Dialect::Codesys
    } else {
        Dialect::Iec
    }
}

/// A duration in milliseconds, as PLCopen files write task intervals: an IEC
/// literal (`T#20ms`, `TIME#1h_2m`, `t#1.5s`), an XML Schema duration (`PT0.02S`),
/// or the old schema's `hh:mm:ss.ffffff`. `None` if it is none of these.
pub(crate) fn duration_ms(text: &str) -> Option<f64> {
    let t = text.trim();
    let num = |x: &str| -> Option<f64> {
        let x = x.replace('_', "");
        (!x.is_empty() && x.bytes().all(|c| c.is_ascii_digit() || c == b'.'))
            .then(|| x.parse::<f64>().ok())
            .flatten()
    };
    if let [h, m, s] = t.split(':').collect::<Vec<_>>()[..] {
        return Some((num(h)? * 3600.0 + num(m)? * 60.0 + num(s)?) * 1000.0);
    }
    let upper = t.to_ascii_uppercase();
    if let Some(rest) = upper.strip_prefix("PT") {
        // PTnHnMn.nS
        let (mut ms, mut digits) = (0.0, String::new());
        for ch in rest.chars() {
            let scale = match ch {
                'H' => 3_600_000.0,
                'M' => 60_000.0,
                'S' => 1000.0,
                c => {
                    digits.push(c);
                    continue;
                }
            };
            ms += num(&digits)? * scale;
            digits.clear();
        }
        return digits.is_empty().then_some(ms);
    }
    let (_, rest) = upper.split_once('#')?;
    if !matches!(&upper[..upper.find('#')?], "T" | "TIME" | "LT" | "LTIME") {
        return None;
    }
    // The parts of an IEC duration, largest unit first: 1d2h3m4s5ms6us7ns.
    let rest = rest.strip_prefix('-').unwrap_or(rest);
    let (mut ms, mut digits) = (0.0, String::new());
    let mut chars = rest.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_ascii_digit() || c == '.' || c == '_' {
            digits.push(c);
            continue;
        }
        let mut unit = c.to_string();
        if matches!(c, 'M' | 'U' | 'N') && chars.peek() == Some(&'S') {
            unit.push(chars.next()?);
        }
        let scale = match unit.as_str() {
            "D" => 86_400_000.0,
            "H" => 3_600_000.0,
            "M" => 60_000.0,
            "S" => 1000.0,
            "MS" => 1.0,
            "US" => 0.001,
            "NS" => 0.000_001,
            _ => return None,
        };
        ms += num(&digits)? * scale;
        digits.clear();
    }
    if !digits.is_empty() {
        return None;
    }
    Some(ms)
}
