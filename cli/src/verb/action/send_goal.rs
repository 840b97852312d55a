//! `horus-ros action send_goal` (ros2action 0.32 `verb/send_goal.py`): sends one goal to an
//! action server of any type and prints what ros2action prints — the goal, its id, with
//! `--feedback` each feedback message of that goal, then the result and the final status. An
//! interrupt (Ctrl-C) while the goal is accepted or executing cancels it first, as
//! ros2action's `finally` block does.
//!
//! The CLI joins as an action client as rcl_action makes one (`action_client.c`): clients of
//! `<action>/_action/send_goal`, `cancel_goal` and `get_result`, subscriptions to
//! `_action/feedback` (default QoS) and `_action/status` (`rcl_action_qos_profile_status_default`),
//! so the graph shows it as the action's client. The action type is read from its `.action`
//! file on `AMENT_PREFIX_PATH`, as ros2action imports it.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use horus_ros_graph::GraphCache;
use horus_ros_msgs::action_msgs::msg::GoalStatus;
use horus_ros_msgs::action_msgs::srv::{CancelGoal, CancelGoalRequest, CancelGoalResponse};
use horus_ros_msgs::unique_identifier_msgs::msg::UUID;
use horus_ros_msgs::{Message, Service, TypeDescription};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{RawEndpointSpec, RawReader, RawReaderWaker};
use horus_ros_services::{EndpointBuilder, ServiceClient};
use serde_json::json;
use yaml_rust2::{Yaml, YamlLoader};

use crate::dynamic::convert::{to_ordereddict, ConvertOptions};
use crate::dynamic::json::to_json;
use crate::dynamic::pyyaml::dump;
use crate::dynamic::yaml::{fill_from_doc, FillError};
use crate::dynamic::{sub_description, Schema, ServiceType, Value};
use crate::session::Session;
use crate::verb::interface::catalog::Catalog;
use crate::verb::interface::definition::describe_files;
use crate::{CliError, Global};
use horus_ros_services::DynamicServiceClient;

/// How long the server may take to answer the goal or a cancel: a bound of our own (rclpy waits
/// without one).
const ANSWER_TIMEOUT: Duration = Duration::from_secs(60);
/// How long a result may take: a goal may run for hours; a server that goes away ends the wait
/// at once (`ServerGone`).
const RESULT_TIMEOUT: Duration = Duration::from_secs(7 * 24 * 3600);
/// The bound on one wait for the server to be known; the wait goes on after it (ros2action
/// waits forever).
const SERVER_WAIT: Duration = Duration::from_secs(3600);

/// Arguments of `action send_goal`.
#[derive(Debug, clap::Args)]
pub struct SendGoalArgs {
    /// Name of the ROS action (e.g. '/fibonacci').
    pub action_name: String,
    /// Type of the ROS action (e.g. 'example_interfaces/action/Fibonacci').
    pub action_type: String,
    /// Goal request values in YAML format (e.g. '{order: 10}').
    #[arg(default_value = "{}", conflicts_with = "stdin")]
    pub goal: String,
    /// Read goal from standard input.
    #[arg(long)]
    pub stdin: bool,
    /// Echo feedback messages for the goal.
    #[arg(short = 'f', long)]
    pub feedback: bool,
}

/// The class of the exception rosidl_runtime_py's `set_message_fields` raises for `e`: a key
/// that is no field is `getattr`'s `AttributeError`, a value that is no mapping its `TypeError`,
/// a string `int()` or `float()` cannot read their `ValueError`, a value the field's setter
/// refuses the setter's `AssertionError`.
fn python_exception(e: &FillError) -> &'static str {
    match e {
        FillError::NoSuchField { .. } => "AttributeError",
        FillError::NotADictionary { .. } => "TypeError",
        FillError::InvalidInteger { .. } | FillError::InvalidFloat { .. } => "ValueError",
        FillError::WrongType { .. }
        | FillError::OutOfRange { .. }
        | FillError::TooLong { .. }
        | FillError::WrongContainer { .. } => "AssertionError",
        _ => "Exception",
    }
}

