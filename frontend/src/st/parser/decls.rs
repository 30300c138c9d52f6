//! Declarations of Structured Text: VAR blocks, types, initial values and
//! configurations (the parser's methods for them).

use super::*;

impl<'a> Parser<'a> {
    // ---------------------------------------------------------------- declarations

    pub(super) fn var_block(&mut self, ctx: DeclCtx) -> Option<VarBlock> {
        let kw = self.bump();
        let kind = var_kind(kw.kind)?;
        let ctx = match kind {
            VarKind::Config => DeclCtx::Config,
            VarKind::Access => DeclCtx::Access,
            _ => ctx,
        };
        let mut constant = false;
        let mut retain = false;
        let mut list = None;
        loop {
            match self.peek() {
                Tok::Constant => constant = true,
                Tok::Retain | Tok::Persistent => retain = true,
                Tok::NonRetain => retain = false,
                // `VAR PUBLIC`, `VAR PROTECTED`, ... of a FUNCTION_BLOCK.
                Tok::Ident
                    if self.peek_at(1) == Tok::Ident
                        && self.s.modifiers[2..6].contains(&Symbol(self.tok().data)) =>
                {
                    let t = self.tok();
                    let i = self.s.modifiers[2..6]
                        .iter()
                        .position(|&x| x == Symbol(t.data))
                        .expect("a modifier");
                    let a = [
                        AccessSpec::Public,
                        AccessSpec::Private,
                        AccessSpec::Protected,
                        AccessSpec::Internal,
                    ][i];
                    self.block_access = Some((a, self.tspan(t)));
                }
                // A global variable list's name (CODESYS's GVLs): on the keyword's
                // line, a name that starts no declaration (`VAR_GLOBAL GVL`).
                Tok::Ident
                    if kind == VarKind::Global
                        && ctx == DeclCtx::Global
                        && list.is_none()
                        && !self.tok().newline_before()
                        && !matches!(self.peek_at(1), Tok::Comma | Tok::Colon | Tok::At) =>
                {
                    list = Some(self.ident(self.tok()));
                }
                _ => break,
            }
            self.bump();
        }
        let mut decls = Vec::new();
        loop {
            let t = self.tok();
            match t.kind {
                Tok::EndVar => {
                    self.bump();
                    break;
                }
                Tok::Semi => {
                    self.bump();
                }
                Tok::Ident | Tok::At => {
                    let n = self.peek_at(1);
                    let stmt_like = t.kind == Tok::Ident
                        && (matches!(n, Tok::Assign | Tok::LParen | Tok::LBracket | Tok::Caret)
                            || (n == Tok::Dot && ctx != DeclCtx::Config)
                            || self.member_at().is_some());
                    if stmt_like {
                        self.missing_end_var(kw);
                        break;
                    }
                    if let Some(d) = self.var_decl(ctx) {
                        decls.push(d);
                    }
                }
                k if is_stmt_keyword(k) || is_section_stop(k) || closer_idx(k).is_some() => {
                    self.missing_end_var(kw);
                    break;
                }
                _ => {
                    let before = self.pos;
                    self.expected("a variable name or `END_VAR`");
                    self.skip_decl();
                    if self.pos == before {
                        self.bump();
                    }
                }
            }
        }
        decls.shrink_to_fit();
        Some(VarBlock {
            kind,
            constant,
            retain,
            list,
            decls,
            span: self.span_from(kw.start),
        })
    }

