//! Members of POUs in Structured Text: finding METHOD, PROPERTY, ACTION and STEP
//! headers inside a POU, the object-oriented members (METHOD, PROPERTY, INTERFACE,
//! their modifiers) and the members plcc reports as unsupported (the parser's
//! methods for them).

use super::*;

impl<'a> Parser<'a> {
    /// A member keyword at the current token (`METHOD m`, `ACTION a:`, `STEP s:`).
    pub(super) fn member_at(&self) -> Option<Member> {
        let t = self.tok();
        if t.kind != Tok::Ident {
            return None;
        }
        let s = Symbol(t.data);
        // `TRANSITION (PRIORITY := 4) FROM a TO b`: the only member whose name may be
        // left out, with properties in parentheses.
        let next = self.peek_at(1);
        if next != Tok::Ident && !(s == self.s.transition && next == Tok::LParen) {
            return None;
        }
        let m = &self.s;
        Some(if s == m.action {
            Member::Action
        } else if s == m.method {
            Member::Method
        } else if s == m.property {
            Member::Property
        } else if s == m.interface {
            Member::Interface
        } else if s == m.class {
            Member::Class
        } else if s == m.initial_step || (s == m.step && self.peek_at(2) == Tok::Colon) {
            Member::Step
        } else if s == m.transition {
            Member::Transition
        } else {
            return None;
        })
    }

    pub(super) fn member_end(m: Member) -> Tok {
        match m {
            Member::Action => Tok::EndAction,
            Member::Method => Tok::EndMethod,
            Member::Property => Tok::EndProperty,
            Member::Interface => Tok::EndInterface,
            Member::Class => Tok::EndClass,
            Member::Step => Tok::EndStep,
            Member::Transition => Tok::EndTransition,
        }
    }

    /// Skips a member to its END_ keyword; returns the span of its header.
    pub(super) fn skip_member(&mut self, m: Member) -> Span {
        let header = self.member_header();
        self.skip_member_rest(m, header);
        header
    }

    /// The keyword, modifiers and name of a member.
    pub(super) fn member_header(&mut self) -> Span {
        let kw = self.bump();
        let mut header_end = kw.end;
        while self.at(Tok::Ident) && !self.tok().newline_before() {
            header_end = self.bump().end;
            if self.at(Tok::Ident)
                && self
                    .s
                    .modifiers
                    .contains(&Symbol(self.toks[self.pos - 1].data))
            {
                continue;
            }
            break;
        }
        self.sp(kw.start, header_end)
    }

