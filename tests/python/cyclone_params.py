#!/usr/bin/env python3
"""Calls a ROS 2 node's parameter services from Cyclone DDS, with types built from the rcl_interfaces .msg/.srv
files alone (msgs/ros_interfaces/rcl_interfaces): a client that shares no code with ros2-client.

  cyclone_params.py [--loopback] call --node /sweetspot --calls '[{"service": "list_parameters",
      "request": {"prefixes": [], "depth": 0}}, ...]' [--timeout S]

Each service `S` of the node `/ns/name` is a pair of DDS topics, as ROS 2 names them: requests on
'rq/ns/name/SRequest' with type 'rcl_interfaces::srv::dds_::S_Request_', replies on 'rr/ns/name/SReply' with
'..._Response_' (S in CamelCase for the type, as in the .srv file name). Requests go out as the plain request
struct (the "enhanced" request/reply mapping of DDS-RPC, which the node's ros2-client server uses: no header in the
payload; the request is identified by its sample identity). The calls are made one after the other, each waiting
for its reply, so a reply belongs to the one request in flight. With --mapping cyclone the requests and replies
carry rmw_cyclonedds_cpp's header `{uint64 guid; int64 seq}` in front of their fields, as a client on that RMW
sends them (cyclone_service.py says more); a reply whose header is not its request's makes the exit status 3.

Output, one JSON object per line: first {"constants": {"rcl_interfaces/ParameterType": {"PARAMETER_BOOL": 1, ...},
...}} (the constants of every .msg/.srv read, from their text), then for each call
{"service": S, "request": {...}, "response": {...}} with the fields of the .srv (NaN as null). Exits non-zero if a
service never matches or a reply does not come within --timeout. Request fields left out take their .srv
default. The domain comes from ROS_DOMAIN_ID; --loopback keeps Cyclone on 127.0.0.1 (cyclone_peer.py).
"""
import argparse
import json
import os
import re
import sys
import time
import types as pytypes
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cyclone_peer import TypeSystem, loopback_config, parse_msg, strip_comment, wait_matched  # noqa: E402
from cyclone_service import CYCLONE_HEADER  # noqa: E402

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct, annotations  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402


def constants(text):
    """The constants of a .msg (or one half of a .srv): {NAME: value} for 'TYPE NAME=VALUE' lines."""
    out = {}
    for raw in text.splitlines():
        line = strip_comment(raw.strip())
        m = re.fullmatch(r"([A-Za-z0-9_/]+)\s+([A-Z][A-Z0-9_]*)\s*=\s*(.+)", line)
        if m:
            type_, name, value = m.groups()
            if type_ == "string":
                out[name] = value.strip()[1:-1] if value.strip()[:1] in "\"'" else value.strip()
            elif type_.startswith("float"):
                out[name] = float(value)
            elif type_ == "bool":
                out[name] = value.strip().lower() in ("true", "1")
            else:
                out[name] = int(value)
    return out


class ServiceTypes(TypeSystem):
    """cyclone_peer's TypeSystem plus the request and response of every srv/*.srv, named '<pkg>/<Srv>_Request'
    and '<pkg>/<Srv>_Response' with the DDS names '<pkg>::srv::dds_::<Srv>_Request_' / '..._Response_'."""

    def __init__(self, msgs_dir, mapping="enhanced"):
        super().__init__(msgs_dir)
        self.srv_keys = set()
        header = CYCLONE_HEADER if mapping == "cyclone" else []
        self.constants = {}
        for path in sorted(Path(msgs_dir).glob("**/msg/*.msg")):
            found = constants(path.read_text())
            if found:
                self.constants[f"{path.parent.parent.name}/{path.stem}"] = found
        for path in sorted(Path(msgs_dir).glob("**/srv/*.srv")):
            pkg = path.parent.parent.name
            halves = re.split(r"^---\s*$", path.read_text(), maxsplit=1, flags=re.M)
            if len(halves) != 2:
                raise ValueError(f"{path}: no '---' between request and response")
            for half, suffix in zip(halves, ("Request", "Response")):
                key = f"{pkg}/{path.stem}_{suffix}"
                self.specs[key] = header + parse_msg(half, pkg)
                self.srv_keys.add(key)
                found = constants(half)
                if found:
                    self.constants[key] = found

    def cls(self, type_name):
        key = self.key(type_name)
        if key not in self.srv_keys:
            return super().cls(type_name)
        if key in self.classes:
            return self.classes[key]
        pkg, name = key.split("/")
        layout = {f.name + "_": self.field_type(f) for f in self.specs[key]}
        cls = pytypes.new_class(f"{name}_", (IdlStruct,), {"typename": f"{pkg}::srv::dds_::{name}_"},
                                lambda ns: ns.update({"__annotations__": layout}))
        cls = dataclass(annotations.final(cls))
        self.classes[key] = cls
        return cls