/// Where the verb is, for the interrupt handler: before a goal is accepted an interrupt ends
/// the process at once (there is nothing to cancel); after, it wakes the wait to cancel.
const PHASE_WAITING: u8 = 0;
const PHASE_GOAL: u8 = 1;
const PHASE_INTERRUPTED: u8 = 2;

/// Runs `action send_goal`.
pub fn run(global: &Global, args: &SendGoalArgs) -> Result<(), CliError> {
    let action_type = normalize_action_type(&args.action_type)?;
    let goal_text = if args.stdin {
        std::io::read_to_string(std::io::stdin())
            .map_err(|e| CliError::new(format!("Cannot read the goal from stdin: {e}")))?
    } else {
        args.goal.clone()
    };
    let goal_doc = YamlLoader::load_from_str(&goal_text)
        .map_err(|e| CliError::new(format!("Failed to parse the goal as YAML: {e}")))?
        .into_iter()
        .next()
        .unwrap_or(Yaml::Null);
    // As ros2action, the type must be installed: a Jazzy node's `~/get_type_description` cannot
    // describe it, because rcl registers the action's services under their service type hashes
    // while their endpoints announce only the request and response hashes (rmw_fastrtps 8.4), so
    // no hash on the wire names the goal or the result.
    let types = types_from_files(&action_type).map_err(|e| {
        tracing::debug!(%action_type, "not on AMENT_PREFIX_PATH: {e}");
        CliError::new("The passed action type is invalid")
    })?;

    let node_name = format!("_ros2cli_send_goal_{}", action_type.replace('/', "_"));
    let session = Session::join_as(global, &node_name)?;
    let action = ServiceName::expand(
        &args.action_name,
        session.node.name(),
        session.node.namespace(),
    )
    .map_err(|e| CliError::new(format!("Invalid action name '{}': {e}", args.action_name)))?;
    let action = action.as_str().to_owned();

    let phase = Arc::new(AtomicU8::new(PHASE_WAITING));
    let wakers: Arc<Mutex<Vec<RawReaderWaker>>> = Arc::default();
    {
        let (phase, wakers) = (Arc::clone(&phase), Arc::clone(&wakers));
        // ros2cli's exit on an interrupt before a goal is out: status 2, nothing printed.
        let _ = ctrlc::set_handler(move || {
            if phase.swap(PHASE_INTERRUPTED, Ordering::SeqCst) == PHASE_WAITING {
                std::process::exit(2);
            }
            for w in wakers.lock().unwrap_or_else(|p| p.into_inner()).iter() {
                w.wake();
            }
        });
    }

    // As send_goal.py: the goal is filled before the wait for a server, so a bad goal fails at
    // once.
    let goal_id: [u8; 16] = *uuid::Uuid::new_v4().as_bytes();
    let request = types.goal_request(&goal_id, &goal_doc)?;
    if !global.json {
        println!("Waiting for an action server to become available...");
    }
    wait_for_server(&session, &action, &action_type);
    tracing::debug!(action, "the action server is known");
    // Each call waits until its server is matched both ways (rclcpp's `service_is_ready`), so
    // neither the goal nor its answer can be lost, and says why when the server cannot be
    // called (e.g. a wire convention this backend does not speak).
    let client = ActionClient::open(&session, &action, &types)?;

    let goal = match &request {
        Value::Struct(fields) => fields.get(1).cloned().unwrap_or(Value::Struct(vec![])),
        _ => Value::Struct(vec![]),
    };
    if global.json {
        print_json(
            json!({"event": "sending_goal", "goal": to_json(types.send_goal.schema(), &types.goal_type, &goal)}),
        );
    } else {
        println!(
            "Sending goal:\n     {}",
            types.yaml(&types.goal_type, &goal)
        );
    }
    let mut send_goal = client.send_goal;
    let response = send_goal
        .call_value(&request, ANSWER_TIMEOUT)
        .map_err(|e| CliError::new(format!("Exception while sending goal: {e}")))?;
    if !field_bool(&response, 0) {
        if global.json {
            print_json(json!({"event": "rejected"}));
        } else {
            println!("Goal was rejected.");
        }
        return Ok(());
    }
    let id_hex: String = goal_id.iter().map(|b| format!("{b:02x}")).collect();
    if global.json {
        print_json(json!({"event": "accepted", "goal_id": id_hex}));
    } else {
        println!("Goal accepted with ID: {id_hex}\n");
    }

    // The result is asked for at once (rclpy's `get_result_async`); its answer comes when the
    // goal ends, on a thread of its own, which wakes the feedback wait.
    let outcome: Arc<Mutex<Option<Result<Value, String>>>> = Arc::default();
    let mut feedback = client.feedback;
    let mut status = client.status;
    wakers
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .push(feedback.waker());
    if phase
        .compare_exchange(
            PHASE_WAITING,
            PHASE_GOAL,
            Ordering::SeqCst,
            Ordering::SeqCst,
        )
        .is_err()
    {
        // Interrupted between the acceptance and here: cancel below.
        feedback.waker().wake();
    }
    {
        let outcome = Arc::clone(&outcome);
        let waker = feedback.waker();
        let mut get_result = client.get_result;
        let request = types.result_request(&goal_id)?;
        std::thread::spawn(move || {
            let answer = get_result
                .call_value(&request, RESULT_TIMEOUT)
                .map_err(|e| e.to_string());
            *outcome.lock().unwrap_or_else(|p| p.into_inner()) = Some(answer);
            waker.wake();
        });
    }

    let mut goal_status = GoalStatus::STATUS_UNKNOWN;
    loop {
        feedback.wait(None);
        while let Some(sample) = take(&mut feedback)? {
            let Ok(Value::Struct(fields)) = types.feedback_schema_decode(&sample) else {
                continue;
            };
            if uuid_of(fields.first()) != Some(goal_id) || !args.feedback {
                continue;
            }
            let fb = fields.get(1).cloned().unwrap_or(Value::Struct(vec![]));
            if global.json {
                print_json(
                    json!({"event": "feedback", "feedback": to_json(&types.feedback_schema, &types.feedback_type, &fb)}),
                );
            } else {
                println!(
                    "Feedback:\n    {}",
                    types.yaml_with(&types.feedback_schema, &types.feedback_type, &fb)
                );
            }
        }
        while let Some(sample) = take(&mut status)? {
            if let Some(s) = status_of(&sample, &goal_id) {
                goal_status = s;
            }
        }
        if let Some(answer) = outcome.lock().unwrap_or_else(|p| p.into_inner()).take() {
            let response = answer
                .map_err(|e| CliError::new(format!("Exception while getting result: {e}")))?;
            let status = match &response {
                Value::Struct(f) => match f.first() {
                    Some(Value::Int(s)) => i8::try_from(*s).unwrap_or(GoalStatus::STATUS_UNKNOWN),
                    _ => GoalStatus::STATUS_UNKNOWN,
                },
                _ => GoalStatus::STATUS_UNKNOWN,
            };
            let result = match &response {
                Value::Struct(f) => f.get(1).cloned().unwrap_or(Value::Struct(vec![])),
                _ => Value::Struct(vec![]),
            };
            if global.json {
                print_json(json!({
                    "event": "result",
                    "status": status_name(status),
                    "result": to_json(types.get_result.schema(), &types.result_type, &result),
                }));
            } else {
                println!("Result:\n    {}", types.yaml(&types.result_type, &result));
                println!("Goal finished with status: {}", status_name(status));
            }
            return Ok(());
        }
        if phase.load(Ordering::SeqCst) == PHASE_INTERRUPTED {
            if goal_status == GoalStatus::STATUS_ACCEPTED
                || goal_status == GoalStatus::STATUS_EXECUTING
            {
                cancel(global, client.cancel, &goal_id)?;
            }
            return Err(CliError {
                message: String::new(),
                code: 2,
            });
        }
    }
}

