//! What `topic echo | hz | bw | delay` share: the topic's type as ros2topic finds it
//! (`api/__init__.py` `get_msg_class`), the type's description (compiled in, else an interface
//! file on `AMENT_PREFIX_PATH`, else the `~/get_type_description` of a node that publishes or
//! subscribes to it), the publishers' QoS (for echo's `choose_qos`, [`super::qos`]), and a raw
//! reader of the topic.

use std::time::Duration;

use horus_ros_graph::GraphCache;
use horus_ros_msgs::{dds_type_name, TypeHash};
use horus_ros_rmw::names::TopicName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{RawEndpointSpec, RawReader, RawSample};

pub use super::message_type::MessageType;
use crate::dynamic::{cdr, Container, Elem, FieldTy, Schema, Value};
use crate::session::Session;
use crate::CliError;

/// Longest wait for a node's answer when a type is read off the graph.
pub const DESCRIBE_TIMEOUT: Duration = Duration::from_secs(5);

/// A topic name as given, expanded for the CLI's node (rclpy `expand_topic_name` +
/// `validate_full_topic_name`, whose errors ros2cli raises as they are).
pub fn expand(session: &Session, given: &str) -> Result<TopicName, CliError> {
    TopicName::expand(given, session.node.name(), session.node.namespace())
        .map_err(|e| CliError::new(e.to_string()))
}

/// ros2topic `_get_msg_class` on the graph: the one type of the topic named `topic` (hidden
/// topics included); `None` when the graph has no such topic.
pub fn graph_type(
    session: &Session,
    given: &str,
    topic: &TopicName,
) -> Result<Option<String>, CliError> {
    session.graph.read(|c| graph_type_in(c, given, topic))
}

