"""Writes the ~300 MB MCAP file of BENCHMARKS.md's reading row: `.venv/bin/python scripts/read_bench_bag.py OUT.mcap 300`
(zstd chunks of 1 MiB, 4 std_msgs/String topics of 1 KiB messages, half random, QoS metadata as rosbag2 writes)."""
import os, struct, sys
from mcap.writer import Writer, CompressionType
QOS = ("- history: 1\n  depth: 10\n  reliability: 1\n  durability: 2\n  deadline:\n    sec: 9223372036\n"
       "    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  liveliness: 1\n"
       "  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  avoid_ros_namespace_conventions: false")
out, target = sys.argv[1], int(sys.argv[2]) * 1024 * 1024
rnd = os.urandom(64 * 1024 * 1024)
with open(out, 'wb') as f:
    w = Writer(f, chunk_size=1024 * 1024, compression=CompressionType.ZSTD)
    w.start(profile='ros2', library='bench')
    sid = w.register_schema(name='std_msgs/msg/String', encoding='ros2msg', data=b'string data\n')
    chans = [w.register_channel(topic=f'/bench/t{i}', message_encoding='cdr', schema_id=sid,
                                metadata={'offered_qos_profiles': QOS}) for i in range(4)]
    i, pos = 0, 0
    while f.tell() < target:
        body = rnd[pos:pos + 512] + bytes(512)   # half random, half zeros: ~2x under zstd
        pos = (pos + 512) % (len(rnd) - 1024)
        cdr = b'\x00\x01\x00\x00' + struct.pack("<I", 1024) + body[:1023] + b'\x00'
        t = 1_700_000_000_000_000_000 + i * 1000
        w.add_message(channel_id=chans[i % 4], log_time=t, publish_time=t, data=cdr, sequence=i)
        i += 1
    w.finish()
print(i, 'messages')
