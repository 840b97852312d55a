"""rclpy's own time to see a node: a fresh rclpy process (rclpy 7.1, rmw_fastrtps_cpp) that starts
a node and waits until its graph API lists node NODE and service SERVICE, for the CLI's
first-contact benchmark.

rclpy offers no graph event in Python (its own `Node.wait_for_node` checks every 100 ms, see
ros2/rclpy#929), so this checks `get_fully_qualified_node_names()` and
`get_service_names_and_types()` every millisecond, which favours rclpy.

Prints one JSON line and exits (status 0 when found, 3 after TIMEOUT seconds):
  {"found": true, "import_ms": …, "from_init_ms": …}
import_ms: importing rclpy; from_init_ms: from before `rclpy.init()` until both were listed.

usage: jazzy_graph_probe.py DOMAIN NODE SERVICE TIMEOUT
"""

import json
import os
import sys
import time


def main() -> int:
    domain, node_name, service = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    timeout = float(sys.argv[4])
    os.environ["ROS_DOMAIN_ID"] = str(domain)
    started = time.monotonic()
    import rclpy

    imported = time.monotonic()
    rclpy.init()
    node = rclpy.create_node(f"_graph_probe_{os.getpid()}")
    deadline = imported + timeout
    found = False
    while time.monotonic() < deadline:
        names = node.get_fully_qualified_node_names()
        services = [name for name, _ in node.get_service_names_and_types()]
        if node_name in names and service in services:
            found = True
            break
        time.sleep(0.001)
    seen = time.monotonic()
    print(json.dumps({
        "found": found,
        "import_ms": (imported - started) * 1e3,
        "from_init_ms": (seen - imported) * 1e3,
    }), flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0 if found else 3


if __name__ == "__main__":
    sys.exit(main())
