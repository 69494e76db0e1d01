//! A small version of the optimizer experiment (few runs, small budget), checked for
//! internal consistency: totals, histories, statistics and the reference agree with each
//! other; runs are reproducible on any number of threads; the command writes every
//! output and fails cleanly on bad options.

mod common;

use outlinefit::optim::Algorithm;
use outlinefit::{Config, Search};
use outlinefit_lab::compare::{compare_image, statistics, CompareOptions, ImageComparison};
use std::path::PathBuf;
use std::process::Command;

fn options(search: Search) -> CompareOptions {
    CompareOptions {
        optimizers: vec![Algorithm::Hs, Algorithm::Pso, Algorithm::De],
        runs: 5,
        budget: 400,
        search,
        seed: 7,
        search_box_scale: 1.0,
        history_points: 50,
        trace: Config {
            timings: false,
            ..Config::default()
        },
    }
}

fn sample(name: &str) -> PathBuf {
    common::samples_dir().join(name)
}

fn run_on_threads(threads: usize, search: Search) -> ImageComparison {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| compare_image(&sample("pear.png"), &options(search), &|| {}).unwrap())
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn runs_and_statistics_are_consistent() {
    for search in [Search::Weights, Search::Full] {
        let img = run_on_threads(2, search);
        let opts = options(search);
        assert!(img.segments.len() >= 5);
        assert!(close(
            img.reference_total,
            img.segments.iter().map(|s| s.reference).sum(),
            1e-12
        ));
        assert_eq!(*img.history_at.last().unwrap(), opts.budget);
        for o in &img.optimizers {
            assert_eq!(o.runs.len(), opts.runs);
            for r in &o.runs {
                assert_eq!(r.segments.len(), img.segments.len());
                assert!(close(r.total, r.segments.iter().sum(), 1e-12));
                // Histories only fall, and end at the run's total.
                assert!(r.history.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-12)));
                assert!(
                    close(*r.history.last().unwrap(), r.total, 1e-9),
                    "{}: history ends at {} but the total is {}",
                    o.name,
                    r.history.last().unwrap(),
                    r.total
                );
                if search == Search::Weights {
                    // Nothing beats the separable optimum of the same formulation.
                    for (e, s) in r.segments.iter().zip(&img.segments) {
                        assert!(
                            *e >= s.reference * (1.0 - 1e-6) - 1e-9,
                            "{e} < {}",
                            s.reference
                        );
                    }
                }
            }
        }
        let st = statistics(&img);
        for (o, runs) in st.optimizers.iter().zip(&img.optimizers) {
            let d = o.describe.value().expect("describe");
            let totals = runs.totals();
            assert_eq!(d.n, opts.runs);
            assert_eq!(d.best, totals.iter().cloned().fold(f64::INFINITY, f64::min));
            assert_eq!(d.worst, totals.iter().cloned().fold(0.0, f64::max));
            assert!(d.best <= d.q1 && d.q1 <= d.median && d.median <= d.q3 && d.q3 <= d.worst);
            assert!(d.best <= d.mean && d.mean <= d.worst);
            assert!(close(d.std_dev * d.std_dev, d.variance, 1e-12));
            let expected_gap = 100.0 * (d.mean - img.reference_total) / img.reference_total;
            assert!(close(o.mean_gap_percent, expected_gap, 1e-12));
            for n in [&o.shapiro_wilk, &o.lilliefors] {
                if let Some(n) = n.value() {
                    assert!((0.0..=1.0).contains(&n.p_value));
                    assert_eq!(n.df, opts.runs);
                }
            }
        }
        let k = img.optimizers.len();
        assert_eq!(st.pairs.len(), k * (k - 1) / 2);
        for p in &st.pairs {
            let da = st.optimizers.iter().find(|o| o.name == p.a).unwrap();
            let db = st.optimizers.iter().find(|o| o.name == p.b).unwrap();
            let (da, db) = (da.describe.value().unwrap(), db.describe.value().unwrap());
            if let Some(f) = p.f_test.value() {
                assert!(close(f.f, da.variance / db.variance, 1e-12));
                assert_eq!((f.df1, f.df2), (4.0, 4.0));
                assert!(close(f.p_two_tail, (2.0 * f.p_one_tail).min(1.0), 1e-12));
            }
            let t = p.t_test.value().expect("t-test");
            assert!(close(t.mean_a, da.mean, 1e-12) && close(t.mean_b, db.mean, 1e-12));
            assert_eq!(t.t < 0.0, da.mean < db.mean);
            assert!(close(t.p_less + t.p_greater, 1.0, 1e-9));
            assert!(close(t.p_two_sided, 2.0 * t.p_less.min(t.p_greater), 1e-9));
            // Welch's df lies between the smaller sample's df and the pooled df.
            assert!(t.df >= 4.0 - 1e-9 && t.df <= 8.0 + 1e-9);
        }
        let a = st.anova.value().expect("anova");
        assert!(close(a.ss_total, a.ss_between + a.ss_within, 1e-9));
        assert_eq!(a.df_between, (k - 1) as f64);
        assert_eq!(a.df_within, (k * opts.runs - k) as f64);
        assert!(close(a.f, a.ms_between / a.ms_within, 1e-12));
        assert!((0.0..=1.0).contains(&a.p_value));
    }
}

