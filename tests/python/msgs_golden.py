#!/usr/bin/env python3
"""Independent CDR encoders/decoders for sweetspot's message tests.

Reads JSON lines on stdin, one per case: {"type": "pkg/msg/Type", "json": {...}, "schema": "<ros2msg text>",
"rust_cdr": "<hex>"}. For each, prints one JSON line:
  {"rosbags": "<hex>", "mcap": "<hex>", "decoded": {...}}
- rosbags: the message built from the .msg files under <repo>/msgs alone (rosbags.typesys.get_types_from_msg)
  and serialised with rosbags' serialize_cdr;
- mcap:    the message serialised by mcap-ros2-support from the schema text sweetspot generated (so the schema
  text must be a valid rosbag2 ros2msg definition);
- decoded: sweetspot's own bytes (rust_cdr) decoded by mcap-ros2-support with that schema, as JSON (NaN as null).

Usage: msgs_golden.py REPO_ROOT < cases.jsonl
"""
import json
import math
import sys
from pathlib import Path

import numpy as np
from mcap_ros2._dynamic import generate_dynamic, serialize_dynamic
from rosbags.typesys import Stores, get_typestore, get_types_from_msg
from rosbags.typesys.store import Nodetype

FLOATS = {"float32", "float64"}


def load_typestore(repo: Path):
    store = get_typestore(Stores.EMPTY)
    types = {}
    for msg in sorted(repo.glob("msgs/**/msg/*.msg")):
        pkg = msg.parent.parent.name
        types.update(get_types_from_msg(msg.read_text(), f"{pkg}/msg/{msg.stem}"))
    store.register(types)
    return store


def to_float(v):
    if v is None:
        return math.nan
    if v == "inf":
        return math.inf
    if v == "-inf":
        return -math.inf
    return float(v)


def build_value(store, desc, value, as_object):
    """Converts JSON into what rosbags (as_object=True) or mcap-ros2-support (False) serialise."""
    node, details = desc
    if node == Nodetype.BASE:
        prim = details[0]
        if prim in FLOATS:
            return to_float(value)
        if prim in ("string", "wstring"):
            return value
        if prim == "bool":
            return bool(value)
        return int(value)
    if node == Nodetype.NAME:
        return build_message(store, details, value, as_object)
    # ARRAY or SEQUENCE
    inner, _size = details
    items = [build_value(store, inner, v, as_object) for v in value]
    if as_object and inner[0] == Nodetype.BASE and inner[1][0] not in ("string", "wstring"):
        dtype = {
            "bool": np.bool_, "byte": np.uint8, "char": np.uint8, "int8": np.int8, "uint8": np.uint8,
            "int16": np.int16, "uint16": np.uint16, "int32": np.int32, "uint32": np.uint32,
            "int64": np.int64, "uint64": np.uint64, "float32": np.float32, "float64": np.float64,
        }[inner[1][0]]
        return np.array(items, dtype=dtype)
    return items


def build_message(store, typename, value, as_object):
    _consts, fields = store.fielddefs[typename]
    kwargs = {}
    for name, desc in fields:
        kwargs[name] = build_value(store, desc, value[name], as_object)
    if as_object:
        return store.types[typename](**kwargs)
    return kwargs


def plain(v):
    """mcap-ros2-support decoded value → JSON (NaN as null, ±inf as strings, like sweetspot)."""
    if isinstance(v, float):
        if math.isnan(v):
            return None
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return v
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, (bytes, bytearray)):
        return list(v)
    if hasattr(v, "__slots__"):
        return {k: plain(getattr(v, k)) for k in v.__slots__}
    return v


def main():
    repo = Path(sys.argv[1])
    store = load_typestore(repo)
    for line in sys.stdin:
        if not line.strip():
            continue
        case = json.loads(line)
        typename, value, schema = case["type"], case["json"], case["schema"]
        obj = build_message(store, typename, value, as_object=True)
        rosbags_hex = store.serialize_cdr(obj, typename).hex()
        encoders = serialize_dynamic(typename, schema)
        mcap_hex = encoders[typename](build_message(store, typename, value, as_object=False)).hex()
        decoders = generate_dynamic(typename, schema)
        decoded = plain(decoders[typename](bytes.fromhex(case["rust_cdr"])))
        print(json.dumps({"rosbags": rosbags_hex, "mcap": mcap_hex, "decoded": decoded}), flush=True)


if __name__ == "__main__":
    main()
