//! `horus-ros topic echo` (ros2topic jazzy 0.32 `verb/echo.py`): prints the messages of a topic.
//!
//! As ros2cli: the type comes from the command line or from the graph (the one type of the
//! topic, hidden topics included; else `WARNING: topic [...] does not appear to be published
//! yet` and `Could not determine the type for the passed topic`); the QoS is echo's
//! `choose_qos` (the `--qos-*` options as given when any policy is, else the `--qos-profile`
//! preset with reliability and durability adapted to the publishers'); each message is printed as
//! `message_to_yaml(…)` followed by `---` (`--csv`: `message_to_csv`, one line), a `--field`
//! that selects no message as Python's `str()` followed by `---`, `--raw` as the Python `repr`
//! of the serialized message followed by `---`; `--include-message-info` prints the message
//! info first (YAML: `yaml.dump(info)` and `---`; CSV: its values prepended): rclpy's dict
//! (rclpy jazzy `src/rclpy/subscription.cpp` `take_message`: `source_timestamp`,
//! `received_timestamp`, `publication_sequence_number`, `reception_sequence_number`) filled as
//! rmw_fastrtps_cpp fills it (the writer's source timestamp, the reception time, the sample's
//! sequence number at its writer; no reception sequence number). Unless `--no-lost-messages`,
//! samples lost before a message are reported first as `_message_lost_event_callback` prints
//! them ([`super::lost`]). With the global `--json`, each message is one JSON object on one line
//! (docs/cli-json.md).
//!
//! Types are resolved as [`super::subscribe::resolve_type`] does: compiled in, interface files on
//! `AMENT_PREFIX_PATH`, else the `~/get_type_description` of a node on the topic.
//!
//! Differences, for lack of support below: `--filter` evaluates a subset of Python
//! ([`Filter`]); on the Cyclone backend the sequence numbers are not known (Cyclone DDS does not
//! report them), so `publication_sequence_number` is `None` there and no loss is reported.

use std::time::{Duration, Instant};

use horus_ros_rmw::SampleId;
use serde_json::{json, Map, Value as Json};

use super::lost::LostSamples;
use super::qos::QosArgs;
use super::subscribe::{
    daemon_graph, decode, drain, expand, graph_type, graph_type_in, numeric, print_report,
    publisher_qos, publisher_qos_in, resolve_type, select, subscribe, warn_incompatible_publishers,
    Filter, Interrupt, MessageType, Part,
};
use crate::dynamic::convert::{to_csv, to_ordereddict, ConvertOptions};
use crate::dynamic::json::to_json;
use crate::dynamic::pyyaml::{dump, PyValue};
use crate::dynamic::repr::{py_bytes, py_float, py_str, repr};
use crate::dynamic::{Container, Elem, Schema, Value};
use crate::session::Session;
use crate::verb::echo_options::EchoOptions;
use crate::verb::type_name::normalize_message_type;
use crate::{CliError, Global};

/// Arguments of `topic echo`.
#[derive(Debug, clap::Args)]
pub struct EchoArgs {
    /// Name of the ROS topic to listen to (e.g. '/chatter')
    pub topic_name: String,
    /// Type of the ROS message (e.g. 'std_msgs/msg/String')
    pub message_type: Option<String>,
    #[command(flatten)]
    pub qos: QosArgs,
    /// Output all recursive fields separated by commas (e.g. for plotting). If
    /// --include-message-info is also passed, the following fields are prepended:
    /// source_timestamp, received_timestamp, publication_sequence_number,
    /// reception_sequence_number.
    #[arg(long)]
    pub csv: bool,
    /// Echo a selected field of a message. Use '.' to select sub-fields. For example, to echo the
    /// position field of a nav_msgs/msg/Odometry message: 'ros2 topic echo /odom --field
    /// pose.pose.position'
    #[arg(long)]
    pub field: Option<String>,
    #[command(flatten)]
    pub output: EchoOptions,
    /// Don't report when a message is lost
    #[arg(long)]
    pub no_lost_messages: bool,
    /// Echo the raw binary representation
    #[arg(long)]
    pub raw: bool,
    /// Python expression to filter messages that are printed. Expression can use Python
    /// builtins as well as m (the message). Here a subset of Python: paths from m
    /// (m.a.b, m.data[0]), len(…), numbers, 'strings', True/False, == != < <= > >=, and, or,
    /// not, parentheses.
    #[arg(long = "filter", value_name = "FILTER_EXPR")]
    pub filter_expr: Option<String>,
    /// Print the first message received and then exit.
    #[arg(long)]
    pub once: bool,
    /// Set a timeout in seconds for waiting
    #[arg(long, value_name = "N", value_parser = crate::args::positive_float)]
    pub timeout: Option<f64>,
    /// Shows the associated message info.
    #[arg(short = 'i', long)]
    pub include_message_info: bool,
}

