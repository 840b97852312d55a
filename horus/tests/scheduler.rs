//! Every rule of the HORUS Node API, on a scheduler without ROS (no DDS) and a manual clock:
//! time moves only when a test or a node moves it, so no test sleeps or times anything.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use horus::prelude::*;
use horus::{BuildError, Clock, ManualClock, SchedulerError, StopHandle};

type Log = Arc<Mutex<Vec<String>>>;

fn log() -> Log {
    Arc::new(Mutex::new(Vec::new()))
}

fn entries(log: &Log) -> Vec<String> {
    log.lock().unwrap_or_else(|p| p.into_inner()).clone()
}

fn push(log: &Log, s: String) {
    log.lock().unwrap_or_else(|p| p.into_inner()).push(s);
}

fn sched(clock: &Arc<ManualClock>) -> Scheduler {
    Scheduler::new()
        .without_ros()
        .print_report(false)
        .clock(clock.clone())
}

/// What a test node does, step by step.
#[derive(Default)]
struct Behaviour {
    /// `init` fails with this error.
    init_error: Option<&'static str>,
    /// `init` fails this many times, then succeeds.
    init_failures: u32,
    /// `tick` panics while this is set.
    panic: Option<Arc<AtomicBool>>,
    /// `tick` moves the clock forward by this much (a tick that takes this long).
    tick_takes: Option<(Arc<ManualClock>, Duration)>,
    /// `is_safe_state` answers this.
    safe: Option<Arc<AtomicBool>>,
    /// `shutdown` blocks until this receiver gets something (or its sender is dropped).
    shutdown_blocks: Option<Mutex<mpsc::Receiver<()>>>,
    /// `shutdown` panics.
    shutdown_panics: bool,
    /// Stop the scheduler after this many ticks.
    stop_after: Option<(u64, StopHandle)>,
}

struct Probe {
    name: String,
    log: Log,
    b: Behaviour,
    ticks: u64,
}

impl Probe {
    fn new(name: &str, log: &Log) -> Self {
        Self::with(name, log, Behaviour::default())
    }
    fn with(name: &str, log: &Log, b: Behaviour) -> Self {
        Self {
            name: name.to_owned(),
            log: log.clone(),
            b,
            ticks: 0,
        }
    }
}

impl Node for Probe {
    fn name(&self) -> &str {
        &self.name
    }
    fn init(&mut self) -> Result<()> {
        push(&self.log, format!("init {}", self.name));
        if self.b.init_failures > 0 {
            self.b.init_failures -= 1;
            return Err(Error::config("not yet"));
        }
        match self.b.init_error {
            Some("panic") => panic!("init exploded"),
            Some(e) => Err(Error::config(e)),
            None => Ok(()),
        }
    }
    fn tick(&mut self) {
        self.ticks += 1;
        push(&self.log, format!("tick {}", self.name));
        if let Some((clock, d)) = &self.b.tick_takes {
            clock.advance(*d);
        }
        if let Some((n, stop)) = &self.b.stop_after {
            if self.ticks >= *n {
                stop.stop();
            }
        }
        if let Some(p) = &self.b.panic {
            if p.load(Ordering::SeqCst) {
                panic!("tick {} exploded", self.ticks);
            }
        }
    }
    fn shutdown(&mut self) -> Result<()> {
        push(&self.log, format!("shutdown {}", self.name));
        if let Some(rx) = &self.b.shutdown_blocks {
            let _ = rx.lock().unwrap_or_else(|p| p.into_inner()).recv();
        }
        if self.b.shutdown_panics {
            panic!("shutdown exploded");
        }
        Ok(())
    }
    fn is_safe_state(&self) -> bool {
        push(&self.log, format!("is_safe_state {}", self.name));
        self.b
            .safe
            .as_ref()
            .is_none_or(|s| s.load(Ordering::SeqCst))
    }
    fn enter_safe_state(&mut self) {
        push(&self.log, format!("enter_safe_state {}", self.name));
    }
    fn on_error(&mut self, error: &str) {
        push(&self.log, format!("on_error {} {error}", self.name));
    }
}

