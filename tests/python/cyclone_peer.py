#!/usr/bin/env python3
"""A Cyclone DDS peer that speaks ROS 2 to sweetspot, with types built from the .msg files alone.

Every msg/*.msg under --msgs (default: <repo>/msgs) is parsed at start-up into a cyclonedds IdlStruct with the
DDS name ROS 2 uses ('sweetspot_msgs::msg::dds_::Swing_', members with a trailing '_'), final extensibility and
plain XCDR1 encoding, as rmw_cyclonedds_cpp does. Topics get the ROS 2 'rt' prefix.

  cyclone_peer.py pub --type sweetspot_msgs/msg/Swing --topic /rig3/swing --json '[{...}, ...]' \
      [--qos swing] [--wait-subscribers N] [--timeout S] [--keep-alive S]
  cyclone_peer.py sub --type sweetspot_msgs/msg/ExitVelocity --topic /exit_velocity --count N [--timeout S] \
      [--qos results] [--ready-file F] [--wait-publishers N]

  cyclone_peer.py endpoints --topic /swing --count N [--timeout S]

`--loopback` (before the command) keeps Cyclone on 127.0.0.1 (sets CYCLONEDDS_URI unless already set).

`pub` prints "published N" once everything is written (then waits for acknowledgments and --keep-alive); `sub` prints one JSON object per received message (NaN as null) and exits
non-zero if fewer than --count arrive before --timeout. `endpoints` reads Cyclone's built-in discovery topics
(DCPSPublication / DCPSSubscription) and prints one JSON object per remote writer or reader of the topic
({"kind", "topic", "type", "user_data"}), exiting non-zero if fewer than --count are seen before --timeout. `--dds-type-name` overrides the DDS type name (a
control: Cyclone matches readers and writers by exact type name, so a wrong one must receive nothing). The domain comes from ROS_DOMAIN_ID; restrict Cyclone to
loopback with CYCLONEDDS_URI (see loopback_config()). Fields left out of a JSON message take the .msg default
(0, '', [], or the declared default value).
"""
import argparse
import json
import math
import os
import re
import sys
import time
import types as pytypes
from dataclasses import dataclass, fields as dc_fields
from pathlib import Path

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct, annotations, types
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

PRIMITIVES = {
    "bool": bool,
    "byte": types.uint8,
    "char": types.uint8,
    "int8": types.int8,
    "uint8": types.uint8,
    "int16": types.int16,
    "uint16": types.uint16,
    "int32": types.int32,
    "uint32": types.uint32,
    "int64": types.int64,
    "uint64": types.uint64,
    "float32": types.float32,
    "float64": types.float64,
    "string": str,
}
FLOATS = {"float32", "float64"}
INTS = {"byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"}

# QoS of sweetspot's topics (reliability is always reliable): (transient_local, depth).
QOS = {
    "params": (True, 16),
    "swing": (False, 1000),
    "results": (False, 100),
    "sweet_spot": (True, 16),
    "diagnostics": (False, 10),
}


def loopback_config():
    """A CYCLONEDDS_URI that keeps Cyclone on 127.0.0.1 and finds same-host peers by unicast too."""
    return (
        "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>"
        "<NetworkInterface name=\"lo\" multicast=\"true\"/></Interfaces>"
        "<AllowMulticast>true</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>50</MaxAutoParticipantIndex>"
        "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"
    )


class Field:
    def __init__(self, name, base, array, bound, default):
        self.name, self.base, self.array, self.bound, self.default = name, base, array, bound, default


def parse_msg(text, pkg):
    """Fields of a .msg file: (name, base type 'float64' | 'string' | 'pkg/Type', array kind, bound, default)."""
    out = []
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        line = strip_comment(line)
        type_tok, _, rest = line.partition(" ")
        rest = rest.strip()
        name = re.match(r"[A-Za-z0-9_]+", rest).group(0)
        after = rest[len(name):].strip()
        if after.startswith("="):
            continue  # a constant
        m = re.fullmatch(r"([A-Za-z0-9_/]+)(<=\d+)?(\[(<=)?(\d*)\])?", type_tok)
        if not m:
            raise ValueError(f"cannot parse type {type_tok!r}")
        base = m.group(1)
        if m.group(3) is None:
            array, bound = None, None
        elif m.group(5) == "":
            array, bound = "seq", None
        elif m.group(4):
            array, bound = "seq", int(m.group(5))
        else:
            array, bound = "array", int(m.group(5))
        if base not in PRIMITIVES:
            base = base if "/" in base else f"{pkg}/{base}"
            base = base.replace("/msg/", "/")
        out.append(Field(name, base, array, bound, parse_default(after, base, array) if after else None))
    return out


def strip_comment(line):
    quote = None
    for i, c in enumerate(line):
        if quote:
            if c == quote:
                quote = None
        elif c in "\"'":
            quote = c
        elif c == "#":
            return line[:i].strip()
    return line


