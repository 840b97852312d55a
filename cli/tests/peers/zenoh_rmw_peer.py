"""An rclpy node on rmw_zenoh_cpp 0.2.10, written by hand with the eclipse-zenoh package.

What rmw_zenoh puts on the wire, per shared/docs/rmw-zenoh-jazzy-wire-facts.md (and
rmw_zenoh_cpp's liveliness_utils.cpp, rmw_publisher_data.cpp, attachment_helpers.cpp):

- a peer session connected to the router, multicast scouting off;
- the node's NN token and its entities' tokens
  @ros2_lv/<domain>/<zid>/<node_id>/<entity_id>/<kind>/<enclave>/<ns>/<node>[/<topic>/<type>/<hash>/<qos>];
- a publisher on /chatter (MP, entity 10 as in rclpy): every 100 ms a sample on
  <domain>/chatter/<type>/<hash>, CDR with the 00 01 00 00 header, and the 33-byte attachment
  (seq from 1, source timestamp ns, 0x10, GID = XXH3-128 of the MP token, low64 LE then high64 LE);
- an AddTwoInts server of /add_two_ints (SS, entity 12; rmw_service_data.cpp): a queryable on
  <domain>/add_two_ints/<srv type>/<srv hash> with complete=true; each query's sum is replied on
  the query's key with an attachment echoing the query's sequence number and GID under a new
  timestamp, and printed as a JSON line {"served": …} (with whether the query's GID is the
  XXH3-128 of an SC token of /add_two_ints seen in the graph); {a: 0, b: 0} is held unanswered;
- a subscription on /back (MS, entity 11): each sample received is printed as a JSON line, with
  whether its attachment GID is the XXH3-128 of a publisher token of /back seen in the graph;
- with a fourth argument <service>, an AddTwoInts client of it (SC, entity 13;
  rmw_client_data.cpp): once an SS token of that service is in the graph, one get on its key with
  {a: 2, b: 3}, the attachment (seq 1, timestamp, GID = XXH3-128 of the SC token), target
  ALL_COMPLETE and consolidation NONE; each reply is printed as a JSON line {"reply": …}.

Usage: zenoh_rmw_peer.py <router port> <domain> <linger seconds> [<service to call>]
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
    call = sys.argv[4] if len(sys.argv) > 4 else None
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
    srv_token = f"{prefix}/12/SS/%/%/talker/%add_two_ints/{SRV_TYPE}/{SRV_HASH}/{QOS}"
    cli_token = None
    if call is not None:
        mangled = call.replace("/", "%")
        cli_token = f"{prefix}/13/SC/%/%/talker/{mangled}/{SRV_TYPE}/{SRV_HASH}/{QOS}"
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

    def add_two_ints_clients():
        return [t for t in graph if "/SC/" in t and "/%add_two_ints/" in t and f"/{zid}/" not in t]

    # The server: queries are answered on a thread of their own (the check of the client's
    # token may wait for it, bounded, as for samples).
    queries = queue.Queue()
    held = []

    def serve():
        while True:
            query = queries.get()
            if query is None:
                return
            payload = query.payload.to_bytes() if query.payload is not None else b""
            attachment = query.attachment.to_bytes() if query.attachment is not None else b""
            out = {"served": {"key": str(query.key_expr), "payload": payload.hex(), "attachment": attachment.hex()}}
            if len(attachment) != 33 or len(payload) != 20:
                # rmw_service_data.cpp: a query without an attachment is not taken.
                print(json.dumps(out), flush=True)
                continue
            seq, _ = struct.unpack_from("<qq", attachment)
            client_gid = attachment[17:]
            a, b = struct.unpack_from("<qq", payload, 4)
            match = lambda: any(gid_of(t) == client_gid for t in add_two_ints_clients())
            with changed:
                changed.wait_for(match, timeout=10)
                out["served"]["gid_is_token_hash"] = match()
                out["served"]["client_tokens"] = [t for t in add_two_ints_clients() if gid_of(t) == client_gid]
            out["served"].update({"seq": seq, "gid": client_gid.hex(), "a": a, "b": b})
            if a == 0 and b == 0:
                # {a: 0, b: 0} is held unanswered (a server that dies while serving it).
                held.append(query)
                print(json.dumps(out), flush=True)
                continue
            reply_attachment = struct.pack("<qq", seq, time.time_ns()) + b"\x10" + client_gid
            query.reply(query.key_expr, b"\x00\x01\x00\x00" + struct.pack("<q", a + b), attachment=reply_attachment)
            del query
            print(json.dumps(out), flush=True)

    serve_thread = threading.Thread(target=serve, daemon=True)
    serve_thread.start()
    srv_key = f"{domain}/add_two_ints/{SRV_TYPE}/{SRV_HASH}"
    queryable = session.declare_queryable(srv_key, queries.put, complete=True)

    declared = [node_token, pub_token, sub_token, srv_token] + ([cli_token] if cli_token else [])
    tokens = [session.liveliness().declare_token(k) for k in declared]
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
                "cli_gid": gid_of(cli_token).hex() if cli_token else None,
            }
        ),
        flush=True,
    )

    def call_ours():
        mangled = call.replace("/", "%")
        servers = lambda: [t for t in graph if "/SS/" in t and f"/{mangled}/{SRV_TYPE}/" in t]
        with changed:
            if not changed.wait_for(servers, timeout=linger):
                return
        attachment = struct.pack("<qq", 1, time.time_ns()) + b"\x10" + gid_of(cli_token)
        request = b"\x00\x01\x00\x00" + struct.pack("<qq", 2, 3)
        replies = session.get(
            f"{domain}/{call.lstrip('/')}/{SRV_TYPE}/{SRV_HASH}",
            target=zenoh.QueryTarget.ALL_COMPLETE,
            consolidation=zenoh.ConsolidationMode.NONE,
            payload=request,
            attachment=attachment,
        )
        for reply in replies:
            if reply.ok is None:
                print(json.dumps({"reply": {"error": True}}), flush=True)
                continue
            sample = reply.ok
            att = sample.attachment.to_bytes() if sample.attachment is not None else b""
            out = {"key": str(sample.key_expr), "payload": sample.payload.to_bytes().hex(), "attachment": att.hex(), "server_tokens": servers()}
            if len(att) == 33:
                seq, ts = struct.unpack_from("<qq", att)
                out.update({"seq": seq, "timestamp": ts, "gid": att[17:].hex()})
            print(json.dumps({"reply": out}), flush=True)

    if call is not None:
        threading.Thread(target=call_ours, daemon=True).start()
    end = time.monotonic() + linger
    seq = 0
    while time.monotonic() < end:
        seq += 1
        attachment = struct.pack("<qq", seq, time.time_ns()) + b"\x10" + gid
        pub.put(cdr_string(f"Hello World: {seq}"), attachment=attachment)
        time.sleep(0.1)
    del tokens, sub, tokens_sub, queryable
    session.close()


if __name__ == "__main__":
    main()
