//! Message types generated at build time from `msgs/` (the one source of truth).