/// [`graph_type`] in a graph.
pub fn graph_type_in(
    c: &GraphCache,
    given: &str,
    topic: &TopicName,
) -> Result<Option<String>, CliError> {
    let types = c.topic_names_and_types(true);
    let Some(t) = types.get(topic.as_str()) else {
        return Ok(None);
    };
    let t: Vec<&String> = t.iter().collect();
    match t.as_slice() {
        [] => Ok(None),
        [one] => Ok(Some((*one).clone())),
        _ => Err(CliError::new(format!(
            "Cannot echo topic '{given}', as it contains more than one type: [{}]",
            t.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// The daemon's graph, as ros2topic's `NodeStrategy` reads it to look a topic up (the daemon
/// started when none runs); `None` with `--no-daemon`, or when no daemon could be used.
pub fn daemon_graph(global: &crate::Global) -> Option<GraphCache> {
    if global.no_daemon {
        return None;
    }
    crate::daemon::client::graph_or_spawn(global).map(|answer| answer.cache)
}

/// ros2topic `get_msg_class(…, blocking=True)`: the topic's type, printing ros2cli's warning
/// once and looking again at every graph change while the topic is not there (ros2cli looks
/// every 0.1 s).
pub fn wait_for_type(
    session: &Session,
    given: &str,
    topic: &TopicName,
) -> Result<String, CliError> {
    if let Some(t) = graph_type(session, given, topic)? {
        return Ok(t);
    }
    println!("WARNING: topic [{given}] does not appear to be published yet");
    loop {
        let seen = session.graph.generation();
        if let Some(t) = graph_type(session, given, topic)? {
            return Ok(t);
        }
        session
            .graph
            .wait_for_graph_change_since(seen, Duration::from_secs(3600));
    }
}

/// The QoS profiles of the topic's publishers.
pub fn publisher_qos(session: &Session, topic: &TopicName) -> Vec<Qos> {
    session.graph.read(|c| publisher_qos_in(c, topic))
}

/// [`publisher_qos`] in a graph.
pub fn publisher_qos_in(c: &GraphCache, topic: &TopicName) -> Vec<Qos> {
    c.publishers_info_by_topic(topic.as_str(), false)
        .into_iter()
        .map(|p| p.qos_profile)
        .collect()
}

/// The hash the topic's endpoints announce for `type_name` (zero when none does): what a reader
/// that does not resolve the type announces.
pub fn announced_hash(session: &Session, topic: &TopicName, type_name: &str) -> TypeHash {
    session.graph.read(|c| {
        c.publishers_info_by_topic(topic.as_str(), false)
            .into_iter()
            .chain(c.subscriptions_info_by_topic(topic.as_str(), false))
            .find(|e| e.topic_type == type_name && e.topic_type_hash.is_set())
            .map_or(TypeHash::ZERO, |e| e.topic_type_hash)
    })
}

/// Whether a node of the graph publishes or subscribes to `type_name` announcing its hash: one
/// whose `~/get_type_description` could describe it.
pub fn type_in_graph(session: &Session, type_name: &str) -> bool {
    session.graph.read(|c| {
        c.topic_names_and_types(true)
            .into_iter()
            .filter(|(_, types)| types.iter().any(|t| t == type_name))
            .any(|(topic, _)| {
                c.publishers_info_by_topic(&topic, false)
                    .into_iter()
                    .chain(c.subscriptions_info_by_topic(&topic, false))
                    .any(|e| e.topic_type == type_name && e.topic_type_hash.is_set())
            })
    })
}

/// The message type `type_name` ([`MessageType`]: compiled in, else its interface file on
/// `AMENT_PREFIX_PATH`, else from a node that publishes or subscribes to it). When none of them
/// has it — where ros2cli cannot import it — the error is ros2cli's `invalid` (`The passed
/// message type is invalid` for a type given, `The message type '…' is invalid` for the
/// topic's), the reasons logged at debug level; when a node has it but cannot describe it, the
/// error says why, naming the nodes asked.
pub fn resolve_type(
    session: &Session,
    type_name: &str,
    invalid: &str,
) -> Result<MessageType, CliError> {
    let failed = |why: String| {
        CliError::new(format!(
            "Could not load the type '{type_name}' of the passed topic: {why}"
        ))
    };
    let unusable = |e: String| failed(format!("its description is not usable: {e}"));
    match MessageType::installed(type_name, unusable)? {
        Ok(t) => Ok(t),
        Err(file_error) if !type_in_graph(session, type_name) => {
            tracing::debug!(
                type_name,
                "not compiled in, not on AMENT_PREFIX_PATH ({file_error}), no node uses it"
            );
            Err(CliError::new(invalid))
        }
        Err(file_error) => MessageType::from_graph(
            session,
            type_name,
            DESCRIBE_TIMEOUT,
            |node_error| {
                failed(format!(
                    "not compiled in, not on AMENT_PREFIX_PATH ({file_error}), and not \
                     described by the graph: {node_error}"
                ))
            },
            unusable,
        ),
    }
}

/// ros2cli's end on Ctrl-C: `ros2cli.cli.main` catches the `KeyboardInterrupt` and exits with
/// status `signal.SIGINT` (2), printing nothing. A stream verb (`echo`, `hz`, `bw`, `delay`)
/// keeps one while it reads: SIGINT wakes its reader, and [`Interrupt::check`] ends the loop.
pub struct Interrupt {
    came: std::sync::Arc<std::sync::atomic::AtomicBool>,
    _hook: Option<horus_ros_rmw::signal_handler::SignalHook>,
}

impl Interrupt {
    /// Watches for SIGINT, waking `reader` when it comes.
    pub fn watch(reader: &RawReader) -> Self {
        use horus_ros_rmw::signal_handler::{on_signal, ShutdownSignal};
        let came = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let waker = reader.waker();
        let flag = std::sync::Arc::clone(&came);
        let hook = on_signal(&[ShutdownSignal::Interrupt], move |_| {
            flag.store(true, std::sync::atomic::Ordering::SeqCst);
            waker.wake();
        })
        .map_err(|e| tracing::debug!("no SIGINT hook: {e}"))
        .ok();
        Self { came, _hook: hook }
    }

    /// `Err` (exit status 2, no message) once SIGINT came.
    pub fn check(&self) -> Result<(), CliError> {
        if self.came.load(std::sync::atomic::Ordering::SeqCst) {
            Err(CliError {
                message: String::new(),
                code: 2,
            })
        } else {
            Ok(())
        }
    }
}

/// rclpy's default incompatible-QoS callback of a subscription (`event_handler.py`): one rcl
/// log line on stderr per publisher of the topic whose QoS cannot match the reader's, naming the
/// policy the DDS reports last (Fast DDS: the highest policy id that fails; Cyclone DDS: the
/// first it checks). Zenoh matches no QoS: nothing is printed there.
pub fn warn_incompatible_publishers(session: &Session, topic: &TopicName, reader_qos: &Qos) {
    use horus_ros_rmw::backend::Backend;
    let backend = session.context.backend();
    if backend == Some(Backend::Zenoh) {
        return;
    }
    for publisher in publisher_qos(session, topic) {
        let failing = horus_ros_rmw::qos::incompatible_policies(&publisher, reader_qos);
        let last = if backend == Some(Backend::Cyclone) {
            failing.first()
        } else {
            failing.iter().max_by_key(|(id, _)| *id)
        };
        if let Some((_, policy)) = last {
            eprintln!(
                "{}New publisher discovered on topic '{}', offering incompatible QoS. No \
                 messages will be received from it. Last incompatible policy: {policy}",
                rcl_log_prefix("WARN", session),
                topic.as_str()
            );
        }
    }
}

/// The start of an rcl log line of the CLI's node (rcutils' default console format:
/// `[SEVERITY] [seconds.nanoseconds] [logger]: `).
pub fn rcl_log_prefix(severity: &str, session: &Session) -> String {
    let now = now_ns();
    format!(
        "[{severity}] [{}.{:09}] [{}]: ",
        now / 1_000_000_000,
        now % 1_000_000_000,
        session.node.name()
    )
}

/// A raw reader of `topic` with type `type_name` (announced with `hash`) and `qos`.
pub fn subscribe(
    session: &Session,
    topic: &TopicName,
    type_name: &str,
    hash: TypeHash,
    qos: Qos,
) -> Result<RawReader, CliError> {
    let spec = RawEndpointSpec {
        dds_topic_name: topic.to_dds_topic_name(false),
        dds_type_name: dds_type_name(type_name),
        type_hash: hash,
        qos,
        service_id: None,
    };
    Ok(session.node.create_raw_reader(&spec)?)
}

/// The samples `reader` holds now, in order; one the DDS layer could not hand over is logged and
/// skipped.
pub fn drain(reader: &mut RawReader) -> impl Iterator<Item = RawSample> + '_ {
    std::iter::from_fn(move || loop {
        match reader.take() {
            Ok(sample) => return sample,
            Err(e) => tracing::warn!("dropped a message: {e}"),
        }
    })
}

/// `sample` decoded as `type_name` of `schema`; one that does not decode is logged and `None`.
pub fn decode(schema: &Schema, type_name: &str, sample: &RawSample) -> Option<Value> {
    cdr::decode(schema, type_name, &sample.body, sample.big_endian)
        .map_err(|e| tracing::warn!("could not decode a message: {e}"))
        .ok()
}

/// Nanoseconds since the epoch (what rclpy's ROS clock reads when no `/clock` drives it).
pub use horus_ros_rmw::unix_time_ns as now_ns;

/// A value inside a message, with its type: a whole message, or a field's value.
#[derive(Clone, Copy)]
pub enum Part<'a> {
    /// A message of type `.0`.
    Message(&'a str, &'a Value),
    /// A field of type `.0` (a single value, array or sequence).
    Field(&'a FieldTy, &'a Value),
    /// One element of an array or sequence field.
    Elem(&'a Elem, &'a Value),
}

impl<'a> Part<'a> {
    /// `getattr(part, name)` on a message part, or Python's `AttributeError` message.
    pub fn attr(self, schema: &'a Schema, name: &str) -> Result<Part<'a>, String> {
        if let Part::Message(t, Value::Struct(fields)) = self {
            if let Ok(s) = schema.get(t) {
                if let Some((m, v)) = s
                    .members
                    .iter()
                    .zip(fields)
                    .find(|(m, _)| m.name == name && !s.is_empty_placeholder())
                {
                    return Ok(match (&m.ty.container, &m.ty.elem) {
                        (Container::Single, Elem::Nested(n)) => Part::Message(n, v),
                        _ => Part::Field(&m.ty, v),
                    });
                }
            }
        }
        Err(format!(
            "'{}' object has no attribute '{name}'",
            self.python_type()
        ))
    }

    /// `part[index]` on a list (negative counts from the end), or `None`.
    pub fn index(self, index: i64) -> Option<Part<'a>> {
        let (elem, items) = match self {
            Part::Field(ty, Value::List(items)) => (&ty.elem, items),
            _ => return None,
        };
        let len = i64::try_from(items.len()).ok()?;
        let i = if index < 0 { len + index } else { index };
        let item = items.get(usize::try_from(i).ok()?)?;
        Some(match elem {
            Elem::Nested(n) => Part::Message(n, item),
            e => Part::Elem(e, item),
        })
    }

    /// The name of the Python type rclpy gives this value (for error messages).
    pub fn python_type(self) -> String {
        match self {
            Part::Message(t, _) => t.rsplit('/').next().unwrap_or(t).to_owned(),
            Part::Field(ty, v) => match (ty.container, v) {
                (Container::Array(_), _) if numeric(&ty.elem) => "numpy.ndarray".to_owned(),
                (Container::Sequence(_), _) if numeric(&ty.elem) => "array.array".to_owned(),
                (Container::Single, v) => scalar_type(v),
                _ => "list".to_owned(),
            },
            Part::Elem(_, v) => scalar_type(v),
        }
    }
}

fn scalar_type(v: &Value) -> String {
    match v {
        Value::Bool(_) => "bool",
        Value::Int(_) => "int",
        Value::Float(_) => "float",
        Value::Str(_) => "str",
        Value::Byte(_) => "bytes",
        Value::List(_) => "list",
        Value::Struct(_) => "object",
    }
    .to_owned()
}

/// Whether rclpy stores arrays of this element as numpy arrays / `array.array`.
pub fn numeric(e: &Elem) -> bool {
    matches!(e, Elem::Int { .. } | Elem::F32 | Elem::F64)
}

/// The part of `message` at `path` (attribute names), as ros2topic echo's `--field` walks it.
pub fn select<'a>(
    schema: &'a Schema,
    type_name: &'a str,
    message: &'a Value,
    path: &[String],
) -> Result<Part<'a>, String> {
    let mut part = Part::Message(type_name, message);
    for name in path {
        part = part.attr(schema, name)?;
    }
    Ok(part)
}

/// A `--filter` expression: the subset of Python that ros2cli's `eval(expr)` filters are
/// usually written in. `m` is the message (echo: the `--field` selected part); attributes
/// (`m.header.frame_id`), indexing (`m.data[0]`, `m.data[-1]`) and `len(…)`; literals `123`,
/// `1.5`, `'text'`, `"text"`, `True`, `False`; comparisons `== != < <= > >=` (chained as in
/// Python); `and`, `or`, `not` and parentheses. Anything else is refused when the verb starts.
#[derive(Debug, Clone)]
pub enum Filter {
    /// A path from `m`.
    Path(Vec<Step>),
    /// `len(path)`.
    Len(Vec<Step>),
    /// A literal.
    Lit(Lit),
    /// `a op b op c …`.
    Compare(Box<Filter>, Vec<(CmpOp, Filter)>),
    /// `not a`.
    Not(Box<Filter>),
    /// `a and b`.
    And(Box<Filter>, Box<Filter>),
    /// `a or b`.
    Or(Box<Filter>, Box<Filter>),
}

/// One step of a path from `m`.
#[derive(Debug, Clone)]
pub enum Step {
    /// `.name`.
    Attr(String),
    /// `[i]`.
    Index(i64),
}

/// A Python value a filter computes with.
#[derive(Debug, Clone, PartialEq)]
pub enum Lit {
    /// `bool`.
    Bool(bool),
    /// `int`.
    Int(i128),
    /// `float`.
    Float(f64),
    /// `str`.
    Str(String),
    /// `bytes` (a `byte` field).
    Bytes(Vec<u8>),
    /// A message, list or array: only its truth value is used.
    Other(bool),
}

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmpOp {
    /// `==`.
    Eq,
    /// `!=`.
    Ne,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Int(i128),
    Float(f64),
    Str(String),
    Op(CmpOp),
    Dot,
    LBracket,
    RBracket,
    LParen,
    RParen,
    Minus,
}

fn tokenize(s: &str) -> Result<Vec<Tok>, String> {
    let chars: Vec<char> = s.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        match c {
            ' ' | '\t' => i += 1,
            '.' if !next.is_some_and(|n| n.is_ascii_digit()) => {
                out.push(Tok::Dot);
                i += 1;
            }
            '[' => {
                out.push(Tok::LBracket);
                i += 1;
            }
            ']' => {
                out.push(Tok::RBracket);
                i += 1;
            }
            '(' => {
                out.push(Tok::LParen);
                i += 1;
            }
            ')' => {
                out.push(Tok::RParen);
                i += 1;
            }
            '-' => {
                out.push(Tok::Minus);
                i += 1;
            }
            '=' | '!' | '<' | '>' => {
                let two = next == Some('=');
                let op = match (c, two) {
                    ('=', true) => CmpOp::Eq,
                    ('!', true) => CmpOp::Ne,
                    ('<', false) => CmpOp::Lt,
                    ('<', true) => CmpOp::Le,
                    ('>', false) => CmpOp::Gt,
                    ('>', true) => CmpOp::Ge,
                    _ => return Err(format!("unsupported operator at '{}'", &s[byte(s, i)..])),
                };
                out.push(Tok::Op(op));
                i += if two { 2 } else { 1 };
            }
            '\'' | '"' => {
                let mut text = String::new();
                i += 1;
                loop {
                    match chars.get(i) {
                        None => return Err("unterminated string".to_owned()),
                        Some(&q) if q == c => break,
                        Some('\\') => {
                            let e = chars.get(i + 1).ok_or("unterminated string")?;
                            text.push(match e {
                                'n' => '\n',
                                't' => '\t',
                                'r' => '\r',
                                '0' => '\0',
                                other => *other,
                            });
                            i += 2;
                            continue;
                        }
                        Some(&ch) => text.push(ch),
                    }
                    i += 1;
                }
                i += 1;
                out.push(Tok::Str(text));
            }
            c if c.is_ascii_digit() || c == '.' => {
                let start = i;
                while i < chars.len()
                    && (chars[i].is_ascii_alphanumeric()
                        || chars[i] == '.'
                        || chars[i] == '_'
                        || ((chars[i] == '-' || chars[i] == '+')
                            && matches!(chars[i - 1], 'e' | 'E')))
                {
                    i += 1;
                }
                let text: String = chars[start..i].iter().filter(|c| **c != '_').collect();
                if let Ok(n) = text.parse::<i128>() {
                    out.push(Tok::Int(n));
                } else if let Ok(f) = text.parse::<f64>() {
                    out.push(Tok::Float(f));
                } else {
                    return Err(format!("invalid number '{text}'"));
                }
            }
            c if c.is_alphabetic() || c == '_' => {
                let start = i;
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                out.push(Tok::Ident(chars[start..i].iter().collect()));
            }
            other => return Err(format!("unsupported character '{other}'")),
        }
    }
    Ok(out)
}

