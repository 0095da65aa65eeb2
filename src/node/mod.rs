//! The ROS 2 shell: topics, QoS, parameters, diagnostics.
