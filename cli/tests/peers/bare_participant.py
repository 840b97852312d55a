"""A DDS participant that never announces ROS nodes (Eclipse Cyclone DDS, Python binding), for
the CLI's discovery-wait tests.

MODE is one of:
  plain       a bare DDS application, as Cyclone's `ddsperf pong`: no USER_DATA, a writer and a
              reader on the DDS topic `bare_chatter`, nothing on `ros_discovery_info`;
  silent_ros  a participant that says it is a ROS participant (USER_DATA `enclave=/;`, as every
              rmw writes, and a `ros_discovery_info` writer and reader, as rmw_dds_common creates
              them) but never publishes its nodes.

It prints one JSON line {"gid": "<participant GUID, dotted>"} once everything is created, then
stays up for LINGER seconds (or until stdin closes) and leaves.

usage: bare_participant.py DOMAIN MODE LINGER
"""

import json
import os
import sys
import threading
from dataclasses import dataclass

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "..", "interop-tests",
                                "peers"))

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct  # noqa: E402
from cyclonedds.idl.types import int32  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402

from ros_types import ParticipantEntitiesInfo, dotted  # noqa: E402


@dataclass
class Count(IdlStruct, typename="Bare::Count"):
    value: int32


def main() -> int:
    domain, mode, linger = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
    keep = []
    if mode == "plain":
        dp = DomainParticipant(domain)
        topic = Topic(dp, "bare_chatter", Count)
        keep += [DataWriter(dp, topic), DataReader(dp, topic)]
    elif mode == "silent_ros":
        dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
        qos = Qos(
            Policy.Reliability.Reliable(max_blocking_time=0),
            Policy.Durability.TransientLocal,
            Policy.History.KeepLast(1),
        )
        topic = Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo)
        keep += [DataWriter(dp, topic, qos=qos), DataReader(dp, topic, qos=qos)]
    else:
        print(f"unknown mode {mode!r}", file=sys.stderr)
        return 2
    print(json.dumps({"gid": dotted(dp.guid.bytes)}), flush=True)
    done = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            done.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    done.wait(linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