/// The byte offset of char index `i` in `s`.
fn byte(s: &str, i: usize) -> usize {
    s.char_indices().nth(i).map_or(s.len(), |(b, _)| b)
}

struct FilterParser {
    toks: Vec<Tok>,
    at: usize,
}

impl FilterParser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at)
    }

    fn next(&mut self) -> Option<Tok> {
        let t = self.toks.get(self.at).cloned();
        self.at += 1;
        t
    }

    fn keyword(&self, k: &str) -> bool {
        matches!(self.peek(), Some(Tok::Ident(w)) if w == k)
    }

    fn or(&mut self) -> Result<Filter, String> {
        let mut left = self.and()?;
        while self.keyword("or") {
            self.at += 1;
            left = Filter::Or(Box::new(left), Box::new(self.and()?));
        }
        Ok(left)
    }

    fn and(&mut self) -> Result<Filter, String> {
        let mut left = self.not()?;
        while self.keyword("and") {
            self.at += 1;
            left = Filter::And(Box::new(left), Box::new(self.not()?));
        }
        Ok(left)
    }

    fn not(&mut self) -> Result<Filter, String> {
        if self.keyword("not") {
            self.at += 1;
            return Ok(Filter::Not(Box::new(self.not()?)));
        }
        self.compare()
    }

    fn compare(&mut self) -> Result<Filter, String> {
        let first = self.operand()?;
        let mut rest = Vec::new();
        while let Some(Tok::Op(op)) = self.peek() {
            let op = *op;
            self.at += 1;
            rest.push((op, self.operand()?));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Filter::Compare(Box::new(first), rest)
        })
    }

    fn operand(&mut self) -> Result<Filter, String> {
        match self.next() {
            Some(Tok::LParen) => {
                let e = self.or()?;
                match self.next() {
                    Some(Tok::RParen) => Ok(e),
                    _ => Err("expected ')'".to_owned()),
                }
            }
            Some(Tok::Minus) => match self.next() {
                Some(Tok::Int(n)) => Ok(Filter::Lit(Lit::Int(-n))),
                Some(Tok::Float(f)) => Ok(Filter::Lit(Lit::Float(-f))),
                _ => Err("expected a number after '-'".to_owned()),
            },
            Some(Tok::Int(n)) => Ok(Filter::Lit(Lit::Int(n))),
            Some(Tok::Float(f)) => Ok(Filter::Lit(Lit::Float(f))),
            Some(Tok::Str(s)) => Ok(Filter::Lit(Lit::Str(s))),
            Some(Tok::Ident(w)) if w == "True" => Ok(Filter::Lit(Lit::Bool(true))),
            Some(Tok::Ident(w)) if w == "False" => Ok(Filter::Lit(Lit::Bool(false))),
            Some(Tok::Ident(w)) if w == "m" => Ok(Filter::Path(self.path()?)),
            Some(Tok::Ident(w)) if w == "len" => {
                if self.next() != Some(Tok::LParen) || self.next() != Some(Tok::Ident("m".into())) {
                    return Err("len() takes a path from m".to_owned());
                }
                let p = self.path()?;
                match self.next() {
                    Some(Tok::RParen) => Ok(Filter::Len(p)),
                    _ => Err("expected ')'".to_owned()),
                }
            }
            Some(t) => Err(format!("unsupported term {t:?}")),
            None => Err("unexpected end of expression".to_owned()),
        }
    }

    fn path(&mut self) -> Result<Vec<Step>, String> {
        let mut steps = Vec::new();
        loop {
            match self.peek() {
                Some(Tok::Dot) => {
                    self.at += 1;
                    match self.next() {
                        Some(Tok::Ident(n)) => steps.push(Step::Attr(n)),
                        _ => return Err("expected a field name after '.'".to_owned()),
                    }
                }
                Some(Tok::LBracket) => {
                    self.at += 1;
                    let i = match self.next() {
                        Some(Tok::Int(n)) => n,
                        Some(Tok::Minus) => match self.next() {
                            Some(Tok::Int(n)) => -n,
                            _ => return Err("expected an index".to_owned()),
                        },
                        _ => return Err("expected an index".to_owned()),
                    };
                    if self.next() != Some(Tok::RBracket) {
                        return Err("expected ']'".to_owned());
                    }
                    steps.push(Step::Index(
                        i64::try_from(i).map_err(|_| "index out of range".to_owned())?,
                    ));
                }
                _ => return Ok(steps),
            }
        }
    }
}

