//! `--ros-args`: the command-line arguments every rclcpp/rclpy executable accepts and
//! `ros2 launch` passes to every node, parsed as rcl 9 (Jazzy) `src/rcl/arguments.c` parses them,
//! and the remapping rules applied as `src/rcl/remap.c` applies them.
//!
//! ```text
//! prog [args] --ros-args [-r|--remap [node:]from:=to] [-p|--param [node:]name:=value]
//!      [--params-file file.yaml] [--log-level [logger:=]level] [-e|--enclave /enclave]
//!      [--log-config-file f] [--log-file-name p] [--enable|--disable-{stdout,rosout,external-lib}-logs]
//!      [--] [args]
//! ```
//!
//! A [`Context`](crate::Context) parses the process's arguments when it is built (unless given
//! [`Arguments`] of its own): every node created from it gets its name and namespace remapped
//! (`-r __node:=x`, `-r __ns:=/ns`), every topic and service name its rules (`-r from:=to`), and
//! the node services of `horus-ros-services` declare the parameters (`-p`, `--params-file`).
//! Malformed arguments are rejected with rcl's messages; ROS arguments that rcl does not know are
//! rejected with rclcpp's (`found unknown ROS arguments: '…'`).

use horus_ros_msgs::rcl_interfaces::msg::{ParameterType, ParameterValue};

use crate::names::{Namespace, NodeName, TopicName};

/// `--ros-args`: starts the ROS arguments.
pub const ROS_ARGS_FLAG: &str = "--ros-args";
/// `--`: ends them.
pub const ROS_ARGS_EXPLICIT_END_TOKEN: &str = "--";

/// Why the arguments were rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ArgumentsError {
    /// A ROS argument is malformed (rcl `RCL_RET_INVALID_ROS_ARGS`); the message is rcl's.
    #[error("{0}")]
    Invalid(String),
    /// ROS arguments rcl does not know (rclcpp's `UnknownROSArgsError`).
    #[error("found unknown ROS arguments: {}", .0.iter().map(|a| format!("'{a}'")).collect::<Vec<_>>().join(", "))]
    Unknown(Vec<String>),
}

/// What a remapping rule replaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RemapKind {
    /// Topic and service names (`from:=to`).
    TopicOrService,
    /// Topic names only (`rostopic://from:=to`).
    Topic,
    /// Service names only (`rosservice://from:=to`).
    Service,
    /// The node name (`__node:=` / `__name:=`).
    NodeName,
    /// The namespace (`__ns:=`).
    Namespace,
}

/// One `-r` rule.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RemapRule {
    /// What it replaces.
    pub kind: RemapKind,
    /// The node it applies to (`node:` prefix), or every node.
    pub node_name: Option<String>,
    /// The name matched (as written; expanded when applied), for name rules.
    pub from: Option<String>,
    /// The replacement (as written).
    pub to: String,
}

/// A log severity (rcutils).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LogSeverity {
    /// `UNSET` (0).
    Unset = 0,
    /// `DEBUG` (10).
    Debug = 10,
    /// `INFO` (20).
    Info = 20,
    /// `WARN` (30).
    Warn = 30,
    /// `ERROR` (40).
    Error = 40,
    /// `FATAL` (50).
    Fatal = 50,
}

impl LogSeverity {
    /// `rcutils_logging_severity_level_from_string`: case-insensitive name.
    pub fn from_name(s: &str) -> Option<Self> {
        match s.to_ascii_uppercase().as_str() {
            "UNSET" => Some(Self::Unset),
            "DEBUG" => Some(Self::Debug),
            "INFO" => Some(Self::Info),
            "WARN" | "WARNING" => Some(Self::Warn),
            "ERROR" => Some(Self::Error),
            "FATAL" => Some(Self::Fatal),
            _ => None,
        }
    }
}

/// A parameter value given on the command line or in a parameters file, for the nodes whose
/// fully-qualified name matches `node` (`/**` for all).
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterOverride {
    /// Node pattern: `/**`, `/*`, or a fully-qualified name with `*`/`**` wildcards.
    pub node: String,
    /// The parameter name (dotted).
    pub name: String,
    /// The value.
    pub value: ParameterValue,
}

