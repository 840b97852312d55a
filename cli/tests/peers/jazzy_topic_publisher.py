"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp) that publishes one message at a fixed rate,
for the CLI's `topic echo | hz | bw | delay` tests.

It fills a TYPE (`pkg/msg/Name`) message from SETTINGS (a JSON list of [dotted.path, value];
a numeric path part indexes an array), and publishes it on TOPIC at RATE Hz from a node named
NODE; with STAMP `stamp`, `header.stamp` is set to the node's clock before each publish. It
prints
  {"node": "/NODE", "topic": TOPIC, "pid": PID, "yaml": ..., "csv": ...}
where "yaml" and "csv" are what ros2topic echo prints for the message (rosidl_runtime_py jazzy
`message_to_yaml` / `message_to_csv`, whose conversion is copied below: rosidl_runtime_py is not
in the suite's venv), then runs until LINGER seconds have passed, stdin closes, or it is
signalled.

usage: jazzy_topic_publisher.py DOMAIN NODE TOPIC TYPE RATE SETTINGS STAMP LINGER
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import array
import importlib
import json
import os
import sys
import threading
import time
from collections import OrderedDict

import numpy
import yaml


def _convert_value(value):
    # rosidl_runtime_py convert.py `_convert_value` without truncation.
    if isinstance(value, bytes):
        return ''.join([chr(c) for c in value])
    if isinstance(value, (tuple, list, array.array, numpy.ndarray)):
        return [_convert_value(v) for v in value]
    if hasattr(value, 'get_fields_and_field_types'):
        return message_to_ordereddict(value)
    if isinstance(value, numpy.generic):
        return value.item()
    return value


def message_to_ordereddict(msg):
    d = OrderedDict()
    for field_name in msg.get_fields_and_field_types().keys():
        d[field_name] = _convert_value(getattr(msg, field_name))
    return d


def _represent_ordereddict(dumper, data):
    items = []
    for k, v in data.items():
        items.append((dumper.represent_data(k), dumper.represent_data(v)))
    return yaml.nodes.MappingNode(u'tag:yaml.org,2002:map', items)


yaml.add_representer(OrderedDict, _represent_ordereddict)


def message_to_yaml(msg):
    return yaml.dump(message_to_ordereddict(msg), allow_unicode=True, width=sys.maxsize,
                     default_flow_style=False)


def message_to_csv(msg):
    def to_string(val):
        r = ''
        if any(isinstance(val, t) for t in [list, tuple, array.array, numpy.ndarray]):
            for v in val:
                if r:
                    r += ','
                r += to_string(v)
        elif any(isinstance(val, t) for t in [bool, bytes, float, int, str, numpy.number]):
            r = str(val)
        else:
            r = message_to_csv(val)
        return r
    result = ''
    for field_name in msg.get_fields_and_field_types().keys():
        if result:
            result += ','
        result += to_string(getattr(msg, field_name))
    return result


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
                      "pid": os.getpid(), "yaml": message_to_yaml(msg),
                      "csv": message_to_csv(msg)}), flush=True)

    stdin_closed = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stdin_closed.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    deadline = time.monotonic() + float(linger)
    while rclpy.ok() and time.monotonic() < deadline and not stdin_closed.is_set():
        rclpy.spin_once(node, timeout_sec=0.05)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