impl Filter {
    /// Parses `expr`; the error says what is not supported.
    pub fn parse(expr: &str) -> Result<Self, String> {
        let mut p = FilterParser {
            toks: tokenize(expr)?,
            at: 0,
        };
        let f = p.or()?;
        match p.peek() {
            None => Ok(f),
            Some(t) => Err(format!("unexpected {t:?}")),
        }
    }

    /// Whether `m` passes (Python truth of the expression); an error as Python would raise it.
    pub fn matches(&self, schema: &Schema, m: Part<'_>) -> Result<bool, String> {
        Ok(truthy(&self.eval(schema, m)?))
    }

    fn eval(&self, schema: &Schema, m: Part<'_>) -> Result<Lit, String> {
        match self {
            Filter::Lit(l) => Ok(l.clone()),
            Filter::Path(steps) => Ok(to_lit(walk(schema, m, steps)?)),
            Filter::Len(steps) => match walk(schema, m, steps)? {
                Part::Field(_, Value::List(items)) => Ok(Lit::Int(items.len() as i128)),
                Part::Field(_, Value::Str(s)) | Part::Elem(_, Value::Str(s)) => {
                    Ok(Lit::Int(s.chars().count() as i128))
                }
                p => Err(format!("object of type '{}' has no len()", p.python_type())),
            },
            Filter::Not(a) => Ok(Lit::Bool(!truthy(&a.eval(schema, m)?))),
            Filter::And(a, b) => {
                let l = a.eval(schema, m)?;
                if truthy(&l) {
                    b.eval(schema, m)
                } else {
                    Ok(l)
                }
            }
            Filter::Or(a, b) => {
                let l = a.eval(schema, m)?;
                if truthy(&l) {
                    Ok(l)
                } else {
                    b.eval(schema, m)
                }
            }
            Filter::Compare(first, rest) => {
                let mut left = first.eval(schema, m)?;
                for (op, right) in rest {
                    let right = right.eval(schema, m)?;
                    if !compare(&left, *op, &right)? {
                        return Ok(Lit::Bool(false));
                    }
                    left = right;
                }
                Ok(Lit::Bool(true))
            }
        }
    }
}

