"""RIHS01 type hashes by an implementation independent of horus-ros: rosbags
(https://gitlab.com/ternaris/rosbags), from its own ROS 2 Jazzy message definitions
(`Stores.ROS2_JAZZY`) and its own REP-2011 hashing (`Typestore.hash_rihs01`).

Reads one type name a line on stdin (`std_msgs/msg/String`), prints `<name> <RIHS01_...>` for
each, or `<name> unknown` when the Jazzy store does not define it.

One rule of rosidl is applied to rosbags' definitions first: the hash is taken over the type
description of the `.idl` that rosidl_adapter makes from a `.msg`, where the `.msg` type `char`
is `uint8` (rosidl_adapter/msg/__init__.py `MSG_TYPE_TO_IDL`); rosbags keeps it a `char`
(FIELD_TYPE_CHAR), which gives std_msgs/Char, rmw_dds_common/Gid and ServiceEventInfo other
hashes than a ROS 2 build.
"""

import sys

from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.base import Nodetype


def as_idl(desc):
    """A field description with rosidl_adapter's `.msg` -> `.idl` type mapping applied."""
    kind, rest = desc
    if kind == Nodetype.BASE and rest[0] == 'char':
        return kind, ('uint8', rest[1])
    if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        inner, count = rest
        return kind, (as_idl(inner), count)
    return desc


def main() -> int:
    store = get_typestore(Stores.ROS2_JAZZY)
    store.fielddefs = {
        name: (consts, [(field, as_idl(desc)) for field, desc in fields])
        for name, (consts, fields) in store.fielddefs.items()
    }
    for line in sys.stdin:
        name = line.strip()
        if not name:
            continue
        if name in store.fielddefs:
            print(name, store.hash_rihs01(name))
        else:
            print(name, 'unknown')
    return 0


if __name__ == '__main__':
    sys.exit(main())
