//! The `merge` command's input file: two adjacent DWB curves as JSON,
//! `{"curves": [{"centers": [[x, y], …], "radii": [r, …]}, {…}]}`.

use crate::{Error, Result};
use outlinefit::curve::wang_ball::{Disk, DiskWangBall};
use outlinefit::Point;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    curves: Vec<CurveJson>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveJson {
    centers: Vec<[f64; 2]>,
    radii: Vec<f64>,
}

/// Parses the two curves of a merge input; `what` names the source in errors (a path).
///
/// Errors ([`Error::InvalidInput`]): malformed JSON, not exactly two curves, a curve with
/// fewer than two disks or with different numbers of centers and radii. Adjacency, finiteness
/// and signs are checked by [`outlinefit::merge::MergeProblem::new`].
pub fn parse_curves(text: &str, what: &str) -> Result<(DiskWangBall, DiskWangBall)> {
    let bad = |message: String| Error::InvalidInput {
        what: what.to_string(),
        message,
    };
    let file: File =
        serde_json::from_str(text).map_err(|e| bad(format!("not a merge input: {e}")))?;
    if file.curves.len() != 2 {
        return Err(bad(format!(
            "expected exactly two curves, found {}",
            file.curves.len()
        )));
    }
    let mut curves = Vec::with_capacity(2);
    for (i, c) in file.curves.iter().enumerate() {
        if c.centers.len() != c.radii.len() {
            return Err(bad(format!(
                "curve {}: {} centers but {} radii",
                i + 1,
                c.centers.len(),
                c.radii.len()
            )));
        }
        if c.centers.len() < 2 {
            return Err(bad(format!("curve {}: needs at least two disks", i + 1)));
        }
        curves.push(DiskWangBall {
            disks: c
                .centers
                .iter()
                .zip(&c.radii)
                .map(|(&[x, y], &r)| Disk::new(Point::new(x, y), r))
                .collect(),
        });
    }
    let b = curves.pop();
    let a = curves.pop();
    match (a, b) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(bad("expected exactly two curves".to_string())), // unreachable: checked above
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        let ok = r#"{"curves": [{"centers": [[0, 0], [1, 1]], "radii": [0.1, 0.2]},
                               {"centers": [[1, 1], [2, 0], [3, 1]], "radii": [0.2, 0.1, 0.3]}]}"#;
        let (a, b) = parse_curves(ok, "in.json").unwrap();
        assert_eq!(a.disks.len(), 2);
        assert_eq!(b.disks[2], Disk::new(Point::new(3.0, 1.0), 0.3));
        for (text, expect) in [
            ("{", "not a merge input"),
            (r#"{"curves": []}"#, "exactly two curves"),
            (
                r#"{"curves": [{"centers": [[0, 0]], "radii": [0.1]}, {"centers": [[0, 0], [1, 1]], "radii": [0.1, 0.1]}]}"#,
                "at least two disks",
            ),
            (
                r#"{"curves": [{"centers": [[0, 0], [1, 1]], "radii": [0.1]}, {"centers": [[1, 1], [2, 2]], "radii": [0.1, 0.1]}]}"#,
                "2 centers but 1 radii",
            ),
            (r#"{"curves": [], "extra": 1}"#, "unknown field"),
        ] {
            let e = parse_curves(text, "in.json").unwrap_err().to_string();
            assert!(e.starts_with("in.json: ") && e.contains(expect), "{e}");
        }
    }
}
