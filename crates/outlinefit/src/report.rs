//! Per-segment error reports: JSON (the whole fit, exact rational data included) and CSV
//! (one row per segment).
//!
//! The JSON document has the shape
//! `{ "outlinefit_version", "config", "images": [ { "path", "image", "summary", "fidelity", "seconds",
//! "contours": [ { "segments": [...], "joints": [...] } ] } ] }`; see the README for every
//! field. Every number in it is reproducible from the configuration and seed except the
//! `seconds` fields, which are 0 when timing is off (`--no-timings`).

use crate::fit::{FittedContour, JointKind};
use crate::geom::Point;
use crate::merge::outline::MergedCurve;
use crate::trace::{Config, TraceResult};
use crate::VERSION;
use serde::Serialize;

/// Totals over one traced image.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct Summary {
    /// Number of contours.
    pub contours: usize,
    /// Number of segments.
    pub segments: usize,
    /// Number of merged disk Wang–Ball curves (`--merge`).
    pub merged_curves: usize,
    /// Number of curves the SVG draws: segments not replaced by merged curves plus merged
    /// curves (= `segments` without `--merge`).
    pub curves: usize,
    /// Number of corner joints.
    pub corner_joints: usize,
    /// Number of smooth joints.
    pub smooth_joints: usize,
    /// Largest tangent angle (radians) over the smooth joints.
    pub max_smooth_joint_angle: f64,
    /// Sum of Eq. 4 errors over all segments (px²).
    pub sum_sq: f64,
    /// Largest point-to-curve distance (px).
    pub max_distance: f64,
    /// Mean point-to-curve distance over all data points (px).
    pub mean_distance: f64,
    /// Number of data points.
    pub points: usize,
    /// Contours fitted to a tolerance wider than `--tolerance`, because their edge is
    /// blurred (`Config::edge_tolerance`).
    pub widened_contours: usize,
    /// The widest tolerance (px) a contour was fitted to.
    pub max_tolerance: f64,
}

impl Summary {
    /// Totals of a trace.
    pub(crate) fn of(result: &TraceResult, tolerance: f64) -> Summary {
        let mut s = Summary {
            contours: result.contours.len(),
            segments: result.segment_count(),
            merged_curves: result.merged.iter().map(Vec::len).sum(),
            curves: result.curve_count(),
            corner_joints: 0,
            smooth_joints: 0,
            max_smooth_joint_angle: 0.0,
            sum_sq: result.sum_sq(),
            max_distance: result.max_distance(),
            mean_distance: 0.0,
            points: 0,
            widened_contours: 0,
            max_tolerance: 0.0,
        };
        let mut weighted = 0.0;
        let mut counted = 0usize;
        for c in &result.contours {
            s.points += c.points.len();
            s.widened_contours += usize::from(c.tolerance > tolerance);
            s.max_tolerance = s.max_tolerance.max(c.tolerance);
            for j in &c.joints {
                match j.kind {
                    JointKind::Corner => s.corner_joints += 1,
                    JointKind::Smooth => {
                        s.smooth_joints += 1;
                        s.max_smooth_joint_angle = s.max_smooth_joint_angle.max(j.angle);
                    }
                }
            }
            for seg in &c.segments {
                weighted += seg.error.mean_distance * seg.point_count as f64;
                counted += seg.point_count;
            }
        }
        s.mean_distance = if counted > 0 {
            weighted / counted as f64
        } else {
            0.0
        };
        s
    }
}

#[derive(Serialize)]
struct SegmentRow<'a> {
    index: usize,
    point_count: usize,
    start: usize,
    end: usize,
    param_range: [f64; 2],
    arc_range: [f64; 2],
    control_points: [[f64; 2]; 4],
    weights: [f64; 4],
    sum_sq: f64,
    rmse: f64,
    max_distance: f64,
    mean_distance: f64,
    evaluations: u64,
    seconds: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    on_search_boundary: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    params: Option<&'a [f64]>,
    #[serde(skip_serializing_if = "<[f64]>::is_empty")]
    history: &'a [f64],
}

#[derive(Serialize)]
struct JointRow {
    index: usize,
    kind: JointKind,
    position: [f64; 2],
    angle: f64,
    beta: f64,
}

