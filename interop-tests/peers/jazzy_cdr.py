"""CDR of ROS 2 messages as rclpy (Jazzy) writes and reads them, for the generated-type tests.

Reads one JSON object from stdin and writes one to stdout:
  {"make": ["pkg/msg/Name", ...]}
      -> {"pkg/msg/Name": {"default": hex, "filled": hex}, ...}: `serialize_message` of a
         default-constructed message and of one filled with deterministic values (every field,
         every element; non-ASCII text; sequences at or below their bounds).
  {"compare": {"pkg/msg/Name": {"default": hex, "filled": hex}, ...}}
      -> {"pkg/msg/Name": {"default": true | str, "filled": true | str}}: whether
         `deserialize_message` of the bytes equals rclpy's own default / filled message (else
         what it read, or why it could not).
Types are any message of the installed packages, including a service's `_Request`,
`_Response`, `_Event` and an action's `_Goal`, `_SendGoal_Request`, `_FeedbackMessage`…
"""

import importlib
import json
import sys

from rclpy.serialization import deserialize_message, serialize_message
from rosidl_parser import definition as d


def message_class(type_name):
    package, namespace, name = type_name.split('/')
    interface = name.split('_')[0]
    top = getattr(importlib.import_module(f'{package}.{namespace}'), interface)
    return getattr(sys.modules[top.__module__], name)


class Filler:
    """Deterministic values: a counter walks every field and element."""

    def __init__(self):
        self.n = 0

    def next(self):
        self.n += 1
        return self.n

    def basic(self, typename):
        n = self.next()
        if typename == 'boolean':
            return n % 2 == 0
        if typename == 'octet':
            return bytes([n % 256])
        if typename in ('char',):
            return chr(ord('a') + n % 26)
        if typename == 'wchar':
            return chr(0x3b1 + n % 20)
        if typename in ('float', 'double'):
            return n + 0.5
        if typename == 'long double':
            return float(n)
        bits = {'int8': 8, 'uint8': 8, 'int16': 16, 'uint16': 16, 'int32': 32, 'uint32': 32,
                'int64': 64, 'uint64': 64}[typename]
        if typename.startswith('u'):
            return (n * 37) % (1 << bits)
        return ((n * 37) % (1 << (bits - 1))) * (-1 if n % 2 else 1)

    def text(self, wide, bound):
        n = self.next()
        s = f'w{n}\u00e9\u6c34' if wide else f's{n}-\u00e9'
        if bound is not None:
            # rosidl checks characters (Python) and bytes / code units (C): stay ASCII then.
            s = f'{n}'[:bound]
        return s

    def value(self, t):
        if isinstance(t, d.BasicType):
            return self.basic(t.typename)
        if isinstance(t, d.UnboundedString):
            return self.text(False, None)
        if isinstance(t, d.BoundedString):
            return self.text(False, t.maximum_size)
        if isinstance(t, d.UnboundedWString):
            return self.text(True, None)
        if isinstance(t, d.BoundedWString):
            return self.text(True, t.maximum_size)
        if isinstance(t, d.NamespacedType):
            return self.fill(message_class('/'.join(t.namespaces + [t.name]))())
        if isinstance(t, d.Array):
            return [self.value(t.value_type) for _ in range(t.size)]
        if isinstance(t, d.BoundedSequence):
            return [self.value(t.value_type) for _ in range(min(2, t.maximum_size))]
        if isinstance(t, d.UnboundedSequence):
            return [self.value(t.value_type) for _ in range(3)]
        raise TypeError(f'unknown slot type {t!r}')

    def fill(self, msg):
        for field, slot in zip(msg.get_fields_and_field_types(), msg.SLOT_TYPES):
            setattr(msg, field, self.value(slot))
        return msg


def main():
    request = json.load(sys.stdin)
    out = {}
    for type_name in request.get('make', []):
        cls = message_class(type_name)
        out[type_name] = {
            'default': serialize_message(cls()).hex(),
            'filled': serialize_message(Filler().fill(cls())).hex(),
        }
    for type_name, sent in request.get('compare', {}).items():
        cls = message_class(type_name)
        expected = {'default': cls(), 'filled': Filler().fill(cls())}
        out[type_name] = {}
        for which, data in sent.items():
            try:
                msg = deserialize_message(bytes.fromhex(data), cls)
                same = msg == expected[which]
                out[type_name][which] = True if same else f'read {msg!r}'
            except Exception as e:  # noqa: B902 - reported to the test, which fails on it
                out[type_name][which] = f'{type(e).__name__}: {e}'

    json.dump(out, sys.stdout)


if __name__ == '__main__':
    main()
