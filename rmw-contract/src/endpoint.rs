//! What a backend's endpoints are given and give back: the endpoint's DDS names, hash and QoS,
//! and the samples with their identities.

use horus_ros_msgs::TypeHash;

use crate::qos::{EndpointKind, HistoryPolicy, Qos};
use crate::Gid;

/// A sample's identity: the GID of the writer that wrote it and its sequence number there
/// (`rmw_request_id_t` / DDS `SampleIdentity`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SampleId {
    /// The writer's GID.
    pub writer: Gid,
    /// The sample's sequence number at that writer.
    pub sequence_number: i64,
}

impl SampleId {
    /// RTPS `SEQUENCENUMBER_UNKNOWN` ({-1, 0}).
    pub const UNKNOWN_SEQUENCE_NUMBER: i64 = -(1 << 32);
}

/// A sample taken from a `RawReader`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RawSample {
    /// The CDR body (after the 4-byte encapsulation header).
    pub body: Vec<u8>,
    /// Whether the body is big-endian (CDR_BE) rather than little-endian.
    pub big_endian: bool,
    /// The sample's own identity (writer GID and sequence number).
    pub id: SampleId,
    /// The `related_sample_identity` inline QoS it carried, if any (PID 0x0083 or 0x800f).
    pub related: Option<SampleId>,
    /// The DDS layer's local instance handle of the writer, where it has one (Cyclone DDS's
    /// `publication_handle`, which rmw_cyclonedds puts in the second half of a request's
    /// `writer_guid`); `None` on RustDDS.
    pub publication_handle: Option<u64>,
    /// The writer's source timestamp (DDS `SampleInfo.source_timestamp`), nanoseconds since the
    /// Unix epoch; `None` where the sample carried none.
    pub source_timestamp: Option<i64>,
    /// When the DDS layer handed the sample over (taken from the reader), nanoseconds since the
    /// Unix epoch (rmw's `received_timestamp`).
    pub received_timestamp: i64,
}

/// Now, in nanoseconds since the Unix epoch (0 if the clock is before it), as a
/// [`RawSample::received_timestamp`].
pub fn unix_time_ns() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_nanos()).unwrap_or(i64::MAX))
}

/// What a raw endpoint is: its DDS topic and type, and the hash and QoS it is listed with.
#[derive(Clone, Debug)]
pub struct RawEndpointSpec {
    /// The DDS topic name, already mangled (e.g. `rq/add_two_intsRequest`).
    pub dds_topic_name: String,
    /// The DDS type name (e.g. `example_interfaces::srv::dds_::AddTwoInts_Request_`).
    pub dds_type_name: String,
    /// The RIHS01 hash of the type.
    pub type_hash: TypeHash,
    /// The QoS, as announced (rmw_zenoh's tokens carry its depth); the local history of a
    /// service endpoint is deeper: see [`RawEndpointSpec::local_qos`].
    pub qos: Qos,
    /// For a service's request/reply endpoint: the id of its client or server, announced in
    /// USER_DATA before the type hash (rmw_cyclonedds `rmw_init_cs`).
    pub service_id: Option<ServiceEndpointId>,
}

/// The history depth of every service writer at least: replies to many concurrent calls must
/// not push each other out of a KEEP_LAST 10 history (services_default's depth) before they are
/// acknowledged. Local only: DDS discovery does not send history depth, and rmw_zenoh's tokens
/// carry the depth asked for.
pub const MIN_SERVICE_HISTORY_DEPTH: usize = 256;

/// The history depth of every service reader at least. A client's reply reader receives the
/// replies to every client of the service from servers that cannot address one reader
/// (rmw_cyclonedds' convention, and the Cyclone backend's: each reply goes to every reply
/// reader and clients pick theirs by the header): with 64 clients waiting, a reader receives 64
/// replies for each of its own, and a client thread that is not scheduled for a while found its
/// reply pushed out of a KEEP_LAST 256 history by those of others (calls lost under load, see the
/// `reliability` benchmark). A server's request reader holds the requests that arrive while its
/// handler runs. The depth bounds memory (a full history is a few hundred KiB of small samples);
/// it is allocated only as samples arrive.
pub const MIN_SERVICE_READER_HISTORY_DEPTH: usize = 4096;

