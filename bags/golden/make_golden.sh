#!/usr/bin/env bash
# Regenerates bags/golden/sweetspot_golden by recording the real node over DDS, inside a private network
# namespace (nothing leaves the machine). Run from the repository root after `cargo build`:
#   bags/golden/make_golden.sh [path/to/sweetspot]
# The node runs with default settings (replay assumes them unless the bag's custom_data says otherwise).
set -euo pipefail
cd "$(dirname "$0")/../.."
B=${1:-target/debug/sweetspot}
OUT=bags/golden/sweetspot_golden
if [ "${INSIDE_NETNS:-}" != 1 ]; then
  rm -rf "$OUT"
  exec unshare --net -- env INSIDE_NETNS=1 bash -c \
    'ip link set lo up multicast on && ip route add 224.0.0.0/4 dev lo && exec "$0" "$1"' "$0" "$B"
fi
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST SWEETSPOT_TEST_NETNS=1
log=$(mktemp)
"$B" node --ros-args -r __ns:=/golden -p record_path:="$OUT" >"$log" 2>&1 &
node=$!
trap 'kill -INT $node 2>/dev/null || true' EXIT
# Bat "game" from a preset, a lively ball, a malformed bat (answered REJECTED), then the swings: two bats,
# the torpedo preset used by name, empty ids (latest bat/ball), an unknown bat, an explicit default ball.
"$B" pub bat '{"bat_id": "game", "preset": "r161"}' --ns /golden --wait-subscribers 1 -q
"$B" pub ball '{"ball_id": "lively", "mass": 0.145, "radius": 0.0366, "cor": 0.55, "stiffness": 7.0e6, "exponent": 1.5}' --ns /golden --wait-subscribers 1 -q
"$B" pub bat '{"bat_id": "broken", "station_z": [0, 0.5], "outer_radius": [0.02], "inner_radius": [0, 0]}' --ns /golden --wait-subscribers 1 -q
"$B" pub swing --file bags/golden/swings.jsonl --ns /golden --wait-subscribers 1 --rate 20 -q
sleep 2
kill -INT $node
wait $node
trap - EXIT
tail -n 2 "$log"
