//! What the package shares with the command line: how a bat, a ball, the oblique inputs and the numerical
//! options are resolved and checked, the simulate loop and the modes document. Sharing them (rather than a
//! copy) is what makes `sweetspot.simulate` print the same numbers, and refuse the same inputs with the same
//! messages, as `sweetspot simulate`. They live in the library's `answer` module, which the command line calls
//! too.

pub use crate::engine::answer::bbcor::bbcor_document as bbcor;
pub use crate::engine::answer::compare::compare;
pub use crate::engine::answer::compare::{batter_from_spec, load_batter_file, BatterSpec};
pub use crate::engine::answer::inputs::{check_options, BallOverrides, ObliqueFlags, ObliqueInputs};
pub use crate::engine::answer::modes::modes_document;
pub use crate::engine::answer::simulate::{oblique_impact, simulate, spatial_impact, DEFAULT_IMPACT_FROM_TIP};
pub use crate::engine::bat_file::load_bat_file;
