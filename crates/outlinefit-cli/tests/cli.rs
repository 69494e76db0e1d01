//! The command line as a user meets it: bad input gives one clear line, a non-zero exit
//! and no output file; the same seed gives byte-identical SVG and JSON on 1 and 2 threads.

mod common;

use common::{bin, scratch};

use std::path::{Path, PathBuf};
use std::process::Output;

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Runs `trace IN -o DIR/out.svg --report DIR/out.json` and checks it fails cleanly.
fn assert_clean_failure(input: &Path, extra: &[&str], expect: &str) {
    let dir = input.parent().unwrap().join("outputs");
    std::fs::create_dir_all(&dir).unwrap();
    let out = bin()
        .arg("trace")
        .arg(input)
        .arg("-o")
        .arg(dir.join("out.svg"))
        .arg("--report")
        .arg(dir.join("out.json"))
        .args(extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "{}: expected failure",
        input.display()
    );
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr.lines().count(),
        1,
        "one line expected, got: {stderr}"
    );
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(expect), "expected {expect:?} in: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        files_in(&dir).is_empty(),
        "outputs left behind: {:?}",
        files_in(&dir)
    );
}

#[test]
fn bad_inputs_fail_with_one_line_and_no_output() {
    let dir = scratch("bad");
    // Missing file.
    assert_clean_failure(&dir.join("missing.png"), &[], "cannot read");
    // Not an image.
    let text = dir.join("notes.png");
    std::fs::write(&text, "this is not an image\n").unwrap();
    assert_clean_failure(&text, &[], "not a readable image");
    // Truncated PNG: the first half of a real sample.
    let sample = std::fs::read(common::samples_dir().join("s.png")).unwrap();
    let truncated = dir.join("truncated.png");
    std::fs::write(&truncated, &sample[..sample.len() / 2]).unwrap();
    assert_clean_failure(&truncated, &[], "not a readable image");
    // Empty (all background) image.
    let blank = dir.join("blank.png");
    image::GrayImage::from_pixel(40, 30, image::Luma([255]))
        .save(&blank)
        .unwrap();
    assert_clean_failure(&blank, &[], "no shape found");
    // Zero-size image (a PGM header that declares 0 × 0 pixels).
    let zero = dir.join("zero.pgm");
    std::fs::write(&zero, b"P5\n0 0\n255\n").unwrap();
    let out = bin()
        .arg("trace")
        .arg(&zero)
        .arg("-o")
        .arg(dir.join("outputs/z.svg"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1);
    // Larger than --max-pixels.
    assert_clean_failure(
        &common::samples_dir().join("s.png"),
        &["--max-pixels", "1000"],
        "more than the limit",
    );
    // Output in a missing folder: no work is done, nothing written anywhere.
    let out = bin()
        .arg("trace")
        .arg(common::samples_dir().join("glyph_aa.png"))
        .arg("-o")
        .arg(dir.join("no/such/folder/out.svg"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("does not exist"), "{stderr}");
    assert!(!dir.join("no").exists());
    // A bad option value is refused by the parser.
    let out = bin()
        .args(["trace", "x.png", "--tolerance", "-1"])
        .output()
        .unwrap();
    assert_ne!(out.status.code(), Some(0));
    // The input is never modified.
    assert_eq!(
        std::fs::read(common::samples_dir().join("s.png")).unwrap(),
        sample
    );
}

#[test]
fn svg_to_stdout_matches_svg_file() {
    let dir = scratch("stdout");
    let input = common::samples_dir().join("glyph_aa.png");
    let file = dir.join("a.svg");
    let a = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&file)
        .output()
        .unwrap();
    assert!(a.status.success());
    let b = bin()
        .arg("trace")
        .arg(&input)
        .args(["-o", "-"])
        .output()
        .unwrap();
    assert!(b.status.success());
    assert_eq!(std::fs::read(&file).unwrap(), b.stdout);
    assert!(String::from_utf8_lossy(&b.stdout).contains("viewBox=\"0 0 6000 6300\""));
}

fn batch(input: &Path, out: &Path, jobs: &str, extra: &[&str]) -> Output {
    bin()
        .arg("batch")
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(["--jobs", jobs, "--no-timings"])
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn same_seed_gives_identical_outputs_on_one_and_two_threads() {
    let dir = scratch("determinism");
    for extra in [
        &[][..],
        &["--optimizer", "hs", "--budget", "300", "--seed", "42"][..],
        &[
            "--optimizer",
            "beeso",
            "--search",
            "full",
            "--budget",
            "300",
        ][..],
    ] {
        let one = dir.join("one");
        let two = dir.join("two");
        let _ = std::fs::remove_dir_all(&one);
        let _ = std::fs::remove_dir_all(&two);
        assert!(batch(&common::samples_dir(), &one, "1", extra)
            .status
            .success());
        assert!(batch(&common::samples_dir(), &two, "2", extra)
            .status
            .success());
        let names = files_in(&one);
        assert_eq!(names, files_in(&two));
        assert!(
            names.iter().filter(|n| n.ends_with(".svg")).count() >= 7,
            "{names:?}"
        );
        assert!(
            names.iter().filter(|n| n.ends_with(".json")).count() >= 7,
            "{names:?}"
        );
        for n in names {
            assert_eq!(
                std::fs::read(one.join(&n)).unwrap(),
                std::fs::read(two.join(&n)).unwrap(),
                "{n} differs ({extra:?})"
            );
        }
    }
}

#[test]
fn an_output_named_for_another_format_is_refused() {
    // `-o x.pdf` once wrote SVG into a .pdf file without a word; now the ending chooses
    // the format, and an ending that names no output format, or another one than
    // --format, is refused.
    let dir = scratch("formats");
    let input = common::samples_dir().join("s.png");
    for (option, name, says) in [
        ("-o", "x.png", "x.png: PNG is not an output format"),
        ("-b", "x.pdf", "--format svg writes SVG, not PDF"),
        ("--report", "r.csv", "--report writes JSON, not CSV"),
        ("--csv", "r.json", "--csv writes CSV, not JSON"),
        ("--overlay", "o.pdf", "--overlay writes SVG, not PDF"),
    ] {
        let path = dir.join(name);
        let mut cmd = bin();
        cmd.arg("trace").arg(&input);
        match option {
            "-o" => cmd.arg("-o").arg(&path),
            "-b" => cmd.args(["-b", "svg", "-o"]).arg(&path),
            _ => cmd.arg(option).arg(&path).arg("-o").arg(dir.join("ok.svg")),
        };
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{option} {name}: {err}");
        assert!(err.contains(says), "{option} {name}: {err}");
        assert!(!path.exists() && !dir.join("ok.svg").exists(), "{name}");
    }
    // The right endings, in any case, and names without one are taken.
    for name in ["x.SVG", "plain"] {
        let out = bin()
            .arg("trace")
            .arg(&input)
            .arg("-o")
            .arg(dir.join(name))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(std::fs::read_to_string(dir.join(name))
            .unwrap()
            .starts_with("<svg"));
    }
}

#[test]
fn a_one_pixel_image_fails_its_row_and_the_batch_goes_on() {
    // A 1 x 1 black image panicked (and took the whole batch down, leaving the summary
    // unfinished); now it is one typed error row among good files.
    let dir = scratch("onepixel");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    for name in ["a.png", "c.png"] {
        std::fs::copy(common::samples_dir().join("s.png"), input.join(name)).unwrap();
    }
    image::GrayImage::from_pixel(1, 1, image::Luma([0u8]))
        .save(input.join("b.png"))
        .unwrap();
    let out = dir.join("out");
    let r = batch(&input, &out, "2", &[]);
    assert_eq!(
        r.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert!(out.join("a.svg").exists() && out.join("c.svg").exists());
    assert!(!out.join("b.svg").exists());
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 4, "{summary}");
    let row = summary.lines().find(|l| l.contains("b.png")).unwrap();
    assert!(
        row.contains(",failed,") && row.contains("smaller than the minimum area"),
        "{row}"
    );
    assert_eq!(summary.matches(",ok,").count(), 2, "{summary}");
}

#[test]
fn batch_reports_failures_and_converts_the_rest() {
    let dir = scratch("batch");
    let input = dir.join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    std::fs::copy(
        common::samples_dir().join("glyph_aa.png"),
        input.join("a.png"),
    )
    .unwrap();
    std::fs::copy(
        common::samples_dir().join("pear.png"),
        input.join("sub/b.png"),
    )
    .unwrap();
    std::fs::write(input.join("broken.png"), b"nope").unwrap();
    let out = dir.join("out");
    let r = batch(&input, &out, "2", &["--recursive"]);
    assert_eq!(
        r.status.code(),
        Some(1),
        "a failed file makes the exit status non-zero"
    );
    assert!(out.join("a.svg").exists() && out.join("a.json").exists());
    assert!(out.join("sub/b.svg").exists());
    assert!(!out.join("broken.svg").exists());
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 4, "{summary}");
    // The fidelity check's verdict is in the summary: held on both samples.
    let header: Vec<&str> = summary.lines().next().unwrap().split(',').collect();
    let held = header.iter().position(|&h| h == "fidelity_held").unwrap();
    for line in summary.lines().skip(1).filter(|l| l.contains(",ok,")) {
        assert_eq!(line.split(',').nth(held), Some("yes"), "{summary}");
    }
    assert!(
        summary
            .lines()
            .any(|l| l.contains("broken.png") && l.contains(",failed,")),
        "{summary}"
    );
    // Shards partition the files; --skip-existing skips what is done.
    let s1 = dir.join("s1");
    let s2 = dir.join("s2");
    batch(&input, &s1, "1", &["--recursive", "--shard", "1/2"]);
    batch(&input, &s2, "1", &["--recursive", "--shard", "2/2"]);
    let count = |d: &Path| {
        std::fs::read_to_string(d.join("summary.csv"))
            .unwrap()
            .lines()
            .count()
            - 1
    };
    assert_eq!(count(&s1) + count(&s2), 3);
    let again = batch(&input, &out, "1", &["--recursive", "--skip-existing"]);
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(
        summary.lines().filter(|l| l.contains(",skipped,")).count(),
        2,
        "{summary}"
    );
    assert_eq!(again.status.code(), Some(1));
}

#[test]
fn report_records_optimizer_search_space_and_history() {
    let dir = scratch("history");
    let report = dir.join("r.json");
    let out = bin()
        .arg("trace")
        .arg(common::samples_dir().join("pear.png"))
        .arg("-o")
        .arg(dir.join("p.svg"))
        .arg("--report")
        .arg(&report)
        .args([
            "--optimizer",
            "de",
            "--budget",
            "250",
            "--history",
            "--no-timings",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["config"]["optimizer"], "de");
    assert_eq!(json["config"]["search"], "weights");
    assert_eq!(json["config"]["budget"], 250);
    let segments = json["images"][0]["contours"][0]["segments"]
        .as_array()
        .unwrap();
    assert!(segments.len() > 5);
    for s in segments {
        assert_eq!(s["evaluations"], 250);
        let h: Vec<f64> = s["history"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(h.len(), 250);
        assert!(h.windows(2).all(|w| w[1] <= w[0]));
        // The history ends at the segment's reported Eq. 4 error (the objective's one-pass
        // quadratic form loses a few digits on near-exact segments).
        let e = s["sum_sq"].as_f64().unwrap();
        assert!((h[249] - e).abs() <= 1e-6 * e + 1e-9, "{} vs {e}", h[249]);
    }
    // Without --history the report has none; lsq has neither search nor history.
    let out = bin()
        .arg("trace")
        .arg(common::samples_dir().join("pear.png"))
        .arg("-o")
        .arg(dir.join("p.svg"))
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    assert!(out.status.success());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["config"]["optimizer"], "lsq");
    let s = &json["images"][0]["contours"][0]["segments"][0];
    assert!(s.get("history").is_none(), "{s}");
}

#[test]
fn optimised_breaks_are_deterministic_on_one_and_two_threads_and_refuse_bad_options() {
    let dir = scratch("breaks");
    let extra = [
        "--breaks",
        "optimize",
        "--break-budget",
        "30",
        "--seed",
        "7",
    ];
    let one = dir.join("one");
    let two = dir.join("two");
    assert!(batch(&common::samples_dir(), &one, "1", &extra)
        .status
        .success());
    assert!(batch(&common::samples_dir(), &two, "2", &extra)
        .status
        .success());
    let names = files_in(&one);
    assert_eq!(names, files_in(&two));
    assert!(names.iter().filter(|n| n.ends_with(".json")).count() >= 7);
    for n in &names {
        assert_eq!(
            std::fs::read(one.join(n)).unwrap(),
            std::fs::read(two.join(n)).unwrap(),
            "{n} differs"
        );
    }
    // The report records the mode, the optimizer and the budget.
    let report = names.iter().find(|n| n.ends_with(".json")).unwrap();
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join(report)).unwrap()).unwrap();
    assert_eq!(json["config"]["breaks"], "optimize");
    assert_eq!(json["config"]["break_optimizer"], "fwa");
    assert_eq!(json["config"]["break_budget"], 30);
    // Bad values: one line, exit code 1, nothing written.
    let input = dir.join("s.png");
    std::fs::copy(common::samples_dir().join("s.png"), &input).unwrap();
    assert_clean_failure(&input, &["--breaks", "sideways"], "--breaks");
    assert_clean_failure(
        &input,
        &["--breaks", "optimize", "--break-optimizer", "lsq"],
        "--break-optimizer",
    );
    assert_clean_failure(&input, &["--break-budget", "0"], "--break-budget");
}