fn count(log: &Log, what: &str) -> usize {
    entries(log).iter().filter(|e| *e == what).count()
}

#[test]
fn nodes_tick_in_order_then_registration_order() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    s.add(Probe::new("c", &log)).order(2).build().expect("ok");
    s.add(Probe::new("a", &log)).order(0).build().expect("ok");
    s.add(Probe::new("b", &log)).order(2).build().expect("ok");
    s.add(Probe::new("d", &log)).order(1).build().expect("ok");
    s.tick_once().expect("ok");
    let ticks: Vec<_> = entries(&log)
        .into_iter()
        .filter(|e| e.starts_with("tick"))
        .collect();
    assert_eq!(ticks, ["tick a", "tick d", "tick c", "tick b"]);
}

#[test]
fn init_is_lazy_and_runs_once() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    s.add(Probe::new("a", &log)).build().expect("ok");
    assert!(entries(&log).is_empty(), "no init at add/build");
    assert_eq!(s.node_state("a"), Some(NodeState::Uninitialized));
    s.tick_once().expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(entries(&log), ["init a", "tick a", "tick a"]);
    assert_eq!(s.node_state("a"), Some(NodeState::Running));
}

#[test]
fn failed_init_means_no_tick_and_no_shutdown() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let failing = Behaviour {
        init_error: Some("no serial port"),
        ..Default::default()
    };
    s.add(Probe::with("bad", &log, failing))
        .failure_policy(FailurePolicy::Ignore)
        .build()
        .expect("ok");
    let panicking = Behaviour {
        init_error: Some("panic"),
        ..Default::default()
    };
    s.add(Probe::with("worse", &log, panicking))
        .failure_policy(FailurePolicy::Skip {
            max_failures: 1,
            cooldown: Duration::from_millis(1),
        })
        .build()
        .expect("ok");
    s.add(Probe::new("good", &log)).build().expect("ok");
    s.tick_once().expect("ok");
    clock.advance(Duration::from_secs(1));
    s.tick_once().expect("ok");
    drop(s);
    assert_eq!(
        entries(&log),
        [
            "init bad",
            "init worse",
            "init good",
            "tick good",
            "tick good",
            "shutdown good"
        ]
    );
}

#[test]
fn fatal_init_failure_stops_the_scheduler_after_shutting_down_the_others() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    s.add(Probe::new("first", &log))
        .order(0)
        .build()
        .expect("ok");
    let failing = Behaviour {
        init_error: Some("calibration missing"),
        ..Default::default()
    };
    s.add(Probe::with("bad", &log, failing))
        .order(1)
        .build()
        .expect("ok");
    s.add(Probe::new("never", &log))
        .order(2)
        .build()
        .expect("ok");
    let err = s.tick_once().expect_err("an error");
    assert_eq!(
        err.downcast_ref::<SchedulerError>(),
        Some(&SchedulerError::InitFailed {
            node: "bad".into(),
            error: "configuration error: calibration missing".into()
        })
    );
    assert!(matches!(s.node_state("bad"), Some(NodeState::Error(_))));
    assert_eq!(
        entries(&log),
        ["init first", "init bad", "shutdown first"],
        "no tick at all; only the initialized node is shut down; later nodes never init"
    );
    s.tick_once().expect("ok");
    assert_eq!(entries(&log).len(), 3, "a stopped scheduler does nothing");
}

#[test]
fn tick_panic_fatal_calls_on_error_and_stops() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        panic: Some(Arc::new(AtomicBool::new(true))),
        ..Default::default()
    };
    s.add(Probe::with("p", &log, b)).build().expect("ok");
    s.add(Probe::new("q", &log)).build().expect("ok");
    let err = s.tick_once().expect_err("an error");
    assert_eq!(
        err.downcast_ref::<SchedulerError>(),
        Some(&SchedulerError::NodeFailed {
            node: "p".into(),
            error: "tick 1 exploded".into()
        })
    );
    assert_eq!(
        entries(&log),
        [
            "init p",
            "init q",
            "tick p",
            "on_error p tick 1 exploded",
            "shutdown p",
            "shutdown q"
        ]
    );
}

