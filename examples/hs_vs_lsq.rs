//! Harmony search (the HS paper's scheme) against the least-squares optimum on the same
//! segments with fixed centripetal parameters, on every bundled sample.
//!
//! `cargo run --release --example hs_vs_lsq [BUDGET] [BOX_SCALE]` prints a markdown table: per sample,
//! the total Eq. 4 error of the separable least-squares optimum (free ends, the lower bound
//! for any scheme on these segments and parameters; and with the G1 tangents of the `lsq`
//! chain), and of HS at BUDGET (default 5000) and 10 × BUDGET evaluations per segment, with
//! wall times, and how many HS segments ended on the boundary of the Eq. 9 search box.

use outlinefit::fit::paper::{fit_contour, PaperOptions};
use outlinefit::fit::solve::{optimum_at_fixed_params, EndCondition};
use outlinefit::optim::HarmonySearch;
use outlinefit::param::centripetal_parameters;
use outlinefit::{trace_file, Config, Point};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let budget: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(5000);
    let box_scale: f64 = std::env::args()
        .nth(2)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(1.0);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("samples");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    paths.sort();
    println!("| sample | segments | LS optimum, free ends | LS optimum, G1 tangents | HS {budget} | time | HS {} | time | on box boundary |", budget * 10);
    println!("|---|---|---|---|---|---|---|---|---|");
    for path in paths {
        let config = Config::default();
        let traced = trace_file(&path, &config)?;
        let (mut free, mut g1, mut segs) = (0.0, 0.0, 0);
        for c in &traced.contours {
            for k in 0..c.segments.len() {
                let pts = c.segment_points(k);
                let params = centripetal_parameters(&pts);
                free +=
                    optimum_at_fixed_params(&pts, &params, EndCondition::Free, EndCondition::Free)
                        .1;
                let cv = &c.segments[k].curve;
                let t = |d: Point| {
                    d.normalized()
                        .map_or(EndCondition::Free, EndCondition::Tangent)
                };
                let start = if c.joints[k].kind == outlinefit::JointKind::Smooth {
                    t(cv.points[1] - cv.points[0])
                } else {
                    EndCondition::Free
                };
                let next = (k + 1) % c.segments.len();
                let end = if c.joints[next].kind == outlinefit::JointKind::Smooth {
                    t(cv.points[3] - cv.points[2])
                } else {
                    EndCondition::Free
                };
                g1 += optimum_at_fixed_params(&pts, &params, start, end).1;
                segs += 1;
            }
        }
        let mut cells = Vec::new();
        let mut boundary = 0;
        for b in [budget, budget * 10] {
            let opts = PaperOptions {
                budget: b,
                seed: 1,
                hs: HarmonySearch::default(),
                timings: false,
                box_scale,
            };
            let started = Instant::now();
            let mut total = 0.0;
            for (i, c) in traced.contours.iter().enumerate() {
                let f = fit_contour(c, &opts, i);
                total += f.sum_sq();
                if b == budget {
                    boundary += f
                        .segments
                        .iter()
                        .filter(|s| s.on_search_boundary == Some(true))
                        .count();
                }
            }
            cells.push(format!(
                "{total:.4} | {:.2} s",
                started.elapsed().as_secs_f64()
            ));
        }
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        println!(
            "| {name} | {segs} | {free:.4} | {g1:.4} | {} | {} | {boundary}/{segs} |",
            cells[0], cells[1]
        );
    }
    Ok(())
}
