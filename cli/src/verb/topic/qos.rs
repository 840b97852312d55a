//! ros2cli's QoS options of the topic verbs (ros2topic 0.32.2 `api/__init__.py`
//! `add_qos_arguments`, `qos_profile_from_short_keys` / `profile_configure_short_keys`) and
//! echo's `choose_qos` (`verb/echo.py`): one set of options, worded for subscribing
//! (`add_qos_arguments(parser, 'subscribe', 'sensor_data')`: `topic echo`) or, through
//! [`publishing`], for publishing (`add_qos_arguments(parser, 'publish', 'default')`:
//! `topic pub`).

use clap::builder::Arg;
use horus_ros_rmw::qos::{
    DurabilityPolicy, HistoryPolicy, LivelinessPolicy, Qos, QosDuration, ReliabilityPolicy,
};

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

/// ros2topic's QoS options, worded for subscribing (`--help`); [`publishing`] rewords them.
#[derive(Debug, Clone, clap::Args)]
pub struct QosArgs {
    /// Quality of service preset profile to subscribe with (default: sensor_data)
    #[arg(long, value_enum, default_value = "sensor_data")]
    pub qos_profile: ProfileKey,
    /// Queue size setting to subscribe with (overrides depth value of --qos-profile option)
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub qos_depth: Option<i64>,
    /// History of samples setting to subscribe with (overrides history value of --qos-profile
    /// option, default: keep_last)
    #[arg(long, value_enum)]
    pub qos_history: Option<HistoryKey>,
    /// Quality of service reliability setting to subscribe with (overrides reliability value of
    /// --qos-profile option, default: Compatible profile with running endpoints )
    #[arg(long, value_enum)]
    pub qos_reliability: Option<ReliabilityKey>,
    /// Quality of service durability setting to subscribe with (overrides durability value of
    /// --qos-profile option, default: Compatible profile with running endpoints )
    #[arg(long, value_enum)]
    pub qos_durability: Option<DurabilityKey>,
    /// Quality of service liveliness setting to subscribe with (overrides liveliness value of
    /// --qos-profile option
    #[arg(long, value_enum)]
    pub qos_liveliness: Option<LivelinessKey>,
    /// Quality of service liveliness lease duration setting to subscribe with (overrides
    /// liveliness lease duration value of --qos-profile option
    #[arg(
        long,
        value_name = "QOS_LIVELINESS_LEASE_DURATION_SECONDS",
        allow_negative_numbers = true
    )]
    pub qos_liveliness_lease_duration_seconds: Option<f64>,
}

/// The QoS options worded for publishing, with the `default` profile as ros2topic pub's
/// (`add_qos_arguments(parser, 'publish', 'default')`); for a command's
/// `#[command(mut_args(publishing))]`. Other arguments pass unchanged.
pub fn publishing(arg: Arg) -> Arg {
    if !arg.get_id().as_str().starts_with("qos_") {
        return arg;
    }
    let arg = if arg.get_id() == "qos_profile" {
        arg.default_value("default")
    } else {
        arg
    };
    let reword = |help: String| {
        help.replace("to subscribe with", "to publish with")
            .replace("(default: sensor_data)", "(default: default)")
    };
    match arg.get_help().map(|h| reword(h.to_string())) {
        Some(help) => arg.help(help),
        None => arg,
    }
}

impl QosArgs {
    /// Whether any policy is given (echo's `choose_qos` then adapts nothing).
    fn overridden(&self) -> bool {
        self.qos_reliability.is_some()
            || self.qos_durability.is_some()
            || self.qos_depth.is_some()
            || self.qos_history.is_some()
            || self.qos_liveliness.is_some()
            || self.qos_liveliness_lease_duration_seconds.is_some()
    }

    /// ros2topic `qos_profile_from_short_keys`: the profile, then each option given over it, as
    /// `profile_configure_short_keys` does (a depth only when positive; a transient-local
    /// profile of depth 0 gets depth 1).
    pub fn profile(&self) -> Qos {
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
        // `if liveliness_lease_duration_s and liveliness_lease_duration_s >= 0`: 0 is falsy.
        if let Some(s) = self.qos_liveliness_lease_duration_seconds {
            if s > 0.0 && s.is_finite() {
                qos.liveliness_lease_duration = QosDuration::from_nanos((s * 1e9) as i64);
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

    /// ros2topic echo `choose_qos`: the options as given when any policy is; else the preset
    /// with reliability and durability adapted to the topic's publishers (reliable /
    /// transient-local when all of them are). Returns the QoS and the lines ros2cli prints when
    /// only some publishers offer reliable or transient-local.
    pub fn choose(&self, publishers: &[Qos]) -> (Qos, Vec<&'static str>) {
        if self.overridden() {
            return (self.profile(), Vec::new());
        }
        let mut qos = self.qos_profile.profile();
        let mut notes = Vec::new();
        if publishers.is_empty() {
            return (qos, notes);
        }
        let reliable = publishers
            .iter()
            .filter(|q| q.reliability == ReliabilityPolicy::Reliable)
            .count();
        let transient = publishers
            .iter()
            .filter(|q| q.durability == DurabilityPolicy::TransientLocal)
            .count();
        if reliable == publishers.len() {
            qos.reliability = ReliabilityPolicy::Reliable;
        } else {
            if reliable > 0 {
                notes.push(
                    "Some, but not all, publishers are offering QoSReliabilityPolicy.RELIABLE. \
                     Falling back to QoSReliabilityPolicy.BEST_EFFORT as it will connect to all \
                     publishers",
                );
            }
            qos.reliability = ReliabilityPolicy::BestEffort;
        }
        if transient == publishers.len() {
            qos.durability = DurabilityPolicy::TransientLocal;
        } else {
            if transient > 0 {
                notes.push(
                    "Some, but not all, publishers are offering \
                     QoSDurabilityPolicy.TRANSIENT_LOCAL. Falling back to \
                     QoSDurabilityPolicy.VOLATILE as it will connect to all publishers",
                );
            }
            qos.durability = DurabilityPolicy::Volatile;
        }
        (qos, notes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            a.profile()
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
    fn publishing_rewords_the_options_and_defaults_to_the_default_profile() {
        use clap::{Args, Command};
        let sub = QosArgs::augment_args(Command::new("echo"));
        let publ = QosArgs::augment_args(Command::new("pub")).mut_args(publishing);
        let help = |c: &Command, id: &str| {
            let a = c.get_arguments().find(|a| a.get_id() == id).expect("arg");
            (
                a.get_help().map(ToString::to_string).unwrap_or_default(),
                a.get_default_values()
                    .iter()
                    .map(|v| v.to_string_lossy().into_owned())
                    .collect::<Vec<_>>(),
            )
        };
        assert_eq!(
            help(&sub, "qos_profile"),
            (
                "Quality of service preset profile to subscribe with (default: sensor_data)"
                    .to_owned(),
                vec!["sensor_data".to_owned()]
            )
        );
        assert_eq!(
            help(&publ, "qos_profile"),
            (
                "Quality of service preset profile to publish with (default: default)".to_owned(),
                vec!["default".to_owned()]
            )
        );
        assert!(help(&publ, "qos_depth")
            .0
            .starts_with("Queue size setting to publish with"));
    }
}
