"""A real ROS 2 Jazzy process (rclpy 7.1 on the RMW that RMW_IMPLEMENTATION names:
rmw_fastrtps_cpp / Fast DDS 2.14 or rmw_cyclonedds_cpp, as scripts/setup installs them) for the
lifecycle tests: an rclpy.lifecycle node, a lifecycle client using lifecycle_msgs' services as
ros2lifecycle's api does, or both.

usage: jazzy_lifecycle.py SPEC_JSON, with SPEC
  {"domain": 7, "name": "peer",
   "lifecycle": true,           # make `name` an rclpy.lifecycle.LifecycleNode
   "watch": ["/managed"]}       # subscribe to NODE/transition_event for each (RELIABLE,
                                # VOLATILE, KEEP_LAST 10: rcl_lifecycle's publisher QoS)

It prints one JSON object a line on stdout:
- {"ready": {"node": "/peer"}} once everything is created;
- {"event": {"node", "timestamp", "transition": [id, label], "start": [id, label],
  "goal": [id, label]}} per transition event taken;
- {"callback": {"name": "on_configure", "previous": [id, label], "returned": "success"}} per
  callback of its own lifecycle node;
- {"reply": ...} once per command read on stdin (one JSON object a line):
    {"behave": {"on_configure": "failure", ...}}  what its callbacks return next
        ("success", "failure", "error", "raise"; default "success") -> {"reply": "ok"}
    {"call": "get_state", "node": "/x"}  -> {"reply": [id, label]}
    {"call": "change_state", "node": "/x", "id": 1, "label": ""} -> {"reply": success}
    {"call": "get_available_states", "node": "/x"} -> {"reply": [[id, label], ...]}
    {"call": "get_available_transitions" | "get_transition_graph", "node": "/x"}
        -> {"reply": [{"transition": [id, label], "start": [...], "goal": [...]}, ...]}
  A call not answered within 10 s replies {"reply": {"timeout": true}}; a service not ready
  within 20 s {"reply": {"unavailable": true}}.
It leaves when stdin ends (or on SIGINT / SIGTERM).
"""

import json
import os
import sys
import threading


def main() -> int:
    spec = json.loads(sys.argv[1])
    os.environ["ROS_DOMAIN_ID"] = str(spec["domain"])

    import rclpy
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
    from rclpy.node import Node
    from rclpy.qos import QoSProfile
    from lifecycle_msgs.msg import TransitionEvent
    from lifecycle_msgs.srv import ChangeState, GetAvailableStates, GetAvailableTransitions
    from lifecycle_msgs.srv import GetState

    out_lock = threading.Lock()

    def emit(obj):
        with out_lock:
            sys.stdout.write(json.dumps(obj) + "\n")
            sys.stdout.flush()

    behaviour = {}
    results = {
        "success": TransitionCallbackReturn.SUCCESS,
        "failure": TransitionCallbackReturn.FAILURE,
        "error": TransitionCallbackReturn.ERROR,
    }

    def run_callback(name, state):
        returned = behaviour.get(name, "success")
        emit({"callback": {"name": name, "previous": [state.state_id, state.label],
                           "returned": returned}})
        if returned == "raise":
            raise RuntimeError(f"{name} raised on purpose")
        return results[returned]

    class Managed(LifecycleNode):
        def on_configure(self, state):
            return run_callback("on_configure", state)

        def on_cleanup(self, state):
            return run_callback("on_cleanup", state)

        def on_shutdown(self, state):
            return run_callback("on_shutdown", state)

        def on_activate(self, state):
            super().on_activate(state)
            return run_callback("on_activate", state)

        def on_deactivate(self, state):
            super().on_deactivate(state)
            return run_callback("on_deactivate", state)

        def on_error(self, state):
            return run_callback("on_error", state)

    rclpy.init()
    if spec.get("lifecycle"):
        node = Managed(spec["name"])
    else:
        node = Node(spec["name"])

    def on_event(watched):
        def take(msg):
            emit({"event": {
                "node": watched, "timestamp": msg.timestamp,
                "transition": [msg.transition.id, msg.transition.label],
                "start": [msg.start_state.id, msg.start_state.label],
                "goal": [msg.goal_state.id, msg.goal_state.label]}})
        return take

    qos = QoSProfile(depth=10)
    for watched in spec.get("watch", []):
        node.create_subscription(
            TransitionEvent, f"{watched}/transition_event", on_event(watched), qos)

    executor = MultiThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    emit({"ready": {"node": node.get_fully_qualified_name()}})

    clients = {}
    kinds = {
        "get_state": GetState,
        "change_state": ChangeState,
        "get_available_states": GetAvailableStates,
        "get_available_transitions": GetAvailableTransitions,
        "get_transition_graph": GetAvailableTransitions,
    }

    def state(s):
        return [s.id, s.label]

    def description(d):
        return {"transition": [d.transition.id, d.transition.label],
                "start": state(d.start_state), "goal": state(d.goal_state)}

    def call(command):
        kind = command["call"]
        key = (command["node"], kind)
        if key not in clients:
            clients[key] = node.create_client(kinds[kind], f"{command['node']}/{kind}")
        client = clients[key]
        if not client.wait_for_service(timeout_sec=20.0):
            return {"unavailable": True}
        request = kinds[kind].Request()
        if kind == "change_state":
            request.transition.id = command.get("id", 0)
            request.transition.label = command.get("label", "")
        response = client.call(request, timeout_sec=10.0)
        if response is None:
            return {"timeout": True}
        if kind == "get_state":
            return state(response.current_state)
        if kind == "change_state":
            return response.success
        if kind == "get_available_states":
            return [state(s) for s in response.available_states]
        return [description(d) for d in response.available_transitions]

    try:
        for line in sys.stdin:
            if not line.strip():
                continue
            command = json.loads(line)
            if "behave" in command:
                behaviour.update(command["behave"])
                emit({"reply": "ok"})
            elif "call" in command:
                emit({"reply": call(command)})
    except KeyboardInterrupt:
        pass
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