def parse_default(text, base, array):
    def scalar(s):
        s = s.strip()
        if base == "string":
            return s[1:-1] if s[:1] in "\"'" else s
        if base == "bool":
            return s.lower() in ("true", "1")
        return float(s) if base in FLOATS else int(s)

    if array:
        inner = text.strip()[1:-1]
        return [scalar(x) for x in inner.split(",")] if inner.strip() else []
    return scalar(text)


class TypeSystem:
    """cyclonedds classes for every .msg under a directory."""

    def __init__(self, msgs_dir):
        self.specs = {}
        for path in sorted(Path(msgs_dir).glob("**/msg/*.msg")):
            pkg = path.parent.parent.name
            self.specs[f"{pkg}/{path.stem}"] = parse_msg(path.read_text(), pkg)
        self.classes = {}

    @staticmethod
    def key(type_name):
        return type_name.replace("/msg/", "/")

    def cls(self, type_name):
        key = self.key(type_name)
        if key in self.classes:
            return self.classes[key]
        pkg, name = key.split("/")
        annotations_ = {}
        for f in self.specs[key]:
            annotations_[f.name + "_"] = self.field_type(f)

        def body(ns):
            ns["__annotations__"] = annotations_

        cls = pytypes.new_class(f"{name}_", (IdlStruct,), {"typename": f"{pkg}::msg::dds_::{name}_"}, body)
        cls = dataclass(annotations.final(cls))
        self.classes[key] = cls
        return cls

    def element_type(self, base):
        return PRIMITIVES[base] if base in PRIMITIVES else self.cls(base)

    def field_type(self, f):
        t = self.element_type(f.base)
        if f.base == "string" and f.array is None and f.bound:
            return types.bounded_str[f.bound]
        if f.array == "seq":
            return types.sequence[t, f.bound] if f.bound else types.sequence[t]
        if f.array == "array":
            return types.array[t, f.bound]
        return t

    # JSON <-> objects -----------------------------------------------------------------------------------

    def scalar_from_json(self, base, v):
        if base in FLOATS:
            if v is None or (isinstance(v, str) and v.lower() in ("nan", "")):
                return math.nan
            if v in ("inf", "-inf"):
                return float(v)
            return float(v)
        if base in INTS:
            return int(v)
        if base == "bool":
            return bool(v)
        if base == "string":
            return str(v)
        return self.from_json(base, v)

    def default_of(self, f):
        if f.default is not None:
            return f.default
        if f.array == "array":
            return [self.default_scalar(f.base) for _ in range(f.bound)]
        if f.array == "seq":
            return []
        return self.default_scalar(f.base)

    def default_scalar(self, base):
        if base in FLOATS:
            return 0.0
        if base in INTS:
            return 0
        if base == "bool":
            return False
        if base == "string":
            return ""
        return self.from_json(base, {})

    def from_json(self, type_name, obj):
        key = self.key(type_name)
        spec = self.specs[key]
        unknown = set(obj) - {f.name for f in spec}
        if unknown:
            raise ValueError(f"{key} has no field(s) {sorted(unknown)}")
        kwargs = {}
        for f in spec:
            if f.name in obj:
                v = obj[f.name]
                if f.array:
                    v = [self.scalar_from_json(f.base, x) for x in v]
                else:
                    v = self.scalar_from_json(f.base, v)
            else:
                v = self.default_of(f)
            kwargs[f.name + "_"] = v
        return self.cls(key)(**kwargs)

    def to_json(self, type_name, value):
        key = self.key(type_name)
        out = {}
        for f in self.specs[key]:
            v = getattr(value, f.name + "_")
            if f.array:
                out[f.name] = [self.scalar_to_json(f.base, x) for x in v]
            else:
                out[f.name] = self.scalar_to_json(f.base, v)
        return out

    def scalar_to_json(self, base, v):
        if base in FLOATS:
            v = float(v)
            if math.isnan(v):
                return None
            if math.isinf(v):
                return "inf" if v > 0 else "-inf"
            return v
        if base in INTS:
            return int(v)
        if base in ("bool", "string"):
            return v
        return self.to_json(base, v)


def make_qos(name, keep_alive_writer=False):
    transient_local, depth = QOS[name]
    policies = [
        Policy.Reliability.Reliable(duration(seconds=10)),
        Policy.History.KeepLast(depth),
        Policy.DataRepresentation(use_cdrv0_representation=True),
        Policy.Durability.TransientLocal if transient_local else Policy.Durability.Volatile,
    ]
    return Qos(*policies)


def endpoints(domain, dds_topic, count, timeout):
    """Prints the remote writers and readers of `dds_topic` as discovery announces them (see the module doc)."""
    from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription

    dp = DomainParticipant(domain)
    # BuiltinDataReader: a plain DataReader on a built-in topic crashes cyclonedds 11's take().
    readers = [("writer", BuiltinDataReader(dp, BuiltinTopicDcpsPublication)),
               ("reader", BuiltinDataReader(dp, BuiltinTopicDcpsSubscription))]
    seen = set()
    deadline = time.monotonic() + timeout
    while len(seen) < count:
        if time.monotonic() > deadline:
            print(f"saw {len(seen)} of {count} endpoints on {dds_topic}", file=sys.stderr)
            return 1
        for kind, reader in readers:
            for sample in reader.take(N=64):
                if not getattr(sample, "topic_name", None) or sample.topic_name != dds_topic or sample.key in seen:
                    continue
                seen.add(sample.key)
                user_data = next((p.data for p in sample.qos if type(p).__name__ == "Userdata"), b"")
                print(json.dumps({"kind": kind, "topic": sample.topic_name, "type": sample.type_name,
                                  "user_data": user_data.decode("utf-8", "replace")}), flush=True)
        time.sleep(0.02)
    return 0


