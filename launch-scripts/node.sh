#!/usr/bin/env bash
# Launches one sweetspot node the way `ros2 run` would, without a ROS installation.
#
#   launch-scripts/node.sh [--rig NAME] [--domain ID] [--localhost] [--no-record] [--params FILE] [-- ROS_ARGS...]
#
#   --rig NAME     namespace /NAME (topics /NAME/swing, /NAME/exit_velocity, …) and node name NAME_sweetspot
#   --domain ID    ROS_DOMAIN_ID (default: inherited, else 0)
#   --localhost    keep DDS discovery on this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST)
#   --no-record    do not write a bag (default: bags/<node>_<UTC time>/)
#   --params FILE  a ROS 2 parameters file (`node_name: ros__parameters: …`, `/**` for every node)
#   -- ROS_ARGS    passed after --ros-args, e.g. -- -p default_modes:=12 -r swing:=/lab/swing
#
# SIGINT/SIGTERM are forwarded to the node, which finishes its bag and exits.
set -euo pipefail
case "${1:-}" in -h|--help) sed -n '2,14p' "$0"; exit 0 ;; esac
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${SWEETSPOT_BIN:-}"
if [ -z "$bin" ]; then
  if [ -x "$here/target/release/sweetspot" ]; then bin="$here/target/release/sweetspot"
  elif command -v sweetspot >/dev/null 2>&1; then bin="$(command -v sweetspot)"
  else
    echo "node.sh: no sweetspot binary: run 'cargo build --release' or set SWEETSPOT_BIN" >&2
    exit 2
  fi
fi

node_args=()
ros_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --rig) ros_args+=(-r "__ns:=/$2" -r "__node:=${2}_sweetspot"); shift 2 ;;
    --domain) export ROS_DOMAIN_ID="$2"; shift 2 ;;
    --localhost) export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST; shift ;;
    --no-record) node_args+=(--no-record); shift ;;
    --params) ros_args+=(--params-file "$2"); shift 2 ;;
    --) shift; ros_args+=("$@"); break ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "node.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

if [ ${#ros_args[@]} -gt 0 ]; then
  exec "$bin" node "${node_args[@]}" --ros-args "${ros_args[@]}"
else
  exec "$bin" node "${node_args[@]}"
fi
