"""Independent Cyclone DDS peer (the cyclonedds Python binding) for rmw-cyclone/tests/python_interop.rs.

usage: cyclone_blob_peer.py DOMAIN SECONDS   (configure Cyclone through CYCLONEDDS_URI)

Reads the built-in topics and prints one JSON line per remote participant / endpoint on
rt/rmwc/* (with its USER_DATA), takes builtin_interfaces/msg/Time samples from rt/rmwc/to_py,
writes three on rt/rmwc/from_py once matched, and exits after it got five samples (or after
SECONDS). Its own participant has USER_DATA enclave=/py; and its endpoints typehash=...;
(a copy of the part of the spike's peer.py this test needs; Time as in interop-tests' ros_types)."""
import json
import sys
import time
from dataclasses import dataclass

from cyclonedds.builtin import (BuiltinDataReader, BuiltinTopicDcpsParticipant,
                                BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription)
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import int32, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


TYPEHASH = "RIHS01_b106235e25a4c5ed35098aa0a61a3ee9c9b18d197f398b0e4206cea9acf9c197"


def out(**kw):
    print(json.dumps(kw), flush=True)


def user_data(s):
    try:
        return s.qos[Policy.Userdata].data.decode(errors="replace")
    except Exception:  # absent
        return None


def main():
    domain, seconds = int(sys.argv[1]), float(sys.argv[2])
    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/py;")))
    me = dp.guid.bytes
    q = Qos(Policy.Reliability.Reliable(max_blocking_time=0), Policy.Durability.Volatile,
            Policy.History.KeepLast(10), Policy.Userdata(f"typehash={TYPEHASH};".encode()))
    rd = DataReader(dp, Topic(dp, "rt/rmwc/to_py", Time), qos=q)
    wr = DataWriter(dp, Topic(dp, "rt/rmwc/from_py", Time), qos=q)
    parts = BuiltinDataReader(dp, BuiltinTopicDcpsParticipant)
    pubs = BuiltinDataReader(dp, BuiltinTopicDcpsPublication)
    subs = BuiltinDataReader(dp, BuiltinTopicDcpsSubscription)
    out(event="ready", guid=me.hex())
    seen, got, sent = set(), 0, False
    end = time.time() + seconds
    while time.time() < end:
        for s in parts.take(N=50):
            if s.key.bytes != me and s.key not in seen:
                seen.add(s.key)
                out(event="participant", guid=s.key.bytes.hex(), user_data=user_data(s))
        for kind, r in (("publication", pubs), ("subscription", subs)):
            for s in r.take(N=50):
                if s.participant_key.bytes != me and s.topic_name.startswith("rt/rmwc") and s.key not in seen:
                    seen.add(s.key)
                    out(event=kind, guid=s.key.bytes.hex(), topic=s.topic_name, type=s.type_name,
                        user_data=user_data(s))
        for s in rd.take(N=10):
            got += 1
            out(event="sample", sec=s.sec, nanosec=s.nanosec)
        if not sent and wr.get_matched_subscriptions():
            time.sleep(0.2)
            for i in range(3):
                wr.write(Time(sec=-5 - i, nanosec=123456 + i))
            sent = True
            out(event="wrote", count=3)
        if got >= 5 and sent:
            time.sleep(1.0)  # let our samples be acknowledged before leaving
            break
        time.sleep(0.05)
    out(event="done", got=got)


main()
