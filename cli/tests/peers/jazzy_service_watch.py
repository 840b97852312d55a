"""What a real ROS 2 Jazzy node (rclpy 7.1 on rmw_fastrtps_cpp, Fast DDS) sees of a service, for
the CLI's passive echo test: rclpy's graph API, polled.

Prints one JSON line at start ({"node": "/NODE", "pid": PID}), then every 0.1 s one line:
  {"services": count_services(SERVICE), "clients": count_clients(SERVICE),
   "types": [types of SERVICE in get_service_names_and_types()],
   "by_node": {"/ns/name": {"servers": [...], "clients": [...]}, ...}}
where by_node holds, for every node of the graph, the services it serves and calls
(get_service_names_and_types_by_node / get_client_names_and_types_by_node), only the non-empty
ones. Runs until LINGER seconds have passed or stdin closes.

usage: jazzy_service_watch.py DOMAIN NODE SERVICE LINGER
"""

import json
import os
import sys
import threading
import time


def main() -> int:
    domain, node_name, service = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    linger = float(sys.argv[4])
    os.environ["ROS_DOMAIN_ID"] = str(domain)
    import rclpy

    rclpy.init()
    node = rclpy.create_node(node_name)
    print(json.dumps({"node": node.get_fully_qualified_name(), "pid": os.getpid()}), flush=True)

    stdin_closed = threading.Event()

    def watch_stdin():
        try:
            sys.stdin.read()
        finally:
            stdin_closed.set()

    threading.Thread(target=watch_stdin, daemon=True).start()
    deadline = time.monotonic() + linger
    while time.monotonic() < deadline and not stdin_closed.is_set():
        types = [t for name, ts in node.get_service_names_and_types() if name == service
                 for t in ts]
        by_node = {}
        for name, ns in node.get_node_names_and_namespaces():
            try:
                servers = node.get_service_names_and_types_by_node(name, ns)
                clients = node.get_client_names_and_types_by_node(name, ns)
            except Exception:  # the node left meanwhile
                continue
            servers = sorted(n for n, _ in servers if n == service)
            clients = sorted(n for n, _ in clients if n == service)
            if servers or clients:
                fq = ns.rstrip("/") + "/" + name
                by_node[fq] = {"servers": servers, "clients": clients}
        print(json.dumps({
            "services": node.count_services(service),
            "clients": node.count_clients(service),
            "types": sorted(types),
            "by_node": by_node,
        }, sort_keys=True), flush=True)
        time.sleep(0.1)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
