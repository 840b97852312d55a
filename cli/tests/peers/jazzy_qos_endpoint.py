"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp, Fast DDS) with one publisher or one
subscription of std_msgs/msg/String of the given QoS, for the CLI's `graph check` tests.

ROLE is `pub` or `sub`; RELIABILITY `reliable` or `best_effort`; DURABILITY `volatile` or
`transient_local` (depth 10, the other policies rclpy's defaults). Once the endpoint exists it
prints one JSON line {"node": "/NODE", "topic": TOPIC, "pid": PID}, then spins until LINGER
seconds have passed, stdin closes, or it is signalled.

usage: jazzy_qos_endpoint.py DOMAIN NODE TOPIC ROLE RELIABILITY DURABILITY LINGER
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import json
import os
import sys
import threading
import time


def main() -> int:
    domain, node_name, topic, role, reliability, durability, linger = sys.argv[1:8]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    qos = QoSProfile(
        depth=10,
        reliability={"reliable": ReliabilityPolicy.RELIABLE,
                     "best_effort": ReliabilityPolicy.BEST_EFFORT}[reliability],
        durability={"volatile": DurabilityPolicy.VOLATILE,
                    "transient_local": DurabilityPolicy.TRANSIENT_LOCAL}[durability],
    )
    rclpy.init()
    node = rclpy.create_node(node_name)
    if role == "pub":
        endpoint = node.create_publisher(String, topic, qos)
    else:
        endpoint = node.create_subscription(String, topic, lambda _msg: None, qos)
    print(json.dumps({"node": node.get_fully_qualified_name(), "topic": endpoint.topic_name,
                      "pid": os.getpid()}), flush=True)

    stdin_closed = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stdin_closed.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    deadline = time.monotonic() + float(linger)
    while rclpy.ok() and time.monotonic() < deadline and not stdin_closed.is_set():
        rclpy.spin_once(node, timeout_sec=0.1)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
