//! Writing a comparison: `summary.md`, `summary.csv`, `segments.csv`, `stats.json` and
//! three SVG charts per image, all written atomically.

use super::plot::{self, ConvergenceSeries};
use super::{CompareOptions, ImageComparison, ImageStats, Outcome};
use crate::{Error, Result};
use outlinefit::io::write_atomic;
use outlinefit::report::csv_document;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A number for a table: 4 significant digits, scientific notation outside [1e-3, 1e5).
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            "n/a".into()
        } else {
            v.to_string()
        };
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

/// A p-value for a table.
fn pval(p: f64) -> String {
    if p.is_finite() && p < 1e-300 {
        "< 1e-300".into()
    } else {
        num(p)
    }
}

fn undefined<T>(o: &Outcome<T>) -> String {
    match o {
        Outcome::Value(_) => String::new(),
        Outcome::Undefined { undefined } => format!("n/a ({undefined})"),
    }
}

/// The Markdown report: per image the descriptive table with the reference row and the
/// gaps, normality, F-tests, t-tests and ANOVA.
pub fn summary_markdown(
    opts: &CompareOptions,
    images: &[ImageComparison],
    stats: &[ImageStats],
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Optimizer comparison\n");
    let _ = writeln!(
        s,
        "{} runs per optimizer, {} evaluations per segment and run, `{}` search, seed {}. \
         Errors are the total Eq. 4 error (sum of squared distances at fixed centripetal \
         parameters, px²) over all segments of the image. The reference row is the separable \
         least-squares optimum of the same segments (weights searched deterministically, \
         control points solved); gaps are relative to it.\n",
        opts.runs,
        opts.budget,
        opts.search.name(),
        opts.seed
    );
    for (img, st) in images.iter().zip(stats) {
        let _ = writeln!(
            s,
            "## {}\n\n{} segments; reference total {}.\n",
            img.path,
            img.segments.len(),
            num(img.reference_total)
        );
        let _ = writeln!(
            s,
            "| optimizer | best | worst | mean | median | variance | std. dev. | mean gap % | best gap % | s/run |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
        let r = num(img.reference_total);
        let _ = writeln!(
            s,
            "| lsq (reference) | {r} | {r} | {r} | {r} | 0 | 0 | 0 | 0 | – |"
        );
        for o in &st.optimizers {
            match o.describe.value() {
                Some(d) => {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                        o.name,
                        num(d.best),
                        num(d.worst),
                        num(d.mean),
                        num(d.median),
                        num(d.variance),
                        num(d.std_dev),
                        num(o.mean_gap_percent),
                        num(o.best_gap_percent),
                        num(o.seconds_per_run)
                    );
                }
                None => {
                    let _ = writeln!(s, "| {} | {} |||||||||", o.name, undefined(&o.describe));
                }
            }
        }
        let _ = writeln!(
            s,
            "\n**Normality** (Kolmogorov–Smirnov with Lilliefors' correction; Shapiro–Wilk)\n"
        );
        let _ = writeln!(s, "| optimizer | KS D | df | p | SW W | df | p |");
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for o in &st.optimizers {
            let cell = |n: &Outcome<crate::stats::Normality>| match n.value() {
                Some(v) => format!("{} | {} | {}", num(v.statistic), v.df, pval(v.p_value)),
                None => format!("{} | | ", undefined(n)),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                o.name,
                cell(&o.lilliefors),
                cell(&o.shapiro_wilk)
            );
        }
        if !st.pairs.is_empty() {
            let _ = writeln!(s, "\n**F-tests of equal variances** (F = var(a)/var(b))\n");
            let _ = writeln!(
                s,
                "| a | b | F | df1 | df2 | p one-tail | F crit. one-tail | p two-tail |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
            for p in &st.pairs {
                match p.f_test.value() {
                    Some(f) => {
                        let _ = writeln!(
                            s,
                            "| {} | {} | {} | {} | {} | {} | {} | {} |",
                            p.a,
                            p.b,
                            num(f.f),
                            f.df1,
                            f.df2,
                            pval(f.p_one_tail),
                            num(f.f_crit_one_tail),
                            pval(f.p_two_tail)
                        );
                    }
                    None => {
                        let _ =
                            writeln!(s, "| {} | {} | {} ||||||", p.a, p.b, undefined(&p.f_test));
                    }
                }
            }
            let _ = writeln!(
                s,
                "\n**Welch two-sample t-tests** (unequal variances; p(a<b) is the one-tailed \
                 p-value for \"a has the smaller mean error\")\n"
            );
            let _ = writeln!(
                s,
                "| a | b | mean a | mean b | t | df | p(a<b) | p(a>b) | p two-tail | t crit. two-tail |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
            for p in &st.pairs {
                match p.t_test.value() {
                    Some(t) => {
                        let _ = writeln!(
                            s,
                            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                            p.a,
                            p.b,
                            num(t.mean_a),
                            num(t.mean_b),
                            num(t.t),
                            num(t.df),
                            pval(t.p_less),
                            pval(t.p_greater),
                            pval(t.p_two_sided),
                            num(t.t_crit_two_tail)
                        );
                    }
                    None => {
                        let _ =
                            writeln!(s, "| {} | {} | {} ||||||||", p.a, p.b, undefined(&p.t_test));
                    }
                }
            }
        }
        let _ = writeln!(s, "\n**One-way ANOVA** over all optimizers\n");
        match st.anova.value() {
            Some(a) => {
                let _ = writeln!(s, "| source | SS | df | MS | F | p | F crit. |");
                let _ = writeln!(s, "|---|---|---|---|---|---|---|");
                let _ = writeln!(
                    s,
                    "| between | {} | {} | {} | {} | {} | {} |",
                    num(a.ss_between),
                    a.df_between,
                    num(a.ms_between),
                    num(a.f),
                    pval(a.p_value),
                    num(a.f_crit)
                );
                let _ = writeln!(
                    s,
                    "| within | {} | {} | {} | | | |",
                    num(a.ss_within),
                    a.df_within,
                    num(a.ms_within)
                );
                let _ = writeln!(
                    s,
                    "| total | {} | {} | | | | |",
                    num(a.ss_total),
                    a.df_total
                );
            }
            None => {
                let _ = writeln!(s, "{}", undefined(&st.anova));
            }
        }
        s.push('\n');
    }
    s
}

/// `summary.csv`: one row per image and optimizer (and the reference).
pub fn summary_csv(images: &[ImageComparison], stats: &[ImageStats]) -> String {
    let header = [
        "image",
        "optimizer",
        "runs",
        "best",
        "worst",
        "mean",
        "median",
        "variance",
        "std_dev",
        "mean_gap_percent",
        "best_gap_percent",
        "seconds_per_run",
    ];
    let mut rows = Vec::new();
    for (img, st) in images.iter().zip(stats) {
        let r = img.reference_total.to_string();
        rows.push(vec![
            img.path.clone(),
            "lsq".into(),
            "1".into(),
            r.clone(),
            r.clone(),
            r.clone(),
            r,
            "0".into(),
            "0".into(),
            "0".into(),
            "0".into(),
            String::new(),
        ]);
        for (o, runs) in st.optimizers.iter().zip(&img.optimizers) {
            let d = o.describe.value();
            let f = |g: fn(&crate::stats::Describe) -> f64| {
                d.map_or(String::new(), |d| g(d).to_string())
            };
            rows.push(vec![
                img.path.clone(),
                o.name.clone(),
                runs.runs.len().to_string(),
                f(|d| d.best),
                f(|d| d.worst),
                f(|d| d.mean),
                f(|d| d.median),
                f(|d| d.variance),
                f(|d| d.std_dev),
                o.mean_gap_percent.to_string(),
                o.best_gap_percent.to_string(),
                o.seconds_per_run.to_string(),
            ]);
        }
    }
    csv_document(&header, &rows)
}

/// `segments.csv`: per image, segment and optimizer, the minimum and mean error over the
/// runs, beside the reference (the paper's Fig. 9 data).
pub fn segments_csv(images: &[ImageComparison]) -> String {
    let header = [
        "image",
        "contour",
        "segment",
        "points",
        "reference",
        "optimizer",
        "min_error",
        "mean_error",
    ];
    let mut rows = Vec::new();
    for img in images {
        let minima: Vec<Vec<f64>> = img.optimizers.iter().map(|o| o.segment_minima()).collect();
        for (s, seg) in img.segments.iter().enumerate() {
            for (o, mins) in img.optimizers.iter().zip(&minima) {
                let mean =
                    o.runs.iter().map(|r| r.segments[s]).sum::<f64>() / o.runs.len().max(1) as f64;
                rows.push(vec![
                    img.path.clone(),
                    seg.contour.to_string(),
                    seg.segment.to_string(),
                    seg.points.to_string(),
                    seg.reference.to_string(),
                    o.name.clone(),
                    mins[s].to_string(),
                    mean.to_string(),
                ]);
            }
        }
    }
    csv_document(&header, &rows)
}

/// Everything, for `stats.json`.
#[derive(Serialize)]
struct StatsDocument<'a> {
    outlinefit_version: &'static str,
    options: &'a CompareOptions,
    images: Vec<ImageDocument<'a>>,
}

#[derive(Serialize)]
struct ImageDocument<'a> {
    comparison: &'a ImageComparison,
    statistics: &'a ImageStats,
}