#[test]
fn tick_panic_ignore_keeps_ticking() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        panic: Some(Arc::new(AtomicBool::new(true))),
        ..Default::default()
    };
    s.add(Probe::with("p", &log, b))
        .failure_policy(FailurePolicy::Ignore)
        .build()
        .expect("ok");
    for _ in 0..3 {
        s.tick_once().expect("ok");
    }
    assert_eq!(count(&log, "tick p"), 3);
    assert_eq!(count(&log, "on_error p tick 3 exploded"), 1);
    let m = s.get_node_metrics("p").expect("ok");
    assert_eq!(
        (m.total_ticks, m.failed_ticks, m.successful_ticks),
        (3, 3, 0)
    );
    assert_eq!(m.errors_count, 3);
    assert!(matches!(s.node_state("p"), Some(NodeState::Crashed(_))));
}

#[test]
fn tick_panic_skip_cools_down_after_max_consecutive_failures() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let panicking = Arc::new(AtomicBool::new(true));
    let b = Behaviour {
        panic: Some(panicking.clone()),
        ..Default::default()
    };
    s.add(Probe::with("p", &log, b))
        .failure_policy(FailurePolicy::Skip {
            max_failures: 2,
            cooldown: Duration::from_millis(100),
        })
        .build()
        .expect("ok");
    s.tick_once().expect("ok");
    s.tick_once().expect("ok"); // second consecutive failure: cooldown starts
    s.tick_once().expect("ok");
    clock.advance(Duration::from_millis(99));
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "tick p"), 2, "skipped during the cooldown");
    clock.advance(Duration::from_millis(1));
    panicking.store(false, Ordering::SeqCst);
    s.tick_once().expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "tick p"), 4, "ticks again after it");
    assert_eq!(s.node_state("p"), Some(NodeState::Running));
}

#[test]
fn restart_backs_off_exponentially_then_escalates_to_fatal() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        panic: Some(Arc::new(AtomicBool::new(true))),
        ..Default::default()
    };
    let backoff = Duration::from_millis(10);
    s.add(Probe::with("p", &log, b))
        .failure_policy(FailurePolicy::Restart {
            max_restarts: 2,
            initial_backoff: backoff,
        })
        .build()
        .expect("ok");
    s.tick_once().expect("ok"); // init, tick panics: restart 1 in 10 ms
    assert_eq!(count(&log, "init p"), 1);
    clock.advance(Duration::from_millis(9));
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "init p"), 1, "not before the backoff");
    clock.advance(Duration::from_millis(1));
    s.tick_once().expect("ok"); // re-init, tick panics: restart 2 in 20 ms
    assert_eq!(count(&log, "init p"), 2);
    assert_eq!(count(&log, "tick p"), 2);
    clock.advance(Duration::from_millis(19));
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "init p"), 2, "the backoff doubled");
    clock.advance(Duration::from_millis(1));
    let err = s.tick_once().expect_err("an error"); // re-init, tick panics: no restart left
    assert_eq!(count(&log, "init p"), 3);
    assert_eq!(
        err.downcast_ref::<SchedulerError>(),
        Some(&SchedulerError::RestartsExhausted {
            node: "p".into(),
            restarts: 2,
            error: "tick 3 exploded".into()
        })
    );
    assert_eq!(entries(&log).last().map(String::as_str), Some("shutdown p"));
}

#[test]
fn restart_retries_a_failed_init() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        init_failures: 1,
        ..Default::default()
    };
    s.add(Probe::with("p", &log, b))
        .failure_policy(FailurePolicy::Restart {
            max_restarts: 3,
            initial_backoff: Duration::from_millis(5),
        })
        .build()
        .expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(entries(&log), ["init p"]);
    clock.advance(Duration::from_millis(5));
    s.tick_once().expect("ok");
    assert_eq!(entries(&log), ["init p", "init p", "tick p"]);
}

fn miss_setup(miss: Miss, log: &Log, clock: &Arc<ManualClock>) -> Scheduler {
    let mut s = sched(clock);
    let b = Behaviour {
        tick_takes: Some((clock.clone(), Duration::from_millis(2))),
        ..Default::default()
    };
    s.add(Probe::with("slow", log, b))
        .deadline(Duration::from_millis(1))
        .on_miss(miss)
        .build()
        .expect("ok");
    s
}

