"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) standing for one ROS 2 Jazzy
process on rmw_cyclonedds_cpp with CLIENTS clients of example_interfaces/srv/AddTwoInts, each
calling as soon as rmw_cyclonedds would let it (rmw_cyclonedds_cpp jazzy, src/rmw_node.cpp):

- one participant for the process (one rcl context), announcing node `first_reply_clients` on
  `ros_discovery_info` with every client's reply reader and request writer, again after each
  change;
- client i (1..CLIENTS) is what `rmw_create_client` / `rmw_init_cs` makes: a request writer on
  `rq<SERVICE>Request`, then a reply reader on `rr<SERVICE>Reply`, RELIABLE, VOLATILE, KEEP_LAST
  DEPTH (rmw_qos_profile_services_default has 10), USER_DATA `clientid=<csid>;typehash=RIHS01_…;`
  with the same csid on both (`get_unique_csid`: the participant's GUID prefix and the context's
  counter, i here);
- the clients are created back to back, before any is looked at; with LEAD > 0, the first LEAD
  clients are created first and the others only once each of those has its first reply (the
  server's reply writer then already has readers of this participant matched, and must tell
  them apart by `clientid=` as `check_for_response_reader` does);
- a client sends its first request the moment `rmw_service_server_is_available`
  (`check_for_service_reader_writer`) says yes — its request writer has matched a request reader
  and its reply reader has matched a reply writer; when matched request readers advertise
  `serviceid=`, one matched reply writer must carry one of those ids. It looks again whenever its
  endpoints' matches change (rclcpp's `wait_for_service` wakes on graph changes; this is the
  earliest a real client can call);
- each request starts with rmw_cyclonedds' 16-byte header {guid, seq}: guid = the request writer's
  instance handle (`rmw_send_request`: `info->client.pub->pubiid`), seq from one counter for the
  whole process (`static std::atomic_uint next_request_id`);
- a client keeps only replies whose header guid is its own (`rmw_take_response` filters on
  `pubiid`) and whose seq is the one it waits for; it makes CALLS calls one after the other, call
  k asking a = k, b = 10 k + i.