    pub(super) fn missing_end_var(&mut self, kw: Token) {
        let msg = format!("expected `END_VAR`, found {}", self.describe(self.pos));
        let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(self.tok()))
            .with_label("expected `END_VAR` before this")
            .with_secondary(self.tspan(kw), "this block is not closed");
        self.emit(self.pos, d);
    }

    /// One declaration with its `;`; `None` (after resynchronising) if it is broken.
    pub(super) fn var_decl(&mut self, ctx: DeclCtx) -> Option<VarDecl> {
        let Some(d) = self.var_decl_inner(ctx) else {
            self.skip_decl();
            return None;
        };
        // Reported by `var_decl_inner`.
        if d.names.is_empty() && matches!(ctx, DeclCtx::Pou | DeclCtx::Struct) {
            return None;
        }
        Some(d)
    }

    pub(super) fn var_decl_inner(&mut self, ctx: DeclCtx) -> Option<VarDecl> {
        let start = self.tok().start;
        let mut names = Vec::with_capacity(1);
        if !self.at(Tok::At) {
            loop {
                let name = if ctx == DeclCtx::Config {
                    self.instance_path()?
                } else {
                    self.expect_ident("a variable name")?
                };
                names.push(name);
                if !self.eat(Tok::Comma) {
                    break;
                }
            }
        }
        if self.at(Tok::Lit) && self.peek_at(1) == Tok::DotDot {
            // `IN 1 ..`: read as the input `IN`, the POU keeps the span.
            let s = self.sp(start, self.token(self.pos + 1).end);
            self.bump();
            self.bump();
            self.extensible.push(s);
        }
        let mut location = None;
        if names.is_empty() && matches!(ctx, DeclCtx::Pou | DeclCtx::Struct) {
            let t = self.tok();
            let d = Diagnostic::error(
                codes::UNNAMED_LOCATED_VAR,
                "a located variable needs a name here",
                self.tspan(t),
            )
            .with_label("add a name before `AT`");
            self.emit(self.pos, d);
        }
        if self.eat(Tok::At) {
            let a = self.tok();
            if a.kind != Tok::Address {
                self.expected("a direct address such as `%IX0.0`");
                return None;
            }
            self.bump();
            location = Some((Box::from(self.slice(a)), self.tspan(a)));
        }
        if ctx == DeclCtx::Access {
            let msg = "VAR_ACCESS declarations are not supported".to_string();
            let span = self.span_from(start);
            let d = Diagnostic::error(codes::SYNTAX_NOT_SUPPORTED, msg, span)
                .with_label("not supported; skipped");
            self.emit(self.pos.saturating_sub(1), d);
            return None;
        }
        self.expect_tok(Tok::Colon, "`:`")?;
        let ty = self.type_spec()?;
        let mut edge = None;
        if self.at_sym(0, self.s.r_edge) || self.at_sym(0, self.s.f_edge) {
            let t = self.bump();
            edge = Some((t.data == self.s.r_edge.0, self.tspan(t)));
        }
        let init = if self.eat(Tok::Assign) {
            Some(self.decl_init(&ty)?)
        } else {
            None
        };
        let span = self.span_from(start);
        self.expect_decl_semi();
        Some(VarDecl {
            names,
            location,
            ty,
            init,
            edge,
            span,
        })
    }

    /// `a.b.c` in VAR_CONFIG: one identifier whose symbol is the dotted path.
    pub(super) fn instance_path(&mut self) -> Option<Ident> {
        let first = self.expect_ident("an instance path")?;
        if !(self.at(Tok::Dot) && self.peek_at(1) == Tok::Ident) {
            return Some(first);
        }
        let mut path = self.interner.name(first.sym).to_string();
        while self.at(Tok::Dot) && self.peek_at(1) == Tok::Ident {
            self.bump();
            let t = self.bump();
            path.push('.');
            path.push_str(self.interner.name(Symbol(t.data)));
        }
        Some(Ident {
            sym: self.interner.intern_upper(&path),
            span: self.span_from(first.span.start),
        })
    }

    pub(super) fn type_block(&mut self, items: &mut Vec<Item>) {
        let kw = self.bump();
        loop {
            let t = self.tok();
            match t.kind {
                Tok::EndType => {
                    self.bump();
                    self.eat(Tok::Semi);
                    break;
                }
                Tok::Ident => {
                    if let Some(d) = self.type_decl() {
                        items.push(Item::Type(d));
                    }
                }
                Tok::Semi => {
                    self.bump();
                }
                k if is_section_stop(k) || is_stmt_keyword(k) => {
                    let msg = format!("expected `END_TYPE`, found {}", self.describe(self.pos));
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label("expected `END_TYPE` before this")
                        .with_secondary(self.tspan(kw), "this TYPE block is not closed");
                    self.emit(self.pos, d);
                    break;
                }
                _ => {
                    self.expected("a type name or `END_TYPE`");
                    self.bump();
                    self.skip_decl();
                }
            }
        }
    }

    pub(super) fn type_decl(&mut self) -> Option<TypeDecl> {
        let r = self.type_decl_inner();
        if r.is_none() {
            self.skip_decl();
        }
        r
    }

    pub(super) fn type_decl_inner(&mut self) -> Option<TypeDecl> {
        let t = self.bump();
        let name = self.ident(t);
        // CODESYS: `Derived EXTENDS Base : STRUCT ... END_STRUCT`.
        let mut extends = None;
        if self.at_sym(0, self.s.extends) {
            self.bump();
            extends = Some(self.expect_ident("the name of the base STRUCT")?);
        }
        self.expect_tok(Tok::Colon, "`:`")?;
        let spec = self.type_spec()?;
        let init = if self.eat(Tok::Assign) {
            Some(self.decl_init(&spec)?)
        } else {
            None
        };
        let span = self.span_from(t.start);
        // CODESYS writes `END_STRUCT END_TYPE` without the `;`.
        if !self.at(Tok::EndType) {
            self.expect_decl_semi();
        }
        Some(TypeDecl {
            name,
            extends,
            spec,
            init,
            span,
        })
    }

    // ---------------------------------------------------------------- types

    pub(super) fn type_spec(&mut self) -> Option<TypeSpec> {
        if !self.enter() {
            return None;
        }
        let r = self.type_spec_inner();
        self.leave();
        r
    }

    pub(super) fn type_spec_inner(&mut self) -> Option<TypeSpec> {
        let t = self.tok();
        match t.kind {
            Tok::String | Tok::WString => self.string_type(t),
            Tok::Array => self.array_type(),
            Tok::RefTo => self.ref_type(t),
            Tok::Struct => self.struct_type(),
            Tok::LParen => self.enum_type(None, t.start),
            Tok::Ident => self.named_type(t),
            _ => {
                self.expected("a type");
                None
            }
        }
    }

    pub(super) fn string_type(&mut self, t: Token) -> Option<TypeSpec> {
        self.bump();
        let close = match self.peek() {
            Tok::LBracket => Some((Tok::RBracket, "`]`")),
            Tok::LParen => Some((Tok::RParen, "`)`")),
            _ => None,
        };
        let mut len = None;
        if let Some((close, what)) = close {
            self.bump();
            len = Some(Box::new(self.expr()?));
            self.expect_tok(close, what)?;
        }
        Some(TypeSpec::String {
            wide: t.kind == Tok::WString,
            len,
            span: self.span_from(t.start),
        })
    }

    pub(super) fn ref_type(&mut self, t: Token) -> Option<TypeSpec> {
        self.bump();
        let target = self.type_spec();
        Some(TypeSpec::Ref {
            target: Box::new(target?),
            span: self.span_from(t.start),
        })
    }

    /// A named type, or `POINTER TO t`, `INT(0..10)`, `BYTE (a, b)`.
    pub(super) fn named_type(&mut self, t: Token) -> Option<TypeSpec> {
        if t.data == self.s.reference.0 && self.peek_at(1) == Tok::To {
            self.bump();
            self.bump();
            let target = self.type_spec();
            return Some(TypeSpec::Reference {
                target: Box::new(target?),
                span: self.span_from(t.start),
            });
        }
        if t.data == self.s.pointer.0 && self.peek_at(1) == Tok::To {
            self.bump();
            self.bump();
            let target = self.type_spec();
            return Some(TypeSpec::Pointer {
                target: Box::new(target?),
                span: self.span_from(t.start),
            });
        }
        self.bump();
        let mut name = self.ident(t);
        if self.at(Tok::Dot) && self.peek_at(1) == Tok::Ident {
            // CPDev's `LIBRARY.TYPE` (`IEC_61131.TON`, `Basic_blocks.TFF`): the
            // qualifier names the library the type comes from, and plcc has one name
            // space, so the type is the last name. The span keeps the qualifier, so a
            // diagnostic quotes the name as written.
            self.bump();
            let last = self.bump();
            name = Ident {
                sym: Symbol(last.data),
                span: self.span_from(t.start),
            };
        }
        if !self.at(Tok::LParen) {
            return Some(TypeSpec::Named(name));
        }
        if self.peek_at(1) == Tok::Ident
            && matches!(self.peek_at(2), Tok::Comma | Tok::Assign | Tok::RParen)
        {
            // `BYTE (a := 1, b := 2)`: an enumeration with its base type first.
            return self.enum_type(Some(name), t.start);
        }
        self.subrange(name)
    }

    /// `(lo..hi)` after the base type.
    pub(super) fn subrange(&mut self, base: Ident) -> Option<TypeSpec> {
        self.bump();
        let lo = self.expr()?;
        self.expect_tok(Tok::DotDot, "`..`")?;
        let hi = self.expr()?;
        self.expect_tok(Tok::RParen, "`)`")?;
        Some(TypeSpec::Subrange {
            base,
            lo: Box::new(lo),
            hi: Box::new(hi),
            span: self.span_from(base.span.start),
        })
    }

    pub(super) fn array_type(&mut self) -> Option<TypeSpec> {
        let t = self.bump();
        let dims = self.array_dims()?;
        let elem = self.type_spec();
        Some(TypeSpec::Array {
            dims,
            elem: Box::new(elem?),
            span: self.span_from(t.start),
        })
    }

    /// `[lo..hi, *] OF`
    #[allow(clippy::type_complexity)]
    pub(super) fn array_dims(&mut self) -> Option<Vec<Option<(Expr, Expr)>>> {
        self.expect_tok(Tok::LBracket, "`[`")?;
        let mut dims = Vec::with_capacity(1);
        loop {
            if self.eat(Tok::Star) {
                dims.push(None);
            } else {
                let lo = self.expr()?;
                self.expect_tok(Tok::DotDot, "`..`")?;
                let hi = self.expr()?;
                dims.push(Some((lo, hi)));
            }
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        self.expect_tok(Tok::RBracket, "`]` or `,`")?;
        self.expect_tok(Tok::Of, "`OF`")?;
        dims.shrink_to_fit();
        Some(dims)
    }

    pub(super) fn struct_type(&mut self) -> Option<TypeSpec> {
        let kw = self.bump();
        let mut fields = Vec::new();
        loop {
            let t = self.tok();
            match t.kind {
                Tok::EndStruct => {
                    self.bump();
                    break;
                }
                Tok::Ident | Tok::At => {
                    if let Some(d) = self.var_decl(DeclCtx::Struct) {
                        fields.push(d);
                    }
                }
                Tok::Semi => {
                    self.bump();
                }
                k if is_section_stop(k) || is_stmt_keyword(k) => {
                    let msg = format!("expected `END_STRUCT`, found {}", self.describe(self.pos));
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label("expected `END_STRUCT` before this")
                        .with_secondary(self.tspan(kw), "this STRUCT is not closed");
                    self.emit(self.pos, d);
                    return None;
                }
                _ => {
                    self.expected("a field name or `END_STRUCT`");
                    self.bump();
                    self.skip_decl();
                }
            }
        }
        Some(TypeSpec::Struct {
            fields,
            span: self.span_from(kw.start),
        })
    }

    /// `(a, b := 5, c)`, with the base type before (`INT (a, b)`) or after (`(a, b) INT`).
    pub(super) fn enum_type(&mut self, base_before: Option<Ident>, start: u32) -> Option<TypeSpec> {
        self.expect_tok(Tok::LParen, "`(`")?;
        let mut values = Vec::new();
        loop {
            let name = self.expect_ident("an enumeration value")?;
            let value = if self.eat(Tok::Assign) {
                Some(self.expr()?)
            } else {
                None
            };
            values.push((name, value));
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        self.expect_tok(Tok::RParen, "`,` or `)`")?;
        let mut base = base_before;
        if base.is_none() && self.at(Tok::Ident) && !self.tok().newline_before() {
            let t = self.bump();
            base = Some(self.ident(t));
        }
        Some(TypeSpec::Enum {
            values,
            base,
            span: self.span_from(start),
        })
    }

    // ---------------------------------------------------------------- initialisers

    pub(super) fn decl_init(&mut self, ty: &TypeSpec) -> Option<Init> {
        if matches!(ty, TypeSpec::Array { .. }) && !self.at(Tok::LBracket) {
            self.loose_array_init()
        } else {
            self.init()
        }
    }

    pub(super) fn init(&mut self) -> Option<Init> {
        if !self.enter() {
            return None;
        }
        let r = self.init_inner();
        self.leave();
        r
    }

    pub(super) fn init_inner(&mut self) -> Option<Init> {
        match self.peek() {
            Tok::LBracket => {
                let open = self.bump();
                let elems = if self.at(Tok::RBracket) {
                    Vec::new()
                } else {
                    self.array_elems()?
                };
                self.expect_tok(Tok::RBracket, "`,` or `]`")?;
                Some(Init::Array {
                    elems,
                    span: self.span_from(open.start),
                })
            }
            Tok::LParen if self.peek_at(1) == Tok::Ident && self.peek_at(2) == Tok::Assign => {
                let open = self.bump();
                let mut fields = Vec::new();
                loop {
                    let name = self.expect_ident("a field name")?;
                    self.expect_tok(Tok::Assign, "`:=`")?;
                    let value = self.init()?;
                    fields.push((name, value));
                    if !self.eat(Tok::Comma) {
                        break;
                    }
                }
                self.expect_tok(Tok::RParen, "`,` or `)`")?;
                Some(Init::Struct {
                    fields,
                    span: self.span_from(open.start),
                })
            }
            _ => Some(Init::Expr(self.expr()?)),
        }
    }

    pub(super) fn array_elems(&mut self) -> Option<Vec<ArrayInitElem>> {
        let mut elems = Vec::new();
        loop {
            elems.push(self.array_elem()?);
            if !self.eat(Tok::Comma) {
                return Some(elems);
            }
        }
    }

    /// `v`, `n(v)` or `n()`; `n` is an integer literal (so `3(0)` is no call).
    pub(super) fn array_elem(&mut self) -> Option<ArrayInitElem> {
        let t = self.tok();
        if self.is_plain_int(t) && self.peek_at(1) == Tok::LParen {
            let count = self.literal_expr(t);
            self.bump();
            self.bump();
            let value = if self.at(Tok::RParen) {
                None
            } else {
                Some(self.init()?)
            };
            self.expect_tok(Tok::RParen, "`)`")?;
            return Some(ArrayInitElem {
                repeat: Some(count),
                value,
                span: self.span_from(t.start),
            });
        }
        let v = self.init()?;
        Some(ArrayInitElem {
            repeat: None,
            span: v.span(),
            value: Some(v),
        })
    }

    /// An array initialiser written without brackets (`:= 1, 2, 3(0)`).
    pub(super) fn loose_array_init(&mut self) -> Option<Init> {
        let start = self.tok().start;
        let first = self.array_elem()?;
        if !self.at(Tok::Comma) && first.repeat.is_none() {
            return first.value;
        }
        let mut elems = vec![first];
        while self.eat(Tok::Comma) {
            elems.push(self.array_elem()?);
        }
        Some(Init::Array {
            elems,
            span: self.span_from(start),
        })
    }

    // ---------------------------------------------------------------- configurations

    pub(super) fn configuration(&mut self) -> Option<Configuration> {
        let kw = self.bump();
        let name = self.expect_ident("a configuration name");
        self.eat(Tok::Semi);
        let items = self.config_items(kw, true);
        let span = self.span_from(kw.start);
        self.eat(Tok::Semi);
        let name = name?;
        let ConfigItems {
            var_blocks,
            mut resources,
            tasks,
            programs,
        } = items;
        if !tasks.is_empty() || !programs.is_empty() {
            let implicit_span = tasks
                .iter()
                .map(|t| t.span)
                .chain(programs.iter().map(|p| p.span))
                .reduce(|a, b| a.to(b))
                .unwrap_or(span);
            resources.push(Resource {
                name,
                on: None,
                var_blocks: Vec::new(),
                tasks,
                programs,
                span: implicit_span,
            });
        }
        Some(Configuration {
            name,
            var_blocks,
            resources,
            span,
        })
    }

    pub(super) fn resource(&mut self) -> Option<Resource> {
        let kw = self.bump();
        let name = self.expect_ident("a resource name");
        let mut on = None;
        if name.is_some() && self.at_sym(0, self.s.on) {
            self.bump();
            on = self.expect_ident("a processor type after `ON`");
        }
        self.eat(Tok::Semi);
        let items = self.config_items(kw, false);
        let span = self.span_from(kw.start);
        self.eat(Tok::Semi);
        Some(Resource {
            name: name?,
            on,
            var_blocks: items.var_blocks,
            tasks: items.tasks,
            programs: items.programs,
            span,
        })
    }

    /// The declarations of a CONFIGURATION (`in_config`: it may hold RESOURCEs) or of a
    /// RESOURCE (`kw`: its keyword), up to and including the END keyword.
    pub(super) fn config_items(&mut self, kw: Token, in_config: bool) -> ConfigItems {
        let (end, what, allowed) = if in_config {
            (
                Tok::EndConfiguration,
                "CONFIGURATION",
                "`VAR_GLOBAL`, `RESOURCE`, `TASK`, `PROGRAM` or `END_CONFIGURATION`",
            )
        } else {
            (
                Tok::EndResource,
                "RESOURCE",
                "`VAR_GLOBAL`, `TASK`, `PROGRAM` or `END_RESOURCE`",
            )
        };
        let mut items = ConfigItems::default();
        loop {
            let t = self.tok();
            match t.kind {
                k if k == end => {
                    self.bump();
                    break;
                }
                Tok::VarGlobal | Tok::VarAccess | Tok::VarConfig => {
                    if let Some(b) = self.var_block(DeclCtx::Global) {
                        items.var_blocks.push(b);
                    }
                }
                Tok::Program if self.at_program_config() => {
                    if let Some(p) = self.program_config() {
                        items.programs.push(p);
                    }
                }
                Tok::Semi => {
                    self.bump();
                }
                Tok::Ident
                    if in_config
                        && self.at_sym(0, self.s.resource)
                        && self.peek_at(1) == Tok::Ident =>
                {
                    if let Some(r) = self.resource() {
                        items.resources.push(r);
                    }
                }
                Tok::Ident if self.at_sym(0, self.s.task) && self.peek_at(1) == Tok::Ident => {
                    if let Some(task) = self.task() {
                        items.tasks.push(task);
                    }
                }
                // (a PROGRAM that is not `PROGRAM inst WITH t : T` starts a POU)
                k if k == Tok::Eof
                    || (in_config && (is_top_start(k) || is_pou_end(k)))
                    || (!in_config && is_section_stop(k)) =>
                {
                    let msg = format!("expected `END_{what}`, found {}", self.describe(self.pos));
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label(format!("expected `END_{what}`"))
                        .with_secondary(self.tspan(kw), format!("this {what} is not closed"));
                    self.emit(self.pos, d);
                    break;
                }
                _ => {
                    self.expected(allowed);
                    self.bump();
                    self.skip_decl();
                }
            }
        }
        items
    }

    pub(super) fn task(&mut self) -> Option<TaskDecl> {
        let r = self.task_inner();
        if r.is_none() {
            self.skip_decl();
        }
        r
    }

    pub(super) fn task_inner(&mut self) -> Option<TaskDecl> {
        let kw = self.bump();
        let name = self.expect_ident("a task name")?;
        let mut props = Vec::new();
        if self.eat(Tok::LParen) && !self.eat(Tok::RParen) {
            loop {
                let p = self.expect_ident("a task property such as `INTERVAL`")?;
                self.expect_tok(Tok::Assign, "`:=`")?;
                let v = self.expr()?;
                props.push((p, v));
                if !self.eat(Tok::Comma) {
                    break;
                }
            }
            self.expect_tok(Tok::RParen, "`,` or `)`")?;
        }
        let span = self.span_from(kw.start);
        self.expect_decl_semi();
        Some(TaskDecl { name, props, span })
    }

    /// `PROGRAM [RETAIN] inst WITH` or `PROGRAM inst :` (else a PROGRAM declaration
    /// follows a configuration that was not closed).
    pub(super) fn at_program_config(&self) -> bool {
        let n = if matches!(self.peek_at(1), Tok::Retain | Tok::NonRetain) {
            2
        } else {
            1
        };
        self.peek_at(n) == Tok::Ident
            && (self.peek_at(n + 1) == Tok::Colon || self.at_sym(n + 1, self.s.with))
    }

    pub(super) fn program_config(&mut self) -> Option<ProgramConfig> {
        let r = self.program_config_inner();
        if r.is_none() {
            self.skip_decl();
        }
        r
    }

    pub(super) fn program_config_inner(&mut self) -> Option<ProgramConfig> {
        let kw = self.bump();
        if matches!(self.peek(), Tok::Retain | Tok::NonRetain) {
            self.bump();
        }
        let name = self.expect_ident("a program instance name")?;
        let mut task = None;
        if self.at_sym(0, self.s.with) {
            self.bump();
            task = Some(self.expect_ident("a task name after `WITH`")?);
        }
        self.expect_tok(Tok::Colon, "`:`")?;
        let pou = self.expect_ident("a PROGRAM type name")?;
        let mut args = Vec::new();
        if self.at(Tok::LParen) {
            let open = self.bump();
            if !self.enter() {
                return None;
            }
            let a = self.call_args(open);
            self.leave();
            args = a?.0;
        }
        let span = self.span_from(kw.start);
        self.expect_decl_semi();
        Some(ProgramConfig {
            name,
            task,
            pou,
            args,
            span,
        })
    }
}
