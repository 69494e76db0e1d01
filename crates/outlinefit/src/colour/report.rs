//! JSON and CSV reports of a colour trace: the palette, every region, every boundary
//! (which two regions and colours it separates, its segments with their exact rational
//! control points, weights and errors), the layers and the check. The CSV has one row per
//! boundary.

use super::result::ColourTrace;
use crate::trace::Config;
use crate::VERSION;
use serde::Serialize;

#[derive(Serialize)]
struct Document<'a> {
    outlinefit_version: &'static str,
    config: &'a Config,
    path: &'a str,
    segments: usize,
    #[serde(flatten)]
    trace: &'a ColourTrace,
}

/// Writes the JSON report of `trace` (traced from `path` with `config`).
pub fn write_json(
    out: &mut dyn std::io::Write,
    config: &Config,
    path: &str,
    trace: &ColourTrace,
) -> std::io::Result<()> {
    let doc = Document {
        outlinefit_version: VERSION,
        config,
        path,
        segments: trace.segment_count(),
        trace,
    };
    serde_json::to_writer(&mut *out, &doc).map_err(std::io::Error::from)?;
    out.write_all(b"\n")
}

/// The CSV report: one row per boundary.
pub fn to_csv(trace: &ColourTrace) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let hex = |c: usize| {
        if c == 0 {
            "transparent".to_string()
        } else {
            trace.palette[c].hex()
        }
    };
    let region = |r: Option<usize>| r.map_or(String::new(), |r| r.to_string());
    let _ = w.write_record([
        "boundary",
        "right_region",
        "left_region",
        "right_colour",
        "left_colour",
        "closed",
        "points",
        "segments",
        "max_distance",
        "rmse",
    ]);
    for (k, b) in trace.boundaries.iter().enumerate() {
        let (n, sq): (usize, f64) = b
            .segments
            .iter()
            .map(|s| (s.point_count, s.error.sum_sq))
            .fold((0, 0.0), |(a, b), (c, d)| (a + c, b + d));
        let rmse = if n > 0 { (sq / n as f64).sqrt() } else { 0.0 };
        let _ = w.write_record([
            k.to_string(),
            region(b.right),
            region(b.left),
            hex(b.colours[0]),
            hex(b.colours[1]),
            b.closed.to_string(),
            b.points.len().to_string(),
            b.segments.len().to_string(),
            format!("{:.6}", b.max_distance()),
            format!("{rmse:.6}"),
        ]);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}