/// Parsed `--ros-args` (rcl's `rcl_arguments_t`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Arguments {
    /// `-r` rules, in order.
    pub remap_rules: Vec<RemapRule>,
    /// `-p` and `--params-file` values, in order (a later one wins).
    pub parameter_overrides: Vec<ParameterOverride>,
    /// `--params-file` paths.
    pub parameter_files: Vec<String>,
    /// `--log-level level`.
    pub default_log_level: Option<LogSeverity>,
    /// `--log-level name:=level`.
    pub logger_levels: Vec<(String, LogSeverity)>,
    /// `-e` / `--enclave`.
    pub enclave: Option<String>,
    /// `--log-config-file`.
    pub log_config_file: Option<String>,
    /// `--log-file-name`.
    pub log_file_name: Option<String>,
    /// `--disable-stdout-logs` (true) / `--enable-stdout-logs` (false).
    pub log_stdout_disabled: Option<bool>,
    /// `--disable-rosout-logs` / `--enable-rosout-logs`.
    pub log_rosout_disabled: Option<bool>,
    /// `--disable-external-lib-logs` / `--enable-external-lib-logs`.
    pub log_ext_lib_disabled: Option<bool>,
    /// Indices of ROS arguments rcl does not know.
    pub unparsed_ros_args: Vec<usize>,
    /// Indices of the arguments that are not ROS arguments (the program's own).
    pub unparsed_args: Vec<usize>,
    /// The argument vector parsed.
    pub argv: Vec<String>,
}

// ---- lexer (rcl `lexer.c`: the lexemes and their numbers, for rcl's messages) ----

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Lexeme {
    None = 0,
    Eof = 1,
    TildeSlash = 2,
    UrlService = 3,
    UrlTopic = 4,
    Colon = 5,
    Node = 6,
    Ns = 7,
    Separator = 8,
    Br = 9,
    Token = 18,
    ForwardSlash = 19,
    WildOne = 20,
    WildMulti = 21,
    Dot = 22,
}

/// The lexeme at the start of `s` and its length.
fn lex(s: &str) -> (Lexeme, usize) {
    let b = s.as_bytes();
    let Some(&c) = b.first() else {
        return (Lexeme::Eof, 0);
    };
    let ident_len = |from: usize| {
        b[from..]
            .iter()
            .take_while(|c| c.is_ascii_alphanumeric() || **c == b'_')
            .count()
    };
    match c {
        b'/' => (Lexeme::ForwardSlash, 1),
        b'.' => (Lexeme::Dot, 1),
        b'~' if b.get(1) == Some(&b'/') => (Lexeme::TildeSlash, 2),
        b'\\' if b.get(1).is_some_and(|d| (b'1'..=b'9').contains(d)) => (Lexeme::Br, 2),
        b'*' if b.get(1) == Some(&b'*') => (Lexeme::WildMulti, 2),
        b'*' => (Lexeme::WildOne, 1),
        b':' if b.get(1) == Some(&b'=') => (Lexeme::Separator, 2),
        b':' => (Lexeme::Colon, 1),
        c if c.is_ascii_alphabetic() || c == b'_' => {
            if s.starts_with("rostopic://") {
                return (Lexeme::UrlTopic, 11);
            }
            if s.starts_with("rosservice://") {
                return (Lexeme::UrlService, 13);
            }
            let n = ident_len(0);
            match &s[..n] {
                "__node" | "__name" => (Lexeme::Node, n),
                "__ns" => (Lexeme::Ns, n),
                _ => (Lexeme::Token, n),
            }
        }
        _ => (Lexeme::None, 0),
    }
}

/// rcl's `rcl_lexer_lookahead2_t`, enough of it.
struct Lookahead<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Lookahead<'a> {
    fn new(text: &'a str) -> Self {
        Self { text, pos: 0 }
    }
    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }
    fn peek(&self) -> Lexeme {
        lex(self.rest()).0
    }
    fn peek2(&self) -> (Lexeme, Lexeme) {
        let (l1, n1) = lex(self.rest());
        if matches!(l1, Lexeme::Eof | Lexeme::None) {
            return (l1, l1);
        }
        (l1, lex(&self.text[self.pos + n1..]).0)
    }
    fn accept(&mut self) -> &'a str {
        let (_, n) = lex(self.rest());
        let t = &self.text[self.pos..self.pos + n];
        self.pos += n;
        t
    }
    /// `rcl_lexer_lookahead2_expect`, with its message.
    fn expect(&mut self, want: Lexeme) -> Result<&'a str, String> {
        let got = self.peek();
        if got == want {
            Ok(self.accept())
        } else {
            Err(format!(
                "Expected lexeme type {}, got {} at index {}",
                want as u8, got as u8, self.pos
            ))
        }
    }
}