/// ros2action's cancel in its `finally` block, with its checks of the answer.
fn cancel(
    global: &Global,
    mut client: ServiceClient<CancelGoal>,
    goal_id: &[u8; 16],
) -> Result<(), CliError> {
    if !global.json {
        println!("Canceling goal...");
    }
    let mut request = CancelGoalRequest::default();
    request.goal_info.goal_id = UUID { uuid: *goal_id };
    let response: CancelGoalResponse = client
        .call(request, ANSWER_TIMEOUT)
        .map_err(|e| CliError::new(format!("Exception while canceling goal: {e}")))?;
    match response.goals_canceling.as_slice() {
        [] => Err(CliError::new("Failed to cancel goal")),
        [one] if one.goal_id.uuid != *goal_id => {
            Err(CliError::new("Canceled goal with incorrect goal ID"))
        }
        [_] => {
            if global.json {
                print_json(json!({"event": "canceled"}));
            } else {
                println!("Goal canceled.");
            }
            Ok(())
        }
        _ => Err(CliError::new("More than one goal canceled")),
    }
}

/// rosidl_runtime_py `get_action`'s names: `pkg/action/Name`, or `pkg/Name`.
fn normalize_action_type(given: &str) -> Result<String, CliError> {
    let invalid = || CliError::new("The passed action type is invalid");
    let parts: Vec<&str> = given.split('/').collect();
    match parts.as_slice() {
        [pkg, name] if !pkg.is_empty() && !name.is_empty() => Ok(format!("{pkg}/action/{name}")),
        [pkg, "action", name] if !pkg.is_empty() && !name.is_empty() => Ok(given.to_owned()),
        _ => Err(invalid()),
    }
}

