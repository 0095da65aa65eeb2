#!/usr/bin/env python3
"""Independent check of a sweetspot bag (a rosbag2 directory of MCAP files).

Reads the bag twice, with two readers that share no code with sweetspot:
  1. PyPI `mcap` + `mcap-ros2-support`: every file, every message decoded from the schemas embedded in the
     file alone (no type knowledge here); also checks the ros2 profile conventions (profile, encodings,
     offered_qos_profiles, the `rosbag2` metadata record, summary present).
  2. `rosbags` (rosbags.rosbag2.Reader): opens the directory through metadata.yaml, registers the types from
     the stored message definitions and deserializes every message.
  3. metadata.yaml read as plain YAML: `ros_distro` and each topic's `type_description_hash` (the MCAP channels'
     `topic_type_hash` is reported by reader 1).
Prints one JSON object: per reader, per topic: type, count, and the first and last message as plain data.
Exits non-zero with a message on the first violation.
"""
import json
import math
import sys
from pathlib import Path


def plain(value):
    """Decoded message -> JSON-able data (both readers' message classes)."""
    if isinstance(value, (bool, int, str)) or value is None:
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if hasattr(value, "tolist"):
        return plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "__dataclass_fields__"):
        return {k: plain(getattr(value, k)) for k in value.__dataclass_fields__
                if k != "__msgtype__" and not k.isupper()}
    # Message constants (e.g. STATUS_OK) are class-level in one reader and instance-level in the other:
    # fields are lower case in ROS 2, constants upper case, so keep only fields.
    if hasattr(value, "__slots__"):
        return {k: plain(getattr(value, k)) for k in value.__slots__ if not k.isupper()}
    if hasattr(value, "__dict__"):
        return {k: plain(v) for k, v in vars(value).items() if not k.startswith("_") and not k.isupper()}
    return repr(value)


def load_yaml(text):
    # ruamel.yaml comes with rosbags (PyYAML is not among the peers).
    from ruamel.yaml import YAML
    return YAML(typ="safe").load(text)


def fail(msg):
    print(f"check_bag.py: {msg}", file=sys.stderr)
    sys.exit(1)


def check_with_mcap(bag: Path):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    topics = {}
    files = sorted(bag.glob("*.mcap"), key=lambda p: int(p.stem.rsplit("_", 1)[1]))
    if not files:
        fail(f"no .mcap files in {bag}")
    for path in files:
        with open(path, "rb") as f:
            reader = make_reader(f, decoder_factories=[DecoderFactory()])
            header = reader.get_header()
            if header.profile != "ros2":
                fail(f"{path.name}: profile {header.profile!r}, expected 'ros2'")
            summary = reader.get_summary()
            if summary is None:
                fail(f"{path.name}: no summary section")
            for channel in summary.channels.values():
                schema = summary.schemas[channel.schema_id]
                if schema.encoding != "ros2msg":
                    fail(f"{channel.topic}: schema encoding {schema.encoding!r}")
                if channel.message_encoding != "cdr":
                    fail(f"{channel.topic}: message encoding {channel.message_encoding!r}")
                qos = channel.metadata.get("offered_qos_profiles")
                if not qos:
                    fail(f"{channel.topic}: no offered_qos_profiles")
                profiles = load_yaml(qos)
                if not isinstance(profiles, list) or not profiles:
                    fail(f"{channel.topic}: offered_qos_profiles is not a YAML list: {qos!r}")
                for key in ("history", "depth", "reliability", "durability", "deadline", "lifespan",
                            "liveliness", "liveliness_lease_duration", "avoid_ros_namespace_conventions"):
                    if key not in profiles[0]:
                        fail(f"{channel.topic}: offered_qos_profiles lacks {key}")
            names = [m.name for m in reader.iter_metadata()]
            if "rosbag2" not in names:
                fail(f"{path.name}: no 'rosbag2' metadata record (found {names})")
            for md in reader.iter_metadata():
                if md.name == "rosbag2":
                    body = load_yaml(md.metadata["serialized_metadata"])
                    if body.get("storage_identifier") != "mcap":
                        fail(f"{path.name}: rosbag2 record has no storage_identifier mcap")
            for schema, channel, message, decoded in reader.iter_decoded_messages():
                t = topics.setdefault(channel.topic, {"type": schema.name, "count": 0, "first": None, "last": None,
                                                      "files": [],
                                                      "topic_type_hash": channel.metadata.get("topic_type_hash")})
                t["count"] += 1
                data = plain(decoded)
                if t["first"] is None:
                    t["first"] = data
                t["last"] = data
                if path.name not in t["files"]:
                    t["files"].append(path.name)
    return {"files": [p.name for p in files], "topics": topics}


def check_with_rosbags(bag: Path):
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore, get_types_from_msg

    typestore = get_typestore(Stores.EMPTY)
    topics = {}
    with Reader(bag) as reader:
        types = {}
        for conn in reader.connections:
            if not conn.msgdef.data:
                fail(f"rosbags: {conn.topic} has no stored message definition")
            types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
        typestore.register(types)
        for conn in reader.connections:
            qos = conn.ext.offered_qos_profiles
            if not qos:
                fail(f"rosbags: {conn.topic} has no offered QoS")
            topics[conn.topic] = {"type": conn.msgtype, "count": 0, "first": None, "last": None,
                                  "metadata_count": conn.msgcount,
                                  "reliability": str(qos[0].reliability.name).lower(),
                                  "durability": str(qos[0].durability.name).lower(),
                                  "depth": qos[0].depth}
        for conn, _timestamp, raw in reader.messages():
            msg = typestore.deserialize_cdr(raw, conn.msgtype)
            t = topics[conn.topic]
            t["count"] += 1
            data = plain(msg)
            if t["first"] is None:
                t["first"] = data
            t["last"] = data
        meta = {"message_count": reader.message_count, "duration": reader.duration,
                "start_time": reader.start_time, "end_time": reader.end_time,
                "custom_data": reader.storage.metadata.custom, "ros_distro": reader.ros_distro}
    for topic, t in topics.items():
        if t["count"] != t["metadata_count"]:
            fail(f"rosbags: {topic}: metadata.yaml says {t['metadata_count']} messages, read {t['count']}")
    return {"topics": topics, "metadata": meta}


def check_metadata_yaml(bag: Path):
    """metadata.yaml as plain YAML: ros_distro and each topic's type_description_hash."""
    info = load_yaml((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    hashes = {t["topic_metadata"]["name"]: t["topic_metadata"].get("type_description_hash")
              for t in info.get("topics_with_message_count") or []}
    return {"ros_distro": info.get("ros_distro"), "type_description_hash": hashes}


def main():
    if len(sys.argv) != 2:
        fail("usage: check_bag.py BAG_DIR")
    bag = Path(sys.argv[1])
    result = {"mcap": check_with_mcap(bag), "rosbags": check_with_rosbags(bag),
              "metadata_yaml": check_metadata_yaml(bag)}
    a, b = result["mcap"]["topics"], result["rosbags"]["topics"]
    for topic in set(a) | set(b):
        if topic not in a or topic not in b or a[topic]["count"] != b[topic]["count"]:
            fail(f"readers disagree on {topic}: mcap {a.get(topic, {}).get('count')} "
                 f"rosbags {b.get(topic, {}).get('count')}")
        if a[topic]["first"] != b[topic]["first"] or a[topic]["last"] != b[topic]["last"]:
            fail(f"readers decode {topic} differently: {a[topic]['first']} vs {b[topic]['first']}")
    json.dump(result, sys.stdout)


if __name__ == "__main__":
    main()
