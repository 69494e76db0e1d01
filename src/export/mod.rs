//! Writers for the traced outline (placeholder: being written by a helper).
