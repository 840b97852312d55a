//! SIGINT and SIGTERM shut the process's contexts down, as rclcpp and rclpy do (rclcpp
//! `signal_handler.cpp`, installed by `rclcpp::init` with `SignalHandlerOptions::All`; rclpy
//! `signal_handler.cpp`, installed by `rclpy.init`), so that a program stopped by either leaves
//! every peer's graph at once instead of lingering there until its DDS lease ends.
//!
//! - The first [`Context`](crate::Context) built asking for a signal (by default
//!   [`SignalHandlerOptions::All`]) installs its handler, process-wide and once, through
//!   `signal-hook`: the handler only writes to a pipe; a dedicated thread named `horus-signals`
//!   does the work, never in signal context.
//! - On a signal, that thread [shuts down](crate::Context::shutdown) every live context that
//!   asked for it (waking [`wait_for_shutdown`](crate::Context::wait_for_shutdown) and running
//!   [`on_shutdown`](crate::Context::on_shutdown) callbacks), then calls the [`SignalHook`]s
//!   registered for it.
//! - If the program handles shutdown — a hook is registered, or one of those contexts is
//!   watched: asked [`ok`](crate::Context::ok), waited on, or given an `on_shutdown` callback —
//!   it is left to end on its own (it drops its contexts, which takes them off the graph).
//!   Otherwise, and on any signal after one was left to the program, each of those contexts
//!   says goodbye at once — its nodes withdrawn on `ros_discovery_info` (acknowledged by the
//!   peers, 1 s at most), then its DDS participant deleted with all on it (its disposes) — and
//!   the signal is raised again with its default action: the process ends as signalled (exit
//!   status 130 / 143 in a shell), like an rclpy program on an unhandled `KeyboardInterrupt`.
//! - Opting out: [`ContextBuilder::signal_handler`](crate::ContextBuilder::signal_handler) per
//!   context, [`set_default_signal_handler_options`] for every context built without it (e.g.
//!   the process's default node in `horus-ros-services`). A signal no context and no hook asked
//!   for keeps its default action. Handlers installed with `sigaction` after ours (the `ctrlc`
//!   crate) replace ours: the program then handles the signal alone.

use std::collections::BTreeSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::{mpsc, Arc, Mutex, MutexGuard, Weak};
use std::time::Duration;

use signal_hook::consts::signal::{SIGHUP, SIGINT, SIGTERM};

use crate::context::ContextInner;

/// Which signals shut a context down (rclcpp's and rclpy's `SignalHandlerOptions`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SignalHandlerOptions {
    /// SIGINT and SIGTERM (the default, as `rclcpp::init`'s).
    #[default]
    All,
    /// SIGINT only.
    SigInt,
    /// SIGTERM only.
    SigTerm,
    /// Neither: both keep their default action (or whatever the program installs).
    None,
}

impl SignalHandlerOptions {
    /// Whether `signal` is one of these.
    pub fn handles(self, signal: ShutdownSignal) -> bool {
        matches!(
            (self, signal),
            (
                Self::All,
                ShutdownSignal::Interrupt | ShutdownSignal::Terminate
            ) | (Self::SigInt, ShutdownSignal::Interrupt)
                | (Self::SigTerm, ShutdownSignal::Terminate)
        )
    }

    /// The signals these options name.
    pub fn signals(self) -> Vec<ShutdownSignal> {
        [ShutdownSignal::Interrupt, ShutdownSignal::Terminate]
            .into_iter()
            .filter(|s| self.handles(*s))
            .collect()
    }

    fn to_u8(self) -> u8 {
        match self {
            Self::All => 0,
            Self::SigInt => 1,
            Self::SigTerm => 2,
            Self::None => 3,
        }
    }

    fn from_u8(v: u8) -> Self {
        match v {
            1 => Self::SigInt,
            2 => Self::SigTerm,
            3 => Self::None,
            _ => Self::All,
        }
    }
}

/// A signal that asks a process to end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShutdownSignal {
    /// SIGINT (Ctrl+C).
    Interrupt,
    /// SIGTERM (`kill`, `ros2 launch` after SIGINT, service managers).
    Terminate,
    /// SIGHUP (the terminal went away); only [`SignalHook`]s ask for it.
    Hangup,
}

impl ShutdownSignal {
    /// The signal's number.
    pub fn number(self) -> i32 {
        match self {
            Self::Interrupt => SIGINT,
            Self::Terminate => SIGTERM,
            Self::Hangup => SIGHUP,
        }
    }

    fn from_number(n: i32) -> Option<Self> {
        [Self::Interrupt, Self::Terminate, Self::Hangup]
            .into_iter()
            .find(|s| s.number() == n)
    }

    /// The exit status a shell shows for a process this signal ended (128 + its number).
    pub fn exit_status(self) -> i32 {
        128 + self.number()
    }
}

