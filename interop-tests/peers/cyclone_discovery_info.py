"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that watches the ROS 2 graph.

It reads `ros_discovery_info` the way rmw_dds_common does (RELIABLE, TRANSIENT_LOCAL, KEEP_ALL) and
Cyclone's own DDS discovery (DCPSParticipant / DCPSPublication / DCPSSubscription built-in topics),
then prints one JSON document on stdout:

  {"discovery_info": [{"gid": "01.0f...", "nodes": [{"namespace", "name", "readers", "writers"}]}],
   "publications": [{"guid", "participant", "topic", "type", "user_data"}], "subscriptions": [...],
   "participants": [{"guid", "user_data"}]}

(USER_DATA as text, "" when absent: what rmw_cyclonedds parses `enclave=`, `typehash=`,
`clientid=` / `serviceid=` from.)

It stops as soon as a participant announces node NAMESPACE/NAME with at least READERS readers and
WRITERS writers that are all visible through DDS discovery (the participant too), or when TIMEOUT
seconds have passed (then it prints what it saw and exits with status 3).

usage: cyclone_discovery_info.py DOMAIN NAMESPACE NAME READERS WRITERS TIMEOUT
"""

import json
import sys
import time

from cyclonedds.builtin import (
    BuiltinDataReader,
    BuiltinTopicDcpsParticipant,
    BuiltinTopicDcpsPublication,
    BuiltinTopicDcpsSubscription,
)
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from ros_types import ParticipantEntitiesInfo, dotted


def user_data(sample) -> str:
    """The participant's or endpoint's USER_DATA as text ("" when absent or empty)."""
    try:
        value = sample.qos[Policy.Userdata]
    except Exception:  # the policy is absent from the discovered QoS
        return ""
    data = getattr(value, "data", b"") or b""
    return bytes(data).decode("utf-8", "replace")


def main() -> int:
    domain, namespace, name = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    want_readers, want_writers = int(sys.argv[4]), int(sys.argv[5])
    deadline = time.monotonic() + float(sys.argv[6])

    dp = DomainParticipant(domain)
    qos = Qos(
        Policy.Reliability.Reliable(max_blocking_time=0),
        Policy.Durability.TransientLocal,
        Policy.History.KeepAll,
    )
    topic = Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo)
    reader = DataReader(dp, topic, qos=qos)
    pubs_reader = BuiltinDataReader(dp, BuiltinTopicDcpsPublication)
    subs_reader = BuiltinDataReader(dp, BuiltinTopicDcpsSubscription)
    participants_reader = BuiltinDataReader(dp, BuiltinTopicDcpsParticipant)

    infos = {}
    pubs, subs, participants = {}, {}, {}
    own_prefix = dp.guid.bytes[:12]
    ok = False
    while time.monotonic() < deadline:
        for s in reader.take(N=100):
            infos[dotted(bytes(s.gid.data))] = s
        for s in pubs_reader.take(N=1000):
            if s.key.bytes[:12] != own_prefix:
                pubs[dotted(s.key.bytes)] = s
        for s in subs_reader.take(N=1000):
            if s.key.bytes[:12] != own_prefix:
                subs[dotted(s.key.bytes)] = s
        for s in participants_reader.take(N=100):
            if s.key.bytes[:12] != own_prefix:
                participants[dotted(s.key.bytes)] = s
        for info in infos.values():
            for node in info.node_entities_info_seq:
                if node.node_namespace != namespace or node.node_name != name:
                    continue
                readers = [dotted(bytes(g.data)) for g in node.reader_gid_seq]
                writers = [dotted(bytes(g.data)) for g in node.writer_gid_seq]
                if (
                    len(readers) >= want_readers
                    and len(writers) >= want_writers
                    and all(r in subs for r in readers)
                    and all(w in pubs for w in writers)
                    and dotted(bytes(info.gid.data)) in participants
                ):
                    ok = True
        if ok:
            break
        time.sleep(0.05)

    def endpoints(table):
        return [
            {
                "guid": guid,
                "participant": dotted(s.participant_key.bytes),
                "topic": s.topic_name,
                "type": s.type_name,
                "user_data": user_data(s),
            }
            for guid, s in sorted(table.items())
        ]

    doc = {
        "discovery_info": [
            {
                "gid": gid,
                "nodes": [
                    {
                        "namespace": n.node_namespace,
                        "name": n.node_name,
                        "readers": [dotted(bytes(g.data)) for g in n.reader_gid_seq],
                        "writers": [dotted(bytes(g.data)) for g in n.writer_gid_seq],
                    }
                    for n in info.node_entities_info_seq
                ],
            }
            for gid, info in sorted(infos.items())
        ],
        "publications": endpoints(pubs),
        "subscriptions": endpoints(subs),
        "participants": [
            {"guid": guid, "user_data": user_data(s)} for guid, s in sorted(participants.items())
        ],
    }
    print(json.dumps(doc), flush=True)
    return 0 if ok else 3


if __name__ == "__main__":
    sys.exit(main())
