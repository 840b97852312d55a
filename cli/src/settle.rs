//! The discovery wait: how long a command (or the daemon, for one query) waits for its graph
//! before it answers, and the one stderr line when the graph could not be completed.
//!
//! A command first waits [`MIN_DISCOVERY`] after joining (or a tenth of `--spin-time`, if more;
//! never more than `--spin-time`) for peers to show up, then until what it knows is consistent
//! and has been quiet for [`GRACE`]. While the graph is known to be incomplete — a ROS participant has not announced
//! its nodes on `ros_discovery_info`, or a node lists endpoints that are not discovered yet — it
//! keeps waiting: each such participant up to [`COMPLETENESS_BOUND`] (or `--spin-time`, if
//! longer) after it became outstanding, since that is when a real peer's discovery has
//! certainly arrived. A participant not known yet to be a ROS participant or not (its USER_DATA
//! unread, none of its writers discovered: [`ParticipantKind::Undecided`]) holds the wait up to
//! [`ENDPOINTS_BOUND`], by when its endpoints have arrived and tell; past that it is taken for a
//! bare DDS participant. A participant that is not a ROS participant never holds it. Only when
//! a bound is hit is the answer incomplete, and [`incomplete_warning`] says so on stderr. Every
//! wait is on the graph's change notification, or until the next bound.
//!
//! [`ParticipantKind::Undecided`]: horus_ros_graph::ParticipantKind::Undecided

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use horus_ros_graph::{Gid, Graph, GraphView, GraphWatcher, Unsettled};
use serde::{Deserialize, Serialize};

/// The shortest discovery wait: peers answer a new participant's announcement within a few
/// milliseconds, but not at once.
pub const MIN_DISCOVERY: Duration = Duration::from_millis(120);
/// The part of `--spin-time` always waited (when more than [`MIN_DISCOVERY`]): a peer that
/// answers our announcement late (a loaded machine, a slow network) is not taken for absent
/// when the user gave discovery more time.
const MIN_DISCOVERY_SHARE: u32 = 10;
/// Once what is known is consistent, the wait ends when nothing has changed for this long
/// (participants not seen yet get this long to show up).
pub const GRACE: Duration = Duration::from_millis(30);

/// Fast DDS 2.14 (rmw_fastrtps_cpp, Jazzy's default rmw): the period of the heartbeats of the
/// built-in SEDP writers (`EDPSimple.cpp`, `edp_heartbeat_period{1, 0}`). A participant's
/// endpoints reach a new peer in answer to the first heartbeat it hears; when that one is
/// missed (it came before the peer had matched the SEDP writer), at the next.
const FASTDDS_EDP_HEARTBEAT: Duration = Duration::from_secs(1);
/// Fast DDS 2.14: how long its SEDP writers wait before answering a NACK
/// (`EDPSimple.cpp`, `edp_nack_response_delay`, 100 ms).
const FASTDDS_EDP_NACK_RESPONSE: Duration = Duration::from_millis(100);
/// Fast DDS 2.14: the heartbeat period of a writer with default times
/// (`WriterAttributes.h`, `WriterTimes::heartbeatPeriod`, 3 s), which rmw_fastrtps_cpp keeps
/// for its `ros_discovery_info` writer (`init_rmw_context_impl.cpp` sets none). A reader that
/// missed the heartbeat the writer sends when it matches it (rmw/src/late_joiner.rs) gets the
/// participant's message at the writer's next periodic one, unless our late-joiner reader, renewed
/// after 1 s and then twice as long each time, gets it first.
const FASTDDS_WRITER_HEARTBEAT: Duration = Duration::from_secs(3);
/// Fast DDS 2.14: how long a writer with default times waits before answering a NACK
/// (`WriterTimes::nackResponseDelay`, 5 ms).
const FASTDDS_NACK_RESPONSE: Duration = Duration::from_millis(5);
/// Round trips and a loaded machine's scheduling on top of the protocol's periods.
const MARGIN: Duration = Duration::from_millis(500);

/// How long a participant's endpoints may take to be discovered after the participant (or
/// after a node listed them): one missed SEDP heartbeat and the NACK's answer, plus
/// [`MARGIN`] — 1.6 s.
pub const ENDPOINTS_BOUND: Duration = FASTDDS_EDP_HEARTBEAT
    .saturating_add(FASTDDS_EDP_NACK_RESPONSE)
    .saturating_add(MARGIN);

/// How long a ROS participant may take to be complete (its nodes announced, their endpoints
/// discovered) after it was first seen: its `ros_discovery_info` writer is discovered within
/// [`ENDPOINTS_BOUND`]'s SEDP exchange, and its message arrives at the latest at the writer's
/// next periodic heartbeat after that, answered after the writer's NACK delay — 4.6 s.
pub const COMPLETENESS_BOUND: Duration = FASTDDS_EDP_HEARTBEAT
    .saturating_add(FASTDDS_EDP_NACK_RESPONSE)
    .saturating_add(FASTDDS_WRITER_HEARTBEAT)
    .saturating_add(FASTDDS_NACK_RESPONSE)
    .saturating_add(MARGIN);

