"""An rclpy node (the ROS 2 Jazzy wheels) for tests/jazzy.rs: takes one message of a topic and
makes one service call, printing what it got as JSON lines:

  {"ready": true} once its subscription and client exist;
  {"heard": MESSAGE} for the first message of the topic;
  {"reply": RESPONSE} or {"no_reply": true} (none within timeout_s of the call).

Messages are printed field by field: numbers, strings, lists (arrays and sequences), a `byte` as
its number, a nested message as an object; a message with no field as rosidl's placeholder
member {"structure_needs_at_least_one_member": 0}, as the Rust types have it.

usage: jazzy_test_msgs.py SPEC_JSON with SPEC {"domain", "topic", "topic_type", "service",
"service_type", "request", "wait_s", "timeout_s"}. It exits when both are done (or wait_s has
passed); status 0 iff it heard a message and got a reply.
"""

import importlib
import json
import sys
import time

import rclpy
from rclpy.qos import QoSProfile


def emit(key, value):
    print(json.dumps({key: value}, sort_keys=True), flush=True)


def ros_type(name):
    package, kind, leaf = name.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), leaf)


def plain(value):
    if hasattr(value, 'get_fields_and_field_types'):
        fields = value.get_fields_and_field_types()
        if not fields:
            return {'structure_needs_at_least_one_member': 0}
        return {f: plain(getattr(value, f)) for f in fields}
    if isinstance(value, bytes) and len(value) == 1:
        return value[0]
    if hasattr(value, 'tolist'):  # numpy arrays and scalars, array.array
        return plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


def fill(message, fields):
    types = message.get_fields_and_field_types()
    for field, value in fields.items():
        if types[field] == 'octet':
            value = bytes([value])
        setattr(message, field, value)
    return message


def main():
    spec = json.loads(sys.argv[1])
    rclpy.init(args=[sys.argv[0], '--ros-args', '--disable-external-lib-logs'],
               domain_id=spec['domain'])
    node = rclpy.create_node('rclpy_test_msgs')
    heard = []
    node.create_subscription(ros_type(spec['topic_type']), spec['topic'],
                             lambda m: heard.append(m), QoSProfile(depth=10))
    service_type = ros_type(spec['service_type'])
    client = node.create_client(service_type, spec['service'])
    emit('ready', True)
    deadline = time.monotonic() + spec.get('wait_s', 30)
    future = None
    called_at = None
    replied = None  # True: a reply; False: none within timeout_s
    printed = False
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
        if heard and not printed:
            emit('heard', plain(heard[0]))
            printed = True
        if future is None and client.service_is_ready():
            future = client.call_async(fill(service_type.Request(), spec['request']))
            called_at = time.monotonic()
        elif future is not None and replied is None:
            if future.done():
                emit('reply', plain(future.result()))
                replied = True
            elif time.monotonic() - called_at > spec.get('timeout_s', 5):
                emit('no_reply', True)
                replied = False
        if printed and replied is not None:
            break
    node.destroy_node()
    rclpy.try_shutdown()
    sys.exit(0 if printed and replied is True else 1)


if __name__ == '__main__':
    main()
