#!/usr/bin/env python3
"""A Cyclone DDS client of sweetspot's ~/simulate_swing service, with types built from the .srv and .msg files.

The request and response types are the two halves of msgs/sweetspot_msgs/srv/SimulateSwing.srv (split at the
`---` line), named as ROS 2 names them on DDS ('sweetspot_msgs::srv::dds_::SimulateSwing_Request_'), built with
cyclone_peer.py's TypeSystem. Requests go to 'rq<service>Request', replies come from 'rr<service>Reply', in the
"enhanced" request/reply mapping (no header in the data) that rmw_fastrtps and sweetspot use: this plain DDS
client cannot write or read the related-sample-identity parameter, so it matches each reply to its request by
exit_velocity.swing_id (every request it sends has its own).

With --mapping cyclone it speaks as a client on rmw_cyclonedds_cpp does (its rmw_node.cpp and serdata.cpp):
every request and reply starts with `cdds_request_header_t { uint64_t guid; int64_t seq; }` in the same CDR
stream as the message's fields; the client puts its own id (--guid) and a sequence number (--first-seq, then
one more per request) in the request, and keeps a reply only if the server echoed both. A reply whose header
is not the request's makes the exit status 3.

  cyclone_service.py call --service /sweetspot/simulate_swing --json '[{request}, ...]' [--timeout S]
      prints one JSON line per request, in request order: the response (NaN as null)
  cyclone_service.py call ... --frame-id-bytes N
      every request's swing.header.frame_id made N bytes long (a hostile request no command line can carry)
  cyclone_service.py call ... --json '{request}' --repeat N [--summary]
      sends N copies of the request at once, swing_id 1..N; --summary prints one JSON object instead:
      {"sent", "answered", "status_counts", "without_reason", "duplicates", "unknown"}

Exits 1 if some request got no reply before --timeout (after printing what arrived). Keep Cyclone on loopback
with --loopback (before the command), as cyclone_peer.py.
"""
import argparse
import json
import os
import sys
import time
import types as pytypes
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cyclone_peer import Field, TypeSystem, loopback_config, parse_msg, wait_matched  # noqa: E402

from cyclonedds.core import Policy, Qos  # noqa: E402
from cyclonedds.domain import DomainParticipant  # noqa: E402
from cyclonedds.idl import IdlStruct, annotations  # noqa: E402
from cyclonedds.pub import DataWriter  # noqa: E402
from cyclonedds.sub import DataReader  # noqa: E402
from cyclonedds.topic import Topic  # noqa: E402
from cyclonedds.util import duration  # noqa: E402

PKG, SRV = "sweetspot_msgs", "SimulateSwing"


# rmw_cyclonedds_cpp's request header, in front of the fields of every request and reply.
CYCLONE_HEADER = [Field("cdds_guid", "uint64", None, None, None), Field("cdds_seq", "int64", None, None, None)]


def add_service_types(ts, msgs_dir, mapping="enhanced"):
    """Registers SimulateSwing_Request and _Response in `ts` (keys 'sweetspot_msgs/SimulateSwing_Request'),
    with rmw_cyclonedds_cpp's header fields first for the cyclone mapping."""
    lines = (Path(msgs_dir) / PKG / "srv" / f"{SRV}.srv").read_text().splitlines()
    sep = lines.index("---")
    halves = {"Request": lines[:sep], "Response": lines[sep + 1:]}
    for suffix, body in halves.items():
        name = f"{SRV}_{suffix}"
        key = f"{PKG}/{name}"
        header = CYCLONE_HEADER if mapping == "cyclone" else []
        ts.specs[key] = header + parse_msg("\n".join(body), PKG)
        layout = {f.name + "_": ts.field_type(f) for f in ts.specs[key]}
        cls = pytypes.new_class(f"{name}_", (IdlStruct,), {"typename": f"{PKG}::srv::dds_::{name}_"},
                                lambda ns, layout=layout: ns.update({"__annotations__": layout}))
        ts.classes[key] = dataclass(annotations.final(cls))
    return f"{PKG}/{SRV}_Request", f"{PKG}/{SRV}_Response"


