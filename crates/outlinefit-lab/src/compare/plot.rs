//! SVG charts for `outlinefit compare`: convergence curves, final-error box plots and
//! per-segment minimum errors (the HS paper's Fig. 9), drawn with `plotters`.
//!
//! Every function returns the whole SVG document as a `String`; the caller decides where
//! (and how atomically) to write it. The output is deterministic: the same input gives a
//! byte-identical document.
//!
//! Text is emitted as SVG `<text>` elements in the `sans-serif` family and laid out by the
//! viewer, so no font is bundled or needed: `plotters` without its `ttf`/`ab_glyph`
//! features only estimates text extents (about 0.7 em per byte) to place labels.
//!
//! All three charts use a logarithmic y axis. Conventions shared by every function:
//!
//! - **Non-finite values** (NaN, ±∞) are treated as missing data and skipped; a chart in
//!   which nothing finite is left fails with [`PlotError::NoData`].
//! - **Zero and negative values** cannot be placed on a log axis; they are drawn at a floor
//!   one decade below the smallest positive value of the chart (`1e-12` if there is none).
//! - The y axis always spans whole decades, so it has at least two labelled ticks.
//! - Series `k` gets colour [`series_color`]`(k)`: eleven distinct colours, then they repeat.

use crate::stats::quantile_sorted;
use plotters::coord::combinators::IntoLogRange;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, KeyPointWeight, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Why a chart could not be drawn.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlotError {
    /// There is nothing to plot (no series, no runs, zero-length runs).
    #[error("nothing to plot: {0}")]
    Empty(String),
    /// Inputs that must have the same length do not.
    #[error("mismatched lengths: {0}")]
    Mismatch(String),
    /// An input is malformed (e.g. evaluation counts that do not increase).
    #[error("invalid input: {0}")]
    Invalid(String),
    /// Every value is NaN or infinite.
    #[error("no finite value to plot: {0}")]
    NoData(String),
    /// The drawing backend failed; the message is its error.
    #[error("drawing failed: {0}")]
    Drawing(String),
}

/// One optimizer's convergence history over several seeded runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceSeries {
    /// The optimizer's name, shown in the legend.
    pub name: String,
    /// For each run, the best-so-far total error after each evaluation count of the
    /// `evaluations` passed to [`convergence`] (`runs[r][i]` = error of run `r` after
    /// `evaluations[i]` evaluations). Every run has `evaluations.len()` values.
    pub runs: Vec<Vec<f64>>,
}

/// Width of every chart, in SVG pixels (the box plot grows with many groups).
pub const WIDTH: u32 = 960;
/// Height of every chart, in SVG pixels.
pub const HEIGHT: u32 = 600;
/// Most points drawn per convergence curve; longer histories are downsampled.
pub const MAX_CURVE_POINTS: usize = 400;
/// Name of the reference series in [`segment_errors`]'s legend.
pub const REFERENCE_LABEL: &str = "least squares (reference)";

/// Fallback floor of the log axis when a chart has no positive value at all.
const ABSOLUTE_FLOOR: f64 = 1e-12;

/// Eleven distinct series colours (Tableau 10 plus navy).
const PALETTE: [RGBColor; 11] = [
    RGBColor(0x1F, 0x77, 0xB4),
    RGBColor(0xFF, 0x7F, 0x0E),
    RGBColor(0x2C, 0xA0, 0x2C),
    RGBColor(0xD6, 0x27, 0x28),
    RGBColor(0x94, 0x67, 0xBD),
    RGBColor(0x8C, 0x56, 0x4B),
    RGBColor(0xE3, 0x77, 0xC2),
    RGBColor(0x7F, 0x7F, 0x7F),
    RGBColor(0xBC, 0xBD, 0x22),
    RGBColor(0x17, 0xBE, 0xCF),
    RGBColor(0x00, 0x00, 0x75),
];

/// The colour of series `k` in every chart: eleven distinct colours, then they repeat.
pub fn series_color(k: usize) -> RGBColor {
    PALETTE[k % PALETTE.len()]
}

/// A drawing error of plotters as a [`PlotError`].
pub(crate) fn drawing<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Drawing(e.to_string())
}

/// Every chart's frame: its caption, margin and axis label areas.
fn chart_frame<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &'b str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(root);
    builder
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70);
    builder
}

/// The series legend of a chart: upper right, on a translucent white box.
fn draw_legend<'a, DB, CT>(chart: &mut ChartContext<'a, DB, CT>) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(drawing)
}

/// Tick label for a positive log-axis value: plain decimals between 1e-3 and 1e4,
/// otherwise scientific with at most three significant digits ("1e-6", "2.5e8").
fn fmt_tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor();
    if (-3.0..=4.0).contains(&e) {
        let decimals = (2.0 - e).max(0.0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((mantissa, exp)) => {
                let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
                format!("{mantissa}e{exp}")
            }
            None => s,
        }
    }
}

/// The floor for non-positive values: a decade below the smallest positive value.
fn log_floor(values: impl IntoIterator<Item = f64>) -> f64 {
    let min_pos = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold(f64::INFINITY, f64::min);
    if min_pos.is_finite() {
        min_pos / 10.0
    } else {
        ABSOLUTE_FLOOR
    }
}

/// A log-axis range of whole decades covering `[lo, hi]` (both positive and finite).
fn decade_range(lo: f64, hi: f64) -> std::ops::Range<f64> {
    let mut a = lo.log10().floor();
    let mut b = hi.log10().ceil();
    if b <= a {
        a -= 1.0;
        b += 1.0;
    }
    // Nudged outwards so that plotters' tick search (ceil of a rounded logarithm, repeated
    // multiplication) keeps the end decades as labelled ticks.
    10f64.powf(a) * (1.0 - 1e-9)..10f64.powf(b) * (1.0 + 1e-9)
}

