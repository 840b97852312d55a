//! `horus-ros topic pub` (ros2topic jazzy `verb/pub.py`): fills a message from YAML as
//! rosidl_runtime_py's `set_message_fields` does (with `header: auto` and `stamp: now`), and
//! publishes it at `--rate`, printing
//!
//! ```text
//! publisher: beginning loop
//! publishing #1: std_msgs.msg.String(data='hi')
//!
//! ```
//!
//! The type is what horus-ros has compiled in, else its interface file in a package on
//! `AMENT_PREFIX_PATH`, else what a node of the graph that publishes or subscribes to it
//! describes (`~/get_type_description`). The message goes out through a raw writer with the
//! type's DDS name and RIHS01 hash, from the CLI's hidden node (`_horus_ros_<pid>`, as ros2cli's
//! `_ros2cli_<pid>`) or the node `--node-name` names.
//!
//! With `--json`, each message printed is one line `{"count": N, "message": {fields}}` instead
//! (docs/cli-json.md), and the waiting line goes to stderr.
//!
//! One difference from ros2cli: the values are checked against the type before waiting for
//! subscriptions, so a wrong value fails at once.

use std::io::Read;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant, SystemTime};

use horus_ros_graph::{GraphView, GraphWatcher};

use horus_ros_rmw::names::TopicName;
use horus_ros_rmw::raw::{RawEndpointSpec, RawWriter};
use yaml_rust2::{Yaml, YamlLoader};

use super::message_type::MessageType;
use super::publish::Stamps;
use super::qos::{publishing, QosArgs};
use crate::dynamic::json::to_json;
use crate::dynamic::{cdr, repr, yaml, Value};
use crate::session::Session;
use crate::verb::type_name::normalize_message_type;
use crate::{CliError, Global};
use serde_json::json;

/// ros2cli's `DEFAULT_WAIT_TIME`: how often the subscription count is checked.
/// How often pub.py repeats its "Waiting for …" line (every tenth 0.1 s check).
const WAIT_LOG_PERIOD: Duration = Duration::from_secs(1);

/// Arguments of `topic pub` (its QoS options worded for publishing).
#[derive(Debug, clap::Args)]
#[command(mut_args(publishing))]
pub struct PubArgs {
    /// Name of the ROS topic to publish to (e.g. '/chatter').
    pub topic_name: String,
    /// Type of the ROS message (e.g. 'std_msgs/String').
    pub message_type: String,
    /// Values to fill the message with in YAML format (e.g. 'data: Hello World'), otherwise the
    /// message will be published with default values.
    #[arg(default_value = "{}", conflicts_with = "stdin")]
    pub values: String,
    /// Read values from standard input.
    #[arg(long)]
    pub stdin: bool,
    /// Publishing rate in Hz (default: 1).
    #[arg(short = 'r', long, value_name = "N", default_value_t = 1.0, value_parser = crate::args::positive_float)]
    pub rate: f64,
    /// Only print every N-th published message (default: 1).
    #[arg(
        short = 'p',
        long = "print",
        value_name = "N",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    pub print_nth: i64,
    /// Publish one message and exit.
    #[arg(short = '1', long, conflicts_with = "times")]
    pub once: bool,
    /// Publish this number of times and then exit.
    #[arg(short = 't', long, default_value_t = 0)]
    pub times: u64,
    /// Wait until finding the specified number of matching subscriptions. Defaults to 1 when
    /// using "-1"/"--once"/"--times", otherwise defaults to 0.
    #[arg(short = 'w', long)]
    pub wait_matching_subscriptions: Option<u64>,
    /// This sets the maximum wait time in seconds if --wait-until-matching-subscriptions is
    /// set. By default, this flag is not set meaning the subscriber will wait endlessly.
    #[arg(long, value_parser = crate::args::positive_float)]
    pub max_wait_time_secs: Option<f64>,
    /// Keep publishing node alive for N seconds after the last msg (default: 0.1).
    #[arg(long, value_name = "N", default_value_t = 0.1, value_parser = crate::args::positive_float)]
    pub keep_alive: f64,
    /// Name of the created publishing node.
    #[arg(short = 'n', long)]
    pub node_name: Option<String>,
    #[command(flatten)]
    pub qos: QosArgs,
    /// Longest wait for a node's ~/get_type_description answer, for a type neither compiled
    /// in nor installed, in seconds.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_parser = crate::args::seconds
    )]
    pub type_timeout: f64,
}

