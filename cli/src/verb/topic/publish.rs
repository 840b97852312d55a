//! What `topic pub` needs besides its loop: the message type resolved at run time
//! ([`MessageType`]), ros2cli's QoS options ([`QosArgs`], ros2topic jazzy `api/__init__.py`
//! `add_qos_arguments` / `profile_configure_short_keys`), and the time stamps ros2cli fills at
//! each publication ([`Stamps`], rosidl_runtime_py jazzy `set_message_fields` with
//! `expand_header_auto` and `expand_time_now`).

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use horus_ros_msgs::message::dds_type_name;
use horus_ros_msgs::{TypeDescription, TypeHash};
use horus_ros_rmw::qos::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, ReliabilityPolicy,
};
use yaml_rust2::Yaml;

use crate::dynamic::compiled::compiled_type;
use crate::dynamic::{Container, Elem, Schema, Value};
use crate::session::Session;
use crate::verb::interface::catalog::Catalog;
use crate::verb::interface::definition;
use crate::verb::service::call::describe;
use crate::CliError;

/// A message type known at run time: its structs, DDS name and RIHS01 hash.
pub struct MessageType {
    /// `pkg/msg/Name`.
    pub name: String,
    /// The structs of the type and of every type it uses.
    pub schema: Schema,
    /// `pkg::msg::dds_::Name_`.
    pub dds_type_name: String,
    /// The RIHS01 hash of the type.
    pub type_hash: TypeHash,
}

/// `pkg/msg/Name`, or `pkg/Name` completed with `msg` as rosidl_runtime_py's `get_message`
/// completes it; anything else is ros2cli's `The passed message type is invalid`.
pub fn normalize_type(t: &str) -> Result<String, CliError> {
    let parts: Vec<&str> = t.split('/').collect();
    let valid = |s: &str| {
        !s.is_empty()
            && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
            && !s.starts_with(|c: char| c.is_ascii_digit())
    };
    match parts.as_slice() {
        [pkg, name] if valid(pkg) && valid(name) => Ok(format!("{pkg}/msg/{name}")),
        [pkg, "msg", name] if valid(pkg) && valid(name) => Ok(t.to_owned()),
        _ => Err(CliError::new("The passed message type is invalid")),
    }
}

impl MessageType {
    /// The type from its description (which must contain it and what it uses).
    fn from_description(name: &str, description: &TypeDescription) -> Result<Self, CliError> {
        let unusable = |e| CliError::new(format!("The message type '{name}' cannot be used: {e}"));
        let schema = Schema::from_description(description).map_err(unusable)?;
        schema.check(name).map_err(unusable)?;
        Ok(Self {
            name: name.to_owned(),
            schema,
            dds_type_name: dds_type_name(name),
            type_hash: description.compute_type_hash(),
        })
    }

    /// The type as horus-ros knows it without a graph: compiled in, else from its interface
    /// file in a package on `AMENT_PREFIX_PATH`; `Ok(None)` when neither has it.
    pub fn without_graph(name: &str) -> Result<Option<Self>, CliError> {
        if let Some(t) = compiled_type(name) {
            return Self::from_description(name, &(t.describe)()).map(Some);
        }
        let catalog = Catalog::from_env();
        let Ok(path) = catalog.index.find_interface(name) else {
            return Ok(None);
        };
        let (package, _, _) = definition::split_type(name)?;
        let description = definition::describe_files(&catalog, package, &path, name)?;
        Self::from_description(name, &description).map(Some)
    }

    /// The type as a node of the graph that publishes or subscribes to it describes it
    /// (`~/get_type_description`); the error says which nodes were asked and why they failed.
    pub fn from_graph(session: &Session, name: &str, timeout: Duration) -> Result<Self, CliError> {
        let description = describe::fetch_message(&session.node, &session.graph, name, timeout)
            .map_err(|why| {
                CliError::new(format!(
                    "The passed message type is invalid: '{name}' is not built into \
                         horus-ros nor in a package on AMENT_PREFIX_PATH, and the graph does not \
                         describe it: {why}"
                ))
            })?;
        Self::from_description(name, &description)
    }
}

/// rclpy's `QoSPresetProfiles` short keys (`--qos-profile`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum ProfileKey {
    /// `qos_profile_unknown`.
    Unknown,
    /// `qos_profile_default`.
    Default,
    /// `qos_profile_system_default`.
    SystemDefault,
    /// `qos_profile_sensor_data`.
    SensorData,
    /// `qos_profile_services_default`.
    ServicesDefault,
    /// `qos_profile_parameters`.
    Parameters,
    /// `qos_profile_parameter_events`.
    ParameterEvents,
    /// `rcl_action_qos_profile_status_default`.
    ActionStatusDefault,
    /// `qos_profile_best_available`.
    BestAvailable,
}