#[derive(Serialize)]
struct ContourRow<'a> {
    index: usize,
    is_hole: bool,
    parent: Option<usize>,
    point_count: usize,
    /// The tolerance (px) the contour was fitted to.
    tolerance: f64,
    segments: Vec<SegmentRow<'a>>,
    joints: Vec<JointRow>,
    #[serde(skip_serializing_if = "<[MergedCurve]>::is_empty")]
    merged: &'a [MergedCurve],
}

#[derive(Serialize)]
struct ImageRow<'a> {
    path: &'a str,
    image: &'a crate::trace::ImageInfo,
    summary: Summary,
    fidelity: &'a crate::Fidelity,
    seconds: f64,
    contours: ContourRows<'a>,
}

#[derive(Serialize)]
struct Document<'a> {
    outlinefit_version: &'static str,
    config: &'a Config,
    images: Vec<ImageRow<'a>>,
}

fn xy(p: Point) -> [f64; 2] {
    [p.x, p.y]
}

fn contour_row<'a>(
    index: usize,
    c: &'a FittedContour,
    merged: &'a [MergedCurve],
    with_params: bool,
) -> ContourRow<'a> {
    ContourRow {
        index,
        is_hole: c.is_hole,
        parent: c.parent,
        point_count: c.points.len(),
        tolerance: c.tolerance,
        segments: c
            .segments
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let (lo, hi) = s
                    .params
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &u| {
                        (a.min(u), b.max(u))
                    });
                SegmentRow {
                    index: k,
                    point_count: s.point_count,
                    start: s.start,
                    end: s.end,
                    param_range: [lo, hi],
                    arc_range: s.arc_range,
                    control_points: s.curve.points.map(xy),
                    weights: s.curve.all_weights(),
                    sum_sq: s.error.sum_sq,
                    rmse: s.error.rmse,
                    max_distance: s.error.max_distance,
                    mean_distance: s.error.mean_distance,
                    evaluations: s.evaluations,
                    seconds: s.seconds,
                    on_search_boundary: s.on_search_boundary,
                    params: with_params.then_some(s.params.as_slice()),
                    history: &s.history,
                }
            })
            .collect(),
        joints: c
            .joints
            .iter()
            .map(|j| JointRow {
                index: j.index,
                kind: j.kind,
                position: xy(j.position),
                angle: j.angle,
                beta: j.beta,
            })
            .collect(),
        merged,
    }
}

/// The JSON report of one or more traced images (see [`write_json`]) as a string.
pub fn to_json(config: &Config, images: &[(&str, &TraceResult)], with_params: bool) -> String {
    let mut bytes = Vec::new();
    // Writing into memory cannot fail.
    let _ = write_json(&mut bytes, config, images, with_params);
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Writes the JSON report of one or more traced images to `out`, ending in a newline.
/// `with_params` includes every data point's parameter (large).
///
/// The layout is indented down to the contours; each segment, joint and merged curve is
/// one line. The document is serialised as it is written, so its size in memory does not
/// grow with the number of contours. Non-finite numbers become `null`.
pub fn write_json(
    out: &mut dyn std::io::Write,
    config: &Config,
    images: &[(&str, &TraceResult)],
    with_params: bool,
) -> std::io::Result<()> {
    let doc = Document {
        outlinefit_version: VERSION,
        config,
        images: images
            .iter()
            .map(|(path, r)| ImageRow {
                path,
                image: &r.image,
                summary: Summary::of(r, config.tolerance),
                fidelity: &r.fidelity,
                seconds: r.seconds,
                contours: ContourRows {
                    result: r,
                    with_params,
                },
            })
            .collect(),
    };
    let mut ser = serde_json::Serializer::with_formatter(&mut *out, RowFormatter::new(ROW_DEPTH));
    doc.serialize(&mut ser).map_err(std::io::Error::from)?;
    out.write_all(b"\n")
}

/// Nesting depth of a segment, joint or merged-curve object in the report (document 1,
/// `images` 2, image 3, `contours` 4, contour 5, its arrays 6, their items 7).
const ROW_DEPTH: usize = 7;

/// The contours of one image, turned into rows while they are serialised (not collected).
struct ContourRows<'a> {
    result: &'a TraceResult,
    with_params: bool,
}

impl Serialize for ContourRows<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(
            self.result
                .contours
                .iter()
                .enumerate()
                .map(|(i, c)| contour_row(i, c, self.result.merged_of(i), self.with_params)),
        )
    }
}

