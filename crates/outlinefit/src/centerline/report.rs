//! The centre-line reports: JSON (the configuration, every stroke with its pieces' control
//! disks, the junctions, the check) and CSV (one row per stroke).

use super::result::{CenterlineResult, StrokeEnd};
use crate::trace::Config;
use crate::VERSION;
use serde::Serialize;

#[derive(Serialize)]
struct Document<'a> {
    outlinefit_version: &'static str,
    mode: &'static str,
    config: &'a Config,
    path: &'a str,
    strokes_over_tolerance: usize,
    trace: &'a CenterlineResult,
}

/// Writes the JSON report of one traced image.
pub fn write_json(
    out: &mut dyn std::io::Write,
    config: &Config,
    path: &str,
    result: &CenterlineResult,
) -> std::io::Result<()> {
    let doc = Document {
        outlinefit_version: VERSION,
        mode: "centerline",
        config,
        path,
        strokes_over_tolerance: result.strokes_over(config.tolerance),
        trace: result,
    };
    serde_json::to_writer(&mut *out, &doc).map_err(std::io::Error::from)?;
    out.write_all(b"\n")
}

/// The CSV report: one row per stroke.
pub fn to_csv(result: &CenterlineResult) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record([
        "stroke",
        "closed",
        "start",
        "end",
        "segments",
        "length",
        "min_width",
        "max_width",
        "centre_max",
        "centre_rms",
        "radius_max",
        "radius_rms",
    ]);
    let end = |e: StrokeEnd| match e {
        StrokeEnd::Free => "free".to_string(),
        StrokeEnd::Junction(j) => format!("junction {j}"),
    };
    let f = |x: f64| format!("{x:.4}");
    for (k, s) in result.strokes.iter().enumerate() {
        let _ = w.write_record([
            k.to_string(),
            s.closed.to_string(),
            end(s.ends[0]),
            end(s.ends[1]),
            s.segments.len().to_string(),
            f(s.length),
            f(s.width_range[0]),
            f(s.width_range[1]),
            f(s.centre_max),
            f(s.centre_rms),
            f(s.radius_max),
            f(s.radius_rms),
        ]);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}