impl ProfileKey {
    /// The profile.
    pub fn profile(self) -> Qos {
        match self {
            Self::Unknown => Qos::unknown(),
            Self::Default => Qos::default_profile(),
            Self::SystemDefault => Qos::system_default(),
            Self::SensorData => Qos::sensor_data(),
            Self::ServicesDefault => Qos::services_default(),
            Self::Parameters => Qos::parameters(),
            Self::ParameterEvents => Qos::parameter_events(),
            Self::ActionStatusDefault => Qos::action_status_default(),
            Self::BestAvailable => Qos::best_available(),
        }
    }
}

/// rclpy's `HistoryPolicy` short keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum HistoryKey {
    /// SYSTEM_DEFAULT.
    SystemDefault,
    /// KEEP_LAST.
    KeepLast,
    /// KEEP_ALL.
    KeepAll,
    /// UNKNOWN.
    Unknown,
}

/// rclpy's `ReliabilityPolicy` short keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum ReliabilityKey {
    /// SYSTEM_DEFAULT.
    SystemDefault,
    /// RELIABLE.
    Reliable,
    /// BEST_EFFORT.
    BestEffort,
    /// UNKNOWN.
    Unknown,
    /// BEST_AVAILABLE.
    BestAvailable,
}

/// rclpy's `DurabilityPolicy` short keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum DurabilityKey {
    /// SYSTEM_DEFAULT.
    SystemDefault,
    /// TRANSIENT_LOCAL.
    TransientLocal,
    /// VOLATILE.
    Volatile,
    /// UNKNOWN.
    Unknown,
    /// BEST_AVAILABLE.
    BestAvailable,
}

/// rclpy's `LivelinessPolicy` short keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[value(rename_all = "snake_case")]
pub enum LivelinessKey {
    /// SYSTEM_DEFAULT.
    SystemDefault,
    /// AUTOMATIC.
    Automatic,
    /// MANUAL_BY_TOPIC.
    ManualByTopic,
    /// UNKNOWN.
    Unknown,
    /// BEST_AVAILABLE.
    BestAvailable,
}

/// ros2topic's QoS options for publishing (`add_qos_arguments(parser, 'publish', 'default')`).
#[derive(Debug, Clone, clap::Args)]
pub struct QosArgs {
    /// Quality of service preset profile to publish with (default: default).
    #[arg(long, value_enum, default_value = "default")]
    pub qos_profile: ProfileKey,
    /// Queue size setting to publish with (overrides depth value of --qos-profile option).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub qos_depth: Option<i64>,
    /// History of samples setting to publish with (overrides history value of --qos-profile
    /// option, default: keep_last).
    #[arg(long, value_enum)]
    pub qos_history: Option<HistoryKey>,
    /// Quality of service reliability setting to publish with (overrides reliability value of
    /// --qos-profile option, default: Compatible profile with running endpoints ).
    #[arg(long, value_enum)]
    pub qos_reliability: Option<ReliabilityKey>,
    /// Quality of service durability setting to publish with (overrides durability value of
    /// --qos-profile option, default: Compatible profile with running endpoints ).
    #[arg(long, value_enum)]
    pub qos_durability: Option<DurabilityKey>,
    /// Quality of service liveliness setting to publish with (overrides liveliness value of
    /// --qos-profile option.
    #[arg(long, value_enum)]
    pub qos_liveliness: Option<LivelinessKey>,
    /// Quality of service liveliness lease duration setting to publish with (overrides
    /// liveliness lease duration value of --qos-profile option.
    #[arg(
        long,
        value_name = "QOS_LIVELINESS_LEASE_DURATION_SECONDS",
        allow_negative_numbers = true
    )]
    pub qos_liveliness_lease_duration_seconds: Option<f64>,
}

