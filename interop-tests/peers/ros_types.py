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
