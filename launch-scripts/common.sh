# Shared by the launch scripts (sourced, not run): finds the sweetspot binary and sets DDS discovery sensibly.
#
# Binary (as node.sh): $SWEETSPOT_BIN, else the repository's target/release/sweetspot, else `sweetspot` on
# PATH, else `cargo run --release --` from the repository.
# Discovery: ROS_AUTOMATIC_DISCOVERY_RANGE is left alone when set (SUBNET for a rig on a lab network);
# unset, it defaults to LOCALHOST so nothing is announced beyond this machine by accident.

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if [ -n "${SWEETSPOT_BIN:-}" ]; then
  sweetspot=("$SWEETSPOT_BIN")
elif [ -x "$repo_root/target/release/sweetspot" ]; then
  sweetspot=("$repo_root/target/release/sweetspot")
elif command -v sweetspot >/dev/null 2>&1; then
  sweetspot=(sweetspot)
else
  sweetspot=(cargo run --quiet --release --manifest-path "$repo_root/Cargo.toml" --)
fi

if [ -z "${ROS_AUTOMATIC_DISCOVERY_RANGE:-}" ] && [ "${ROS_LOCALHOST_ONLY:-0}" != "1" ]; then
  export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
fi
echo "sweetspot: ${sweetspot[*]} (ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-0}, ROS_AUTOMATIC_DISCOVERY_RANGE=${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST via ROS_LOCALHOST_ONLY})" >&2
