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
import time

from jazzy_linger import spin_until_done


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

    next_publish = [time.monotonic()]

    def publish_now_and_then():
        if time.monotonic() >= next_publish[0]:
            publisher.publish(message_type())
            next_publish[0] = time.monotonic() + 0.5

    spin_until_done(rclpy, node, linger, after_each=publish_now_and_then)
    return 0


if __name__ == "__main__":
    sys.exit(main())
