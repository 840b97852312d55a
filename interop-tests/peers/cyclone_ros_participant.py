"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that joins the graph as a ROS 2
participant would: it announces one node on `ros_discovery_info` (as rmw_dds_common does) owning a
writer on `rt/NAMESPACE/chatter` and a reader on `rt/NAMESPACE/echo`, both carrying rmw's
`typehash=RIHS01_…;` USER_DATA. It prints one JSON line describing what it created, then stays up
for LINGER seconds so the test can watch it, and leaves.

usage: cyclone_ros_participant.py DOMAIN NAMESPACE NODE TYPEHASH LINGER
"""

import json
import sys
import time

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from ros_types import Gid, NodeEntitiesInfo, ParticipantEntitiesInfo, Time, dotted


def main() -> int:
    domain, namespace, node = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    typehash, linger = sys.argv[4], float(sys.argv[5])
    dp = DomainParticipant(domain)
    user_data = Policy.Userdata(f"typehash={typehash};".encode())
    default = Qos(Policy.Reliability.Reliable(max_blocking_time=0), Policy.Durability.Volatile,
                  Policy.History.KeepLast(10), user_data)
    prefix = "" if namespace == "/" else namespace
    writer = DataWriter(dp, Topic(dp, f"rt{prefix}/chatter", Time), qos=default)
    reader = DataReader(dp, Topic(dp, f"rt{prefix}/echo", Time), qos=default)

    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=0),
                   Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
    info_writer = DataWriter(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo), qos=info_qos)
    # The participant GID: GUID prefix + ENTITYID_PARTICIPANT, as rmw_dds_common fills it.
    participant_gid = dp.guid.bytes
    info_writer.write(ParticipantEntitiesInfo(
        gid=Gid(list(participant_gid)),
        node_entities_info_seq=[NodeEntitiesInfo(
            node_namespace=namespace, node_name=node,
            reader_gid_seq=[Gid(list(reader.guid.bytes))],
            writer_gid_seq=[Gid(list(writer.guid.bytes))],
        )],
    ))
    print(json.dumps({
        "participant": dotted(participant_gid),
        "writer": dotted(writer.guid.bytes),
        "reader": dotted(reader.guid.bytes),
    }), flush=True)
    time.sleep(linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