/// Runs `topic pub`.
pub fn run(global: &Global, args: &PubArgs) -> Result<(), CliError> {
    let times = if args.once { 1 } else { args.times };
    let values = if args.stdin {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| CliError::new(format!("Cannot read the values from stdin: {e}")))?;
        text
    } else {
        args.values.clone()
    };
    let type_name = normalize_message_type(&args.message_type)?;
    let unusable = |e: String| {
        CliError::new(format!(
            "The message type '{type_name}' cannot be used: {e}"
        ))
    };
    let known = MessageType::installed(&type_name, unusable)?.ok();
    let mut doc = load_values(&values)?;

    let mut session = match &args.node_name {
        Some(name) => Session::join_as(global, name)?,
        None => Session::join(global)?,
    };
    session.settle(global);
    let message_type = match known {
        Some(t) => t,
        // ros2topic's error for a type it cannot import, where no node could describe it.
        None if !super::subscribe::type_in_graph(&session, &type_name) => {
            tracing::debug!(
                type_name,
                "not compiled in, not on AMENT_PREFIX_PATH, no node uses it"
            );
            return Err(CliError::new("The passed message type is invalid"));
        }
        None => MessageType::from_graph(
            &session,
            &type_name,
            Duration::from_secs_f64(args.type_timeout),
            |why| {
                CliError::new(format!(
                    "The passed message type is invalid: '{type_name}' is not built into \
                     horus-ros nor in a package on AMENT_PREFIX_PATH, and the graph does not \
                     describe it: {why}"
                ))
            },
            unusable,
        )?,
    };
    let stamps = Stamps::take(&message_type.schema, &message_type.name, &mut doc);
    let mut message = yaml::fill_from_doc(&message_type.schema, &message_type.name, &doc)
        .map_err(|e| CliError::new(format!("Failed to populate field: {e}")))?;

    let topic = TopicName::expand(
        &args.topic_name,
        session.node.name(),
        session.node.namespace(),
    )
    .map_err(|e| CliError::new(format!("Invalid topic name '{}': {e}", args.topic_name)))?;
    let qos = resolve_qos(&session, topic.as_str(), args.qos.profile());
    let writer = session.node.create_raw_writer(&RawEndpointSpec {
        dds_topic_name: topic.to_dds_topic_name(qos.avoid_ros_namespace_conventions),
        dds_type_name: message_type.dds_type_name(),
        type_hash: message_type.hash,
        qos,
        service_id: None,
    })?;

    let wait_for = args
        .wait_matching_subscriptions
        .unwrap_or(u64::from(times != 0));
    if wait_for == 0 && args.max_wait_time_secs.is_some() {
        return Err(CliError::new(
            "--max-wait-time-secs option is only effective with \
             --wait-matching-subscriptions, --once or --times",
        ));
    }
    let stop = Wakeup::new();
    interrupt_on_signal(&stop);
    let watcher: Arc<dyn GraphWatcher> = stop.clone();
    session.graph.watch(Arc::downgrade(&watcher));
    let publisher = Publisher {
        session: &session,
        writer: &writer,
        topic: topic.as_str(),
        stop: &stop,
    };
    if !publisher.wait_for_subscriptions(wait_for, args.max_wait_time_secs, global.json)? {
        return Err(interrupted());
    }

    if !global.json {
        println!("publisher: beginning loop");
    }
    let period = Duration::from_secs_f64(1.0 / args.rate);
    let keep_alive = Duration::from_secs_f64(args.keep_alive);
    let mut count: u64 = 0;
    let publish = |message: &mut Value, count: u64| -> Result<(), CliError> {
        if !stamps.is_empty() {
            stamps.apply(message, SystemTime::now());
        }
        if args.print_nth != 0 && i128::from(count) % i128::from(args.print_nth) == 0 {
            if global.json {
                let line = json!({
                    "count": count,
                    "message": to_json(&message_type.schema, &message_type.name, message),
                });
                println!("{line}");
            } else {
                println!(
                    "publishing #{count}: {}\n",
                    repr::repr(&message_type.schema, &message_type.name, message)
                );
            }
        }
        let body = cdr::encode(&message_type.schema, &message_type.name, message)
            .map_err(|e| CliError::new(format!("Cannot encode the message: {e}")))?;
        writer
            .write(body, None, None)
            .map_err(|e| CliError::new(format!("Cannot publish on {topic}: {e}")))?;
        Ok(())
    };
    count += 1;
    publish(&mut message, count)?;
    if times != 1 {
        // rclpy's timer: the first tick one period after it is created, then every period,
        // missed ticks skipped (rcl `rcl_timer_call`).
        let mut next = Instant::now() + period;
        while times == 0 || count < times {
            if !stop.sleep_until(next) {
                publisher.linger(keep_alive);
                return Err(interrupted());
            }
            count += 1;
            publish(&mut message, count)?;
            let now = Instant::now();
            next += period;
            if next <= now {
                let behind = (now - next).as_nanos() / period.as_nanos().max(1) + 1;
                next += period * u32::try_from(behind).unwrap_or(u32::MAX);
            }
        }
    }
    // ros2cli: "give some time for the messages to reach the wire before exiting".
    publisher.linger(keep_alive);
    Ok(())
}

