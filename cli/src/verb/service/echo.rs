//! `horus-ros service echo` (ros2service jazzy `verb/echo.py`): prints the service events that
//! servers and clients with introspection on publish on `<service>/_service_event`.
//!
//! As ros2cli: the service type comes from the command line or from the graph (the one type of
//! the service name as given, hidden services included; failing that, here, the type of the
//! event topic's publishers); the subscription uses the `services_default` QoS; when nothing
//! publishes on the event topic it says so once; each event is printed as
//! `yaml.dump(message_to_ordereddict(event, …), allow_unicode=True, width=sys.maxsize,
//! default_flow_style=--flow-style)` with `info.event_type` replaced by its constant's name,
//! followed by `---` (`--csv`: `message_to_csv(event, …)`, the event type left a number). With
//! the global `--json`, each event is one JSON object on one line (docs/cli-json.md).
//!
//! Types compiled into horus-ros-msgs are described from their definitions; any other type by
//! its server's node through `~/get_type_description` (see `service call`), and its `_Event`
//! message is derived from the request and response as rosidl does.
//!
//! `--passive` (our own, [`passive`]) reads the service's request and reply topics instead, and
//! needs no introspection.

mod passive;

use std::io::Write;
use std::sync::Arc;
use std::time::Duration;

use horus_ros_graph::{GraphView, GraphWatcher};
use horus_ros_msgs::dds_type_name;
use horus_ros_msgs::description::{service_event_description, EVENT_SUFFIX};
use horus_ros_msgs::service_msgs::msg::ServiceEventInfo;
use horus_ros_rmw::names::{ServiceName, TopicName};
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{RawEndpointSpec, RawReaderWaker};
use horus_ros_services::SERVICE_EVENT_TOPIC_POSTFIX;
use serde_json::{json, Value as Json};

use super::call::describe;
use crate::dynamic::convert::{to_csv, to_ordereddict};
use crate::dynamic::json::to_json;
use crate::dynamic::pyyaml::{dump, PyValue};
use crate::dynamic::{Schema, ServiceType, Value};
use crate::session::Session;
use crate::verb::echo_options::EchoOptions;
use crate::verb::topic::subscribe::{decode, drain, print_report};
use crate::verb::type_name::normalize_service_type;
use crate::{CliError, Global};

/// Longest wait for the server's node to describe a type that is not compiled in.
const DESCRIBE_TIMEOUT: Duration = Duration::from_secs(5);

/// Arguments of `service echo`.
#[derive(Debug, clap::Args)]
pub struct EchoArgs {
    /// Name of the ROS service to echo (e.g. '/add_two_ints').
    pub service_name: String,
    /// Type of the ROS service (e.g. 'example_interfaces/srv/AddTwoInts').
    pub service_type: Option<String>,
    /// Output all recursive fields separated by commas (e.g. for plotting).
    #[arg(long)]
    pub csv: bool,
    #[command(flatten)]
    pub output: EchoOptions,
    /// Read the service's request and reply topics instead of its event topic: print requests
    /// and replies, paired, with the time between them, whether or not introspection is on
    /// (no server or client is created).
    #[arg(long)]
    pub passive: bool,
    /// With --passive: how long a request waits for its reply before it is printed unpaired,
    /// in seconds.
    #[arg(
        long,
        default_value_t = 10.0,
        value_name = "SECS",
        requires = "passive"
    )]
    pub reply_timeout: f64,
    /// With --passive: how many requests (and replies) wait to be paired at most; beyond that
    /// the oldest is dropped and counted.
    #[arg(long, default_value_t = 1024, value_name = "N", requires = "passive")]
    pub max_outstanding: usize,
    /// Exit after this many events (for tests).
    #[arg(long, hide = true, value_name = "N")]
    pub count: Option<u64>,
}

/// The event message of one service type, ready to decode.
struct EventType {
    schema: Schema,
    /// `pkg/srv/Name_Event`.
    name: String,
    description: horus_ros_msgs::TypeDescription,
}