def service_qos():
    # ROS 2's service profile is reliable and volatile; all history kept, so a burst is never overwritten here.
    return Qos(Policy.Reliability.Reliable(duration(seconds=60)), Policy.History.KeepAll,
               Policy.DataRepresentation(use_cdrv0_representation=True), Policy.Durability.Volatile)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--msgs", default=str(Path(__file__).resolve().parents[2] / "msgs"))
    ap.add_argument("--loopback", action="store_true")
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("call")
    c.add_argument("--service", default="/sweetspot/simulate_swing")
    c.add_argument("--json", required=True)
    c.add_argument("--repeat", type=int, default=0)
    c.add_argument("--summary", action="store_true")
    c.add_argument("--timeout", type=float, default=60.0)
    c.add_argument("--mapping", choices=["enhanced", "cyclone"], default="enhanced")
    c.add_argument("--guid", type=int, default=0x5EE7_5907_0000_0001, help="cyclone: the client's id (uint64)")
    c.add_argument("--first-seq", type=int, default=1, help="cyclone: the first request's sequence number")
    c.add_argument("--frame-id-bytes", type=int, default=None,
                   help="set every request's swing.header.frame_id to this many bytes ('f' repeated): requests "
                        "too large for a command line")
    args = ap.parse_args()
    if args.loopback:
        os.environ.setdefault("CYCLONEDDS_URI", loopback_config())
    domain = int(os.environ.get("ROS_DOMAIN_ID", "0") or 0)

    ts = TypeSystem(args.msgs)
    req_type, resp_type = add_service_types(ts, args.msgs, args.mapping)
    cyclone = args.mapping == "cyclone"
    data = json.loads(args.json)
    if args.repeat:
        requests = []
        for i in range(1, args.repeat + 1):
            r = json.loads(args.json)
            r.setdefault("swing", {})["swing_id"] = i
            requests.append(r)
    else:
        requests = data if isinstance(data, list) else [data]
    if args.frame_id_bytes is not None:
        for r in requests:
            r.setdefault("swing", {}).setdefault("header", {})["frame_id"] = "f" * args.frame_id_bytes
    ids = [r.get("swing", {}).get("swing_id", 0) for r in requests]
    if len(set(ids)) != len(ids):
        print("every request needs its own swing.swing_id (replies are matched by it)", file=sys.stderr)
        return 2
    sent_header = {}
    if cyclone:
        for k, r in enumerate(requests):
            r["cdds_guid"], r["cdds_seq"] = args.guid, args.first_seq + k
            sent_header[ids[k]] = (args.guid, args.first_seq + k)
    samples = [ts.from_json(req_type, r) for r in requests]

    dp = DomainParticipant(domain)
    rq = Topic(dp, "rq" + args.service + "Request", ts.cls(req_type))
    rr = Topic(dp, "rr" + args.service + "Reply", ts.cls(resp_type))
    reader = DataReader(dp, rr, qos=service_qos())
    writer = DataWriter(dp, rq, qos=service_qos())
    if not (wait_matched(reader.get_matched_publications, 1, args.timeout, f"repliers on {args.service}")
            and wait_matched(writer.get_matched_subscriptions, 1, args.timeout, f"servers on {args.service}")):
        return 2
    for s in samples:
        writer.write(s)

    replies, duplicates, unknown, wrong_header = {}, 0, 0, 0
    wanted = set(ids)
    deadline = time.monotonic() + args.timeout
    while len(replies) < len(wanted) and time.monotonic() < deadline:
        for sample in reader.take(N=1024):
            if getattr(sample, "sample_info", None) and not sample.sample_info.valid_data:
                continue
            response = ts.to_json(resp_type, sample)
            swing_id = response["exit_velocity"]["swing_id"]
            if cyclone:
                header = (response.pop("cdds_guid"), response.pop("cdds_seq"))
                if header[0] != args.guid:
                    continue  # another client's reply, as rmw_cyclonedds_cpp filters them
                if sent_header.get(swing_id) != header:
                    wrong_header += 1
                    continue
            if swing_id not in wanted:
                unknown += 1
            elif swing_id in replies:
                duplicates += 1
            else:
                replies[swing_id] = response
        time.sleep(0.005)

    if args.summary:
        counts = {}
        for r in replies.values():
            key = str(r["exit_velocity"]["status"])
            counts[key] = counts.get(key, 0) + 1
        without_reason = sum(1 for r in replies.values()
                             if r["exit_velocity"]["status"] != 0 and not r["exit_velocity"]["message"])
        print(json.dumps({"sent": len(samples), "answered": len(replies), "status_counts": counts,
                          "without_reason": without_reason, "duplicates": duplicates, "unknown": unknown}))
    else:
        for i in ids:
            if i in replies:
                print(json.dumps(replies[i]), flush=True)
    if wrong_header:
        print(f"{wrong_header} replies carried a header that is not their request's", file=sys.stderr)
        return 3
    if len(replies) < len(wanted):
        print(f"{len(wanted) - len(replies)} of {len(wanted)} requests got no reply within {args.timeout} s",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
