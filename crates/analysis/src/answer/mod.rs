//! The answers of sweetspot's one-shot tools, each a document built by one function: [`simulate::simulate`],
//! [`sweep::sweep`], [`bbcor::bbcor_document`], [`compare::compare`] and [`modes::modes_document`]. The command line parses its
//! flags into these functions' inputs and prints what they return; the Python package calls the same
//! functions, so both answer with the same numbers. [`inputs`] holds what they share: the defaults, the
//! checks of numerical options, the oblique and 3-D inputs, how a bat is named (a preset or a bat file).
pub mod bbcor;
pub mod compare;
pub mod inputs;
pub mod modes;
pub mod simulate;
pub mod sweep;
