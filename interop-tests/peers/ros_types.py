"""ROS 2 Jazzy interface types the Cyclone DDS test peers use, declared for the Cyclone DDS Python
binding. Layouts from rmw_dds_common (jazzy) msg/Gid.msg (char[16] data), NodeEntitiesInfo.msg,
ParticipantEntitiesInfo.msg, and builtin_interfaces/msg/Time.msg."""

from dataclasses import dataclass

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, bounded_str, int32, int64, sequence, uint8, uint32


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


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


def dotted(raw: bytes) -> str:
    """A GID or GUID printed as ros2cli prints GIDs."""
    return ".".join(f"{b:02x}" for b in raw)


@dataclass
class AddTwoIntsRequest(IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Request_"):
    a: int64
    b: int64


@dataclass
class AddTwoIntsResponse(IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Response_"):
    sum: int64


# RIHS01 hashes ROS 2 Jazzy generates for example_interfaces/srv/AddTwoInts_Request / _Response.
ADD_TWO_INTS_REQUEST_HASH = "RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302"
ADD_TWO_INTS_RESPONSE_HASH = "RIHS01_de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f"


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


@dataclass
class CddsAddTwoIntsResponse(
    IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Response_"
):
    client_guid: uint64  # echoed from the request
    seq: int64  # echoed from the request
    sum: int64


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


def rmw_parse_key_value(raw: bytes) -> dict:
    """USER_DATA parsed as rmw/impl/cpp/key_value.hpp `parse_key_value` (jazzy) does: `key=value;`
    pairs, alphanumeric keys, values may hold anything but ';'; anything malformed yields {}."""
    pairs, key, value, key_found, prev = {}, b"", b"", False, 0
    if not raw:
        return {}
    for c in raw:
        if key_found:
            if c == 0x3B and prev != 0x3B:  # first ';' ends the value
                prev = c
                continue
            if c != 0x3B and prev == 0x3B:  # next key starts
                if not value:
                    return {}
                pairs[key.decode("latin-1")] = value
                key, value, key_found = b"", b"", False
            else:
                value += bytes([c])
        if not key_found:
            if c == 0x3D:  # '='
                if not key:
                    return {}
                key_found = True
            elif chr(c).isascii() and chr(c).isalnum():  # C isalnum, "C" locale
                key += bytes([c])
            elif c == 0 and not key and pairs:
                break  # trailing NULs are accepted
            elif prev != 0x3B or key:
                return {}
        prev = c
    if key_found:
        if not value:
            return {}
        pairs[key.decode("latin-1")] = value
    elif key:
        return {}
    return pairs


def user_data_key(qos, key: str):
    """rmw_node.cpp `get_user_data_key`: the value of `key` in a QoS's USER_DATA, or None."""
    from cyclonedds.core import Policy

    ud = qos[Policy.Userdata] if qos is not None else None
    if ud is None:
        return None
    value = rmw_parse_key_value(bytes(ud.data)).get(key)
    return None if value is None else value.decode("latin-1")


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


def service_is_available(request_writer, reply_reader) -> bool:
    """rmw_node.cpp `check_for_service_reader_writer` (called by rmw_service_server_is_available
    after the graph cache shows ≥ 1 request reader and ≥ 1 reply writer, which matching implies)."""
    readers = request_writer.get_matched_subscriptions()
    writers = reply_reader.get_matched_publications()
    needles = set()
    for handle in readers:
        reader = request_writer.get_matched_subscription_data(handle)
        serviceid = user_data_key(reader.qos, "serviceid") if reader is not None else None
        if serviceid is not None:
            needles.add(serviceid)
    if not needles:
        # no matched request reader advertises a serviceid: old rule, any matches will do
        return bool(readers) and bool(writers)
    for handle in writers:
        writer = reply_reader.get_matched_publication_data(handle)
        if writer is not None and user_data_key(writer.qos, "serviceid") in needles:
            return True
    return False