def camel(service):
    """'describe_parameters' -> 'DescribeParameters' (the .srv of the node's parameter service)."""
    return "".join(part.capitalize() for part in service.split("_"))


def service_qos():
    # rclcpp's services profile: reliable, volatile, keep last 10.
    return Qos(Policy.Reliability.Reliable(duration(seconds=10)), Policy.History.KeepLast(10),
               Policy.Durability.Volatile, Policy.DataRepresentation(use_cdrv0_representation=True))


class ServiceClient:
    def __init__(self, dp, ts, node, service):
        self.ts, self.service = ts, service
        srv = camel(service)
        self.request_type, self.response_type = f"rcl_interfaces/{srv}_Request", f"rcl_interfaces/{srv}_Response"
        path = node.rstrip("/") + "/" + service
        self.writer = DataWriter(dp, Topic(dp, f"rq{path}Request", ts.cls(self.request_type)), qos=service_qos())
        self.reader = DataReader(dp, Topic(dp, f"rr{path}Reply", ts.cls(self.response_type)), qos=service_qos())

    def wait_matched(self, timeout):
        # A volatile reader drops replies from a writer it has not matched: both sides before the first call.
        return (wait_matched(self.reader.get_matched_publications, 1, timeout, f"reply writers of {self.service}")
                and wait_matched(self.writer.get_matched_subscriptions, 1, timeout,
                                 f"request readers of {self.service}"))

    def call(self, request, timeout, header=None):
        """The response to `request`; with `header` (guid, seq) the cyclone header is sent and must come back."""
        sent = dict(request, cdds_guid=header[0], cdds_seq=header[1]) if header else request
        self.writer.write(self.ts.from_json(self.request_type, sent))
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for sample in self.reader.take(N=1):
                if not getattr(sample, "sample_info", None) or sample.sample_info.valid_data:
                    response = self.ts.to_json(self.response_type, sample)
                    if header and (response.pop("cdds_guid"), response.pop("cdds_seq")) != header:
                        raise HeaderMismatch(f"{self.service}: a reply without the request's header {header}")
                    return response
            time.sleep(0.005)
        return None


class HeaderMismatch(Exception):
    pass


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--msgs", default=str(Path(__file__).resolve().parents[2] / "msgs"))
    ap.add_argument("--loopback", action="store_true", help="keep Cyclone on 127.0.0.1")
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("call")
    c.add_argument("--node", required=True, help="fully qualified node name, e.g. /sweetspot")
    c.add_argument("--calls", required=True,
                   help="JSON list of {\"service\", \"request\"}, or @PATH to read it from a file (for requests "
                        "too large for a command line)")
    c.add_argument("--timeout", type=float, default=30.0)
    c.add_argument("--mapping", choices=["enhanced", "cyclone"], default="enhanced")
    args = ap.parse_args()
    if args.loopback:
        os.environ.setdefault("CYCLONEDDS_URI", loopback_config())
    domain = int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)

    ts = ServiceTypes(args.msgs, args.mapping)
    print(json.dumps({"constants": ts.constants}), flush=True)
    calls = json.loads(Path(args.calls[1:]).read_text() if args.calls.startswith("@") else args.calls)
    dp = DomainParticipant(domain)
    clients = {}
    for call in calls:
        if call["service"] not in clients:
            clients[call["service"]] = ServiceClient(dp, ts, args.node, call["service"])
    for client in clients.values():
        if not client.wait_matched(args.timeout):
            return 2
    guid = 0x5EE7_5907_0000_0002
    for k, call in enumerate(calls):
        request = call.get("request", {})
        header = (guid, (1 << 32) + 1 + k) if args.mapping == "cyclone" else None
        try:
            response = clients[call["service"]].call(request, args.timeout, header)
        except HeaderMismatch as e:
            print(e, file=sys.stderr)
            return 3
        if response is None:
            print(f"no reply from {call['service']} within {args.timeout} s", file=sys.stderr)
            return 1
        print(json.dumps({"service": call["service"], "request": request, "response": response}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
