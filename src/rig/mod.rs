//! The simulated test rig: its sessions of swings ([`sweetspot_analysis::rig`], pure) and the DDS publisher
//! that plays them to a node ([`dds`]).
pub use sweetspot_analysis::rig::*;

pub mod dds;
