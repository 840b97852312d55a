//! Context shutdown and the SIGINT/SIGTERM handlers, in this process: a signal the program
//! handles (a watched context, a hook) shuts down exactly the contexts that asked for it, wakes
//! their waiters and runs their callbacks and the hooks, and leaves the process running.
//!
//! A signal reaches every context of the process, so this file raises one signal only (a
//! second would end the process, as designed), and the other test's contexts opt out of
//! signals. How an unhandled signal ends a program, seen by a real rclpy peer:
//! `services/tests/goodbye.rs`.

use std::future::Future;
use std::pin::pin;
use std::sync::mpsc;
use std::sync::Arc;
use std::task::{Wake, Waker};
use std::thread::Thread;
use std::time::Duration;

use horus_ros_rmw::signal_handler::{self, ShutdownSignal, SignalHandlerOptions};
use horus_ros_rmw::Context;
use nix::sys::signal::{raise, Signal};

/// A "did not hang" bound for what the signal thread does.
const LIMIT: Duration = Duration::from_secs(10);

fn context(domain: u32, signals: SignalHandlerOptions) -> Context {
    Context::builder()
        .domain_id(domain)
        .signal_handler(signals)
        .build()
        .expect("context")
}

/// Wakes the thread that waits for a future.
struct Unpark(Thread);

impl Wake for Unpark {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

#[test]
fn sigint_shuts_down_the_contexts_that_asked_for_it_and_the_program_goes_on() {
    let watched = context(61, SignalHandlerOptions::All);
    let sigint_only = context(61, SignalHandlerOptions::SigInt);
    let sigterm_only = context(61, SignalHandlerOptions::SigTerm);
    let opted_out = context(61, SignalHandlerOptions::None);
    let installed = signal_handler::installed_signals();
    assert!(
        installed.contains(&ShutdownSignal::Interrupt)
            && installed.contains(&ShutdownSignal::Terminate),
        "{installed:?}"
    );

    let (reasons, reason) = mpsc::channel();
    watched.on_shutdown(move |why| {
        let _ = reasons.send(why.to_owned());
    });
    let (signals, signalled) = mpsc::channel();
    let _hook = signal_handler::on_signal(&[ShutdownSignal::Interrupt], move |s| {
        let _ = signals.send(s);
    })
    .expect("hook");
    let mut shutdown = pin!(sigint_only.wait_for_shutdown_async());
    let waker = Waker::from(Arc::new(Unpark(std::thread::current())));
    let mut cx = std::task::Context::from_waker(&waker);
    assert!(shutdown.as_mut().poll(&mut cx).is_pending());

    raise(Signal::SIGINT).expect("raise SIGINT");

    assert_eq!(
        reason.recv_timeout(LIMIT).as_deref(),
        Ok("signal handler: SIGINT")
    );
    assert_eq!(signalled.recv_timeout(LIMIT), Ok(ShutdownSignal::Interrupt));
    assert!(watched.wait_for_shutdown(LIMIT));
    assert!(!watched.ok());
    // The future was woken by the shutdown itself.
    let deadline = std::time::Instant::now() + LIMIT;
    while shutdown.as_mut().poll(&mut cx).is_pending() {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        assert!(!left.is_zero(), "the shutdown future was never woken");
        std::thread::park_timeout(left);
    }
    assert_eq!(
        sigint_only.shutdown_reason().as_deref(),
        Some("signal handler: SIGINT")
    );
    assert!(sigterm_only.ok(), "SIGINT shut down a SIGTERM-only context");
    assert!(opted_out.ok(), "SIGINT shut down a context that opted out");
    // Shut down, the participant still works: a node can still be made and announced.
    let node = watched.create_node("after_shutdown", "/").expect("node");
    assert_eq!(node.name().as_str(), "after_shutdown");
}

#[test]
fn a_context_shuts_down_once_and_wakes_its_waiters() {
    let context = context(62, SignalHandlerOptions::None);
    assert_eq!(context.signal_handler(), SignalHandlerOptions::None);
    assert!(context.ok());
    assert!(!context.wait_for_shutdown(Duration::from_millis(1)));
    let waiter = {
        let context = context.clone();
        std::thread::spawn(move || context.wait_for_shutdown(None))
    };
    let (calls, called) = mpsc::channel();
    let early = calls.clone();
    context.on_shutdown(move |why| {
        let _ = early.send(format!("early: {why}"));
    });
    context.on_shutdown(|_| panic!("a panicking callback is logged, nothing more"));
    assert!(context.shutdown("done"));
    assert!(!context.shutdown("again"), "a second shutdown");
    assert!(waiter.join().expect("waiter"));
    assert_eq!(called.recv_timeout(LIMIT).as_deref(), Ok("early: done"));
    // Registered after the shutdown: runs at once.
    context.on_shutdown(move |why| {
        let _ = calls.send(format!("late: {why}"));
    });
    assert_eq!(called.recv_timeout(LIMIT).as_deref(), Ok("late: done"));
    assert!(!context.ok());
    assert!(context.wait_for_shutdown(None));
    assert_eq!(context.shutdown_reason().as_deref(), Some("done"));
    // A clone shares the state.
    assert!(!context.clone().ok());
}
