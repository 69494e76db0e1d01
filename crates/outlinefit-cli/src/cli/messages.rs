//! What the command line tells the user: the warnings and notes of a finished trace (a
//! fidelity check that did not hold among them), and errors in its own words — the
//! library names options by their fields (`max_pixels`), the user reads flags
//! (`--max-pixels`).

use outlinefit::{Config, Error, ForegroundHint, ThresholdMode, TraceResult};

/// Share of the image border above which foreground along it is worth a warning (above
/// one half, the polarity warning says more).
const BORDER_WARNING: f64 = 0.25;
use outlinefit_lab::Error as LabError;

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
    } else if result.image.border_foreground > BORDER_WARNING {
        let hint = match result.image.threshold_mode {
            ThresholdMode::Local => "crop the image if that is not part of the drawing",
            _ => "if that is a shadow or the dark edge of a scan, try --threshold-mode local or crop the image",
        };
        out.push(format!(
            "warning: {name}: the traced foreground covers {:.0}% of the image border; {hint}",
            100.0 * result.image.border_foreground
        ));
    }
    if let Some(problem) = fidelity_problem(config, result) {
        out.push(format!("warning: {name}: {problem}"));
    }
    let widened = result
        .contours
        .iter()
        .filter(|c| c.tolerance > config.tolerance);
    let (count, widest) = widened.fold((0, 0.0f64), |(n, w), c| (n + 1, w.max(c.tolerance)));
    if count > 0 {
        let of = result.contours.len();
        out.push(format!(
            "note: {name}: {count} of {of} outlines have blurred edges and were fitted to a tolerance of up to {widest:.2} px (--fixed-tolerance holds them to {} px)",
            config.tolerance
        ));
    }
    let f = &result.fidelity;
    if config.check && f.segments_over_tolerance > 0 {
        let (n, plural) = match f.segments_over_tolerance {
            1 => (1, "segment lies"),
            n => (n, "segments lie"),
        };
        let limit = if count > 0 {
            "their outline's tolerance (widened on blurred edges)".to_string()
        } else {
            format!("--tolerance {} px", config.tolerance)
        };
        out.push(format!(
            "warning: {name}: {n} {plural} farther than {limit} from their data (up to {:.2} px): too short to split (see \"segments_over_tolerance\" in the report)",
            f.worst_segment_distance
        ));
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

/// The message a panic carried (its payload is a `&str` or a `String` when it came from
/// `panic!` with a message), or an empty string.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default()
}

/// The flag of an options field: `max_pixels` → `--max-pixels`, `omega/lambda/mu` →
/// `--omega/--lambda/--mu`; the two fields whose flags differ are mapped by name.
pub(crate) fn flag_of(field: &str) -> String {
    match field {
        "shape" => "--omega/--lambda/--mu".to_string(),
        "feature_grid" => "--grid".to_string(),
        _ => field
            .split('/')
            .map(|f| format!("--{}", f.replace('_', "-")))
            .collect::<Vec<_>>()
            .join("/"),
    }
}

/// A library error worded for the command line, where it names options or hints at them.
fn cli_text(e: &Error) -> Option<String> {
    Some(match e {
        Error::InvalidOption { name, message } => {
            format!("invalid option {}: {message}", flag_of(name))
        }
        Error::TooLarge {
            width,
            height,
            pixels,
            limit,
        } => format!(
            "the image is {width}×{height} = {pixels} pixels, more than the limit of {limit} (raise --max-pixels)"
        ),
        Error::NoForeground { threshold, hint } => {
            let hint = match hint {
                ForegroundHint::TraceAlpha { transparent } => format!(
                    "{:.1} % of the image is transparent: --alpha traces its alpha channel",
                    100.0 * transparent
                ),
                ForegroundHint::InvertOrThreshold => {
                    "if the shapes are light on a dark background try --invert, otherwise --threshold"
                        .to_string()
                }
            };
            format!("no shape found: no pixel has {threshold}, so every pixel is background; {hint}")
        }
        Error::AllBelowMinArea { shapes, min_area } => format!(
            "no shape found: all {shapes} shapes are smaller than the minimum area of {min_area} px² (lower --min-area to keep them)"
        ),
        _ => return None,
    })
}

/// An error and its causes on one line, each cause appended unless the text so far
/// already holds it; the tracer's and the lab's errors in the command line's words
/// ([`flag_of`]).
pub(crate) fn error_line(e: &(dyn std::error::Error + 'static)) -> String {
    let text = |e: &(dyn std::error::Error + 'static)| {
        let worded = match e.downcast_ref::<LabError>() {
            Some(LabError::Tracer(e)) => cli_text(e),
            Some(LabError::InvalidOption { name, message }) => {
                Some(format!("invalid option {}: {message}", flag_of(name)))
            }
            Some(_) => None,
            None => e.downcast_ref::<Error>().and_then(cli_text),
        };
        worded.unwrap_or_else(|| e.to_string())
    };
    let mut line = text(e);
    let mut source = e.source();
    while let Some(s) = source {
        let t = text(s);
        if !line.contains(&t) {
            line.push_str(": ");
            line.push_str(&t);
        }
        source = s.source();
    }
    line.replace('\n', " ")
}

#[cfg(test)]
mod tests {
    use super::{error_line, flag_of};
    use outlinefit::{Config, Error};

    #[test]
    fn fields_map_to_their_flags() {
        assert_eq!(flag_of("max_pixels"), "--max-pixels");
        assert_eq!(flag_of("tolerance"), "--tolerance");
        assert_eq!(flag_of("shape"), "--omega/--lambda/--mu");
        assert_eq!(flag_of("feature_grid"), "--grid");
    }

    #[test]
    fn an_invalid_config_is_reported_with_the_flag() {
        let config = Config {
            tolerance: -1.0,
            ..Config::default()
        };
        let e = config.validate().unwrap_err();
        assert!(matches!(
            e,
            Error::InvalidOption {
                name: "tolerance",
                ..
            }
        ));
        assert_eq!(
            error_line(&e),
            "invalid option --tolerance: must be a positive number of pixels"
        );
        let e = Error::AllBelowMinArea {
            shapes: 3,
            min_area: 2.0,
        };
        assert!(error_line(&e).ends_with("(lower --min-area to keep them)"));
    }
}