// ---- remap rules (rcl `arguments.c` `_rcl_parse_remap_*`) ----

fn parse_match_token(lx: &mut Lookahead<'_>) -> Result<(), String> {
    match lx.peek() {
        Lexeme::Token => {
            lx.accept();
            Ok(())
        }
        Lexeme::WildOne => Err("Wildcard '*' is not implemented".to_owned()),
        Lexeme::WildMulti => Err("Wildcard '**' is not implemented".to_owned()),
        _ => Err("Expecting token or wildcard".to_owned()),
    }
}

fn parse_resource_match(lx: &mut Lookahead<'_>) -> Result<String, String> {
    let start = lx.pos;
    if matches!(lx.peek(), Lexeme::TildeSlash | Lexeme::ForwardSlash) {
        lx.accept();
    }
    parse_match_token(lx)?;
    while lx.peek() != Lexeme::Separator {
        lx.expect(Lexeme::ForwardSlash)?;
        parse_match_token(lx)?;
    }
    Ok(lx.text[start..lx.pos].to_owned())
}

fn parse_replacement_token(lx: &mut Lookahead<'_>) -> Result<(), String> {
    match lx.peek() {
        Lexeme::Br => Err("Backreferences are not implemented".to_owned()),
        Lexeme::Token => {
            lx.accept();
            Ok(())
        }
        got => Err(format!(
            "Expected lexeme type {}, got {} at index {}",
            Lexeme::Token as u8,
            got as u8,
            lx.pos
        )),
    }
}

fn parse_replacement_name(lx: &mut Lookahead<'_>) -> Result<String, String> {
    let start = lx.pos;
    if matches!(lx.peek(), Lexeme::TildeSlash | Lexeme::ForwardSlash) {
        lx.accept();
    }
    parse_replacement_token(lx)?;
    while lx.peek() != Lexeme::Eof {
        lx.expect(Lexeme::ForwardSlash)?;
        parse_replacement_token(lx)?;
    }
    Ok(lx.text[start..lx.pos].to_owned())
}

/// Parses one remap rule (`_rcl_parse_remap_rule`).
pub(crate) fn parse_remap_rule(arg: &str) -> Result<RemapRule, String> {
    let mut lx = Lookahead::new(arg);
    let mut node_name = None;
    if lx.peek2() == (Lexeme::Token, Lexeme::Colon) {
        node_name = Some(lx.accept().to_owned());
        lx.accept();
    }
    let rule = match lx.peek() {
        Lexeme::Node => {
            lx.accept();
            lx.expect(Lexeme::Separator)?;
            let rest = lx.rest();
            let name = lx.expect(Lexeme::Token).inspect_err(|_| {
                tracing::warn!("Node name not remapped to invalid name: '{rest}'");
            })?;
            RemapRule {
                kind: RemapKind::NodeName,
                node_name,
                from: None,
                to: name.to_owned(),
            }
        }
        Lexeme::Ns => {
            lx.accept();
            lx.expect(Lexeme::Separator)?;
            let start = lx.pos;
            let rest = lx.rest();
            lx.expect(Lexeme::ForwardSlash).inspect_err(|_| {
                tracing::warn!("Namespace not remapped to a fully qualified name (found: {rest})");
            })?;
            loop {
                if lx.peek() != Lexeme::Token {
                    break;
                }
                lx.accept();
                if lx.peek() != Lexeme::ForwardSlash {
                    break;
                }
                lx.accept();
            }
            if lx.peek() != Lexeme::Eof {
                tracing::warn!(
                    "Namespace not remapped to a fully qualified name (found: {})",
                    &arg[start..]
                );
            }
            RemapRule {
                kind: RemapKind::Namespace,
                node_name,
                from: None,
                to: lx.text[start..lx.pos].to_owned(),
            }
        }
        _ => {
            let kind = match lx.peek() {
                Lexeme::UrlService => {
                    lx.accept();
                    RemapKind::Service
                }
                Lexeme::UrlTopic => {
                    lx.accept();
                    RemapKind::Topic
                }
                _ => RemapKind::TopicOrService,
            };
            let from = parse_resource_match(&mut lx)?;
            lx.expect(Lexeme::Separator)?;
            let to = parse_replacement_name(&mut lx)?;
            RemapRule {
                kind,
                node_name,
                from: Some(from),
                to,
            }
        }
    };
    lx.expect(Lexeme::Eof)?;
    Ok(rule)
}

