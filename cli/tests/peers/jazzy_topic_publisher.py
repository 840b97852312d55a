"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp) that publishes one message at a fixed rate,
for the CLI's `topic echo | hz | bw | delay` tests.

It fills a TYPE (`pkg/msg/Name`) message from SETTINGS (a JSON list of [dotted.path, value];
a numeric path part indexes an array), and publishes it on TOPIC at RATE Hz from a node named
NODE; with STAMP `stamp`, `header.stamp` is set to the node's clock before each publish. It
prints
  {"node": "/NODE", "topic": TOPIC, "pid": PID}
then runs until LINGER seconds have passed, stdin closes, or it is signalled.

usage: jazzy_topic_publisher.py DOMAIN NODE TOPIC TYPE RATE SETTINGS STAMP LINGER
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import importlib
import json
import os
import sys

from jazzy_linger import spin_until_done


def set_path(msg, path, value):
    parts = path.split('.')
    target = msg
    for p in parts[:-1]:
        target = target[int(p)] if p.isdigit() else getattr(target, p)
    last = parts[-1]
    if last.isdigit():
        target[int(last)] = value
    else:
        setattr(target, last, value)


def main() -> int:
    domain, node_name, topic, type_name, rate, settings, stamp, linger = sys.argv[1:9]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy

    package, namespace, name = type_name.split("/")
    message_type = getattr(importlib.import_module(f"{package}.{namespace}"), name)
    msg = message_type()
    for path, value in json.loads(settings):
        set_path(msg, path, value)
    rclpy.init()
    node = rclpy.create_node(node_name)
    publisher = node.create_publisher(message_type, topic, 10)
    count = [0]

    def publish():
        if stamp == "stamp":
            msg.header.stamp = node.get_clock().now().to_msg()
        publisher.publish(msg)
        count[0] += 1

    node.create_timer(1.0 / float(rate), publish)
    print(json.dumps({"node": node.get_fully_qualified_name(), "topic": topic,
                      "pid": os.getpid()}), flush=True)

    spin_until_done(rclpy, node, linger, period=0.05)
    return 0


if __name__ == "__main__":
    sys.exit(main())