impl QosArgs {
    /// The profile, then each option given over it, as ros2topic's
    /// `profile_configure_short_keys` does (a depth only when positive; a transient-local
    /// profile of depth 0 gets depth 1).
    pub fn qos(&self) -> Qos {
        let mut qos = self.qos_profile.profile();
        if let Some(h) = self.qos_history {
            qos.history = match h {
                HistoryKey::SystemDefault => HistoryPolicy::SystemDefault,
                HistoryKey::KeepLast => HistoryPolicy::KeepLast,
                HistoryKey::KeepAll => HistoryPolicy::KeepAll,
                HistoryKey::Unknown => HistoryPolicy::Unknown,
            };
        }
        if let Some(d) = self.qos_durability {
            qos.durability = match d {
                DurabilityKey::SystemDefault => DurabilityPolicy::SystemDefault,
                DurabilityKey::TransientLocal => DurabilityPolicy::TransientLocal,
                DurabilityKey::Volatile => DurabilityPolicy::Volatile,
                DurabilityKey::Unknown => DurabilityPolicy::Unknown,
                DurabilityKey::BestAvailable => DurabilityPolicy::BestAvailable,
            };
        }
        if let Some(r) = self.qos_reliability {
            qos.reliability = match r {
                ReliabilityKey::SystemDefault => ReliabilityPolicy::SystemDefault,
                ReliabilityKey::Reliable => ReliabilityPolicy::Reliable,
                ReliabilityKey::BestEffort => ReliabilityPolicy::BestEffort,
                ReliabilityKey::Unknown => ReliabilityPolicy::Unknown,
                ReliabilityKey::BestAvailable => ReliabilityPolicy::BestAvailable,
            };
        }
        if let Some(l) = self.qos_liveliness {
            qos.liveliness = match l {
                LivelinessKey::SystemDefault => LivelinessPolicy::SystemDefault,
                LivelinessKey::Automatic => LivelinessPolicy::Automatic,
                LivelinessKey::ManualByTopic => LivelinessPolicy::ManualByTopic,
                LivelinessKey::Unknown => LivelinessPolicy::Unknown,
                LivelinessKey::BestAvailable => LivelinessPolicy::BestAvailable,
            };
        }
        // Python's truthiness: 0 and NaN-free negatives leave the lease as it is.
        if let Some(s) = self.qos_liveliness_lease_duration_seconds {
            if s > 0.0 && s.is_finite() {
                qos.liveliness_lease_duration = QosDuration::from(Duration::from_secs_f64(s));
            }
        }
        match self.qos_depth.and_then(|d| usize::try_from(d).ok()) {
            Some(d) if d > 0 => qos.depth = d,
            _ => {
                if qos.durability == DurabilityPolicy::TransientLocal && qos.depth == 0 {
                    qos.depth = 1;
                }
            }
        }
        qos
    }
}

/// The time fields ros2cli sets to the current time at each publication: a `std_msgs/Header`
/// given as `auto` (its `stamp`) and a `builtin_interfaces/Time` given as `now`, found by
/// [`Stamps::take`]. Each is a path of indices from the message to the `Time` value (a struct's
/// field, or a sequence's element).
#[derive(Debug, Default)]
pub struct Stamps(Vec<Vec<usize>>);

const HEADER: &str = "std_msgs/msg/Header";
const TIME: &str = "builtin_interfaces/msg/Time";

impl Stamps {
    /// Takes out of `doc` (values for a message of type `type_name`) the `auto` headers and
    /// `now` times, as rosidl_runtime_py's `set_message_fields(…, expand_header_auto=True,
    /// expand_time_now=True)` does: those fields keep their defaults and are stamped at each
    /// publication. Values of any other shape are left for the filling to judge.
    pub fn take(schema: &Schema, type_name: &str, doc: &mut Yaml) -> Self {
        let mut stamps = Self::default();
        stamps.walk(schema, type_name, doc, &mut Vec::new());
        stamps
    }

    /// Whether there is no field to stamp.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    fn walk(&mut self, schema: &Schema, type_name: &str, doc: &mut Yaml, path: &mut Vec<usize>) {
        let (Ok(s), Yaml::Hash(map)) = (schema.get(type_name), doc) else {
            return;
        };
        let keys: Vec<Yaml> = map.keys().cloned().collect();
        for key in keys {
            let Yaml::String(field) = &key else { continue };
            let Some(index) = s.members.iter().position(|m| &m.name == field) else {
                continue;
            };
            let member = &s.members[index];
            let Elem::Nested(nested) = &member.ty.elem else {
                continue;
            };
            let Some(value) = map.get_mut(&key) else {
                continue;
            };
            path.push(index);
            match (member.ty.container, value) {
                (Container::Single, Yaml::String(v)) if nested == HEADER && v == "auto" => {
                    if let Some(stamp) = header_stamp(schema) {
                        let mut p = path.clone();
                        p.push(stamp);
                        self.0.push(p);
                        map.remove(&key);
                    }
                }
                (Container::Single, Yaml::String(v))
                    if nested == TIME && v == "now" && is_time(schema) =>
                {
                    self.0.push(path.clone());
                    map.remove(&key);
                }
                (Container::Single, value @ Yaml::Hash(_)) => {
                    self.walk(schema, nested, value, path);
                }
                (Container::Array(_) | Container::Sequence(_), Yaml::Array(items)) => {
                    for (i, item) in items.iter_mut().enumerate() {
                        path.push(i);
                        self.walk(schema, nested, item, path);
                        path.pop();
                    }
                }
                _ => {}
            }
            path.pop();
        }
    }

    /// Sets every stamped field of `message` to `now` (rclpy's `Clock().now().to_msg()`: the
    /// system time, in whole seconds and nanoseconds).
    pub fn apply(&self, message: &mut Value, now: SystemTime) {
        let since = now.duration_since(UNIX_EPOCH).unwrap_or_default();
        let time = Value::Struct(vec![
            Value::Int(i128::from(since.as_secs())),
            Value::Int(i128::from(since.subsec_nanos())),
        ]);
        for path in &self.0 {
            if let Some(at) = at_path(message, path) {
                *at = time.clone();
            }
        }
    }
}

