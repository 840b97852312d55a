"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that calls
example_interfaces/srv/AddTwoInts exactly as a ROS 2 Jazzy client on rmw_cyclonedds_cpp does, on the
wire and in its matching rules (rmw_cyclonedds_cpp jazzy, src/rmw_node.cpp, src/serdata.*,
src/Serialization.cpp):

- it announces node `add_two_ints_client` in namespace `/` on `ros_discovery_info`, listing the
  client's reply reader and request writer;
- the client is a request writer on `rq<SERVICE>Request` and a reply reader on `rr<SERVICE>Reply`
  (`rmw_init_cs`, created in that order), rmw_qos_profile_services_default (RELIABLE, VOLATILE,
  KEEP_LAST 10), USER_DATA `clientid=<csid>;typehash=RIHS01_…;` (same csid on both endpoints);
- it waits, at most TIMEOUT seconds, until the service is available as
  `rmw_service_server_is_available` / `check_for_service_reader_writer` decide: its request writer
  has matched a request reader and its reply reader has matched a reply writer; when matched
  request readers advertise `serviceid=`, one matched reply writer must carry one of those ids;
- it then sends COUNT requests one after the other, call i (1..COUNT) with a = i, b = 10*i; each
  request starts with the 16-byte header {guid, seq}: guid = the request writer's 64-bit instance
  handle (`dds_get_instance_handle(pub->enth, &pub->pubiid)` in `rmw_init_cs`, used by
  `rmw_send_request`), seq = a process-wide counter 1, 2, … (`++next_request_id`);
- it keeps only replies whose header guid equals its own (`rmw_take_response` filters on
  `info->client.pub->pubiid`) and, as rclcpp does with its pending requests, whose seq is the one
  it is waiting for.

Output: a JSON line at start ({"participant", "request_writer", "reply_reader", "guid", "clientid",
…}), then one per call ({"a", "b", "sum", "seq"}), then a summary
({"summary": true, "count", "replies", "ok", "service_available", "foreign_replies",
"stale_replies"}). Exit status 0 iff all COUNT replies arrived with sum == a + b within TIMEOUT
(counted from start), else 3.

usage: cyclone_add_two_ints_client.py DOMAIN SERVICE COUNT TIMEOUT    (SERVICE like /add_two_ints)
"""

import json
import sys
import time

from cyclonedds.core import Policy, Qos, ReadCondition, SampleState, ViewState, InstanceState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from ros_types import (
    services_qos,
    ADD_TWO_INTS_REQUEST_HASH,
    ADD_TWO_INTS_RESPONSE_HASH,
    CddsAddTwoIntsRequest,
    CddsAddTwoIntsResponse,
    Gid,
    NodeEntitiesInfo,
    ParticipantEntitiesInfo,
    cdds_csid,
    cdds_csid_text,
    dotted,
    service_is_available,
)

NODE_NAMESPACE, NODE_NAME = "/", "add_two_ints_client"
U64 = (1 << 64) - 1


def main() -> int:
    if len(sys.argv) != 5:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    domain, service = int(sys.argv[1]), sys.argv[2]
    count, timeout = int(sys.argv[3]), float(sys.argv[4])
    deadline = time.monotonic() + timeout

    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo), qos=info_qos)

    participant_gid = dp.guid.bytes
    clientid = cdds_csid_text(cdds_csid(participant_gid, 1))  # first client/service of the context
    request_user_data = f"clientid={clientid};typehash={ADD_TWO_INTS_REQUEST_HASH};"
    reply_user_data = f"clientid={clientid};typehash={ADD_TWO_INTS_RESPONSE_HASH};"
    request_writer = DataWriter(dp, Topic(dp, f"rq{service}Request", CddsAddTwoIntsRequest),
                                qos=services_qos(request_user_data, writer=True))
    reply_reader = DataReader(dp, Topic(dp, f"rr{service}Reply", CddsAddTwoIntsResponse),
                              qos=services_qos(reply_user_data, writer=False))
    # The request header's guid: the writer's instance handle (uint64 in Cyclone).
    guid = request_writer.get_instance_handle() & U64

    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(participant_gid)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=NODE_NAMESPACE, node_name=NODE_NAME,
            reader_gid_seq=[Gid(list(reply_reader.guid.bytes))],
            writer_gid_seq=[Gid(list(request_writer.guid.bytes))],
        )],
    ))
    print(json.dumps({
        "participant": dotted(participant_gid),
        "request_writer": dotted(request_writer.guid.bytes),
        "reply_reader": dotted(reply_reader.guid.bytes),
        "guid": guid,
        "clientid": clientid,
        "request_writer_user_data": request_user_data,
        "reply_reader_user_data": reply_user_data,
    }), flush=True)

    summary = {"summary": True, "count": count, "replies": 0, "ok": False,
               "service_available": False, "foreign_replies": 0, "stale_replies": 0}
    while not (available := service_is_available(request_writer, reply_reader)) \
            and time.monotonic() < deadline:
        time.sleep(0.01)
    summary["service_available"] = available

    waitset = WaitSet(dp)
    waitset.attach(ReadCondition(reply_reader, SampleState.Any | ViewState.Any | InstanceState.Any))
    next_request_id = 0
    all_correct = available
    for i in range(1, count + 1):
        if not available or time.monotonic() >= deadline:
            all_correct = False
            break
        next_request_id += 1
        seq = next_request_id
        a, b = i, 10 * i
        request_writer.write(CddsAddTwoIntsRequest(client_guid=guid, seq=seq, a=a, b=b))
        reply = None
        while reply is None and (remaining := deadline - time.monotonic()) > 0:
            waitset.wait(duration(seconds=min(remaining, 0.1)))
            for sample in reply_reader.take(N=16):
                if not sample.sample_info.valid_data:
                    continue
                if sample.client_guid != guid:
                    summary["foreign_replies"] += 1  # another client's reply
                elif sample.seq != seq:
                    summary["stale_replies"] += 1
                else:
                    reply = sample
        if reply is None:
            all_correct = False
            break
        summary["replies"] += 1
        print(json.dumps({"a": a, "b": b, "sum": reply.sum, "seq": reply.seq}), flush=True)
        if reply.sum != a + b:
            all_correct = False
    summary["ok"] = all_correct and summary["replies"] == count
    print(json.dumps(summary), flush=True)
    return 0 if summary["ok"] else 3


if __name__ == "__main__":
    sys.exit(main())
