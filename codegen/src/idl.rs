//! `.idl` files as rosidl generates them (rosidl_adapter `resource/*.idl.em`), parsed into the
//! [`definition`](crate::definition) model as rosidl_parser (jazzy) does: the subset of IDL 4.2
//! of rosidl_parser `grammar.lark`, read as rosidl_parser `parser.py` `extract_content_from_ast`
//! reads it.
//!
//! - One struct is a message, two (`Name_Request`, `Name_Response`) a service, three
//!   (`Name_Goal`, `Name_Result`, `Name_Feedback`) an action; each inside
//!   `module <package> { module <msg|srv|action> { ... }; };`.
//! - `typedef`s (also of arrays and of scoped names) are resolved wherever they are declared.
//! - The constants of struct `Name` are the `const`s of any `module Name_Constants`.
//! - `@verbatim (language="comment", text=...)` gives comment lines, `@default (value=...)` a
//!   default (for an array or sequence, a string holding a Python tuple, as rosidl_adapter
//!   `to_idl_literal` writes it), `@unit (value=...)` a unit; other annotations are ignored.
//! - A struct whose only member is rosidl_adapter's `uint8 structure_needs_at_least_one_member`
//!   has no fields.
//!
//! Where this differs from rosidl_parser: a service's and an action's structs keep their
//! `@verbatim` comments (`extract_content_from_ast` keeps struct annotations only for a message);
//! octal and hexadecimal literals, which the grammar accepts and `get_const_expr_value` refuses,
//! are integers.
//!
//! Beyond rosidl_parser, which accepts them and fails later (or never): integer values out of
//! their type's range, array defaults of the wrong length and defaults of the wrong kind are
//! errors here; constant expressions are a literal or a name with at most one sign, as
//! rosidl_parser `get_const_expr_value` supports.

use std::collections::HashMap;
use std::path::Path;

use crate::definition::{
    Action, BaseType, Constant, Container, Field, FieldType, Interface, Literal, Message,
    NamedType, Primitive, Service, Value,
};
use crate::error::ParseError;

/// The member rosidl_adapter `struct.idl.em` gives a message without fields.
const PLACEHOLDER_MEMBER: &str = "structure_needs_at_least_one_member";

/// The suffix of the module holding a struct's constants (rosidl_parser
/// `CONSTANT_MODULE_SUFFIX`).
const CONSTANTS_SUFFIX: &str = "_Constants";

/// Deepest nesting of modules accepted (a bound on recursion, far above any real file).
const MAX_MODULE_DEPTH: usize = 32;

/// Longest chain of typedefs resolved (a bound on cycles).
const MAX_TYPEDEF_DEPTH: usize = 32;

/// Parses the `.idl` file `file` (named in errors) whose text is `text`.
pub fn parse_idl(file: &Path, text: &str) -> Result<Interface, ParseError> {
    let tokens = Lexer::new(file, text).tokens()?;
    let mut parser = Parser {
        file,
        tokens,
        next: 0,
        modules: Vec::new(),
        spec: Spec::default(),
    };
    parser.specification()?;
    Builder {
        file,
        spec: parser.spec,
    }
    .interface()
}

// ---------------------------------------------------------------------------------------------
// Tokens (grammar.lark's terminals)

/// A 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pos {
    line: usize,
    column: usize,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Int(i128),
    Float(f64),
    /// A string literal, escapes decoded; `wide` for `L"..."`.
    Str {
        text: String,
        wide: bool,
    },
    /// `#include "..."` or `#include <...>`.
    Include,
    /// Punctuation (`::` is one).
    Punct(&'static str),
    Eof,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    pos: Pos,
}

fn describe(tok: &Tok) -> String {
    match tok {
        Tok::Ident(s) => format!("`{s}`"),
        Tok::Int(i) => format!("integer `{i}`"),
        Tok::Float(f) => format!("number `{f}`"),
        Tok::Str { .. } => "a string literal".to_owned(),
        Tok::Include => "`#include`".to_owned(),
        Tok::Punct(p) => format!("`{p}`"),
        Tok::Eof => "end of file".to_owned(),
    }
}

const PUNCTS: &[&str] = &[
    "{", "}", ";", "<", ">", "(", ")", "[", "]", ",", "=", "@", "-", "+", "~", "|", "^", "&", "*",
    "/", "%",
];

struct Lexer<'a> {
    file: &'a Path,
    chars: Vec<char>,
    at: usize,
    pos: Pos,
}

impl<'a> Lexer<'a> {
    fn new(file: &'a Path, text: &str) -> Self {
        Self {
            file,
            chars: text.chars().collect(),
            at: 0,
            pos: Pos { line: 1, column: 1 },
        }
    }

    fn error(&self, pos: Pos, message: impl Into<String>) -> ParseError {
        ParseError::new(self.file, pos.line, pos.column, message)
    }

    fn peek(&self, ahead: usize) -> Option<char> {
        self.chars.get(self.at + ahead).copied()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek(0)?;
        self.at += 1;
        if c == '\n' {
            self.pos.line += 1;
            self.pos.column = 1;
        } else {
            self.pos.column += 1;
        }
        Some(c)
    }

    fn tokens(mut self) -> Result<Vec<Token>, ParseError> {
        let mut tokens = Vec::new();
        loop {
            self.skip_blanks()?;
            let pos = self.pos;
            let Some(c) = self.peek(0) else {
                tokens.push(Token { tok: Tok::Eof, pos });
                return Ok(tokens);
            };
            let tok = if c.is_ascii_alphabetic() {
                self.word(pos)?
            } else if c.is_ascii_digit()
                || (c == '.' && self.peek(1).is_some_and(|d| d.is_ascii_digit()))
            {
                self.number(pos)?
            } else if c == '"' {
                self.string(pos, false)?
            } else if c == '#' {
                self.include(pos)?
            } else if c == '\'' {
                return Err(self.error(pos, "character literals are not supported"));
            } else if c == ':' {
                self.bump();
                if self.peek(0) == Some(':') {
                    self.bump();
                    Tok::Punct("::")
                } else {
                    Tok::Punct(":")
                }
            } else if let Some(p) = PUNCTS.iter().find(|p| p.starts_with(c)) {
                self.bump();
                Tok::Punct(p)
            } else {
                return Err(self.error(pos, format!("unexpected character `{c}`")));
            };
            tokens.push(Token { tok, pos });
        }
    }