    pub(super) fn skip_member_rest(&mut self, m: Member, header: Span) {
        let end = Self::member_end(m);
        loop {
            let t = self.peek();
            if t == end {
                self.bump();
                self.eat(Tok::Semi);
                break;
            }
            if t == Tok::Eof || is_pou_end(t) || is_top_start(t) {
                let msg = format!(
                    "expected `{}`, found {}",
                    end.text(),
                    self.describe(self.pos)
                );
                let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(self.tok()))
                    .with_label(format!("expected `{}`", end.text()))
                    .with_secondary(header, "this member is not closed");
                self.emit(self.pos, d);
                break;
            }
            self.bump();
        }
    }

    /// INTERFACE, CLASS, METHOD... at top level: reported once and skipped.
    pub(super) fn unsupported_member(&mut self, m: Member) {
        let t = self.tok();
        let word = self.slice(t).to_ascii_uppercase();
        let msg = format!("`{word}` declarations are not supported");
        let idx = self.pos;
        let header = self.member_header();
        let d = Diagnostic::error(codes::SYNTAX_NOT_SUPPORTED, msg, header)
            .with_label("not supported; skipped up to its END_ keyword");
        self.emit(idx, d);
        self.skip_member_rest(m, header);
    }

    /// `a, b, c`: names separated by commas (at least one).
    pub(super) fn ident_list(&mut self, what: &str) -> Vec<Ident> {
        let mut names = Vec::new();
        while let Some(n) = self.expect_ident(what) {
            names.push(n);
            if !self.eat(Tok::Comma) {
                break;
            }
        }
        names
    }

    /// ABSTRACT, FINAL, OVERRIDE and the access specifiers before a name.
    pub(super) fn modifiers(&mut self) -> Modifiers {
        let mut m = Modifiers::default();
        while self.at(Tok::Ident)
            && self.peek_at(1) == Tok::Ident
            && self.s.modifiers.contains(&Symbol(self.tok().data))
        {
            let t = self.bump();
            let span = self.tspan(t);
            let i = self
                .s
                .modifiers
                .iter()
                .position(|&x| x == Symbol(t.data))
                .expect("a modifier");
            match i {
                0 => m.abstract_ = Some(span),
                1 => m.final_ = Some(span),
                6 => m.override_ = Some(span),
                _ => {
                    let a = [
                        AccessSpec::Public,
                        AccessSpec::Private,
                        AccessSpec::Protected,
                        AccessSpec::Internal,
                    ][i - 2];
                    m.access = Some((a, span));
                }
            }
        }
        m
    }

    /// `METHOD [modifiers] name [: type] ... END_METHOD`.
    pub(super) fn method(&mut self) -> Option<Method> {
        let kw = self.bump();
        let modifiers = self.modifiers();
        let name = self.expect_ident("a method name");
        let mut return_type = None;
        if name.is_some() && self.eat(Tok::Colon) {
            return_type = self.type_spec();
            if return_type.is_none() {
                self.skip_header_rest();
            }
        }
        self.eat(Tok::Semi);
        let pou = self.pou_rest(
            PouKind::Function,
            kw,
            Tok::EndMethod,
            name,
            return_type,
            None,
            OoParts::default(),
        )?;
        Some(Method { modifiers, pou })
    }

    /// `PROPERTY [modifiers] name : type GET ... END_GET SET ... END_SET
    /// END_PROPERTY`. The getter is a FUNCTION named as the property returning its
    /// type; the setter one with an input of that name and type.
    pub(super) fn property(&mut self) -> Option<Property> {
        let kw = self.bump();
        let modifiers = self.modifiers();
        let Some(name) = self.expect_ident("a property name") else {
            self.skip_member_body(Tok::EndProperty);
            return None;
        };
        let ty = if self.eat(Tok::Colon) {
            self.type_spec()
        } else {
            self.expected("`:` and the property's type");
            None
        };
        let Some(ty) = ty else {
            self.skip_member_body(Tok::EndProperty);
            return None;
        };
        self.eat(Tok::Semi);
        let mut get = None;
        let mut set = None;
        loop {
            if self.at_sym(0, self.s.get) {
                let k = self.bump();
                self.eat(Tok::Semi);
                get = self.pou_rest(
                    PouKind::Function,
                    k,
                    Tok::EndGet,
                    Some(name),
                    Some(ty.clone()),
                    None,
                    OoParts::default(),
                );
            } else if self.at_sym(0, self.s.set) {
                let k = self.bump();
                self.eat(Tok::Semi);
                let value = VarBlock {
                    kind: VarKind::Input,
                    constant: false,
                    retain: false,
                    list: None,
                    decls: vec![VarDecl {
                        names: vec![name],
                        location: None,
                        ty: ty.clone(),
                        init: None,
                        edge: None,
                        span: name.span,
                    }],
                    span: name.span,
                };
                set = self
                    .pou_rest(
                        PouKind::Function,
                        k,
                        Tok::EndSet,
                        Some(name),
                        None,
                        None,
                        OoParts::default(),
                    )
                    .map(|mut p| {
                        p.var_blocks.insert(0, value);
                        p
                    });
            } else if self.eat(Tok::EndProperty) {
                self.eat(Tok::Semi);
                break;
            } else {
                self.expected("`GET`, `SET` or `END_PROPERTY`");
                self.skip_member_body(Tok::EndProperty);
                break;
            }
        }
        Some(Property {
            modifiers,
            name,
            ty,
            get,
            set,
            span: self.span_from(kw.start),
        })
    }

    /// `INTERFACE name [EXTENDS a, b] ... END_INTERFACE`.
    pub(super) fn interface(&mut self) -> Option<Interface> {
        let kw = self.bump();
        let name = self.expect_ident("an interface name");
        let mut extends = Vec::new();
        if name.is_some() && self.at_sym(0, self.s.extends) {
            self.bump();
            extends = self.ident_list("the name of an INTERFACE");
        }
        self.eat(Tok::Semi);
        let mut methods = Vec::new();
        let mut properties = Vec::new();
        loop {
            let t = self.tok();
            match self.member_at() {
                Some(Member::Method) => methods.extend(self.method()),
                Some(Member::Property) => properties.extend(self.property()),
                _ if t.kind == Tok::EndInterface => {
                    self.bump();
                    self.eat(Tok::Semi);
                    break;
                }
                _ if t.kind == Tok::Semi => {
                    self.bump();
                }
                _ if t.kind == Tok::Eof || is_top_start(t.kind) || is_pou_end(t.kind) => {
                    let msg = format!(
                        "expected `END_INTERFACE`, found {}",
                        self.describe(self.pos)
                    );
                    let d = Diagnostic::error(codes::UNCLOSED_BLOCK, msg, self.tspan(t))
                        .with_label("expected `END_INTERFACE`")
                        .with_secondary(self.tspan(kw), "this INTERFACE is not closed");
                    self.emit(self.pos, d);
                    break;
                }
                _ => {
                    self.expected("`METHOD`, `PROPERTY` or `END_INTERFACE`");
                    self.bump();
                }
            }
        }
        Some(Interface {
            name: name?,
            extends,
            methods,
            properties,
            span: self.span_from(kw.start),
        })
    }
}
