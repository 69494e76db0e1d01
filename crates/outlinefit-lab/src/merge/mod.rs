//! The `merge` command around [`outlinefit::merge::MergeProblem`] (the BEESO paper's
//! merging of two adjacent disk Wang–Ball curves): its input file ([`input`]), its
//! picture ([`picture`]) and the paper's example curves ([`examples`]).

pub mod examples;
pub mod input;
pub mod picture;

#[cfg(test)]
mod tests;