/// rmw's message info of one sample, in rclpy's dict order (`None` where the rmw reports no
/// number: rmw_fastrtps_cpp has no `reception_sequence_number`).
struct MessageInfo {
    source_timestamp: i64,
    received_timestamp: i64,
    publication_sequence_number: Option<i64>,
    reception_sequence_number: Option<i64>,
}

impl MessageInfo {
    fn entries(&self) -> [(&'static str, Option<i64>); 4] {
        [
            ("source_timestamp", Some(self.source_timestamp)),
            ("received_timestamp", Some(self.received_timestamp)),
            (
                "publication_sequence_number",
                self.publication_sequence_number,
            ),
            ("reception_sequence_number", self.reception_sequence_number),
        ]
    }

    /// `yaml.dump(info)`: block style, keys sorted, `None` as `null`.
    fn yaml(&self) -> String {
        let mut e = self.entries();
        e.sort_by_key(|(k, _)| *k);
        e.iter()
            .map(|(k, v)| match v {
                Some(v) => format!("{k}: {v}\n"),
                None => format!("{k}: null\n"),
            })
            .collect()
    }

    /// Python `str()` of each value, in order (`--csv`).
    fn csv_values(&self) -> Vec<String> {
        self.entries()
            .iter()
            .map(|(_, v)| v.map_or_else(|| "None".to_owned(), |v| v.to_string()))
            .collect()
    }

    /// `print(info)`: the dict's repr.
    fn py_repr(&self) -> String {
        let items: Vec<String> = self
            .entries()
            .iter()
            .zip(self.csv_values())
            .map(|((k, _), v)| format!("'{k}': {v}"))
            .collect();
        format!("{{{}}}", items.join(", "))
    }

    fn json(&self) -> Json {
        let mut m = Map::new();
        for (k, v) in self.entries() {
            m.insert(k.to_owned(), json!(v));
        }
        Json::Object(m)
    }
}

/// Runs `topic echo`.
pub fn run(global: &Global, args: &EchoArgs) -> Result<(), CliError> {
    // echo.py `main`: the field is validated first.
    let field: Option<Vec<String>> = match &args.field {
        None => None,
        Some(f) => {
            let parts: Vec<String> = f
                .split('.')
                .filter(|s| !s.is_empty())
                .map(str::to_owned)
                .collect();
            if parts.is_empty() {
                return Err(CliError::new(format!("Invalid field value '{f}'")));
            }
            Some(parts)
        }
    };
    let filter = args
        .filter_expr
        .as_deref()
        .map(|e| {
            Filter::parse(e).map_err(|why| {
                CliError::new(format!(
                    "Unsupported --filter expression '{e}': {why} (horus-ros evaluates a subset \
                     of Python: paths from m, len(), literals, comparisons, and/or/not)"
                ))
            })
        })
        .transpose()?;
    let options = args.output.convert();
    let deadline = args
        .timeout
        .map(|t| Instant::now() + Duration::from_secs_f64(t));

    let session = Session::open(global)?;
    let topic = expand(&session, &args.topic_name)?;
    // ros2topic looks the topic up through its daemon (`NodeStrategy`): when our own discovery
    // has not seen it (a peer that answered late on a loaded machine), the daemon's graph does.
    let mut publishers = publisher_qos(&session, &topic);
    let mut daemon = None;
    if publishers.is_empty() {
        daemon = daemon_graph(global);
        if let Some(c) = &daemon {
            publishers = publisher_qos_in(c, &topic);
        }
    }
    let (qos, notes) = args.qos.choose(&publishers);
    for n in notes {
        println!("{n}");
    }
    let found = match graph_type(&session, &args.topic_name, &topic)? {
        Some(t) => Some(t),
        None => match &daemon {
            Some(c) => graph_type_in(c, &args.topic_name, &topic)?,
            None => None,
        },
    };
    let type_name = match &args.message_type {
        Some(t) => normalize_message_type(t)?,
        None => match found {
            Some(t) => t,
            None => {
                println!(
                    "WARNING: topic [{}] does not appear to be published yet",
                    args.topic_name
                );
                return Err(CliError::new(
                    "Could not determine the type for the passed topic",
                ));
            }
        },
    };
    // `--raw` needs no description: the bytes are printed as they came.
    // ros2topic's errors for a type it cannot import: the one given (echo.py `main`), or the
    // topic's (api `_get_msg_class`).
    let invalid = if args.message_type.is_some() {
        "The passed message type is invalid".to_owned()
    } else {
        format!("The message type '{type_name}' is invalid")
    };
    let message_type = if args.raw {
        None
    } else {
        Some(resolve_type(&session, &type_name, &invalid)?)
    };
    let hash = match &message_type {
        Some(t) => t.hash,
        None => super::subscribe::announced_hash(&session, &topic, &type_name),
    };
    let mut reader = subscribe(&session, &topic, &type_name, hash, qos)?;
    warn_incompatible_publishers(&session, &topic, &qos);
    let interrupt = Interrupt::watch(&reader);
    // What the RMW reports: the DDS RMWs none (rclpy prints `null`), rmw_zenoh_cpp 0.2 always 0.
    let reception_sequence_number =
        (session.context.backend() == Some(horus_ros_rmw::backend::Backend::Zenoh)).then_some(0);

    let mut lost = LostSamples::default();
    loop {
        let left = match deadline {
            Some(d) => match d.checked_duration_since(Instant::now()) {
                Some(left) => Some(left),
                None => return Ok(()),
            },
            None => None,
        };
        reader.wait(left);
        interrupt.check()?;
        for sample in drain(&mut reader) {
            if !args.no_lost_messages {
                if let Some(status) = lost.observe(sample.id) {
                    let text = if global.json {
                        json!({ "message_lost": {
                            "total_count_change": status.total_count_change,
                            "total_count": status.total_count,
                        }})
                        .to_string()
                    } else {
                        status.text()
                    };
                    if !print_report(&text) {
                        return Ok(());
                    }
                }
            }
            let info = MessageInfo {
                source_timestamp: sample.source_timestamp.unwrap_or(0),
                received_timestamp: sample.received_timestamp,
                publication_sequence_number: (sample.id.sequence_number
                    != SampleId::UNKNOWN_SEQUENCE_NUMBER)
                    .then_some(sample.id.sequence_number),
                reception_sequence_number,
            };
            let text = match &message_type {
                None => {
                    let mut bytes = vec![0, if sample.big_endian { 0 } else { 1 }, 0, 0];
                    bytes.extend_from_slice(&sample.body);
                    if let Some(f) = &field {
                        return Err(CliError::new(format!(
                            "Invalid field '{}': 'bytes' object has no attribute '{}'",
                            f.join("."),
                            f[0]
                        )));
                    }
                    if filter.is_some() {
                        return Err(CliError::new("--filter is not supported with --raw here"));
                    }
                    raw_text(global, args, &info, &bytes)
                }
                Some(t) => {
                    let Some(value) = decode(&t.schema, &t.name, &sample) else {
                        continue;
                    };
                    let part = match &field {
                        None => Part::Message(&t.name, &value),
                        Some(f) => select(&t.schema, &t.name, &value, f).map_err(|e| {
                            CliError::new(format!("Invalid field '{}': {e}", f.join(".")))
                        })?,
                    };
                    if let Some(filter) = &filter {
                        match filter.matches(&t.schema, part) {
                            Ok(true) => {}
                            Ok(false) => continue,
                            Err(e) => {
                                return Err(CliError::new(format!(
                                    "The --filter expression failed: {e}"
                                )))
                            }
                        }
                    }
                    message_text(
                        global,
                        args,
                        options,
                        t,
                        &value,
                        field.as_deref(),
                        part,
                        &info,
                    )
                }
            };
            if !print_report(&text) {
                // stdout closed (e.g. `| head`): nothing more to do.
                return Ok(());
            }
            if args.once {
                return Ok(());
            }
        }
    }
}

/// What `--raw` prints for one message (without the final newline).
fn raw_text(global: &Global, args: &EchoArgs, info: &MessageInfo, bytes: &[u8]) -> String {
    if global.json {
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let mut j = json!({ "raw": hex });
        if args.include_message_info {
            j["message_info"] = info.json();
        }
        return serde_json::to_string(&j).unwrap_or_default();
    }
    let mut t = String::new();
    if args.include_message_info {
        t.push_str("---Got new message, message info:---\n");
        t.push_str(&info.py_repr());
        t.push_str("\n---Message data:---\n");
    }
    t.push_str(&py_bytes(bytes));
    t.push_str("\n---");
    t
}

/// What echo prints for one decoded message (without the final newline).
#[allow(clippy::too_many_arguments)]
fn message_text(
    global: &Global,
    args: &EchoArgs,
    options: ConvertOptions,
    t: &MessageType,
    value: &Value,
    field: Option<&[String]>,
    part: Part<'_>,
    info: &MessageInfo,
) -> String {
    if global.json {
        let mut j = to_json(&t.schema, &t.name, value);
        for name in field.unwrap_or_default() {
            j = j.get(name).cloned().unwrap_or(Json::Null);
        }
        if args.include_message_info {
            j = json!({ "message_info": info.json(), "message": j });
        }
        return serde_json::to_string(&j).unwrap_or_default();
    }
    let (type_name, v) = match part {
        Part::Message(n, v) => (n, v),
        other => {
            // Not a message: `print(submsg, end='\n---\n')`.
            let mut s = String::new();
            if args.include_message_info {
                s.push_str("---Got new message, message info:---\n");
                s.push_str(&info.py_repr());
                s.push_str("\n---Message data:---\n");
            }
            s.push_str(&py_str_of(&t.schema, other));
            s.push_str("\n---");
            return s;
        }
    };
    if args.csv {
        let csv = to_csv(&t.schema, type_name, v, options);
        if args.include_message_info {
            return format!("{},{csv}", info.csv_values().join(","));
        }
        return csv;
    }
    let mut s = String::new();
    if args.include_message_info {
        s.push_str(&info.yaml());
        s.push_str("---\n");
    }
    let d: PyValue = to_ordereddict(&t.schema, type_name, v, options);
    s.push_str(&dump(&d, args.output.flow_style));
    s.push_str("---");
    s
}

/// array.array typecode of a numeric element.
fn typecode(e: &Elem) -> char {
    match e {
        Elem::Int { bits: 8, signed } => {
            if *signed {
                'b'
            } else {
                'B'
            }
        }
        Elem::Int { bits: 16, signed } => {
            if *signed {
                'h'
            } else {
                'H'
            }
        }
        Elem::Int { bits: 32, signed } => {
            if *signed {
                'i'
            } else {
                'I'
            }
        }
        Elem::Int { signed, .. } => {
            if *signed {
                'q'
            } else {
                'Q'
            }
        }
        Elem::F32 => 'f',
        _ => 'd',
    }
}

/// Python `repr` of one element as rclpy stores it.
fn elem_repr(schema: &Schema, e: &Elem, v: &Value) -> String {
    match (e, v) {
        (Elem::Nested(n), v) => repr(schema, n, v),
        (_, Value::Bool(b)) => (if *b { "True" } else { "False" }).to_owned(),
        (_, Value::Int(i)) => i.to_string(),
        (_, Value::Float(f)) => py_float(*f),
        (_, Value::Str(s)) => py_str(s),
        (_, Value::Byte(b)) => py_bytes(&[*b]),
        (_, other) => format!("{other:?}"),
    }
}

/// numpy's `str()` of a 1-D array of `elem` (rclpy holds a numeric fixed array `T[N]` as one):
/// each element as numpy's `repr` writes it — taken from horus-ros-dynamic's `repr` of a
/// one-field message of this array type, `…(a=array([w, w, …]))` — then numpy's
/// `_formatArray` with the separator `' '`: one space between elements, lines wrapped at 75
/// columns with a one-space hanging indent (numpy 1.26 and 2.x default print options).
fn numpy_str(elem: &Elem, items: &[Value]) -> Option<String> {
    use horus_ros_msgs::{DescriptionBuilder, FieldType};
    let base: u8 = match elem {
        Elem::Int { bits: 8, signed } => 2 + u8::from(!*signed),
        Elem::Int { bits: 16, signed } => 4 + u8::from(!*signed),
        Elem::Int { bits: 32, signed } => 6 + u8::from(!*signed),
        Elem::Int { signed, .. } => 8 + u8::from(!*signed),
        Elem::F32 => 10,
        Elem::F64 => 11,
        _ => return None,
    };
    const ARRAY_OFFSET: u8 = 48;
    const NAME: &str = "horus_ros/msg/NumpyStr";
    let description = DescriptionBuilder::new(NAME)
        .push_field(
            "a",
            FieldType {
                type_id: base + ARRAY_OFFSET,
                capacity: u64::try_from(items.len()).ok()?,
                string_capacity: 0,
                nested_type_name: String::new(),
            },
        )
        .build();
    let schema = Schema::from_description(&description).ok()?;
    let text = repr(
        &schema,
        NAME,
        &Value::Struct(vec![Value::List(items.to_vec())]),
    );
    let inner = text.split_once("array([")?.1.rsplit_once(']')?.0;
    // Each element keeps its padding: after the first, what follows a comma is the separator's
    // space, or a line break and the repr's hanging indent (the width of `array([`), then the
    // element.
    let hanging_indent = " ".repeat("array([".len());
    let words: Vec<&str> = inner
        .split(',')
        .enumerate()
        .map(|(i, w)| match w.split_once('\n') {
            Some((_, rest)) => rest.strip_prefix(hanging_indent.as_str()).unwrap_or(rest),
            None if i > 0 => w.strip_prefix(' ').unwrap_or(w),
            None => w,
        })
        .collect();
    // `_formatArray`: every element's width limit is the line width less `len(']')`.
    const LINE_WIDTH: usize = 75;
    let (hanging, limit) = (" ", LINE_WIDTH - 1);
    let (mut out, mut line) = (String::new(), hanging.to_owned());
    for (i, word) in words.iter().enumerate() {
        if line.len() + word.len() > limit && line.len() > hanging.len() {
            out.push_str(line.trim_end());
            out.push('\n');
            line = hanging.to_owned();
        }
        line.push_str(word);
        if i + 1 < words.len() {
            line.push(' ');
        }
    }
    out.push_str(&line);
    Some(format!("[{}]", &out[hanging.len()..]))
}

/// Python `str()` of a part that is not a message, as rclpy holds it: scalars as Python
/// prints them, numeric sequences as `array.array`, numeric fixed arrays as numpy prints
/// 1-D arrays (`[1 2 3]`; floats as Python writes them), other lists as Python lists.
fn py_str_of(schema: &Schema, part: Part<'_>) -> String {
    match part {
        Part::Message(n, v) => repr(schema, n, v),
        Part::Elem(e, v) => match v {
            Value::Str(s) => s.clone(),
            v => elem_repr(schema, e, v),
        },
        Part::Field(ty, v) => match (ty.container, v) {
            (_, Value::List(items)) if numeric(&ty.elem) => {
                let words: Vec<String> = items
                    .iter()
                    .map(|i| elem_repr(schema, &ty.elem, i))
                    .collect();
                if matches!(ty.container, Container::Array(_)) {
                    numpy_str(&ty.elem, items).unwrap_or_else(|| format!("[{}]", words.join(" ")))
                } else if items.is_empty() {
                    format!("array('{}')", typecode(&ty.elem))
                } else {
                    format!("array('{}', [{}])", typecode(&ty.elem), words.join(", "))
                }
            }
            (_, Value::List(items)) => {
                let words: Vec<String> = items
                    .iter()
                    .map(|i| elem_repr(schema, &ty.elem, i))
                    .collect();
                format!("[{}]", words.join(", "))
            }
            (_, Value::Str(s)) => s.clone(),
            (_, v) => elem_repr(schema, &ty.elem, v),
        },
    }
}
