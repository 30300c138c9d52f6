//! Structured Text: lexer and parser.