// ---- parameters (`_rcl_parse_param_rule`, rcl_yaml_param_parser) ----

fn parse_param_name(lx: &mut Lookahead<'_>) -> Result<String, String> {
    // `_rcl_parse_param_name_token`: one or more tokens and slashes.
    fn token(lx: &mut Lookahead<'_>) -> Result<(), String> {
        match lx.peek() {
            Lexeme::Token | Lexeme::ForwardSlash => {}
            Lexeme::WildOne => return Err("Wildcard '*' is not implemented".to_owned()),
            Lexeme::WildMulti => return Err("Wildcard '**' is not implemented".to_owned()),
            _ => return Err("Expecting token or wildcard".to_owned()),
        }
        while matches!(lx.peek(), Lexeme::Token | Lexeme::ForwardSlash) {
            lx.accept();
        }
        Ok(())
    }
    let start = lx.pos;
    token(lx)?;
    while lx.peek() != Lexeme::Separator {
        lx.expect(Lexeme::Dot)?;
        token(lx)?;
    }
    Ok(lx.text[start..lx.pos].to_owned())
}

/// Parses one `-p` rule: `[node:]name:=yaml`.
pub(crate) fn parse_param_rule(arg: &str) -> Result<ParameterOverride, String> {
    let mut lx = Lookahead::new(arg);
    let node = if lx.peek2() == (Lexeme::Token, Lexeme::Colon) {
        let n = lx.accept().to_owned();
        lx.accept();
        format!("/{n}")
    } else {
        "/**".to_owned()
    };
    let name = parse_param_name(&mut lx)?;
    lx.expect(Lexeme::Separator)?;
    let value = yaml::parse_value(lx.rest()).map_err(|e| {
        format!(
            "Failed to parse value '{}' of parameter '{name}': {e}",
            lx.rest()
        )
    })?;
    Ok(ParameterOverride { node, name, value })
}

mod yaml {
    //! YAML values as rcl_yaml_param_parser types them (`parse.c` `get_value`): plain scalars
    //! are bool (YAML 1.1 words), then integer, then double, else string; quoted scalars are
    //! strings; a sequence holds values of one type.

    use super::{ParameterType, ParameterValue};
    use yaml_rust2::parser::{Event, Parser};
    use yaml_rust2::scanner::TScalarStyle;

    /// A YAML node with the scalar styles kept.
    #[derive(Debug)]
    pub(super) enum Node {
        Scalar(String, bool),
        Seq(Vec<Node>),
        Map(Vec<(String, Node)>),
    }

    pub(super) fn parse(text: &str) -> Result<Option<Node>, String> {
        let mut parser = Parser::new_from_str(text);
        let mut stack: Vec<(Node, Option<String>)> = Vec::new();
        let mut root = None;
        loop {
            let (event, _) = parser.next_token().map_err(|e| e.to_string())?;
            let finished = match event {
                Event::StreamEnd => break,
                Event::Scalar(value, style, _, _) => {
                    Some(Node::Scalar(value, style != TScalarStyle::Plain))
                }
                Event::SequenceStart(..) => {
                    stack.push((Node::Seq(Vec::new()), None));
                    None
                }
                Event::MappingStart(..) => {
                    stack.push((Node::Map(Vec::new()), None));
                    None
                }
                Event::SequenceEnd | Event::MappingEnd => stack.pop().map(|(n, _)| n),
                Event::Alias(_) => return Err("aliases are not supported".to_owned()),
                _ => None,
            };
            let Some(node) = finished else { continue };
            match stack.last_mut() {
                None => root = Some(node),
                Some((Node::Seq(items), _)) => items.push(node),
                Some((Node::Map(entries), key)) => match key.take() {
                    None => match node {
                        Node::Scalar(k, _) => *key = Some(k),
                        _ => return Err("a map key must be a scalar".to_owned()),
                    },
                    Some(k) => entries.push((k, node)),
                },
                Some((Node::Scalar(..), _)) => {}
            }
        }
        Ok(root)
    }