fn walk<'a>(schema: &'a Schema, m: Part<'a>, steps: &[Step]) -> Result<Part<'a>, String> {
    let mut part = m;
    for s in steps {
        part = match s {
            Step::Attr(n) => part.attr(schema, n)?,
            Step::Index(i) => part
                .index(*i)
                .ok_or_else(|| format!("index {i} out of range or not a list"))?,
        };
    }
    Ok(part)
}

fn to_lit(p: Part<'_>) -> Lit {
    let v = match p {
        Part::Message(..) => return Lit::Other(true),
        Part::Field(_, v) | Part::Elem(_, v) => v,
    };
    match v {
        Value::Bool(b) => Lit::Bool(*b),
        Value::Int(i) => Lit::Int(*i),
        Value::Float(f) => Lit::Float(*f),
        Value::Str(s) => Lit::Str(s.clone()),
        Value::Byte(b) => Lit::Bytes(vec![*b]),
        Value::List(items) => Lit::Other(!items.is_empty()),
        Value::Struct(_) => Lit::Other(true),
    }
}

fn truthy(l: &Lit) -> bool {
    match l {
        Lit::Bool(b) | Lit::Other(b) => *b,
        Lit::Int(i) => *i != 0,
        Lit::Float(f) => *f != 0.0,
        Lit::Str(s) => !s.is_empty(),
        Lit::Bytes(b) => !b.is_empty(),
    }
}

