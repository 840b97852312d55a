"""A real ROS 2 Jazzy node: rclpy 7.1 on the RMW that RMW_IMPLEMENTATION names (the tests run it in
the real peers' environment, where HORUS_ROS_PEER_RMW chooses it: rmw_fastrtps_cpp 8.4 / Fast DDS
2.14 by default, or rmw_cyclonedds_cpp 2.2 / Cyclone DDS 0.10), built from a JSON spec so that one
test can give it everything it needs at once (interop-tests/src/peers/peer.rs writes the spec):

  {"domain": 7, "namespace": "/ns", "name": "node",
   "servers": [{"service": "/ns/set", "type": "std_srvs/srv/SetBool", "introspection": true}],
   "clients": [{"service": "/x", "type": "std_srvs/srv/SetBool", "calls": [{"data": true}],
                "wait_s": 20, "timeout_s": 5, "introspection": true}],
   "publishers": [{"topic": "/chatter", "type": "std_msgs/msg/String", "count": 0,
                   "period_s": 0.05}],
   "subscriptions": [{"topic": "/chatter", "type": "std_msgs/msg/String"}],
   "echoes": [{"type": "test_msgs/msg/Arrays", "in": "/gen/in", "out": "/gen/out"}],
   "parameters": {"gain": 1.5},
   "parameter_client": {"node": "/horus_node", "list": true, "get": ["p"], "set": {"p": 2},
                        "wait_s": 20, "timeout_s": 5},
   "event_watches": [{"service": "/add", "type": "example_interfaces/srv/AddTwoInts"}],
   "event_publishers": [{"service": "/add", "type": "example_interfaces/srv/AddTwoInts",
                         "events": [{"event_type": 0, "stamp": [100, 100000000],
                                     "client_gid": [1, 16, ...], "sequence_number": 7,
                                     "request": [{"a": 2, "b": 3}], "response": []}]}],
   "bare": false, "graph": true, "info_heartbeat_s": 3600, "leave_when_done": false}

"bare" leaves out what rclpy adds to every node unless told not to: the parameter services
(start_parameter_services=False), `~/get_type_description` (the parameter
start_type_description_service overridden to false) and the /rosout publisher
(enable_rosout=False); its /parameter_events publisher stays (rclpy always makes it).

"info_heartbeat_s" makes the periodic heartbeat of the node's `ros_discovery_info` writer that many
seconds apart (on rmw_cyclonedds, of every writer of the node: see cyclone_heartbeat_config).

Every key but domain, namespace and name is optional. What it prints on stdout, one JSON object a
line:
- {"ready": {"node": "/ns/node"}} once every entity is created;
- {"graph": {...}} at start and whenever rclpy's own view of the graph changed ("graph": true):
  nodes with enclaves, topic and service names and types, for every topic rclpy lists (with
  no_demangle: the DDS topics on rmw_fastrtps and rmw_cyclonedds; rmw_zenoh ignores it and lists
  ROS names) its publishers and subscriptions as rclpy's TopicEndpointInfo prints them (`ros2
  topic info -v`), and each node's services and clients ("node_services");
- {"served": {"service", "request"}} per request a server took; {"event": {"service",
  "event_type", "stamp": [sec, nanosec], "client_gid", "sequence_number", "request",
  "response"}} per introspection event of its own servers and clients and of the services of
  "event_watches" (their `_service_event` topics, read by a subscription of this node, with
  rmw_qos_profile_services_default as `ros2 service echo` reads them); {"matched": {"topic",
  "count"}} each time the number of writers matched to an "event_watches" subscription changes;
- {"published_events": {"service", "count"}} once an "event_publishers" publisher (of the
  service's Event type on its `_service_event` topic: RELIABLE, VOLATILE, KEEP_LAST 10) has a
  matched reader and has published its events, given as fields (client_gid as 16 numbers);
- {"reply": {"service", "index", "response"}} per call answered, {"no_reply": {...}} per call not
  answered within timeout_s, {"calls_done": {"service", "available", "answered", "calls"}};
- {"echoed": {"type", "equal"}} per message an echo took on its "in" topic (RELIABLE,
  TRANSIENT_LOCAL, depth 1, as its "out" publisher) and published again on "out": "equal" says
  whether it is the message jazzy_cdr.py's Filler makes for that type;
- {"published": data} per message published, {"heard": {"topic", "data", "publisher_gid"}} per
  message taken;
- {"parameters": {"list": [...], "get": [...], "set": [...]}} with what the parameter client got
  ({"parameters": {"unavailable": true}} if the services never showed up within wait_s,
  {"parameters": {"timeout": "list"|"get"|"set"}} naming the first request not answered within
  timeout_s).

rclpy offers no event for graph changes (ros2/rclpy#929), and its executor can miss a shutdown
signal, so the node is spun by `spin_once(timeout_sec=0.1)` in a loop that wakes on its own: each
wake re-reads the graph view, the clients' progress and whether to leave. It leaves (destroying
its node, then its context, so that peers see it go) when its standard input ends, on SIGINT or
SIGTERM, or once its clients and publishers are done if leave_when_done. Exit status 0 iff every
call was answered (and the parameter client got its answers).

usage: jazzy_node.py SPEC_JSON
"""

