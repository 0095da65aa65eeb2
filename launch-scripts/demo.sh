#!/usr/bin/env bash
# The whole system in one command: node, simulated rig and recorder over loopback DDS, then a table and
# figures. Arguments go to `sweetspot demo` (e.g. --swings 400 --true-cor 0.50 --out /tmp/bags).
set -euo pipefail
source "$(dirname "$0")/common.sh"
exec "${sweetspot[@]}" demo "$@"
