"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp) that subscribes to one message type, for
the CLI's `topic pub` tests.

It subscribes to TYPE (`pkg/msg/Name`) on TOPIC from a node named NODE (QoS: KEEP_LAST 10,
RELIABLE unless `--best-effort`, VOLATILE), prints
  {"node": "/NODE", "topic": TOPIC, "pid": PID}
then, for each message received, one line
  {"repr": repr(message), "message": {field: value, ...}}
(`repr` as rclpy prints messages, which is what `ros2 topic pub` prints of the message it sends;
`message` the fields as JSON: nested messages as objects, bytes and arrays as lists of numbers),
and runs until LINGER seconds have passed, stdin closes, or it is signalled.

usage: jazzy_subscriber.py DOMAIN NODE TOPIC TYPE LINGER [--best-effort]
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import argparse
import importlib
import json
import os
import sys

from jazzy_linger import spin_until_done


def to_json(value):
    """A message or field value as JSON."""
    if hasattr(value, "get_fields_and_field_types"):
        return {name: to_json(getattr(value, name))
                for name in value.get_fields_and_field_types()}
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, str):
        return value
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)) or type(value).__name__ == "array":
        return [to_json(v) for v in value]
    return value


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("domain")
    parser.add_argument("node")
    parser.add_argument("topic")
    parser.add_argument("type")
    parser.add_argument("linger", type=float)
    parser.add_argument("--best-effort", action="store_true")
    args = parser.parse_args()
    os.environ["ROS_DOMAIN_ID"] = args.domain

    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    package, namespace, name = args.type.split("/")
    message_type = getattr(importlib.import_module(f"{package}.{namespace}"), name)
    rclpy.init()
    node = rclpy.create_node(args.node)
    qos = QoSProfile(depth=10)
    if args.best_effort:
        qos.reliability = ReliabilityPolicy.BEST_EFFORT

    def received(message):
        print(json.dumps({"repr": repr(message), "message": to_json(message)}), flush=True)

    node.create_subscription(message_type, args.topic, received, qos)
    print(json.dumps({"node": node.get_fully_qualified_name(), "topic": args.topic,
                      "pid": os.getpid()}), flush=True)

    spin_until_done(rclpy, node, args.linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