import array
import importlib
import json
import os
import sys
import tempfile
import threading
import time

import rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import (DurabilityPolicy, qos_profile_services_default, QoSProfile,
                       ReliabilityPolicy)
from rclpy.service_introspection import ServiceIntrospectionState


def emit(key, value):
    print(json.dumps({key: value}, sort_keys=True), flush=True)


def ros_type(name):
    """The Python class of `pkg/msg/Name` or `pkg/srv/Name`."""
    package, kind, leaf = name.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), leaf)


def gid_text(gid):
    """A GID as rclpy's TopicEndpointInfo prints it."""
    return '.'.join(format(b, '02x') for b in gid)


def to_plain(value):
    """A message as JSON-friendly data (bytes as lists of numbers; rclpy gives sequences of
    numbers as array.array, arrays as numpy arrays)."""
    if hasattr(value, 'get_fields_and_field_types'):
        return {f: to_plain(getattr(value, f)) for f in value.get_fields_and_field_types()}
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, (list, tuple, array.array)) or type(value).__name__ == 'ndarray':
        return [to_plain(v) for v in value]
    return value


def fill(message, fields):
    """Sets message fields from JSON data (a `byte` field from a number)."""
    types = message.get_fields_and_field_types()
    for field, value in fields.items():
        if types[field] == 'octet' and isinstance(value, int):
            value = bytes([value])
        setattr(message, field, value)
    return message


def answer(service_type, request, response):
    """What the servers answer: SetBool says what it was set to, Trigger triggers, every other
    type echoes the request's fields that the response has (AddTwoInts adds) (test_msgs' BasicTypes, Arrays, …)."""
    name = service_type.__name__
    if name == 'SetBool':
        response.success = request.data
        response.message = f'set to {request.data}'
    elif name == 'Trigger':
        response.success = True
        response.message = 'triggered'
    elif name == 'AddTwoInts':
        response.sum = request.a + request.b
    else:
        for field in response.get_fields_and_field_types():
            if hasattr(request, field):
                setattr(response, field, getattr(request, field))
    return response


def graph_view(node):
    """rclpy's own view of the graph, through its graph API."""
    endpoints = {}
    for topic, _ in node.get_topic_names_and_types(no_demangle=True):
        endpoints[topic] = {
            'publishers': sorted(
                str(i) for i in node.get_publishers_info_by_topic(topic, no_mangle=True)),
            'subscriptions': sorted(
                str(i) for i in node.get_subscriptions_info_by_topic(topic, no_mangle=True)),
        }
    return {
        'nodes': sorted(
            [ns, name, enclave]
            for name, ns, enclave in node.get_node_names_and_namespaces_with_enclaves()),
        'topics': {name: sorted(types) for name, types in node.get_topic_names_and_types()},
        'services': {name: sorted(types) for name, types in node.get_service_names_and_types()},
        'endpoints': endpoints,
        'node_services': node_services(node),
    }


def node_services(node):
    """Each node's services and clients with their types, by fully qualified node name (a node
    gone between the listing and its query is left out)."""
    out = {}
    for name, ns in node.get_node_names_and_namespaces():
        try:
            services = node.get_service_names_and_types_by_node(name, ns)
            clients = node.get_client_names_and_types_by_node(name, ns)
        except Exception:  # rclpy's NodeNameNonExistentError: it left meanwhile
            continue
        out[ns.rstrip('/') + '/' + name] = {
            'services': {n: sorted(t) for n, t in services},
            'clients': {n: sorted(t) for n, t in clients},
        }
    return out