impl std::fmt::Display for ShutdownSignal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Interrupt => "SIGINT",
            Self::Terminate => "SIGTERM",
            Self::Hangup => "SIGHUP",
        })
    }
}

/// Why a signal handler could not be installed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SignalHandlerError {
    /// The pipe from the handler to the signal thread could not be made.
    #[error("could not set up the signal pipe")]
    Pipe(#[source] std::io::Error),
    /// The OS refused the handler (`sigaction`).
    #[error("could not install the handler of {signal}")]
    Install {
        /// The signal.
        signal: ShutdownSignal,
        /// What the OS said.
        #[source]
        source: std::io::Error,
    },
    /// The signal thread could not be started.
    #[error("could not start the signal thread")]
    Thread(#[source] std::io::Error),
}

/// What contexts built without [`ContextBuilder::signal_handler`](crate::ContextBuilder::signal_handler)
/// ask for (initially [`SignalHandlerOptions::All`]). Set it before the first context is built,
/// e.g. to `None` in a program that handles SIGINT and SIGTERM itself.
pub fn set_default_signal_handler_options(options: SignalHandlerOptions) {
    DEFAULT_OPTIONS.store(options.to_u8(), Ordering::SeqCst);
}

/// See [`set_default_signal_handler_options`].
pub fn default_signal_handler_options() -> SignalHandlerOptions {
    SignalHandlerOptions::from_u8(DEFAULT_OPTIONS.load(Ordering::SeqCst))
}

/// Installs the handlers of these signals now (each once per process; building a context does
/// it for the signals it asks for), as `rclcpp::install_signal_handlers`.
pub fn install_signal_handlers(options: SignalHandlerOptions) -> Result<(), SignalHandlerError> {
    install(&options.signals())
}

/// The signals whose handlers are installed.
pub fn installed_signals() -> Vec<ShutdownSignal> {
    lock(&DISPATCHER)
        .as_ref()
        .map(|d| d.installed.iter().copied().collect())
        .unwrap_or_default()
}

/// Calls `callback` on the signal thread for each of `signals` that comes while the returned
/// hook lives (after the contexts are shut down): the program handles these signals itself, so
/// they no longer end the process (a second one still does, after the goodbye). Installs their
/// handlers if needed. For schedulers and event loops that stop on a signal.
pub fn on_signal(
    signals: &[ShutdownSignal],
    callback: impl Fn(ShutdownSignal) + Send + Sync + 'static,
) -> Result<SignalHook, SignalHandlerError> {
    install(signals)?;
    let hook = Arc::new(Hook {
        signals: signals.iter().copied().collect(),
        callback: Box::new(callback),
    });
    let mut hooks = lock(&HOOKS);
    hooks.retain(|h| h.strong_count() > 0);
    hooks.push(Arc::downgrade(&hook));
    Ok(SignalHook { _hook: hook })
}

/// A registered [`on_signal`] callback; dropping it unregisters it.
#[must_use = "the callback is unregistered when the hook is dropped"]
pub struct SignalHook {
    _hook: Arc<Hook>,
}

impl std::fmt::Debug for SignalHook {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SignalHook")
            .field("signals", &self._hook.signals)
            .finish()
    }
}

struct Hook {
    signals: BTreeSet<ShutdownSignal>,
    callback: Box<dyn Fn(ShutdownSignal) + Send + Sync>,
}

/// How long the goodbye of an unhandled signal may take before the signal is raised anyway (a
/// participant's deletion joins its DDS threads; it must not keep a signalled process alive).
const GOODBYE_LIMIT: Duration = Duration::from_secs(3);

static DEFAULT_OPTIONS: AtomicU8 = AtomicU8::new(0);
static DISPATCHER: Mutex<Option<Dispatcher>> = Mutex::new(None);
static CONTEXTS: Mutex<Vec<Weak<ContextInner>>> = Mutex::new(Vec::new());
static HOOKS: Mutex<Vec<Weak<Hook>>> = Mutex::new(Vec::new());
/// Set once a signal was left to the program: the next one ends the process.
static HANDLING: AtomicBool = AtomicBool::new(false);

/// The installed handlers and the way to add more to the signal thread's set.
struct Dispatcher {
    handle: signal_hook::iterator::Handle,
    installed: BTreeSet<ShutdownSignal>,
}

