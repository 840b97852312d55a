//! `horus-ros service call` (ros2service jazzy `verb/call.py`): fills the request from YAML as
//! `rosidl_runtime_py.set_message_fields` does, calls, and prints
//!
//! ```text
//! requester: making request: example_interfaces.srv.AddTwoInts_Request(a=2, b=3)
//!
//! response:
//! example_interfaces.srv.AddTwoInts_Response(sum=5)
//!
//! ```
//!
//! Every type goes through one dynamic path ([`crate::dynamic`]): types compiled into
//! horus-ros-msgs use their compiled description; any other type is described by its server's
//! node through `~/get_type_description` ([`describe`]), so no package needs installing.
//!
//! Unlike ros2cli, which waits for a server forever, we print ros2cli's
//! `waiting for service to become available...` and give up after `--timeout` seconds; each
//! call also waits at most `--timeout` for its reply. Failures are one line on stderr, exit 1.

pub(crate) mod describe;

use std::time::{Duration, Instant};

use horus_ros_graph::GraphCache;
use horus_ros_rmw::names::ServiceName;

use crate::dynamic::{ServiceType, Value};
use crate::session::Session;
use crate::verb::type_name::normalize_service_type;
use crate::{CliError, Global};
use horus_ros_services::{
    DynamicCallError, DynamicServiceClient, EndpointBuilder, RawResponse, ServiceError,
    TransportError,
};

/// Arguments of `service call`.
#[derive(Debug, clap::Args)]
pub struct CallArgs {
    /// Name of the ROS service to call to (e.g. '/add_two_ints').
    pub service_name: String,
    /// Type of the ROS service (e.g. 'std_srvs/srv/Empty').
    pub service_type: String,
    /// Values to fill the service request with in YAML format (e.g. '{a: 1, b: 2}'), otherwise
    /// the service request will be published with default values.
    #[arg(default_value = "{}", conflicts_with = "stdin")]
    pub values: String,
    /// Read values from standard input.
    #[arg(long)]
    pub stdin: bool,
    /// Repeat the call at a specific rate in Hz.
    #[arg(short = 'r', long, value_name = "N")]
    pub rate: Option<f64>,
    /// Longest wait for a server to appear, and for each reply, in seconds (ros2cli waits for
    /// the server forever).
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 10.0,
        allow_negative_numbers = true,
        value_parser = crate::args::seconds
    )]
    pub timeout: f64,
    /// Stop after this many calls (with -r; for tests).
    #[arg(long, hide = true, value_name = "N")]
    pub count: Option<u64>,
}