/// When each participant with something outstanding (see [`Unsettled`]) became so: kept up to
/// date by a [`GraphWatcher`] on every change of the graph, so that a participant that has been
/// outstanding for longer than its bound does not hold a later wait (the daemon's).
#[derive(Debug, Default)]
pub struct Outstanding {
    since: Mutex<BTreeMap<Gid, Instant>>,
}

impl Outstanding {
    /// Starts keeping track of `graph` (until the returned value is dropped).
    pub fn watch(graph: &Graph) -> Arc<Self> {
        let outstanding = Arc::new(Self::default());
        let watcher: Arc<dyn GraphWatcher> = outstanding.clone();
        graph.watch(Arc::downgrade(&watcher));
        // What was outstanding before the first change.
        let mut since = outstanding.lock();
        let unsettled = graph.read(|c| c.unsettled());
        observe(&mut since, &unsettled, Instant::now());
        drop(since);
        outstanding
    }

    fn lock(&self) -> MutexGuard<'_, BTreeMap<Gid, Instant>> {
        self.since.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Since when `participant` has been outstanding, if it has been seen so.
    fn since(&self, participant: &Gid) -> Option<Instant> {
        self.lock().get(participant).copied()
    }
}

impl GraphWatcher for Outstanding {
    fn graph_changed(&self, graph: &GraphView<'_>) {
        // Read under our lock, so that two observations are recorded in the order they were made.
        let mut since = self.lock();
        let unsettled = graph.read(|c| c.unsettled());
        observe(&mut since, &unsettled, Instant::now());
    }
}

/// Records the participants newly outstanding in `unsettled` as of `now`, and forgets those no
/// longer outstanding.
fn observe(since: &mut BTreeMap<Gid, Instant>, unsettled: &Unsettled, now: Instant) {
    let outstanding = unsettled.participants();
    since.retain(|gid, _| outstanding.binary_search(gid).is_ok());
    for gid in outstanding {
        since.entry(gid).or_insert(now);
    }
}

/// An answer given before the graph was complete: what was missing when the bound was hit.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Incomplete {
    /// What was outstanding.
    pub unsettled: Unsettled,
    /// The bound that was hit, in milliseconds.
    pub bound_ms: u64,
}

/// One discovery wait: the graph, when its participant joined, and when the wait began.
pub struct Wait<'a> {
    /// The graph waited for.
    pub graph: &'a Graph,
    /// Its tracker of outstanding participants.
    pub outstanding: &'a Outstanding,
    /// When the graph started following discovery.
    pub joined: Instant,
    /// When this wait began (the command's join, or the daemon's request).
    pub start: Instant,
    /// `--spin-time`.
    pub spin: Duration,
}

impl Wait<'_> {
    /// Waits as the module says; `None` when the graph is complete, else what is missing.
    pub fn run(&self) -> Option<Incomplete> {
        let bound = COMPLETENESS_BOUND.max(self.spin);
        let cap = deadline_after(self.start, bound);
        let discovering_until = deadline_after(self.joined, discovery_window(self.spin));
        loop {
            // Read before looking, so that no change can fall between the look and the wait.
            let generation = self.graph.generation();
            let now = Instant::now();
            if now >= cap {
                break;
            }
            let wake_at = if now < discovering_until {
                discovering_until
            } else {
                let unsettled = self.graph.read(|c| c.unsettled());
                match self.held_until(&unsettled, bound, now) {
                    Some(until) => until,
                    // Everything outstanding of a ROS participant is past its bound: answer.
                    None if unsettled.ros_outstanding() => break,
                    None => {
                        let quiet_from = self.graph.last_change() + GRACE;
                        if now >= quiet_from {
                            return None;
                        }
                        quiet_from
                    }
                }
            };
            self.graph
                .wait_for_graph_change_since(generation, wake_at.min(cap) - now);
        }
        let unsettled = self.graph.read(|c| c.unsettled());
        unsettled.ros_outstanding().then(|| Incomplete {
            unsettled,
            bound_ms: u64::try_from(bound.as_millis()).unwrap_or(u64::MAX),
        })
    }

    /// The earliest moment a participant outstanding in `unsettled` stops holding the wait, if
    /// one still holds it at `now` (one not seen outstanding before holds it from `now`).
    fn held_until(&self, unsettled: &Unsettled, bound: Duration, now: Instant) -> Option<Instant> {
        let holds = |gid: &Gid, bound: Duration| {
            let until = deadline_after(self.outstanding.since(gid).unwrap_or(now), bound);
            (until > now).then_some(until)
        };
        let ros = unsettled
            .unannounced
            .iter()
            .chain(&unsettled.incomplete)
            .filter_map(|gid| holds(gid, bound));
        let undecided = unsettled
            .undecided
            .iter()
            .filter_map(|gid| holds(gid, ENDPOINTS_BOUND));
        ros.chain(undecided).min()
    }
}