/// Installs the handlers of `signals` not installed yet, starting the signal thread first.
fn install(signals: &[ShutdownSignal]) -> Result<(), SignalHandlerError> {
    if signals.is_empty() {
        return Ok(());
    }
    let mut dispatcher = lock(&DISPATCHER);
    if dispatcher.is_none() {
        let mut iterator = signal_hook::iterator::Signals::new(std::iter::empty::<i32>())
            .map_err(SignalHandlerError::Pipe)?;
        let handle = iterator.handle();
        std::thread::Builder::new()
            .name("horus-signals".to_owned())
            .spawn(move || {
                for number in iterator.forever() {
                    if let Some(signal) = ShutdownSignal::from_number(number) {
                        deliver(signal);
                    }
                }
            })
            .map_err(SignalHandlerError::Thread)?;
        *dispatcher = Some(Dispatcher {
            handle,
            installed: BTreeSet::new(),
        });
    }
    let Some(d) = dispatcher.as_mut() else {
        return Ok(());
    };
    for &signal in signals {
        if d.installed.contains(&signal) {
            continue;
        }
        d.handle
            .add_signal(signal.number())
            .map_err(|source| SignalHandlerError::Install { signal, source })?;
        d.installed.insert(signal);
        tracing::debug!(%signal, "installed the signal handler");
    }
    Ok(())
}

/// Registers a new context: the signal thread shuts it down on the signals it asked for.
pub(crate) fn register_context(context: &Arc<ContextInner>) -> Result<(), SignalHandlerError> {
    install(&context.shutdown.signals().signals())?;
    let mut contexts = lock(&CONTEXTS);
    contexts.retain(|c| c.strong_count() > 0);
    contexts.push(Arc::downgrade(context));
    Ok(())
}

/// What the signal thread does with one signal (see the module's documentation).
fn deliver(signal: ShutdownSignal) {
    tracing::debug!(%signal, "signal received");
    let contexts: Vec<Arc<ContextInner>> = lock(&CONTEXTS)
        .iter()
        .filter_map(Weak::upgrade)
        .filter(|c| c.shutdown.signals().handles(signal))
        .collect();
    let reason = format!("signal handler: {signal}");
    let mut watched = false;
    for context in &contexts {
        context.shutdown.shutdown(&reason);
        watched |= context.shutdown.is_watched();
    }
    let hooks: Vec<Arc<Hook>> = lock(&HOOKS)
        .iter()
        .filter_map(Weak::upgrade)
        .filter(|h| h.signals.contains(&signal))
        .collect();
    for hook in &hooks {
        if catch_unwind(AssertUnwindSafe(|| (hook.callback)(signal))).is_err() {
            tracing::error!(%signal, "a signal hook panicked");
        }
    }
    let handled = watched || !hooks.is_empty();
    if handled && !HANDLING.swap(true, Ordering::SeqCst) {
        tracing::debug!(%signal, "left to the program");
        return;
    }
    goodbye(contexts);
    tracing::debug!(%signal, "ending the process as signalled");
    if let Err(e) = signal_hook::low_level::emulate_default_handler(signal.number()) {
        tracing::error!(%signal, "could not end the process as signalled: {e}");
        std::process::exit(signal.exit_status());
    }
}

/// Deletes the participants of `contexts` (peers see them leave at once), waiting for it at
/// most [`GOODBYE_LIMIT`].
fn goodbye(contexts: Vec<Arc<ContextInner>>) {
    if contexts.is_empty() {
        return;
    }
    let (done, finished) = mpsc::channel::<()>();
    let spawned = std::thread::Builder::new()
        .name("horus-goodbye".to_owned())
        .spawn(move || {
            for context in &contexts {
                context.goodbye();
            }
            let _ = done.send(());
        });
    match spawned {
        Ok(_) => {
            if finished.recv_timeout(GOODBYE_LIMIT).is_err() {
                tracing::warn!("the participants' goodbye took longer than {GOODBYE_LIMIT:?}");
            }
        }
        Err(e) => tracing::warn!("could not start the goodbye: {e}"),
    }
}

/// Locks a mutex whose data stays consistent even if a holder panicked.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_name_their_signals() {
        use ShutdownSignal::*;
        assert_eq!(SignalHandlerOptions::All.signals(), [Interrupt, Terminate]);
        assert_eq!(SignalHandlerOptions::SigInt.signals(), [Interrupt]);
        assert_eq!(SignalHandlerOptions::SigTerm.signals(), [Terminate]);
        assert!(SignalHandlerOptions::None.signals().is_empty());
        assert!(!SignalHandlerOptions::All.handles(Hangup));
        for o in [
            SignalHandlerOptions::All,
            SignalHandlerOptions::SigInt,
            SignalHandlerOptions::SigTerm,
            SignalHandlerOptions::None,
        ] {
            assert_eq!(SignalHandlerOptions::from_u8(o.to_u8()), o);
        }
    }

    #[test]
    fn signals_have_their_numbers_and_shell_statuses() {
        assert_eq!(ShutdownSignal::Interrupt.number(), 2);
        assert_eq!(ShutdownSignal::Interrupt.exit_status(), 130);
        assert_eq!(ShutdownSignal::Terminate.exit_status(), 143);
        assert_eq!(ShutdownSignal::from_number(1), Some(ShutdownSignal::Hangup));
        assert_eq!(ShutdownSignal::from_number(10), None);
        assert_eq!(ShutdownSignal::Terminate.to_string(), "SIGTERM");
    }
}