#[test]
fn miss_warn_counts_and_goes_on() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = miss_setup(Miss::Warn, &log, &clock);
    for _ in 0..3 {
        s.tick_once().expect("ok");
    }
    assert_eq!(count(&log, "tick slow"), 3);
    assert_eq!(s.get_node_metrics("slow").expect("ok").warnings_count, 3);
    assert_eq!(s.timing_report().nodes[0].deadline_misses, 3);
}

#[test]
fn miss_skip_skips_the_next_tick() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = miss_setup(Miss::Skip, &log, &clock);
    for _ in 0..4 {
        s.tick_once().expect("ok");
    }
    assert_eq!(count(&log, "tick slow"), 2, "tick, skip, tick, skip");
}

#[test]
fn miss_safe_mode_isolates_until_safe() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let safe = Arc::new(AtomicBool::new(false));
    let b = Behaviour {
        tick_takes: Some((clock.clone(), Duration::from_millis(2))),
        safe: Some(safe.clone()),
        ..Default::default()
    };
    s.add(Probe::with("m", &log, b))
        .deadline(Duration::from_millis(1))
        .on_miss(Miss::SafeMode)
        .build()
        .expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("m"), Some(NodeHealthState::Isolated));
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "tick m"), 1, "isolated: not ticked");
    safe.store(true, Ordering::SeqCst);
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "tick m"), 2, "safe again: ticked");
    assert_eq!(count(&log, "enter_safe_state m"), 2, "on every miss");
    assert_eq!(count(&log, "is_safe_state m"), 2);
}

#[test]
fn miss_stop_stops_the_scheduler() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = miss_setup(Miss::Stop, &log, &clock);
    let err = s.tick_once().expect_err("an error");
    assert!(matches!(
        err.downcast_ref::<SchedulerError>(),
        Some(SchedulerError::DeadlineMissed { node, .. }) if node == "slow"
    ));
    assert_eq!(entries(&log), ["init slow", "tick slow", "shutdown slow"]);
}

#[test]
fn budget_overrun_is_a_warning() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        tick_takes: Some((clock.clone(), Duration::from_micros(300))),
        ..Default::default()
    };
    s.add(Probe::with("b", &log, b))
        .budget(Duration::from_micros(200))
        .build()
        .expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(s.get_node_metrics("b").expect("ok").warnings_count, 1);
    assert_eq!(s.timing_report().nodes[0].budget_overruns, 1);
}

#[test]
fn watchdog_escalates_to_isolated_and_recovers_through_is_safe_state() {
    let clock = ManualClock::new();
    let log = log();
    let timeout = Duration::from_millis(100);
    let mut s = sched(&clock).watchdog(timeout);
    let panicking = Arc::new(AtomicBool::new(true));
    let safe = Arc::new(AtomicBool::new(false));
    let b = Behaviour {
        panic: Some(panicking.clone()),
        safe: Some(safe.clone()),
        ..Default::default()
    };
    s.add(Probe::with("w", &log, b))
        .failure_policy(FailurePolicy::Ignore)
        .build()
        .expect("ok");
    s.tick_once().expect("ok"); // fed at init; the tick fails: not fed
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Healthy));
    clock.advance(timeout);
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Warning));
    assert_eq!(count(&log, "tick w"), 2, "a Warning node still ticks");
    clock.advance(timeout);
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Unhealthy));
    assert_eq!(count(&log, "tick w"), 2, "an Unhealthy node is skipped");
    assert_eq!(count(&log, "enter_safe_state w"), 0);
    clock.advance(timeout);
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Isolated));
    assert_eq!(count(&log, "enter_safe_state w"), 1);
    s.tick_once().expect("ok");
    assert_eq!(count(&log, "is_safe_state w"), 1);
    assert_eq!(count(&log, "tick w"), 2, "isolated until is_safe_state");
    safe.store(true, Ordering::SeqCst);
    panicking.store(false, Ordering::SeqCst);
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Healthy));
    assert_eq!(
        count(&log, "tick w"),
        3,
        "recovered: ticks in the same cycle"
    );
    clock.advance(timeout / 2);
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("w"), Some(NodeHealthState::Healthy));
    assert_eq!(
        count(&log, "enter_safe_state w"),
        1,
        "called once on isolation"
    );
}

