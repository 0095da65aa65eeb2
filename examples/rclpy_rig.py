#!/usr/bin/env python3
"""A batting rig written the way a ROS 2 lab would write it: an rclpy node that describes its bat once
(BatParams, reliable and transient-local, so a sweetspot node started later still gets it), waits until the
node has taken it (the node's SweetSpot for that bat), sends its swings (Swing, NaN for whatever the rig did
not measure), and prints the answer to each (ExitVelocity).

Needs sweetspot_msgs built in a ROS 2 workspace (docs/ros2.md; in this repository `bash scripts/ros2-env
prepare` does it) and a running `sweetspot node`:

    sweetspot node --no-record &
    python3 examples/rclpy_rig.py --swings 5             # after sourcing the workspace, or:
    bash scripts/ros2-env python examples/rclpy_rig.py --swings 5

Each answer is printed as one JSON line: swing_id, status (0 OK, 1 REJECTED, 2 DROPPED), message, and the
predicted exit speed, launch angle and spin (null where the model has no number). Exits non-zero if an
answer is missing after --timeout seconds.
"""
import argparse
import json
import math
import time

import rclpy
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sweetspot_msgs.msg import BatParams, ExitVelocity, SweetSpot, Swing

NAN = math.nan


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--swings", type=int, default=5, help="swings to send (impact points spread over the barrel)")
    p.add_argument("--bat-id", default="rig bat")
    p.add_argument("--preset", default="r161", help="a built-in bat of sweetspot (r161, torpedo, ...)")
    p.add_argument("--timeout", type=float, default=30.0)
    args = p.parse_args()

    rclpy.init()
    node = Node("rclpy_rig")
    reliable = QoSProfile(
        history=HistoryPolicy.KEEP_LAST, depth=1000, reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )
    latched = QoSProfile(
        history=HistoryPolicy.KEEP_LAST, depth=1, reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )
    answers = {}
    node.create_subscription(ExitVelocity, "exit_velocity", lambda m: answers.setdefault(m.swing_id, m), reliable)
    # The node answers each new bat with its SweetSpot (latched): the sign that it has the bat. DDS orders
    # nothing across topics, so a swing sent before that could reach the node first ("unknown bat_id").
    bats_taken = set()
    node.create_subscription(SweetSpot, "sweet_spot", lambda m: bats_taken.add(m.bat_id), latched)
    bats = node.create_publisher(BatParams, "bat/params", latched)
    swings = node.create_publisher(Swing, "swing", reliable)

    bat = BatParams(bat_id=args.bat_id, preset=args.preset)
    bat.header.stamp = node.get_clock().now().to_msg()
    bats.publish(bat)

    # Wait until the node has our bat, reads swings and answers on exit_velocity, so nothing is sent into the
    # void.
    deadline = time.monotonic() + args.timeout
    while (
        args.bat_id not in bats_taken
        or swings.get_subscription_count() == 0
        or node.count_publishers("exit_velocity") == 0
    ):
        if time.monotonic() > deadline:
            raise SystemExit("rclpy_rig: no sweetspot node took the bat (is `sweetspot node` running?)")
        rclpy.spin_once(node, timeout_sec=0.1)
    time.sleep(1.0)  # let its exit_velocity writer match our reader too

    for k in range(1, args.swings + 1):
        swing = Swing(
            swing_id=k,
            bat_id=args.bat_id,
            ball_id="",  # the node's latest ball (its default_ball, the game ball mlb2024, before any BallParams)
            ball_speed=40.0,  # m/s, pitch speed toward the bat
            bat_cm_speed=20.0,  # m/s, the bat's centre of mass
            bat_angular_speed=50.0,  # rad/s
            impact_z=0.60 + 0.02 * (k - 1),  # m from the knob
            # The rig measured neither the exit speed nor the launch: NaN = "not measured".
            measured_exit_speed=NAN,
            measured_launch_angle=NAN,
            measured_spin=NAN,
        )
        swing.header.stamp = node.get_clock().now().to_msg()
        swings.publish(swing)

    while len(answers) < args.swings and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    for k in sorted(answers):
        a = answers[k]
        number = lambda x: x if math.isfinite(x) else None  # noqa: E731
        print(json.dumps({
            "swing_id": a.swing_id, "bat_id": a.bat_id, "status": a.status, "message": a.message,
            "impact_z": number(a.impact_z), "exit_speed": number(a.exit_speed),
            "launch_angle": number(a.launch_angle), "spin": number(a.spin), "residual": number(a.residual),
        }))
    node.destroy_node()
    rclpy.try_shutdown()
    if len(answers) < args.swings:
        raise SystemExit(f"rclpy_rig: {args.swings - len(answers)} of {args.swings} swings unanswered")


if __name__ == "__main__":
    main()
