"""An rclpy node on rmw_zenoh_cpp 0.2.10, written by hand with the eclipse-zenoh package.

What rmw_zenoh puts on the wire, per shared/docs/rmw-zenoh-jazzy-wire-facts.md (and
rmw_zenoh_cpp's liveliness_utils.cpp, rmw_publisher_data.cpp, attachment_helpers.cpp):

- a peer session connected to the router, multicast scouting off;
- the node's NN token and its entities' tokens
  @ros2_lv/<domain>/<zid>/<node_id>/<entity_id>/<kind>/<enclave>/<ns>/<node>[/<topic>/<type>/<hash>/<qos>];
- a publisher on /chatter (MP, entity 10 as in rclpy): every 100 ms a sample on
  <domain>/chatter/<type>/<hash>, CDR with the 00 01 00 00 header, and the 33-byte attachment
  (seq from 1, source timestamp ns, 0x10, GID = XXH3-128 of the MP token, low64 LE then high64 LE);
- a service server token for /add_two_ints (SS, entity 12; no queryable yet);
- a subscription on /back (MS, entity 11): each sample received is printed as a JSON line, with
  whether its attachment GID is the XXH3-128 of a publisher token of /back seen in the graph.

Usage: zenoh_rclpy_talker.py <router port> <domain> <linger seconds>
Prints one JSON line when its tokens are declared: zid, the tokens and the publisher's GID.
"""

import json
import queue
import struct
import sys
import threading
import time

import xxhash
import zenoh

STRING_TYPE = "std_msgs::msg::dds_::String_"
STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
SRV_TYPE = "example_interfaces::srv::dds_::AddTwoInts_"
SRV_HASH = "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"
QOS = "::,10:,:,:,,"  # RELIABLE, VOLATILE, KEEP_LAST 10: rclpy's default, as qos_to_keyexpr writes it


def gid_of(key):
    h = xxhash.xxh3_128_intdigest(key.encode())
    return struct.pack("<QQ", h & (2**64 - 1), h >> 64)


def cdr_string(text):
    data = text.encode() + b"\0"
    return b"\x00\x01\x00\x00" + struct.pack("<I", len(data)) + data


def main():
    port, domain, linger = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("connect/endpoints", json.dumps([f"tcp/127.0.0.1:{port}"]))
    conf.insert_json5("listen/endpoints", '["tcp/127.0.0.1:0"]')
    conf.insert_json5("scouting/multicast/enabled", "false")
    session = zenoh.open(conf)
    zid = str(session.zid())
    prefix = f"@ros2_lv/{domain}/{zid}/0"
    node_token = f"{prefix}/0/NN/%/%/talker"
    pub_token = f"{prefix}/10/MP/%/%/talker/%chatter/{STRING_TYPE}/{STRING_HASH}/{QOS}"
    sub_token = f"{prefix}/11/MS/%/%/talker/%back/{STRING_TYPE}/{STRING_HASH}/{QOS}"
    # A server's token only (the graph's view of a service; its queryable is milestone 2's).
    srv_token = f"{prefix}/12/SS/%/%/talker/%add_two_ints/{SRV_TYPE}/{SRV_HASH}/{QOS}"
    gid = gid_of(pub_token)

    # The graph, as rmw_zenoh's graph cache learns it: tokens with history.
    graph = set()
    changed = threading.Condition()

    def on_token(sample):
        with changed:
            if sample.kind == zenoh.SampleKind.PUT:
                graph.add(str(sample.key_expr))
            else:
                graph.discard(str(sample.key_expr))
            changed.notify_all()

    tokens_sub = session.liveliness().declare_subscriber(
        f"@ros2_lv/{domain}/**", on_token, history=True
    )

    def back_publishers():
        return [t for t in graph if "/MP/" in t and "/%back/" in t and f"/{zid}/" not in t]

    # Samples are judged on a thread of their own: a sample may come (peer to peer) before its
    # publisher's token (through the router), so the check waits for the token, bounded.
    received = queue.Queue()

    def judge():
        while True:
            sample = received.get()
            if sample is None:
                return
            key, payload, attachment = sample
            out = {"key": key, "payload": payload.hex(), "attachment": attachment.hex()}
            if len(payload) >= 8:
                (n,) = struct.unpack_from("<I", payload, 4)
                out["data"] = payload[8 : 8 + n - 1].decode(errors="replace")
            if len(attachment) == 33:
                seq, ts = struct.unpack_from("<qq", attachment)
                out["seq"], out["timestamp"] = seq, ts
                out["gid"] = attachment[17:].hex()
                match = lambda: any(gid_of(t) == attachment[17:] for t in back_publishers())
                with changed:
                    changed.wait_for(match, timeout=10)
                    out["publisher_tokens"] = back_publishers()
                    out["gid_is_token_hash"] = match()
            print(json.dumps(out), flush=True)

    judge_thread = threading.Thread(target=judge, daemon=True)
    judge_thread.start()

    def on_back(sample):
        attachment = sample.attachment.to_bytes() if sample.attachment is not None else b""
        received.put((str(sample.key_expr), sample.payload.to_bytes(), attachment))

    back_key = f"{domain}/back/{STRING_TYPE}/{STRING_HASH}"
    sub = session.declare_subscriber(back_key, on_back)
    tokens = [session.liveliness().declare_token(k) for k in (node_token, pub_token, sub_token, srv_token)]
    pub = session.declare_publisher(f"{domain}/chatter/{STRING_TYPE}/{STRING_HASH}")
    print(
        json.dumps(
            {
                "zid": zid,
                "node_token": node_token,
                "pub_token": pub_token,
                "sub_token": sub_token,
                "pub_gid": gid.hex(),
                "srv_token": srv_token,
                "srv_gid": gid_of(srv_token).hex(),
            }
        ),
        flush=True,
    )
    end = time.monotonic() + linger
    seq = 0
    while time.monotonic() < end:
        seq += 1
        attachment = struct.pack("<qq", seq, time.time_ns()) + b"\x10" + gid
        pub.put(cdr_string(f"Hello World: {seq}"), attachment=attachment)
        time.sleep(0.1)
    del tokens, sub, tokens_sub
    session.close()


if __name__ == "__main__":
    main()