def info_heartbeat_profile(seconds):
    """A Fast DDS XML profile giving the `ros_discovery_info` writer a periodic heartbeat of
    `seconds` (rmw_fastrtps_cpp jazzy `publisher.cpp` loads the data_writer profile named after
    the topic from FASTRTPS_DEFAULT_PROFILES_FILE; Fast DDS' default period is 3 s)."""
    xml = f'''<?xml version="1.0" encoding="UTF-8"?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <data_writer profile_name="ros_discovery_info">
    <times><heartbeatPeriod><sec>{int(seconds)}</sec></heartbeatPeriod></times>
  </data_writer>
</profiles>
'''
    fd, path = tempfile.mkstemp(prefix='rclpy-peer-', suffix='.xml')
    with os.fdopen(fd, 'w') as f:
        f.write(xml)
    return path


def cyclone_heartbeat_config(seconds):
    """A Cyclone DDS configuration fragment (CYCLONEDDS_URI) making the periodic heartbeat of every
    writer `seconds` apart: Cyclone DDS 0.10 has no setting per topic, so `ros_discovery_info`'s
    writer gets it with the others (`Internal/HeartbeatInterval`, its base interval and the bounds
    it varies within; default 100 ms, from 20 ms to 8 s). The heartbeat a writer schedules on
    matching a reader (`ddsi_entity_match.c` `writer_add_connection`) and those answering
    ACKNACKs are not periodic ones."""
    interval = f'{int(seconds)} s'
    return ('<CycloneDDS><Domain Id="any"><Internal>'
            f'<HeartbeatInterval minsched="{interval}" max="{interval}">{interval}'
            '</HeartbeatInterval></Internal></Domain></CycloneDDS>')


