#!/usr/bin/python3
"""Prints, as JSON, every numeric field of every message of a ROS 1 bag as
Debian's python3-rosbag decodes it (genpy classes generated from the bag's
own message definitions): {topic: {field: [value per message]}}.

Fields are named as RoverLab names its channels (docs/log-format.md): '.'
between levels, array elements by index, numeric arrays after a `string[]
name` field of the same length by its entries, elements that have a
`child_frame_id` (tf2_msgs/TFMessage's transforms) by it, without a leading
'/'; time and duration as seconds,
bool as 0/1; strings skipped; arrays longer than MAX_ARRAY skipped. The
roll/pitch/yaw RoverLab derives from quaternions are not fields and not here.

    /usr/bin/python3 rosbag_numeric_fields.py FILE.bag [MAX_ARRAY]
"""
import json
import sys

import genpy
import rosbag

MAX_ARRAY = int(sys.argv[2]) if len(sys.argv) > 2 else 64


def numeric(value):
    if isinstance(value, bool):
        return 1.0 if value else 0.0
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, (genpy.Time, genpy.Duration)):
        return value.secs + value.nsecs * 1e-9
    return None


def flatten(message, prefix, out):
    labels = None
    for slot, slot_type in zip(message.__slots__, message._slot_types):
        value = getattr(message, slot)
        name = prefix + slot
        if slot_type == "string[]" and slot == "name":
            labels = [str(v).replace("/", "_") for v in value] if len(value) <= MAX_ARRAY else None
            continue
        if isinstance(value, (list, tuple, bytes)):
            if len(value) > MAX_ARRAY or slot_type.startswith("string"):
                continue
            if isinstance(value, bytes):  # uint8[] and char[] come as bytes
                value = list(value)
            for i, element in enumerate(value):
                label = labels[i] if labels is not None and len(labels) == len(value) and labels[i] else str(i)
                frame = getattr(element, "child_frame_id", None)
                if isinstance(frame, str) and frame.lstrip("/"):
                    label = frame.lstrip("/").replace("/", "_")
                if hasattr(element, "__slots__"):
                    flatten(element, name + "." + label + ".", out)
                else:
                    out[name + "." + label] = numeric(element)
            continue
        if hasattr(value, "__slots__") and not isinstance(value, (genpy.Time, genpy.Duration)):
            flatten(value, name + ".", out)
            continue
        number = numeric(value)
        if number is not None:
            out[name] = number


topics = {}
with rosbag.Bag(sys.argv[1]) as bag:
    for topic, message, _ in bag.read_messages():
        fields = {}
        flatten(message, "", fields)
        columns = topics.setdefault(topic, {})
        for name, value in fields.items():
            columns.setdefault(name, []).append(value)
json.dump(topics, sys.stdout)