/// Indices of at most `max` (≥ 4) samples of a history of `len` points: half log-spaced,
/// half evenly spaced, always including the first and last, strictly increasing.
fn sample_indices(len: usize, max: usize) -> Vec<usize> {
    if len <= max {
        return (0..len).collect();
    }
    let half = max / 2;
    let ln = (len as f64).ln();
    let mut idx = Vec::with_capacity(2 * half);
    for j in 0..half {
        let t = j as f64 / (half - 1) as f64;
        let position = (t * ln).exp().round() as usize; // 1..=len
        idx.push(position.clamp(1, len) - 1);
        idx.push((t * (len - 1) as f64).round() as usize);
    }
    idx.sort_unstable();
    idx.dedup();
    idx
}

/// A linear f64 axis whose ticks sit exactly at given values (group or segment numbers),
/// labelled by the chart's own formatter.
struct TickedAxis {
    linear: RangedCoordf64,
    ticks: Vec<f64>,
}

impl TickedAxis {
    fn new(range: std::ops::Range<f64>, ticks: Vec<f64>) -> Self {
        TickedAxis {
            linear: range.into(),
            ticks,
        }
    }
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.linear.map(value, limit)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        match hint.weight() {
            // Light mesh lines between the ticks would only add clutter.
            KeyPointWeight::Any => vec![],
            KeyPointWeight::Bold => self.ticks.clone(),
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.linear.range()
    }
}

/// The quartiles of one sampled evaluation: `(evaluation, q25, median, q75)`.
type BandPoint = (f64, f64, f64, f64);

