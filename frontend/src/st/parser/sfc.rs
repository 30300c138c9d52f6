//! Textual sequential function charts (IEC 61131-3, 6.7.2): `INITIAL_STEP`, `STEP`
//! and `TRANSITION` written in place of a PROGRAM's or FUNCTION_BLOCK's statements.
//! The chart's `ACTION`s are parsed as any POU action. [`crate::sfc`] turns the chart
//! into statements.

use super::*;

impl<'a> Parser<'a> {
    /// `INITIAL_STEP name: assoc; … END_STEP` or `STEP name: …` (at the keyword).
    pub(super) fn sfc_step(&mut self) -> Option<SfcStep> {
        let kw = self.bump();
        let initial = Symbol(kw.data) == self.s.initial_step;
        let name = self.expect_ident("a step name");
        if name.is_none() {
            self.skip_member_body(Tok::EndStep);
            return None;
        }
        self.expect_tok(Tok::Colon, "`:` after the step name");
        let mut assocs = Vec::new();
        while self.at(Tok::Ident) && self.member_at().is_none() {
            match self.sfc_assoc() {
                Some(a) => assocs.push(a),
                None => {
                    self.skip_member_body(Tok::EndStep);
                    return None;
                }
            }
        }
        if !self.at(Tok::EndStep) {
            self.expected("an action association or `END_STEP`");
            self.skip_member_body(Tok::EndStep);
            return None;
        }
        self.bump();
        let span = self.span_from(kw.start);
        self.eat(Tok::Semi);
        Some(SfcStep {
            name: name?,
            initial,
            assocs,
            span,
        })
    }

    /// `action(qualifier[, duration][, indicator…]);`
    fn sfc_assoc(&mut self) -> Option<SfcAssoc> {
        let first = self.bump();
        let action = self.ident(first);
        // `inst.A` (CODESYS step actions of FB instances).
        let mut qualified = None;
        while self.at(Tok::Dot) && self.peek_at(1) == Tok::Ident {
            self.bump();
            self.bump();
            qualified = Some(self.span_from(first.start));
        }
        let open = self.expect_tok(Tok::LParen, "`(` after the action name")?;
        let mut qualifier = None;
        let mut duration = None;
        let mut indicators = Vec::new();
        if self.at(Tok::Ident) || self.at(Tok::Exit) {
            let q = self.bump();
            let timed = matches!(
                self.slice(q).to_ascii_uppercase().as_str(),
                "L" | "D" | "SD" | "DS" | "SL"
            );
            qualifier = Some(if q.kind == Tok::Exit {
                // CODESYS's exit step action: `A(EXIT);` (EXIT is a keyword).
                Ident {
                    sym: self.interner().intern_upper("EXIT"),
                    span: self.tspan(q),
                }
            } else {
                self.ident(q)
            });
            // A timed qualifier's first item is its duration (a TIME expression);
            // the other items are indicator variables.
            let mut k = 0;
            while self.eat(Tok::Comma) {
                let start = self.tok().start;
                if (timed && k == 0) || !self.at(Tok::Ident) {
                    self.expr()?;
                    if duration.is_some() {
                        self.expected("an indicator variable");
                        return None;
                    }
                    duration = Some(self.span_from(start));
                } else {
                    let t = self.bump();
                    indicators.push(self.ident(t));
                }
                k += 1;
            }
        }
        self.expect_close(Tok::RParen, "`)`", open)?;
        let span = self.span_from(first.start);
        self.expect_tok(Tok::Semi, "`;` after the association")?;
        Some(SfcAssoc {
            action,
            qualified,
            qualifier,
            duration,
            indicators,
            span,
        })
    }

    /// `TRANSITION [name] [(PRIORITY := p)] FROM s | (s, …) TO s | (s, …) := cond;
    /// END_TRANSITION` (at the keyword).
    pub(super) fn sfc_transition(&mut self) -> Option<SfcTransition> {
        let kw = self.bump();
        let name = if self.at(Tok::Ident) && !self.at_word("FROM") {
            let t = self.bump();
            Some(self.ident(t))
        } else {
            None
        };
        let head = self.span_from(kw.start);
        let mut priority = None;
        if let Some(open) = self.at(Tok::LParen).then(|| self.bump()) {
            let start = self.tok().start;
            if !self.at_word("PRIORITY") {
                self.expected("`PRIORITY`");
                self.skip_member_body(Tok::EndTransition);
                return None;
            }
            self.bump();
            self.expect_tok(Tok::Assign, "`:=`")?;
            let e = self.expr()?;
            let span = self.span_from(start);
            match e.literal_kind() {
                Some(&LiteralKind::Int(n)) if (0..=u32::MAX as i128).contains(&n) => {
                    priority = Some((n as u32, span))
                }
                _ => {
                    let d = Diagnostic::error(
                        codes::UNEXPECTED_TOKEN,
                        "a transition's PRIORITY is a non-negative integer literal",
                        e.span,
                    );
                    self.emit(self.pos, d);
                }
            }
            self.expect_close(Tok::RParen, "`)`", open)?;
        }
        if !self.at_word("FROM") {
            self.expected("`FROM` and the steps before the transition");
            self.skip_member_body(Tok::EndTransition);
            return None;
        }
        self.bump();
        let from = self.sfc_steps()?;
        if !self.eat(Tok::To) {
            self.expected("`TO` and the steps after the transition");
            self.skip_member_body(Tok::EndTransition);
            return None;
        }
        let to = self.sfc_steps()?;
        let mut il = false;
        let condition = if self.eat(Tok::Assign) {
            let start = self.tok().start;
            self.expr()?;
            let span = self.span_from(start);
            self.expect_tok(Tok::Semi, "`;` after the condition")?;
            Some(span)
        } else if self.at(Tok::Colon) {
            // An IL list whose result is the condition: kept as text, up to
            // END_TRANSITION (`crate::sfc` makes it an action of its own).
            self.bump();
            let start = self.tok().start;
            while !self.at(Tok::EndTransition)
                && !self.at(Tok::Eof)
                && !is_pou_end(self.peek())
                && self.member_at().is_none()
            {
                self.bump();
            }
            if !self.at(Tok::EndTransition) {
                self.expected("`END_TRANSITION` after the IL condition");
                return None;
            }
            il = true;
            Some(self.sp(start, self.prev_end().max(start)))
        } else {
            self.expected("`:=` and the transition's condition");
            self.skip_member_body(Tok::EndTransition);
            return None;
        };
        if !self.at(Tok::EndTransition) {
            self.expected("`END_TRANSITION`");
            self.skip_member_body(Tok::EndTransition);
            return None;
        }
        self.bump();
        let span = self.span_from(kw.start);
        self.eat(Tok::Semi);
        Some(SfcTransition {
            name,
            priority,
            from,
            to,
            condition,
            il,
            head,
            span,
        })
    }

    /// `s` or `(s1, s2, …)`.
    fn sfc_steps(&mut self) -> Option<Vec<Ident>> {
        if let Some(open) = self.at(Tok::LParen).then(|| self.bump()) {
            let mut out = vec![self.expect_ident("a step name")?];
            while self.eat(Tok::Comma) {
                out.push(self.expect_ident("a step name")?);
            }
            self.expect_close(Tok::RParen, "`)`", open)?;
            Some(out)
        } else {
            Some(vec![self.expect_ident("a step name")?])
        }
    }

    /// The current token is the identifier `word` (upper case).
    fn at_word(&self, word: &str) -> bool {
        self.at(Tok::Ident) && self.slice(self.tok()).eq_ignore_ascii_case(word)
    }
}
