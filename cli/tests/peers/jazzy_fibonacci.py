"""Real ROS 2 Jazzy action endpoints (rclpy on rmw_fastrtps_cpp) of test_msgs' Fibonacci, for
the CLI's `action` tests.

server: an rclpy ActionServer on ACTION from a node named NODE. A goal with a negative order is
  rejected; an accepted one builds the sequence from [0, 1], publishing the sequence so far as
  feedback after each step (STEP seconds apart), and succeeds with it. A cancel request is
  accepted; a goal canceled mid-way prints {"canceled": true} and ends canceled.
client: an rclpy ActionClient of ACTION from a node named NODE, idle.
Either prints {"node": "/NODE", "pid": PID} first, then runs until LINGER seconds have passed,
stdin closes, or it is signalled.

usage: jazzy_fibonacci.py DOMAIN server|client NODE ACTION STEP LINGER
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import json
import os
import sys
import threading
import time


def main() -> int:
    domain, role, node_name, action, step, linger = sys.argv[1:7]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy
    from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
    from rclpy.executors import MultiThreadedExecutor
    from test_msgs.action import Fibonacci

    rclpy.init()
    node = rclpy.create_node(node_name)
    step = float(step)
    stop = threading.Event()

    def goal_callback(goal_request):
        return GoalResponse.REJECT if goal_request.order < 0 else GoalResponse.ACCEPT

    def cancel_callback(_goal_handle):
        return CancelResponse.ACCEPT

    def execute_callback(goal_handle):
        sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            # Woken early by a cancel request or the end of the run; never a busy wait.
            stop.wait(step)
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                print(json.dumps({"canceled": True}), flush=True)
                return Fibonacci.Result(sequence=sequence)
            sequence.append(sequence[i] + sequence[i - 1])
            goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
        goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)

    if role == "server":
        endpoint = ActionServer(node, Fibonacci, action, execute_callback,
                                goal_callback=goal_callback, cancel_callback=cancel_callback)
    else:
        endpoint = ActionClient(node, Fibonacci, action)
    print(json.dumps({"node": node.get_fully_qualified_name(), "pid": os.getpid()}),
          flush=True)

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stop.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    executor = MultiThreadedExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + float(linger)
    while rclpy.ok() and time.monotonic() < deadline and not stop.is_set():
        executor.spin_once(timeout_sec=0.1)
    stop.set()
    endpoint.destroy()
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