/// Draws convergence curves: per optimizer, the median best-so-far error across runs as a
/// line and its inter-quartile range (25–75 %) as a translucent band, against the number of
/// evaluations, on a log y axis, with a legend.
///
/// `evaluations[i]` is the evaluation count after which every run's `i`-th value was
/// recorded (strictly increasing; for a full history pass `1..=len`). Histories longer than
/// [`MAX_CURVE_POINTS`] are downsampled (half log-spaced, half evenly spaced indices, always
/// keeping the first and the last). At each sampled point the quartiles are taken over the
/// runs whose value is finite; a series with no finite value is listed in the legend but
/// not drawn.
///
/// Errors: no series, a series without runs, no evaluation counts, runs whose length
/// differs from `evaluations.len()`, evaluation counts that do not strictly increase, or
/// no finite value anywhere.
pub fn convergence(
    title: &str,
    evaluations: &[u64],
    series: &[ConvergenceSeries],
) -> Result<String, PlotError> {
    if series.is_empty() {
        return Err(PlotError::Empty("no convergence series".into()));
    }
    let len = evaluations.len();
    if len == 0 {
        return Err(PlotError::Empty("no evaluation counts".into()));
    }
    if let Some(w) = evaluations.windows(2).find(|w| w[0] >= w[1]) {
        return Err(PlotError::Invalid(format!(
            "evaluation counts must increase, found {} then {}",
            w[0], w[1]
        )));
    }
    for s in series {
        if s.runs.is_empty() {
            return Err(PlotError::Empty(format!("series {:?} has no runs", s.name)));
        }
        if let Some((r, run)) = s.runs.iter().enumerate().find(|(_, run)| run.len() != len) {
            return Err(PlotError::Mismatch(format!(
                "run {r} of {:?} has {} values for {len} evaluation counts",
                s.name,
                run.len()
            )));
        }
    }

    let indices = sample_indices(len, MAX_CURVE_POINTS);
    let bands: Vec<Vec<BandPoint>> = series
        .iter()
        .map(|s| {
            let mut column = Vec::with_capacity(s.runs.len());
            indices
                .iter()
                .filter_map(|&i| {
                    column.clear();
                    column.extend(s.runs.iter().map(|run| run[i]).filter(|v| v.is_finite()));
                    if column.is_empty() {
                        return None;
                    }
                    column.sort_unstable_by(f64::total_cmp);
                    Some((
                        evaluations[i] as f64,
                        quantile_sorted(&column, 0.25),
                        quantile_sorted(&column, 0.5),
                        quantile_sorted(&column, 0.75),
                    ))
                })
                .collect()
        })
        .collect();
    if bands.iter().all(Vec::is_empty) {
        return Err(PlotError::NoData(
            "every convergence value is non-finite".into(),
        ));
    }

    let floor = log_floor(bands.iter().flatten().flat_map(|p| [p.1, p.2, p.3]));
    let clamp = |v: f64| v.max(floor);
    let (lo, hi) = bands
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(clamp(p.1)), hi.max(clamp(p.3)))
        });

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let mut chart = chart_frame(&root, title)
            .build_cartesian_2d(
                0f64..(evaluations[len - 1] as f64).max(1.0),
                decade_range(lo, hi).log_scale(),
            )
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("evaluations")
            .y_desc("best total error")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| fmt_tick(*y))
            .draw()
            .map_err(drawing)?;

        for (k, band) in bands.iter().enumerate() {
            if band.is_empty() {
                continue;
            }
            let outline: Vec<(f64, f64)> = band
                .iter()
                .map(|p| (p.0, clamp(p.3)))
                .chain(band.iter().rev().map(|p| (p.0, clamp(p.1))))
                .collect();
            chart
                .draw_series(std::iter::once(Polygon::new(
                    outline,
                    series_color(k).mix(0.2).filled(),
                )))
                .map_err(drawing)?;
        }
        for (k, (s, band)) in series.iter().zip(&bands).enumerate() {
            let color = series_color(k);
            chart
                .draw_series(LineSeries::new(
                    band.iter().map(|p| (p.0, clamp(p.2))),
                    color.stroke_width(2),
                ))
                .map_err(drawing)?
                .label(s.name.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        draw_legend(&mut chart)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// Tukey box-plot statistics of one group, every value already clamped to the floor.
struct BoxStats {
    q1: f64,
    median: f64,
    q3: f64,
    /// Smallest value within 1.5 IQR below the lower quartile.
    low_whisker: f64,
    /// Largest value within 1.5 IQR above the upper quartile.
    high_whisker: f64,
    outliers: Vec<f64>,
}

impl BoxStats {
    /// `sorted` must be non-empty and sorted ascending.
    fn new(sorted: &[f64]) -> Self {
        let q1 = quantile_sorted(sorted, 0.25);
        let median = quantile_sorted(sorted, 0.5);
        let q3 = quantile_sorted(sorted, 0.75);
        let iqr = q3 - q1;
        let (lo_fence, hi_fence) = (q1 - 1.5 * iqr, q3 + 1.5 * iqr);
        let inside = || {
            sorted
                .iter()
                .copied()
                .filter(|v| (lo_fence..=hi_fence).contains(v))
        };
        BoxStats {
            q1,
            median,
            q3,
            low_whisker: inside().next().unwrap_or(q1).min(q1),
            high_whisker: inside().next_back().unwrap_or(q3).max(q3),
            outliers: sorted
                .iter()
                .copied()
                .filter(|v| !(lo_fence..=hi_fence).contains(v))
                .collect(),
        }
    }
}

/// Draws one box per group (an optimizer's final errors over its runs) on a log y axis,
/// with the group names on the x axis: the box spans the quartiles (linear-interpolation
/// percentiles), a black line marks the median, the whiskers reach the most extreme values
/// within 1.5 IQR of the box (Tukey) and values beyond are drawn as hollow circles.
///
/// A group whose values are all equal draws as a flat box. A group that is empty or
/// holds only non-finite values keeps its place and label but draws nothing.
///
/// Errors: no groups, or no finite value in any group.
pub fn boxplot(title: &str, groups: &[(String, Vec<f64>)]) -> Result<String, PlotError> {
    if groups.is_empty() {
        return Err(PlotError::Empty("no box-plot groups".into()));
    }
    let finite: Vec<Vec<f64>> = groups
        .iter()
        .map(|(_, values)| values.iter().copied().filter(|v| v.is_finite()).collect())
        .collect();
    if finite.iter().all(Vec::is_empty) {
        return Err(PlotError::NoData(
            "every box-plot value is non-finite".into(),
        ));
    }
    let floor = log_floor(finite.iter().flatten().copied());
    let stats: Vec<Option<BoxStats>> = finite
        .iter()
        .map(|values| {
            if values.is_empty() {
                return None;
            }
            let mut sorted: Vec<f64> = values.iter().map(|v| v.max(floor)).collect();
            sorted.sort_unstable_by(f64::total_cmp);
            Some(BoxStats::new(&sorted))
        })
        .collect();
    let (lo, hi) =
        stats
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                let min = s.outliers.iter().copied().fold(s.low_whisker, f64::min);
                let max = s.outliers.iter().copied().fold(s.high_whisker, f64::max);
                (lo.min(min), hi.max(max))
            });

    let n = groups.len();
    let width = WIDTH.max(160 + 90 * n as u32);
    let names: Vec<&str> = groups.iter().map(|(name, _)| name.as_str()).collect();
    let label = |x: &f64| {
        let i = x.round();
        if i >= 0.0 && (i as usize) < names.len() {
            names[i as usize].to_string()
        } else {
            String::new()
        }
    };

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let key_points: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let mut chart = chart_frame(&root, title)
            .build_cartesian_2d(
                TickedAxis::new(-0.5..n as f64 - 0.5, key_points),
                decade_range(lo, hi).log_scale(),
            )
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .y_desc("final total error")
            .x_label_formatter(&label)
            .y_label_formatter(&|y| fmt_tick(*y))
            .draw()
            .map_err(drawing)?;

        const HALF_BOX: f64 = 0.3;
        const HALF_CAP: f64 = 0.15;
        for (i, s) in stats.iter().enumerate() {
            let Some(s) = s else { continue };
            let color = series_color(i);
            let x = i as f64;
            let line = |a: (f64, f64), b: (f64, f64)| PathElement::new(vec![a, b], color);
            chart
                .draw_series([
                    line((x, s.q1), (x, s.low_whisker)),
                    line((x, s.q3), (x, s.high_whisker)),
                    line((x - HALF_CAP, s.low_whisker), (x + HALF_CAP, s.low_whisker)),
                    line(
                        (x - HALF_CAP, s.high_whisker),
                        (x + HALF_CAP, s.high_whisker),
                    ),
                ])
                .map_err(drawing)?;
            let corners = [(x - HALF_BOX, s.q3), (x + HALF_BOX, s.q1)];
            chart
                .draw_series([
                    Rectangle::new(corners, color.mix(0.25).filled()),
                    Rectangle::new(corners, color.stroke_width(1)),
                ])
                .map_err(drawing)?;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(x - HALF_BOX, s.median), (x + HALF_BOX, s.median)],
                    BLACK.stroke_width(2),
                )))
                .map_err(drawing)?;
            chart
                .draw_series(
                    s.outliers
                        .iter()
                        .map(|&v| Circle::new((x, v), 3, color.stroke_width(1))),
                )
                .map_err(drawing)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// Draws each optimizer's minimum error per segment (the HS paper's Fig. 9): x is the
