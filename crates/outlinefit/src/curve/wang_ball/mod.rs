//! Wang–Ball curves and disk Wang–Ball (DWB) curves.
//!
//! A Wang–Ball curve of degree n is `W(t) = Σ_{i=0}^{n} W_{i,n}(t) p_i`, `t ∈ [0, 1]`, where
//! the Wang–Ball basis `W_{i,n}` (Eq. 2 of "Approximate merging of disk Wang–Ball curves
//! with BEESO", §2.1) is, with
//! `h = ⌊n/2⌋` and `H = ⌈n/2⌉`:
//!
//! * `W_i(t) = (2t)^i (1−t)^{i+2}` for `0 ≤ i ≤ h − 1`,
//! * `W_h(t) = (2t)^h (1−t)^H`,
//! * `W_H(t) = (2(1−t))^h t^H`,
//! * `W_i(t) = W_{n−i}(1−t)` for the remaining indices `H + 1 ≤ i ≤ n`.
//!
//! For even n the two middle formulas describe the same function (`h = H`), which is used
//! once. The paper's text extraction lost the floor and ceiling brackets of Eq. 2; they are
//! restored here, which makes the basis a partition of unity for every n (a test checks
//! it). Like the Bernstein basis, the Wang–Ball basis spans the
//! polynomials of degree ≤ n, so every Wang–Ball curve is a Bézier curve of the same degree
//! and vice versa (`wang_ball_to_bernstein`, `bernstein_to_wang_ball`). For n ≤ 3 it is
//! the Said–Ball / cubic Ball basis; its lower-degree factors make evaluation cheaper than
//! de Casteljau for high degrees.
//!
//! A disk Wang–Ball curve (Eq. 1 and 3) has control *disks* `(p_i, r_i)` instead of points
//! and describes the family of disks `(C(t), R(t))` whose center curve `C` and radius function
//! `R` use the same Wang–Ball basis. For approximate merging of two adjacent DWB curves
//! (§2.2.2) the paper subdivides the merged curve at `λ = L₁ / (L₁ + L₂)`, the ratio of the
//! arc lengths of the two center curves (`merge_lambda`).
//!
//! No maintained crate implements Wang–Ball curves, so this module is hand-written.
//!
//! Files: `basis` (the basis), `convert` (the exact change of basis to and from Bernstein
//! form), `disk` (the curve types and the merge ratio), `envelope` (the two curves a disk
//! curve's circles touch).

mod basis;
mod convert;
mod disk;
pub(crate) mod envelope;

pub(crate) use basis::wang_ball_basis;
pub(crate) use convert::{bezier_points_to_wang_ball, wang_ball_points_to_bezier};
pub(crate) use disk::merge_lambda;
pub use disk::{Disk, DiskWangBall, WangBall};
pub use envelope::{envelope, envelope_band, envelope_points};

#[cfg(test)]
mod tests;
