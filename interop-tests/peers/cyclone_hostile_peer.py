"""An independent DDS peer (Eclipse Cyclone DDS, Python binding) that misbehaves on a service's
request topic `rq<SERVICE>Request`, to check that a server is not held up by it:

- MODE `stall`: a crashed rmw_cyclonedds_cpp client. It has the client's request writer (USER_DATA
  `clientid=…;typehash=…;`, rmw_qos_profile_services_default, as rmw_cyclonedds' `rmw_init_cs`) but
  no reply reader, and sends well-formed AddTwoInts requests with the 16-byte rmw_cyclonedds header
  (rmw_node.cpp `rmw_send_request`) 20 times a second: no reply can ever reach it, and
  rmw_cyclonedds' own `rmw_send_response` would wait up to 100 ms for its reader each time.
- MODE `garbage`: random bytes, 0 B to 1 MiB, 100 samples a second (at most 500), under the
  request type's name (a `sequence<octet>`, so the body is a length and the bytes): many parse as
  an rmw_cyclonedds header, some as a whole request.

It starts writing once its writer is matched with a request reader, for SECONDS, then prints a JSON
summary ({"mode", "written", "matched"}) and exits 0 (3 if it never matched).

usage: cyclone_hostile_peer.py DOMAIN SERVICE MODE SECONDS    (SERVICE like /add_two_ints)
"""

import json
import random
import sys
import time
from dataclasses import dataclass

from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import sequence, uint8
from cyclonedds.pub import DataWriter
from cyclonedds.topic import Topic

from ros_types import (
    ADD_TWO_INTS_REQUEST_HASH,
    CddsAddTwoIntsRequest,
    cdds_csid,
    cdds_csid_text,
    services_qos,
)

U64 = (1 << 64) - 1
MATCH_TIMEOUT = 20.0


@dataclass
class Garbage(IdlStruct, typename="example_interfaces::srv::dds_::AddTwoInts_Request_"):
    junk: sequence[uint8]


def main() -> int:
    if len(sys.argv) != 5 or sys.argv[3] not in ("stall", "garbage"):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    domain, service, mode, seconds = int(sys.argv[1]), sys.argv[2], sys.argv[3], float(sys.argv[4])
    dp = DomainParticipant(domain)
    clientid = cdds_csid_text(cdds_csid(dp.guid.bytes, 1))
    user_data = f"clientid={clientid};typehash={ADD_TWO_INTS_REQUEST_HASH};"
    kind = CddsAddTwoIntsRequest if mode == "stall" else Garbage
    writer = DataWriter(dp, Topic(dp, f"rq{service}Request", kind),
                        qos=services_qos(user_data, writer=True))
    guid = writer.get_instance_handle() & U64
    deadline = time.monotonic() + MATCH_TIMEOUT
    while not writer.get_matched_subscriptions() and time.monotonic() < deadline:
        time.sleep(0.01)
    matched = bool(writer.get_matched_subscriptions())
    written = 0
    rng = random.Random(0x5EED)
    end = time.monotonic() + seconds
    while matched and time.monotonic() < end:
        if mode == "stall":
            written += 1
            writer.write(CddsAddTwoIntsRequest(client_guid=guid, seq=written, a=written, b=1))
            time.sleep(0.05)
        else:
            if written < 500:
                length = min(rng.randrange(1 << rng.randrange(21)), 1 << 20)
                writer.write(Garbage(junk=list(rng.randbytes(length))))
                written += 1
            time.sleep(0.01)
    print(json.dumps({"mode": mode, "written": written, "matched": matched}), flush=True)
    return 0 if matched else 3


if __name__ == "__main__":
    sys.exit(main())
