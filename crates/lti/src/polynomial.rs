//! (Contents follow.)
