//! The example curves of the BEESO merging paper (§3.3), for tests, `examples/merge_paper.rs`
//! and anyone rerunning its tables. Example 2 is left out: its printed data is a copy of
//! Example 1's (papers/NOTES.md).

use outlinefit::curve::wang_ball::{Disk, DiskWangBall};
use outlinefit::Point;

/// A DWB curve from `(x, y, r)` triples.
pub(crate) fn dwb(data: &[(f64, f64, f64)]) -> DiskWangBall {
    DiskWangBall::new(
        data.iter()
            .map(|&(x, y, r)| Disk::new(Point::new(x, y), r))
            .collect(),
    )
}

/// Example 1 (Table 1): adjacent curves of degrees 3 and 4, merged into degree 6.
pub fn example1() -> (DiskWangBall, DiskWangBall) {
    (
        dwb(&[
            (0.3, 0.3, 0.13),
            (0.8, 1.6, 0.15),
            (1.6, 1.8, 0.19),
            (2.5, 1.7, 0.17),
        ]),
        dwb(&[
            (2.5, 1.7, 0.17),
            (3.4, 1.8, 0.12),
            (3.8, 1.3, 0.13),
            (3.4, 0.7, 0.1),
            (2.2, 0.3, 0.16),
        ]),
    )
}

/// Example 3 (Table 7): adjacent curves of degrees 3 and 4, merged into degree 4.
pub fn example3() -> (DiskWangBall, DiskWangBall) {
    (
        dwb(&[
            (2.0, 7.2, 0.1),
            (-1.0, 1.0, 0.3),
            (2.5, 0.1, 0.4),
            (5.0, 1.5, 0.2),
        ]),
        dwb(&[
            (5.0, 1.5, 0.2),
            (7.5, 3.0, 0.4),
            (7.3, 7.8, 0.3),
            (3.0, 7.0, 0.2),
            (2.5, 2.5, 0.2),
        ]),
    )
}
