"""A real ROS 2 Jazzy process (rclpy on rmw_fastrtps_cpp) with CLIENTS clients of
std_srvs/srv/SetBool on SERVICE in one node, as an application writes it: each client waits with
`wait_for_service`, then all make CALLS rounds of calls, each round's calls sent together with
`call_async` and spun until answered.

Call r of client i asks data = (r + i) % 2 == 0; the reply must say success == data.

Output: one JSON line per client when it ends ({"client", "available", "first_reply", "replies"}),
then a summary ({"summary": true, "clients", "first_replies", "complete"}). Exit status 0 iff every
client got all CALLS correct replies within TIMEOUT seconds from start; else 3.

usage: jazzy_set_bool_clients.py SERVICE CLIENTS CALLS TIMEOUT    (domain from ROS_DOMAIN_ID)
"""

import json
import sys
import time

import rclpy
from std_srvs.srv import SetBool


def main() -> int:
    if len(sys.argv) != 5:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    service, n, calls, timeout = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    deadline = time.monotonic() + timeout
    rclpy.init()
    node = rclpy.create_node("first_reply_rclpy_clients")
    clients = [node.create_client(SetBool, service) for _ in range(n)]
    available = [c.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic()))
                 for c in clients]
    replies = [0] * n
    correct = all(available)
    for r in range(1, calls + 1):
        if not correct:
            break
        asked = [(r + i) % 2 == 0 for i in range(n)]
        futures = [c.call_async(SetBool.Request(data=asked[i])) for i, c in enumerate(clients)]
        # rclpy 7.1's executor can miss a wake-up: spin in bounded steps.
        while not all(f.done() for f in futures) and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.1)
        for i, f in enumerate(futures):
            if f.done() and f.result() is not None and f.result().success == asked[i]:
                replies[i] += 1
            else:
                correct = False
    for i in range(n):
        print(json.dumps({"client": i, "available": available[i],
                          "first_reply": replies[i] > 0, "replies": replies[i]}), flush=True)
    complete = correct and all(x == calls for x in replies)
    print(json.dumps({"summary": True, "clients": n,
                      "first_replies": sum(x > 0 for x in replies), "complete": complete}),
          flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0 if complete else 3


if __name__ == "__main__":
    sys.exit(main())