def wait_matched(matched, wanted, timeout, what):
    """Waits until `matched()` lists `wanted` remote endpoints (False, with a message, after `timeout` s).

    Matching is seen by each side on its own: once we see it, the other side gets 300 ms to see it too.
    """
    deadline = time.monotonic() + timeout
    while len(matched()) < wanted:
        if time.monotonic() > deadline:
            print(f"only {len(matched())} of {wanted} {what}", file=sys.stderr)
            return False
        time.sleep(0.02)
    if wanted:
        time.sleep(0.3)
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--msgs", default=str(Path(__file__).resolve().parents[2] / "msgs"))
    ap.add_argument("--loopback", action="store_true", help="keep Cyclone on 127.0.0.1")
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("pub")
    p.add_argument("--type", required=True)
    p.add_argument("--topic", required=True)
    p.add_argument("--json", required=True, help="a JSON object or list of objects")
    p.add_argument("--qos", default="swing", choices=sorted(QOS))
    p.add_argument("--wait-subscribers", type=int, default=0)
    p.add_argument("--timeout", type=float, default=30.0)
    p.add_argument("--keep-alive", type=float, default=1.0)
    s = sub.add_parser("sub")
    s.add_argument("--type", required=True)
    s.add_argument("--topic", required=True)
    s.add_argument("--count", type=int, default=1)
    s.add_argument("--timeout", type=float, default=30.0)
    s.add_argument("--qos", default="results", choices=sorted(QOS))
    s.add_argument("--ready-file", help="touch this file once the reader exists (and has matched --wait-publishers)")
    s.add_argument("--wait-publishers", type=int, default=0,
                   help="before the ready file, wait until the reader has matched this many remote writers")
    s.add_argument("--dds-type-name", help="use this DDS type name instead of the ROS 2 one")
    e = sub.add_parser("endpoints")
    e.add_argument("--topic", required=True)
    e.add_argument("--count", type=int, default=1)
    e.add_argument("--timeout", type=float, default=30.0)
    args = ap.parse_args()
    if args.loopback:
        os.environ.setdefault("CYCLONEDDS_URI", loopback_config())
    domain = int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)
    if args.cmd == "endpoints":
        return endpoints(domain, "rt" + args.topic, args.count, args.timeout)

    ts = TypeSystem(args.msgs)
    cls = ts.cls(args.type)
    if getattr(args, "dds_type_name", None):
        layout = dict(cls.__annotations__)
        cls = dataclass(annotations.final(pytypes.new_class(
            "Renamed_", (IdlStruct,), {"typename": args.dds_type_name},
            lambda ns: ns.update({"__annotations__": layout}))))
    dp = DomainParticipant(domain)
    topic = Topic(dp, "rt" + args.topic, cls)

    if args.cmd == "pub":
        data = json.loads(args.json)
        messages = [ts.from_json(args.type, m) for m in (data if isinstance(data, list) else [data])]
        writer = DataWriter(dp, topic, qos=make_qos(args.qos))
        # A volatile reader drops samples from a writer it has not matched yet.
        if not wait_matched(writer.get_matched_subscriptions, args.wait_subscribers, args.timeout,
                            f"subscriptions matched on {args.topic}"):
            return 2
        for m in messages:
            writer.write(m)
        print(f"published {len(messages)}", flush=True)
        writer.wait_for_acks(duration(seconds=args.timeout))
        time.sleep(args.keep_alive)
        return 0

    reader = DataReader(dp, topic, qos=make_qos(args.qos))
    # A volatile reader gets nothing a writer sent before the two matched: the caller starts sending only after
    # the ready file, so the file waits for the match (on a loaded machine discovery can take seconds).
    if not wait_matched(reader.get_matched_publications, args.wait_publishers, args.timeout,
                        f"publications matched on {args.topic}"):
        return 2
    if args.ready_file:
        Path(args.ready_file).touch()
    received = 0
    deadline = time.monotonic() + args.timeout
    while received < args.count:
        if time.monotonic() > deadline:
            print(f"timed out on {args.topic} after {received} of {args.count} messages", file=sys.stderr)
            return 1
        for sample in reader.take(N=args.count - received):
            if not getattr(sample, "sample_info", None) or sample.sample_info.valid_data:
                print(json.dumps(ts.to_json(args.type, sample)), flush=True)
                received += 1
        time.sleep(0.01)
    return 0


if __name__ == "__main__":
    sys.exit(main())
