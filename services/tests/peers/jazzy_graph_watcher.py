"""A long-lived rclpy process (a real ROS 2 Jazzy node, on the run's RMW) that watches the ROS
graph's nodes, as `ros2 node list` sees them.

Prints `ready` once its node is up, then `+ /ns/name` when a node appears and `- /ns/name` when
one disappears (its own node left out), and `+service /name` / `-service /name` for services. A
line `list` on standard input is answered with `list /a /b ...`, the nodes rclpy sees now. It
ends when its standard input closes.

rclpy offers no graph event to wait on (rclpy's own `Node.wait_for_node` polls the graph every
0.1 s, ros2/rclpy#929), so the graph is read again after each `spin_once` of at most 20 ms: what
it reports is at most one such period late.

usage: jazzy_graph_watcher.py   (ROS_DOMAIN_ID from the environment)
"""

import sys
import threading

import rclpy
from rclpy.signals import SignalHandlerOptions

SPIN_PERIOD_S = 0.02


def main() -> None:
    # The test stops this peer by closing its standard input, never by a signal.
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node('goodbye_watcher')
    own = node.get_fully_qualified_name()
    printing = threading.Lock()
    commands = []
    stdin_closed = threading.Event()

    def say(line: str) -> None:
        with printing:
            print(line, flush=True)

    def read_commands() -> None:
        for line in sys.stdin:
            with printing:
                commands.append(line.strip())
        stdin_closed.set()

    def names() -> set:
        return {n for n in node.get_fully_qualified_node_names() if n != own}

    def services() -> set:
        return {s for s, _ in node.get_service_names_and_types() if not s.startswith(own + '/')}

    threading.Thread(target=read_commands, daemon=True).start()

    def report_changes(kind, known, now):
        """Says `+<kind> name` for each name in `now` not in `known` and `-<kind> name` for
        each gone; returns `now`."""
        for name in sorted(now - known):
            say(f'+{kind} {name}')
        for name in sorted(known - now):
            say(f'-{kind} {name}')
        return now

    known = set()
    known_services = set()
    say('ready')
    while rclpy.ok() and not stdin_closed.is_set():
        rclpy.spin_once(node, timeout_sec=SPIN_PERIOD_S)
        known = report_changes('', known, names())
        known_services = report_changes('service', known_services, services())
        with printing:
            pending, commands[:] = list(commands), []
        for command in pending:
            if command == 'list':
                say('list ' + ' '.join(sorted(known)))
    node.destroy_node()
    rclpy.shutdown()


if __name__ == '__main__':
    main()
