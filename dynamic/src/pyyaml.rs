//! `yaml.dump(data, allow_unicode=True, width=sys.maxsize, default_flow_style=…)` of PyYAML (the
//! version ros2cli jazzy runs on, 6.0) for the values `rosidl_runtime_py.message_to_ordereddict`
//! produces: `OrderedDict`s (represented by ros2cli's own representer, as mappings with no flow
//! style: block unless inside a flow collection), lists (flow when `default_flow_style` is true),
//! strings, ints, floats and bools.
//!
//! The scalar style follows PyYAML `emitter.py` `analyze_scalar` / `choose_scalar_style`: plain
//! when allowed and the plain text would not resolve to another type (`resolver.py`'s YAML 1.1
//! implicit resolvers), else single-quoted, else double-quoted with PyYAML's escapes. Lines are
//! never folded (`width=sys.maxsize`).

use std::sync::OnceLock;

use regex::Regex;

use super::repr::py_float;

/// A Python value as `message_to_ordereddict` leaves it.
#[derive(Clone, Debug, PartialEq)]
pub enum PyValue {
    /// `OrderedDict`: keys in order.
    Map(Vec<(String, PyValue)>),
    /// `list`.
    List(Vec<PyValue>),
    /// `str`.
    Str(String),
    /// `int`.
    Int(i128),
    /// `float`.
    Float(f64),
    /// `bool`.
    Bool(bool),
}