/// The values as ros2cli loads them (`yaml.safe_load`), which must be a mapping.
fn load_values(values: &str) -> Result<Yaml, CliError> {
    let docs = YamlLoader::load_from_str(values)
        .map_err(|e| CliError::new(format!("Failed to parse values as YAML: {e}")))?;
    match docs.into_iter().next() {
        Some(doc @ Yaml::Hash(_)) => Ok(doc),
        _ => Err(CliError::new(
            "The passed value needs to be a dictionary in YAML format",
        )),
    }
}

/// A profile with best-available policies resolved against the subscriptions the graph lists
/// on `topic`, as rmw does for a publisher (rmw_dds_common `qos_profile_get_best_available_for_
/// topic_publisher`); any other profile as it is.
fn resolve_qos(
    session: &Session,
    topic: &str,
    qos: horus_ros_rmw::qos::Qos,
) -> horus_ros_rmw::qos::Qos {
    if !qos.has_best_available_policy() {
        return qos;
    }
    let subscriptions: Vec<_> = session.graph.read(|c| {
        c.subscriptions_info_by_topic(topic, false)
            .into_iter()
            .map(|s| s.qos_profile)
            .collect()
    });
    qos.resolve_best_available_for_publisher(&subscriptions)
}

/// What ends this verb's waits: SIGINT or SIGTERM (the loop then ends quietly, as ros2cli does
/// on `KeyboardInterrupt`), and, for the wait for subscriptions, every graph change.
struct Wakeup {
    /// Whether a signal came, and how many graph changes were seen.
    state: Mutex<(bool, u64)>,
    changed: Condvar,
}

impl Wakeup {
    fn new() -> Arc<Self> {
        Arc::new(Self {
            state: Mutex::new((false, 0)),
            changed: Condvar::new(),
        })
    }

