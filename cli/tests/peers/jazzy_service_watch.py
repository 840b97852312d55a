"""What a real ROS 2 Jazzy node (rclpy 7.1 on rmw_fastrtps_cpp, Fast DDS) sees of a service, for
the CLI's passive echo test: rclpy's graph API, read each time the graph changes.

Prints one JSON line at start ({"node": "/NODE", "pid": PID}), then one report at start, one
each time the node's graph changes (rcl's graph guard condition of the node, which rmw triggers
on every discovery change) and one for each line read on stdin (a request):
  {"request": LINE or null, "services": count_services(SERVICE),
   "clients": count_clients(SERVICE),
   "types": [types of SERVICE in get_service_names_and_types()],
   "by_node": {"/ns/name": {"servers": [...], "clients": [...]}, ...}}
where request is the stdin line a report answers (null for the start and graph changes), and
by_node holds, for every node of the graph, the services it serves and calls
(get_service_names_and_types_by_node / get_client_names_and_types_by_node), only the non-empty
ones. Runs until LINGER seconds have passed or stdin closes.

rclpy 7.1 offers no wait on graph changes (its Node.wait_for_node polls, ros2/rclpy#929), so the
graph guard condition (rcl/node.h, rcl_node_get_graph_guard_condition) is waited on with rcl's
wait set (rcl/wait.h) through ctypes, beside an rclpy guard condition that the stdin reader
triggers.

usage: jazzy_service_watch.py DOMAIN NODE SERVICE LINGER
"""

import ctypes
import json
import os
import queue
import sys
import threading
import time


class WaitSet(ctypes.Structure):
    """rcl_wait_set_t (rcl/wait.h, Jazzy)."""

    _fields_ = [
        ("subscriptions", ctypes.c_void_p), ("size_of_subscriptions", ctypes.c_size_t),
        ("guard_conditions", ctypes.POINTER(ctypes.c_void_p)),
        ("size_of_guard_conditions", ctypes.c_size_t),
        ("timers", ctypes.c_void_p), ("size_of_timers", ctypes.c_size_t),
        ("clients", ctypes.c_void_p), ("size_of_clients", ctypes.c_size_t),
        ("services", ctypes.c_void_p), ("size_of_services", ctypes.c_size_t),
        ("events", ctypes.c_void_p), ("size_of_events", ctypes.c_size_t),
        ("impl", ctypes.c_void_p),
    ]


class Allocator(ctypes.Structure):
    """rcutils_allocator_t (rcutils/allocator.h)."""

    _fields_ = [
        ("allocate", ctypes.c_void_p), ("deallocate", ctypes.c_void_p),
        ("reallocate", ctypes.c_void_p), ("zero_allocate", ctypes.c_void_p),
        ("state", ctypes.c_void_p),
    ]


RCL_RET_OK = 0
RCL_RET_TIMEOUT = 2


def check(what, ret):
    if ret != RCL_RET_OK:
        raise RuntimeError(f"{what} failed: {ret}")


def main() -> int:
    domain, node_name, service = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    linger = float(sys.argv[4])
    os.environ["ROS_DOMAIN_ID"] = str(domain)
    import rclpy
    from rclpy.guard_condition import GuardCondition

    rclpy.init()
    node = rclpy.create_node(node_name)
    print(json.dumps({"node": node.get_fully_qualified_name(), "pid": os.getpid()}), flush=True)

    # The libraries rclpy loaded (same sonames, so dlopen returns them).
    rcl = ctypes.CDLL("librcl.so")
    rcutils = ctypes.CDLL("librcutils.so")
    rcl.rcl_node_get_graph_guard_condition.restype = ctypes.c_void_p
    rcl.rcl_node_get_graph_guard_condition.argtypes = [ctypes.c_void_p]
    rcl.rcl_get_zero_initialized_wait_set.restype = WaitSet
    rcutils.rcutils_get_default_allocator.restype = Allocator
    rcl.rcl_wait_set_init.argtypes = [ctypes.POINTER(WaitSet)] + [ctypes.c_size_t] * 6 + [
        ctypes.c_void_p, Allocator]
    rcl.rcl_wait_set_clear.argtypes = [ctypes.POINTER(WaitSet)]
    rcl.rcl_wait_set_add_guard_condition.argtypes = [
        ctypes.POINTER(WaitSet), ctypes.c_void_p, ctypes.c_void_p]
    rcl.rcl_wait.argtypes = [ctypes.POINTER(WaitSet), ctypes.c_int64]
    rcl.rcl_wait_set_fini.argtypes = [ctypes.POINTER(WaitSet)]

    graph = rcl.rcl_node_get_graph_guard_condition(node.handle.pointer)
    if not graph:
        raise RuntimeError("rcl_node_get_graph_guard_condition failed")
    wake = GuardCondition(None, None, context=node.context)
    wait_set = rcl.rcl_get_zero_initialized_wait_set()
    check("rcl_wait_set_init", rcl.rcl_wait_set_init(
        ctypes.byref(wait_set), 0, 2, 0, 0, 0, 0, node.context.handle.pointer,
        rcutils.rcutils_get_default_allocator()))

    # Requests (stdin lines); None once stdin closed. Each one triggers `wake`.
    requests = queue.Queue()

    def read_stdin():
        try:
            for line in sys.stdin:
                requests.put(line.strip())
                wake.trigger()
        finally:
            requests.put(None)
            wake.trigger()

    threading.Thread(target=read_stdin, daemon=True).start()

    def report(request):
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
            "request": request,
            "services": node.count_services(service),
            "clients": node.count_clients(service),
            "types": sorted(types),
            "by_node": by_node,
        }, sort_keys=True), flush=True)

    report(None)
    deadline = time.monotonic() + linger
    stdin_open = True
    while stdin_open:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        check("rcl_wait_set_clear", rcl.rcl_wait_set_clear(ctypes.byref(wait_set)))
        check("rcl_wait_set_add_guard_condition", rcl.rcl_wait_set_add_guard_condition(
            ctypes.byref(wait_set), graph, None))
        check("rcl_wait_set_add_guard_condition", rcl.rcl_wait_set_add_guard_condition(
            ctypes.byref(wait_set), wake.handle.pointer, None))
        ret = rcl.rcl_wait(ctypes.byref(wait_set), int(left * 1e9))
        if ret == RCL_RET_TIMEOUT:
            break
        check("rcl_wait", ret)
        # A woken guard condition keeps its slot; the others are set to NULL.
        if wait_set.guard_conditions[0]:
            report(None)
        while True:
            try:
                request = requests.get_nowait()
            except queue.Empty:
                break
            if request is None:
                stdin_open = False
                break
            report(request)
    check("rcl_wait_set_fini", rcl.rcl_wait_set_fini(ctypes.byref(wait_set)))
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
