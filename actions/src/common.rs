//! What servers and clients share: goal ids, the entity names and QoS of rcl_action, time
//! stamps and the wake-up used by the server thread.

use std::hash::{BuildHasher, Hasher};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::task::Wake;
use std::time::{Duration, Instant};

use horus_ros_msgs::builtin_interfaces::msg::Time;
use horus_ros_rmw::qos::Qos;

/// The id of a goal: the 16 bytes of its `unique_identifier_msgs/msg/UUID` (a random version 4
/// UUID when a client of this crate makes it, as rclpy's `uuid.uuid4()` and rclcpp's
/// `generate_goal_id`).
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct GoalId(pub [u8; 16]);

impl GoalId {
    /// A new random (version 4) id.
    pub fn random() -> Self {
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let state = std::collections::hash_map::RandomState::new();
        let mut bytes = [0u8; 16];
        for (i, chunk) in bytes.chunks_mut(8).enumerate() {
            let mut h = state.build_hasher();
            h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
            h.write_usize(i);
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .unwrap_or_default()
                    .as_nanos(),
            );
            chunk.copy_from_slice(&h.finish().to_le_bytes());
        }
        // RFC 4122: version 4, variant 10.
        bytes[6] = (bytes[6] & 0x0f) | 0x40;
        bytes[8] = (bytes[8] & 0x3f) | 0x80;
        Self(bytes)
    }

    /// Whether every byte is zero (the "any goal" id of a cancel request).
    pub fn is_zero(&self) -> bool {
        self.0 == [0; 16]
    }
}

impl std::fmt::Display for GoalId {
    /// The canonical UUID form, `xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, b) in self.0.iter().enumerate() {
            if matches!(i, 4 | 6 | 8 | 10) {
                f.write_str("-")?;
            }
            write!(f, "{b:02x}")?;
        }
        Ok(())
    }
}

impl std::fmt::Debug for GoalId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GoalId({self})")
    }
}

impl From<[u8; 16]> for GoalId {
    fn from(bytes: [u8; 16]) -> Self {
        Self(bytes)
    }
}

/// The entity names of an action, as rcl_action's `names.c` makes them
/// (`rcl_action_get_goal_service_name` etc.): `<action>/_action/send_goal`, `cancel_goal`,
/// `get_result` (services), `feedback`, `status` (topics).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionNames {
    /// `<action>/_action/send_goal`.
    pub send_goal: String,
    /// `<action>/_action/cancel_goal`.
    pub cancel_goal: String,
    /// `<action>/_action/get_result`.
    pub get_result: String,
    /// `<action>/_action/feedback`.
    pub feedback: String,
    /// `<action>/_action/status`.
    pub status: String,
}

impl ActionNames {
    /// The names of action `action` (as given: relative names expand later, with the node's
    /// namespace, as the entities are made).
    pub fn of(action: &str) -> Self {
        let n = |suffix: &str| format!("{action}/_action/{suffix}");
        Self {
            send_goal: n("send_goal"),
            cancel_goal: n("cancel_goal"),
            get_result: n("get_result"),
            feedback: n("feedback"),
            status: n("status"),
        }
    }
}

/// The QoS of the feedback topic: rclpy's `QoSProfile(depth=10)` (reliable, volatile, keep last
/// 10), the `rmw_qos_profile_default` that `rcl_action_server_get_default_options` and
/// `rcl_action_client_get_default_options` set (rcl_action `action_server.c`,
/// `action_client.c`).
pub fn feedback_qos() -> Qos {
    Qos::default_profile()
}

/// The QoS of the status topic: `rcl_action_qos_profile_status_default` (rcl_action
/// `default_qos.h`: reliable, transient local, keep last 1).
pub fn status_qos() -> Qos {
    Qos::action_status_default()
}

/// The three services' QoS: `rmw_qos_profile_services_default`, as rcl_action's default
/// options set for `goal_service_qos`, `cancel_service_qos` and `result_service_qos`.
pub fn services_qos() -> Qos {
    Qos::services_default()
}

/// How long a server keeps a goal's result after the goal ended: rcl_action's default
/// `result_timeout` (`rcl_action_server_get_default_options`: 15 minutes; rclpy's
/// `result_timeout=900`).
pub const DEFAULT_RESULT_TIMEOUT: Duration = Duration::from_secs(900);

/// A stamp in nanoseconds, as rcl_action's `_goal_info_stamp_to_nanosec`.
pub(crate) fn stamp_nanos(t: &Time) -> i64 {
    i64::from(t.sec) * 1_000_000_000 + i64::from(t.nanosec)
}

/// Locks, ignoring poisoning (a panicking callback never leaves our state half-changed: the
/// state is changed only by this crate's code, outside user callbacks).
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// A wake-up flag a thread waits on, set by `std::task::Waker`s (the services' request wakers)
/// and by the crate itself.
#[derive(Default)]
pub(crate) struct Notify {
    flag: Mutex<bool>,
    cond: Condvar,
}

impl Notify {
    /// Sets the flag and wakes the waiter.
    pub(crate) fn notify(&self) {
        *lock(&self.flag) = true;
        self.cond.notify_all();
    }

    /// Waits until notified or `deadline` (`None`: no limit); clears the flag.
    pub(crate) fn wait(&self, deadline: Option<Instant>) {
        let mut flag = lock(&self.flag);
        while !*flag {
            match deadline {
                None => flag = self.cond.wait(flag).unwrap_or_else(|p| p.into_inner()),
                Some(d) => {
                    let now = Instant::now();
                    if now >= d {
                        break;
                    }
                    flag = self
                        .cond
                        .wait_timeout(flag, d - now)
                        .unwrap_or_else(|p| p.into_inner())
                        .0;
                }
            }
        }
        *flag = false;
    }
}

/// The [`Notify`] as a `std::task::Waker`.
pub(crate) struct NotifyWaker(pub(crate) Arc<Notify>);

impl Wake for NotifyWaker {
    fn wake(self: Arc<Self>) {
        self.0.notify();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.0.notify();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_rcl_actions() {
        let n = ActionNames::of("/fibonacci");
        assert_eq!(n.send_goal, "/fibonacci/_action/send_goal");
        assert_eq!(n.cancel_goal, "/fibonacci/_action/cancel_goal");
        assert_eq!(n.get_result, "/fibonacci/_action/get_result");
        assert_eq!(n.feedback, "/fibonacci/_action/feedback");
        assert_eq!(n.status, "/fibonacci/_action/status");
    }

    #[test]
    fn random_ids_are_version_4_and_differ() {
        let (a, b) = (GoalId::random(), GoalId::random());
        assert_ne!(a, b);
        assert_eq!(a.0[6] >> 4, 4);
        assert_eq!(a.0[8] >> 6, 0b10);
        assert!(!a.is_zero() && GoalId::default().is_zero());
        assert_eq!(a.to_string().len(), 36);
    }
}
