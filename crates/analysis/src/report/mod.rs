//! What the commands show a person: aligned text tables and compact numbers, the JSON documents of the physics
//! commands, line charts (SVG or PNG, with an embedded font) and the seed paper's figures. The command line and
//! the demo both draw with it; it knows nothing of either.

mod crisp_text;
pub mod figures;
pub mod json;
pub mod plot;
pub mod stdout;
pub mod sweep;
pub mod table;
