"""rclpy's side of msgs/tests/runtime.rs, for test_msgs values that the Rust test builds too
(keep the two in step).

Without arguments: prints `Name hex` lines, rclpy's CDR (serialize_message) of each value.
With `check`: reads `Name hex` lines (CDR written by horus-ros-msgs) from stdin, decodes each with
rclpy (deserialize_message) and prints `Name ok`, or `Name differs: field ...`."""

import sys

from rclpy.serialization import deserialize_message, serialize_message
from test_msgs.msg import (Arrays, BasicTypes, BoundedSequences, Constants, Defaults,
                           Strings, WStrings)

FIELDS = ['bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16',
          'uint16', 'int32', 'uint32', 'int64', 'uint64']


def basic(m, i):
    m.bool_value = i % 2 == 0
    m.byte_value = bytes([0x10 + i])
    m.char_value = 0x41 + i
    m.float32_value = 1.5 + i
    m.float64_value = -2.25 * i
    m.int8_value = -5 - i
    m.uint8_value = 200 + i
    m.int16_value = -1000 - i
    m.uint16_value = 60000 + i
    m.int32_value = -100000 - i
    m.uint32_value = 4000000000 + i
    m.int64_value = -(1 << 40) - i
    m.uint64_value = (1 << 63) + i
    return m


def copy_defaults(m):
    for f in FIELDS + ['string']:
        if hasattr(m, f + '_values_default'):
            setattr(m, f + '_values_default', getattr(m, f + '_values'))
    m.alignment_check = 0x12345678
    return m


def arrays():
    m = Arrays()
    m.bool_values = [True, False, True]
    m.byte_values = [b'\x00', b'\x7f', b'\xff']
    m.char_values = [0, 65, 255]
    m.float32_values = [1.125, -0.5, 65536.0]
    m.float64_values = [1.2345, 0.0, -1e300]
    m.int8_values = [-128, 0, 127]
    m.uint8_values = [0, 1, 255]
    m.int16_values = [-32768, 5, 32767]
    m.uint16_values = [0, 2, 65535]
    m.int32_values = [-2147483648, 7, 2147483647]
    m.uint32_values = [0, 9, 4294967295]
    m.int64_values = [-(1 << 63), 11, (1 << 63) - 1]
    m.uint64_values = [0, 13, (1 << 64) - 1]
    m.string_values = ['', 'zwei', 'drei und mehr']
    m.basic_types_values = [basic(BasicTypes(), i) for i in range(3)]
    m.constants_values = [Constants() for _ in range(3)]
    m.defaults_values = [basic(Defaults(), 10 + i) for i in range(3)]
    return copy_defaults(m)


def bounded_sequences():
    m = BoundedSequences()
    m.bool_values = [True]
    m.byte_values = []
    m.char_values = [1, 2, 3]
    m.float32_values = [2.5, -1.0]
    m.float64_values = [1e-300]
    m.int8_values = [-1, -2]
    m.uint8_values = [250]
    m.int16_values = []
    m.uint16_values = [65535, 0, 1]
    m.int32_values = [-7]
    m.uint32_values = [8, 9]
    m.int64_values = [-1]
    m.uint64_values = []
    m.string_values = ['a', '', 'ccc']
    m.basic_types_values = [basic(BasicTypes(), 5)]
    m.constants_values = [Constants(), Constants()]
    m.defaults_values = []
    return copy_defaults(m)


def strings():
    m = Strings()
    m.string_value = 'unbounded ünïcode'
    m.bounded_string_value = '0123456789abcdefghijkl'
    return m


def wstrings():
    m = WStrings()
    m.wstring_value = 'aé😀 wide'
    m.array_of_wstrings = ['x', '', 'yz😀']
    m.bounded_sequence_of_wstrings = ['q', 'ü']
    m.unbounded_sequence_of_wstrings = ['ab', 'c', '', 'd']
    return m


VALUES = {'Arrays': arrays(), 'BoundedSequences': bounded_sequences(), 'Strings': strings(),
          'WStrings': wstrings()}

if sys.argv[1:] == ['check']:
    for line in sys.stdin:
        name, hex_bytes = line.split()
        expected = VALUES[name]
        decoded = deserialize_message(bytes.fromhex(hex_bytes), type(expected))
        # repr: numpy arrays (array fields) do not compare to one bool.
        wrong = [f for f in expected.get_fields_and_field_types()
                 if repr(getattr(decoded, f)) != repr(getattr(expected, f))]
        print(name, 'ok' if decoded == expected and not wrong else 'differs: ' + ' '.join(wrong))
else:
    for name, msg in VALUES.items():
        print(name, serialize_message(msg).hex())
