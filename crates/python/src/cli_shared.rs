//! What the package shares with the command line: how a bat, a ball, the oblique inputs and the numerical
//! options are resolved and checked, the simulate loop and the modes document. Sharing them (rather than a
//! copy) is what makes `sweetspot.simulate` print the same numbers, and refuse the same inputs with the same
//! messages, as `sweetspot simulate`. They live in the library's `cli` module today; every use goes through
//! this file, so when they move to the DDS-free layers only these paths change.

pub use crate::engine::cli::bat_file::load_bat_file;
pub use crate::engine::cli::bbcor::bbcor_document as bbcor;
pub use crate::engine::cli::common::{check_options, BallArgs, ObliqueInputs};
pub use crate::engine::cli::compare::compare;
pub use crate::engine::cli::compare::{batter_from_spec, load_batter_file, BatterSpec};
pub use crate::engine::cli::modes::modes_document;
pub use crate::engine::cli::simulate::{oblique_impact, simulate, spatial_impact, DEFAULT_IMPACT_FROM_TIP};
