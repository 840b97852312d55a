"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) for service introspection events of
example_interfaces/srv/AddTwoInts, with its own declaration of the event type.

The type is what rosidl generates for a service (rosidl_parser jazzy `definition.py`
`Service.__init__`): `AddTwoInts_Event { service_msgs/ServiceEventInfo info;
AddTwoInts_Request[<=1] request; AddTwoInts_Response[<=1] response; }`, with
service_msgs/msg/ServiceEventInfo.msg (jazzy) `uint8 event_type; builtin_interfaces/Time stamp;
char[16] client_gid; int64 sequence_number` (`char` is uint8 to rosidl). The topic is
`rt<SERVICE>/_service_event` (rcl `RCL_SERVICE_INTROSPECTION_TOPIC_POSTFIX`).

- `listen DOMAIN SERVICE COUNT TIMEOUT`: a reader (services_default QoS, as `ros2 service echo`
  subscribes) that decodes COUNT events and prints each as a JSON line; first line
  {"reader": GUID}, then {"matched": 2} once two writers are matched. Exit 0 iff COUNT events arrived within TIMEOUT, else 3.
- `publish DOMAIN SERVICE TIMEOUT`: a writer as rclpy on rmw_cyclonedds_cpp creates it
  (`configure_introspection(clock, qos, CONTENTS)`: RELIABLE, VOLATILE, KEEP_LAST 10, USER_DATA `typehash=<RIHS01 of AddTwoInts_Event>;`); first line {"writer": GUID};
  once a reader has matched it publishes the four events of one call (a=2, b=3, sum=5, client
  GID 01.10.…, sequence number 7, stamps 100.1 … 100.4 s) and prints {"published": 4}, then stays
  until TIMEOUT. Exit 3 if no reader matched within TIMEOUT.

usage: cyclone_service_events.py listen|publish DOMAIN SERVICE [COUNT] TIMEOUT
"""

import json
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import InstanceState, Policy, Qos, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, int64, sequence, uint8
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from ros_types import AddTwoIntsRequest, AddTwoIntsResponse, Time, dotted, services_qos

# RIHS01 of example_interfaces/srv/AddTwoInts_Event as ROS 2 Jazzy generates it.
ADD_TWO_INTS_EVENT_HASH = "RIHS01_32c1d140259c71e5c355115942bcb31df98b4330e4d906b1b75ccb1c9b3ce6c8"


@dataclass
class ServiceEventInfo(IdlStruct, typename="service_msgs::msg::dds_::ServiceEventInfo_"):
    event_type: uint8
    stamp: Time
    client_gid: array[uint8, 16]
    sequence_number: int64


@dataclass
class AddTwoIntsEvent(IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Event_"):
    info: ServiceEventInfo
    request: sequence[AddTwoIntsRequest, 1]
    response: sequence[AddTwoIntsResponse, 1]


def listen(domain: int, service: str, count: int, timeout: float) -> int:
    deadline = time.monotonic() + timeout
    dp = DomainParticipant(domain)
    reader = DataReader(dp, Topic(dp, f"rt{service}/_service_event", AddTwoIntsEvent),
                        qos=services_qos(f"typehash={ADD_TWO_INTS_EVENT_HASH};", writer=False))
    print(json.dumps({"reader": dotted(reader.guid.bytes)}), flush=True)
    waitset = WaitSet(dp)
    waitset.attach(ReadCondition(reader, SampleState.Any | ViewState.Any | InstanceState.Any))
    # Announced once two writers (a server's and a client's) are matched, so that the test calls
    # only when this reader is sure to take their events.
    announced = False
    got = 0
    while got < count and (remaining := deadline - time.monotonic()) > 0:
        if not announced and len(reader.get_matched_publications()) >= 2:
            print(json.dumps({"matched": 2}), flush=True)
            announced = True
        waitset.wait(duration(seconds=min(remaining, 0.01 if not announced else 0.1)))
        for e in reader.take(N=16):
            if not e.sample_info.valid_data:
                continue
            got += 1
            print(json.dumps({
                "event_type": e.info.event_type,
                "sec": e.info.stamp.sec,
                "nanosec": e.info.stamp.nanosec,
                "client_gid": dotted(bytes(e.info.client_gid)),
                "sequence_number": e.info.sequence_number,
                "request": [[r.a, r.b] for r in e.request],
                "response": [r.sum for r in e.response],
            }), flush=True)
    return 0 if got >= count else 3


def publish(domain: int, service: str, timeout: float) -> int:
    deadline = time.monotonic() + timeout
    dp = DomainParticipant(domain)
    qos = Qos(
        Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100)),
        Policy.Durability.Volatile,
        # rclpy's system default is KEEP_LAST 1; 10 lets the four events go back to back.
        Policy.History.KeepLast(10),
        Policy.Userdata(f"typehash={ADD_TWO_INTS_EVENT_HASH};".encode()),
        Policy.DataRepresentation(use_cdrv0_representation=True),
    )
    writer = DataWriter(dp, Topic(dp, f"rt{service}/_service_event", AddTwoIntsEvent), qos=qos)
    print(json.dumps({"writer": dotted(writer.guid.bytes)}), flush=True)
    while not writer.get_matched_subscriptions():
        if time.monotonic() >= deadline:
            return 3
        time.sleep(0.01)
    gid = [0x01, 0x10, 0xAB, 0xCD, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x05]
    req, resp = AddTwoIntsRequest(a=2, b=3), AddTwoIntsResponse(sum=5)
    for event_type, request, response in [(0, [req], []), (1, [req], []),
                                          (2, [], [resp]), (3, [], [resp])]:
        info = ServiceEventInfo(event_type=event_type,
                                stamp=Time(sec=100, nanosec=100_000_000 * (event_type + 1)),
                                client_gid=gid, sequence_number=7)
        writer.write(AddTwoIntsEvent(info=info, request=request, response=response))
    print(json.dumps({"published": 4}), flush=True)
    time.sleep(max(0.0, deadline - time.monotonic()))
    return 0


def main() -> int:
    args = sys.argv[1:]
    if len(args) == 5 and args[0] == "listen":
        return listen(int(args[1]), args[2], int(args[3]), float(args[4]))
    if len(args) == 4 and args[0] == "publish":
        return publish(int(args[1]), args[2], float(args[3]))
    print(__doc__.strip().splitlines()[-1], file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