    /// Skips white space (`WS`) and comments (`COMMENT`).
    fn skip_blanks(&mut self) -> Result<(), ParseError> {
        loop {
            match (self.peek(0), self.peek(1)) {
                (Some(' ' | '\t' | '\n' | '\r' | '\x0c'), _) => {
                    self.bump();
                }
                (Some('/'), Some('/')) => {
                    while self.peek(0).is_some_and(|c| c != '\n') {
                        self.bump();
                    }
                }
                (Some('/'), Some('*')) => {
                    let start = self.pos;
                    self.bump();
                    self.bump();
                    loop {
                        match self.bump() {
                            None => return Err(self.error(start, "unterminated comment")),
                            Some('*') if self.peek(0) == Some('/') => {
                                self.bump();
                                break;
                            }
                            Some(_) => {}
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    /// An `IDENTIFIER` (a letter, then letters, digits and `_`), or `L"...`.
    fn word(&mut self, pos: Pos) -> Result<Tok, ParseError> {
        if self.peek(0) == Some('L') && self.peek(1) == Some('"') {
            self.bump();
            return self.string(pos, true);
        }
        let mut word = String::new();
        while let Some(c) = self
            .peek(0)
            .filter(|c| c.is_ascii_alphanumeric() || *c == '_')
        {
            word.push(c);
            self.bump();
        }
        Ok(Tok::Ident(word))
    }

    /// `decimal_literal`, `octal_literal`, `hexadecimal_literal`, `floating_pt_literal` (`FLOAT`)
    /// or `fixed_pt_literal` (`1.5d`, read as a float as rosidl_parser does).
    fn number(&mut self, pos: Pos) -> Result<Tok, ParseError> {
        let mut text = String::new();
        let digits = |lexer: &mut Self, text: &mut String, hex: bool| {
            while let Some(c) = lexer
                .peek(0)
                .filter(|c| c.is_ascii_digit() || (hex && c.is_ascii_hexdigit()))
            {
                text.push(c);
                lexer.bump();
            }
        };
        let tok = if self.peek(0) == Some('0') && matches!(self.peek(1), Some('x' | 'X')) {
            self.bump();
            self.bump();
            digits(self, &mut text, true);
            i128::from_str_radix(&text, 16).ok().map(Tok::Int)
        } else {
            digits(self, &mut text, false);
            let mut float = false;
            if self.peek(0) == Some('.') {
                float = true;
                text.push('.');
                self.bump();
                digits(self, &mut text, false);
            }
            let sign = usize::from(matches!(self.peek(1), Some('+' | '-')));
            if matches!(self.peek(0), Some('e' | 'E'))
                && self.peek(1 + sign).is_some_and(|c| c.is_ascii_digit())
            {
                float = true;
                for _ in 0..=sign {
                    text.extend(self.bump());
                }
                digits(self, &mut text, false);
            }
            if matches!(self.peek(0), Some('d' | 'D')) {
                float = true;
                self.bump();
            }
            if float {
                text.parse().ok().map(Tok::Float)
            } else if text.len() > 1 && text.starts_with('0') {
                i128::from_str_radix(&text, 8).ok().map(Tok::Int)
            } else {
                text.parse().ok().map(Tok::Int)
            }
        };
        match tok {
            Some(tok)
                if !self
                    .peek(0)
                    .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') =>
            {
                Ok(tok)
            }
            _ => Err(self.error(pos, "malformed or out-of-range number")),
        }
    }

    /// `ESCAPED_STRING` / `ESCAPED_WIDE_STRING` (at the `"`): up to the first `"` not escaped,
    /// on one line.
    fn string(&mut self, pos: Pos, wide: bool) -> Result<Tok, ParseError> {
        self.bump();
        let mut raw = String::new();
        loop {
            match self.peek(0) {
                None | Some('\n') => return Err(self.error(pos, "unterminated string literal")),
                Some('"') => {
                    self.bump();
                    break;
                }
                Some('\\') if self.peek(1).is_some_and(|c| c != '\n') => {
                    raw.extend(self.bump());
                    raw.extend(self.bump());
                }
                Some(c) => {
                    raw.push(c);
                    self.bump();
                }
            }
        }
        let text = decode_idl_string(&raw, wide).map_err(|m| self.error(pos, m))?;
        Ok(Tok::Str { text, wide })
    }

    /// `include_directive`: `#include "path"` or `#include <path>` (the path is not kept).
    fn include(&mut self, pos: Pos) -> Result<Tok, ParseError> {
        self.bump();
        let mut word = String::new();
        while let Some(c) = self.peek(0).filter(char::is_ascii_alphabetic) {
            word.push(c);
            self.bump();
        }
        if word != "include" {
            return Err(self.error(pos, "expected `#include` (the only directive supported)"));
        }
        while matches!(self.peek(0), Some(' ' | '\t' | '\n' | '\r' | '\x0c')) {
            self.bump();
        }
        let close = match self.bump() {
            Some('"') => '"',
            Some('<') => '>',
            _ => return Err(self.error(pos, "expected `\"` or `<` after `#include`")),
        };
        let mut len = 0;
        loop {
            match self.bump() {
                None => return Err(self.error(pos, "unterminated `#include`")),
                Some(c) if c == close && len > 0 => return Ok(Tok::Include),
                Some(c) if c == close => return Err(self.error(pos, "empty `#include` path")),
                Some(_) => len += 1,
            }
        }
    }
}

/// The value of a string literal's text between its quotes, as rosidl_parser
/// `get_string_literal_value` decodes it: escape sequences (IDL Table 7-9, `\u` only in wide
/// strings) through Python's `unicode-escape`, then once more a backslash dropped before `"` or
/// `\`.
fn decode_idl_string(raw: &str, wide: bool) -> Result<String, String> {
    let chars: Vec<char> = raw.chars().collect();
    let mut out: Vec<char> = Vec::with_capacity(chars.len());
    let mut i = 0;
    while i < chars.len() {
        let (c, next) = (chars[i], chars.get(i + 1).copied());
        if c != '\\' || next.is_none() {
            out.push(c);
            i += 1;
            continue;
        }
        let run = |from: usize, max: usize, radix: u32| {
            chars[from..]
                .iter()
                .take(max)
                .take_while(|c| c.is_digit(radix))
                .count()
        };
        let (decoded, len) = match next {
            Some('n') => (Some('\n'), 2),
            Some('t') => (Some('\t'), 2),
            Some('v') => (Some('\x0b'), 2),
            Some('b') => (Some('\x08'), 2),
            Some('r') => (Some('\r'), 2),
            Some('f') => (Some('\x0c'), 2),
            Some('a') => (Some('\x07'), 2),
            Some(c @ ('\\' | '\'' | '"')) => (Some(c), 2),
            // Python's unicode-escape keeps an unknown escape such as `\?`.
            Some('?') => (None, 2),
            Some('0'..='7') => {
                let n = run(i + 1, 3, 8);
                (escaped_char(&chars[i + 1..i + 1 + n], 8)?, 1 + n)
            }
            Some('x') if run(i + 2, 2, 16) > 0 => {
                let n = run(i + 2, 2, 16);
                if n < 2 {
                    return Err("truncated `\\xXX` escape".to_owned());
                }
                (escaped_char(&chars[i + 2..i + 4], 16)?, 4)
            }
            Some('u') if wide && run(i + 2, 4, 16) > 0 => {
                let n = run(i + 2, 4, 16);
                if n < 4 {
                    return Err("truncated `\\uXXXX` escape".to_owned());
                }
                (escaped_char(&chars[i + 2..i + 6], 16)?, 6)
            }
            _ => (None, 1),
        };
        match decoded {
            Some(d) => out.push(d),
            None => out.extend(&chars[i..i + len]),
        }
        i += len;
    }
    // rosidl_parser: "unescape double quote and backslash if preceeded by a backslash".
    let mut i = 0;
    while i < out.len() {
        if out[i] == '\\' && matches!(out.get(i + 1), Some('"' | '\\')) {
            out.remove(i);
        }
        i += 1;
    }
    Ok(out.into_iter().collect())
}

fn escaped_char(digits: &[char], radix: u32) -> Result<Option<char>, String> {
    let text: String = digits.iter().collect();
    u32::from_str_radix(&text, radix)
        .ok()
        .and_then(char::from_u32)
        .map(Some)
        .ok_or_else(|| format!("escape `{text}` is not a character"))
}

// ---------------------------------------------------------------------------------------------
// Parsing (grammar.lark's rules), into what the file declares

/// A constant expression's value (rosidl_parser `get_const_expr_value`).
#[derive(Clone, Debug, PartialEq)]
enum Expr {
    Int(i128),
    Float(f64),
    Bool(bool),
    Str(String),
    /// A scoped name (its first identifier, as rosidl_parser keeps it).
    Name(String),
}

/// An annotation (`annotation_appl`): its name and parameters.
#[derive(Clone, Debug)]
struct Annotation {
    name: String,
    pos: Pos,
    /// `(value)` is one unnamed parameter; `(a=1, b=2)` named ones.
    params: Vec<(Option<String>, Expr, Pos)>,
}

impl Annotation {
    fn param(&self, name: &str) -> Option<(&Expr, Pos)> {
        // A Python dict: the last of a repeated name wins.
        self.params
            .iter()
            .rev()
            .find(|(n, _, _)| n.as_deref() == Some(name))
            .map(|(_, e, p)| (e, *p))
    }
}

/// A type as written, before typedefs are resolved.
#[derive(Clone, Debug, PartialEq)]
enum RawBase {
    Known(BaseType),
    /// A single identifier: a typedef's name.
    Typedef(String),
}

#[derive(Clone, Debug)]
struct RawType {
    base: RawBase,
    container: Container,
    pos: Pos,
}

#[derive(Clone, Debug)]
struct RawMember {
    name: String,
    ty: RawType,
    default: Option<(Expr, Pos)>,
    comment: Vec<String>,
    unit: Option<String>,
}

#[derive(Clone, Debug)]
struct RawStruct {
    modules: Vec<String>,
    name: String,
    pos: Pos,
    comment: Vec<String>,
    members: Vec<RawMember>,
}

/// Everything of the file that the model keeps.
#[derive(Default)]
struct Spec {
    typedefs: HashMap<String, RawType>,
    /// Constants by the name of their innermost module.
    constants: HashMap<String, Vec<Constant>>,
    structs: Vec<RawStruct>,
}

struct Parser<'a> {
    file: &'a Path,
    tokens: Vec<Token>,
    next: usize,
    modules: Vec<String>,
    spec: Spec,
}

impl Parser<'_> {
    fn peek(&self) -> &Token {
        // The lexer ends every list with `Eof`, which is never consumed.
        &self.tokens[self.next.min(self.tokens.len() - 1)]
    }

    fn advance(&mut self) -> Token {
        let token = self.peek().clone();
        if token.tok != Tok::Eof {
            self.next += 1;
        }
        token
    }

    fn error(&self, pos: Pos, message: impl Into<String>) -> ParseError {
        ParseError::new(self.file, pos.line, pos.column, message)
    }

    /// "expected `what`, found ..." at the next token.
    fn expected(&self, what: &str) -> ParseError {
        let token = self.peek();
        self.error(
            token.pos,
            format!("expected {what}, found {}", describe(&token.tok)),
        )
    }

    fn at_punct(&self, p: &str) -> bool {
        matches!(self.peek().tok, Tok::Punct(q) if q == p)
    }

    fn at_word(&self, word: &str) -> bool {
        matches!(&self.peek().tok, Tok::Ident(w) if w == word)
    }

    fn eat_punct(&mut self, p: &str) -> bool {
        let at = self.at_punct(p);
        if at {
            self.advance();
        }
        at
    }

    fn eat_word(&mut self, word: &str) -> bool {
        let at = self.at_word(word);
        if at {
            self.advance();
        }
        at
    }

    fn expect_punct(&mut self, p: &str) -> Result<Pos, ParseError> {
        if self.at_punct(p) {
            Ok(self.advance().pos)
        } else {
            Err(self.expected(&format!("`{p}`")))
        }
    }

    fn identifier(&mut self, what: &str) -> Result<(String, Pos), ParseError> {
        match self.peek().tok.clone() {
            Tok::Ident(name) => Ok((name, self.advance().pos)),
            _ => Err(self.expected(what)),
        }
    }

    /// `specification`: `definition+`.
    fn specification(&mut self) -> Result<(), ParseError> {
        self.definition()?;
        while self.peek().tok != Tok::Eof {
            self.definition()?;
        }
        Ok(())
    }

    /// `definition`: an include, or a module, constant or type declaration and `;`.
    fn definition(&mut self) -> Result<(), ParseError> {
        if self.peek().tok == Tok::Include {
            self.advance();
            return Ok(());
        }
        let annotations = self.annotations()?;
        if self.eat_word("module") {
            self.module()?;
        } else if self.eat_word("const") {
            self.constant(&annotations)?;
        } else if self.eat_word("typedef") {
            self.typedef()?;
        } else if self.eat_word("struct") {
            self.structure(&annotations)?;
        } else if self.eat_word("enum") {
            self.enumeration()?;
        } else {
            return Err(self.expected("`module`, `const`, `typedef`, `struct` or `enum`"));
        }
        self.expect_punct(";")?;
        Ok(())
    }

    /// `module_dcl` after `module`: `IDENTIFIER "{" definition+ "}"`.
    fn module(&mut self) -> Result<(), ParseError> {
        let (name, pos) = self.identifier("a module name")?;
        if self.modules.len() >= MAX_MODULE_DEPTH {
            return Err(self.error(pos, "modules nested too deeply"));
        }
        self.expect_punct("{")?;
        self.modules.push(name);
        self.definition()?;
        while !self.at_punct("}") {
            if self.peek().tok == Tok::Eof {
                return Err(self.expected("`}`"));
            }
            self.definition()?;
        }
        self.advance();
        self.modules.pop();
        Ok(())
    }

    /// `const_dcl` after `const`: `const_type IDENTIFIER "=" const_expr`; the constant belongs to
    /// the innermost module (rosidl_parser `extract_content_from_ast`).
    fn constant(&mut self, annotations: &[Annotation]) -> Result<(), ParseError> {
        let ty_pos = self.peek().pos;
        let ty = self.type_spec()?;
        let (name, _) = self.identifier("the constant's name")?;
        self.expect_punct("=")?;
        let (value, value_pos) = self.const_expr()?;
        let base = match (ty.container, ty.base) {
            (Container::Single, RawBase::Known(BaseType::Primitive(p))) => BaseType::Primitive(p),
            // rosidl_parser `get_abstract_type_from_const_expr`: a string constant's type is
            // bounded by its value's length, whatever the declaration says.
            (
                Container::Single,
                RawBase::Known(b @ (BaseType::String(_) | BaseType::WString(_))),
            ) => {
                let Expr::Str(s) = &value else {
                    return Err(self.error(value_pos, "expected a string literal"));
                };
                let len = Some(s.chars().count() as u64);
                if matches!(b, BaseType::String(_)) {
                    BaseType::String(len)
                } else {
                    BaseType::WString(len)
                }
            }
            _ => {
                return Err(self.error(
                    ty_pos,
                    "expected a constant type (a basic type, `string` or `wstring`)",
                ))
            }
        };
        let value = scalar_literal(&base, &value).map_err(|m| self.error(value_pos, m))?;
        let Some(module) = self.modules.last() else {
            return Err(self.error(ty_pos, "a constant must be inside a module"));
        };
        let comment = comment_lines(annotations).map_err(|(m, p)| self.error(p, m))?;
        self.spec
            .constants
            .entry(module.clone())
            .or_default()
            .push(Constant {
                name,
                ty: base,
                value,
                comment,
            });
        Ok(())
    }

    /// `typedef_dcl` after `typedef`: one type and one (array) declarator.
    fn typedef(&mut self) -> Result<(), ParseError> {
        let ty = self.type_spec()?;
        let (name, ty) = self.declarator(ty)?;
        if self.at_punct(",") {
            return Err(self.expected("`;` (one declarator per typedef)"));
        }
        match self.spec.typedefs.get(&name) {
            Some(old) if old.base != ty.base || old.container != ty.container => {
                return Err(self.error(ty.pos, format!("typedef `{name}` redefined differently")))
            }
            Some(_) => {}
            None => {
                self.spec.typedefs.insert(name, ty);
            }
        }
        Ok(())
    }

    /// `struct_def` (or `struct_forward_dcl`, ignored) after `struct`.
    fn structure(&mut self, annotations: &[Annotation]) -> Result<(), ParseError> {
        let (name, pos) = self.identifier("the struct's name")?;
        if !self.eat_punct("{") {
            return Ok(());
        }
        let mut members = Vec::new();
        loop {
            self.member(&mut members)?;
            if self.eat_punct("}") {
                break;
            }
        }
        let comment = comment_lines(annotations).map_err(|(m, p)| self.error(p, m))?;
        self.spec.structs.push(RawStruct {
            modules: self.modules.clone(),
            name,
            pos,
            comment,
            members,
        });
        Ok(())
    }

    /// `enum_dcl` after `enum` (accepted by the grammar, ignored by rosidl_parser).
    fn enumeration(&mut self) -> Result<(), ParseError> {
        self.identifier("the enum's name")?;
        self.expect_punct("{")?;
        loop {
            self.annotations()?;
            self.identifier("an enumerator")?;
            if !self.eat_punct(",") {
                break;
            }
        }
        self.expect_punct("}")?;
        Ok(())
    }

    /// `member`: annotations, a type and declarators, `;`.
    fn member(&mut self, members: &mut Vec<RawMember>) -> Result<(), ParseError> {
        let annotations = self.annotations()?;
        if self.at_punct("}") {
            return Err(self.expected("a member"));
        }
        let comment = comment_lines(&annotations).map_err(|(m, p)| self.error(p, m))?;
        let default = self.unique_param(&annotations, "default")?;
        let unit = match self.unique_param(&annotations, "unit")? {
            Some((Expr::Str(s), _)) => Some(s),
            Some((_, pos)) => return Err(self.error(pos, "expected the unit as a string literal")),
            None => None,
        };
        let ty = self.type_spec()?;
        loop {
            let (name, ty) = self.declarator(ty.clone())?;
            members.push(RawMember {
                name,
                ty,
                default: default.clone(),
                comment: comment.clone(),
                unit: unit.clone(),
            });
            if !self.eat_punct(",") {
                break;
            }
        }
        self.expect_punct(";")?;
        Ok(())
    }

    /// The `value` of the only annotation `name` (rosidl_parser `get_annotation_value`).
    fn unique_param(
        &self,
        annotations: &[Annotation],
        name: &str,
    ) -> Result<Option<(Expr, Pos)>, ParseError> {
        let mut found = annotations.iter().filter(|a| a.name == name);
        let Some(annotation) = found.next() else {
            return Ok(None);
        };
        if let Some(again) = found.next() {
            return Err(self.error(again.pos, format!("more than one `@{name}`")));
        }
        match annotation.param("value") {
            Some((expr, pos)) => Ok(Some((expr.clone(), pos))),
            None => Err(self.error(annotation.pos, format!("expected `@{name} (value=...)`"))),
        }
    }

    /// `declarator`/`any_declarator`: a name, and one `[N]` making `ty` an array.
    fn declarator(&mut self, mut ty: RawType) -> Result<(String, RawType), ParseError> {
        let (name, _) = self.identifier("a name")?;
        if self.at_punct("[") {
            let pos = self.advance().pos;
            let size = self.positive_int("an array size (a positive integer)", 1)?;
            self.expect_punct("]")?;
            if self.at_punct("[") {
                return Err(
                    self.error(self.peek().pos, "multidimensional arrays are not supported")
                );
            }
            if ty.container != Container::Single {
                return Err(self.error(pos, "arrays of arrays or sequences are not supported"));
            }
            ty.container = Container::Array(size);
        }
        Ok((name, ty))
    }

    /// `type_spec` (also what a `typedef` declares).
    fn type_spec(&mut self) -> Result<RawType, ParseError> {
        let pos = self.peek().pos;
        let single = |base| RawType {
            base,
            container: Container::Single,
            pos,
        };
        if self.at_punct("::") {
            return self.scoped_type(pos);
        }
        let Tok::Ident(word) = self.peek().tok.clone() else {
            return Err(self.expected("a type"));
        };
        if let Some(primitive) = self.base_type()? {
            return Ok(single(RawBase::Known(BaseType::Primitive(primitive))));
        }
        match word.as_str() {
            "string" | "wstring" => {
                self.advance();
                let bound = if self.eat_punct("<") {
                    let min = u64::from(word == "string");
                    let bound = self.positive_int("a string bound (a positive integer)", min)?;
                    self.expect_punct(">")?;
                    Some(bound)
                } else {
                    None
                };
                Ok(single(RawBase::Known(if word == "string" {
                    BaseType::String(bound)
                } else {
                    BaseType::WString(bound)
                })))
            }
            "sequence" => {
                self.advance();
                self.expect_punct("<")?;
                let inner_pos = self.peek().pos;
                if self.at_word("sequence") {
                    return Err(self.error(inner_pos, "sequences of sequences are not supported"));
                }
                let inner = self.type_spec()?;
                let container = if self.eat_punct(",") {
                    Container::BoundedSequence(
                        self.positive_int("a sequence bound (a positive integer)", 1)?,
                    )
                } else {
                    Container::UnboundedSequence
                };
                self.expect_punct(">")?;
                Ok(RawType {
                    base: inner.base,
                    container,
                    pos,
                })
            }
            "fixed" => Err(self.error(pos, "fixed-point types are not supported")),
            "struct" | "enum" | "union" => Err(self.error(pos, "expected a type name")),
            _ => self.scoped_type(pos),
        }
    }

    /// `scoped_name` as a type: `pkg::msg::Name` or a typedef's name.
    fn scoped_type(&mut self, pos: Pos) -> Result<RawType, ParseError> {
        let (parts, leading) = self.scoped_name()?;
        let base = match parts.as_slice() {
            [name] if !leading => RawBase::Typedef(name.clone()),
            [package, namespace, name] => {
                RawBase::Known(BaseType::Named(NamedType::new(package, namespace, name)))
            }
            _ => {
                return Err(self.error(
                    pos,
                    "expected a type named `package::namespace::Name` or a typedef's name",
                ))
            }
        };
        Ok(RawType {
            base,
            container: Container::Single,
            pos,
        })
    }

    /// `scoped_name`: identifiers joined by `::`, maybe after a leading `::`.
    fn scoped_name(&mut self) -> Result<(Vec<String>, bool), ParseError> {
        let leading = self.eat_punct("::");
        let mut parts = vec![self.identifier("a name")?.0];
        while self.eat_punct("::") {
            parts.push(self.identifier("a name after `::`")?.0);
        }
        Ok((parts, leading))
    }

    /// `base_type_spec` (rosidl_parser `BASE_TYPE_SPEC_TO_IDL_TYPE`), if the next words are one.
    fn base_type(&mut self) -> Result<Option<Primitive>, ParseError> {
        let Tok::Ident(word) = self.peek().tok.clone() else {
            return Ok(None);
        };
        let primitive = match word.as_str() {
            "boolean" => Primitive::Bool,
            "octet" => Primitive::Byte,
            "char" => Primitive::Char,
            "wchar" => Primitive::WChar,
            "float" => Primitive::Float32,
            "double" => Primitive::Float64,
            "short" | "int16" => Primitive::Int16,
            "int8" => Primitive::Int8,
            "uint8" => Primitive::UInt8,
            "uint16" => Primitive::UInt16,
            "int32" => Primitive::Int32,
            "uint32" => Primitive::UInt32,
            "int64" => Primitive::Int64,
            "uint64" => Primitive::UInt64,
            "long" => {
                self.advance();
                return Ok(Some(if self.eat_word("double") {
                    Primitive::LongDouble
                } else if self.eat_word("long") {
                    Primitive::Int64
                } else {
                    Primitive::Int32
                }));
            }
            "unsigned" => {
                self.advance();
                return Ok(Some(if self.eat_word("short") {
                    Primitive::UInt16
                } else if self.eat_word("long") {
                    if self.eat_word("long") {
                        Primitive::UInt64
                    } else {
                        Primitive::UInt32
                    }
                } else {
                    return Err(self.expected("`short` or `long` after `unsigned`"));
                }));
            }
            _ => return Ok(None),
        };
        self.advance();
        Ok(Some(primitive))
    }

    /// `positive_int_const`: an integer literal of at least `min`.
    fn positive_int(&mut self, what: &str, min: u64) -> Result<u64, ParseError> {
        let pos = self.peek().pos;
        match self.const_expr() {
            Ok((Expr::Int(i), _)) => u64::try_from(i)
                .ok()
                .filter(|n| *n >= min)
                .ok_or_else(|| self.error(pos, format!("expected {what}, found {i}"))),
            Ok(_) => Err(self.error(pos, format!("expected {what}"))),
            Err(_) => Err(self.error(pos, format!("expected {what}"))),
        }
    }

    /// `const_expr` as rosidl_parser evaluates it: at most one sign, then a literal or a scoped
    /// name.
    fn const_expr(&mut self) -> Result<(Expr, Pos), ParseError> {
        let pos = self.peek().pos;
        let negate = if self.eat_punct("-") {
            true
        } else {
            self.eat_punct("+");
            false
        };
        let primary_pos = self.peek().pos;
        let value = match self.peek().tok.clone() {
            Tok::Int(i) => Expr::Int(i),
            Tok::Float(f) => Expr::Float(f),
            Tok::Str { text, wide } => {
                self.advance();
                let mut text = text;
                // Adjacent string literals (all narrow or all wide) are one.
                while let Tok::Str {
                    text: more,
                    wide: w,
                } = &self.peek().tok
                {
                    if *w != wide {
                        return Err(self.expected("string literals all wide or all narrow"));
                    }
                    text.push_str(more);
                    self.advance();
                }
                return self.negated(Expr::Str(text), negate, pos);
            }
            Tok::Ident(w) if w == "TRUE" => Expr::Bool(true),
            Tok::Ident(w) if w == "FALSE" => Expr::Bool(false),
            Tok::Ident(_) | Tok::Punct("::") => {
                let (parts, _) = self.scoped_name()?;
                return self.negated(Expr::Name(parts[0].clone()), negate, pos);
            }
            Tok::Punct("(") => {
                return Err(self.error(primary_pos, "parenthesized expressions are not supported"))
            }
            _ => return Err(self.expected("a literal")),
        };
        self.advance();
        self.negated(value, negate, pos)
    }

    fn negated(&self, value: Expr, negate: bool, pos: Pos) -> Result<(Expr, Pos), ParseError> {
        let value = match (negate, value) {
            (false, value) => value,
            (true, Expr::Int(i)) => Expr::Int(-i),
            (true, Expr::Float(f)) => Expr::Float(-f),
            (true, _) => return Err(self.error(pos, "`-` before something not a number")),
        };
        Ok((value, pos))
    }

    /// `annotation_appl*`.
    fn annotations(&mut self) -> Result<Vec<Annotation>, ParseError> {
        let mut annotations = Vec::new();
        while self.at_punct("@") {
            let pos = self.advance().pos;
            let (parts, _) = self.scoped_name()?;
            let mut params = Vec::new();
            if self.eat_punct("(") {
                let named = matches!(self.peek().tok, Tok::Ident(_))
                    && matches!(
                        self.tokens.get(self.next + 1).map(|t| &t.tok),
                        Some(Tok::Punct("="))
                    );
                if named {
                    loop {
                        let (name, _) = self.identifier("a parameter name")?;
                        self.expect_punct("=")?;
                        let (value, pos) = self.const_expr()?;
                        params.push((Some(name), value, pos));
                        if !self.eat_punct(",") {
                            break;
                        }
                    }
                } else {
                    let (value, pos) = self.const_expr()?;
                    params.push((None, value, pos));
                }
                self.expect_punct(")")?;
            }
            annotations.push(Annotation {
                name: parts[0].clone(),
                pos,
                params,
            });
        }
        Ok(annotations)
    }
}

/// The comment lines of `@verbatim (language="comment", text=...)` annotations
/// (rosidl_parser `Annotatable.get_comment_lines`).
fn comment_lines(annotations: &[Annotation]) -> Result<Vec<String>, (String, Pos)> {
    let mut lines = Vec::new();
    for a in annotations.iter().filter(|a| a.name == "verbatim") {
        let (Some((Expr::Str(language), _)), Some((text, pos))) =
            (a.param("language"), a.param("text"))
        else {
            continue;
        };
        if language != "comment" {
            continue;
        }
        let Expr::Str(text) = text else {
            return Err(("expected the comment as a string literal".to_owned(), pos));
        };
        lines.extend(python_splitlines(text));
    }
    Ok(lines)
}

/// Python's `str.splitlines()`.
fn python_splitlines(text: &str) -> Vec<String> {
    let is_break = |c: char| {
        matches!(
            c,
            '\n' | '\r'
                | '\x0b'
                | '\x0c'
                | '\x1c'
                | '\x1d'
                | '\x1e'
                | '\u{85}'
                | '\u{2028}'
                | '\u{2029}'
        )
    };
    let mut lines = Vec::new();
    let mut line = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if is_break(c) {
            if c == '\r' && chars.peek() == Some(&'\n') {
                chars.next();
            }
            lines.push(std::mem::take(&mut line));
        } else {
            line.push(c);
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

// ---------------------------------------------------------------------------------------------
// Values

/// A literal for one value of `base` (a constant, a scalar default, an array default's element).
fn scalar_literal(base: &BaseType, value: &Expr) -> Result<Literal, String> {
    match (base, value) {
        (BaseType::Primitive(Primitive::Bool), Expr::Bool(b)) => Ok(Literal::Bool(*b)),
        (BaseType::Primitive(Primitive::Bool), _) => Err("expected `TRUE` or `FALSE`".to_owned()),
        (
            BaseType::Primitive(Primitive::Float32 | Primitive::Float64 | Primitive::LongDouble),
            Expr::Int(i),
        ) => Ok(Literal::Float(*i as f64)),
        (
            BaseType::Primitive(Primitive::Float32 | Primitive::Float64 | Primitive::LongDouble),
            Expr::Float(f),
        ) => Ok(Literal::Float(*f)),
        (BaseType::Primitive(p), Expr::Int(i)) => match p.integer() {
            Some((bits, signed)) if in_range(*i, bits, signed) => Ok(Literal::Int(*i)),
            Some(_) => Err(format!("{i} is out of the range of {}", p.msg_name())),
            None => Err("expected a number".to_owned()),
        },
        (BaseType::Primitive(p), _) => Err(format!("expected a literal of type {}", p.msg_name())),
        (BaseType::String(_) | BaseType::WString(_), Expr::Str(s)) => {
            Ok(Literal::String(s.clone()))
        }
        (BaseType::String(_) | BaseType::WString(_), _) => {
            Err("expected a string literal".to_owned())
        }
        (BaseType::Named(n), _) => Err(format!("a member of type {n} has no default value")),
    }
}

fn in_range(i: i128, bits: u32, signed: bool) -> bool {
    if signed {
        let half = 1i128 << (bits - 1);
        (-half..half).contains(&i)
    } else {
        (0..1i128 << bits).contains(&i)
    }
}

/// A Python literal of an array default (rosidl_adapter `to_idl_literal`: `repr(tuple(...))`).
#[derive(Debug, PartialEq)]
enum PyLiteral {
    Bool(bool),
    Int(i128),
    Float(f64),
    Str(String),
}

/// Parses a Python tuple (or list) of bools, numbers and strings: `(1, 2)`, `(1.5,)`, `()`,
/// `('a', "b'c")`.
fn python_sequence(text: &str) -> Result<Vec<PyLiteral>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut at = 0;
    let skip = |at: &mut usize| {
        while chars.get(*at).is_some_and(|c| c.is_whitespace()) {
            *at += 1;
        }
    };
    skip(&mut at);
    let close = match chars.get(at) {
        Some('(') => ')',
        Some('[') => ']',
        _ => return Err("expected a Python tuple such as \"(1, 2)\"".to_owned()),
    };
    at += 1;
    let mut items = Vec::new();
    loop {
        skip(&mut at);
        if chars.get(at) == Some(&close) {
            at += 1;
            break;
        }
        items.push(python_literal(&chars, &mut at)?);
        skip(&mut at);
        match chars.get(at) {
            Some(',') => at += 1,
            Some(c) if *c == close => {
                at += 1;
                break;
            }
            _ => return Err(format!("expected `,` or `{close}` in the Python tuple")),
        }
    }
    skip(&mut at);
    if at != chars.len() {
        return Err("unexpected text after the Python tuple".to_owned());
    }
    Ok(items)
}

fn python_literal(chars: &[char], at: &mut usize) -> Result<PyLiteral, String> {
    let start = *at;
    match chars.get(start) {
        Some(q @ ('\'' | '"')) => python_string(chars, at, *q).map(PyLiteral::Str),
        Some(c) if c.is_ascii_alphabetic() => {
            while chars.get(*at).is_some_and(|c| c.is_ascii_alphanumeric()) {
                *at += 1;
            }
            match chars[start..*at].iter().collect::<String>().as_str() {
                "True" => Ok(PyLiteral::Bool(true)),
                "False" => Ok(PyLiteral::Bool(false)),
                word => Err(format!("unexpected `{word}` in the Python tuple")),
            }
        }
        _ => {
            while chars
                .get(*at)
                .is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '+' | '-' | '_'))
            {
                // A sign only at the start or after an exponent.
                let c = chars[*at];
                if matches!(c, '+' | '-') && *at > start && !matches!(chars[*at - 1], 'e' | 'E') {
                    break;
                }
                *at += 1;
            }
            let text: String = chars[start..*at].iter().filter(|c| **c != '_').collect();
            let digits = text.trim_start_matches(['+', '-']);
            let is_float = digits.contains(['.', 'e', 'E']);
            if digits.is_empty() || !digits.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
                Err("expected a number in the Python tuple".to_owned())
            } else if is_float {
                text.parse()
                    .map(PyLiteral::Float)
                    .map_err(|_| format!("malformed number `{text}` in the Python tuple"))
            } else {
                text.parse()
                    .map(PyLiteral::Int)
                    .map_err(|_| format!("malformed number `{text}` in the Python tuple"))
            }
        }
    }
}

/// A Python string literal quoted by `quote` (at `at`), escapes decoded.
fn python_string(chars: &[char], at: &mut usize, quote: char) -> Result<String, String> {
    let mut out = String::new();
    *at += 1;
    loop {
        let c = *chars
            .get(*at)
            .ok_or("unterminated string in the Python tuple")?;
        *at += 1;
        if c == quote {
            return Ok(out);
        }
        if c != '\\' {
            out.push(c);
            continue;
        }
        let e = *chars
            .get(*at)
            .ok_or("unterminated string in the Python tuple")?;
        *at += 1;
        let hex = |at: &mut usize, n: usize| -> Result<char, String> {
            let digits: String = chars.get(*at..*at + n).unwrap_or_default().iter().collect();
            *at += n;
            u32::from_str_radix(&digits, 16)
                .ok()
                .filter(|_| digits.len() == n)
                .and_then(char::from_u32)
                .ok_or_else(|| format!("bad escape `{digits}` in the Python tuple"))
        };
        match e {
            '\n' => {}
            '\\' | '\'' | '"' => out.push(e),
            'a' => out.push('\x07'),
            'b' => out.push('\x08'),
            'f' => out.push('\x0c'),
            'n' => out.push('\n'),
            'r' => out.push('\r'),
            't' => out.push('\t'),
            'v' => out.push('\x0b'),
            'x' => out.push(hex(at, 2)?),
            'u' => out.push(hex(at, 4)?),
            'U' => out.push(hex(at, 8)?),
            '0'..='7' => {
                let mut n = e.to_digit(8).unwrap_or(0);
                for _ in 0..2 {
                    match chars.get(*at).and_then(|c| c.to_digit(8)) {
                        Some(d) => {
                            n = n * 8 + d;
                            *at += 1;
                        }
                        None => break,
                    }
                }
                out.push(char::from_u32(n).ok_or("bad octal escape in the Python tuple")?);
            }
            other => {
                out.push('\\');
                out.push(other);
            }
        }
    }
}

/// A member's default: a literal, or for an array or sequence a string holding a Python tuple.
fn default_value(ty: &FieldType, value: &Expr) -> Result<Value, String> {
    if ty.container == Container::Single {
        return scalar_literal(&ty.base, value).map(Value::Scalar);
    }
    let Expr::Str(text) = value else {
        return Err("expected the default of an array or sequence as a string literal holding a Python tuple".to_owned());
    };
    let items = python_sequence(text)?
        .into_iter()
        .map(|item| {
            let expr = match item {
                PyLiteral::Bool(b) => Expr::Bool(b),
                PyLiteral::Int(i) => Expr::Int(i),
                PyLiteral::Float(f) => Expr::Float(f),
                PyLiteral::Str(s) => Expr::Str(s),
            };
            scalar_literal(&ty.base, &expr)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let n = items.len() as u64;
    match ty.container {
        Container::Array(size) if n != size => {
            Err(format!("{n} default values for an array of {size}"))
        }
        Container::BoundedSequence(max) if n > max => Err(format!(
            "{n} default values for a sequence of at most {max}"
        )),
        _ => Ok(Value::Array(items)),
    }
}

// ---------------------------------------------------------------------------------------------
// The interface (rosidl_parser `extract_content_from_ast`)

struct Builder<'a> {
    file: &'a Path,
    spec: Spec,
}

impl Builder<'_> {
    fn error(&self, pos: Pos, message: impl Into<String>) -> ParseError {
        ParseError::new(self.file, pos.line, pos.column, message)
    }

    fn interface(&self) -> Result<Interface, ParseError> {
        let structs = &self.spec.structs;
        match structs.as_slice() {
            [] => Err(self.error(
                Pos { line: 1, column: 1 },
                "expected a struct (a message, a service's two or an action's three)",
            )),
            [message] => Ok(Interface::Message(self.message(message)?)),
            [request, response] => {
                let name = self.part_of(request, "_Request", None)?;
                self.part_of(response, "_Response", Some(&name))?;
                Ok(Interface::Service(Service {
                    name,
                    request: self.message(request)?,
                    response: self.message(response)?,
                }))
            }
            [goal, result, feedback] => {
                let name = self.part_of(goal, "_Goal", None)?;
                self.part_of(result, "_Result", Some(&name))?;
                self.part_of(feedback, "_Feedback", Some(&name))?;
                Ok(Interface::Action(Action {
                    name,
                    goal: self.message(goal)?,
                    result: self.message(result)?,
                    feedback: self.message(feedback)?,
                }))
            }
            [_, _, _, extra, ..] => Err(self.error(
                extra.pos,
                "more than three structs (only a message, a service or an action)",
            )),
        }
    }

    /// The struct's type name (`pkg/namespace/Name`).
    fn type_name(&self, s: &RawStruct) -> Result<NamedType, ParseError> {
        match s.modules.as_slice() {
            [package, namespace] => Ok(NamedType::new(package, namespace, &s.name)),
            _ => Err(self.error(
                s.pos,
                "expected the struct inside `module <package> { module <msg|srv|action> {`",
            )),
        }
    }

    /// The service's or action's name, from a part named `Name<suffix>` (and the same as
    /// `expected`'s, if given).
    fn part_of(
        &self,
        s: &RawStruct,
        suffix: &str,
        expected: Option<&NamedType>,
    ) -> Result<NamedType, ParseError> {
        let ty = self.type_name(s)?;
        let base = ty.name.strip_suffix(suffix).unwrap_or_default();
        let name = NamedType::new(&ty.package, &ty.namespace, base);
        match expected {
            _ if base.is_empty() => {}
            Some(e) if *e != name => {}
            _ => return Ok(name),
        }
        let want = expected.map_or_else(
            || format!("`Name{suffix}`"),
            |e| format!("`{}{suffix}`", e.name),
        );
        Err(self.error(s.pos, format!("expected a struct named {want} here")))
    }

    fn message(&self, s: &RawStruct) -> Result<Message, ParseError> {
        let name = self.type_name(s)?;
        let mut fields = s
            .members
            .iter()
            .map(|m| self.field(m))
            .collect::<Result<Vec<_>, _>>()?;
        if let [only] = fields.as_slice() {
            if only.name == PLACEHOLDER_MEMBER
                && only.ty == FieldType::single(BaseType::Primitive(Primitive::UInt8))
            {
                fields.clear();
            }
        }
        let constants = self
            .spec
            .constants
            .get(&format!("{}{CONSTANTS_SUFFIX}", s.name))
            .cloned()
            .unwrap_or_default();
        Ok(Message {
            name,
            fields,
            constants,
            comment: s.comment.clone(),
        })
    }

    fn field(&self, m: &RawMember) -> Result<Field, ParseError> {
        let ty = self.resolve(&m.ty, 0, m.ty.pos)?;
        let default = match &m.default {
            Some((value, pos)) => {
                Some(default_value(&ty, value).map_err(|msg| self.error(*pos, msg))?)
            }
            None => None,
        };
        Ok(Field {
            name: m.name.clone(),
            ty,
            default,
            comment: m.comment.clone(),
            unit: m.unit.clone(),
        })
    }

    /// The type with typedefs resolved (rosidl_parser `resolve_typedefed_names`, to any depth);
    /// a cycle is reported where the member names its type (`used`).
    fn resolve(&self, ty: &RawType, depth: usize, used: Pos) -> Result<FieldType, ParseError> {
        let name = match &ty.base {
            RawBase::Known(base) => {
                return Ok(FieldType {
                    base: base.clone(),
                    container: ty.container,
                })
            }
            RawBase::Typedef(name) => name,
        };
        let Some(target) = self.spec.typedefs.get(name) else {
            return Err(self.error(
                ty.pos,
                format!("unknown type `{name}` (neither a basic type nor a typedef)"),
            ));
        };
        if depth >= MAX_TYPEDEF_DEPTH {
            return Err(self.error(used, format!("typedef `{name}` refers to itself")));
        }
        let inner = self.resolve(target, depth + 1, used)?;
        match (ty.container, inner.container) {
            (Container::Single, _) => Ok(inner),
            (outer, Container::Single) => Ok(FieldType {
                base: inner.base,
                container: outer,
            }),
            _ => Err(self.error(
                ty.pos,
                format!("`{name}` is an array: arrays or sequences of it are not supported"),
            )),
        }
    }
}