    enum Scalar {
        Bool(bool),
        Int(i64),
        Double(f64),
        Str(String),
    }

    fn scalar(value: &str, quoted: bool) -> Scalar {
        if quoted {
            return Scalar::Str(value.to_owned());
        }
        match value {
            "Y" | "y" | "yes" | "Yes" | "YES" | "true" | "True" | "TRUE" | "on" | "On" | "ON" => {
                return Scalar::Bool(true)
            }
            "N" | "n" | "no" | "No" | "NO" | "false" | "False" | "FALSE" | "off" | "Off"
            | "OFF" => return Scalar::Bool(false),
            _ => {}
        }
        if let Ok(i) = value.parse::<i64>() {
            return Scalar::Int(i);
        }
        match value {
            ".nan" | ".NaN" | ".NAN" => return Scalar::Double(f64::NAN),
            ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => {
                return Scalar::Double(f64::INFINITY)
            }
            "-.inf" | "-.Inf" | "-.INF" => return Scalar::Double(f64::NEG_INFINITY),
            _ => {}
        }
        if let Ok(d) = value.parse::<f64>() {
            if !value.eq_ignore_ascii_case("nan") && !value.to_ascii_lowercase().contains("inf") {
                return Scalar::Double(d);
            }
        }
        Scalar::Str(value.to_owned())
    }

    pub(super) fn value_of(node: &Node) -> Result<ParameterValue, String> {
        let mut v = ParameterValue::default();
        match node {
            Node::Scalar(s, quoted) => {
                if s.is_empty() && !quoted {
                    return Err("no value".to_owned());
                }
                match scalar(s, *quoted) {
                    Scalar::Bool(b) => {
                        v.r#type = ParameterType::PARAMETER_BOOL;
                        v.bool_value = b;
                    }
                    Scalar::Int(i) => {
                        v.r#type = ParameterType::PARAMETER_INTEGER;
                        v.integer_value = i;
                    }
                    Scalar::Double(d) => {
                        v.r#type = ParameterType::PARAMETER_DOUBLE;
                        v.double_value = d;
                    }
                    Scalar::Str(s) => {
                        v.r#type = ParameterType::PARAMETER_STRING;
                        v.string_value = s;
                    }
                }
            }
            Node::Seq(items) => {
                let mut kind = None;
                for item in items {
                    let Node::Scalar(s, quoted) = item else {
                        return Err("Sequences can only contain scalars".to_owned());
                    };
                    let sc = scalar(s, *quoted);
                    let k = match &sc {
                        Scalar::Bool(_) => 0,
                        Scalar::Int(_) => 1,
                        Scalar::Double(_) => 2,
                        Scalar::Str(_) => 3,
                    };
                    if kind.is_some_and(|prev| prev != k) {
                        return Err("Sequence should be of same type".to_owned());
                    }
                    kind = Some(k);
                    match sc {
                        Scalar::Bool(b) => v.bool_array_value.push(b),
                        Scalar::Int(i) => v.integer_array_value.push(i),
                        Scalar::Double(d) => v.double_array_value.push(d),
                        Scalar::Str(s) => v.string_array_value.push(s),
                    }
                }
                v.r#type = match kind {
                    Some(0) => ParameterType::PARAMETER_BOOL_ARRAY,
                    Some(1) => ParameterType::PARAMETER_INTEGER_ARRAY,
                    Some(2) => ParameterType::PARAMETER_DOUBLE_ARRAY,
                    Some(_) => ParameterType::PARAMETER_STRING_ARRAY,
                    None => return Err("an empty sequence has no type".to_owned()),
                };
            }
            Node::Map(_) => return Err("a map is not a parameter value".to_owned()),
        }
        Ok(v)
    }

    pub(super) fn parse_value(text: &str) -> Result<ParameterValue, String> {
        match parse(text)? {
            Some(node) => value_of(&node),
            None => Err("no value".to_owned()),
        }
    }
}

