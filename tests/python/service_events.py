#!/usr/bin/env python3
"""Reads the service events of a sweetspot bag with rosbags (independent of sweetspot's code).

  service_events.py BAG_DIR TOPIC

The types come from the message definition stored in the bag alone. rosbags files a `pkg/srv/T` it parses as
`pkg/srv/msg/T` (and mcap-ros2-support refuses `T_Event` as a message name), so the parsed names are put back
as stored before registering. Prints {"type", "count", "events": [...]} as JSON (NaN as a string).
"""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from check_bag import plain  # noqa: E402
from srv_hashes import fix_names  # noqa: E402

from rosbags.rosbag2 import Reader  # noqa: E402
from rosbags.typesys import Stores, get_typestore, get_types_from_msg  # noqa: E402


def main():
    bag, topic = Path(sys.argv[1]), sys.argv[2]
    store = get_typestore(Stores.EMPTY)
    with Reader(bag) as reader:
        conns = [c for c in reader.connections if c.topic == topic]
        if not conns:
            print(f"no topic {topic} in {bag}", file=sys.stderr)
            return 1
        conn = conns[0]
        pkg = conn.msgtype.split("/")[0]
        store.register(fix_names(get_types_from_msg(conn.msgdef.data, conn.msgtype), pkg))
        events = [plain(store.deserialize_cdr(raw, conn.msgtype)) for _, _, raw in reader.messages(connections=conns)]
    print(json.dumps({"type": conn.msgtype, "count": len(events), "metadata_count": conn.msgcount,
                      "events": events}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