#[test]
fn a_tick_longer_than_the_watchdog_does_not_feed_it() {
    let clock = ManualClock::new();
    let log = log();
    let timeout = Duration::from_millis(10);
    let mut s = sched(&clock).watchdog(timeout);
    let b = Behaviour {
        tick_takes: Some((clock.clone(), Duration::from_millis(15))),
        ..Default::default()
    };
    s.add(Probe::with("slow", &log, b)).build().expect("ok");
    s.tick_once().expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(s.node_health("slow"), Some(NodeHealthState::Warning));
}

#[test]
fn shutdown_runs_in_registration_order_and_survives_panics() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let b = Behaviour {
        shutdown_panics: true,
        ..Default::default()
    };
    s.add(Probe::new("z", &log)).order(5).build().expect("ok");
    s.add(Probe::with("y", &log, b))
        .order(0)
        .build()
        .expect("ok");
    s.add(Probe::new("x", &log)).order(1).build().expect("ok");
    s.tick_once().expect("ok");
    s.stop();
    s.tick_once().expect("ok");
    let shutdowns: Vec<_> = entries(&log)
        .into_iter()
        .filter(|e| e.starts_with("shutdown"))
        .collect();
    assert_eq!(shutdowns, ["shutdown z", "shutdown y", "shutdown x"]);
    let report = s.timing_report();
    assert_eq!(report.nodes[0].shutdown, "ok");
    assert_eq!(report.nodes[1].shutdown, "panicked: shutdown exploded");
    assert_eq!(s.node_state("x"), Some(NodeState::Stopped));
}

#[test]
fn a_shutdown_that_outlasts_the_timeout_is_detached() {
    let clock = ManualClock::new();
    let log = log();
    let (release, rx) = mpsc::channel();
    let b = Behaviour {
        shutdown_blocks: Some(Mutex::new(rx)),
        ..Default::default()
    };
    // The stuck node costs the test this timeout; the other node's shutdown has all of it.
    let mut s = sched(&clock).shutdown_timeout(Duration::from_secs(1));
    s.add(Probe::with("stuck", &log, b)).build().expect("ok");
    s.add(Probe::new("next", &log)).build().expect("ok");
    s.tick_once().expect("ok");
    s.stop();
    s.tick_once().expect("ok");
    let report = s.timing_report();
    assert_eq!(
        report.nodes[0].shutdown,
        "timed out after 1.000 s (detached)"
    );
    assert_eq!(
        report.nodes[1].shutdown, "ok",
        "the next node is shut down anyway"
    );
    assert_eq!(count(&log, "shutdown next"), 1);
    drop(release);
    assert_eq!(horus::SHUTDOWN_TIMEOUT, Duration::from_secs(3));
}

#[test]
fn metrics_values() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    let panicking = Arc::new(AtomicBool::new(false));
    let b = Behaviour {
        tick_takes: Some((clock.clone(), Duration::from_millis(2))),
        panic: Some(panicking.clone()),
        ..Default::default()
    };
    s.add(Probe::with("m", &log, b))
        .order(7)
        .failure_policy(FailurePolicy::Ignore)
        .build()
        .expect("ok");
    let before = s.get_node_metrics("m").expect("ok");
    assert_eq!(before.total_ticks, 0);
    assert_eq!(before.min_tick_duration_ms, 0.0);
    assert_eq!(before.uptime_seconds, 0.0);
    s.tick_once().expect("ok");
    s.tick_once().expect("ok");
    panicking.store(true, Ordering::SeqCst);
    s.tick_once().expect("ok");
    let m = s.get_node_metrics("m").expect("ok");
    assert_eq!(m.name, "m");
    assert_eq!(m.order, 7);
    assert_eq!(m.total_ticks, 3);
    assert_eq!(m.successful_ticks, 2);
    assert_eq!(m.failed_ticks, 1);
    assert_eq!(m.avg_tick_duration_ms, 2.0);
    assert_eq!(m.min_tick_duration_ms, 2.0);
    assert_eq!(m.max_tick_duration_ms, 2.0);
    assert_eq!(m.last_tick_duration_ms, 2.0);
    assert_eq!(m.messages_sent, 0);
    assert_eq!(m.messages_received, 0);
    assert_eq!(m.errors_count, 1);
    assert_eq!(m.warnings_count, 0);
    assert_eq!(m.uptime_seconds, 0.006);
    assert!(s.get_node_metrics("nope").is_none());
}