/// rcl_action `rcl_action_server_is_available`: servers of the three services and publishers of
/// feedback and status are known. Woken by graph changes; ros2action waits without a bound.
fn wait_for_server(session: &Session, action: &str, action_type: &str) {
    while !session
        .graph
        .wait_until(SERVER_WAIT, |c| server_known(c, action, action_type))
    {}
}

fn server_known(c: &GraphCache, action: &str, action_type: &str) -> bool {
    let serves = |suffix: &str, ty: &str| {
        c.servers_info_by_service(&format!("{action}/_action/{suffix}"), false)
            .is_ok_and(|s| s.iter().any(|s| s.service_type == ty))
    };
    serves("send_goal", &format!("{action_type}_SendGoal"))
        && serves("get_result", &format!("{action_type}_GetResult"))
        && serves("cancel_goal", CancelGoal::TYPE_NAME)
        && c.count_publishers(&format!("{action}/_action/feedback")) > 0
        && c.count_publishers(&format!("{action}/_action/status")) > 0
}

/// The run-time types of one action.
struct ActionTypes {
    send_goal: ServiceType,
    get_result: ServiceType,
    feedback_schema: Schema,
    feedback_description: TypeDescription,
    goal_type: String,
    result_type: String,
    feedback_message_type: String,
    feedback_type: String,
}

impl ActionTypes {
    fn new(
        action_type: &str,
        send_goal: ServiceType,
        get_result: ServiceType,
        feedback_description: TypeDescription,
    ) -> Result<Self, String> {
        let feedback_message_type = format!("{action_type}_FeedbackMessage");
        let mut feedback_schema =
            Schema::from_description(&feedback_description).map_err(|e| e.to_string())?;
        feedback_schema
            .check(&feedback_message_type)
            .map_err(|e| e.to_string())?;
        // Nothing else to add: the feedback message holds the feedback type.
        let _ = &mut feedback_schema;
        Ok(Self {
            send_goal,
            get_result,
            feedback_schema,
            feedback_description,
            goal_type: format!("{action_type}_Goal"),
            result_type: format!("{action_type}_Result"),
            feedback_message_type,
            feedback_type: format!("{action_type}_Feedback"),
        })
    }

    /// The `SendGoal` request: the goal id and the goal filled from YAML.
    fn goal_request(&self, goal_id: &[u8; 16], goal: &Yaml) -> Result<Value, CliError> {
        let mut request = yaml_rust2::yaml::Hash::new();
        request.insert(Yaml::String("goal_id".into()), uuid_yaml(goal_id));
        request.insert(Yaml::String("goal".into()), goal.clone());
        fill_from_doc(
            self.send_goal.schema(),
            self.send_goal.request_type(),
            &Yaml::Hash(request),
        )
        .map_err(|e| {
            // send_goal.py: `'Failed to populate message fields: {!r}'.format(ex)`.
            CliError::new(format!(
                "Failed to populate message fields: {}({})",
                python_exception(&e),
                crate::dynamic::repr::py_str(&e.to_string())
            ))
        })
    }