#[test]
fn same_seed_same_numbers_on_any_thread_count() {
    let a = run_on_threads(1, Search::Weights);
    let b = run_on_threads(2, Search::Weights);
    for (x, y) in a.optimizers.iter().zip(&b.optimizers) {
        for (r, s) in x.runs.iter().zip(&y.runs) {
            assert_eq!(r.seed, s.seed);
            assert_eq!(r.segments, s.segments);
            assert_eq!(r.history, s.history);
        }
    }
    // Different runs use different seeds and (for a stochastic method) give different
    // totals.
    let hs = &a.optimizers[0];
    assert!(hs.runs.windows(2).any(|w| w[0].total != w[1].total));
}

#[test]
fn command_writes_every_output_and_rejects_bad_options() {
    let dir = std::env::temp_dir().join(format!("outlinefit-compare-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_outlinefit"))
        .arg("compare")
        .arg(sample("s.png"))
        .args([
            "--optimizers",
            "hs,ga,lsq",
            "--runs",
            "3",
            "--budget",
            "200",
        ])
        .args(["--search", "full", "--jobs", "2", "-o"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    let md = read("summary.md");
    assert!(md.contains("| lsq (reference) |") && md.contains("| hs |") && md.contains("| ga |"));
    assert!(md.contains("One-way ANOVA"));
    let csv = read("summary.csv");
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 4, "{csv}"); // header, lsq, hs, ga
    assert!(rows[1].contains(",lsq,"));
    let json: serde_json::Value = serde_json::from_str(&read("stats.json")).unwrap();
    assert_eq!(json["options"]["runs"], 3);
    assert_eq!(json["options"]["search"], "full");
    assert_eq!(
        json["images"][0]["comparison"]["optimizers"][1]["runs"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    let segments = read("segments.csv");
    let n_segments = json["images"][0]["comparison"]["segments"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(segments.lines().count(), 1 + 2 * n_segments);
    for chart in ["s-convergence.svg", "s-boxplot.svg", "s-segments.svg"] {
        let svg = read(chart);
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let text: String = doc
            .descendants()
            .filter(|n| n.is_text())
            .map(|n| n.text().unwrap_or(""))
            .collect();
        assert!(text.contains("hs") && text.contains("ga"), "{chart}");
    }
    let _ = std::fs::remove_dir_all(&dir);

    for (args, expect) in [
        (&["--runs", "0"][..], "--runs"),
        (&["--budget", "0"][..], "--budget"),
        (&["--history-points", "1"][..], "--history-points"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_outlinefit"))
            .arg("compare")
            .arg(sample("s.png"))
            .args(args)
            .arg("-o")
            .arg(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(expect),
            "{stderr}"
        );
        assert!(!dir.exists(), "nothing is written on bad options");
    }
    // An unreadable image: one line naming it once, and no output folder.
    let bad = std::env::temp_dir().join(format!("outlinefit-bad-{}.png", std::process::id()));
    std::fs::write(&bad, b"not an image").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_outlinefit"))
        .arg("compare")
        .arg(&bad)
        .args(["--runs", "2", "--budget", "10", "-o"])
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert_eq!(stderr.matches("outlinefit-bad-").count(), 1, "{stderr}");
    assert!(!dir.exists(), "nothing is written when an image fails");
    let _ = std::fs::remove_file(&bad);
    let out = Command::new(env!("CARGO_BIN_EXE_outlinefit"))
        .args(["compare", "samples/s.png", "--optimizers", "nope", "-o"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope"));
}