/// Runs `service echo`.
pub fn run(global: &Global, args: &EchoArgs) -> Result<(), CliError> {
    let given_type = args
        .service_type
        .as_deref()
        .map(|t| {
            normalize_service_type(t)
                .map_err(|_| CliError::new(format!("The service type '{t}' is invalid")))
        })
        .transpose()?;
    let session = Session::open(global)?;
    let service = ServiceName::expand(
        &args.service_name,
        session.node.name(),
        session.node.namespace(),
    )
    .map_err(|_| {
        CliError::new(format!(
            "The service name '{}' is invalid",
            args.service_name
        ))
    })?;
    let service_type = match given_type {
        Some(t) => t,
        None => type_from_graph(&session, &args.service_name, &service)?,
    };
    let options = args.output.convert();
    if args.passive {
        if args.csv {
            return Err(CliError::new("--csv is not available with --passive"));
        }
        let reply_timeout = Duration::try_from_secs_f64(args.reply_timeout)
            .ok()
            .filter(|d| !d.is_zero())
            .ok_or_else(|| {
                CliError::new(format!(
                    "--reply-timeout must be a positive number of seconds, not {}",
                    args.reply_timeout
                ))
            })?;
        let info = service_type_info(&session, &service, &service_type)?;
        return passive::run(
            &session,
            &service,
            &info,
            passive::PassiveOptions {
                json: global.json,
                flow_style: args.output.flow_style,
                convert: options,
                reply_timeout,
                max_outstanding: args.max_outstanding,
                count: args.count,
            },
        );
    }
    let event = event_type(&session, &service, &service_type)?;

    // ros2cli appends the postfix to the name as given.
    let shown_topic = format!("{}{SERVICE_EVENT_TOPIC_POSTFIX}", args.service_name);
    let topic_str = format!("{service}{SERVICE_EVENT_TOPIC_POSTFIX}");
    let topic = TopicName::new(&topic_str)
        .map_err(|e| CliError::new(format!("Invalid topic '{topic_str}': {e}")))?;
    let qos = Qos::services_default();
    let spec = RawEndpointSpec {
        dds_topic_name: topic.to_dds_topic_name(false),
        dds_type_name: dds_type_name(&event.name),
        type_hash: event.description.compute_type_hash(),
        qos,
        service_id: None,
    };
    let mut reader = session.node.create_raw_reader(&spec)?;

    let stdout = std::io::stdout();
    // Until the warning is printed, the graph wakes the reader when the event topic has no
    // publishers left; watching from before the first check, so no change falls in between.
    let wake: Arc<dyn GraphWatcher> = Arc::new(NoPublishersWake {
        topic: topic.as_str().to_owned(),
        reader: reader.waker(),
    });
    session.graph.watch(Arc::downgrade(&wake));
    let mut until_warned = Some(wake);
    let mut printed = 0u64;
    loop {
        if until_warned.is_some() && session.graph.read(|c| c.count_publishers(topic.as_str())) < 1
        {
            let mut out = stdout.lock();
            let _ = writeln!(
                out,
                "No publishers on topic '{shown_topic}'; is service introspection on the client \
                 or server enabled?"
            );
            let _ = out.flush();
            // Said once: the graph keeps the watcher weakly, so dropping it ends its wake-ups.
            until_warned = None;
        }
        // Woken by data, or by the watcher above: no time limit, no periodic wake-up.
        reader.wait(None);
        for sample in drain(&mut reader) {
            let Some(value) = decode(&event.schema, &event.name, &sample) else {
                continue;
            };
            let text = if global.json {
                serde_json::to_string(&event_json(&event.schema, &event.name, &value))
                    .unwrap_or_default()
            } else if args.csv {
                to_csv(&event.schema, &event.name, &value, options)
            } else {
                let mut d = to_ordereddict(&event.schema, &event.name, &value, options);
                name_event_type(&mut d);
                let mut t = dump(&d, args.output.flow_style);
                t.push_str("---");
                t
            };
            if !print_report(&text) {
                // stdout closed (e.g. `| head`): nothing more to do.
                return Ok(());
            }
            printed += 1;
            if args.count.is_some_and(|n| printed >= n) {
                return Ok(());
            }
        }
    }
}

/// Wakes `service echo`'s reader at a graph change after which nothing publishes on the event
/// topic, for the loop to print its warning then (as ros2cli checks before each spin).
struct NoPublishersWake {
    /// The event topic, as the graph names it.
    topic: String,
    reader: RawReaderWaker,
}

impl GraphWatcher for NoPublishersWake {
    fn graph_changed(&self, graph: &GraphView<'_>) {
        if graph.read(|c| c.count_publishers(&self.topic)) < 1 {
            self.reader.wake();
        }
    }
}

