"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) on ROS 2's `/chatter`: the DDS
topic `rt/chatter` with `std_msgs::msg::dds_::String_` (one CDR string), rclcpp's default QoS
(RELIABLE, VOLATILE, KEEP_LAST 10) and rmw's `typehash=RIHS01_…;` USER_DATA, as demo_nodes'
talker and listener use it.

usage: cyclone_chatter.py DOMAIN talk|listen COUNT LIMIT_SECONDS
  talk:   publishes `Hello World: <n>` every 50 ms until COUNT messages were matched-and-sent
          after a reader appeared (it keeps going until LIMIT_SECONDS so late readers hear some)
  listen: prints `I heard: [<data>]` for each message, exits after COUNT of them
"""

import sys
import time
from dataclasses import dataclass

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"


@dataclass
class String(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str


def main() -> int:
    domain, mode, count, limit = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
    dp = DomainParticipant(domain)
    qos = Qos(
        Policy.Reliability.Reliable(0),
        Policy.Durability.Volatile,
        Policy.History.KeepLast(10),
        Policy.Userdata(f"typehash={STRING_HASH};".encode()),
    )
    topic = Topic(dp, "rt/chatter", String)
    end = time.monotonic() + limit
    if mode == "talk":
        writer = DataWriter(dp, topic, qos=qos)
        n = 0
        while time.monotonic() < end:
            n += 1
            writer.write(String(data=f"Hello World: {n}"))
            print(f"Publishing: 'Hello World: {n}'", flush=True)
            time.sleep(0.05)
        return 0
    reader = DataReader(dp, topic, qos=qos)
    heard = 0
    while time.monotonic() < end and heard < count:
        left_ns = max(1, int((end - time.monotonic()) * 1e9))
        for sample in reader.take_iter(timeout=left_ns):
            print(f"I heard: [{sample.data}]", flush=True)
            heard += 1
            if heard >= count:
                break
    return 0 if heard >= count else 1


if __name__ == "__main__":
    sys.exit(main())
