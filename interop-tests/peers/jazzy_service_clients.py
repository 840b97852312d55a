"""A real ROS 2 Jazzy process (rclpy 7.1.6 on the RMW that RMW_IMPLEMENTATION names:
rmw_fastrtps_cpp, rmw_cyclonedds_cpp or rmw_zenoh_cpp) with CLIENTS clients of TYPE on SERVICE in
one node, as an application writes it: each client waits with `wait_for_service`, then all make
CALLS rounds of calls, each round's calls sent together with `call_async` and spun until answered.

TYPE is example_interfaces/srv/AddTwoInts (call r of client i asks a = r, b = 10 * r + i; the
reply must say sum == a + b) or std_srvs/srv/SetBool (call r of client i asks
data = (r + i) % 2 == 0; the reply must say success == data).

With LEAD > 0 the first LEAD clients are created, wait for the service and get one reply each
before the others are created (the server then already knows a client of this process and must
tell the newer ones apart). DEPTH is the history depth of every client
(rmw_qos_profile_services_default: 10).

A call not answered within 10 s (or by TIMEOUT) is given up and counts as lost; its client goes
on with its next call.

Output: one JSON line per client when it ends ({"client", "available", "first_reply",
"replies"}), then a summary ({"summary": true, "clients", "first_replies", "replies",
"complete"}). Exit
status 0 iff every client got all its correct replies within TIMEOUT seconds from start; else 3.

usage: jazzy_service_clients.py SERVICE TYPE CLIENTS CALLS TIMEOUT [LEAD [DEPTH]]
    (domain from ROS_DOMAIN_ID)
"""

import json
import sys
import time

import rclpy
from rclpy.qos import qos_profile_services_default

CALL_TIMEOUT_S = 10.0


def request_for(srv, r, i):
    """The request of call r of client i, and a test of its reply."""
    if srv.__name__ == "AddTwoInts":
        a, b = r, 10 * r + i
        return srv.Request(a=a, b=b), lambda reply: reply.sum == a + b
    data = (r + i) % 2 == 0
    return srv.Request(data=data), lambda reply: reply.success == data


def main() -> int:
    if len(sys.argv) not in (6, 7, 8):
        print(__doc__.strip().splitlines()[-2], file=sys.stderr)
        return 2
    service, type_name = sys.argv[1], sys.argv[2]
    n, calls, timeout = int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
    lead = int(sys.argv[6]) if len(sys.argv) > 6 else 0
    depth = int(sys.argv[7]) if len(sys.argv) > 7 else 10
    package, _, name = type_name.split("/")
    srv = getattr(__import__(f"{package}.srv", fromlist=[name]), name)
    qos = qos_profile_services_default
    qos.depth = depth
    deadline = time.monotonic() + timeout

    rclpy.init()
    node = rclpy.create_node("jazzy_service_clients")
    clients, available = [], []
    outcomes = [[] for _ in range(n)]  # per client, whether each of its calls was answered
    correct = True

    def wait_until(futures):
        # rclpy 7.1's executor can miss a wake-up: spin in bounded steps.
        give_up = min(deadline, time.monotonic() + CALL_TIMEOUT_S)
        while not all(f.done() for f in futures) and time.monotonic() < give_up:
            rclpy.spin_once(node, timeout_sec=0.1)

    def call_round(r, which):
        nonlocal correct
        asked = {i: request_for(srv, r, i) for i in which}
        futures = {i: clients[i].call_async(asked[i][0]) for i in which}
        wait_until(list(futures.values()))
        for i, f in futures.items():
            ok = f.done() and f.result() is not None and asked[i][1](f.result())
            outcomes[i].append(ok)
            if not ok:
                clients[i].remove_pending_request(f)
                correct = False

    def create(count):
        made = [node.create_client(srv, service, qos_profile=qos) for _ in range(count)]
        clients.extend(made)
        available.extend(
            c.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic())) for c in made)

    create(min(lead, n))
    if lead and all(available):
        call_round(1, range(len(clients)))
    create(n - len(clients))
    correct = correct and all(available)
    for r in range(1, calls + 1):
        if time.monotonic() >= deadline or not all(available):
            break
        call_round(r, [i for i in range(n) if len(outcomes[i]) < r])
    first = [bool(o) and o[0] for o in outcomes]
    replies = [sum(o) for o in outcomes]
    for i in range(n):
        print(json.dumps({"client": i, "available": available[i],
                          "first_reply": first[i], "replies": replies[i]}), flush=True)
    complete = correct and all(available) and all(x == calls for x in replies)
    print(json.dumps({"summary": True, "clients": n, "first_replies": sum(first),
                      "replies": sum(replies), "complete": complete}), flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0 if complete else 3


if __name__ == "__main__":
    sys.exit(main())
