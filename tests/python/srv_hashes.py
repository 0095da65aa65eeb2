#!/usr/bin/env python3
"""RIHS01 hashes of a ROS 2 service, computed by rosbags (an implementation independent of build.rs).

  srv_hashes.py MSGS_DIR PKG/NAME

rosbags parses .msg text only, so the .srv is split as rosidl_adapter splits it (at the line `---`), and the two
types rosidl adds to every service are written out as rosidl_generator_type_description defines them:
`Name_Event` (`service_msgs/ServiceEventInfo info`, `Name_Request[<=1] request`, `Name_Response[<=1] response`)
and the service `Name` (`request_message`, `response_message`, `event_message`). Every .msg under MSGS_DIR is
registered. One deviation from rosbags' own rules: rosidl_adapter turns a .msg `char` into an IDL `uint8`
(type id 3), rosbags into an IDL `char` (13); rosidl's is used (the published hash of
service_msgs/msg/ServiceEventInfo, 41bcbbe0…, needs it). Prints {"pkg/srv/Name": hash, ...Request, Response,
Event} as JSON.
"""
import json
import re
import sys
from pathlib import Path

from rosbags.typesys import Stores, get_typestore, get_types_from_msg


def fix_names(value, pkg):
    """rosbags files a `pkg/srv/T` it parses as `pkg/srv/msg/T`; undo that everywhere."""
    if isinstance(value, str):
        return value.replace(f"{pkg}/srv/msg/", f"{pkg}/srv/")
    if isinstance(value, tuple):
        return tuple(fix_names(v, pkg) for v in value)
    if isinstance(value, list):
        return [fix_names(v, pkg) for v in value]
    if isinstance(value, dict):
        return {fix_names(k, pkg): fix_names(v, pkg) for k, v in value.items()}
    return value


def main():
    msgs_dir, service = Path(sys.argv[1]), sys.argv[2]
    pkg, name = service.split("/")
    types = {}
    for path in sorted(msgs_dir.glob("**/msg/*.msg")):
        text = re.sub(r"^char(\[|\s)", r"uint8\1", path.read_text(), flags=re.MULTILINE)
        types.update(get_types_from_msg(text, f"{path.parent.parent.name}/msg/{path.stem}"))
    lines = (msgs_dir / pkg / "srv" / f"{name}.srv").read_text().splitlines()
    sep = lines.index("---")
    halves = {
        f"{name}_Request": "\n".join(lines[:sep]) + "\n",
        f"{name}_Response": "\n".join(lines[sep + 1:]) + "\n",
        f"{name}_Event": f"service_msgs/ServiceEventInfo info\n{name}_Request[<=1] request\n"
                         f"{name}_Response[<=1] response\n",
        name: f"{name}_Request request_message\n{name}_Response response_message\n{name}_Event event_message\n",
    }
    for type_name, text in halves.items():
        # Unqualified types of the .srv are messages of its package; the service's own types are in srv/.
        text = re.sub(rf"^({name}_\w+)", rf"{pkg}/srv/\1", text, flags=re.MULTILINE)
        text = re.sub(r"^([A-Z]\w*)", rf"{pkg}/\1", text, flags=re.MULTILINE)
        types.update(fix_names(get_types_from_msg(text, f"{pkg}/srv/{type_name}"), pkg))
    store = get_typestore(Stores.EMPTY)
    store.register(types)
    print(json.dumps({f"{pkg}/srv/{t}": store.hash_rihs01(f"{pkg}/srv/{t}") for t in halves}))


if __name__ == "__main__":
    main()