/// The value at `path` (field or element indices) inside `value`.
fn at_path<'a>(value: &'a mut Value, path: &[usize]) -> Option<&'a mut Value> {
    let Some((first, rest)) = path.split_first() else {
        return Some(value);
    };
    match value {
        Value::Struct(items) | Value::List(items) => at_path(items.get_mut(*first)?, rest),
        _ => None,
    }
}

/// The index of `stamp` in `std_msgs/msg/Header`, when it is a `builtin_interfaces/msg/Time`.
fn header_stamp(schema: &Schema) -> Option<usize> {
    let header = schema.get(HEADER).ok()?;
    let index = header.members.iter().position(|m| m.name == "stamp")?;
    let m = &header.members[index];
    (m.ty.container == Container::Single
        && m.ty.elem == Elem::Nested(TIME.to_owned())
        && is_time(schema))
    .then_some(index)
}

/// Whether `builtin_interfaces/msg/Time` is `int32 sec, uint32 nanosec`, as [`Stamps::apply`]
/// writes it.
fn is_time(schema: &Schema) -> bool {
    schema.get(TIME).is_ok_and(|t| {
        t.members
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            == ["sec", "nanosec"]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamic::{repr, yaml};

    fn header_type() -> MessageType {
        MessageType::without_graph("std_msgs/msg/Header")
            .expect("usable")
            .expect("compiled")
    }

    #[test]
    fn message_types_are_normalized_as_rosidl_runtime_py_does() {
        assert_eq!(
            normalize_type("std_msgs/String").expect("short"),
            "std_msgs/msg/String"
        );
        assert_eq!(
            normalize_type("std_msgs/msg/String").expect("full"),
            "std_msgs/msg/String"
        );
        for bad in ["std_srvs/srv/SetBool", "String", "a/b/c/d", "/x"] {
            assert_eq!(
                normalize_type(bad).map_err(|e| e.message),
                Err("The passed message type is invalid".to_owned()),
                "{bad}"
            );
        }
    }

    #[test]
    fn qos_options_override_the_profile_as_ros2topic_does() {
        let args = |f: &dyn Fn(&mut QosArgs)| {
            let mut a = QosArgs {
                qos_profile: ProfileKey::Default,
                qos_depth: None,
                qos_history: None,
                qos_reliability: None,
                qos_durability: None,
                qos_liveliness: None,
                qos_liveliness_lease_duration_seconds: None,
            };
            f(&mut a);
            a.qos()
        };
        assert_eq!(args(&|_| {}), Qos::default_profile());
        let q = args(&|a| {
            a.qos_profile = ProfileKey::SensorData;
            a.qos_depth = Some(3);
            a.qos_reliability = Some(ReliabilityKey::Reliable);
        });
        assert_eq!((q.depth, q.reliability), (3, ReliabilityPolicy::Reliable));
        let q = args(&|a| {
            a.qos_profile = ProfileKey::SystemDefault;
            a.qos_durability = Some(DurabilityKey::TransientLocal);
            a.qos_depth = Some(-1);
        });
        assert_eq!(
            (q.depth, q.durability),
            (1, DurabilityPolicy::TransientLocal)
        );
    }

    #[test]
    fn auto_headers_and_now_times_are_stamped_at_each_publication() {
        let t = header_type();
        let mut doc = yaml_rust2::YamlLoader::load_from_str("{stamp: now, frame_id: map}")
            .expect("yaml")
            .remove(0);
        let stamps = Stamps::take(&t.schema, &t.name, &mut doc);
        assert!(!stamps.is_empty());
        let mut v = yaml::fill_from_doc(&t.schema, &t.name, &doc).expect("filled");
        stamps.apply(&mut v, UNIX_EPOCH + Duration::new(12, 34));
        assert_eq!(
            repr::repr(&t.schema, &t.name, &v),
            "std_msgs.msg.Header(stamp=builtin_interfaces.msg.Time(sec=12, nanosec=34), \
             frame_id='map')"
        );
    }
}
