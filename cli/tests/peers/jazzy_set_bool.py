"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp, Fast DDS) for the CLI's tests.

It serves std_srvs/srv/SetBool on SERVICE (answering `success = data`, message "set" or "unset")
from a node named NODE. With `--client`, the same node also calls SERVICE every 0.2 s (a new call
once the last one was answered). With `--introspection contents`, service introspection is on
with contents for the server and the client (`configure_introspection`), so their service events
are published on SERVICE/_service_event.

Once serving, it prints one JSON line on stdout:
  {"node": "/NAMESPACE/NODE", "service": SERVICE, "pid": PID}
then runs until LINGER seconds have passed, stdin closes, or it is signalled. The loop wakes on its
own every 0.1 s (rclpy 7.1's executor can miss a shutdown signal otherwise).

usage: jazzy_set_bool.py DOMAIN NODE SERVICE LINGER [--namespace NS] [--client]
                         [--introspection off|metadata|contents]
The domain goes to ROS_DOMAIN_ID before rclpy starts (the environment wins otherwise).
"""

import argparse
import json
import os
import sys
import time

from jazzy_linger import spin_until_done


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("domain", type=int)
    parser.add_argument("node")
    parser.add_argument("service")
    parser.add_argument("linger", type=float)
    parser.add_argument("--namespace", default="/")
    parser.add_argument("--client", action="store_true")
    parser.add_argument("--introspection", default="off", choices=["off", "metadata", "contents"])
    args = parser.parse_args()
    os.environ["ROS_DOMAIN_ID"] = str(args.domain)

    import rclpy
    from rclpy.qos import qos_profile_system_default
    from rclpy.service_introspection import ServiceIntrospectionState
    from std_srvs.srv import SetBool

    rclpy.init()
    node = rclpy.create_node(args.node, namespace=args.namespace)

    def handle(request, response):
        response.success = request.data
        response.message = "set" if request.data else "unset"
        return response

    server = node.create_service(SetBool, args.service, handle)
    client = node.create_client(SetBool, args.service) if args.client else None
    state = {
        "off": ServiceIntrospectionState.OFF,
        "metadata": ServiceIntrospectionState.METADATA,
        "contents": ServiceIntrospectionState.CONTENTS,
    }[args.introspection]
    if state != ServiceIntrospectionState.OFF:
        clock = node.get_clock()
        server.configure_introspection(clock, qos_profile_system_default, state)
        if client is not None:
            client.configure_introspection(clock, qos_profile_system_default, state)

    print(json.dumps({"node": node.get_fully_qualified_name(), "service": args.service,
                      "pid": os.getpid()}), flush=True)

    pending = [None]
    next_call = [time.monotonic()]
    flip = [False]

    def call_now_and_then():
        if client is not None and (pending[0] is None or pending[0].done()):
            now = time.monotonic()
            if now >= next_call[0] and client.service_is_ready():
                flip[0] = not flip[0]
                pending[0] = client.call_async(SetBool.Request(data=flip[0]))
                next_call[0] = now + 0.2

    spin_until_done(rclpy, node, args.linger, after_each=call_now_and_then)
    return 0


if __name__ == "__main__":
    sys.exit(main())