class Peer:
    def __init__(self, spec):
        self.spec = spec
        bare = spec.get('bare', False)
        self.node = Node(
            spec['name'], namespace=spec.get('namespace', '/'), enable_rosout=not bare,
            start_parameter_services=not bare,
            parameter_overrides=(
                [Parameter('start_type_description_service', value=False)] if bare else []))
        self.leaving = threading.Event()
        self.last_view = None
        self.ok = True
        self.keep = []
        for s in spec.get('servers', []):
            self.add_server(s)
        self.clients = [self.add_client(c) for c in spec.get('clients', [])]
        self.publishers = [self.add_publisher(p) for p in spec.get('publishers', [])]
        for s in spec.get('subscriptions', []):
            self.add_subscription(s)
        for e in spec.get('echoes', []):
            self.add_echo(e)
        for w in spec.get('event_watches', []):
            self.watch_events(w['service'], ros_type(w['type']), matched=True)
        self.event_publishers = [self.add_event_publisher(p)
                                 for p in spec.get('event_publishers', [])]
        for name, value in spec.get('parameters', {}).items():
            self.node.declare_parameter(name, value)
        self.parameter_client = spec.get('parameter_client')
        if self.parameter_client:
            self.parameter_client['client'] = AsyncParameterClient(
                self.node, self.parameter_client['node'])

    def watch_events(self, service, service_type, matched=False):
        """Reads the introspection events of `service` (of its servers and clients, ours or
        others'); with `matched`, reports the writers matched to the reader."""
        def on_event(event):
            emit('event', {
                'service': service,
                'event_type': event.info.event_type,
                'stamp': [event.info.stamp.sec, event.info.stamp.nanosec],
                'client_gid': gid_text(event.info.client_gid),
                'sequence_number': event.info.sequence_number,
                'request': to_plain(event.request),
                'response': to_plain(event.response),
            })
        topic = service + '/_service_event'
        callbacks = None
        if matched:
            callbacks = SubscriptionEventCallbacks(matched=lambda info: emit(
                'matched', {'topic': topic, 'count': info.current_count}))
        qos = qos_profile_services_default if matched else 100
        self.keep.append(self.node.create_subscription(
            service_type.Event, topic, on_event, qos, event_callbacks=callbacks))

    def add_event_publisher(self, p):
        """A publisher of `p`'s events on the service's `_service_event` topic."""
        service_type = ros_type(p['type'])
        qos = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.VOLATILE)
        publisher = self.node.create_publisher(
            service_type.Event, p['service'] + '/_service_event', qos)
        return {'spec': p, 'type': service_type, 'publisher': publisher, 'done': False}

    def step_event_publisher(self, e):
        """Publishes the events of `e` once a reader has matched its publisher."""
        if e['done'] or e['publisher'].get_subscription_count() == 0:
            return
        for fields in e['spec']['events']:
            event = e['type'].Event()
            event.info.event_type = fields['event_type']
            event.info.stamp.sec, event.info.stamp.nanosec = fields['stamp']
            event.info.client_gid = fields['client_gid']
            event.info.sequence_number = fields['sequence_number']
            event.request = [fill(e['type'].Request(), r) for r in fields['request']]
            event.response = [fill(e['type'].Response(), r) for r in fields['response']]
            e['publisher'].publish(event)
        e['done'] = True
        emit('published_events', {'service': e['spec']['service'],
                                  'count': len(e['spec']['events'])})

    def add_server(self, s):
        service_type = ros_type(s['type'])

        def on_request(request, response):
            emit('served', {'service': s['service'], 'request': to_plain(request)})
            return answer(service_type, request, response)
        server = self.node.create_service(service_type, s['service'], on_request)
        if s.get('introspection'):
            server.configure_introspection(
                self.node.get_clock(), qos_profile_services_default,
                ServiceIntrospectionState.METADATA)
            self.watch_events(s['service'], service_type)
        self.keep.append(server)

    def add_client(self, c):
        service_type = ros_type(c['type'])
        client = self.node.create_client(service_type, c['service'])
        if c.get('introspection'):
            client.configure_introspection(
                self.node.get_clock(), qos_profile_services_default,
                ServiceIntrospectionState.METADATA)
            self.watch_events(c['service'], service_type)
        return {'spec': c, 'type': service_type, 'client': client, 'index': 0,
                'future': None, 'answered': 0, 'available': False, 'done': not c.get('calls'),
                'since': time.monotonic()}

    def add_publisher(self, p):
        publisher = self.node.create_publisher(ros_type(p['type']), p['topic'], 10)
        state = {'spec': p, 'publisher': publisher, 'count': 0, 'done': False}

        def publish():
            if state['done']:
                return
            state['count'] += 1
            message = ros_type(p['type'])()
            message.data = f"Hello World: {state['count']}"
            publisher.publish(message)
            emit('published', message.data)
            if p.get('count') and state['count'] >= p['count']:
                state['done'] = True
        self.keep.append(self.node.create_timer(p.get('period_s', 0.05), publish))
        return state

    def add_echo(self, e):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from jazzy_cdr import Filler, message_class
        cls = message_class(e['type'])
        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        publisher = self.node.create_publisher(cls, e['out'], qos)

        def on_message(message):
            emit('echoed', {'type': e['type'], 'equal': message == Filler().fill(cls())})
            publisher.publish(message)
        self.keep.append(self.node.create_subscription(cls, e['in'], on_message, qos))

    def add_subscription(self, s):
        def on_message(message):
            emit('heard', {'topic': s['topic'], 'data': message.data})
        self.keep.append(self.node.create_subscription(
            ros_type(s['type']), s['topic'], on_message, QoSProfile(depth=10)))

    def step_client(self, c):
        """Advances one client: waits for its server, then makes its calls one at a time."""
        spec = c['spec']
        if c['done']:
            return
        now = time.monotonic()
        if not c['available']:
            if c['client'].service_is_ready():
                c['available'] = True
                c['since'] = now
            elif now - c['since'] > spec.get('wait_s', 20):
                self.finish_client(c)
            return
        if c['future'] is None:
            request = fill(c['type'].Request(), spec['calls'][c['index']])
            c['future'] = c['client'].call_async(request)
            c['since'] = now
            return
        if c['future'].done():
            emit('reply', {'service': spec['service'], 'index': c['index'],
                           'response': to_plain(c['future'].result())})
            c['answered'] += 1
        elif now - c['since'] > spec.get('timeout_s', 5):
            emit('no_reply', {'service': spec['service'], 'index': c['index']})
            c['client'].remove_pending_request(c['future'])
        else:
            return
        c['future'] = None
        c['index'] += 1
        if c['index'] == len(spec['calls']):
            self.finish_client(c)

    def finish_client(self, c):
        c['done'] = True
        calls = len(c['spec']['calls'])
        self.ok = self.ok and c['answered'] == calls
        emit('calls_done', {'service': c['spec']['service'], 'available': c['available'],
                            'answered': c['answered'], 'calls': calls})

    def step_parameter_client(self):
        """Waits for the remote node's parameter services, then asks them one request after
        the other: list, get, set."""
        p = self.parameter_client
        if not p or p.get('done'):
            return
        client = p['client']
        now = time.monotonic()
        p.setdefault('since', now)
        if 'steps' not in p:
            if client.services_are_ready():
                p['steps'] = [k for k in ('list', 'get', 'set') if p.get(k)]
                p['results'] = {}
                p['future'] = None
            elif now - p['since'] > p.get('wait_s', 20):
                emit('parameters', {'unavailable': True})
                p['done'] = True
                self.ok = False
            return
        if p['future'] is None:
            if not p['steps']:
                emit('parameters', p['results'])
                p['done'] = True
                return
            key = p['steps'][0]
            if key == 'list':
                p['future'] = client.list_parameters()
            elif key == 'get':
                p['future'] = client.get_parameters(p['get'])
            else:
                p['future'] = client.set_parameters(
                    [Parameter(n, value=v) for n, v in p['set'].items()])
            p['since'] = now
            return
        if p['future'].done():
            key = p['steps'].pop(0)
            result = p['future'].result()
            if key == 'list':
                p['results'][key] = sorted(result.result.names)
            elif key == 'get':
                p['results'][key] = [to_plain(v) for v in result.values]
            else:
                p['results'][key] = [to_plain(r) for r in result.results]
            p['future'] = None
        elif now - p['since'] > p.get('timeout_s', 5):
            emit('parameters', {'timeout': p['steps'][0]})
            p['done'] = True
            self.ok = False

    def done(self):
        return (all(c['done'] for c in self.clients)
                and all(p['done'] for p in self.publishers)
                and (not self.parameter_client or self.parameter_client.get('done')))

    def run(self):
        emit('ready', {'node': self.node.get_fully_qualified_name()})
        while rclpy.ok() and not self.leaving.is_set():
            try:
                rclpy.spin_once(self.node, timeout_sec=0.1)
            except Exception:
                # A signal shut the context down while the node was spun: that is leaving.
                if rclpy.ok():
                    raise
                break
            if self.spec.get('graph'):
                view = graph_view(self.node)
                if view != self.last_view:
                    self.last_view = view
                    emit('graph', view)
            for c in self.clients:
                self.step_client(c)
            for e in self.event_publishers:
                self.step_event_publisher(e)
            self.step_parameter_client()
            if self.spec.get('leave_when_done') and self.done():
                break


