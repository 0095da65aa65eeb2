#!/usr/bin/env bash
# Republishes a recorded session's inputs (params first, then swings with their original timing) so a
# running node recomputes it. Usage: launch-scripts/play.sh BAG [sweetspot bag play options…]
#   launch-scripts/play.sh bags/demo_2026_11_21-05_19_10 --rate 2 --loop
set -euo pipefail
source "$(dirname "$0")/common.sh"
if [ $# -lt 1 ]; then echo "usage: $0 BAG [sweetspot bag play options…]" >&2; exit 2; fi
exec "${sweetspot[@]}" bag play "$@"
