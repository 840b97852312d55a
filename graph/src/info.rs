//! Endpoint information by topic and by service, printed as rclpy prints it.
//!
//! `Display` follows rclpy `rclpy/endpoint_info.py` (rolling): `TopicEndpointInfo.__str__`
//! (the same text as jazzy's `topic_endpoint_info.py`) and `ServiceEndpointInfo.__str__`.

use std::fmt;

use horus_ros_msgs::rmw_dds_common::Gid;
use horus_ros_msgs::TypeHash;
use horus_ros_rmw::qos::Qos;

/// Kind of a topic endpoint (`rmw_endpoint_type_t`: PUBLISHER / SUBSCRIPTION).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TopicEndpointType {
    /// A DDS writer on an `rt/` topic.
    Publisher,
    /// A DDS reader on an `rt/` topic.
    Subscription,
}

impl fmt::Display for TopicEndpointType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Publisher => "PUBLISHER",
            Self::Subscription => "SUBSCRIPTION",
        })
    }
}

/// Kind of a service endpoint (`rmw_endpoint_type_t`: CLIENT / SERVER).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ServiceEndpointType {
    /// A service client: response reader + request writer.
    Client,
    /// A service server: request reader + response writer.
    Server,
}

impl fmt::Display for ServiceEndpointType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Client => "CLIENT",
            Self::Server => "SERVER",
        })
    }
}

/// rclpy `TypeHash.__str__`: `INVALID` for an unset hash (version 0), else `RIHS01_<hex>`.
fn type_hash_text(hash: &TypeHash) -> String {
    if hash.is_set() {
        hash.to_string()
    } else {
        "INVALID".to_owned()
    }
}

/// One publisher or subscription of a topic (`rmw_topic_endpoint_info_t`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicEndpointInfo {
    /// Name of the node owning the endpoint (or a `_…_` placeholder, see the crate constants).
    pub node_name: String,
    /// Namespace of that node.
    pub node_namespace: String,
    /// Demangled type, e.g. `std_msgs/msg/String` (the DDS name when not a ROS type).
    pub topic_type: String,
    /// Type hash from USER_DATA; [`TypeHash::ZERO`] when unknown.
    pub topic_type_hash: TypeHash,
    /// Publisher or subscription.
    pub endpoint_type: TopicEndpointType,
    /// The endpoint's GID.
    pub endpoint_gid: Gid,
    /// The endpoint's QoS.
    pub qos_profile: Qos,
}

/// As `ros2 topic info -v` prints each endpoint (no trailing newline).
impl fmt::Display for TopicEndpointInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Node name: {}", self.node_name)?;
        writeln!(f, "Node namespace: {}", self.node_namespace)?;
        writeln!(f, "Topic type: {}", self.topic_type)?;
        writeln!(
            f,
            "Topic type hash: {}",
            type_hash_text(&self.topic_type_hash)
        )?;
        writeln!(f, "Endpoint type: {}", self.endpoint_type)?;
        writeln!(f, "GID: {}", self.endpoint_gid)?;
        f.write_str("QoS profile:")?;
        for line in self.qos_profile.info_lines() {
            write!(f, "\n  {line}")?;
        }
        Ok(())
    }
}

/// One server or client of a service (`rmw_service_endpoint_info_t`, rolling).
///
/// On DDS a server or client is two endpoints; [`endpoint_gids`](Self::endpoint_gids),
/// [`qos_profiles`](Self::qos_profiles) and [`endpoint_type_hashes`](Self::endpoint_type_hashes)
/// list them in rmw's order, reader then writer: a server's request reader then response
/// writer, a client's response reader then request writer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServiceEndpointInfo {
    /// Name of the node owning the endpoints (or a `_…_` placeholder).
    pub node_name: String,
    /// Namespace of that node.
    pub node_namespace: String,
    /// Demangled service type, e.g. `example_interfaces/srv/AddTwoInts`.
    pub service_type: String,
    /// The service's own type hash. Jazzy peers do not send it (their endpoints carry the
    /// `_Request`/`_Response` hashes), so it is [`TypeHash::ZERO`] unless registered with
    /// [`GraphCache::set_service_type_hash`](crate::GraphCache::set_service_type_hash).
    pub service_type_hash: TypeHash,
    /// Server or client.
    pub endpoint_type: ServiceEndpointType,
    /// GIDs, reader then writer.
    pub endpoint_gids: Vec<Gid>,
    /// QoS profiles, reader then writer.
    pub qos_profiles: Vec<Qos>,
    /// The endpoints' own type hashes from USER_DATA (request / response type), reader then
    /// writer. Not printed.
    pub endpoint_type_hashes: Vec<TypeHash>,
}

