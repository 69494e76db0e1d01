//! `--palette` through the program: what it writes (SVG groups per colour, JSON and CSV
//! reports that agree), what it refuses, `batch` on one and two threads, standard input.

mod common;

use common::{bin, render_svg_coverage, scratch};
use image::{Rgba, RgbaImage};
use std::path::{Path, PathBuf};
use std::process::Output;

/// A flag-like image: red on the left, white in the middle, a blue disk on the right,
/// anti-aliased by 8×8 supersampling.
fn write_logo(path: &Path) {
    let img = RgbaImage::from_fn(72, 48, |px, py| {
        let mut sum = [0u32; 3];
        for s in 0..64 {
            let x = f64::from(px) + (f64::from(s % 8) + 0.5) / 8.0;
            let y = f64::from(py) + (f64::from(s / 8) + 0.5) / 8.0;
            let c: [u32; 3] = if (x - 52.3).hypot(y - 23.8) < 12.6 {
                [30, 60, 200]
            } else if x < 24.4 {
                [220, 40, 30]
            } else {
                [255, 255, 255]
            };
            for k in 0..3 {
                sum[k] += c[k];
            }
        }
        Rgba([
            (sum[0] / 64) as u8,
            (sum[1] / 64) as u8,
            (sum[2] / 64) as u8,
            255,
        ])
    });
    img.save(path).unwrap();
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn trace_writes_one_group_per_colour_and_reports_that_agree() {
    let dir = scratch("trace");
    let input = dir.join("logo.png");
    write_logo(&input);
    let (svg, json, csv) = (dir.join("o.svg"), dir.join("r.json"), dir.join("r.csv"));
    let out = run(&[
        "trace",
        s(&input),
        "-o",
        s(&svg),
        "--palette",
        "auto",
        "--report",
        s(&json),
        "--csv",
        s(&csv),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    // Drawn largest first: white, red, blue.
    let groups: Vec<&str> = text
        .match_indices("<g ")
        .map(|(i, _)| &text[i..i + 50])
        .collect();
    assert_eq!(groups.len(), 3, "{text}");
    for (g, colour) in groups.iter().zip(["ffffff", "dc281e", "1e3cc8"]) {
        assert!(g.contains(&format!(r##"fill="#{colour}""##)), "{g}");
        assert!(g.contains(&format!(r#"id="colour-{colour}""#)), "{g}");
    }
    // Stacked: the whole opaque image is covered, no pixel shows the background.
    let alpha = render_svg_coverage(&text, 72, 48);
    assert!(alpha.iter().all(|&a| a == 1.0));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["fidelity"]["held"], true);
    assert_eq!(report["layout"], "stacked");
    assert_eq!(report["palette"].as_array().unwrap().len(), 4);
    let boundaries = report["boundaries"].as_array().unwrap();
    let segments: usize = boundaries
        .iter()
        .map(|b| b["segments"].as_array().unwrap().len())
        .sum();
    assert_eq!(report["segments"], segments);
    let csv_text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv_text.lines().count(), boundaries.len() + 1);
    assert!(csv_text.starts_with("boundary,right_region,left_region,right_colour,left_colour"));
    // The red|white boundary is a straight line at x = 24.4, drawn from 0 to 48.
    let straight = boundaries.iter().find(|b| {
        let c = b["colours"].as_array().unwrap();
        let mut c: Vec<u64> = c.iter().map(|v| v.as_u64().unwrap()).collect();
        c.sort_unstable();
        c == [1, 2]
    });
    let seg = &straight.expect("a red|white boundary")["segments"][0]["curve"]["points"];
    for p in seg.as_array().unwrap() {
        assert!((p["x"].as_f64().unwrap() - 24.4).abs() < 0.05, "{p}");
    }

    // The cutout layout: the same colours, abutting.
    let cut = dir.join("cut.svg");
    let out = run(&[
        "trace",
        s(&input),
        "-o",
        s(&cut),
        "--palette",
        "3",
        "--layout",
        "cutout",
    ]);
    assert!(out.status.success());
    let cut_text = std::fs::read_to_string(&cut).unwrap();
    assert_eq!(cut_text.matches("<g ").count(), 3);
    assert_ne!(cut_text, text);
}

#[test]
fn colour_options_that_cannot_work_are_refused_before_any_output() {
    let dir = scratch("refuse");
    let input = dir.join("logo.png");
    write_logo(&input);
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let (o, dxf) = (out_dir.join("o.svg"), out_dir.join("o.dxf"));
    for (args, expect) in [
        (
            vec!["--palette", "auto", "-o", s(&dxf)],
            "--palette writes SVG, PDF, EPS or PostScript",
        ),
        (vec!["--palette", "0"], "expected `auto` or a number"),
        (vec!["--palette", "many"], "expected `auto` or a number"),
        (vec!["--layout", "cutout"], "--palette"),
        (vec!["--palette", "auto", "--layout", "tiled"], "stacked"),
        (
            vec!["--palette", "auto", "--optimizer", "hs"],
            "fits with lsq",
        ),
        (vec!["--palette", "auto", "--overlay", "x.svg"], "--overlay"),
        (
            vec!["--palette", "auto", "-C", "#ff0000"],
            "cannot be used with",
        ),
    ] {
        let mut all = vec!["trace", s(&input)];
        if !args.contains(&"-o") {
            all.extend(["-o", s(&o)]);
        }
        all.extend(args.iter());
        let out = run(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(
            stderr.contains(expect),
            "{args:?}: expected {expect:?} in {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            std::fs::read_dir(&out_dir).unwrap().next().is_none(),
            "{args:?} wrote a file"
        );
    }
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

#[test]
fn batch_in_colour_is_the_same_on_one_and_two_threads_and_reads_standard_input() {
    let dir = scratch("batch");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    write_logo(&input.join("a.png"));
    image::imageops::flip_horizontal(&image::open(input.join("a.png")).unwrap())
        .save(input.join("b.png"))
        .unwrap();
    std::fs::write(input.join("broken.png"), b"not an image").unwrap();
    let mut outputs = Vec::new();
    for jobs in ["1", "2"] {
        let out_dir = dir.join(format!("out{jobs}"));
        let out = run(&[
            "batch",
            s(&input),
            "-o",
            s(&out_dir),
            "--palette",
            "auto",
            "--jobs",
            jobs,
            "--no-timings",
        ]);
        assert_eq!(out.status.code(), Some(1), "the broken file fails its row");
        let summary = std::fs::read_to_string(out_dir.join("summary.csv")).unwrap();
        assert_eq!(summary.matches(",ok,").count(), 2, "{summary}");
        assert_eq!(summary.matches(",failed,").count(), 1, "{summary}");
        let names: Vec<String> = files(&out_dir)
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.json", "a.svg", "b.json", "b.svg", "summary.csv"]);
        outputs.push(
            files(&out_dir)
                .iter()
                .map(|p| std::fs::read(p).unwrap())
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(outputs[0], outputs[1]);
    // Standard input gives the file's SVG.
    let mut child = bin()
        .args(["trace", "-", "--palette", "auto", "-o", "-"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    use std::io::Write;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(&std::fs::read(input.join("a.png")).unwrap())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    assert_eq!(
        out.stdout,
        std::fs::read(dir.join("out1").join("a.svg")).unwrap()
    );
}

/// RGB pixels of a rendered page.
fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn colour_pdf_and_eps_draw_what_the_svg_draws() {
    let dir = scratch("pages");
    let input = dir.join("logo.png");
    write_logo(&input);
    let svg = dir.join("o.svg");
    assert!(
        run(&["trace", s(&input), "-o", s(&svg), "--palette", "auto"])
            .status
            .success()
    );
    // The SVG's rendering, composited on white as the page renderers paint.
    let tree = resvg::usvg::Tree::from_str(
        &std::fs::read_to_string(&svg).unwrap(),
        &resvg::usvg::Options::default(),
    )
    .unwrap();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(72, 48).unwrap();
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::identity(),
        &mut pixmap.as_mut(),
    );
    let want: Vec<[u8; 3]> = pixmap
        .pixels()
        .iter()
        .map(|p| [p.red(), p.green(), p.blue()])
        .collect();
    let renders = [
        ("pdf", "pdftoppm", vec!["-r", "72", "-png", "-singlefile"]),
        (
            "eps",
            "gs",
            vec![
                "-q",
                "-dSAFER",
                "-dBATCH",
                "-dNOPAUSE",
                "-sDEVICE=png16m",
                "-dEPSCrop",
                "-r72",
            ],
        ),
    ];
    for (ending, program, args) in renders {
        let page = dir.join(format!("o.{ending}"));
        let out = run(&["trace", s(&input), "-o", s(&page), "--palette", "auto"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let png = dir.join(format!("{ending}.png"));
        let mut cmd = std::process::Command::new(program);
        cmd.args(&args);
        if program == "gs" {
            cmd.arg(format!("-sOutputFile={}", png.display()))
                .arg(&page);
        } else {
            cmd.arg(&page).arg(dir.join(ending));
        }
        let Ok(status) = cmd.status() else {
            // The readers are installed by .ci/run; a machine without them checks the rest.
            eprintln!("{program} not found: {ending} rendering not checked");
            continue;
        };
        assert!(status.success(), "{program} failed on {}", page.display());
        let got = rgb(&png);
        assert_eq!((got.width(), got.height()), (72, 48), "{ending} page size");
        // Every pixel away from the edges (where renderers anti-alias differently, or not
        // at all) has the SVG's colour.
        let interior = |i: usize| {
            let (x, y) = ((i % 72) as i64, (i / 72) as i64);
            (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let (cx, cy) = (x + dx, y + dy);
                    !(0..72).contains(&cx)
                        || !(0..48).contains(&cy)
                        || want[(cy * 72 + cx) as usize] == want[i]
                })
            })
        };
        let off: Vec<usize> = (0..want.len())
            .filter(|&i| interior(i))
            .filter(|&i| {
                let g = got.get_pixel((i % 72) as u32, (i / 72) as u32);
                (0..3).any(|k| (i32::from(g[k]) - i32::from(want[i][k])).abs() > 8)
            })
            .collect();
        assert!(
            off.is_empty(),
            "{ending}: pixels of another colour at {off:?}"
        );
        // And the colours are there: the middle of the disk is blue.
        assert_eq!(got.get_pixel(52, 24).0, [30, 60, 200], "{ending}");
    }
}
