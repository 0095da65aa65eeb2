#!/usr/bin/env bash
# A simulated batting rig publishing its bats, ball and swings to a node.
# Usage: launch-scripts/rig.sh [NAMESPACE] [sweetspot rig options…]
#   launch-scripts/rig.sh /rig3 --rate 5 --count 200 --true-cor 0.50
# The node it feeds must run in the same namespace: launch-scripts/record.sh bags/rig3 /rig3
set -euo pipefail
source "$(dirname "$0")/common.sh"
namespace=/
if [ $# -gt 0 ] && [[ "$1" == /* ]]; then namespace="$1"; shift; fi
exec "${sweetspot[@]}" rig --namespace "$namespace" "$@"