fn number(l: &Lit) -> Option<f64> {
    match l {
        Lit::Bool(b) => Some(f64::from(u8::from(*b))),
        Lit::Int(i) => Some(*i as f64),
        Lit::Float(f) => Some(*f),
        _ => None,
    }
}

/// Python's comparison of two values: numbers with numbers (ints exactly), strings with
/// strings, bytes with bytes; `==`/`!=` of anything else is unequal, ordering them a TypeError.
fn compare(a: &Lit, op: CmpOp, b: &Lit) -> Result<bool, String> {
    use std::cmp::Ordering;
    let ord: Option<Ordering> = match (a, b) {
        (Lit::Int(x), Lit::Int(y)) => Some(x.cmp(y)),
        (Lit::Str(x), Lit::Str(y)) => Some(x.cmp(y)),
        (Lit::Bytes(x), Lit::Bytes(y)) => Some(x.cmp(y)),
        _ => match (number(a), number(b)) {
            (Some(x), Some(y)) => x.partial_cmp(&y),
            _ => {
                return match op {
                    CmpOp::Eq => Ok(false),
                    CmpOp::Ne => Ok(true),
                    _ => Err("'<' not supported between these types".to_owned()),
                }
            }
        },
    };
    let Some(ord) = ord else {
        // NaN: only `!=` holds.
        return Ok(op == CmpOp::Ne);
    };
    Ok(match op {
        CmpOp::Eq => ord == Ordering::Equal,
        CmpOp::Ne => ord != Ordering::Equal,
        CmpOp::Lt => ord == Ordering::Less,
        CmpOp::Le => ord != Ordering::Greater,
        CmpOp::Gt => ord == Ordering::Greater,
        CmpOp::Ge => ord != Ordering::Less,
    })
}

/// Prints one report (a line or a few) and flushes; false when stdout is closed.
pub fn print_report(text: &str) -> bool {
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    use std::io::Write;
    writeln!(out, "{text}").and_then(|()| out.flush()).is_ok()
}
