"""A real ROS 2 Jazzy process (rclpy on the RMW that RMW_IMPLEMENTATION names) serving or calling
the action test_msgs/action/Fibonacci, as rclpy's own action tests and the action tutorials write
them.

server ACTION PERIOD
    An rclpy ActionServer on ACTION: rejects orders above 40, accepts every cancel request;
    each step (one feedback) takes PERIOD seconds; a goal asked to cancel ends CANCELED with the
    sequence so far. Two goals run at once (MultiThreadedExecutor). Prints {"ready": true} once
    created, then runs until killed.

client ACTION SCENARIO TIMEOUT
    An rclpy ActionClient on ACTION. Prints one JSON line per event, then {"done": true, "ok": ..}:
    - accept: order 10; every feedback ({"feedback": seq}), then {"status": s, "result": seq}
    - reject: order 41; {"accepted": false}
    - cancel: order 20; after the first feedback, cancels ({"cancel": return_code, "canceling":
      n}), then the result
    - two: two goals of orders 5 and 7 sent together; both results ({"goal": i, ...})

usage: jazzy_fibonacci.py server ACTION PERIOD | client ACTION SCENARIO TIMEOUT
"""

import json
import sys
import threading
import time

import rclpy
from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
from rclpy.executors import MultiThreadedExecutor
from test_msgs.action import Fibonacci


def say(**fields):
    print(json.dumps(fields), flush=True)


def serve(action, period):
    rclpy.init()
    node = rclpy.create_node("jazzy_fibonacci_server")

    def on_goal(request):
        return GoalResponse.REJECT if request.order > 40 else GoalResponse.ACCEPT

    def execute(handle):
        sequence = [0, 1]
        for i in range(1, max(handle.request.order, 1)):
            if handle.is_cancel_requested:
                handle.canceled()
                return Fibonacci.Result(sequence=sequence)
            sequence.append(sequence[i] + sequence[i - 1])
            handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
            time.sleep(period)
        handle.succeed()
        return Fibonacci.Result(sequence=sequence)

    ActionServer(node, Fibonacci, action, execute_callback=execute, goal_callback=on_goal,
                 cancel_callback=lambda _: CancelResponse.ACCEPT)
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    say(ready=True)
    executor.spin()


def wait(node, future, deadline):
    while not future.done() and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    return future.result() if future.done() else None


def call(action, scenario, timeout):
    deadline = time.monotonic() + timeout
    rclpy.init()
    node = rclpy.create_node("jazzy_fibonacci_client")
    client = ActionClient(node, Fibonacci, action)
    if not client.wait_for_server(timeout_sec=timeout):
        say(done=True, ok=False, why="no server")
        return 3
    ok = True
    if scenario in ("accept", "reject", "cancel"):
        order = {"accept": 10, "reject": 41, "cancel": 20}[scenario]
        first = threading.Event()

        def feedback(msg):
            say(feedback=list(msg.feedback.sequence))
            first.set()

        handle = wait(node, client.send_goal_async(Fibonacci.Goal(order=order),
                                                   feedback_callback=feedback), deadline)
        if handle is None or not handle.accepted:
            say(accepted=False)
            ok = scenario == "reject"
        else:
            say(accepted=True, stamp=[handle.stamp.sec, handle.stamp.nanosec])
            if scenario == "cancel":
                while not first.is_set() and time.monotonic() < deadline:
                    rclpy.spin_once(node, timeout_sec=0.1)
                response = wait(node, handle.cancel_goal_async(), deadline)
                say(cancel=response.return_code if response else None,
                    canceling=len(response.goals_canceling) if response else None)
            result = wait(node, handle.get_result_async(), deadline)
            if result is None:
                ok = False
            else:
                say(status=result.status, result=list(result.result.sequence))
    elif scenario == "two":
        futures = [client.send_goal_async(Fibonacci.Goal(order=o)) for o in (5, 7)]
        handles = [wait(node, f, deadline) for f in futures]
        if not all(h is not None and h.accepted for h in handles):
            ok = False
        else:
            say(ids_differ=bytes(handles[0].goal_id.uuid) != bytes(handles[1].goal_id.uuid))
            results = [h.get_result_async() for h in handles]
            for i, f in enumerate(results):
                r = wait(node, f, deadline)
                if r is None:
                    ok = False
                else:
                    say(goal=i, status=r.status, result=list(r.result.sequence))
    say(done=True, ok=ok)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0 if ok else 3


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "server":
        return serve(sys.argv[2], float(sys.argv[3]))
    if len(sys.argv) == 5 and sys.argv[1] == "client":
        return call(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    print(__doc__.strip().splitlines()[-1], file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
