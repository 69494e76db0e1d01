//! What `trace` and `batch` tell the user about a finished trace: warnings, notes and a
//! fidelity check that did not hold.

use outlinefit::{Config, TraceResult};

/// The warnings and notes a trace deserves, one line each with its `warning: ` or `note: `
/// prefix: a polarity that looks wrong, a drawn outline that does not match the input, and
/// which frame of a file with several was traced.
pub(crate) fn trace_warnings(name: &str, config: &Config, result: &TraceResult) -> Vec<String> {
    let mut out = Vec::new();
    let (frame, frames) = (result.image.frame, result.image.frames);
    if frames > 1 {
        out.push(format!(
            "note: {name}: traced frame {frame} of {frames} (counted from 0; --frame N picks another)"
        ));
    }
    if result.image.dark_border {
        out.push(if config.invert {
            format!(
                "warning: {name}: most of the image border is foreground with --invert; if the shapes are dark on a light background, leave --invert out"
            )
        } else {
            format!(
                "warning: {name}: most of the image border is foreground; if the shapes are light on a dark background, use --invert"
            )
        });
    }
    if let Some(problem) = fidelity_problem(config, result) {
        out.push(format!("warning: {name}: {problem}"));
    }
    out
}

/// What is wrong with the trace's fidelity, if the check ran and did not hold.
pub(crate) fn fidelity_problem(config: &Config, result: &TraceResult) -> Option<String> {
    let f = &result.fidelity;
    if !config.check || f.held {
        return None;
    }
    let mut parts = Vec::new();
    if f.max_deviation > f.deviation_limit {
        parts.push(format!(
            "a data point lies {:.2} px from the drawn outline (limit {:.2} px)",
            f.max_deviation, f.deviation_limit
        ));
    }
    if f.largest_region > f.region_limit {
        let at = f.region_box.map_or(String::new(), |[x0, y0, x1, y1]| {
            format!(" at pixels ({x0},{y0})-({x1},{y1})")
        });
        parts.push(format!(
            "a region of {:.0} px² is lost or invented{at}",
            f.largest_region
        ));
    }
    Some(format!(
        "the drawn outline does not match the input: {} (see \"fidelity\" in the report)",
        parts.join("; ")
    ))
}