    /// The `GetResult` request of a goal.
    fn result_request(&self, goal_id: &[u8; 16]) -> Result<Value, CliError> {
        let mut request = yaml_rust2::yaml::Hash::new();
        request.insert(Yaml::String("goal_id".into()), uuid_yaml(goal_id));
        fill_from_doc(
            self.get_result.schema(),
            self.get_result.request_type(),
            &Yaml::Hash(request),
        )
        .map_err(|e| CliError::new(format!("Cannot make the result request: {e}")))
    }

    fn feedback_schema_decode(
        &self,
        sample: &horus_ros_rmw::RawSample,
    ) -> Result<Value, crate::dynamic::cdr::DecodeError> {
        crate::dynamic::cdr::decode(
            &self.feedback_schema,
            &self.feedback_message_type,
            &sample.body,
            sample.big_endian,
        )
    }

    /// rosidl_runtime_py `message_to_yaml` of a part of the send-goal or get-result types.
    fn yaml(&self, type_name: &str, value: &Value) -> String {
        let schema = if self.send_goal.schema().get(type_name).is_ok() {
            self.send_goal.schema()
        } else {
            self.get_result.schema()
        };
        self.yaml_with(schema, type_name, value)
    }

    /// `message_to_yaml` with ros2action's options (no truncation, arrays and strings shown).
    fn yaml_with(&self, schema: &Schema, type_name: &str, value: &Value) -> String {
        dump(
            &to_ordereddict(schema, type_name, value, ConvertOptions::default()),
            false,
        )
    }
}

fn uuid_yaml(goal_id: &[u8; 16]) -> Yaml {
    let mut id = yaml_rust2::yaml::Hash::new();
    id.insert(
        Yaml::String("uuid".into()),
        Yaml::Array(
            goal_id
                .iter()
                .map(|b| Yaml::Integer(i64::from(*b)))
                .collect(),
        ),
    );
    Yaml::Hash(id)
}

/// The action's types from its `.action` file on `AMENT_PREFIX_PATH`.
fn types_from_files(action_type: &str) -> Result<ActionTypes, String> {
    let catalog = Catalog::from_env();
    let package = action_type.split('/').next().unwrap_or_default();
    let path = catalog
        .index
        .find_interface(action_type)
        .map_err(|e| e.to_string())?;
    let description =
        describe_files(&catalog, package, &path, action_type).map_err(|e| e.message)?;
    let send_goal = ServiceType::from_descriptions(
        &format!("{action_type}_SendGoal"),
        std::slice::from_ref(&description),
    )
    .map_err(|e| e.to_string())?;
    let get_result = ServiceType::from_descriptions(
        &format!("{action_type}_GetResult"),
        std::slice::from_ref(&description),
    )
    .map_err(|e| e.to_string())?;
    let feedback = sub_description(&description, &format!("{action_type}_FeedbackMessage"))
        .map_err(|e| e.to_string())?;
    ActionTypes::new(action_type, send_goal, get_result, feedback)
}

/// The CLI's action client: rcl_action's five entities.
struct ActionClient {
    send_goal: DynamicServiceClient,
    get_result: DynamicServiceClient,
    cancel: ServiceClient<CancelGoal>,
    feedback: RawReader,
    status: RawReader,
}

impl ActionClient {
    fn open(session: &Session, action: &str, types: &ActionTypes) -> Result<Self, CliError> {
        let node = &session.node;
        let send_goal = DynamicServiceClient::builder(types.send_goal.clone())
            .name(format!("{action}/_action/send_goal"))
            .node(node)
            .build()?;
        let cancel = ServiceClient::<CancelGoal>::builder()
            .name(format!("{action}/_action/cancel_goal"))
            .node(node)
            .build()?;
        let get_result = DynamicServiceClient::builder(types.get_result.clone())
            .name(format!("{action}/_action/get_result"))
            .node(node)
            .build()?;
        let topic = |suffix: &str| -> Result<String, CliError> {
            let name = horus_ros_rmw::names::TopicName::new(&format!("{action}/_action/{suffix}"))
                .map_err(|e| CliError::new(e.to_string()))?;
            Ok(name.to_dds_topic_name(false))
        };
        let feedback = node.create_raw_reader(&RawEndpointSpec {
            dds_topic_name: topic("feedback")?,
            dds_type_name: horus_ros_msgs::dds_type_name(&types.feedback_message_type),
            type_hash: types.feedback_description.compute_type_hash(),
            // rcl_action `rcl_action_client_get_default_options`: feedback `rmw_qos_profile_default`.
            qos: Qos::default_profile(),
            service_id: None,
        })?;
        let status = node.create_raw_reader(&RawEndpointSpec {
            dds_topic_name: topic("status")?,
            dds_type_name: horus_ros_msgs::dds_type_name(
                horus_ros_msgs::action_msgs::msg::GoalStatusArray::TYPE_NAME,
            ),
            type_hash: horus_ros_msgs::action_msgs::msg::GoalStatusArray::type_hash(),
            qos: Qos::action_status_default(),
            service_id: None,
        })?;
        Ok(Self {
            send_goal,
            get_result,
            cancel,
            feedback,
            status,
        })
    }
}

