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
        // The QoS as asked for is what the endpoints announce (rmw_zenoh's SS/SC tokens carry its
        // depth); the rmw layer keeps deeper local histories for service endpoints
        // (`RawEndpointSpec::local_qos`).
        // One id for both endpoints (announced as `clientid=`/`serviceid=` where USER_DATA is).
        let service_id = Some(node.context().new_service_endpoint_id(role, service_hash));
        Ok(Self {
            request: RawEndpointSpec {
                dds_topic_name: name.to_dds_request_topic_name(avoid),
                dds_type_name: request.0,
                type_hash: request.1,
                qos: *qos,
                service_id,
            },
            reply: RawEndpointSpec {
                dds_topic_name: name.to_dds_reply_topic_name(avoid),
                dds_type_name: response.0,
                type_hash: response.1,
                qos: *qos,
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