/// Reads a parameters file (`rcl_parse_yaml_file`): `<node pattern>: {ros__parameters: {…}}`,
/// node patterns nested as namespaces, nested maps as dotted names.
pub(crate) fn parse_params_file(path: &str) -> Result<Vec<ParameterOverride>, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("Error opening YAML file: {e}"))?;
    parse_params_yaml(&text)
}

/// Parses the contents of a parameters file.
pub(crate) fn parse_params_yaml(text: &str) -> Result<Vec<ParameterOverride>, String> {
    let Some(root) = yaml::parse(text)? else {
        return Ok(Vec::new());
    };
    let yaml::Node::Map(entries) = root else {
        return Err("the top level of a parameters file must be a map".to_owned());
    };
    let mut out = Vec::new();
    fn node_level(
        prefix: &str,
        entries: &[(String, yaml::Node)],
        out: &mut Vec<ParameterOverride>,
    ) -> Result<(), String> {
        for (key, value) in entries {
            let yaml::Node::Map(inner) = value else {
                return Err(format!("'{key}': a node or namespace must be a map"));
            };
            let key = key.trim_matches('/');
            let name = if prefix.is_empty() {
                format!("/{key}")
            } else {
                format!("{prefix}/{key}")
            };
            if let Some((_, params)) = inner.iter().find(|(k, _)| k == "ros__parameters") {
                let yaml::Node::Map(params) = params else {
                    return Err(format!("'{name}': ros__parameters must be a map"));
                };
                param_level(&name, "", params, out)?;
            } else {
                node_level(&name, inner, out)?;
            }
        }
        Ok(())
    }
    fn param_level(
        node: &str,
        prefix: &str,
        entries: &[(String, yaml::Node)],
        out: &mut Vec<ParameterOverride>,
    ) -> Result<(), String> {
        for (key, value) in entries {
            let name = if prefix.is_empty() {
                key.clone()
            } else {
                format!("{prefix}.{key}")
            };
            match value {
                yaml::Node::Map(inner) => param_level(node, &name, inner, out)?,
                other => out.push(ParameterOverride {
                    node: node.to_owned(),
                    value: yaml::value_of(other).map_err(|e| format!("'{name}': {e}"))?,
                    name,
                }),
            }
        }
        Ok(())
    }
    node_level("", &entries, &mut out)?;
    Ok(out)
}

/// `--log-level`: `level` or `name:=level`.
fn parse_log_level(arg: &str, out: &mut Arguments) -> Result<(), String> {
    if let Some((name, level)) = arg.split_once(":=") {
        if name.is_empty() {
            return Err("Argument has an invalid logger item that name is empty".to_owned());
        }
        let level = LogSeverity::from_name(level)
            .ok_or_else(|| "Argument does not use a valid severity level".to_owned())?;
        out.logger_levels.push((name.to_owned(), level));
    } else {
        let level = LogSeverity::from_name(arg)
            .ok_or_else(|| "Argument does not use a valid severity level".to_owned())?;
        out.default_log_level = Some(level);
    }
    Ok(())
}

/// `--enable-X` / `--disable-X`.
fn parse_disabling_flag(arg: &str, key: &str) -> Option<bool> {
    if arg.strip_prefix("--enable-") == Some(key) {
        Some(false)
    } else if arg.strip_prefix("--disable-") == Some(key) {
        Some(true)
    } else {
        None
    }
}

