"""ROS 2 launch file for sweetspot (for people who have ROS 2 installed).

sweetspot is a single Rust binary, not an ament package, so it is started with ExecuteProcess:

    ros2 launch launch-scripts/sweetspot.launch.py                       # node only, root namespace
    ros2 launch launch-scripts/sweetspot.launch.py namespace:=/rig3 rig:=true rig_rate:=5
    ros2 launch launch-scripts/sweetspot.launch.py record_path:=bags/session1 sweetspot:=/opt/sweetspot/bin/sweetspot

Several rigs share one DDS domain with one node per rig namespace: include this file once per rig with a
different `namespace`. DDS discovery follows the usual ROS_DOMAIN_ID / ROS_AUTOMATIC_DISCOVERY_RANGE of the
environment `ros2 launch` runs in.
"""

import os
import shutil

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, ExecuteProcess, OpaqueFunction
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration


def _default_binary():
    here = os.path.dirname(os.path.abspath(__file__))
    built = os.path.join(here, "..", "target", "release", "sweetspot")
    if os.path.exists(built):
        return os.path.normpath(built)
    return shutil.which("sweetspot") or "sweetspot"


def _node(context):
    binary = LaunchConfiguration("sweetspot").perform(context)
    namespace = LaunchConfiguration("namespace").perform(context)
    record_path = LaunchConfiguration("record_path").perform(context)
    cmd = [binary, "node", "--ros-args", "-r", f"__ns:={namespace}"]
    if LaunchConfiguration("record").perform(context).lower() in ("false", "0", "no"):
        cmd += ["-p", "record:=false"]
    elif record_path:
        cmd += ["-p", f"record_path:={record_path}"]
    return [ExecuteProcess(cmd=cmd, name="sweetspot_node", output="screen", sigterm_timeout="5")]


def _rig(context):
    binary = LaunchConfiguration("sweetspot").perform(context)
    cmd = [
        binary,
        "rig",
        "--namespace",
        LaunchConfiguration("namespace").perform(context),
        "--rate",
        LaunchConfiguration("rig_rate").perform(context),
        "--seed",
        LaunchConfiguration("rig_seed").perform(context),
        "--quiet",
    ]
    return [
        ExecuteProcess(
            cmd=cmd,
            name="sweetspot_rig",
            output="screen",
            condition=IfCondition(LaunchConfiguration("rig")),
        )
    ]


def generate_launch_description():
    return LaunchDescription(
        [
            DeclareLaunchArgument("sweetspot", default_value=_default_binary(), description="path of the sweetspot binary"),
            DeclareLaunchArgument("namespace", default_value="/", description="namespace of the node (one per rig)"),
            DeclareLaunchArgument("record", default_value="true", description="record a bag"),
            DeclareLaunchArgument("record_path", default_value="", description="bag directory (default bags/<node>_<UTC time>)"),
            DeclareLaunchArgument("rig", default_value="false", description="also start the simulated rig"),
            DeclareLaunchArgument("rig_rate", default_value="2", description="simulated swings per second"),
            DeclareLaunchArgument("rig_seed", default_value="2000", description="random seed of the simulated rig"),
            OpaqueFunction(function=_node),
            OpaqueFunction(function=_rig),
        ]
    )
