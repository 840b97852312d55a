"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp) that publishes one message type, for the
CLI's `interface show --from-graph` tests: rclpy nodes serve ~/get_type_description, and their
publishers announce the type's hash.

It publishes a default TYPE (`pkg/msg/Name`) on TOPIC every 0.5 s from a node named NODE, prints
  {"node": "/NODE", "topic": TOPIC, "pid": PID}
then runs until LINGER seconds have passed, stdin closes, or it is signalled.

usage: jazzy_publisher.py DOMAIN NODE TOPIC TYPE LINGER
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import importlib
import json
import os
import sys
import threading
import time


def main() -> int:
    domain, node_name, topic, type_name, linger = sys.argv[1:6]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy

    package, namespace, name = type_name.split("/")
    message_type = getattr(importlib.import_module(f"{package}.{namespace}"), name)
    rclpy.init()
    node = rclpy.create_node(node_name)
    publisher = node.create_publisher(message_type, topic, 10)
    print(json.dumps({"node": node.get_fully_qualified_name(), "topic": topic,
                      "pid": os.getpid()}), flush=True)

    stdin_closed = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stdin_closed.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    deadline = time.monotonic() + float(linger)
    next_publish = time.monotonic()
    while rclpy.ok() and time.monotonic() < deadline and not stdin_closed.is_set():
        rclpy.spin_once(node, timeout_sec=0.1)
        if time.monotonic() >= next_publish:
            publisher.publish(message_type())
            next_publish = time.monotonic() + 0.5
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