impl Arguments {
    /// Parses `argv` (program name included, as rcl's `argv`) as `rcl_parse_arguments` does.
    pub fn parse<S: AsRef<str>>(argv: &[S]) -> Result<Self, ArgumentsError> {
        let argv: Vec<String> = argv.iter().map(|a| a.as_ref().to_owned()).collect();
        let mut out = Arguments::default();
        let mut ros = false;
        let mut i = 0;
        let invalid = |m: String| ArgumentsError::Invalid(m);
        while i < argv.len() {
            let arg = argv[i].as_str();
            if !ros {
                if arg == ROS_ARGS_FLAG {
                    ros = true;
                } else if let Ok(rule) = parse_remap_rule(arg) {
                    // The deprecated form (a bare `from:=to` outside --ros-args).
                    tracing::warn!(
                        "Found remap rule '{arg}'. This syntax is deprecated. Use '--ros-args --remap {arg}' instead."
                    );
                    out.remap_rules.push(rule);
                } else {
                    out.unparsed_args.push(i);
                }
                i += 1;
                continue;
            }
            if arg == ROS_ARGS_FLAG {
                i += 1;
                continue;
            }
            if arg == ROS_ARGS_EXPLICIT_END_TOKEN {
                ros = false;
                i += 1;
                continue;
            }
            let next = argv.get(i + 1).map(String::as_str);
            match arg {
                "--param" | "-p" => {
                    let Some(rule) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No parameter override rule found."
                        )));
                    };
                    let p = parse_param_rule(rule).map_err(|e| {
                        invalid(format!(
                            "Couldn't parse parameter override rule: '{arg} {rule}'. Error: {e}"
                        ))
                    })?;
                    out.parameter_overrides.push(p);
                    i += 2;
                }
                "--remap" | "-r" => {
                    let Some(rule) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No remap rule found."
                        )));
                    };
                    let r = parse_remap_rule(rule).map_err(|e| {
                        invalid(format!(
                            "Couldn't parse remap rule: '{arg} {rule}'. Error: {e}"
                        ))
                    })?;
                    out.remap_rules.push(r);
                    i += 2;
                }
                "--params-file" => {
                    let Some(file) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No file path provided."
                        )));
                    };
                    let params = parse_params_file(file).map_err(|e| {
                        invalid(format!(
                            "Couldn't parse params file: '{arg} {file}'. Error: {e}"
                        ))
                    })?;
                    out.parameter_overrides.extend(params);
                    out.parameter_files.push(file.to_owned());
                    i += 2;
                }
                "--log-level" => {
                    let Some(level) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing log level flag: '{arg}'. No log level provided."
                        )));
                    };
                    parse_log_level(level, &mut out).map_err(|e| {
                        invalid(format!(
                            "Couldn't parse log level: '{arg} {level}'. Error: {e}"
                        ))
                    })?;
                    i += 2;
                }
                "--log-file-name" => {
                    let Some(name) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No string prefix provided."
                        )));
                    };
                    out.log_file_name = Some(name.to_owned());
                    i += 2;
                }
                "--log-config-file" => {
                    let Some(file) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No file path provided."
                        )));
                    };
                    out.log_config_file = Some(file.to_owned());
                    i += 2;
                }
                "--enclave" | "-e" => {
                    let Some(enclave) = next else {
                        return Err(invalid(format!(
                            "Couldn't parse trailing {arg} flag. No enclave path provided."
                        )));
                    };
                    out.enclave = Some(enclave.to_owned());
                    i += 2;
                }
                _ => {
                    if let Some(v) = parse_disabling_flag(arg, "stdout-logs") {
                        out.log_stdout_disabled = Some(v);
                    } else if let Some(v) = parse_disabling_flag(arg, "rosout-logs") {
                        out.log_rosout_disabled = Some(v);
                    } else if let Some(v) = parse_disabling_flag(arg, "external-lib-logs") {
                        out.log_ext_lib_disabled = Some(v);
                    } else {
                        out.unparsed_ros_args.push(i);
                    }
                    i += 1;
                }
            }
        }
        out.argv = argv;
        Ok(out)
    }

    /// Parses and, as `rclcpp::init` does, rejects ROS arguments rcl does not know.
    pub fn parse_strict<S: AsRef<str>>(argv: &[S]) -> Result<Self, ArgumentsError> {
        let parsed = Self::parse(argv)?;
        if !parsed.unparsed_ros_args.is_empty() {
            return Err(ArgumentsError::Unknown(
                parsed
                    .unparsed_ros_args
                    .iter()
                    .map(|&i| parsed.argv[i].clone())
                    .collect(),
            ));
        }
        Ok(parsed)
    }

    /// The process's arguments (`std::env::args`), strictly parsed.
    pub fn from_process() -> Result<Self, ArgumentsError> {
        let argv: Vec<String> = std::env::args().collect();
        Self::parse_strict(&argv)
    }

    /// The arguments that are not ROS arguments (`rcl_remove_ros_arguments`), program name
    /// first.
    pub fn non_ros_args(&self) -> Vec<String> {
        self.unparsed_args
            .iter()
            .map(|&i| self.argv[i].clone())
            .collect()
    }

    fn first_rule(
        &self,
        node_name: &str,
        accept: impl Fn(&RemapRule) -> bool,
    ) -> Option<&RemapRule> {
        self.remap_rules
            .iter()
            .find(|r| accept(r) && r.node_name.as_deref().is_none_or(|n| n == node_name))
    }

    /// The node's name after `__node:=` rules (`rcl_remap_node_name`; `original` is the name
    /// the program gave).
    pub fn remap_node_name(&self, original: &str) -> Option<&str> {
        self.first_rule(original, |r| r.kind == RemapKind::NodeName)
            .map(|r| r.to.as_str())
    }

    /// The node's namespace after `__ns:=` rules (`rcl_remap_node_namespace`).
    pub fn remap_namespace(&self, original_node_name: &str) -> Option<&str> {
        self.first_rule(original_node_name, |r| r.kind == RemapKind::Namespace)
            .map(|r| r.to.as_str())
    }

    fn remap_name(
        &self,
        expanded: &str,
        node: &NodeName,
        namespace: &Namespace,
        service: bool,
    ) -> Option<String> {
        self.remap_rules
            .iter()
            .filter(|r| match r.kind {
                RemapKind::TopicOrService => true,
                RemapKind::Topic => !service,
                RemapKind::Service => service,
                _ => false,
            })
            .filter(|r| r.node_name.as_deref().is_none_or(|n| n == node.as_str()))
            .find_map(|r| {
                let from = r.from.as_deref()?;
                let m = TopicName::expand(from, node, namespace).ok()?;
                if m.as_str() != expanded {
                    return None;
                }
                TopicName::expand(&r.to, node, namespace)
                    .ok()
                    .map(|t| t.as_str().to_owned())
            })
    }

    /// A topic's name after the `-r` rules (`rcl_remap_topic_name`): `expanded` is the
    /// fully-qualified name; rules are expanded for `node` in `namespace`; the first match wins.
    pub fn remap_topic(
        &self,
        expanded: &str,
        node: &NodeName,
        namespace: &Namespace,
    ) -> Option<String> {
        self.remap_name(expanded, node, namespace, false)
    }

    /// A service's name after the `-r` rules (`rcl_remap_service_name`).
    pub fn remap_service(
        &self,
        expanded: &str,
        node: &NodeName,
        namespace: &Namespace,
    ) -> Option<String> {
        self.remap_name(expanded, node, namespace, true)
    }

    /// The parameter values for the node `fully_qualified_name`, in order (later wins), as
    /// rclcpp's `resolve_parameter_overrides` picks them (`/**`, `/*` in the node's namespace,
    /// exact name, wildcards).
    pub fn parameters_for(&self, fully_qualified_name: &str) -> Vec<(String, ParameterValue)> {
        self.parameter_overrides
            .iter()
            .filter(|p| node_pattern_matches(&p.node, fully_qualified_name))
            .map(|p| (p.name.clone(), p.value.clone()))
            .collect()
    }

    /// The log level of logger `name`: its own `--log-level name:=level`, else the default one.
    pub fn log_level_for(&self, logger: &str) -> Option<LogSeverity> {
        self.logger_levels
            .iter()
            .rev()
            .find(|(n, _)| n == logger)
            .map(|(_, l)| *l)
            .or(self.default_log_level)
    }
}

/// Whether a node pattern of a parameters file (`/**`, `/ns/*`, `/ns/node`) matches a node.
fn node_pattern_matches(pattern: &str, fqn: &str) -> bool {
    fn go(p: &[&str], n: &[&str]) -> bool {
        match (p.first(), n.first()) {
            (None, None) => true,
            (Some(&"**"), _) => go(&p[1..], n) || (!n.is_empty() && go(p, &n[1..])),
            (Some(&"*"), Some(_)) => go(&p[1..], &n[1..]),
            (Some(a), Some(b)) if a == b => go(&p[1..], &n[1..]),
            _ => false,
        }
    }
    let p: Vec<&str> = pattern.trim_start_matches('/').split('/').collect();
    let n: Vec<&str> = fqn.trim_start_matches('/').split('/').collect();
    go(&p, &n)
}

#[cfg(test)]
mod tests;
