//! [`EndpointRole`]: what a DDS reader or writer is to a ROS user, read from its topic name's
//! prefix and its side (rmw_dds_common's mangling: `rt/` topics, `rq/…Request` and
//! `rr/…Reply` services).

use horus_ros_rmw::names::DemangledTopic;
use horus_ros_rmw::qos::EndpointKind;

/// What a DDS endpoint is to ROS: a publisher, a subscription, or which of a service server's
/// or client's two DDS endpoints it is.
///
/// Ordered as listings show them: a topic's publishers then subscriptions, a service's server
/// (request reader, response writer) then client (request writer, response reader) endpoints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum EndpointRole {
    /// A writer on `rt/…`.
    Publisher,
    /// A reader on `rt/…`.
    Subscription,
    /// A service server's reader on `rq/…Request`.
    ServerRequestReader,
    /// A service server's writer on `rr/…Reply`.
    ServerResponseWriter,
    /// A service client's writer on `rq/…Request`.
    ClientRequestWriter,
    /// A service client's reader on `rr/…Reply`.
    ClientResponseReader,
}

/// An endpoint as ROS sees it: its role and the topic or service it serves (e.g. `/chatter`,
/// `/add_two_ints`).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct RosEndpoint {
    /// What it is.
    pub role: EndpointRole,
    /// The ROS topic name (for publishers and subscriptions) or service name.
    pub name: String,
}

impl RosEndpoint {
    /// The endpoint a `kind` endpoint on DDS topic `dds_topic` is; `None` for a topic that is
    /// not ROS (e.g. `ros_discovery_info`).
    pub fn of(dds_topic: &str, kind: EndpointKind) -> Option<Self> {
        use EndpointKind::{Reader, Writer};
        let (role, name) = match (DemangledTopic::from_dds_topic_name(dds_topic), kind) {
            (DemangledTopic::Topic(t), Writer) => (EndpointRole::Publisher, t.as_str().to_owned()),
            (DemangledTopic::Topic(t), Reader) => {
                (EndpointRole::Subscription, t.as_str().to_owned())
            }
            (DemangledTopic::ServiceRequest(s), Reader) => {
                (EndpointRole::ServerRequestReader, s.as_str().to_owned())
            }
            (DemangledTopic::ServiceReply(s), Writer) => {
                (EndpointRole::ServerResponseWriter, s.as_str().to_owned())
            }
            (DemangledTopic::ServiceRequest(s), Writer) => {
                (EndpointRole::ClientRequestWriter, s.as_str().to_owned())
            }
            (DemangledTopic::ServiceReply(s), Reader) => {
                (EndpointRole::ClientResponseReader, s.as_str().to_owned())
            }
            (DemangledTopic::NotRos, _) => return None,
        };
        Some(Self { role, name })
    }
}

impl EndpointRole {
    /// Whether it is one of a service server's or client's two endpoints.
    pub fn is_service(self) -> bool {
        !matches!(self, Self::Publisher | Self::Subscription)
    }

    /// Whether it is one of a service server's two endpoints.
    pub fn is_server(self) -> bool {
        matches!(self, Self::ServerRequestReader | Self::ServerResponseWriter)
    }

    /// Whether it is one of a service client's two endpoints.
    pub fn is_client(self) -> bool {
        matches!(self, Self::ClientRequestWriter | Self::ClientResponseReader)
    }

    /// Reader or writer.
    pub fn kind(self) -> EndpointKind {
        match self {
            Self::Publisher | Self::ServerResponseWriter | Self::ClientRequestWriter => {
                EndpointKind::Writer
            }
            Self::Subscription | Self::ServerRequestReader | Self::ClientResponseReader => {
                EndpointKind::Reader
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_from_dds_topics() {
        use EndpointKind::{Reader, Writer};
        let of = |topic: &str, kind| RosEndpoint::of(topic, kind).map(|e| (e.role, e.name));
        let cases = [
            (
                "rt/ns/chatter",
                Writer,
                EndpointRole::Publisher,
                "/ns/chatter",
            ),
            ("rt/chatter", Reader, EndpointRole::Subscription, "/chatter"),
            (
                "rq/add_two_intsRequest",
                Reader,
                EndpointRole::ServerRequestReader,
                "/add_two_ints",
            ),
            (
                "rr/add_two_intsReply",
                Writer,
                EndpointRole::ServerResponseWriter,
                "/add_two_ints",
            ),
            (
                "rq/add_two_intsRequest",
                Writer,
                EndpointRole::ClientRequestWriter,
                "/add_two_ints",
            ),
            (
                "rr/add_two_intsReply",
                Reader,
                EndpointRole::ClientResponseReader,
                "/add_two_ints",
            ),
        ];
        for (topic, kind, role, name) in cases {
            assert_eq!(
                of(topic, kind),
                Some((role, name.to_owned())),
                "{topic} {kind:?}"
            );
            assert_eq!(role.kind(), kind);
            assert_eq!(role.is_service(), role.is_server() || role.is_client());
        }
        assert_eq!(of("ros_discovery_info", Reader), None);
    }
}