#[test]
fn threshold_is_on_the_luminance_scale_and_reported_on_it() {
    // A grey ramp: luminance = column. `--threshold 64` makes columns 0..=63 the shape.
    let dir = scratch("ramp");
    let ramp = image::GrayImage::from_fn(256, 24, |x, _| image::Luma([x as u8]));
    let input = dir.join("ramp.png");
    ramp.save(&input).unwrap();
    let out = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(dir.join("ramp.svg"))
        .arg("--report")
        .arg(dir.join("ramp.json"))
        .args(["--threshold", "64"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("ramp.json")).unwrap()).unwrap();
    let image = &report["images"][0]["image"];
    assert_eq!(image["threshold_scale"], "luminance");
    assert!(
        (image["threshold"].as_f64().unwrap() - 63.5).abs() < 1e-9,
        "{image}"
    );
    assert_eq!(report["images"][0]["fidelity"]["held"], true);
    let svg = std::fs::read_to_string(dir.join("ramp.svg")).unwrap();
    let cov = common::render_svg_coverage(&svg, 256, 24);
    let row = &cov[12 * 256..13 * 256];
    let filled = row.iter().filter(|&&c| c >= 0.5).count();
    assert_eq!(filled, 64, "columns drawn: {filled}");
}

#[test]
fn strict_and_no_check_are_exclusive_and_no_check_reports_nothing_held() {
    let dir = scratch("strict");
    let input = common::samples_dir().join("pear.png");
    let out = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(dir.join("p.svg"))
        .args(["--strict", "--no-check"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(!dir.join("p.svg").exists());
    let out = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(dir.join("p.svg"))
        .arg("--report")
        .arg(dir.join("p.json"))
        .arg("--no-check")
        .output()
        .unwrap();
    assert!(out.status.success());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("p.json")).unwrap()).unwrap();
    assert_eq!(report["images"][0]["fidelity"]["held"], false);
    // With the check (the default) and --strict, a clean sample passes.
    let out = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(dir.join("q.svg"))
        .arg("--strict")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("q.svg").exists());
}

