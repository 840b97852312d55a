"""rosidl_parser's own parse of every .idl file of <sys.prefix>/share/*/{msg,srv,action}/
(or of the files given as arguments, each in <base>/<package>/<msg|srv|action>/).

Prints one JSON object per line and file, in the shape codegen/tests/idl.rs builds from
horus-ros-codegen's model:
  {"file", "kind": "message"|"service"|"action", "name": "pkg/ns/Name", "messages": [...]}
with each message {"name", "comment", "fields", "constants"}. Normalised as the model stores
things: a struct whose only member is rosidl_adapter's placeholder has no fields; an integer
value of a floating-point type is a float; floats are their IEEE 754 bits and integers decimal
strings (exact); array defaults are the Python tuple in the string, read by ast.literal_eval.
"""

import ast
import json
import pathlib
import struct
import sys

from rosidl_parser import definition as d
from rosidl_parser.parser import get_annotations
from rosidl_parser.parser import get_ast_from_idl_string
from rosidl_parser.parser import get_child_identifier_value
from rosidl_parser.parser import parse_idl_file

PLACEHOLDER = 'structure_needs_at_least_one_member'
FLOATS = ('float', 'double', 'long double')


def base_json(t):
    if isinstance(t, d.BasicType):
        return {'primitive': t.typename}
    if isinstance(t, d.BoundedString):
        return {'string': t.maximum_size}
    if isinstance(t, d.UnboundedString):
        return {'string': None}
    if isinstance(t, d.BoundedWString):
        return {'wstring': t.maximum_size}
    if isinstance(t, d.UnboundedWString):
        return {'wstring': None}
    if isinstance(t, d.NamespacedType):
        return {'named': '/'.join(t.namespaces + [t.name])}
    raise TypeError(f'unexpected type {t!r}')


def type_json(t):
    if isinstance(t, d.Array):
        return {'base': base_json(t.value_type), 'container': 'array', 'size': t.size}
    if isinstance(t, d.BoundedSequence):
        return {'base': base_json(t.value_type), 'container': 'bounded_sequence',
                'size': t.maximum_size}
    if isinstance(t, d.UnboundedSequence):
        return {'base': base_json(t.value_type), 'container': 'sequence', 'size': None}
    return {'base': base_json(t), 'container': 'single', 'size': None}


def literal_json(value, base):
    if isinstance(value, bool):
        return {'bool': value}
    if isinstance(value, int) and base.get('primitive') in FLOATS:
        value = float(value)
    if isinstance(value, int):
        return {'int': str(value)}
    if isinstance(value, float):
        return {'float': str(struct.unpack('<Q', struct.pack('<d', value))[0])}
    if isinstance(value, str):
        return {'string': value}
    raise TypeError(f'unexpected value {value!r}')


def default_json(member):
    if not member.has_annotation('default'):
        return None
    value = member.get_annotation_value('default')['value']
    t = type_json(member.type)
    if t['container'] == 'single':
        return {'scalar': literal_json(value, t['base'])}
    return {'array': [literal_json(v, t['base']) for v in ast.literal_eval(value)]}


def member_json(member):
    unit = None
    if member.has_annotation('unit'):
        unit = member.get_annotation_value('unit')['value']
    return {
        'name': member.name,
        'type': type_json(member.type),
        'default': default_json(member),
        'comment': member.get_comment_lines(),
        'unit': unit,
    }


def constant_json(constant):
    base = base_json(constant.type)
    return {
        'name': constant.name,
        'type': base,
        'value': literal_json(constant.value, base),
        'comment': constant.get_comment_lines(),
    }


def struct_comments(path):
    """Each struct's comment lines, by name, from rosidl_parser's own annotations of the tree.

    rosidl_parser `extract_content_from_ast` keeps a struct's annotations only for a message;
    the model also keeps a service's or action's (rosidl_adapter writes them).
    """
    tree = get_ast_from_idl_string(path.read_text(encoding='utf-8'))
    comments = {}
    for struct_def in tree.find_data('struct_def'):
        holder = d.Annotatable()
        holder.annotations = get_annotations(struct_def)
        comments[get_child_identifier_value(struct_def)] = holder.get_comment_lines()
    return comments


def message_json(message, comments):
    s = message.structure
    members = s.members
    if len(members) == 1 and members[0].name == PLACEHOLDER and \
            members[0].type == d.BasicType('uint8'):
        members = []
    return {
        'name': '/'.join(s.namespaced_type.namespaces + [s.namespaced_type.name]),
        'comment': comments[s.namespaced_type.name],
        'fields': [member_json(m) for m in members],
        'constants': [constant_json(c) for c in message.constants],
    }


def interface_json(path, base):
    locator = d.IdlLocator(base, path.relative_to(base))
    content = parse_idl_file(locator).content
    comments = struct_comments(path)
    for element in content.elements:
        if isinstance(element, d.Message):
            kind, name, messages = 'message', element.structure.namespaced_type, [element]
        elif isinstance(element, d.Service):
            kind, name = 'service', element.namespaced_type
            messages = [element.request_message, element.response_message]
        elif isinstance(element, d.Action):
            kind, name = 'action', element.namespaced_type
            messages = [element.goal, element.result, element.feedback]
        else:
            continue
        return {
            'file': str(path),
            'kind': kind,
            'name': '/'.join(name.namespaces + [name.name]),
            'messages': [message_json(m, comments) for m in messages],
        }
    raise ValueError(f'{path}: no message, service or action')


def main():
    if len(sys.argv) > 1:
        # The files named, each under <base>/<pkg>/<msg|srv|action>/.
        files = [(pathlib.Path(a).resolve(), pathlib.Path(a).resolve().parents[2])
                 for a in sys.argv[1:]]
    else:
        share = pathlib.Path(sys.prefix) / 'share'
        files = sorted(
            (p, share) for kind in ('msg', 'srv', 'action') for p in share.glob(f'*/{kind}/*.idl'))
    for path, base in files:
        print(json.dumps(interface_json(path, base), ensure_ascii=False), flush=True)


if __name__ == '__main__':
    main()
