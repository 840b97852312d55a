//! Service names and the DDS topics and types behind them.

use horus_ros_msgs::{Service, TypeHash};
use horus_ros_rmw::names::ServiceName;
use horus_ros_rmw::qos::Qos;
use horus_ros_rmw::{Node, RawEndpointSpec, ServiceEndpointRole};

use crate::SetupError;

/// The name a service gets when none is given: its type's name in snake case, absolute
/// (`horus_ros/srv/GetMapRegion` → `/get_map_region`).
pub fn default_service_name<S: Service>() -> String {
    default_name_of_type(S::TYPE_NAME)
}

/// [`default_service_name`] of a service type known by its name (`pkg/srv/Name`) at run time.
pub(crate) fn default_name_of_type(type_name: &str) -> String {
    use heck::ToSnakeCase as _;
    let short = type_name.rsplit('/').next().unwrap_or(type_name);
    format!("/{}", short.to_snake_case())
}

/// The history depth of every service writer at least: replies to many concurrent calls must
/// not push each other out of a KEEP_LAST 10 history (services_default's depth) before they are
/// acknowledged. History depth is not sent in DDS discovery, so peers see no difference.
pub(crate) const MIN_SERVICE_HISTORY_DEPTH: usize = 256;

/// The history depth of every service reader at least. A client's reply reader receives the
/// replies to every client of the service from servers that cannot address one reader
/// (rmw_cyclonedds' convention, and the Cyclone backend's: each reply goes to every reply
/// reader and clients pick theirs by the header): with 64 clients waiting, a reader receives 64
/// replies for each of its own, and a client thread that is not scheduled for a while found its
/// reply pushed out of a KEEP_LAST 256 history by those of others (calls lost under load, see the
/// `reliability` benchmark). A server's request reader holds the requests that arrive while its
/// handler runs. The depth bounds memory (a full history is a few hundred KiB of small samples);
/// it is allocated only as samples arrive.
pub(crate) const MIN_SERVICE_READER_HISTORY_DEPTH: usize = 4096;

/// A service's resolved name and the specs of its request and reply topics.
pub(crate) struct ServiceTopics {
    pub(crate) name: ServiceName,
    pub(crate) request: RawEndpointSpec,
    pub(crate) reply: RawEndpointSpec,
}

impl ServiceTopics {
    /// Resolves `name` (relative names, `~`, substitutions) for `node` and names the topics:
    /// `rq/<name>Request` with the request's DDS type name (`pkg::srv::dds_::Name_Request_`) and
    /// hash, `rr/<name>Reply` with the response's (`pkg::srv::dds_::Name_Response_`); both carry
    /// one [`ServiceEndpointId`](horus_ros_rmw::ServiceEndpointId) with the service type's hash.
    pub(crate) fn resolve(
        node: &Node,
        name: &str,
        qos: &Qos,
        role: ServiceEndpointRole,
        service_hash: TypeHash,
        request: (String, TypeHash),
        response: (String, TypeHash),
    ) -> Result<Self, SetupError> {
        let name = ServiceName::expand(name, node.name(), node.namespace()).map_err(|source| {
            SetupError::InvalidName {
                name: name.to_owned(),
                cause: source,
            }
        })?;
        // `-r from:=to` (rcl_remap_service_name), unless the QoS avoids ROS conventions.
        let name = if qos.avoid_ros_namespace_conventions {
            name
        } else {
            match node.context().arguments().remap_service(
                name.as_str(),
                node.name(),
                node.namespace(),
            ) {
                Some(remapped) => {
                    ServiceName::new(&remapped).map_err(|source| SetupError::InvalidName {
                        name: remapped.clone(),
                        cause: horus_ros_rmw::names::ExpandError::InvalidExpansion {
                            expanded: remapped.clone(),
                            cause: source,
                        },
                    })?
                }
                None => name,
            }
        };
        let avoid = qos.avoid_ros_namespace_conventions;
        let keep_last = qos.history == horus_ros_rmw::qos::HistoryPolicy::KeepLast;
        let deepen = |min: usize| {
            let mut qos = *qos;
            if keep_last {
                qos.depth = qos.depth.max(min);
            }
            qos
        };
        let (writer_qos, reader_qos) = (
            deepen(MIN_SERVICE_HISTORY_DEPTH),
            deepen(MIN_SERVICE_READER_HISTORY_DEPTH),
        );
        // A client writes requests and reads replies; a server the other way round.
        let (request_qos, reply_qos) = match role {
            ServiceEndpointRole::Client => (writer_qos, reader_qos),
            ServiceEndpointRole::Server => (reader_qos, writer_qos),
        };
        // One id for both endpoints (announced as `clientid=`/`serviceid=` where USER_DATA is).
        let service_id = Some(node.context().new_service_endpoint_id(role, service_hash));
        Ok(Self {
            request: RawEndpointSpec {
                dds_topic_name: name.to_dds_request_topic_name(avoid),
                dds_type_name: request.0,
                type_hash: request.1,
                qos: request_qos,
                service_id,
            },
            reply: RawEndpointSpec {
                dds_topic_name: name.to_dds_reply_topic_name(avoid),
                dds_type_name: response.0,
                type_hash: response.1,
                qos: reply_qos,
                service_id,
            },
            name,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_names_are_snake_case() {
        assert_eq!(
            default_service_name::<horus_ros_msgs::example_interfaces::srv::AddTwoInts>(),
            "/add_two_ints"
        );
        assert_eq!(
            default_service_name::<horus_ros_msgs::std_srvs::srv::SetBool>(),
            "/set_bool"
        );
    }
}
