"""A real ROS 2 Jazzy node (rclpy on rmw_fastrtps_cpp, Fast DDS) with parameters, for the CLI's
`param` tests.

The node NODE declares (besides rclpy's own `use_sim_time`):
  flag: true                      (bool)
  count: 5                        (integer, range 0..100 step 5, with a description)
  ratio: 0.25                     (double, range -1.0..1.0)
  name: "hello world"             (string)
  quoted: "true"                  (string that YAML would read as a bool)
  flags: [true, false]            (bool array)
  numbers: [1, 2, 3]              (integer array)
  doubles: [1.5, -2.0, 1e-05]     (double array)
  words: ["a", "b c", "5"]        (string array)
  nested.depth: 2                 (integer)
  nested.deeper.label: "x"        (string)
  fixed: 7                        (integer, read-only)
  dynamic: "any"                  (string, dynamically typed: deletable)
With --allow-undeclared, the node allows undeclared parameters.

Once serving, it prints one JSON line on stdout:
  {"node": "/NAMESPACE/NODE", "pid": PID}
then runs until LINGER seconds have passed, stdin closes, or it is signalled.

usage: jazzy_param_node.py DOMAIN NODE LINGER [--allow-undeclared]
The domain goes to ROS_DOMAIN_ID before rclpy starts (the environment wins otherwise).
"""

import argparse
import json
import os
import sys

from jazzy_linger import spin_until_done


def declare_parameters(node) -> None:
    """Declares the parameters this docstring lists on `node` (also used by
    jazzy_live_graph.py)."""
    from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor

    node.declare_parameter("flag", True)
    node.declare_parameter("count", 5, ParameterDescriptor(
        description="how many", integer_range=[IntegerRange(from_value=0, to_value=100, step=5)]))
    node.declare_parameter("ratio", 0.25, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=-1.0, to_value=1.0, step=0.0)]))
    node.declare_parameter("name", "hello world")
    node.declare_parameter("quoted", "true")
    node.declare_parameter("flags", [True, False])
    node.declare_parameter("numbers", [1, 2, 3])
    node.declare_parameter("doubles", [1.5, -2.0, 1e-05])
    node.declare_parameter("words", ["a", "b c", "5"])
    node.declare_parameter("nested.depth", 2)
    node.declare_parameter("nested.deeper.label", "x")
    node.declare_parameter("fixed", 7, ParameterDescriptor(
        read_only=True, additional_constraints="never changes"))
    node.declare_parameter("dynamic", "any", ParameterDescriptor(dynamic_typing=True))


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("domain", type=int)
    parser.add_argument("node")
    parser.add_argument("linger", type=float)
    parser.add_argument("--allow-undeclared", action="store_true")
    args = parser.parse_args()
    os.environ["ROS_DOMAIN_ID"] = str(args.domain)

    import rclpy

    rclpy.init()
    node = rclpy.create_node(
        args.node, allow_undeclared_parameters=args.allow_undeclared)
    declare_parameters(node)

    print(json.dumps({"node": node.get_fully_qualified_name(), "pid": os.getpid()}), flush=True)

    spin_until_done(rclpy, node, args.linger)
    return 0


if __name__ == "__main__":
    sys.exit(main())
