//! The tables of the text form. Function tables: `table t0 "I_Shape.Area" (ptr) -> f32
//! = [@a, -, @b]`, one line each (`-` is an empty entry), and their resolution. Tables
//! are numbered in declaration order; `call_table t0, v2(v1)` names one by its number.
//! Jump tables are the operands of an instruction: `br_table v5, block9(v1), [block2,
//! block3(v4)]`.

use super::*;

/// A `table` line, raw.
#[derive(Debug)]
pub(super) struct RawTable<'a> {
    pub(super) num: V,
    pub(super) name: Cow<'a, str>,
    pub(super) params: Vec<Type>,
    pub(super) result: Option<Type>,
    pub(super) entries: Vec<Option<Named<'a>>>,
}

impl<'a> Parser<'a> {
    /// `table tN "name" (types) [-> type] = [@f, -, …]`.
    pub(super) fn table_def(&mut self) -> Result<(), ParseError> {
        self.bump();
        let num = self.table_ref()?;
        let name = self.string("the table's name as a string")?;
        let (params, result) = self.signature()?;
        self.expect(Tok::Equals, "`=`")?;
        self.expect(Tok::LBracket, "`[`")?;
        let mut entries = Vec::new();
        if !self.eat(&Tok::RBracket) {
            loop {
                if self.eat(&Tok::Dash) {
                    entries.push(None);
                } else {
                    entries.push(Some(self.global("a function name such as `@f`, or `-`")?));
                }
                if self.eat(&Tok::RBracket) {
                    break;
                }
                self.expect(Tok::Comma, "`,` or `]`")?;
            }
        }
        self.raw.tables.push(RawTable {
            num,
            name,
            params,
            result,
            entries,
        });
        Ok(())
    }

    /// The operands of `br_table` after its mnemonic: `vI, default(args), [dest(args),
    /// …]` (the table may be empty: `[]`).
    pub(super) fn br_table(&mut self) -> Result<RawOp<'a>, ParseError> {
        let index = self.value()?;
        self.expect(Tok::Comma, "`,`")?;
        let default = self.block_call()?;
        self.expect(Tok::Comma, "`,`")?;
        self.expect(Tok::LBracket, "`[`")?;
        let mut table = Vec::new();
        if !self.eat(&Tok::RBracket) {
            loop {
                table.push(self.block_call()?);
                if self.eat(&Tok::RBracket) {
                    break;
                }
                self.expect(Tok::Comma, "`,` or `]`")?;
            }
        }
        Ok(RawOp::BrTable(Box::new((index, default, table))))
    }

    /// A table number such as `t0`.
    pub(super) fn table_ref(&mut self) -> Result<V, ParseError> {
        let (w, pos) = self.word("a table such as `t0`")?;
        match numbered(w, "t") {
            Some(n) => Ok(V { n, pos }),
            None => self.err(pos, format!("expected a table such as `t0`, found `{w}`")),
        }
    }
}

impl Resolver<'_> {
    /// The tables of the raw form, and the map from their numbers to their ids.
    pub(super) fn tables(
        &self,
        raw: &[RawTable],
        funcs: &HashMap<&str, FuncId>,
    ) -> Result<(Vec<Table>, HashMap<u32, TableId>), ParseError> {
        let mut ids = HashMap::new();
        let mut tables = Vec::with_capacity(raw.len());
        for t in raw {
            if ids.insert(t.num.n, TableId::new(tables.len())).is_some() {
                return self.err(t.num.pos, format!("t{} is declared twice", t.num.n));
            }
            let mut entries = Vec::with_capacity(t.entries.len());
            for e in &t.entries {
                entries.push(match e {
                    None => None,
                    Some(n) => match funcs.get(n.name.as_ref()) {
                        Some(&id) => Some(id),
                        None => return self.err(n.pos, format!("unknown function `@{}`", n.name)),
                    },
                });
            }
            tables.push(Table {
                name: t.name.to_string(),
                params: t.params.clone(),
                result: t.result,
                entries,
            });
        }
        Ok((tables, ids))
    }
}
