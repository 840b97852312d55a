"""ROS 2 Jazzy interface types the Cyclone DDS test peers use, declared for the Cyclone DDS Python
binding. Layouts from rmw_dds_common (jazzy) msg/Gid.msg (char[16] data), NodeEntitiesInfo.msg,
ParticipantEntitiesInfo.msg, and builtin_interfaces/msg/Time.msg."""

from dataclasses import dataclass

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, bounded_str, int32, sequence, uint8, uint32


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
