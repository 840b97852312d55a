"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) standing for a ROS 2 Jazzy node
on rmw_cyclonedds_cpp that serves a service of a type horus-ros does not compile in,
`horus_test_msgs/srv/Describe`, and serves `~/get_type_description` for its node as rcl (jazzy
9.2 `node.c` `rcl_node_type_description_service_handle_request`) does:

- node `typed_server` in namespace `/`, announced on `ros_discovery_info` with every endpoint;
- `/describe` (Describe) and `/typed_server/get_type_description`
  (type_description_interfaces/srv/GetTypeDescription), each a reply writer `rr…Reply` and a
  request reader `rq…Request` in rmw_cyclonedds' layout (16-byte request header in the CDR stream,
  XCDR1, USER_DATA `serviceid=…;typehash=RIHS01_…;`; see cyclone_add_two_ints_server.py);
- with INTROSPECTION (as after rclcpp `configure_introspection`), a publisher of
  `/describe/_service_event` (`horus_test_msgs/srv/Describe_Event`), whose type hash is on the
  graph: rcl's type cache is keyed by hash alone and Jazzy never puts a service's own type hash
  on the wire, so this is the hash a caller can ask for;
- the node's type cache holds what rcl registers: the Describe service type (by the service type
  hash), the Describe_Event message (event publisher, only with INTROSPECTION) and the
  GetTypeDescription service type. A request's `type_name` is ignored; an unknown hash gets
  `successful=False, failure_reason="Type not currently in use by this node"`, an unparsable one
  "Failed to parse type hash".

Descriptions and RIHS01 hashes are built here, independently of horus-ros, as
rosidl_generator_type_description (jazzy) does.

Describe.srv:
    bool verbose
    float64[] samples
    string label
    horus_test_msgs/Point origin        # Point.msg: int32 id, float64 x, float64 y
    int16[3] dims
    ---
    string summary
    float64 total
    horus_test_msgs/Point[] points
    uint8[2] flags
    float32 ratio

The reply: summary = "<label>: <n> samples" (+ " (verbose)"), total = sum(samples),
points = [origin, Point(id + 1, x + total, y)], flags = [len(samples), dims[0] & 255],
ratio = 0.1.

It prints one JSON line with its hashes at start, then one line per request, and exits after
LINGER seconds.

