"""What the Cyclone DDS test peers that no real ROS 2 node can stand for (a hostile peer, a DDS-level
discovery observer, a bare participant) declare for the Cyclone DDS Python binding: the
`ros_discovery_info` types of rmw_dds_common (jazzy) msg/Gid.msg (char[16] data),
NodeEntitiesInfo.msg and ParticipantEntitiesInfo.msg, and rmw_cyclonedds_cpp's service wire format
for example_interfaces/srv/AddTwoInts requests."""

from dataclasses import dataclass

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, bounded_str, int64, sequence, uint8


@dataclass
class Gid(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
    data: array[uint8, 16]


@dataclass
class NodeEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
    node_namespace: bounded_str[256]
    node_name: bounded_str[256]
    reader_gid_seq: sequence[Gid]
    writer_gid_seq: sequence[Gid]


@dataclass
class ParticipantEntitiesInfo(
    IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"
):
    gid: Gid
    node_entities_info_seq: sequence[NodeEntitiesInfo]


def dotted(raw: bytes) -> str:
    """A GID or GUID printed as ros2cli prints GIDs."""
    return ".".join(f"{b:02x}" for b in raw)


ADD_TWO_INTS_REQUEST_HASH = "RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302"


# --- rmw_cyclonedds_cpp service wire format (jazzy) -------------------------------------------------
# rmw_cyclonedds_cpp serialises every request and reply as the 16-byte cdds_request_header_t
# { uint64_t guid; int64_t seq; } (src/serdata.hpp: `typedef struct cdds_request_header`) put into the
# CDR stream right after the 4-byte encapsulation header and before the message's own fields
# (src/Serialization.cpp, `serialize_top_level(CDRCursor *, const cdds_request_wrapper_t &)`:
# put_rtps_header, then put_bytes(guid, 8), put_bytes(seq, 8), then the message). The encapsulation
# header is {0x00, 0x01 (little endian), 0x00, 0x00}: CDR_LE, i.e. XCDR1 (`put_rtps_header`). Both
# header fields are 8 bytes at stream offset 0 and 8, so the int64 message fields that follow need
# no padding. These types keep the ROS type names so they match rmw_cyclonedds' endpoints; their
# bytes on the wire are exactly rmw_cyclonedds' for example_interfaces/srv/AddTwoInts.
from cyclonedds.idl.types import uint64  # noqa: E402  (appended section)


@dataclass
class CddsAddTwoIntsRequest(
    IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Request_"
):
    client_guid: uint64  # cdds_request_header_t.guid: the client's request-writer instance handle
    seq: int64  # cdds_request_header_t.seq
    a: int64
    b: int64


def cdds_csid(participant_guid: bytes, counter: int) -> bytes:
    """rmw_cyclonedds' client/service id (rmw_node.cpp `get_unique_csid`): the participant's 12-byte
    GUID prefix followed by the context's client/service counter (1 for the first client or service
    created in the context) as a 4-byte big-endian number."""
    return bytes(participant_guid[:12]) + counter.to_bytes(4, "big")


def cdds_csid_text(csid: bytes) -> str:
    """The id as rmw_node.cpp `csid_to_string` prints it: `std::hex`, the first byte under
    `std::setw(2)` (so space-padded to two characters, e.g. " 1"), the other 15 bytes unpadded, all
    joined by '.'."""
    return f"{csid[0]:>2x}" + "".join(f".{b:x}" for b in csid[1:])


def services_qos(user_data: str, writer: bool, depth: int = 10):
    """rmw_qos_profile_services_default as rmw_cyclonedds' `create_readwrite_qos` (rmw_node.cpp)
    turns it into DDS QoS; writers say XCDR1 explicitly (rmw_cyclonedds writes XCDR1,
    Serialization.cpp `put_rtps_header`), so the binding never picks XCDR2. `depth` is the profile's
    history depth (10 in rmw_qos_profile_services_default; a client or server created with another
    QoS profile gets its depth, `create_readwrite_qos`)."""
    from cyclonedds.core import Policy, Qos
    from cyclonedds.util import duration

    policies = [
        Policy.Reliability.Reliable(max_blocking_time=duration(infinite=True)),
        Policy.Durability.Volatile,
        Policy.History.KeepLast(depth),
        Policy.Liveliness.Automatic(lease_duration=duration(infinite=True)),
        Policy.WriterDataLifecycle(autodispose=False),
        Policy.Userdata(user_data.encode()),
    ]
    if writer:
        policies.append(Policy.DataRepresentation(use_cdrv0_representation=True))
    return Qos(*policies)
