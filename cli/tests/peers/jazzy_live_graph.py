"""A real ROS 2 Jazzy graph in one rclpy process, on the RMW its environment chooses
(RMW_IMPLEMENTATION), for `cli/tests/cli_diff.rs`: the graph on which `horus-ros ARGS` and
`ros2 ARGS` are run and compared. Every value is fixed, so that what both tools print depends
on nothing but the graph.

Nodes (ROS_DOMAIN_ID from the environment):
  /talker                 publishes /chatter (std_msgs/msg/String "Hello World", 10 Hz),
                          /long (std_msgs/msg/String of 300 characters, 10 Hz),
                          /latched (std_msgs/msg/String "latched", TRANSIENT_LOCAL, once),
                          /best_effort (std_msgs/msg/String "best effort", BEST_EFFORT, 10 Hz)
  /robot/imu_node         publishes /robot/imu (sensor_msgs/msg/Imu, fixed values, 10 Hz)
  /strings_node           publishes /strings (test_msgs/msg/Strings, its defaults) and /arrays
                          (test_msgs/msg/Arrays: fixed arrays of each type, some values set),
                          10 Hz
  /listener               subscribes /chatter and /pub_target (std_msgs/msg/String); prints
                          {"heard": DATA} for each /pub_target message
  /param_node             the parameters of jazzy_param_node.py
  /add_two_ints_server    serves /add_two_ints (example_interfaces/srv/AddTwoInts)
  /add_two_ints_client    a client of /add_two_ints, idle
  /fibonacci_server       serves the action /fibonacci (example_interfaces/action/Fibonacci):
                          a negative order is rejected; an accepted goal publishes the sequence
                          so far after each step (STEP seconds apart) and succeeds with it
  /fibonacci_client       an action client of /fibonacci, idle
  /py_managed             an rclpy.lifecycle.LifecycleNode (unconfigured)

It prints {"ready": true} once everything is created, then one JSON reply per command read on
stdin (one JSON object a line):
  {"redeclare": NAME}          declares the parameter NAME again as jazzy_param_node.py does
                               (after a delete) -> {"done": "redeclare"}
  {"lifecycle": TRANSITION}    triggers TRANSITION (configure, cleanup, activate, deactivate,
                               shutdown) on /py_managed -> {"done": STATE LABEL}
  {"behave": {CALLBACK: "success"|"failure"}}  what /py_managed's callback returns next
                               -> {"done": "behave"}
It leaves when stdin ends (or on SIGINT / SIGTERM).

usage: jazzy_live_graph.py STEP
"""

import json
import sys
import threading


