"""ros2lifecycle's output without ros2cli: the `main` bodies of ros2lifecycle 0.32 (Jazzy,
ros2/ros2cli branch `jazzy`, `ros2lifecycle/ros2lifecycle/verb/{nodes,list,get,set}.py` and
`ros2lifecycle/api/__init__.py`, with ros2node's `get_node_names` / `get_absolute_node_name` and
ros2service's `get_service_names_and_types`), transcribed with rclpy (the suite's Jazzy wheels)
in place of ros2cli's NodeStrategy and DirectNode, so that the CLI tests compare
`horus-ros lifecycle …` with what ros2lifecycle prints.

Before the verb runs, the reference waits (at most 20 s, rclpy having no graph event) until
every node given with --wait-for offers its `get_state` service, as a settled graph would.

usage: jazzy_ros2lifecycle_reference.py DOMAIN [--wait-for NODE]… VERB ARGS…
The domain goes to ROS_DOMAIN_ID before rclpy starts. A string returned by a verb is printed on
stderr with exit status 1 (as `sys.exit(main())` does); a number is the exit status.
"""

import argparse
import os
import sys
import time


def main():
    domain = sys.argv[1]
    rest = sys.argv[2:]
    wait_for = []
    while rest[:1] == ["--wait-for"]:
        wait_for.append(rest[1])
        rest = rest[2:]
    verb, rest = rest[0], rest[1:]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy
    from lifecycle_msgs.srv import ChangeState, GetAvailableTransitions, GetState
    from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden

    parser = argparse.ArgumentParser()
    if verb == "nodes":
        parser.add_argument('-a', '--all', action='store_true')
        parser.add_argument('-c', '--count-nodes', action='store_true')
    if verb == "list":
        parser.add_argument('node_name')
        parser.add_argument('--include-hidden-nodes', action='store_true')
        parser.add_argument('-a', '--all', action='store_true')
    if verb == "get":
        parser.add_argument('node_name', nargs='?')
        parser.add_argument('--include-hidden-nodes', action='store_true')
    if verb == "set":
        parser.add_argument('node_name')
        parser.add_argument('--include-hidden-nodes', action='store_true')
        parser.add_argument('transition')
    args = parser.parse_args(rest)

    rclpy.init()
    node = rclpy.create_node("_ros2cli_reference")

    # ros2node.api
    class NodeName:
        def __init__(self, name, namespace, full_name):
            self.name, self.namespace, self.full_name = name, namespace, full_name

    def get_all_node_names(*, node, include_hidden_nodes=False):
        return [
            NodeName(t[0], t[1], t[1] + ('' if t[1].endswith('/') else '/') + t[0])
            for t in node.get_node_names_and_namespaces()
            if include_hidden_nodes or (t[0] and not t[0].startswith('_'))]

    def get_absolute_node_name(node_name):
        if not node_name:
            return None
        if node_name[0] != '/':
            node_name = '/' + node_name
        return node_name

    # ros2service.api
    def get_service_names_and_types(*, node, include_hidden_services=False):
        service_names_and_types = node.get_service_names_and_types()
        if not include_hidden_services:
            service_names_and_types = [
                (n, t) for (n, t) in service_names_and_types
                if not topic_or_service_is_hidden(n)]
        return service_names_and_types

    # ros2lifecycle.api
    def get_node_names(*, node, include_hidden_nodes=False):
        node_names = get_all_node_names(
            node=node, include_hidden_nodes=include_hidden_nodes)
        service_names_and_types = get_service_names_and_types(
            node=node, include_hidden_services=include_hidden_nodes)
        return [
            n for n in node_names
            if _has_lifecycle(n.full_name, service_names_and_types)]

    def _has_lifecycle(node_name, service_names_and_types):
        for (service_name, service_types) in service_names_and_types:
            if (
                service_name == f'{node_name}/get_state' and
                'lifecycle_msgs/srv/GetState' in service_types
            ):
                return True
        return False

    def call_get_states(*, node, node_names):
        clients = {}
        futures = {}
        for node_name in node_names:
            clients[node_name] = \
                node.create_client(GetState, f'{node_name}/get_state')
        while True:
            for node_name in [n for n in node_names if n not in futures]:
                client = clients[node_name]
                if client.service_is_ready():
                    request = GetState.Request()
                    future = client.call_async(request)
                    futures[node_name] = future
            if len(futures) == len(clients):
                break
            rclpy.spin_once(node, timeout_sec=1.0)
        for future in futures.values():
            rclpy.spin_until_future_complete(node, future)
        states = {}
        for node_name, future in futures.items():
            if future.result() is not None:
                response = future.result()
                states[node_name] = response.current_state
            else:
                states[node_name] = future.exception()
        return states

    def _call_get_transitions(node, states, service_name):
        clients = {}
        futures = {}
        for node_name in states.keys():
            clients[node_name] = node.create_client(
                GetAvailableTransitions, f'{node_name}/{service_name}')
        while True:
            for node_name in [n for n in states.keys() if n not in futures]:
                client = clients[node_name]
                if client.service_is_ready():
                    request = GetAvailableTransitions.Request()
                    future = client.call_async(request)
                    futures[node_name] = future
            if len(futures) == len(clients):
                break
            rclpy.spin_once(node, timeout_sec=1.0)
        for future in futures.values():
            rclpy.spin_until_future_complete(node, future)
        transitions = {}
        for node_name, future in futures.items():
            if future.result() is not None:
                response = future.result()
                transitions[node_name] = []
                for transition_description in response.available_transitions:
                    if (
                        states[node_name] is None or
                        transition_description.start_state == states[node_name]
                    ):
                        transitions[node_name].append(
                            transition_description)
            else:
                transitions[node_name] = future.exception()
        return transitions

    def call_change_states(*, node, transitions):
        clients = {}
        futures = {}
        for node_name in transitions.keys():
            clients[node_name] = node.create_client(
                ChangeState, f'{node_name}/change_state')
        while True:
            for node_name in [n for n in transitions.keys() if n not in futures]:
                client = clients[node_name]
                if client.service_is_ready():
                    request = ChangeState.Request()
                    request.transition = transitions[node_name]
                    future = client.call_async(request)
                    futures[node_name] = future
            if len(futures) == len(clients):
                break
            rclpy.spin_once(node, timeout_sec=1.0)
        for future in futures.values():
            rclpy.spin_until_future_complete(node, future)
        results = {}
        for node_name, future in futures.items():
            if future.result() is not None:
                response = future.result()
                results[node_name] = response.success
            else:
                results[node_name] = future.exception()
        return results

    # The settled graph (NodeStrategy's daemon would have it).
    deadline = time.monotonic() + 20.0
    while time.monotonic() < deadline:
        found = {n.full_name for n in get_node_names(node=node, include_hidden_nodes=True)}
        if all(w in found for w in wait_for):
            break
        rclpy.spin_once(node, timeout_sec=0.05)

    # verb/nodes.py
    def nodes_main(args):
        node_names = get_node_names(node=node, include_hidden_nodes=args.all)
        if args.count_nodes:
            print(len(node_names))
        elif node_names:
            print(*sorted({n.full_name for n in node_names}), sep='\n')

    # verb/list.py
    def list_main(args):
        node_names = get_node_names(
            node=node, include_hidden_nodes=args.include_hidden_nodes)
        node_name = get_absolute_node_name(args.node_name)
        if node_name not in {n.full_name for n in node_names}:
            return 'Node not found'
        if args.all:
            transitions = _call_get_transitions(node, {node_name: None}, 'get_transition_graph')
        else:
            transitions = _call_get_transitions(
                node, {node_name: None}, 'get_available_transitions')
        transitions = transitions[node_name]
        if isinstance(transitions, Exception):
            return 'Exception while calling service of node ' \
                f"'{args.node_name}': {transitions}"
        for t in transitions:
            print(
                f'- {t.transition.label} [{t.transition.id}]\n'
                f'\tStart: {t.start_state.label}\n'
                f'\tGoal: {t.goal_state.label}')

    # verb/get.py
    def get_main(args):
        node_names = get_node_names(
            node=node, include_hidden_nodes=args.include_hidden_nodes)
        node_names = {n.full_name for n in node_names}
        node_name = get_absolute_node_name(args.node_name)
        if node_name:
            if node_name not in node_names:
                return 'Node not found'
            nodes_to_query = [node_name]
        else:
            nodes_to_query = node_names
        states = call_get_states(node=node, node_names=nodes_to_query)
        for node_name in sorted(states.keys()):
            state = states[node_name]
            if isinstance(state, Exception):
                print(
                    'Exception while calling service of node '
                    f"'{node_name}': {state}",
                    file=sys.stderr)
                del states[node_name]
                if args.node_name:
                    return 1
        for node_name in sorted(states.keys()):
            state = states[node_name]
            prefix = ''
            if not args.node_name:
                prefix = f'{node_name}: '
            print(prefix + f'{state.label} [{state.id}]')

    # verb/set.py
    def set_main(args):
        node_names = get_node_names(
            node=node, include_hidden_nodes=args.include_hidden_nodes)
        node_name = get_absolute_node_name(args.node_name)
        if node_name not in {n.full_name for n in node_names}:
            return 'Node not found'
        transitions = _call_get_transitions(node, {node_name: None}, 'get_available_transitions')
        transitions = transitions[node_name]
        if isinstance(transitions, Exception):
            return 'Exception while calling service of node ' \
                f"'{args.node_name}': {transitions}"
        for transition in [t.transition for t in transitions]:
            if transition.label == args.transition:
                break
        else:
            for transition in [t.transition for t in transitions]:
                if str(transition.id) == args.transition:
                    break
            else:
                return \
                    'Unknown transition requested, available ones are:' + \
                    ''.join(
                        f'\n- {t.transition.label} [{t.transition.id}]'
                        for t in transitions)
        results = call_change_states(node=node, transitions={node_name: transition})
        result = results[node_name]
        if isinstance(result, Exception):
            print(
                'Exception while calling service of node '
                f"'{args.node_name}': {result}", file=sys.stderr)
        elif result:
            print('Transitioning successful')
        else:
            print('Transitioning failed', file=sys.stderr)

    rc = {"nodes": nodes_main, "list": list_main, "get": get_main, "set": set_main}[verb](args)
    node.destroy_node()
    rclpy.try_shutdown()
    return rc


if __name__ == "__main__":
    sys.exit(main())
