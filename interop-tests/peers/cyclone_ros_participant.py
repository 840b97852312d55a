"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that joins the graph as a ROS 2
participant would: it announces one node on `ros_discovery_info` (as rmw_dds_common does) owning a
writer on `rt/NAMESPACE/chatter` and a reader on `rt/NAMESPACE/echo`, both carrying rmw's
`typehash=RIHS01_…;` USER_DATA, and — when SERVICE is given — an example_interfaces/AddTwoInts
server for it (request reader on `rq/SERVICERequest`, reply writer on `rr/SERVICEReply`, with
rmw_qos_profile_services_default: RELIABLE, VOLATILE, KEEP_LAST 10). It prints one JSON line
describing what it created (GIDs, and the QoS Cyclone holds for the server's endpoints), then stays
up for LINGER seconds so the test can watch it, and leaves.

usage: cyclone_ros_participant.py DOMAIN NAMESPACE NODE TYPEHASH LINGER [SERVICE]
"""

import json
import sys
import time

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from ros_types import (
    ADD_TWO_INTS_REQUEST_HASH,
    ADD_TWO_INTS_RESPONSE_HASH,
    AddTwoIntsRequest,
    AddTwoIntsResponse,
    Gid,
    NodeEntitiesInfo,
    ParticipantEntitiesInfo,
    Time,
    dotted,
)


def qos_text(qos) -> dict:
    """The reliability / durability / history Cyclone holds for an endpoint."""
    rel, dur = repr(qos[Policy.Reliability]), repr(qos[Policy.Durability])
    return {
        "reliability": "RELIABLE" if "Reliable" in rel else "BEST_EFFORT",
        "durability": {"Policy.Durability.Volatile": "VOLATILE",
                       "Policy.Durability.TransientLocal": "TRANSIENT_LOCAL"}.get(dur, dur),
    }


def main() -> int:
    domain, namespace, node = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    typehash, linger = sys.argv[4], float(sys.argv[5])
    service = sys.argv[6] if len(sys.argv) > 6 else None
    dp = DomainParticipant(domain)
    user_data = Policy.Userdata(f"typehash={typehash};".encode())
    default = Qos(Policy.Reliability.Reliable(max_blocking_time=0), Policy.Durability.Volatile,
                  Policy.History.KeepLast(10), user_data)
    prefix = "" if namespace == "/" else namespace
    writer = DataWriter(dp, Topic(dp, f"rt{prefix}/chatter", Time), qos=default)
    reader = DataReader(dp, Topic(dp, f"rt{prefix}/echo", Time), qos=default)

    readers, writers = [reader], [writer]
    server = None
    if service is not None:
        services_default = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                               Policy.Durability.Volatile, Policy.History.KeepLast(10))
        request_reader = DataReader(
            dp, Topic(dp, f"rq{service}Request", AddTwoIntsRequest),
            qos=Qos(*services_default, Policy.Userdata(f"typehash={ADD_TWO_INTS_REQUEST_HASH};".encode())))
        reply_writer = DataWriter(
            dp, Topic(dp, f"rr{service}Reply", AddTwoIntsResponse),
            qos=Qos(*services_default, Policy.Userdata(f"typehash={ADD_TWO_INTS_RESPONSE_HASH};".encode())))
        readers.append(request_reader)
        writers.append(reply_writer)
        server = {
            "request_reader": dotted(request_reader.guid.bytes),
            "reply_writer": dotted(reply_writer.guid.bytes),
            "request_reader_qos": qos_text(request_reader.get_qos()),
            "reply_writer_qos": qos_text(reply_writer.get_qos()),
        }

    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo), qos=info_qos)
    # The participant GID: GUID prefix + ENTITYID_PARTICIPANT, as rmw_dds_common fills it.
    participant_gid = dp.guid.bytes
    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(participant_gid)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=namespace, node_name=node,
            reader_gid_seq=[Gid(list(r.guid.bytes)) for r in readers],
            writer_gid_seq=[Gid(list(w.guid.bytes)) for w in writers],
        )],
    ))
    print(json.dumps({
        "participant": dotted(participant_gid),
        "writer": dotted(writer.guid.bytes),
        "reader": dotted(reader.guid.bytes),
        "server": server,
    }), flush=True)
    time.sleep(linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