def main() -> int:
    step = float(sys.argv[1])

    import rclpy
    from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
    from rclpy.executors import MultiThreadedExecutor
    from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
    from rclpy.qos import QoSDurabilityPolicy, QoSProfile, QoSReliabilityPolicy
    from example_interfaces.action import Fibonacci
    from example_interfaces.srv import AddTwoInts
    from sensor_msgs.msg import Imu
    from std_msgs.msg import String
    from test_msgs.msg import Arrays, Strings

    from jazzy_param_node import declare_parameters

    out_lock = threading.Lock()

    def emit(obj):
        with out_lock:
            sys.stdout.write(json.dumps(obj) + "\n")
            sys.stdout.flush()

    rclpy.init()
    nodes = []

    def node(name, namespace=""):
        n = rclpy.create_node(name, namespace=namespace)
        nodes.append(n)
        return n

    talker = node("talker")
    chatter = talker.create_publisher(String, "/chatter", 10)
    long = talker.create_publisher(String, "/long", 10)
    latched = talker.create_publisher(
        String, "/latched",
        QoSProfile(depth=1, durability=QoSDurabilityPolicy.TRANSIENT_LOCAL))
    best_effort = talker.create_publisher(
        String, "/best_effort", QoSProfile(depth=10, reliability=QoSReliabilityPolicy.BEST_EFFORT))
    latched.publish(String(data="latched"))
    long_text = "".join(chr(ord("a") + i % 26) for i in range(300))

    def talk():
        chatter.publish(String(data="Hello World"))
        long.publish(String(data=long_text))
        best_effort.publish(String(data="best effort"))

    talker.create_timer(0.1, talk)

    imu_node = node("imu_node", "/robot")
    imu = imu_node.create_publisher(Imu, "imu", 10)
    imu_msg = Imu()
    imu_msg.header.stamp.sec = 1
    imu_msg.header.stamp.nanosec = 500
    imu_msg.header.frame_id = "imu_link"
    imu_msg.orientation.w = 1.0
    imu_msg.orientation_covariance[0] = 0.5
    imu_msg.angular_velocity.x = -0.25
    imu_msg.linear_acceleration.z = 9.81
    imu_node.create_timer(0.1, lambda: imu.publish(imu_msg))

    strings_node = node("strings_node")
    strings = strings_node.create_publisher(Strings, "/strings", 10)
    strings_msg = Strings()
    arrays = strings_node.create_publisher(Arrays, "/arrays", 10)
    arrays_msg = Arrays()
    arrays_msg.float32_values = [1.5, -2.25, 0.1]
    arrays_msg.float64_values = [1e-05, 1.0, 300.0]
    arrays_msg.int8_values = [-128, 0, 127]
    arrays_msg.uint8_values = [0, 7, 255]
    arrays_msg.int32_values = [1, -10, 100]
    arrays_msg.uint64_values = [0, 1, 18446744073709551615]
    arrays_msg.string_values = ["a", "b c", ""]

    def publish_strings():
        strings.publish(strings_msg)
        arrays.publish(arrays_msg)

    strings_node.create_timer(0.1, publish_strings)

    listener = node("listener")
    listener.create_subscription(String, "/chatter", lambda _m: None, 10)
    listener.create_subscription(
        String, "/pub_target", lambda m: emit({"heard": m.data}), 10)

    param_node = node("param_node")
    declare_parameters(param_node)

    server = node("add_two_ints_server")

    def add(request, response):
        response.sum = request.a + request.b
        return response

    server.create_service(AddTwoInts, "/add_two_ints", add)
    client = node("add_two_ints_client")
    client.create_client(AddTwoInts, "/add_two_ints")

    fibonacci_server = node("fibonacci_server")
    stop = threading.Event()

    def execute(goal_handle):
        sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            # Woken early by the end of the run; never a busy wait.
            stop.wait(step)
            sequence.append(sequence[i] + sequence[i - 1])
            goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
        goal_handle.succeed()
        return Fibonacci.Result(sequence=sequence)

    action_server = ActionServer(
        fibonacci_server, Fibonacci, "/fibonacci", execute,
        goal_callback=lambda g: GoalResponse.REJECT if g.order < 0 else GoalResponse.ACCEPT,
        cancel_callback=lambda _g: CancelResponse.ACCEPT)
    fibonacci_client = node("fibonacci_client")
    action_client = ActionClient(fibonacci_client, Fibonacci, "/fibonacci")

    behaviour = {}
    results = {"success": TransitionCallbackReturn.SUCCESS,
               "failure": TransitionCallbackReturn.FAILURE}

    class Managed(LifecycleNode):
        def on_configure(self, state):
            return results[behaviour.get("on_configure", "success")]

        def on_cleanup(self, state):
            return results[behaviour.get("on_cleanup", "success")]

        def on_activate(self, state):
            return results[behaviour.get("on_activate", "success")]

        def on_deactivate(self, state):
            return results[behaviour.get("on_deactivate", "success")]

        def on_shutdown(self, state):
            return results[behaviour.get("on_shutdown", "success")]

    managed = Managed("py_managed")
    nodes.append(managed)

    executor = MultiThreadedExecutor()
    for n in nodes:
        executor.add_node(n)
    emit({"ready": True})

    def commands():
        try:
            for line in sys.stdin:
                if not line.strip():
                    continue
                command = json.loads(line)
                if "redeclare" in command:
                    name = command["redeclare"]
                    from rcl_interfaces.msg import ParameterDescriptor
                    if name == "dynamic":
                        param_node.declare_parameter(
                            "dynamic", "any", ParameterDescriptor(dynamic_typing=True))
                    else:
                        raise ValueError(f"cannot redeclare {name}")
                    emit({"done": "redeclare"})
                elif "lifecycle" in command:
                    getattr(managed, "trigger_" + command["lifecycle"])()
                    emit({"done": managed._state_machine.current_state[1]})
                elif "behave" in command:
                    behaviour.update(command["behave"])
                    emit({"done": "behave"})
                else:
                    raise ValueError(f"unknown command {command}")
        finally:
            stop.set()

    threading.Thread(target=commands, daemon=True).start()
    while rclpy.ok() and not stop.is_set():
        executor.spin_once(timeout_sec=0.1)
    action_server.destroy()
    action_client.destroy()
    for n in nodes:
        n.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
