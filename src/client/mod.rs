//! The ROS 2 command-line client: what `ros2 topic pub/echo`, `ros2 param`, `ros2 service call`, `ros2
//! topic/service/node list` and `ros2 interface` do, for sweetspot's topics and for any ROS 2 node, without a
//! ROS installation. Each of `pub`, `echo`, `param`, `call`, `topic`, `service`, `nodes` and `interface`
//! parses its flags in `cli/` and calls one function here.
//!
//! Inside, imports run one way: [`pubsub`] → [`kind`], [`values`]; [`call`] → [`values`], [`graph`];
//! [`param`] → [`graph`].

pub mod call;
pub mod graph;
pub mod kind;
pub mod param;
pub mod pubsub;
pub mod values;