struct Unnamed;
impl Node for Unnamed {
    fn tick(&mut self) {}
}

#[test]
fn names_are_unique_and_default_to_the_type_name() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock);
    s.add(Unnamed).build().expect("ok");
    assert_eq!(s.node_names(), ["Unnamed"]);
    assert_eq!(
        s.add(Unnamed).build(),
        Err(BuildError::DuplicateName("Unnamed".into()))
    );
    s.add(Probe::new("a", &log)).build().expect("ok");
    assert_eq!(
        s.add(Probe::new("a", &log)).order(3).build(),
        Err(BuildError::DuplicateName("a".into()))
    );
    assert!(matches!(
        s.add(Probe::new("1abc", &log)).build(),
        Err(BuildError::InvalidName { .. })
    ));
    assert!(matches!(
        s.add(Probe::new("r", &log)).rate(0_u64.hz()).build(),
        Err(BuildError::InvalidRate { .. })
    ));
    assert_eq!(s.node_names(), ["Unnamed", "a"]);
    s.tick_once().expect("ok");
    assert_eq!(
        s.add(Probe::new("late", &log)).build(),
        Err(BuildError::AlreadyStarted("late".into()))
    );
}

#[test]
fn run_follows_rates_until_stopped() {
    let clock = ManualClock::new();
    let log = log();
    let mut s = sched(&clock).tick_rate(100_u64.hz());
    let stop = s.stop_handle();
    let b = Behaviour {
        stop_after: Some((10, stop)),
        ..Default::default()
    };
    s.add(Probe::with("every_cycle", &log, b))
        .order(0)
        .build()
        .expect("ok");
    s.add(Probe::new("half", &log))
        .order(1)
        .rate(50_u64.hz())
        .build()
        .expect("ok");
    s.run().expect("ok");
    assert_eq!(count(&log, "tick every_cycle"), 10);
    // At 100 Hz the first node ticks at 0, 10, …, 90 ms (it stops the scheduler at its tenth
    // tick; the loop ends after that cycle); the 50 Hz node at 0, 20, …, 80 ms.
    assert_eq!(count(&log, "tick half"), 5);
    assert_eq!(clock.now(), Duration::from_millis(90));
    assert_eq!(
        entries(&log).last().map(String::as_str),
        Some("shutdown half")
    );
}

node! {
    /// A node from the macro.
    PingCounter {
        pub {
            out: Int64Msg -> "ping.count",
        }
        sub {
            input: BoolMsg -> "ping.reset",
        }
        data {
            n: i64 = 41,
        }
        tick(self) {
            self.n += 1;
        }
        init(self) {
            self.n += 0;
            Ok(())
        }
    }
}

use horus::msgs::std_msgs::msg::{Bool as BoolMsg, Int64 as Int64Msg};

#[test]
fn node_macro_generates_name_topics_and_metadata() {
    let node = PingCounter::new().expect("ok");
    assert_eq!(node.name(), "ping_counter");
    assert_eq!(node.out.ros_name(), "ping/count");
    assert_eq!(
        node.publishers(),
        [TopicMetadata {
            topic_name: "ping.count".into(),
            type_name: "std_msgs/msg/Int64".into()
        }]
    );
    assert_eq!(node.subscribers()[0].type_name, "std_msgs/msg/Bool");
    let clock = ManualClock::new();
    let mut s = sched(&clock);
    s.add(node).build().expect("ok");
    s.tick_once().expect("ok");
    assert_eq!(s.node_topics("ping_counter").expect("ok").0.len(), 1);
}