/// `outlinefit FILE …` is `outlinefit trace FILE …`: the same SVG; a missing file is named
/// as such, and a misspelt command still gets the parser's suggestion.
#[test]
fn a_file_as_first_argument_means_trace() {
    let dir = scratch("default_command");
    let input = common::samples_dir().join("s.png");
    let short = dir.join("short.svg");
    let long = dir.join("long.svg");
    let a = bin().arg(&input).arg("-o").arg(&short).output().unwrap();
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let b = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&long)
        .output()
        .unwrap();
    assert!(b.status.success());
    assert_eq!(
        std::fs::read(&short).unwrap(),
        std::fs::read(&long).unwrap()
    );
    let missing = bin().arg(dir.join("missing.png")).output().unwrap();
    assert_eq!(missing.status.code(), Some(1));
    let err = String::from_utf8_lossy(&missing.stderr);
    assert!(
        err.contains("cannot read") && err.contains("missing.png"),
        "{err}"
    );
    let typo = bin().arg("trcae").output().unwrap();
    assert_eq!(typo.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&typo.stderr).contains("'trace'"));
}

/// The SVGs under a folder, as paths relative to it.
fn svgs_under(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for sub in ["", "sub"] {
        let d = dir.join(sub);
        if d.is_dir() {
            out.extend(
                files_in(&d)
                    .into_iter()
                    .filter(|f| f.ends_with(".svg"))
                    .map(|f| Path::new(sub).join(f).to_string_lossy().into_owned()),
            );
        }
    }
    out
}