impl ServiceEndpointInfo {
    /// `endpoint_count`: 2 on DDS (reader + writer).
    pub fn endpoint_count(&self) -> usize {
        self.endpoint_gids.len()
    }
}

/// rclpy `ServiceEndpointInfo.__str__`'s `format_qos`: unlike topics it always prints
/// `History (Depth): <policy> (<depth>)`.
fn write_service_qos(f: &mut fmt::Formatter<'_>, qos: &Qos, indent: &str) -> fmt::Result {
    write!(f, "\n{indent}Reliability: {}", qos.reliability)?;
    write!(
        f,
        "\n{indent}History (Depth): {} ({})",
        qos.history, qos.depth
    )?;
    write!(f, "\n{indent}Durability: {}", qos.durability)?;
    write!(f, "\n{indent}Lifespan: {}", qos.lifespan)?;
    write!(f, "\n{indent}Deadline: {}", qos.deadline)?;
    write!(f, "\n{indent}Liveliness: {}", qos.liveliness)?;
    write!(
        f,
        "\n{indent}Liveliness lease duration: {}",
        qos.liveliness_lease_duration
    )
}

/// As `ros2 service info -v` (rolling) prints each server or client (no trailing newline).
impl fmt::Display for ServiceEndpointInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Node name: {}", self.node_name)?;
        writeln!(f, "Node namespace: {}", self.node_namespace)?;
        writeln!(f, "Service type: {}", self.service_type)?;
        writeln!(
            f,
            "Service type hash: {}",
            type_hash_text(&self.service_type_hash)
        )?;
        writeln!(f, "Endpoint type: {}", self.endpoint_type)?;
        write!(f, "Endpoint count: {}", self.endpoint_count())?;
        const INDENT: &str = "      ";
        match (
            self.endpoint_gids.as_slice(),
            self.qos_profiles.as_slice(),
            self.endpoint_type,
        ) {
            ([gid], [qos], _) => {
                write!(f, "\nGID: {gid}\nQoS profile:")?;
                write_service_qos(f, qos, "  ")
            }
            ([reader, writer], [reader_qos, writer_qos], ServiceEndpointType::Client) => {
                write!(f, "\nGIDs:")?;
                write!(f, "\n - Request Writer : {writer}")?;
                write!(f, "\n - Response Reader : {reader}")?;
                write!(f, "\nQoS profiles:\n - Request Writer :")?;
                write_service_qos(f, writer_qos, INDENT)?;
                write!(f, "\n - Response Reader :")?;
                write_service_qos(f, reader_qos, INDENT)
            }
            ([reader, writer], [reader_qos, writer_qos], ServiceEndpointType::Server) => {
                write!(f, "\nGIDs:")?;
                write!(f, "\n - Request Reader : {reader}")?;
                write!(f, "\n - Response Writer : {writer}")?;
                write!(f, "\nQoS profiles:\n - Request Reader :")?;
                write_service_qos(f, reader_qos, INDENT)?;
                write!(f, "\n - Response Writer :")?;
                write_service_qos(f, writer_qos, INDENT)
            }
            // Not produced by this crate; print what there is rather than fail.
            (gids, _, _) => {
                for gid in gids {
                    write!(f, "\nGID: {gid}")?;
                }
                Ok(())
            }
        }
    }
}