/// segment number (1-based), each optimizer's values are filled circles joined by a line in
/// its colour, on a log y axis; `reference` (the least-squares optimum of each segment), if
/// given, is a black line with crosses labelled [`REFERENCE_LABEL`].
///
/// `errors[k][s]` is optimizer `k`'s minimum error on segment `s`. A non-finite value is
/// skipped and breaks that line (as does a non-finite reference value).
///
/// Errors: no optimizers or no segments; `optimizers`, `errors` or `reference` lengths that
/// disagree; no finite value at all.
pub fn segment_errors(
    title: &str,
    optimizers: &[String],
    errors: &[Vec<f64>],
    reference: Option<&[f64]>,
) -> Result<String, PlotError> {
    if optimizers.is_empty() {
        return Err(PlotError::Empty("no optimizers".into()));
    }
    if optimizers.len() != errors.len() {
        return Err(PlotError::Mismatch(format!(
            "{} optimizer names but {} error rows",
            optimizers.len(),
            errors.len()
        )));
    }
    let segments = errors[0].len();
    if segments == 0 {
        return Err(PlotError::Empty("no segments".into()));
    }
    for (name, row) in optimizers.iter().zip(errors) {
        if row.len() != segments {
            return Err(PlotError::Mismatch(format!(
                "{name:?} has {} segment errors, expected {segments}",
                row.len()
            )));
        }
    }
    if let Some(r) = reference {
        if r.len() != segments {
            return Err(PlotError::Mismatch(format!(
                "the reference has {} segment errors, expected {segments}",
                r.len()
            )));
        }
    }
    let all = || {
        errors
            .iter()
            .flatten()
            .chain(reference.into_iter().flatten())
    };
    if !all().any(|v| v.is_finite()) {
        return Err(PlotError::NoData(
            "every segment error is non-finite".into(),
        ));
    }
    let floor = log_floor(all().copied());
    let clamp = |v: f64| v.max(floor);
    let (lo, hi) = all()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(clamp(v)), hi.max(clamp(v)))
        });

    // Runs of consecutive finite values, as (segment number, clamped error) points.
    let pieces = |row: &[f64]| -> Vec<Vec<(f64, f64)>> {
        let mut out: Vec<Vec<(f64, f64)>> = vec![];
        let mut current = vec![];
        for (s, &v) in row.iter().enumerate() {
            if v.is_finite() {
                current.push(((s + 1) as f64, clamp(v)));
            } else if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
        out
    };

    let step = segments.div_ceil(20);
    let key_points: Vec<f64> = (1..=segments).step_by(step).map(|s| s as f64).collect();

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let mut chart = chart_frame(&root, title)
            .build_cartesian_2d(
                TickedAxis::new(0.5..segments as f64 + 0.5, key_points),
                decade_range(lo, hi).log_scale(),
            )
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("segment")
            .y_desc("minimum error")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| fmt_tick(*y))
            .draw()
            .map_err(drawing)?;

        for (k, (name, row)) in optimizers.iter().zip(errors).enumerate() {
            let color = series_color(k);
            let pieces = pieces(row);
            chart
                .draw_series(
                    pieces
                        .iter()
                        .map(|p| PathElement::new(p.clone(), color.stroke_width(2))),
                )
                .map_err(drawing)?
                .label(name.as_str())
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (20, 0)], color.stroke_width(2))
                        + Circle::new((10, 0), 3, color.filled())
                });
            chart
                .draw_series(
                    pieces
                        .iter()
                        .flatten()
                        .map(|&p| Circle::new(p, 3, color.filled())),
                )
                .map_err(drawing)?;
        }
        if let Some(r) = reference {
            let pieces = pieces(r);
            chart
                .draw_series(
                    pieces
                        .iter()
                        .map(|p| PathElement::new(p.clone(), BLACK.stroke_width(1))),
                )
                .map_err(drawing)?
                .label(REFERENCE_LABEL)
                .legend(|(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (20, 0)], BLACK.stroke_width(1))
                        + Cross::new((10, 0), 4, BLACK.stroke_width(2))
                });
            chart
                .draw_series(
                    pieces
                        .iter()
                        .flatten()
                        .map(|&p| Cross::new(p, 4, BLACK.stroke_width(2))),
                )
                .map_err(drawing)?;
        }
        draw_legend(&mut chart)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random stream in (0, 1) for test data.
    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
    }

    /// Best-so-far histories decaying from about `start` towards `end` over `len` evaluations.
    fn histories(runs: usize, len: usize, start: f64, end: f64, seed: u64) -> Vec<Vec<f64>> {
        let mut rand = lcg(seed);
        (0..runs)
            .map(|_| {
                let speed = 2.0 + 6.0 * rand();
                let mut best = f64::INFINITY;
                (0..len)
                    .map(|i| {
                        let t = i as f64 / len as f64;
                        let v = end * (start / end).powf((-speed * t).exp()) * (1.0 + rand());
                        best = best.min(v);
                        best
                    })
                    .collect()
            })
            .collect()
    }

    /// Evaluation counts 1..=len, for full histories.
    fn every(len: usize) -> Vec<u64> {
        (1..=len as u64).collect()
    }

    fn example_convergence() -> Vec<ConvergenceSeries> {
        vec![
            ConvergenceSeries {
                name: "hs".into(),
                runs: histories(30, 5000, 1e5, 1e-3, 1),
            },
            ConvergenceSeries {
                name: "ga".into(),
                runs: histories(30, 5000, 1e5, 1e-1, 2),
            },
            ConvergenceSeries {
                name: "pso".into(),
                runs: histories(30, 5000, 1e5, 3.0, 3),
            },
        ]
    }

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    fn hex(c: RGBColor) -> String {
        format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
    }

    /// The trimmed contents of every `<text>` element.
    fn texts(svg: &str) -> Vec<String> {
        let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
        doc.descendants()
            .filter(|n| n.has_tag_name("text"))
            .map(|n| n.text().unwrap_or("").trim().to_string())
            .collect()
    }

    /// Every element named `tag` whose `attr` attribute equals `value`, as attribute maps.
    fn elements(svg: &str, tag: &str, attr: &str, value: &str) -> Vec<Vec<(String, String)>> {
        let doc = roxmltree::Document::parse(svg).expect("well-formed SVG");
        doc.descendants()
            .filter(|n| n.has_tag_name(tag) && n.attribute(attr) == Some(value))
            .map(|n| {
                n.attributes()
                    .map(|a| (a.name().to_string(), a.value().to_string()))
                    .collect()
            })
            .collect()
    }

    fn attr<'a>(element: &'a [(String, String)], name: &str) -> &'a str {
        element
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
            .unwrap_or_else(|| panic!("no attribute {name}"))
    }

    fn num(element: &[(String, String)], name: &str) -> f64 {
        attr(element, name).parse().unwrap()
    }

    fn points(element: &[(String, String)]) -> Vec<(i32, i32)> {
        attr(element, "points")
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    }

    /// The pixel row of the y-axis tick labelled `label` (labels are centred on their tick).
    fn tick_y(svg: &str, label: &str) -> i32 {
        let doc = roxmltree::Document::parse(svg).unwrap();
        doc.descendants()
            .find(|n| {
                n.has_tag_name("text")
                    && n.attribute("text-anchor") == Some("end")
                    && n.text().map(str::trim) == Some(label)
            })
            .and_then(|n| n.attribute("y"))
            .unwrap_or_else(|| panic!("no y tick {label}"))
            .parse()
            .unwrap()
    }

    /// Polylines stroked in `color` with more than two points (data lines, not legend
    /// swatches or whisker segments).
    fn data_lines(svg: &str, color: RGBColor) -> Vec<Vec<(i32, i32)>> {
        elements(svg, "polyline", "stroke", &hex(color))
            .iter()
            .map(|e| points(e))
            .filter(|p| p.len() > 2)
            .collect()
    }

    /// The renderer the viewers use must accept the document.
    fn renders(svg: &str) {
        let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default())
            .expect("usvg parses the chart");
        let size = tree.size().to_int_size();
        let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
        resvg::render(&tree, Default::default(), &mut pixmap.as_mut());
        // Something other than the white background was drawn.
        assert!(pixmap
            .pixels()
            .iter()
            .any(|p| p.red() < 200 || p.blue() < 200));
    }

    #[test]
    fn tick_labels_are_short_and_exact() {
        assert_eq!(fmt_tick(1e-6), "1e-6");
        assert_eq!(fmt_tick(2.5e8), "2.5e8");
        assert_eq!(fmt_tick(0.001), "0.001");
        assert_eq!(fmt_tick(0.01), "0.01");
        assert_eq!(fmt_tick(1.0), "1");
        assert_eq!(fmt_tick(10000.0), "10000");
        assert_eq!(fmt_tick(1e5), "1e5");
        assert_eq!(fmt_tick(0.15), "0.15");
        assert_eq!(fmt_tick(300.0), "300");
    }

    #[test]
    fn decade_range_covers_whole_decades_and_degenerate_values() {
        let r = decade_range(0.003, 40.0);
        assert!(r.start <= 1e-3 && r.start > 0.99e-3, "{r:?}");
        assert!(r.end >= 100.0 && r.end < 100.1, "{r:?}");
        let r = decade_range(0.1, 0.1);
        assert!(r.start < 0.1 && r.end > 0.1, "{r:?}");
    }

    #[test]
    fn sampling_keeps_ends_is_increasing_and_bounded() {
        for len in [1, 2, 399, 400, 401, 5000, 100_000] {
            let idx = sample_indices(len, MAX_CURVE_POINTS);
            assert!(idx.len() <= MAX_CURVE_POINTS, "{len}: {}", idx.len());
            assert_eq!(idx[0], 0);
            assert_eq!(*idx.last().unwrap(), len - 1);
            assert!(idx.windows(2).all(|w| w[0] < w[1]));
        }
        // Dense at the start (log-spaced) and spread over the end (evenly spaced).
        let idx = sample_indices(5000, MAX_CURVE_POINTS);
        assert!((0..10).all(|i| idx.contains(&i)));
        assert!(idx.iter().filter(|&&i| i >= 2500).count() > 90);
    }

    #[test]
    fn convergence_draws_every_series_with_band_line_and_legend() {
        let series = example_convergence();
        let svg = convergence("Convergence on letter S", &every(5000), &series).unwrap();
        let texts = texts(&svg);
        assert!(texts.iter().any(|t| t == "Convergence on letter S"));
        for (k, s) in series.iter().enumerate() {
            assert!(texts.contains(&s.name), "legend lacks {}", s.name);
            let color = series_color(k);
            let lines = data_lines(&svg, color);
            assert_eq!(lines.len(), 1, "one median line for {}", s.name);
            assert!(lines[0].len() > 100 && lines[0].len() <= MAX_CURVE_POINTS);
            let bands = elements(&svg, "polygon", "fill", &hex(color));
            assert_eq!(bands.len(), 1, "one band for {}", s.name);
            assert!(num(&bands[0], "opacity") < 1.0, "the band is translucent");
            // The band spans twice the sampled evaluations (upper edge, then lower).
            assert_eq!(points(&bands[0]).len(), 2 * lines[0].len());
            let swatches = elements(&svg, "polyline", "stroke", &hex(color))
                .iter()
                .filter(|e| points(e).len() == 2)
                .count();
            assert_eq!(swatches, 1, "one legend swatch for {}", s.name);
        }
        renders(&svg);
    }

    #[test]
    fn convergence_series_ending_lower_ends_lower_on_the_chart() {
        let series = example_convergence(); // hs → 1e-3, ga → 1e-1, pso → 3
        let svg = convergence("c", &every(5000), &series).unwrap();
        let last_y = |k: usize| data_lines(&svg, series_color(k))[0].last().unwrap().1;
        let first_y = |k: usize| data_lines(&svg, series_color(k))[0][0].1;
        assert!(last_y(0) > last_y(1), "{} vs {}", last_y(0), last_y(1));
        assert!(last_y(1) > last_y(2), "{} vs {}", last_y(1), last_y(2));
        // Each curve descends, and all start near the same value.
        for k in 0..3 {
            assert!(first_y(k) < last_y(k) - 100);
            assert!((first_y(k) - first_y(0)).abs() <= 5);
        }
        // The last point is at the right end of the x axis, the first at its left.
        let line = &data_lines(&svg, series_color(0))[0];
        assert!(line.last().unwrap().0 - line[0].0 > 800);
    }

    #[test]
    fn convergence_median_is_the_middle_run() {
        // Five constant runs: the quartiles are 1e-4 and 1 (the axis spans exactly those
        // decades) and the median 1e-2 lies halfway up the log axis.
        let runs = vec![
            vec![1e-4; 50],
            vec![1.0; 50],
            vec![1e-2; 50],
            vec![1e-4; 50],
            vec![1.0; 50],
        ];
        let svg = convergence(
            "m",
            &every(50),
            &[ConvergenceSeries {
                name: "x".into(),
                runs,
            }],
        )
        .unwrap();
        let median_y = data_lines(&svg, series_color(0))[0][0].1;
        // The y axis spans 1e-4..1 exactly, so 1e-2 is at its middle; the axis labels
        // give the pixel rows of those decades.
        let label_y = |label: &str| tick_y(&svg, label);
        let (top, bottom) = (label_y("1"), label_y("1e-4"));
        let middle = (top + bottom) / 2;
        assert!((median_y - middle).abs() <= 2, "{median_y} vs {middle}");
        assert_eq!(label_y("0.01"), middle);
    }

    #[test]
    fn convergence_tolerates_infinite_starts_and_zeros() {
        let mut run = vec![f64::INFINITY; 3];
        run.extend([5.0, 1.0, 0.0, 0.0]);
        let svg = convergence(
            "z",
            &every(7),
            &[
                ConvergenceSeries {
                    name: "zeroes".into(),
                    runs: vec![run.clone(), run],
                },
                ConvergenceSeries {
                    name: "nan".into(),
                    runs: vec![vec![f64::NAN; 7]],
                },
            ],
        )
        .unwrap();
        // The non-finite prefix is skipped: four points remain.
        assert_eq!(data_lines(&svg, series_color(0))[0].len(), 4);
        // The all-NaN series is in the legend but draws no line.
        assert!(texts(&svg).contains(&"nan".to_string()));
        assert!(data_lines(&svg, series_color(1)).is_empty());
        for bad in ["NaN", "inf"] {
            assert!(!svg.contains(bad), "{bad} leaked into the SVG");
        }
    }

    #[test]
    fn convergence_places_points_at_their_evaluation_counts() {
        // Sampled after 1, 10 and 1000 evaluations: the gaps between the points are in
        // the ratio 9 : 990 on the linear x axis, and the last point is at its right end.
        let runs = vec![vec![100.0, 10.0, 1.0]];
        let series = [ConvergenceSeries {
            name: "s".into(),
            runs,
        }];
        let svg = convergence("x", &[1, 10, 1000], &series).unwrap();
        let line = &data_lines(&svg, series_color(0))[0];
        let (a, b) = (line[1].0 - line[0].0, line[2].0 - line[1].0);
        // The plot area is about 865 px wide for 1000 evaluations: 9 → ~8 px, 990 → ~857 px.
        assert!(
            (6..=10).contains(&a) && (840..=870).contains(&b),
            "{line:?}"
        );
        assert!(texts(&svg).contains(&"1000".to_string()));
    }

    #[test]
    fn convergence_rejects_bad_input() {
        let s = |runs: Vec<Vec<f64>>| ConvergenceSeries {
            name: "a".into(),
            runs,
        };
        let five = every(5);
        assert!(matches!(
            convergence("t", &five, &[]),
            Err(PlotError::Empty(_))
        ));
        assert!(matches!(
            convergence("t", &five, &[s(vec![])]),
            Err(PlotError::Empty(_))
        ));
        assert!(matches!(
            convergence("t", &[], &[s(vec![vec![]])]),
            Err(PlotError::Empty(_))
        ));
        assert!(matches!(
            convergence("t", &five, &[s(vec![vec![1.0; 5], vec![1.0; 4]])]),
            Err(PlotError::Mismatch(_))
        ));
        assert!(matches!(
            convergence("t", &five, &[s(vec![vec![1.0; 5]]), s(vec![vec![1.0; 6]])]),
            Err(PlotError::Mismatch(_))
        ));
        assert!(matches!(
            convergence("t", &[1, 5, 5], &[s(vec![vec![1.0; 3]])]),
            Err(PlotError::Invalid(_))
        ));
        assert!(matches!(
            convergence("t", &[1, 2], &[s(vec![vec![f64::NAN, f64::INFINITY]])]),
            Err(PlotError::NoData(_))
        ));
    }

    /// The y extent (top, bottom) of the outlined box of group `k`.
    fn box_extent(svg: &str, k: usize) -> (f64, f64) {
        let boxes = elements(svg, "rect", "stroke", &hex(series_color(k)));
        assert_eq!(boxes.len(), 1, "one box outline for group {k}");
        let y = num(&boxes[0], "y");
        (y, y + num(&boxes[0], "height"))
    }

    #[test]
    fn boxplot_places_boxes_by_their_quartiles() {
        let groups = vec![
            ("low".to_string(), vec![0.01, 0.02, 0.03, 0.04, 0.05]),
            ("high".to_string(), vec![1.0, 2.0, 3.0, 4.0, 5.0]),
            ("flat".to_string(), vec![0.3; 7]),
        ];
        let svg = boxplot("Final error", &groups).unwrap();
        let texts = texts(&svg);
        for (name, _) in &groups {
            assert!(texts.contains(name), "x axis lacks {name}");
        }
        let (low_top, low_bottom) = box_extent(&svg, 0);
        let (high_top, high_bottom) = box_extent(&svg, 1);
        let (flat_top, flat_bottom) = box_extent(&svg, 2);
        assert!(high_bottom < low_top, "the larger group's box sits higher");
        assert!(low_top < low_bottom && high_top < high_bottom);
        assert_eq!(flat_top, flat_bottom, "identical values give a flat box");
        assert!(high_bottom < flat_top && flat_bottom < low_top);
        // One black median bar per group, inside its box.
        let medians: Vec<_> = elements(&svg, "polyline", "stroke-width", "2")
            .into_iter()
            .filter(|e| attr(e, "stroke") == "#000000")
            .map(|e| points(&e))
            .collect();
        assert_eq!(medians.len(), 3);
        for (m, (top, bottom)) in medians.iter().zip([
            (low_top, low_bottom),
            (high_top, high_bottom),
            (flat_top, flat_bottom),
        ]) {
            assert_eq!(m[0].1, m[1].1, "the median bar is horizontal");
            assert!(top <= m[0].1 as f64 && m[0].1 as f64 <= bottom);
        }
        // On the log axis the median 3 of 1..5 sits log(3/2)/log(4/2) = 58.5 % of the way
        // up the box from its lower quartile 2 to its upper quartile 4.
        let expected = high_bottom - (1.5f64.ln() / 2f64.ln()) * (high_bottom - high_top);
        let got = f64::from(medians[1][0].1);
        assert!((got - expected).abs() <= 2.0, "{got} vs {expected}");
        // The flat group's bar sits at 0.3, between the 0.1 and 1 ticks.
        let ratio = f64::from(tick_y(&svg, "0.1") - medians[2][0].1)
            / f64::from(tick_y(&svg, "0.1") - tick_y(&svg, "1"));
        assert!((ratio - 0.3f64.log10() - 1.0).abs() < 0.02, "{ratio}");
        renders(&svg);
    }

    #[test]
    fn boxplot_whiskers_stop_at_the_fences_and_outliers_are_circles() {
        let mut values: Vec<f64> = (1..=20).map(f64::from).collect();
        values.push(1000.0);
        let svg = boxplot("o", &[("g".to_string(), values)]).unwrap();
        let color = hex(series_color(0));
        let outliers = elements(&svg, "circle", "stroke", &color);
        assert_eq!(outliers.len(), 1);
        // The whisker caps are horizontal segments in the group colour; the top one (at 20)
        // lies below the outlier (at 1000).
        let caps: Vec<i32> = elements(&svg, "polyline", "stroke", &color)
            .iter()
            .map(|e| points(e))
            .filter(|p| p.len() == 2 && p[0].1 == p[1].1)
            .map(|p| p[0].1)
            .collect();
        assert_eq!(caps.len(), 2);
        let top_cap = *caps.iter().min().unwrap();
        assert!(num(&outliers[0], "cy") < f64::from(top_cap) - 50.0);
    }

    #[test]
    fn boxplot_skips_non_finite_values_and_empty_groups() {
        let svg = boxplot(
            "s",
            &[
                (
                    "a".to_string(),
                    vec![1.0, f64::NAN, 2.0, f64::INFINITY, 0.0],
                ),
                ("empty".to_string(), vec![]),
            ],
        )
        .unwrap();
        assert_eq!(
            elements(&svg, "rect", "stroke", &hex(series_color(0))).len(),
            1
        );
        assert!(elements(&svg, "rect", "stroke", &hex(series_color(1))).is_empty());
        assert!(texts(&svg).contains(&"empty".to_string()));
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    #[test]
    fn boxplot_rejects_bad_input() {
        assert!(matches!(boxplot("t", &[]), Err(PlotError::Empty(_))));
        assert!(matches!(
            boxplot("t", &[("a".into(), vec![f64::NAN]), ("b".into(), vec![])]),
            Err(PlotError::NoData(_))
        ));
    }

    #[test]
    fn segment_errors_draws_each_optimizer_and_the_reference() {
        let optimizers = names(&["hs", "ga"]);
        let errors = vec![vec![0.01, 0.1, 1.0, 0.5], vec![0.02, 0.2, 2.0, 1.0]];
        let reference = [0.005, 0.05, 0.5, 0.2];
        let svg = segment_errors("Fig. 9", &optimizers, &errors, Some(&reference)).unwrap();
        let texts = texts(&svg);
        for name in optimizers
            .iter()
            .map(String::as_str)
            .chain([REFERENCE_LABEL])
        {
            assert!(texts.iter().any(|t| t == name), "legend lacks {name}");
        }
        for s in 1..=4 {
            assert!(texts.contains(&s.to_string()), "x axis lacks segment {s}");
        }
        for k in 0..2 {
            let color = series_color(k);
            let lines = data_lines(&svg, color);
            assert_eq!(lines.len(), 1);
            let ys: Vec<i32> = lines[0].iter().map(|p| p.1).collect();
            // Larger error → higher on the chart (smaller pixel y).
            assert!(ys[0] > ys[1] && ys[1] > ys[2] && ys[3] > ys[2] && ys[3] < ys[0]);
            if k == 0 {
                // hs's 0.1 and 1 sit exactly on those ticks.
                assert!((ys[1] - tick_y(&svg, "0.1")).abs() <= 1, "{ys:?}");
                assert!((ys[2] - tick_y(&svg, "1")).abs() <= 1, "{ys:?}");
            }
            // One marker per segment plus one in the legend.
            assert_eq!(elements(&svg, "circle", "fill", &hex(color)).len(), 5);
        }
        // ga's errors are twice hs's: its line runs above, by a constant log offset.
        let hs = &data_lines(&svg, series_color(0))[0];
        let ga = &data_lines(&svg, series_color(1))[0];
        let offsets: Vec<i32> = hs.iter().zip(ga).map(|(h, g)| h.1 - g.1).collect();
        assert!(offsets
            .iter()
            .all(|&d| d > 5 && (d - offsets[0]).abs() <= 1));
        // The reference: a black line below both, and a cross (two strokes) per segment
        // plus one in the legend.
        let reference_line = data_lines(&svg, BLACK);
        assert_eq!(reference_line.len(), 1);
        assert!(reference_line[0].iter().zip(hs).all(|(r, h)| r.1 > h.1));
        let cross_strokes = elements(&svg, "line", "stroke-width", "2")
            .iter()
            .filter(|e| attr(e, "stroke") == "#000000")
            .count();
        assert_eq!(cross_strokes, 2 * 5);
        renders(&svg);
    }

    #[test]
    fn segment_errors_without_reference_and_with_gaps() {
        let optimizers = names(&["a"]);
        let errors = vec![vec![1.0, 2.0, f64::NAN, 4.0, 5.0, 0.0]];
        let svg = segment_errors("g", &optimizers, &errors, None).unwrap();
        // The NaN splits the line in two; the zero is drawn at the floor.
        let pieces: Vec<usize> = elements(&svg, "polyline", "stroke", &hex(series_color(0)))
            .iter()
            .map(|e| points(e).len())
            .collect();
        assert_eq!(pieces, vec![2, 3, 2], "two pieces, then the legend swatch");
        assert_eq!(
            elements(&svg, "circle", "fill", &hex(series_color(0))).len(),
            6
        );
        assert!(!texts(&svg).iter().any(|t| t == REFERENCE_LABEL));
        assert!(data_lines(&svg, BLACK).is_empty());
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    #[test]
    fn segment_errors_rejects_bad_input() {
        let one = names(&["a"]);
        let row = vec![vec![1.0, 2.0]];
        assert!(matches!(
            segment_errors("t", &[], &[], None),
            Err(PlotError::Empty(_))
        ));
        assert!(matches!(
            segment_errors("t", &one, &[vec![]], None),
            Err(PlotError::Empty(_))
        ));
        assert!(matches!(
            segment_errors("t", &one, &[], None),
            Err(PlotError::Mismatch(_))
        ));
        assert!(matches!(
            segment_errors("t", &names(&["a", "b"]), &[vec![1.0, 2.0], vec![1.0]], None),
            Err(PlotError::Mismatch(_))
        ));
        assert!(matches!(
            segment_errors("t", &one, &row, Some(&[1.0])),
            Err(PlotError::Mismatch(_))
        ));
        assert!(matches!(
            segment_errors("t", &one, &[vec![f64::NAN]], Some(&[f64::INFINITY])),
            Err(PlotError::NoData(_))
        ));
    }

    #[test]
    fn charts_are_deterministic_and_distinguish_eleven_series() {
        let series: Vec<ConvergenceSeries> = (0..11)
            .map(|k| ConvergenceSeries {
                name: format!("opt{k}"),
                runs: histories(5, 300, 1e3, 10f64.powi(-k / 2), k as u64),
            })
            .collect();
        let a = convergence("d", &every(300), &series).unwrap();
        assert_eq!(a, convergence("d", &every(300), &series).unwrap());
        let colors: std::collections::BTreeSet<String> =
            (0..11).map(|k| hex(series_color(k))).collect();
        assert_eq!(colors.len(), 11);
        assert!(
            !colors.contains("#000000"),
            "black is the reference's colour"
        );
        for k in 0..11 {
            assert_eq!(data_lines(&a, series_color(k)).len(), 1, "series {k}");
        }

        let groups: Vec<(String, Vec<f64>)> = series
            .iter()
            .map(|s| (s.name.clone(), s.runs.iter().map(|r| r[299]).collect()))
            .collect();
        let b = boxplot("d", &groups).unwrap();
        assert_eq!(b, boxplot("d", &groups).unwrap());

        let optimizers: Vec<String> = groups.iter().map(|g| g.0.clone()).collect();
        let errors: Vec<Vec<f64>> = groups.iter().map(|g| g.1.clone()).collect();
        let reference = vec![1e-6; 5];
        let c = segment_errors("d", &optimizers, &errors, Some(&reference)).unwrap();
        assert_eq!(
            c,
            segment_errors("d", &optimizers, &errors, Some(&reference)).unwrap()
        );
    }
}