/// Pretty-prints JSON down to nesting depth `flat_from`; containers that deep or deeper are
/// written compactly, each on one line.
struct RowFormatter {
    pretty: serde_json::ser::PrettyFormatter<'static>,
    depth: usize,
    flat_from: usize,
}

impl RowFormatter {
    fn new(flat_from: usize) -> RowFormatter {
        RowFormatter {
            pretty: serde_json::ser::PrettyFormatter::new(),
            depth: 0,
            flat_from,
        }
    }

    fn flat(&self) -> bool {
        self.depth >= self.flat_from
    }
}

/// Forwards a formatter call to the compact formatter inside one-line containers and to
/// the pretty one above them.
macro_rules! by_depth {
    ($self:ident, $method:ident ( $($arg:expr),* )) => {
        if $self.flat() {
            serde_json::ser::CompactFormatter.$method($($arg),*)
        } else {
            $self.pretty.$method($($arg),*)
        }
    };
}

impl serde_json::ser::Formatter for RowFormatter {
    fn begin_array<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.depth += 1;
        by_depth!(self, begin_array(w))
    }
    fn end_array<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        let r = by_depth!(self, end_array(w));
        self.depth -= 1;
        r
    }
    fn begin_array_value<W: ?Sized + std::io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        by_depth!(self, begin_array_value(w, first))
    }
    fn end_array_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        by_depth!(self, end_array_value(w))
    }
    fn begin_object<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        self.depth += 1;
        by_depth!(self, begin_object(w))
    }
    fn end_object<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        let r = by_depth!(self, end_object(w));
        self.depth -= 1;
        r
    }
    fn begin_object_key<W: ?Sized + std::io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        by_depth!(self, begin_object_key(w, first))
    }
    fn begin_object_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        by_depth!(self, begin_object_value(w))
    }
    fn end_object_value<W: ?Sized + std::io::Write>(&mut self, w: &mut W) -> std::io::Result<()> {
        by_depth!(self, end_object_value(w))
    }
}

/// The CSV report: a header and one row per segment.
pub fn to_csv(config: &Config, images: &[(&str, &TraceResult)]) -> String {
    let header = [
        "image",
        "contour",
        "is_hole",
        "segment",
        "optimizer",
        "point_count",
        "start",
        "end",
        "c0x",
        "c0y",
        "c1x",
        "c1y",
        "c2x",
        "c2y",
        "c3x",
        "c3y",
        "w1",
        "w2",
        "sum_sq",
        "rmse",
        "max_distance",
        "mean_distance",
        "start_joint",
        "start_joint_angle",
        "start_joint_beta",
        "evaluations",
        "seconds",
    ];
    let mut rows: Vec<Vec<String>> = Vec::new();
    for (path, r) in images {
        for (ci, c) in r.contours.iter().enumerate() {
            for (k, s) in c.segments.iter().enumerate() {
                let p = s.curve.points;
                let j = c.joints.get(k);
                let mut row = vec![
                    path.to_string(),
                    ci.to_string(),
                    c.is_hole.to_string(),
                    k.to_string(),
                    config.optimizer.name().to_string(),
                    s.point_count.to_string(),
                    s.start.to_string(),
                    s.end.to_string(),
                ];
                for q in p {
                    row.push(q.x.to_string());
                    row.push(q.y.to_string());
                }
                row.extend([
                    s.curve.weights[0].to_string(),
                    s.curve.weights[1].to_string(),
                    s.error.sum_sq.to_string(),
                    s.error.rmse.to_string(),
                    s.error.max_distance.to_string(),
                    s.error.mean_distance.to_string(),
                    j.map_or(String::new(), |j| format!("{:?}", j.kind).to_lowercase()),
                    j.map_or(String::new(), |j| j.angle.to_string()),
                    j.map_or(String::new(), |j| j.beta.to_string()),
                    s.evaluations.to_string(),
                    s.seconds.to_string(),
                ]);
                rows.push(row);
            }
        }
    }
    csv_document(&header, &rows)
}

/// A CSV document from a header and rows of fields (quoted where needed), ending in a
/// newline. Writing CSV into memory cannot fail.
pub fn csv_document(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let result = (|| -> csv::Result<()> {
        w.write_record(header)?;
        for r in rows {
            w.write_record(r)?;
        }
        w.flush()?;
        Ok(())
    })();
    match (result, w.into_inner()) {
        (Ok(()), Ok(bytes)) => String::from_utf8_lossy(&bytes).into_owned(),
        _ => String::new(),
    }
}
