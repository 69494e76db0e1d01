//! `--mode centerline` on `trace` and `batch`: the options, what they refuse, and the
//! warnings of a centre-line trace.

use super::args::FitArgs;
use anyhow::bail;
use clap::{Args, ValueEnum};
use outlinefit::centerline::{CenterlineResult, StrokeWidth};
use outlinefit::{Config, Format, Method};

/// What is traced, as named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum ModeArg {
    /// The outlines of shapes (letters, logos, silhouettes), filled.
    Outline,
    /// The centre lines of strokes (line art, handwriting, technical drawings) with their
    /// width.
    Centerline,
}

/// How a stroke's width is fitted, as named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum StrokeWidthArg {
    /// A width that varies along each stroke (disk Wang–Ball curves), drawn as the filled
    /// envelope of the disks.
    Variable,
    /// One width per stroke, drawn as a stroked centre line.
    Constant,
}

/// The tracing mode, shared by `trace` and `batch`.
#[derive(Args, Debug, Clone)]
pub(crate) struct ModeArgs {
    /// What to trace: `outline` (shapes, filled) or `centerline` (strokes as centre lines
    /// with their width).
    ///
    /// What to trace. `outline` (default): the outlines of shapes, filled. `centerline`:
    /// line art and handwriting as strokes, each a centre line with its width (a chain of
    /// disk Wang–Ball curves); the SVG holds the drawn strokes in <g id="strokes"> and the
    /// bare centre lines (for plotters, engravers, cutters) in <g id="centerlines">, and
    /// the reports list every stroke. SVG only.
    #[arg(
        long,
        value_enum,
        default_value = "outline",
        value_name = "MODE",
        help_heading = "Tracing"
    )]
    pub(crate) mode: ModeArg,
    /// With --mode centerline: `variable` width along each stroke (default) or one
    /// `constant` width per stroke.
    #[arg(long, value_enum, value_name = "W", help_heading = "Tracing")]
    pub(crate) stroke_width: Option<StrokeWidthArg>,
}

impl ModeArgs {
    /// The stroke width of a centre-line trace, or `None` for outlines. Refuses what a
    /// centre-line trace cannot do, before any work.
    pub(crate) fn centerline(
        &self,
        fit: &FitArgs,
        config: &Config,
        format: Format,
        palette: bool,
    ) -> anyhow::Result<Option<StrokeWidth>> {
        if self.mode == ModeArg::Outline {
            if self.stroke_width.is_some() {
                bail!("--stroke-width applies to --mode centerline; leave it out for outlines");
            }
            return Ok(None);
        }
        if format != Format::Svg {
            bail!(
                "--mode centerline writes SVG only, not {}; give an output ending in .svg or --format svg",
                format.extension().to_uppercase()
            );
        }
        if palette {
            bail!("--mode centerline traces one colour; leave --palette out");
        }
        if config.optimizer != Method::Lsq {
            bail!("--optimizer applies to outlines; --mode centerline fits by least squares");
        }
        if fit.merge {
            bail!(
                "--merge applies to outlines; --mode centerline already fits disk Wang–Ball curves"
            );
        }
        if config.breaks != outlinefit::BreakPlacement::Curvature {
            bail!("--breaks optimize applies to outlines; leave it out with --mode centerline");
        }
        Ok(Some(match self.stroke_width {
            Some(StrokeWidthArg::Constant) => StrokeWidth::Constant,
            _ => StrokeWidth::Variable,
        }))
    }
}

/// What is wrong with a centre-line trace, if its check ran and did not hold.
pub(crate) fn centerline_problem(config: &Config, result: &CenterlineResult) -> Option<String> {
    let c = &result.check;
    if !config.check || c.held {
        return None;
    }
    Some(format!(
        "the drawn strokes do not match the input: {} lost and {} invented regions (largest {} px; {} px lost, {} px invented in all)",
        c.lost_regions, c.invented_regions, c.largest_region, c.lost_pixels, c.invented_pixels
    ))
}

/// The warnings of a centre-line trace, one line each.
pub(crate) fn centerline_warnings(
    name: &str,
    config: &Config,
    result: &CenterlineResult,
) -> Vec<String> {
    let mut out = Vec::new();
    if result.not_stroke_like {
        let blob = result
            .strokes
            .iter()
            .filter(|s| !s.is_stroke_like())
            .max_by(|a, b| a.width_range[1].total_cmp(&b.width_range[1]));
        let detail = blob.map_or(String::new(), |s| {
            format!(
                " (the widest is {:.1} px wide and {:.1} px long)",
                s.width_range[1], s.length
            )
        });
        out.push(format!(
            "warning: {name}: the shapes are not stroke-like: much of the ink is in strokes wider than half their length{detail}; --mode outline traces filled shapes"
        ));
    }
    if let Some(problem) = centerline_problem(config, result) {
        out.push(format!("warning: {name}: {problem}"));
    }
    let tol = config.tolerance;
    let centre: Vec<f64> = result
        .strokes
        .iter()
        .map(|s| s.centre_max)
        .filter(|&d| d > tol)
        .collect();
    let radius: Vec<f64> = result
        .strokes
        .iter()
        .map(|s| s.radius_max)
        .filter(|&d| d > tol)
        .collect();
    let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let n = result.strokes.len();
    if !centre.is_empty() {
        out.push(format!(
            "warning: {name}: the centre line of {} of {n} strokes misses --tolerance {tol} px somewhere (up to {:.2} px; pieces too short to split, or noisy edges)",
            centre.len(),
            worst(&centre)
        ));
    }
    if !radius.is_empty() {
        let why = match result.stroke_width {
            StrokeWidth::Constant => "their width varies more than one width per stroke can draw; --stroke-width variable follows it",
            StrokeWidth::Variable => "pieces too short to split, or noisy edges",
        };
        out.push(format!(
            "warning: {name}: the width of {} of {n} strokes misses --tolerance {tol} px somewhere (radius up to {:.2} px off: {why})",
            radius.len(),
            worst(&radius)
        ));
    }
    out
}