/// Runs `service call`.
pub fn run(global: &Global, args: &CallArgs) -> Result<(), CliError> {
    let period = match args.rate {
        Some(r) if r <= 0.0 || r.is_nan() => {
            return Err(CliError::new("rate must be greater than zero"))
        }
        Some(r) => Some(Duration::from_secs_f64(1.0 / r)),
        None => None,
    };
    let timeout = Duration::from_secs_f64(args.timeout);
    // ros2cli's `collect_stdin`: all of standard input, as the values.
    let values = if args.stdin {
        std::io::read_to_string(std::io::stdin())
            .map_err(|e| CliError::new(format!("Cannot read the values from stdin: {e}")))?
    } else {
        args.values.clone()
    };
    let target = Target::prepare(&args.service_type, &values)?;
    let opened = target.open(global, &args.service_name, timeout)?;
    let mut client = opened.client()?;
    let request_repr = opened.request_repr();
    let mut calls = 0u64;
    loop {
        println!("requester: making request: {request_repr}\n");
        let last_call = Instant::now();
        let response = client
            .call_value(&opened.request, timeout)
            .map_err(|e| match e {
                DynamicCallError::Call(e) => call_error(e, &opened.service, timeout),
                e => CliError::new(format!("Cannot call {}: {e}", opened.service)),
            })?;
        println!("response:\n{}\n", opened.info.response_repr(&response));
        calls += 1;
        let Some(period) = period else { break };
        if args.count.is_some_and(|n| calls >= n) {
            break;
        }
        if let Some(wait) = (last_call + period).checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    Ok(())
}

/// A service type and the request's YAML, checked: what `service call` and `service bench`
/// share before joining the graph.
pub(crate) struct Target {
    service_type: String,
    values: String,
    /// The type information and the request, when the type is compiled in.
    compiled: Option<(ServiceType, Value)>,
}

impl Target {
    /// Checks the type and, when it is compiled in, the request — before joining the graph, as
    /// ros2cli does.
    pub(crate) fn prepare(service_type: &str, values: &str) -> Result<Self, CliError> {
        let service_type = normalize_service_type(service_type)?;
        // ros2cli loads the YAML before anything else.
        if let Err(e) = yaml_rust2::YamlLoader::load_from_str(values) {
            return Err(CliError::new(format!(
                "Failed to parse values as YAML: {e}"
            )));
        }
        let compiled = match ServiceType::compiled(&service_type) {
            Some(info) => {
                let request = fill(&info, values)?;
                Some((info, request))
            }
            None => None,
        };
        Ok(Self {
            service_type,
            values: values.to_owned(),
            compiled,
        })
    }

    /// Joins the graph, resolves `service_name`, waits (within `timeout`) for a server, learns
    /// the type from its node if it is not compiled in, and encodes the request.
    pub(crate) fn open(
        self,
        global: &Global,
        service_name: &str,
        timeout: Duration,
    ) -> Result<Opened, CliError> {
        self.open_in(Session::open(global)?, service_name, timeout)
    }

    /// [`open`](Self::open) in a session already open.
    pub(crate) fn open_in(
        self,
        session: Session,
        service_name: &str,
        timeout: Duration,
    ) -> Result<Opened, CliError> {
        let service =
            ServiceName::expand(service_name, session.node.name(), session.node.namespace())
                .map_err(|e| {
                    CliError::new(format!("Invalid service name '{service_name}': {e}"))
                })?;
        let service_type = self.service_type;
        // A type not compiled in can only be learnt from a server that offers it; ros2cli
        // fails at once on a type it cannot import, and so do we when no server in the graph
        // has it.
        if self.compiled.is_none() && !type_offered(&session, &service_type) {
            tracing::debug!(
                %service_type,
                "not compiled in, and no node in the graph uses it (a server's \
                 ~/get_type_description would describe it)"
            );
            return Err(CliError::new("The passed service type is invalid"));
        }
        if !session
            .graph
            .read(|c| server_listed(c, service.as_str(), &service_type))
        {
            println!("waiting for service to become available...");
            // Checked at once and after every graph change.
            let listed = session.graph.wait_until(timeout, |c| {
                server_listed(c, service.as_str(), &service_type)
            });
            if !listed {
                return Err(no_server(
                    &session,
                    service.as_str(),
                    &service_type,
                    timeout,
                ));
            }
        }
        let (info, request) = match self.compiled {
            Some(compiled) => compiled,
            None => {
                let info = describe::fetch(
                    &session.node,
                    &session.graph,
                    service.as_str(),
                    &service_type,
                    timeout,
                )
                .map_err(|e| CliError::new(format!("Cannot call {service}: {e}")))?;
                let request = fill(&info, &self.values)?;
                (info, request)
            }
        };
        let body = info
            .encode_request(&request)
            .map_err(|e| CliError::new(format!("Cannot encode the request: {e}")))?;
        Ok(Opened {
            session,
            service,
            service_type,
            info,
            request,
            body,
        })
    }
}

/// The request of `info` filled from `values`.
fn fill(info: &ServiceType, values: &str) -> Result<Value, CliError> {
    info.request_from_yaml(values)
        .map_err(|e| CliError::new(format!("Failed to populate field: {e}")))
}

/// A [`Target`] on the graph: the session, the service's full name and type, the encoded
/// request.
pub(crate) struct Opened {
    /// The CLI's session (its node and graph).
    pub(crate) session: Session,
    /// The fully-qualified service name.
    pub(crate) service: ServiceName,
    /// The service type (`pkg/srv/Name`).
    pub(crate) service_type: String,
    info: ServiceType,
    request: Value,
    /// The encoded request.
    pub(crate) body: Vec<u8>,
}

impl Opened {
    /// A new client of the service on the session's node.
    pub(crate) fn client(&self) -> Result<DynamicServiceClient, CliError> {
        Ok(DynamicServiceClient::builder(self.info.clone())
            .name(self.service.as_str())
            .node(&self.session.node)
            .build()?)
    }

    /// The request as Python's `repr` shows it.
    pub(crate) fn request_repr(&self) -> String {
        self.info.request_repr(&self.request)
    }

    /// A reply decoded as the response type, as Python's `repr` shows it.
    pub(crate) fn response_repr(&self, reply: &RawResponse) -> Result<String, CliError> {
        let response = self
            .info
            .decode_response(&reply.body, reply.big_endian)
            .map_err(|e| {
                CliError::new(format!(
                    "Cannot decode the response of {}: {e}",
                    self.service
                ))
            })?;
        Ok(self.info.response_repr(&response))
    }
}

/// Whether any server or client in the graph has type `service_type`.
fn type_offered(session: &Session, service_type: &str) -> bool {
    session.graph.read(|c| {
        c.service_names_and_types(true)
            .values()
            .any(|types| types.iter().any(|t| t == service_type))
    })
}

/// Whether the graph lists a server of `service` with this type, both endpoints known.
fn server_listed(cache: &GraphCache, service: &str, service_type: &str) -> bool {
    cache
        .servers_info_by_service(service, false)
        .is_ok_and(|s| s.iter().any(|s| s.service_type == service_type))
}

fn no_server(session: &Session, service: &str, service_type: &str, timeout: Duration) -> CliError {
    let others: Vec<String> = session.graph.read(|c| {
        c.service_names_and_types(true)
            .get(service)
            .map(|t| t.iter().filter(|t| *t != service_type).cloned().collect())
            .unwrap_or_default()
    });
    if others.is_empty() {
        CliError::new(format!(
            "No server of {service} appeared within {} s",
            timeout.as_secs_f64()
        ))
    } else {
        CliError::new(format!(
            "Service {service} has type {}, not {service_type}",
            others.join(", ")
        ))
    }
}

pub(crate) fn call_error(e: ServiceError, service: &ServiceName, timeout: Duration) -> CliError {
    CliError::new(match e {
        ServiceError::NoServer => format!(
            "The server of {service} did not become reachable within {} s",
            timeout.as_secs_f64()
        ),
        ServiceError::Timeout => format!(
            "No response from {service} within {} s",
            timeout.as_secs_f64()
        ),
        ServiceError::ServiceFailed(m) => format!("The service {service} failed: {m}"),
        ServiceError::Transport(TransportError::ServerGone) => {
            format!("The server of {service} left before answering")
        }
        ServiceError::Transport(cause) => format!("Calling {service} failed: {cause}"),
    })
}
