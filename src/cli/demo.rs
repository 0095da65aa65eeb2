//! `sweetspot demo` (arguments; the runner lives in `crate::demo`).
pub use crate::demo::{run, DemoArgs};
