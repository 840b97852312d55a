//! `hlog!`: logging from nodes, to `tracing` and (as rcl does for every node) to `/rosout`.

use std::fmt;

use crate::api::runtime::with_current_ref;

/// Severity of a log message; the values are `rcl_interfaces/msg/Log`'s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(u8)]
pub enum LogLevel {
    /// `Log.DEBUG` (10).
    Debug = 10,
    /// `Log.INFO` (20).
    Info = 20,
    /// `Log.WARN` (30).
    Warn = 30,
    /// `Log.ERROR` (40).
    Error = 40,
    /// `Log.FATAL` (50).
    Fatal = 50,
}

/// Logs `args` at `level` under the current node (used by [`hlog!`](crate::hlog!)).
#[doc(hidden)]
pub fn log(
    level: LogLevel,
    file: &'static str,
    line: u32,
    function: &'static str,
    args: fmt::Arguments<'_>,
) {
    with_current_ref(|node| {
        let name = node.map(|n| n.name.as_str()).unwrap_or("horus");
        let ros = node.and_then(|n| n.ros());
        if let Some(ros) = &ros {
            if !ros.log_enabled(level) {
                return;
            }
            ros.publish_log(level, file, line, function, &args);
        } else if level < LogLevel::Info && !tracing::enabled!(tracing::Level::DEBUG) {
            return;
        }
        match level {
            LogLevel::Debug => tracing::debug!(target: "horus", node = name, "{args}"),
            LogLevel::Info => tracing::info!(target: "horus", node = name, "{args}"),
            LogLevel::Warn => tracing::warn!(target: "horus", node = name, "{args}"),
            LogLevel::Error | LogLevel::Fatal => {
                tracing::error!(target: "horus", node = name, "{args}")
            }
        }
    });
}

/// Logs from a node: `hlog!(info, "Lidar connected on {}", port)`. Levels: `trace`/`debug`,
/// `info`, `warn`, `error`, `fatal`.
///
/// The message goes to `tracing` (target `horus`, field `node`) and, for a node on the ROS
/// graph, to `/rosout` as an `rcl_interfaces/msg/Log` with the node's logger name, as rcl
/// publishes every node's log messages (`--disable-rosout-logs` turns that off;
/// `--log-level [name:=]level` filters).
#[macro_export]
macro_rules! hlog {
    (trace, $($arg:tt)+) => { $crate::hlog!(@at Debug, $($arg)+) };
    (debug, $($arg:tt)+) => { $crate::hlog!(@at Debug, $($arg)+) };
    (info, $($arg:tt)+) => { $crate::hlog!(@at Info, $($arg)+) };
    (warn, $($arg:tt)+) => { $crate::hlog!(@at Warn, $($arg)+) };
    (error, $($arg:tt)+) => { $crate::hlog!(@at Error, $($arg)+) };
    (fatal, $($arg:tt)+) => { $crate::hlog!(@at Fatal, $($arg)+) };
    (@at $level:ident, $($arg:tt)+) => {
        $crate::__private::log(
            $crate::LogLevel::$level,
            ::core::file!(),
            ::core::line!(),
            ::core::module_path!(),
            ::core::format_args!($($arg)+),
        )
    };
}