Everything runs in one thread woken by DDS (a waitset on the endpoints' matched statuses and the
reply readers' data), never by a timer.

Output: one JSON line at start ({"participant", "clients", "lead"}), one per client when it ends
({"client", "clientid", "guid", "available", "first_reply", "replies", "foreign_replies",
"stale_replies"}), then a summary ({"summary": true, "clients", "created", "available",
"first_replies", "complete"}). Exit status 0 iff every client got all CALLS replies, each with
sum == a + b, within TIMEOUT seconds from start; else 3.

usage: cyclone_service_clients.py DOMAIN SERVICE CLIENTS CALLS TIMEOUT [LEAD [DEPTH]]
"""

import json
import sys
import time

from cyclonedds.core import (DDSStatus, InstanceState, Policy, Qos, ReadCondition, SampleState,
                             ViewState, WaitSet)
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from ros_types import (
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
    services_qos,
    service_is_available,
)

NODE_NAMESPACE, NODE_NAME = "/", "first_reply_clients"
U64 = (1 << 64) - 1


class Client:
    """One rmw_cyclonedds client: its two endpoints, its header guid, its calls."""

    def __init__(self, dp, service: str, index: int, depth: int):
        self.index = index
        self.clientid = cdds_csid_text(cdds_csid(dp.guid.bytes, index))
        request_ud = f"clientid={self.clientid};typehash={ADD_TWO_INTS_REQUEST_HASH};"
        reply_ud = f"clientid={self.clientid};typehash={ADD_TWO_INTS_RESPONSE_HASH};"
        # rmw_init_cs: the writer first, then the reader.
        self.writer = DataWriter(dp, Topic(dp, f"rq{service}Request", CddsAddTwoIntsRequest),
                                 qos=services_qos(request_ud, writer=True, depth=depth))
        self.reader = DataReader(dp, Topic(dp, f"rr{service}Reply", CddsAddTwoIntsResponse),
                                 qos=services_qos(reply_ud, writer=False, depth=depth))
        self.writer.set_status_mask(DDSStatus.PublicationMatched)
        self.reader.set_status_mask(DDSStatus.SubscriptionMatched)
        self.guid = self.writer.get_instance_handle() & U64
        self.available = False
        self.call = 0  # the call in flight (1-based), 0 before the first
        self.seq = None  # its request's seq
        self.replies = 0
        self.correct = True
        self.foreign = 0
        self.stale = 0
        self.done = False

    def send(self, seq: int) -> None:
        self.call += 1
        self.seq = seq
        a, b = self.call, 10 * self.call + self.index
        self.writer.write(CddsAddTwoIntsRequest(client_guid=self.guid, seq=seq, a=a, b=b))

    def report(self) -> dict:
        return {"client": self.index, "clientid": self.clientid, "guid": self.guid,
                "available": self.available, "first_reply": self.replies > 0,
                "replies": self.replies, "foreign_replies": self.foreign,
                "stale_replies": self.stale}


def announce(info_writer, dp, clients) -> None:
    """`ros_discovery_info` as rmw_dds_common publishes it after each change of the node."""
    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(dp.guid.bytes)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=NODE_NAMESPACE, node_name=NODE_NAME,
            reader_gid_seq=[Gid(list(c.reader.guid.bytes)) for c in clients],
            writer_gid_seq=[Gid(list(c.writer.guid.bytes)) for c in clients],
        )],
    ))


def main() -> int:
    if len(sys.argv) not in (6, 7, 8):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    domain, service = int(sys.argv[1]), sys.argv[2]
    n, calls, timeout = int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
    lead = int(sys.argv[6]) if len(sys.argv) >= 7 else 0
    depth = int(sys.argv[7]) if len(sys.argv) >= 8 else 10
    if not 0 <= lead < n:
        print("LEAD must be below CLIENTS", file=sys.stderr)
        return 2
    deadline = time.monotonic() + timeout
    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo),
                             qos=info_qos)
    print(json.dumps({"participant": dotted(dp.guid.bytes), "clients": n, "lead": lead}),
          flush=True)
    waitset = WaitSet(dp)
    clients = []

    def create(count: int) -> None:
        # Back to back, before any of them is looked at.
        new = [Client(dp, service, len(clients) + i + 1, depth) for i in range(count)]
        clients.extend(new)
        announce(info_writer, dp, clients)
        for c in new:
            waitset.attach(c.writer)
            waitset.attach(c.reader)
            waitset.attach(ReadCondition(c.reader,
                                         SampleState.Any | ViewState.Any | InstanceState.Any))

    create(lead or n)
    next_request_id = 0
    while not (len(clients) == n and all(c.done for c in clients)):
        for c in clients:
            # Reset the matched statuses before looking, so a change after the look wakes us.
            c.writer.take_status(DDSStatus.PublicationMatched)
            c.reader.take_status(DDSStatus.SubscriptionMatched)
            if not c.available and service_is_available(c.writer, c.reader):
                c.available = True
                next_request_id += 1
                c.send(next_request_id)
            for sample in c.reader.take(N=64):
                if not sample.sample_info.valid_data:
                    continue
                if sample.client_guid != c.guid:
                    c.foreign += 1
                elif c.done or sample.seq != c.seq:
                    c.stale += 1
                else:
                    c.replies += 1
                    c.correct &= sample.sum == c.call + 10 * c.call + c.index
                    if c.replies == calls:
                        c.done = True
                        print(json.dumps(c.report()), flush=True)
                    else:
                        next_request_id += 1
                        c.send(next_request_id)
        if len(clients) < n and all(c.replies > 0 for c in clients):
            # The lead clients are answered (their reply readers are matched with the server's
            # reply writer): now the others, in the same participant.
            create(n - len(clients))
            continue
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            break
        if not (len(clients) == n and all(c.done for c in clients)):
            waitset.wait(duration(seconds=remaining))
    for c in clients:
        if not c.done:
            print(json.dumps(c.report()), flush=True)
    complete = len(clients) == n and all(c.done and c.correct for c in clients)
    print(json.dumps({"summary": True, "clients": n, "created": len(clients),
                      "available": sum(c.available for c in clients),
                      "first_replies": sum(c.replies > 0 for c in clients),
                      "complete": complete}), flush=True)
    return 0 if complete else 3


if __name__ == "__main__":
    sys.exit(main())