/// The YAML document PyYAML writes for `value` (ends with a newline).
pub fn dump(value: &PyValue, flow_lists: bool) -> String {
    let mut e = Emitter {
        out: String::new(),
        column: 0,
        whitespace: true,
        indention: true,
        flow_lists,
    };
    e.node(value, 0, Ctx::Root, 0);
    if e.column > 0 {
        e.out.push('\n');
    }
    e.out
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Ctx {
    Root,
    /// A value in a block mapping.
    MapValue,
    /// An item of a block sequence.
    SeqItem,
    /// Inside a flow collection.
    Flow,
}

struct Emitter {
    out: String,
    column: usize,
    whitespace: bool,
    indention: bool,
    flow_lists: bool,
}

impl Emitter {
    fn write(&mut self, s: &str) {
        self.column += s.chars().count();
        self.out.push_str(s);
    }

    fn line_break(&mut self) {
        self.out.push('\n');
        self.whitespace = true;
        self.indention = true;
        self.column = 0;
    }

    /// PyYAML `write_indent`.
    fn write_indent(&mut self, indent: usize) {
        if !self.indention || self.column > indent || (self.column == indent && !self.whitespace) {
            self.line_break();
        }
        if self.column < indent {
            self.whitespace = true;
            let pad = " ".repeat(indent - self.column);
            self.column = indent;
            self.out.push_str(&pad);
        }
    }

    /// PyYAML `write_indicator`.
    fn indicator(&mut self, ind: &str, need_ws: bool, whitespace: bool, indention: bool) {
        let data = if self.whitespace || !need_ws {
            ind.to_owned()
        } else {
            format!(" {ind}")
        };
        self.whitespace = whitespace;
        self.indention = self.indention && indention;
        self.write(&data);
    }

    /// Emits one node. `indent` is the emitter's current indentation, `flow` the flow level.
    fn node(&mut self, v: &PyValue, indent: usize, ctx: Ctx, flow: usize) {
        match v {
            PyValue::Map(items) => {
                if flow > 0 || items.is_empty() {
                    self.flow_map(items, indent, flow);
                } else {
                    self.block_map(items, indent, ctx);
                }
            }
            PyValue::List(items) => {
                if flow > 0 || items.is_empty() || self.flow_lists {
                    self.flow_seq(items, indent, flow);
                } else {
                    self.block_seq(items, indent, ctx);
                }
            }
            scalar => {
                let (text, is_str) = scalar_text(scalar);
                // expect_scalar: increase_indent(flow=True) while writing.
                let inner = if ctx == Ctx::Root { 0 } else { indent + 2 };
                self.scalar(&text, is_str, inner, flow > 0);
            }
        }
    }

    fn block_map(&mut self, items: &[(String, PyValue)], indent: usize, ctx: Ctx) {
        let inner = if ctx == Ctx::Root { 0 } else { indent + 2 };
        for (k, v) in items {
            self.write_indent(inner);
            self.scalar(k, true, inner + 2, false);
            self.indicator(":", false, false, false);
            self.node(v, inner, Ctx::MapValue, 0);
        }
    }

    fn block_seq(&mut self, items: &[PyValue], indent: usize, ctx: Ctx) {
        // Sequences that are mapping values are indentless (PyYAML `expect_block_sequence`).
        let inner = match ctx {
            Ctx::Root => 0,
            Ctx::MapValue => indent,
            _ => indent + 2,
        };
        for v in items {
            self.write_indent(inner);
            self.indicator("-", true, false, true);
            self.node(v, inner, Ctx::SeqItem, 0);
        }
    }

    fn flow_seq(&mut self, items: &[PyValue], indent: usize, flow: usize) {
        self.indicator("[", true, true, false);
        let inner = indent + 2;
        for (i, v) in items.iter().enumerate() {
            if i > 0 {
                self.indicator(",", false, false, false);
            }
            self.node(v, inner, Ctx::Flow, flow + 1);
        }
        self.indicator("]", false, false, false);
    }

    fn flow_map(&mut self, items: &[(String, PyValue)], indent: usize, flow: usize) {
        self.indicator("{", true, true, false);
        let inner = indent + 2;
        for (i, (k, v)) in items.iter().enumerate() {
            if i > 0 {
                self.indicator(",", false, false, false);
            }
            self.scalar(k, true, inner + 2, true);
            self.indicator(":", false, false, false);
            self.node(v, inner, Ctx::Flow, flow + 1);
        }
        self.indicator("}", false, false, false);
    }

    /// Writes a scalar in the style PyYAML chooses (`is_str`: a `str`, whose plain form must not
    /// resolve to another type; other scalars are always plain).
    fn scalar(&mut self, text: &str, is_str: bool, indent: usize, in_flow: bool) {
        let implicit = !is_str || resolves_to_str(text);
        let a = analyze(text);
        // Keys are short single-line names here: simple-key restrictions never bite.
        let plain = implicit
            && if in_flow {
                a.allow_flow_plain
            } else {
                a.allow_block_plain
            };
        if plain {
            if !self.whitespace {
                self.write(" ");
            }
            self.write(text);
            self.whitespace = false;
            self.indention = false;
        } else if a.allow_single_quoted {
            self.single_quoted(text, indent);
        } else {
            self.double_quoted(text);
        }
    }

    /// PyYAML `write_single_quoted` (never folding: width is `sys.maxsize`).
    fn single_quoted(&mut self, text: &str, indent: usize) {
        self.indicator("'", true, false, false);
        let chars: Vec<char> = text.chars().collect();
        let (mut spaces, mut breaks) = (false, false);
        let (mut start, mut end) = (0usize, 0usize);
        while end <= chars.len() {
            let ch = chars.get(end).copied();
            if spaces {
                if ch != Some(' ') {
                    let data: String = chars[start..end].iter().collect();
                    self.write(&data);
                    start = end;
                }
            } else if breaks {
                if ch.is_none_or(|c| !is_break(c)) {
                    if chars[start] == '\n' {
                        self.line_break();
                    }
                    for &br in &chars[start..end] {
                        if br == '\n' {
                            self.line_break();
                        } else {
                            self.out.push(br);
                            self.whitespace = true;
                            self.indention = true;
                            self.column = 0;
                        }
                    }
                    self.write_indent(indent);
                    start = end;
                }
            } else if (ch.is_none_or(|c| c == ' ' || is_break(c) || c == '\'')) && start < end {
                let data: String = chars[start..end].iter().collect();
                self.write(&data);
                start = end;
            }
            if ch == Some('\'') {
                self.write("''");
                start = end + 1;
            }
            if let Some(c) = ch {
                spaces = c == ' ';
                breaks = is_break(c);
            }
            end += 1;
        }
        self.indicator("'", false, false, false);
    }

    /// PyYAML `write_double_quoted` with `allow_unicode`.
    fn double_quoted(&mut self, text: &str) {
        self.indicator("\"", true, false, false);
        let mut buf = String::new();
        for c in text.chars() {
            let printable = (' '..='\x7e').contains(&c)
                || ('\u{a0}'..='\u{d7ff}').contains(&c)
                || ('\u{e000}'..='\u{fffd}').contains(&c);
            let special = matches!(
                c,
                '"' | '\\' | '\u{85}' | '\u{2028}' | '\u{2029}' | '\u{feff}'
            );
            if printable && !special {
                buf.push(c);
                continue;
            }
            let esc = match c {
                '\0' => "0".to_owned(),
                '\x07' => "a".to_owned(),
                '\x08' => "b".to_owned(),
                '\t' => "t".to_owned(),
                '\n' => "n".to_owned(),
                '\x0b' => "v".to_owned(),
                '\x0c' => "f".to_owned(),
                '\r' => "r".to_owned(),
                '\x1b' => "e".to_owned(),
                '"' => "\"".to_owned(),
                '\\' => "\\".to_owned(),
                '\u{85}' => "N".to_owned(),
                '\u{a0}' => "_".to_owned(),
                '\u{2028}' => "L".to_owned(),
                '\u{2029}' => "P".to_owned(),
                c if u32::from(c) <= 0xff => format!("x{:02X}", u32::from(c)),
                c if u32::from(c) <= 0xffff => format!("u{:04X}", u32::from(c)),
                c => format!("U{:08X}", u32::from(c)),
            };
            buf.push('\\');
            buf.push_str(&esc);
        }
        self.write(&buf);
        self.indicator("\"", false, false, false);
    }
}

fn is_break(c: char) -> bool {
    matches!(c, '\n' | '\u{85}' | '\u{2028}' | '\u{2029}')
}

/// A scalar's text as PyYAML's representer writes it, and whether it is a `str`.
fn scalar_text(v: &PyValue) -> (String, bool) {
    match v {
        PyValue::Str(s) => (s.clone(), true),
        PyValue::Int(i) => (i.to_string(), false),
        PyValue::Bool(b) => ((if *b { "true" } else { "false" }).to_owned(), false),
        PyValue::Float(f) => (represent_float(*f), false),
        PyValue::Map(_) | PyValue::List(_) => (String::new(), false),
    }
}

/// PyYAML `represent_float`.
fn represent_float(f: f64) -> String {
    if f.is_nan() {
        return ".nan".to_owned();
    }
    if f.is_infinite() {
        return if f > 0.0 { ".inf" } else { "-.inf" }.to_owned();
    }
    let v = py_float(f).to_lowercase();
    if !v.contains('.') && v.contains('e') {
        v.replacen('e', ".0e", 1)
    } else {
        v
    }
}

/// Whether PyYAML's implicit resolvers leave plain `text` a string (no bool, int, float, null,
/// timestamp, merge or value match). Python's `re.match(…$)` also matches before a final `\n`.
fn resolves_to_str(text: &str) -> bool {
    static RESOLVERS: OnceLock<Vec<Regex>> = OnceLock::new();
    let resolvers = RESOLVERS.get_or_init(|| {
        [
            r"^(?:yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF)$",
            r"^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+][0-9]+)?|\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?|[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\.[0-9_]*|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$",
            r"^(?:[-+]?0b[0-1_]+|[-+]?0[0-7_]+|[-+]?(?:0|[1-9][0-9_]*)|[-+]?0x[0-9a-fA-F_]+|[-+]?[1-9][0-9_]*(?::[0-5]?[0-9])+)$",
            r"^(?:<<)$",
            r"^(?:~|null|Null|NULL|)$",
            r"^(?:[0-9][0-9][0-9][0-9]-[0-9][0-9]-[0-9][0-9]|[0-9][0-9][0-9][0-9]-[0-9][0-9]?-[0-9][0-9]?(?:[Tt]|[ \t]+)[0-9][0-9]?:[0-9][0-9]:[0-9][0-9](?:\.[0-9]*)?(?:[ \t]*(?:Z|[-+][0-9][0-9]?(?::[0-9][0-9])?))?)$",
            r"^(?:=)$",
        ]
        .iter()
        .filter_map(|r| Regex::new(r).ok())
        .collect()
    });
    let t = text.strip_suffix('\n').unwrap_or(text);
    !resolvers.iter().any(|r| r.is_match(t))
}

struct Analysis {
    allow_flow_plain: bool,
    allow_block_plain: bool,
    allow_single_quoted: bool,
}

fn ws(c: Option<char>) -> bool {
    c.is_none_or(|c| {
        matches!(
            c,
            '\0' | ' ' | '\t' | '\r' | '\n' | '\u{85}' | '\u{2028}' | '\u{2029}'
        )
    })
}

/// PyYAML `analyze_scalar` (with `allow_unicode`).
fn analyze(s: &str) -> Analysis {
    if s.is_empty() {
        return Analysis {
            allow_flow_plain: false,
            allow_block_plain: true,
            allow_single_quoted: true,
        };
    }
    let chars: Vec<char> = s.chars().collect();
    let n = chars.len();
    let (mut block_ind, mut flow_ind) = (false, false);
    let (mut line_breaks, mut special) = (false, false);
    let (mut leading_space, mut leading_break, mut trailing_space, mut trailing_break) =
        (false, false, false, false);
    let (mut break_space, mut space_break) = (false, false);
    if s.starts_with("---") || s.starts_with("...") {
        block_ind = true;
        flow_ind = true;
    }
    let mut preceded_by_ws = true;
    let mut followed_by_ws = n == 1 || ws(chars.get(1).copied());
    let (mut prev_space, mut prev_break) = (false, false);
    for (i, &ch) in chars.iter().enumerate() {
        if i == 0 {
            if "#,[]{}&*!|>'\"%@`".contains(ch) {
                flow_ind = true;
                block_ind = true;
            }
            if ch == '?' || ch == ':' {
                flow_ind = true;
                if followed_by_ws {
                    block_ind = true;
                }
            }
            if ch == '-' && followed_by_ws {
                flow_ind = true;
                block_ind = true;
            }
        } else {
            if ",?[]{}".contains(ch) {
                flow_ind = true;
            }
            if ch == ':' {
                flow_ind = true;
                if followed_by_ws {
                    block_ind = true;
                }
            }
            if ch == '#' && preceded_by_ws {
                flow_ind = true;
                block_ind = true;
            }
        }
        if is_break(ch) {
            line_breaks = true;
        }
        if !(ch == '\n' || (' '..='\x7e').contains(&ch)) {
            let unicode = (ch == '\u{85}'
                || ('\u{a0}'..='\u{d7ff}').contains(&ch)
                || ('\u{e000}'..='\u{fffd}').contains(&ch)
                || ('\u{10000}'..'\u{10ffff}').contains(&ch))
                && ch != '\u{feff}';
            if !unicode {
                special = true;
            }
        }
        if ch == ' ' {
            if i == 0 {
                leading_space = true;
            }
            if i == n - 1 {
                trailing_space = true;
            }
            if prev_break {
                break_space = true;
            }
            prev_space = true;
            prev_break = false;
        } else if is_break(ch) {
            if i == 0 {
                leading_break = true;
            }
            if i == n - 1 {
                trailing_break = true;
            }
            if prev_space {
                space_break = true;
            }
            prev_space = false;
            prev_break = true;
        } else {
            prev_space = false;
            prev_break = false;
        }
        preceded_by_ws = ws(Some(ch));
        followed_by_ws = i + 2 >= n || ws(chars.get(i + 2).copied());
    }
    let mut a = Analysis {
        allow_flow_plain: true,
        allow_block_plain: true,
        allow_single_quoted: true,
    };
    if leading_space || leading_break || trailing_space || trailing_break {
        a.allow_flow_plain = false;
        a.allow_block_plain = false;
    }
    if break_space {
        a.allow_flow_plain = false;
        a.allow_block_plain = false;
        a.allow_single_quoted = false;
    }
    if space_break || special {
        a.allow_flow_plain = false;
        a.allow_block_plain = false;
        a.allow_single_quoted = false;
    }
    if line_breaks {
        a.allow_flow_plain = false;
        a.allow_block_plain = false;
    }
    if flow_ind {
        a.allow_flow_plain = false;
    }
    if block_ind {
        a.allow_block_plain = false;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(items: Vec<(&str, PyValue)>) -> PyValue {
        PyValue::Map(items.into_iter().map(|(k, v)| (k.to_owned(), v)).collect())
    }

    fn s(v: &str) -> PyValue {
        PyValue::Str(v.to_owned())
    }

    // Expected texts are what PyYAML 6.0 prints for the same Python values (checked with
    // `yaml.dump(..., allow_unicode=True, width=sys.maxsize, default_flow_style=...)` and
    // ros2cli's OrderedDict representer).
    #[test]
    fn block_and_flow_layouts() {
        let event = m(vec![
            (
                "info",
                m(vec![
                    ("event_type", s("REQUEST_SENT")),
                    (
                        "stamp",
                        m(vec![("sec", PyValue::Int(5)), ("nanosec", PyValue::Int(7))]),
                    ),
                    (
                        "client_gid",
                        PyValue::List(vec![PyValue::Int(1), PyValue::Int(15)]),
                    ),
                    ("sequence_number", PyValue::Int(1)),
                ]),
            ),
            (
                "request",
                PyValue::List(vec![m(vec![
                    ("a", PyValue::Int(2)),
                    ("b", PyValue::Int(3)),
                ])]),
            ),
            ("response", PyValue::List(vec![])),
        ]);
        assert_eq!(
            dump(&event, false),
            "info:\n  event_type: REQUEST_SENT\n  stamp:\n    sec: 5\n    nanosec: 7\n  \
             client_gid:\n  - 1\n  - 15\n  sequence_number: 1\nrequest:\n- a: 2\n  b: 3\n\
             response: []\n"
        );
        assert_eq!(
            dump(&event, true),
            "info:\n  event_type: REQUEST_SENT\n  stamp:\n    sec: 5\n    nanosec: 7\n  \
             client_gid: [1, 15]\n  sequence_number: 1\nrequest: [{a: 2, b: 3}]\nresponse: []\n"
        );
        let nested = m(vec![(
            "l",
            PyValue::List(vec![
                PyValue::List(vec![PyValue::Int(1), PyValue::Int(2)]),
                m(vec![("x", PyValue::List(vec![s("a")]))]),
            ]),
        )]);
        assert_eq!(dump(&nested, false), "l:\n- - 1\n  - 2\n- x:\n  - a\n");
    }

    #[test]
    fn scalar_styles() {
        let one = |v: PyValue| dump(&m(vec![("k", v)]), false);
        assert_eq!(one(s("")), "k: ''\n");
        assert_eq!(one(s("hello world")), "k: hello world\n");
        assert_eq!(one(s("true")), "k: 'true'\n");
        assert_eq!(one(s("12")), "k: '12'\n");
        assert_eq!(one(s("1.5")), "k: '1.5'\n");
        assert_eq!(one(s("null")), "k: 'null'\n");
        assert_eq!(one(s("...")), "k: '...'\n");
        assert_eq!(
            one(s("<string length: <5>>")),
            "k: '<string length: <5>>'\n"
        );
        assert_eq!(one(s("it's")), "k: it's\n");
        assert_eq!(one(s("'q'")), "k: '''q'''\n");
        assert_eq!(one(s("tab\there")), "k: \"tab\\there\"\n");
        assert_eq!(one(s("\0")), "k: \"\\0\"\n");
        assert_eq!(one(s("a\nb")), "k: 'a\n\n  b'\n");
        assert_eq!(one(s("ünï")), "k: ünï\n");
        assert_eq!(one(s(" lead")), "k: ' lead'\n");
        assert_eq!(one(s("- x")), "k: '- x'\n");
        assert_eq!(one(s("a: b")), "k: 'a: b'\n");
        assert_eq!(one(s("a:b")), "k: a:b\n");
        assert_eq!(one(s("#x")), "k: '#x'\n");
        assert_eq!(one(PyValue::Float(0.5)), "k: 0.5\n");
        assert_eq!(one(PyValue::Float(1e-5)), "k: 1.0e-05\n");
        assert_eq!(one(PyValue::Float(3.0)), "k: 3.0\n");
        assert_eq!(one(PyValue::Float(f64::NAN)), "k: .nan\n");
        assert_eq!(one(PyValue::Float(f64::NEG_INFINITY)), "k: -.inf\n");
        assert_eq!(one(PyValue::Bool(true)), "k: true\n");
        assert_eq!(one(PyValue::Int(-4)), "k: -4\n");
        // In flow lists, flow indicators rule plain out.
        assert_eq!(
            dump(&m(vec![("k", PyValue::List(vec![s("a,b"), s("c")]))]), true),
            "k: ['a,b', c]\n"
        );
    }
    /// Strings as PyYAML 6.0.3 writes them (generated with the dump call above), in a block
    /// mapping and in a flow sequence.
    #[test]
    fn strings_match_pyyaml() {
        let cases: &[(&str, &str, &str)] = &[
            ("", "k: ''\n", "k: ['']\n"),
            ("hello world", "k: hello world\n", "k: [hello world]\n"),
            ("true", "k: 'true'\n", "k: ['true']\n"),
            ("12", "k: '12'\n", "k: ['12']\n"),
            ("1.5", "k: '1.5'\n", "k: ['1.5']\n"),
            ("null", "k: 'null'\n", "k: ['null']\n"),
            ("...", "k: '...'\n", "k: ['...']\n"),
            (
                "<string length: <5>>",
                "k: '<string length: <5>>'\n",
                "k: ['<string length: <5>>']\n",
            ),
            ("it's", "k: it's\n", "k: [it's]\n"),
            ("'q'", "k: '''q'''\n", "k: ['''q''']\n"),
            ("tab\there", "k: \"tab\\there\"\n", "k: [\"tab\\there\"]\n"),
            ("\u{0}", "k: \"\\0\"\n", "k: [\"\\0\"]\n"),
            ("a\nb", "k: 'a\n\n  b'\n", "k: ['a\n\n    b']\n"),
            ("ünï", "k: ünï\n", "k: [ünï]\n"),
            (" lead", "k: ' lead'\n", "k: [' lead']\n"),
            ("- x", "k: '- x'\n", "k: ['- x']\n"),
            ("a: b", "k: 'a: b'\n", "k: ['a: b']\n"),
            ("a:b", "k: a:b\n", "k: ['a:b']\n"),
            ("#x", "k: '#x'\n", "k: ['#x']\n"),
            ("a\n b", "k: \"a\\n b\"\n", "k: [\"a\\n b\"]\n"),
            ("x\n\ny", "k: 'x\n\n\n  y'\n", "k: ['x\n\n\n    y']\n"),
            ("😀", "k: 😀\n", "k: [😀]\n"),
            ("\u{7f}", "k: \"\\x7F\"\n", "k: [\"\\x7F\"]\n"),
            ("é\u{2028}", "k: 'é\u{2028}  '\n", "k: ['é\u{2028}    ']\n"),
            ("2024-01-01", "k: '2024-01-01'\n", "k: ['2024-01-01']\n"),
            ("0o17", "k: 0o17\n", "k: [0o17]\n"),
            ("0x1F", "k: '0x1F'\n", "k: ['0x1F']\n"),
            ("1_000", "k: '1_000'\n", "k: ['1_000']\n"),
            (":x", "k: :x\n", "k: [':x']\n"),
            ("?", "k: '?'\n", "k: ['?']\n"),
            ("-", "k: '-'\n", "k: ['-']\n"),
            ("a #b", "k: 'a #b'\n", "k: ['a #b']\n"),
            ("a#b", "k: a#b\n", "k: [a#b]\n"),
            ("@x", "k: '@x'\n", "k: ['@x']\n"),
            ("%x", "k: '%x'\n", "k: ['%x']\n"),
            ("!x", "k: '!x'\n", "k: ['!x']\n"),
            ("NO", "k: 'NO'\n", "k: ['NO']\n"),
            ("y", "k: y\n", "k: [y]\n"),
            ("~", "k: '~'\n", "k: ['~']\n"),
            ("=", "k: '='\n", "k: ['=']\n"),
            ("<<", "k: '<<'\n", "k: ['<<']\n"),
            ("1:20", "k: '1:20'\n", "k: ['1:20']\n"),
            (".5", "k: '.5'\n", "k: ['.5']\n"),
            ("+.inf", "k: '+.inf'\n", "k: ['+.inf']\n"),
            ("a ", "k: 'a '\n", "k: ['a ']\n"),
            ("a\n", "k: 'a\n\n  '\n", "k: ['a\n\n    ']\n"),
            ("REQUEST_SENT", "k: REQUEST_SENT\n", "k: [REQUEST_SENT]\n"),
            ("x...", "k: x...\n", "k: [x...]\n"),
            ("--- x", "k: '--- x'\n", "k: ['--- x']\n"),
            ("a\u{85}b", "k: 'a\u{85}  b'\n", "k: ['a\u{85}    b']\n"),
        ];
        for (text, block, flow) in cases {
            assert_eq!(
                &dump(&m(vec![("k", s(text))]), false),
                block,
                "block {text:?}"
            );
            assert_eq!(
                &dump(&m(vec![("k", PyValue::List(vec![s(text)]))]), true),
                flow,
                "flow {text:?}"
            );
        }
        assert_eq!(
            dump(
                &m(vec![("k", PyValue::List(vec![m(vec![("a", s("x\ny"))])]))]),
                true
            ),
            "k: [{a: 'x\n\n      y'}]\n"
        );
        assert_eq!(
            dump(&m(vec![("m", m(vec![("k", s("a\nb"))]))]), false),
            "m:\n  k: 'a\n\n    b'\n"
        );
    }
}
