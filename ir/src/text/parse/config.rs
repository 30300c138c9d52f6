//! The lines of the text form that name the globals' data object and describe the
//! configuration: `globals @"$globals"`, `configuration "Config0"` and, after it, one
//! `resource "Res0" programs "main" globals "g"` line per resource.

use super::*;

/// A `resource` line, raw.
#[derive(Debug)]
pub(super) struct RawResource<'a> {
    pub(super) name: Cow<'a, str>,
    pub(super) programs: Vec<Cow<'a, str>>,
    pub(super) globals: Vec<Cow<'a, str>>,
}

/// A `configuration` line and its `resource` lines, raw.
#[derive(Debug)]
pub(super) struct RawConfiguration<'a> {
    pub(super) name: Cow<'a, str>,
    pub(super) resources: Vec<RawResource<'a>>,
}

impl<'a> Parser<'a> {
    /// `globals @data`.
    pub(super) fn globals_line(&mut self) -> Result<(), ParseError> {
        let pos = self.bump();
        let d = self.global("a data name")?;
        if self.raw.globals.is_some() {
            return self.err(pos, "`globals` is given twice");
        }
        self.raw.globals = Some(d);
        Ok(())
    }

    /// `configuration "name"`.
    pub(super) fn configuration_line(&mut self) -> Result<(), ParseError> {
        let pos = self.bump();
        let name = self.string("the configuration's name as a string")?;
        if self.raw.configuration.is_some() {
            return self.err(pos, "`configuration` is given twice");
        }
        self.raw.configuration = Some(RawConfiguration {
            name,
            resources: Vec::new(),
        });
        Ok(())
    }

    /// `resource "name" [programs "a" "b"] [globals "g"]`, after `configuration`.
    pub(super) fn resource_line(&mut self) -> Result<(), ParseError> {
        let pos = self.bump();
        let name = self.string("the resource's name as a string")?;
        let mut lists: [Vec<Cow<'a, str>>; 2] = [Vec::new(), Vec::new()];
        for (k, kw) in ["programs", "globals"].iter().enumerate() {
            if self.is_word(kw) {
                self.bump();
                while matches!(self.peek(), Tok::Str(_)) {
                    let s = self.string("a name as a string")?;
                    lists[k].push(s);
                }
            }
        }
        let [programs, globals] = lists;
        let Some(c) = self.raw.configuration.as_mut() else {
            return self.err(
                pos,
                "a `resource` line comes after the `configuration` line",
            );
        };
        c.resources.push(RawResource {
            name,
            programs,
            globals,
        });
        Ok(())
    }
}

impl Resolver<'_> {
    /// The configuration of the raw form (its names are checked by the verifier).
    pub(super) fn configuration(&self, c: &RawConfiguration) -> Configuration {
        Configuration {
            name: c.name.to_string(),
            resources: c
                .resources
                .iter()
                .map(|r| Resource {
                    name: r.name.to_string(),
                    programs: r.programs.iter().map(|p| p.to_string()).collect(),
                    globals: r.globals.iter().map(|g| g.to_string()).collect(),
                })
                .collect(),
        }
    }
}