impl RawEndpointSpec {
    /// The QoS the local endpoint of `kind` is made with: [`qos`](Self::qos), with a KEEP_LAST
    /// history deepened to [`MIN_SERVICE_HISTORY_DEPTH`] (writers) or
    /// [`MIN_SERVICE_READER_HISTORY_DEPTH`] (readers) for a service's request/reply endpoint
    /// (one with a [`service_id`](Self::service_id)).
    pub fn local_qos(&self, kind: EndpointKind) -> Qos {
        let mut qos = self.qos;
        if self.service_id.is_some() && qos.history == HistoryPolicy::KeepLast {
            let min = match kind {
                EndpointKind::Writer => MIN_SERVICE_HISTORY_DEPTH,
                EndpointKind::Reader => MIN_SERVICE_READER_HISTORY_DEPTH,
            };
            qos.depth = qos.depth.max(min);
        }
        qos
    }

    /// The USER_DATA a backend that announces it gives this endpoint:
    /// `[clientid=…;|serviceid=…;]typehash=RIHS01_…;` (rmw_cyclonedds `create_readwrite_qos`).
    pub fn user_data(&self) -> String {
        let mut s = self.service_id.map(|id| id.user_data()).unwrap_or_default();
        s.push_str(&self.type_hash.to_user_data());
        s
    }
}

/// Whether a service endpoint belongs to a client or a server.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ServiceEndpointRole {
    /// A client's request writer and reply reader (`clientid=`).
    Client,
    /// A server's request reader and reply writer (`serviceid=`).
    Server,
}

/// The id shared by the two endpoints of one service client or server (rmw_cyclonedds
/// `client_service_id_t`), with the service type's hash; see
/// `Context::new_service_endpoint_id`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ServiceEndpointId {
    /// Client or server.
    pub role: ServiceEndpointRole,
    /// The 16 bytes: participant GUID prefix + big-endian counter.
    pub id: [u8; 16],
    /// The RIHS01 hash of the service type (`pkg/srv/Name`, not its request or response), which
    /// rmw_zenoh's service keys and tokens carry; [`TypeHash::ZERO`] where it is not known.
    pub service_type_hash: TypeHash,
}

impl ServiceEndpointId {
    /// `clientid=…;` or `serviceid=…;`, the id written as rmw_cyclonedds `csid_to_string` does:
    /// lower-case hex bytes joined by `.`, no zero padding except that the first is right-aligned
    /// in two characters (`std::setw(2)` with the default space fill), e.g. ` 1.10.a.…`.
    pub fn user_data(&self) -> String {
        use std::fmt::Write;
        let key = match self.role {
            ServiceEndpointRole::Client => "clientid",
            ServiceEndpointRole::Server => "serviceid",
        };
        let mut s = format!("{key}={:>2x}", self.id[0]);
        for b in &self.id[1..] {
            let _ = write!(s, ".{b:x}");
        }
        s.push(';');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn service_ids_are_written_as_rmw_cyclonedds_writes_them() {
        let mut id = [0u8; 16];
        id[..4].copy_from_slice(&[0x01, 0x10, 0x0a, 0xff]);
        id[15] = 3;
        let client = ServiceEndpointId {
            role: ServiceEndpointRole::Client,
            id,
            service_type_hash: TypeHash::ZERO,
        };
        assert_eq!(
            client.user_data(),
            "clientid= 1.10.a.ff.0.0.0.0.0.0.0.0.0.0.0.3;"
        );
        id[0] = 0xab;
        let server = ServiceEndpointId {
            role: ServiceEndpointRole::Server,
            id,
            service_type_hash: TypeHash::ZERO,
        };
        assert!(server.user_data().starts_with("serviceid=ab.10.a.ff."));
        let spec = RawEndpointSpec {
            dds_topic_name: "rq/xRequest".to_owned(),
            dds_type_name: "x::srv::dds_::X_Request_".to_owned(),
            type_hash: TypeHash::ZERO,
            qos: Qos::services_default(),
            service_id: Some(client),
        };
        assert_eq!(
            spec.user_data(),
            client.user_data(),
            "no hash, no typehash="
        );
    }
}