usage: cyclone_typed_server.py DOMAIN LINGER INTROSPECTION(0|1)
"""

import hashlib
import json
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import InstanceState, Policy, Qos, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import (array, bounded_str, float32, float64, int16, int32, int64, sequence,
                                  uint8, uint32, uint64)
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from ros_types import services_qos, Gid, NodeEntitiesInfo, ParticipantEntitiesInfo, Time, cdds_csid, cdds_csid_text, dotted

NODE_NAMESPACE, NODE_NAME = "/", "typed_server"

# --- type descriptions and RIHS01 (rosidl_generator_type_description jazzy) ------------------------
NESTED, INT8, UINT8, INT16, UINT16, INT32, UINT32, INT64, UINT64 = 1, 2, 3, 4, 5, 6, 7, 8, 9
FLOAT, DOUBLE, BOOLEAN, STRING, BOUNDED_STRING = 10, 11, 15, 17, 21
ARRAY, BOUNDED_SEQ, SEQ = 48, 96, 144


def ftype(type_id, capacity=0, string_capacity=0, nested=""):
    return {"type_id": type_id, "capacity": capacity, "string_capacity": string_capacity,
            "nested_type_name": nested}


def field(name, t, default=""):
    return {"name": name, "type": t, "default_value": default}


class Desc:
    """A full TypeDescription: the main type and every referenced type, sorted, no repeats."""

    def __init__(self, name, fields, refs=()):
        self.main = {"type_name": name, "fields": fields}
        referenced = {}
        for r in refs:
            for t in [r.main] + r.referenced:
                referenced[t["type_name"]] = t
        self.referenced = [referenced[k] for k in sorted(referenced)]

    def hash(self):
        def strip(t):
            return {"type_name": t["type_name"],
                    "fields": [{"name": f["name"], "type": f["type"]} for f in t["fields"]]}
        doc = {"type_description": strip(self.main),
               "referenced_type_descriptions": [strip(t) for t in self.referenced]}
        text = json.dumps(doc, separators=(", ", ": "), sort_keys=False, ensure_ascii=True)
        return "RIHS01_" + hashlib.sha256(text.encode()).hexdigest()


TIME = Desc("builtin_interfaces/msg/Time", [field("sec", ftype(INT32)), field("nanosec", ftype(UINT32))])
EVENT_INFO = Desc("service_msgs/msg/ServiceEventInfo", [
    field("event_type", ftype(UINT8)),
    field("stamp", ftype(NESTED, nested=TIME.main["type_name"])),
    field("client_gid", ftype(UINT8 + ARRAY, 16)),
    field("sequence_number", ftype(INT64)),
], [TIME])


def service_descs(name, request, response):
    """(service, event) descriptions as rosidl builds them (`add_srv`, rosidl_parser `Service`)."""
    event = Desc(name + "_Event", [
        field("info", ftype(NESTED, nested=EVENT_INFO.main["type_name"])),
        field("request", ftype(NESTED + BOUNDED_SEQ, 1, nested=request.main["type_name"])),
        field("response", ftype(NESTED + BOUNDED_SEQ, 1, nested=response.main["type_name"])),
    ], [EVENT_INFO, request, response])
    service = Desc(name, [
        field("request_message", ftype(NESTED, nested=request.main["type_name"])),
        field("response_message", ftype(NESTED, nested=response.main["type_name"])),
        field("event_message", ftype(NESTED, nested=event.main["type_name"])),
    ], [request, response, event])
    return service, event


POINT = Desc("horus_test_msgs/msg/Point", [
    field("id", ftype(INT32)), field("x", ftype(DOUBLE)), field("y", ftype(DOUBLE))])
DESCRIBE_REQUEST = Desc("horus_test_msgs/srv/Describe_Request", [
    field("verbose", ftype(BOOLEAN)),
    field("samples", ftype(DOUBLE + SEQ)),
    field("label", ftype(STRING)),
    field("origin", ftype(NESTED, nested=POINT.main["type_name"])),
    field("dims", ftype(INT16 + ARRAY, 3)),
], [POINT])
DESCRIBE_RESPONSE = Desc("horus_test_msgs/srv/Describe_Response", [
    field("summary", ftype(STRING)),
    field("total", ftype(DOUBLE)),
    field("points", ftype(NESTED + SEQ, nested=POINT.main["type_name"])),
    field("flags", ftype(UINT8 + ARRAY, 2)),
    field("ratio", ftype(FLOAT)),
], [POINT])
DESCRIBE, DESCRIBE_EVENT = service_descs("horus_test_msgs/srv/Describe", DESCRIBE_REQUEST, DESCRIBE_RESPONSE)

TDI = "type_description_interfaces/msg/"
FIELD_TYPE = Desc(TDI + "FieldType", [
    field("type_id", ftype(UINT8), "0"), field("capacity", ftype(UINT64)),
    field("string_capacity", ftype(UINT64)),
    field("nested_type_name", ftype(BOUNDED_STRING, 0, 255))])
FIELD = Desc(TDI + "Field", [
    field("name", ftype(STRING)), field("type", ftype(NESTED, nested=TDI + "FieldType")),
    field("default_value", ftype(STRING))], [FIELD_TYPE])
INDIVIDUAL = Desc(TDI + "IndividualTypeDescription", [
    field("type_name", ftype(BOUNDED_STRING, 0, 255)),
    field("fields", ftype(NESTED + SEQ, nested=TDI + "Field"))], [FIELD])
TYPE_DESCRIPTION = Desc(TDI + "TypeDescription", [
    field("type_description", ftype(NESTED, nested=TDI + "IndividualTypeDescription")),
    field("referenced_type_descriptions", ftype(NESTED + SEQ, nested=TDI + "IndividualTypeDescription"))],
    [INDIVIDUAL])
KEY_VALUE = Desc(TDI + "KeyValue", [field("key", ftype(STRING)), field("value", ftype(STRING))])
TYPE_SOURCE = Desc(TDI + "TypeSource", [
    field("type_name", ftype(STRING)), field("encoding", ftype(STRING)),
    field("raw_file_contents", ftype(STRING))])
GTD = "type_description_interfaces/srv/GetTypeDescription"
GTD_REQUEST = Desc(GTD + "_Request", [
    field("type_name", ftype(STRING)), field("type_hash", ftype(STRING)),
    field("include_type_sources", ftype(BOOLEAN), "True")])
GTD_RESPONSE = Desc(GTD + "_Response", [
    field("successful", ftype(BOOLEAN)), field("failure_reason", ftype(STRING)),
    field("type_description", ftype(NESTED, nested=TDI + "TypeDescription")),
    field("type_sources", ftype(NESTED + SEQ, nested=TDI + "TypeSource")),
    field("extra_information", ftype(NESTED + SEQ, nested=TDI + "KeyValue"))],
    [TYPE_DESCRIPTION, TYPE_SOURCE, KEY_VALUE])
GTD_SERVICE, _ = service_descs(GTD, GTD_REQUEST, GTD_RESPONSE)


# --- wire types (rmw_cyclonedds: request header first) ----------------------------------------------
@dataclass
class Point(IdlStruct, typename="horus_test_msgs::msg::dds_::Point_"):
    id: int32
    x: float64
    y: float64


@dataclass
class DescribeRequest(IdlStruct, typename="horus_test_msgs::srv::dds_::Describe_Request_"):
    client_guid: uint64
    seq: int64
    verbose: bool
    samples: sequence[float64]
    label: str
    origin: Point
    dims: array[int16, 3]


@dataclass
class DescribeResponse(IdlStruct, typename="horus_test_msgs::srv::dds_::Describe_Response_"):
    client_guid: uint64
    seq: int64
    summary: str
    total: float64
    points: sequence[Point]
    flags: array[uint8, 2]
    ratio: float32


@dataclass
class PlainDescribeRequest(IdlStruct, typename="horus_test_msgs::srv::dds_::Describe_Request_"):
    verbose: bool
    samples: sequence[float64]
    label: str
    origin: Point
    dims: array[int16, 3]


@dataclass
class PlainDescribeResponse(IdlStruct, typename="horus_test_msgs::srv::dds_::Describe_Response_"):
    summary: str
    total: float64
    points: sequence[Point]
    flags: array[uint8, 2]
    ratio: float32


@dataclass
class ServiceEventInfo(IdlStruct, typename="service_msgs::msg::dds_::ServiceEventInfo_"):
    event_type: uint8
    stamp: Time
    client_gid: array[uint8, 16]
    sequence_number: int64


@dataclass
class DescribeEvent(IdlStruct, typename="horus_test_msgs::srv::dds_::Describe_Event_"):
    info: ServiceEventInfo
    request: sequence[PlainDescribeRequest, 1]
    response: sequence[PlainDescribeResponse, 1]


@dataclass
class FieldType(IdlStruct, typename="type_description_interfaces::msg::dds_::FieldType_"):
    type_id: uint8
    capacity: uint64
    string_capacity: uint64
    nested_type_name: bounded_str[255]


@dataclass
class Field(IdlStruct, typename="type_description_interfaces::msg::dds_::Field_"):
    name: str
    type: FieldType
    default_value: str


@dataclass
class IndividualTypeDescription(
        IdlStruct, typename="type_description_interfaces::msg::dds_::IndividualTypeDescription_"):
    type_name: bounded_str[255]
    fields: sequence[Field]


@dataclass
class TypeDescription(IdlStruct, typename="type_description_interfaces::msg::dds_::TypeDescription_"):
    type_description: IndividualTypeDescription
    referenced_type_descriptions: sequence[IndividualTypeDescription]


@dataclass
class TypeSource(IdlStruct, typename="type_description_interfaces::msg::dds_::TypeSource_"):
    type_name: str
    encoding: str
    raw_file_contents: str


@dataclass
class KeyValue(IdlStruct, typename="type_description_interfaces::msg::dds_::KeyValue_"):
    key: str
    value: str


@dataclass
class GetTypeDescriptionRequest(
        IdlStruct, typename="type_description_interfaces::srv::dds_::GetTypeDescription_Request_"):
    client_guid: uint64
    seq: int64
    type_name: str
    type_hash: str
    include_type_sources: bool


@dataclass
class GetTypeDescriptionResponse(
        IdlStruct, typename="type_description_interfaces::srv::dds_::GetTypeDescription_Response_"):
    client_guid: uint64
    seq: int64
    successful: bool
    failure_reason: str
    type_description: TypeDescription
    type_sources: sequence[TypeSource]
    extra_information: sequence[KeyValue]


def wire_description(d: Desc) -> TypeDescription:
    def individual(t):
        return IndividualTypeDescription(type_name=t["type_name"], fields=[
            Field(name=f["name"], type=FieldType(**f["type"]), default_value=f["default_value"])
            for f in t["fields"]])
    return TypeDescription(type_description=individual(d.main),
                           referenced_type_descriptions=[individual(t) for t in d.referenced])



def rihs_ok(text: str) -> bool:
    """rosidl_parse_type_hash_string: `RIHS01_` + 64 hex digits."""
    return (len(text) == 71 and text.startswith("RIHS01_")
            and all(c in "0123456789abcdefABCDEF" for c in text[7:]))


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    domain, linger, introspection = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3] == "1"
    deadline = time.monotonic() + linger

    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo), qos=info_qos)
    participant_gid = dp.guid.bytes

    def service(counter, name, req_type, resp_type, req_hash, resp_hash):
        sid = cdds_csid_text(cdds_csid(participant_gid, counter))
        writer = DataWriter(dp, Topic(dp, f"rr{name}Reply", resp_type),
                            qos=services_qos(f"serviceid={sid};typehash={resp_hash};", writer=True))
        reader = DataReader(dp, Topic(dp, f"rq{name}Request", req_type),
                            qos=services_qos(f"serviceid={sid};typehash={req_hash};", writer=False))
        return reader, writer

    d_reader, d_writer = service(1, "/describe", DescribeRequest, DescribeResponse,
                                 DESCRIBE_REQUEST.hash(), DESCRIBE_RESPONSE.hash())
    g_reader, g_writer = service(2, f"/{NODE_NAME}/get_type_description", GetTypeDescriptionRequest,
                                 GetTypeDescriptionResponse, GTD_REQUEST.hash(), GTD_RESPONSE.hash())
    writers = [d_writer, g_writer]
    type_cache = {DESCRIBE.hash(): DESCRIBE, GTD_SERVICE.hash(): GTD_SERVICE}
    if introspection:
        event_writer = DataWriter(
            dp, Topic(dp, "rt/describe/_service_event", DescribeEvent),
            qos=Qos(Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
                    Policy.Durability.Volatile, Policy.History.KeepLast(1000),
                    Policy.DataRepresentation(use_cdrv0_representation=True),
                    Policy.Userdata(f"typehash={DESCRIBE_EVENT.hash()};".encode())))
        writers.append(event_writer)
        type_cache[DESCRIBE_EVENT.hash()] = DESCRIBE_EVENT

    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(participant_gid)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=NODE_NAMESPACE, node_name=NODE_NAME,
            reader_gid_seq=[Gid(list(d_reader.guid.bytes)), Gid(list(g_reader.guid.bytes))],
            writer_gid_seq=[Gid(list(w.guid.bytes)) for w in writers],
        )],
    ))
    print(json.dumps({
        "participant": dotted(participant_gid),
        "describe_hash": DESCRIBE.hash(),
        "describe_request_hash": DESCRIBE_REQUEST.hash(),
        "describe_response_hash": DESCRIBE_RESPONSE.hash(),
        "describe_event_hash": DESCRIBE_EVENT.hash(),
        "get_type_description_request_hash": GTD_REQUEST.hash(),
        "get_type_description_response_hash": GTD_RESPONSE.hash(),
    }), flush=True)

    waitset = WaitSet(dp)
    any_state = SampleState.Any | ViewState.Any | InstanceState.Any
    waitset.attach(ReadCondition(d_reader, any_state))
    waitset.attach(ReadCondition(g_reader, any_state))
    while (remaining := deadline - time.monotonic()) > 0:
        waitset.wait(duration(seconds=min(remaining, 0.1)))
        for r in g_reader.take(N=16):
            if not r.sample_info.valid_data:
                continue
            if not rihs_ok(r.type_hash):
                ok, reason, desc = False, "Failed to parse type hash", None
            elif "RIHS01_" + r.type_hash[7:].lower() in type_cache:
                ok, reason, desc = True, "", type_cache["RIHS01_" + r.type_hash[7:].lower()]
            else:
                ok, reason, desc = False, "Type not currently in use by this node", None
            empty = TypeDescription(IndividualTypeDescription("", []), [])
            time.sleep(0.1)  # rmw_send_response waits up to 100 ms for the client's reader
            g_writer.write(GetTypeDescriptionResponse(
                client_guid=r.client_guid, seq=r.seq, successful=ok, failure_reason=reason,
                type_description=wire_description(desc) if desc else empty,
                type_sources=[], extra_information=[]))
            print(json.dumps({"get_type_description": r.type_name, "hash": r.type_hash,
                              "successful": ok}), flush=True)
        for r in d_reader.take(N=16):
            if not r.sample_info.valid_data:
                continue
            total = sum(r.samples)
            summary = f"{r.label}: {len(r.samples)} samples" + (" (verbose)" if r.verbose else "")
            o = r.origin
            time.sleep(0.1)
            d_writer.write(DescribeResponse(
                client_guid=r.client_guid, seq=r.seq, summary=summary, total=total,
                points=[Point(o.id, o.x, o.y), Point(o.id + 1, o.x + total, o.y)],
                flags=[len(r.samples) & 255, r.dims[0] & 255], ratio=0.1))
            print(json.dumps({"describe": r.label, "samples": list(r.samples),
                              "dims": list(r.dims)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
