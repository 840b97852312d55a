"""What the CLI tests' rclpy peers share: spinning their node until LINGER seconds have passed,
the test closes their stdin (or dies), or rclpy is shut down (a signal); then the node is
destroyed and rclpy shut down. Imported by the peers beside it (a script's own folder is on
Python's path).
"""

import sys
import threading
import time


def spin_until_done(rclpy, node, linger, period=0.1, after_each=None):
    """Spins `node` once per `period` seconds at most, calling `after_each()` after each spin."""
    stdin_closed = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stdin_closed.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    deadline = time.monotonic() + float(linger)
    while rclpy.ok() and time.monotonic() < deadline and not stdin_closed.is_set():
        rclpy.spin_once(node, timeout_sec=period)
        if after_each is not None:
            after_each()
    node.destroy_node()
    rclpy.try_shutdown()