def main():
    spec = json.loads(sys.argv[1])
    if spec.get('info_heartbeat_s'):
        if os.environ.get('RMW_IMPLEMENTATION') == 'rmw_cyclonedds_cpp':
            # Cyclone DDS reads a comma-separated list of configurations, later ones on top.
            uri = [os.environ.get('CYCLONEDDS_URI', ''),
                   cyclone_heartbeat_config(spec['info_heartbeat_s'])]
            os.environ['CYCLONEDDS_URI'] = ','.join(u for u in uri if u)
        else:
            os.environ['FASTRTPS_DEFAULT_PROFILES_FILE'] = info_heartbeat_profile(
                spec['info_heartbeat_s'])
    # No log files: rcl's external logging (spdlog) would write under ~/.ros/log.
    rclpy.init(args=[sys.argv[0], '--ros-args', '--disable-external-lib-logs'],
               domain_id=spec['domain'])
    peer = Peer(spec)

    def watch_stdin():
        for _ in sys.stdin:
            pass
        peer.leaving.set()
    threading.Thread(target=watch_stdin, daemon=True).start()
    try:
        peer.run()
    except KeyboardInterrupt:
        pass
    finally:
        peer.node.destroy_node()
        rclpy.try_shutdown()
        if os.environ.get('FASTRTPS_DEFAULT_PROFILES_FILE', '').startswith(tempfile.gettempdir()):
            os.unlink(os.environ['FASTRTPS_DEFAULT_PROFILES_FILE'])
    sys.exit(0 if peer.ok else 1)


if __name__ == '__main__':
    main()
