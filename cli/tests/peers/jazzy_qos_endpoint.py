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

from jazzy_linger import spin_until_done


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

    spin_until_done(rclpy, node, linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