/// `stats.json`: the options, every run (totals, segment errors, sampled histories) and
/// every statistic.
pub fn stats_json(
    opts: &CompareOptions,
    images: &[ImageComparison],
    stats: &[ImageStats],
) -> String {
    let doc = StatsDocument {
        outlinefit_version: outlinefit::VERSION,
        options: opts,
        images: images
            .iter()
            .zip(stats)
            .map(|(comparison, statistics)| ImageDocument {
                comparison,
                statistics,
            })
            .collect(),
    };
    let mut s =
        serde_json::to_string_pretty(&doc).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}

/// The three charts of one image: convergence, box plot of totals, per-segment minima.
pub fn charts(img: &ImageComparison) -> Result<[(&'static str, String); 3]> {
    let name = Path::new(&img.path)
        .file_name()
        .map_or_else(|| img.path.clone(), |n| n.to_string_lossy().into_owned());
    let err = |e: plot::PlotError| Error::Plot {
        what: format!("the charts of {name}"),
        message: e.to_string(),
    };
    let series: Vec<ConvergenceSeries> = img
        .optimizers
        .iter()
        .map(|o| ConvergenceSeries {
            name: o.name.clone(),
            runs: o.runs.iter().map(|r| r.history.clone()).collect(),
        })
        .collect();
    let convergence = plot::convergence(
        &format!("{name}: total error vs evaluations per segment"),
        &img.history_at,
        &series,
    )
    .map_err(err)?;
    let groups: Vec<(String, Vec<f64>)> = img
        .optimizers
        .iter()
        .map(|o| (o.name.clone(), o.totals()))
        .collect();
    let boxes = plot::boxplot(&format!("{name}: total error over runs"), &groups).map_err(err)?;
    let names: Vec<String> = img.optimizers.iter().map(|o| o.name.clone()).collect();
    let minima: Vec<Vec<f64>> = img.optimizers.iter().map(|o| o.segment_minima()).collect();
    let reference: Vec<f64> = img.segments.iter().map(|s| s.reference).collect();
    let segments = plot::segment_errors(
        &format!("{name}: minimum error per segment"),
        &names,
        &minima,
        Some(&reference),
    )
    .map_err(err)?;
    Ok([
        ("convergence", convergence),
        ("boxplot", boxes),
        ("segments", segments),
    ])
}

/// Writes every output into `dir` (which must exist) and returns the paths written.
pub fn write_all(
    dir: &Path,
    opts: &CompareOptions,
    images: &[ImageComparison],
    stats: &[ImageStats],
    stems: &[String],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let mut put = |name: String, text: &str| -> Result<()> {
        let path = dir.join(name);
        write_atomic(&path, text.as_bytes())?;
        written.push(path);
        Ok(())
    };
    put("summary.md".into(), &summary_markdown(opts, images, stats))?;
    put("summary.csv".into(), &summary_csv(images, stats))?;
    put("segments.csv".into(), &segments_csv(images))?;
    put("stats.json".into(), &stats_json(opts, images, stats))?;
    for (img, stem) in images.iter().zip(stems) {
        for (kind, svg) in charts(img)? {
            put(format!("{stem}-{kind}.svg"), &svg)?;
        }
    }
    Ok(written)
}
