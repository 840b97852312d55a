"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that serves
example_interfaces/srv/AddTwoInts exactly as a ROS 2 Jazzy node on rmw_cyclonedds_cpp does, on the
wire and in its matching rules (rmw_cyclonedds_cpp jazzy, src/rmw_node.cpp, src/serdata.*,
src/Serialization.cpp):

- it announces node `add_two_ints_server` in namespace `/` on `ros_discovery_info` (as rmw_dds_common
  does), listing the service's request reader and reply writer;
- the service is a reply writer on `rr<SERVICE>Reply` and a request reader on `rq<SERVICE>Request`
  (`rmw_init_cs`, created in that order), with rmw_qos_profile_services_default (RELIABLE with
  infinite max_blocking_time, VOLATILE, KEEP_LAST 10, autodispose off: `create_readwrite_qos`) and
  USER_DATA `serviceid=<csid>;typehash=RIHS01_…;` (`rmw_init_cs` passes `serviceid=…;` as the extra
  user data that `create_readwrite_qos` puts before `typehash=…;`);
- every sample starts with the 16-byte request header {uint64 guid, int64 seq} in the CDR stream
  (ros_types.CddsAddTwoIntsRequest / CddsAddTwoIntsResponse), written as XCDR1 (CDR_LE);
- for each request it replies `sum = a + b` with the request's header echoed (`rmw_send_response`),
  first waiting up to 100 ms, polling every 10 ms, until its reply writer has matched the reader of
  the same client (a reader whose USER_DATA `clientid=` equals the request writer's); a request
  writer without `clientid=` is taken as matched; a request writer no longer matched means the
  client is gone and the reply is dropped; still unmatched after 100 ms means RMW_RET_TIMEOUT, no
  reply (`check_for_response_reader`, `rmw_send_response`).

It prints one JSON line with its GUIDs and USER_DATA at start, then one JSON line per request taken:
{"guid": <header guid, u64>, "seq": …, "a": …, "b": …, "sum": …, "reply": "sent"|"timeout"|"gone",
"clientid": <the request writer's USER_DATA clientid, or null>},
and exits after LINGER seconds.

usage: cyclone_add_two_ints_server.py DOMAIN SERVICE LINGER      (SERVICE like /add_two_ints)
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
    user_data_key,
)

NODE_NAMESPACE, NODE_NAME = "/", "add_two_ints_server"
U64 = (1 << 64) - 1


def signed64(handle: int) -> int:
    """Instance handles are uint64 in Cyclone; the binding's ctypes declare them int64."""
    handle &= U64
    return handle - (1 << 64) if handle >= 1 << 63 else handle



def request_writer_clientid(request_reader, request_writer_handle: int):
    """The matched request writer's USER_DATA `clientid=` value; None when it has none, False when
    that writer is no longer matched."""
    request_writer = request_reader.get_matched_publication_data(signed64(request_writer_handle))
    if request_writer is None:
        return False
    return user_data_key(request_writer.qos, "clientid")


def check_for_response_reader(request_reader, reply_writer, request_writer_handle: int) -> str:
    """rmw_node.cpp `check_for_response_reader`: "yes", "maybe" or "gone"."""
    clientid = request_writer_clientid(request_reader, request_writer_handle)
    if clientid is False:
        return "gone"
    if clientid is None:
        return "yes"  # a client without a client id: assume all is well
    for handle in reply_writer.get_matched_subscriptions():
        reader = reply_writer.get_matched_subscription_data(handle)
        if reader is not None and user_data_key(reader.qos, "clientid") == clientid:
            return "yes"
    return "maybe"


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    domain, service, linger = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
    deadline = time.monotonic() + linger

    # rmw_context_impl_t::init: participant USER_DATA "enclave=<enclave>;" (default enclave "/").
    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo), qos=info_qos)

    participant_gid = dp.guid.bytes
    serviceid = cdds_csid_text(cdds_csid(participant_gid, 1))  # first client/service of the context
    reply_user_data = f"serviceid={serviceid};typehash={ADD_TWO_INTS_RESPONSE_HASH};"
    request_user_data = f"serviceid={serviceid};typehash={ADD_TWO_INTS_REQUEST_HASH};"
    reply_writer = DataWriter(dp, Topic(dp, f"rr{service}Reply", CddsAddTwoIntsResponse),
                              qos=services_qos(reply_user_data, writer=True))
    request_reader = DataReader(dp, Topic(dp, f"rq{service}Request", CddsAddTwoIntsRequest),
                                qos=services_qos(request_user_data, writer=False))

    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(participant_gid)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=NODE_NAMESPACE, node_name=NODE_NAME,
            reader_gid_seq=[Gid(list(request_reader.guid.bytes))],
            writer_gid_seq=[Gid(list(reply_writer.guid.bytes))],
        )],
    ))
    print(json.dumps({
        "participant": dotted(participant_gid),
        "request_reader": dotted(request_reader.guid.bytes),
        "reply_writer": dotted(reply_writer.guid.bytes),
        "serviceid": serviceid,
        "request_reader_user_data": request_user_data,
        "reply_writer_user_data": reply_user_data,
    }), flush=True)

    waitset = WaitSet(dp)
    waitset.attach(ReadCondition(request_reader, SampleState.Any | ViewState.Any | InstanceState.Any))
    while (remaining := deadline - time.monotonic()) > 0:
        waitset.wait(duration(seconds=min(remaining, 0.1)))
        for request in request_reader.take(N=16):
            if not request.sample_info.valid_data:
                continue
            # rmw_take_request: request_id.writer_guid = header.guid (8 bytes) followed by the
            # sample's publication_handle (8 bytes); sequence_number = header.seq.
            writer_handle = request.sample_info.publication_handle & U64
            response = CddsAddTwoIntsResponse(client_guid=request.client_guid, seq=request.seq,
                                              sum=request.a + request.b)
            # rmw_send_response: wait up to 100 ms (10 ms steps) for the client's reply reader.
            tend = time.monotonic() + 0.1
            while (state := check_for_response_reader(request_reader, reply_writer, writer_handle)) \
                    == "maybe" and time.monotonic() < tend:
                time.sleep(0.01)
            if state == "yes":
                reply_writer.write(response)
                outcome = "sent"
            else:
                outcome = "timeout" if state == "maybe" else "gone"
            clientid = request_writer_clientid(request_reader, writer_handle)
            print(json.dumps({"guid": request.client_guid, "seq": request.seq, "a": request.a,
                              "b": request.b, "sum": response.sum, "reply": outcome,
                              "clientid": clientid or None}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