/// ros2service `get_service_class`: the one type of the service named exactly as given (hidden
/// services included). Beyond ros2cli, a service known only by its event topic (introspection
/// on, no server or client endpoints seen) takes the event type's service.
fn type_from_graph(
    session: &Session,
    given: &str,
    service: &ServiceName,
) -> Result<String, CliError> {
    let types = session.graph.read(|c| c.service_names_and_types(true));
    if let Some(t) = types.get(given) {
        let t: Vec<&String> = t.iter().collect();
        return match t.as_slice() {
            [] => Err(CliError::new(format!("No types associated with '{given}'"))),
            [one] => Ok((*one).clone()),
            _ => Err(CliError::new(format!(
                "More than one type associated with service '{given}'"
            ))),
        };
    }
    let topic = format!("{service}{SERVICE_EVENT_TOPIC_POSTFIX}");
    let mut from_events: Vec<String> = session
        .graph
        .read(|c| c.publishers_info_by_topic(&topic, false))
        .into_iter()
        .filter_map(|p| p.topic_type.strip_suffix(EVENT_SUFFIX).map(str::to_owned))
        .collect();
    from_events.sort();
    from_events.dedup();
    match from_events.as_slice() {
        [one] => Ok(one.clone()),
        _ => Err(CliError::new(format!("Cannot find type for '{given}'"))),
    }
}

/// `service_type`: compiled in, else as its server's node describes it.
fn service_type_info(
    session: &Session,
    service: &ServiceName,
    service_type: &str,
) -> Result<ServiceType, CliError> {
    match ServiceType::compiled(service_type) {
        Some(info) => Ok(info),
        None => describe::fetch(
            &session.node,
            &session.graph,
            service.as_str(),
            service_type,
            DESCRIBE_TIMEOUT,
        ),
    }
    .map_err(|e| {
        CliError::new(format!(
            "Could not load the type for the passed service: {e}"
        ))
    })
}

/// The `_Event` message of `service_type`: compiled in, else derived from the request and
/// response its server's node describes.
fn event_type(
    session: &Session,
    service: &ServiceName,
    service_type: &str,
) -> Result<EventType, CliError> {
    let name = format!("{service_type}{EVENT_SUFFIX}");
    let info = service_type_info(session, service, service_type)?;
    let description = service_event_description(
        service_type,
        info.request_description(),
        info.response_description(),
    );
    let schema = Schema::from_description(&description)
        .and_then(|s| s.check(&name).map(|()| s))
        .map_err(|e| {
            CliError::new(format!(
                "Could not load the type for the passed service: {e}"
            ))
        })?;
    Ok(EventType {
        schema,
        name,
        description,
    })
}

/// ros2service echo: `info['event_type']` becomes the name of its `ServiceEventInfo` constant.
fn name_event_type(d: &mut PyValue) {
    let PyValue::Map(items) = d else { return };
    let Some((_, PyValue::Map(info))) = items.iter_mut().find(|(k, _)| k == "info") else {
        return;
    };
    if let Some((_, v)) = info.iter_mut().find(|(k, _)| k == "event_type") {
        if let PyValue::Int(n) = v {
            if let Some(name) = event_type_name(*n) {
                *v = PyValue::Str(name.to_owned());
            }
        }
    }
}

/// The `ServiceEventInfo` constant named for an event type.
fn event_type_name(n: i128) -> Option<&'static str> {
    match u8::try_from(n).ok()? {
        ServiceEventInfo::REQUEST_SENT => Some("REQUEST_SENT"),
        ServiceEventInfo::REQUEST_RECEIVED => Some("REQUEST_RECEIVED"),
        ServiceEventInfo::RESPONSE_SENT => Some("RESPONSE_SENT"),
        ServiceEventInfo::RESPONSE_RECEIVED => Some("RESPONSE_RECEIVED"),
        _ => None,
    }
}

/// One event as JSON: `info` with `event_type` by name and `client_gid` as a dotted GID; the
/// request and response as JSON values of their fields.
fn event_json(schema: &Schema, name: &str, v: &Value) -> Json {
    let mut j = to_json(schema, name, v);
    if let Some(info) = j.get_mut("info").and_then(Json::as_object_mut) {
        if let Some(n) = info.get("event_type").and_then(Json::as_i64) {
            if let Some(name) = event_type_name(i128::from(n)) {
                info.insert("event_type".to_owned(), json!(name));
            }
        }
        if let Some(bytes) = info.get("client_gid").and_then(Json::as_array) {
            let gid: Vec<String> = bytes
                .iter()
                .map(|b| format!("{:02x}", b.as_u64().unwrap_or(0)))
                .collect();
            info.insert("client_gid".to_owned(), json!(gid.join(".")));
        }
    }
    j
}
