#!/usr/bin/env bash
# Runs the node recording every input and answer into a rosbag2/MCAP directory until Ctrl-C.
# Usage: launch-scripts/record.sh BAG_DIR [NAMESPACE] [more --ros-args…]
#   launch-scripts/record.sh bags/session1 /rig3 -p default_modes:=12
#   launch-scripts/record.sh - /rig3          # "-" = the default bags/<node>_<UTC time>
# BAG_DIR must not exist yet.
set -euo pipefail
source "$(dirname "$0")/common.sh"
if [ $# -lt 1 ]; then echo "usage: $0 BAG_DIR|- [NAMESPACE] [more --ros-args…]" >&2; exit 2; fi
ros_args=()
if [ "$1" != "-" ]; then ros_args+=(-p "record_path:=$1"); fi
shift
if [ $# -gt 0 ] && [[ "$1" == /* ]]; then ros_args+=(-r "__ns:=$1"); shift; fi
exec "${sweetspot[@]}" node --ros-args "${ros_args[@]}" "$@"