#[test]
fn shards_merge_into_the_summary_of_one_unsharded_run() {
    let dir = scratch("shards");
    let input = dir.join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    for (sample, name) in [
        ("glyph_aa.png", "a.png"),
        ("pear.png", "sub/b.png"),
        ("s.png", "c.png"),
        ("e.png", "sub/d.png"),
        ("glyph_bw.png", "e-f.png"),
    ] {
        std::fs::copy(common::samples_dir().join(sample), input.join(name)).unwrap();
    }
    let whole = dir.join("whole");
    let r = batch(&input, &whole, "2", &["--recursive", "--svg-only"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // Three shards, as three array jobs would run them, each into its own folder.
    let shards: Vec<PathBuf> = (1..=3).map(|k| dir.join(format!("shard{k}"))).collect();
    let mut traced = Vec::new();
    for (k, out) in shards.iter().enumerate() {
        // The third as a scheduler with 0-based indices would ask for it.
        let spec = format!("{}/3", k + 1);
        let index = k.to_string();
        let shard: Vec<&str> = if k == 2 {
            vec!["--shard-index", &index, "--shard-count", "3"]
        } else {
            vec!["--shard", &spec]
        };
        let mut extra = vec!["--recursive", "--svg-only"];
        extra.extend(shard);
        let r = batch(&input, out, "1", &extra);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        traced.extend(svgs_under(out));
    }
    // The union is the whole folder, no file twice, and each outline is the unsharded
    // run's.
    traced.sort();
    let mut all = svgs_under(&whole);
    all.sort();
    for f in &all {
        let from_shard = shards.iter().find_map(|s| std::fs::read(s.join(f)).ok());
        assert_eq!(
            from_shard,
            Some(std::fs::read(whole.join(f)).unwrap()),
            "{f}"
        );
    }
    assert_eq!(traced, all);
    assert_eq!(all.len(), 5);
    let merged = dir.join("merged.csv");
    let merge = |extra: &[&str], summaries: &[&Path]| {
        bin()
            .args(["summary", "merge"])
            .args(summaries)
            .arg("-o")
            .arg(&merged)
            .args(extra)
            .output()
            .unwrap()
    };
    let by_folder: Vec<&Path> = shards.iter().map(PathBuf::as_path).collect();
    let input_arg = input.to_str().unwrap();
    let r = merge(&["--input", input_arg, "--recursive"], &by_folder);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(
        std::fs::read_to_string(&merged).unwrap(),
        std::fs::read_to_string(whole.join("summary.csv")).unwrap()
    );
    std::fs::remove_file(&merged).unwrap();
    // A shard given twice, a shard missing, a shard unfinished: refused, nothing written.
    let twice = [by_folder[0], by_folder[1], by_folder[2], by_folder[0]];
    let missing = [by_folder[0], by_folder[2]];
    let unfinished = dir.join("unfinished.csv");
    std::fs::write(
        &unfinished,
        "file,status,segments,curves,sum_sq,max_distance,fidelity_held,max_deviation,largest_region,seconds,error\n,unfinished,,,,,,,,,the run has not finished\n",
    )
    .unwrap();
    for (summaries, says) in [
        (&twice[..], "appear in more than one summary"),
        (&missing[..], "are in no summary"),
        (
            &[by_folder[0], unfinished.as_path()][..],
            "has not finished",
        ),
    ] {
        let r = merge(&["--input", input_arg, "--recursive"], summaries);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(err.contains(says), "{err}");
        assert!(!merged.exists());
    }
}

#[test]
fn batch_writes_the_format_asked_for() {
    let dir = scratch("batch-formats");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::copy(common::samples_dir().join("s.png"), input.join("s.png")).unwrap();
    for (format, ending, starts) in [
        ("pdf", "pdf", &b"%PDF-"[..]),
        ("dxf", "dxf", &b"  0\r\nSECTION"[..]),
        ("dxf-r12", "dxf", &b"  0\r\nSECTION"[..]),
        ("geojson", "geojson", &b"{\"features\""[..]),
        ("eps", "eps", &b"%!PS-Adobe-3.0 EPSF"[..]),
    ] {
        let out = dir.join(format);
        let r = batch(&input, &out, "1", &["--format", format]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let bytes = std::fs::read(out.join(format!("s.{ending}"))).unwrap();
        assert!(bytes.starts_with(starts), "{format}");
        assert!(out.join("s.json").exists() && !out.join("s.svg").exists());
        // --skip-existing looks for the outline in that format.
        let again = batch(&input, &out, "1", &["--format", format, "--skip-existing"]);
        assert!(again.status.success());
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        assert!(summary.contains(",skipped,"), "{format}: {summary}");
    }
}

/// `outlinefit trace …` and the shorthand `outlinefit FILE …` are parsed by a tree with
/// `trace` alone (it is what a script calls once per file); what the user sees must be
/// what the whole tree shows: the help (`help trace` goes through the whole tree), the
/// usage errors and their exit status, the same for both spellings.
#[test]
fn trace_alone_parses_and_explains_as_the_whole_command_line() {
    let run = |args: &[&str]| {
        let out = bin().args(args).output().unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let alone = run(&["trace", "--help"]);
    let whole = run(&["help", "trace"]);
    assert_eq!(alone.0, Some(0));
    assert!(alone.1.contains("--tolerance") && alone.1.contains("Exit status:"));
    assert_eq!(alone, whole);
    for bad in [
        &["missing.png", "--no-such-option"][..],
        &["missing.png", "--tolerance"],
        &["missing.png", "--seed", "x"],
    ] {
        let alone = run(&[&["trace"][..], bad].concat());
        let whole = run(bad);
        assert_eq!(alone.0, Some(2), "{bad:?}: {}", alone.2);
        assert!(alone.2.starts_with("error: "), "{}", alone.2);
        assert_eq!(alone, whole, "{bad:?}");
    }
    let unknown = run(&["trace", "missing.png", "--no-such-option"]);
    assert!(
        unknown.2.contains("Usage: outlinefit trace"),
        "{}",
        unknown.2
    );
    let short_help = run(&["trace", "-h"]);
    assert_eq!(short_help.0, Some(0));
    assert!(short_help.1.len() < alone.1.len());
}