    fn lock(&self) -> MutexGuard<'_, (bool, u64)> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn stop(&self) {
        self.lock().0 = true;
        self.changed.notify_all();
    }

    /// The graph changes seen so far (read before looking at the graph).
    fn changes(&self) -> u64 {
        self.lock().1
    }

    /// Waits until `deadline`, a signal, or (with `changes`) a graph change after that many;
    /// returns whether no signal came.
    fn wait(&self, deadline: Instant, changes: Option<u64>) -> bool {
        let mut state = self.lock();
        loop {
            if state.0 {
                return false;
            }
            let now = Instant::now();
            if now >= deadline || changes.is_some_and(|seen| state.1 != seen) {
                return true;
            }
            state = self
                .changed
                .wait_timeout(state, deadline - now)
                .map(|(s, _)| s)
                .unwrap_or_else(|p| p.into_inner().0);
        }
    }

    /// Sleeps until `deadline`, woken early by a signal; returns whether none came.
    fn sleep_until(&self, deadline: Instant) -> bool {
        self.wait(deadline, None)
    }
}

impl GraphWatcher for Wakeup {
    fn graph_changed(&self, _graph: &GraphView<'_>) {
        self.lock().1 += 1;
        self.changed.notify_all();
    }
}

/// Stops `wakeup` on SIGINT or SIGTERM. Without the handler a signal ends the process at once,
/// which is still an end.
fn interrupt_on_signal(wakeup: &Arc<Wakeup>) {
    let wakeup = Arc::clone(wakeup);
    let _ = ctrlc::set_handler(move || wakeup.stop());
}

/// ros2cli's exit on an interrupt: status `signal.SIGINT` (2), nothing printed.
fn interrupted() -> CliError {
    CliError {
        message: String::new(),
        code: 2,
    }
}

/// The writer on the graph.
struct Publisher<'a> {
    session: &'a Session,
    writer: &'a RawWriter,
    topic: &'a str,
    stop: &'a Wakeup,
}

impl Publisher<'_> {
    /// rclpy's `get_subscription_count`: the subscriptions of the topic the writer is matched
    /// with.
    fn subscription_count(&self) -> usize {
        let readers = self
            .session
            .graph
            .read(|c| c.subscriptions_info_by_topic(self.topic, false));
        let gid = self.writer.gid();
        readers
            .iter()
            .filter(|r| self.session.graph.is_matched(gid, r.endpoint_gid))
            .count()
    }

    /// pub.py's wait: the count checked (here at every graph change, where pub.py looks every
    /// 100 ms), a line printed every second, ros2cli's error (its spelling kept) once `max_wait`
    /// has passed. `Ok(false)` when interrupted.
    /// With `json`, the waiting line goes to stderr, leaving stdout to the JSON lines.
    fn wait_for_subscriptions(
        &self,
        wanted: u64,
        max_wait: Option<f64>,
        json: bool,
    ) -> Result<bool, CliError> {
        let wanted_count = usize::try_from(wanted).unwrap_or(usize::MAX);
        let started = Instant::now();
        let give_up = max_wait.map(|m| started + Duration::from_secs_f64(m.max(0.0)));
        let mut next_log = started;
        loop {
            let changes = self.stop.changes();
            if self.subscription_count() >= wanted_count {
                return Ok(true);
            }
            let now = Instant::now();
            if now >= next_log {
                let line = format!("Waiting for at least {wanted} matching subscription(s)...");
                if json {
                    eprintln!("{line}");
                } else {
                    println!("{line}");
                }
                next_log = now + WAIT_LOG_PERIOD;
            }
            if give_up.is_some_and(|g| now >= g) {
                return Err(CliError::new(format!(
                    "Timed out waiting for subscribers: Expected {wanted} subcribers but \
                     only got {} subscribers",
                    self.subscription_count()
                )));
            }
            // Woken by the graph's next change (a match is one), the next log line, the
            // limit, or a signal: no polling.
            let until = give_up.map_or(next_log, |g| g.min(next_log));
            if !self.stop.wait(until, Some(changes)) {
                return Ok(false);
            }
        }
    }

    /// ros2cli's `time.sleep(keep_alive)` after the last message; the matched reliable readers'
    /// acknowledgments are awaited within that time.
    fn linger(&self, keep_alive: Duration) {
        let end = Instant::now() + keep_alive;
        self.writer.wait_for_acknowledgments(keep_alive);
        self.stop.sleep_until(end);
    }
}
