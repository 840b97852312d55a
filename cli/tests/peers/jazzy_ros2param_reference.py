"""ros2param's output without ros2cli: the `main` bodies of ros2param 0.32.2 (Jazzy,
ros2/ros2cli branch `jazzy`, `ros2param/ros2param/verb/{list,get,set,delete,describe,dump,
load}.py` and `ros2param/api/__init__.py`), transcribed with rclpy (the suite's Jazzy wheels) in
place of ros2cli's DirectNode, so that the CLI tests compare `horus-ros param …` with what
ros2param prints — values typed by rclpy's own `get_parameter_value`, files read by rclpy's own
`parameter_dict_from_yaml_file`, dumps written by PyYAML itself.

Only what follows the node lookup is transcribed (the tests' node is known to exist).

usage: jazzy_ros2param_reference.py DOMAIN VERB ARGS…   (VERB ARGS as `ros2 param VERB ARGS`)
The domain goes to ROS_DOMAIN_ID before rclpy starts.
"""

import argparse
import os
import re
import sys


def main() -> int:
    domain, verb, rest = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.environ["ROS_DOMAIN_ID"] = domain

    import rclpy
    import yaml
    from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
    from rclpy.parameter import (PARAMETER_SEPARATOR_STRING, get_parameter_value,
                                 parameter_dict_from_yaml_file, parameter_value_to_python)
    from rclpy.parameter_client import AsyncParameterClient

    parser = argparse.ArgumentParser()
    parser.add_argument("node_name", nargs="?" if verb == "list" else None)
    if verb == "list":
        parser.add_argument("--filter", nargs=1)
        parser.add_argument("--param-prefixes", nargs="+", default=[])
        parser.add_argument("--param-type", action="store_true")
    if verb in ("get", "set", "delete"):
        parser.add_argument("parameter_name")
    if verb == "get":
        parser.add_argument("--hide-type", action="store_true")
    if verb == "set":
        parser.add_argument("value")
    if verb == "describe":
        parser.add_argument("parameter_names", nargs="+")
    if verb == "load":
        parser.add_argument("parameter_file")
        parser.add_argument("--no-use-wildcard", action="store_true")
    args = parser.parse_args(rest)

    rclpy.init()
    node = rclpy.create_node("_ros2param_reference")

    def client_for(node_name):
        client = AsyncParameterClient(node, node_name)
        if not client.wait_for_services(timeout_sec=5.0):
            raise RuntimeError('Wait for service timed out waiting for '
                               f'parameter services for node {node_name}')
        return client

    def spin(future):
        rclpy.spin_until_future_complete(node, future)
        return future.result()

    type_strings = {
        ParameterType.PARAMETER_BOOL: 'boolean',
        ParameterType.PARAMETER_INTEGER: 'integer',
        ParameterType.PARAMETER_DOUBLE: 'double',
        ParameterType.PARAMETER_STRING: 'string',
        ParameterType.PARAMETER_BYTE_ARRAY: 'byte array',
        ParameterType.PARAMETER_BOOL_ARRAY: 'boolean array',
        ParameterType.PARAMETER_INTEGER_ARRAY: 'integer array',
        ParameterType.PARAMETER_DOUBLE_ARRAY: 'double array',
        ParameterType.PARAMETER_STRING_ARRAY: 'string array',
        ParameterType.PARAMETER_NOT_SET: 'not set',
    }
    node_name = args.node_name if args.node_name.startswith('/') else '/' + args.node_name

    if verb == "list":
        regex_filter = re.compile(args.filter[0]) if args.filter is not None else None
        client = client_for(node_name)
        response = spin(client.list_parameters(prefixes=args.param_prefixes))
        sorted_names = sorted(response.result.names)
        if regex_filter is not None:
            sorted_names = [name for name in sorted_names if regex_filter.match(name)]
        name_to_type_map = {}
        if args.param_type is True:
            resp = spin(client.describe_parameters(sorted_names))
            for descriptor in resp.descriptors:
                name_to_type_map[descriptor.name] = type_strings[descriptor.type]
        for name in sorted_names:
            if args.param_type is True:
                print(f'  {name} (type: {name_to_type_map[name]})')
            else:
                print(f'  {name}')
    elif verb == "get":
        response = spin(client_for(node_name).get_parameters([args.parameter_name]))
        if not response.values:
            print('Parameter not set', file=sys.stderr)
            return 1
        pvalue = response.values[0]
        labels = {
            ParameterType.PARAMETER_BOOL: ('Boolean value is:', lambda v: v.bool_value),
            ParameterType.PARAMETER_INTEGER: ('Integer value is:', lambda v: v.integer_value),
            ParameterType.PARAMETER_DOUBLE: ('Double value is:', lambda v: v.double_value),
            ParameterType.PARAMETER_STRING: ('String value is:', lambda v: v.string_value),
            ParameterType.PARAMETER_BYTE_ARRAY: ('Byte values are:',
                                                 lambda v: v.byte_array_value),
            ParameterType.PARAMETER_BOOL_ARRAY: ('Boolean values are:',
                                                 lambda v: v.bool_array_value),
            ParameterType.PARAMETER_INTEGER_ARRAY: ('Integer values are:',
                                                    lambda v: v.integer_array_value.tolist()),
            ParameterType.PARAMETER_DOUBLE_ARRAY: ('Double values are:',
                                                   lambda v: v.double_array_value.tolist()),
            ParameterType.PARAMETER_STRING_ARRAY: ('String values are:',
                                                   lambda v: v.string_array_value),
            ParameterType.PARAMETER_NOT_SET: ('Parameter not set.', lambda v: None),
        }
        label, get = labels[pvalue.type]
        value = get(pvalue)
        if not args.hide_type:
            print(label, value) if value is not None else print(label)
        else:
            print(value)
    elif verb in ("set", "delete"):
        parameter = Parameter()
        parameter.name = args.parameter_name
        if verb == "set":
            parameter.value = get_parameter_value(string_value=args.value)
            ok, failed = 'Set parameter successful', 'Setting parameter failed'
        else:
            parameter.value = ParameterValue(type=ParameterType.PARAMETER_NOT_SET)
            ok, failed = 'Deleted parameter successfully', 'Deleting parameter failed'
        response = spin(client_for(node_name).set_parameters([parameter]))
        result = response.results[0]
        msg = ok if result.successful else failed
        if result.reason:
            msg += ': ' + result.reason
        print(msg, file=sys.stdout if result.successful else sys.stderr)
    elif verb == "describe":
        response = spin(client_for(node_name).describe_parameters(args.parameter_names))
        for descriptor in response.descriptors:
            print('Parameter name:', descriptor.name)
            print('  Type:', type_strings[descriptor.type])
            if descriptor.description:
                print('  Description:', descriptor.description)
            print('  Constraints:')
            if descriptor.read_only:
                print('    Read only: true')
            ranges = descriptor.floating_point_range + descriptor.integer_range
            if ranges:
                range_ = ranges[0]
                print('    Min value:', range_.from_value)
                print('    Max value:', range_.to_value)
                if range_.step:
                    print('    Step:', range_.step)
            if descriptor.additional_constraints:
                print('    Additional constraints:', descriptor.additional_constraints)
    elif verb == "dump":
        def insert_dict(dictionary, key, value):
            split = key.split(PARAMETER_SEPARATOR_STRING, 1)
            if len(split) > 1:
                if not split[0] in dictionary:
                    dictionary[split[0]] = {}
                insert_dict(dictionary[split[0]], split[1], value)
            else:
                dictionary[key] = value

        client = client_for(node_name)
        yaml_output = {node_name: {'ros__parameters': {}}}
        parameter_names = sorted(spin(client.list_parameters()).result.names)
        response = spin(client.get_parameters(parameter_names))
        parameter_values = [parameter_value_to_python(i) for i in response.values]
        for param_name, pval in zip(parameter_names, parameter_values):
            insert_dict(yaml_output[node_name]['ros__parameters'], param_name, pval)
        print(yaml.dump(yaml_output, default_flow_style=False))
    elif verb == "load":
        client = client_for(node_name)
        use_wildcard = not args.no_use_wildcard
        future = client.load_parameter_file(args.parameter_file, use_wildcard)
        parameters = list(parameter_dict_from_yaml_file(
            args.parameter_file, use_wildcard).values())
        response = spin(future)
        assert len(response.results) == len(parameters), 'Not all parameters set'
        for i in range(0, len(response.results)):
            result = response.results[i]
            param_name = parameters[i].name
            if result.successful:
                msg = 'Set parameter {} successful'.format(param_name)
                if result.reason:
                    msg += ': ' + result.reason
                print(msg)
            else:
                msg = 'Set parameter {} failed'.format(param_name)
                if result.reason:
                    msg += ': ' + result.reason
                print(msg, file=sys.stderr)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