fn take(reader: &mut RawReader) -> Result<Option<horus_ros_rmw::RawSample>, CliError> {
    match reader.take() {
        Ok(s) => Ok(s),
        // A sample that does not decode is dropped; the next one is read.
        Err(e) => {
            tracing::warn!("{e}");
            Ok(None)
        }
    }
}

/// The 16 bytes of a `unique_identifier_msgs/UUID` value.
fn uuid_of(value: Option<&Value>) -> Option<[u8; 16]> {
    let Some(Value::Struct(fields)) = value else {
        return None;
    };
    let Some(Value::List(items)) = fields.first() else {
        return None;
    };
    let bytes: Vec<u8> = items
        .iter()
        .filter_map(|v| match v {
            Value::Int(i) => u8::try_from(*i).ok(),
            Value::Byte(b) => Some(*b),
            _ => None,
        })
        .collect();
    bytes.try_into().ok()
}

/// The status of goal `goal_id` in a `GoalStatusArray` sample, when it lists it.
fn status_of(sample: &horus_ros_rmw::RawSample, goal_id: &[u8; 16]) -> Option<i8> {
    let array: horus_ros_msgs::action_msgs::msg::GoalStatusArray = if sample.big_endian {
        horus_ros_msgs::cdr::from_cdr_body::<_, byteorder::BigEndian>(&sample.body).ok()?
    } else {
        horus_ros_msgs::cdr::from_cdr_body::<_, byteorder::LittleEndian>(&sample.body).ok()?
    };
    array
        .status_list
        .iter()
        .find(|s| s.goal_info.goal_id.uuid == *goal_id)
        .map(|s| s.status)
}

fn field_bool(value: &Value, index: usize) -> bool {
    matches!(value, Value::Struct(f) if matches!(f.get(index), Some(Value::Bool(true))))
}

/// send_goal.py `_goal_status_to_string`.
fn status_name(status: i8) -> &'static str {
    match status {
        GoalStatus::STATUS_ACCEPTED => "ACCEPTED",
        GoalStatus::STATUS_EXECUTING => "EXECUTING",
        GoalStatus::STATUS_CANCELING => "CANCELING",
        GoalStatus::STATUS_SUCCEEDED => "SUCCEEDED",
        GoalStatus::STATUS_CANCELED => "CANCELED",
        GoalStatus::STATUS_ABORTED => "ABORTED",
        _ => "UNKNOWN",
    }
}

fn print_json(value: serde_json::Value) {
    println!("{value}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn action_types_as_get_action_takes_them() {
        assert_eq!(
            normalize_action_type("test_msgs/Fibonacci").ok(),
            Some("test_msgs/action/Fibonacci".to_owned())
        );
        assert_eq!(
            normalize_action_type("test_msgs/action/Fibonacci").ok(),
            Some("test_msgs/action/Fibonacci".to_owned())
        );
        for bad in ["Fibonacci", "test_msgs/msg/Fibonacci", "a/b/c/d", "/x"] {
            assert!(normalize_action_type(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn statuses_as_ros2action_names_them() {
        assert_eq!(status_name(GoalStatus::STATUS_SUCCEEDED), "SUCCEEDED");
        assert_eq!(status_name(GoalStatus::STATUS_CANCELED), "CANCELED");
        assert_eq!(status_name(42), "UNKNOWN");
    }
}