/// How long after joining a command waits for peers to show up at all, whatever it knows:
/// [`MIN_DISCOVERY`], or a tenth of `--spin-time` if more, but never more than `--spin-time`
/// (`--spin-time 0` answers with what is known at once, unless that is known to be incomplete).
fn discovery_window(spin: Duration) -> Duration {
    MIN_DISCOVERY.max(spin / MIN_DISCOVERY_SHARE).min(spin)
}

/// `--spin-time` as a duration (negative: none; too large for one: the longest there is).
pub fn spin_time(global: &crate::Global) -> Duration {
    Duration::try_from_secs_f64(global.spin_time.max(0.0)).unwrap_or(Duration::MAX)
}

/// `start + limit`, or a moment far enough away when that cannot be represented.
pub fn deadline_after(start: Instant, limit: Duration) -> Instant {
    const FAR: Duration = Duration::from_secs(100 * 365 * 24 * 3600);
    start
        .checked_add(limit.min(FAR))
        .unwrap_or(start + Duration::from_secs(24 * 3600))
}

/// The longest a discovery wait with `--spin-time` `spin` can take.
pub fn longest_wait(spin: Duration) -> Duration {
    COMPLETENESS_BOUND.max(spin)
}

/// The one stderr line for an answer given before the graph was complete.
pub fn incomplete_warning(incomplete: &Incomplete) -> String {
    let unsettled = &incomplete.unsettled;
    let mut missing = Vec::new();
    match unsettled.unannounced.as_slice() {
        [] => {}
        [one] => missing.push(format!(
            "participant {one} has not announced its nodes (ros_discovery_info)"
        )),
        many => missing.push(format!(
            "{} participants have not announced their nodes",
            many.len()
        )),
    }
    match unsettled.missing_endpoints {
        0 => {}
        1 => missing.push("1 endpoint listed by a node is not discovered yet".to_owned()),
        n => missing.push(format!(
            "{n} endpoints listed by nodes are not discovered yet"
        )),
    }
    format!(
        "WARNING: discovery incomplete after {}: {}; the answer may be incomplete (raise \
         --spin-time)",
        seconds(Duration::from_millis(incomplete.bound_ms)),
        missing.join(", "),
    )
}

/// Seconds as `--spin-time` takes them (`4.605 s`).
fn seconds(d: Duration) -> String {
    format!("{} s", d.as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_follow_fast_dds_periods() {
        assert_eq!(ENDPOINTS_BOUND, Duration::from_millis(1600));
        assert_eq!(COMPLETENESS_BOUND, Duration::from_millis(4605));
        assert_eq!(longest_wait(Duration::from_millis(500)), COMPLETENESS_BOUND);
        assert_eq!(
            longest_wait(Duration::from_secs(15)),
            Duration::from_secs(15)
        );
    }

    #[test]
    fn the_discovery_window_follows_spin_time() {
        assert_eq!(discovery_window(Duration::from_millis(500)), MIN_DISCOVERY);
        assert_eq!(
            discovery_window(Duration::from_secs(10)),
            Duration::from_secs(1)
        );
        assert_eq!(
            discovery_window(Duration::from_millis(50)),
            Duration::from_millis(50)
        );
        assert_eq!(discovery_window(Duration::ZERO), Duration::ZERO);
    }

    fn participant(n: u8) -> Gid {
        let mut data = [n; 16];
        data[12..].copy_from_slice(&[0, 0, 1, 0xc1]);
        Gid::from_bytes(data)
    }

    #[test]
    fn outstanding_participants_keep_their_first_time() {
        let mut since = BTreeMap::new();
        let t0 = Instant::now();
        let first = Unsettled {
            unannounced: vec![participant(1)],
            undecided: vec![participant(2)],
            ..Unsettled::default()
        };
        observe(&mut since, &first, t0);
        // Participant 1 announced, but lists an endpoint not discovered: still outstanding.
        let second = Unsettled {
            incomplete: vec![participant(1)],
            missing_endpoints: 1,
            ..Unsettled::default()
        };
        let t1 = t0 + Duration::from_secs(1);
        observe(&mut since, &second, t1);
        assert_eq!(since.get(&participant(1)), Some(&t0));
        assert_eq!(since.get(&participant(2)), None, "no longer outstanding");
        observe(&mut since, &first, t1);
        assert_eq!(since.get(&participant(2)), Some(&t1), "outstanding anew");
    }

    #[test]
    fn the_warning_names_what_is_missing_and_the_bound() {
        let incomplete = Incomplete {
            unsettled: Unsettled {
                unannounced: vec![participant(1)],
                incomplete: vec![participant(2)],
                missing_endpoints: 3,
                ..Unsettled::default()
            },
            bound_ms: 4605,
        };
        assert_eq!(
            incomplete_warning(&incomplete),
            format!(
                "WARNING: discovery incomplete after 4.605 s: participant {} has not announced \
                 its nodes (ros_discovery_info), 3 endpoints listed by nodes are not discovered \
                 yet; the answer may be incomplete (raise --spin-time)",
                participant(1)
            )
        );
    }
}
