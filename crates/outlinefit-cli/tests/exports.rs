//! Every output format through the binary, read back by independent programs: PDF by
//! poppler's `pdftoppm`, EPS and PostScript by Ghostscript, DXF by `ezdxf` and GeoJSON by
//! `shapely` (the Python script beside this file). Each rendering is compared with the SVG
//! rendered by resvg at the same size. A reader that is not installed skips its check with
//! a message; `.ci/run` installs them all.

mod common;

use common::{bin, coverage_iou, render_svg_coverage_scaled, scratch};
use resvg::tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Transform};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Size of the test image.
const W: u32 = 200;
const H: u32 = 150;
/// Renderings are made at this many pixels per image pixel and compared as masks (pixels
/// more than half covered), so that the renderers' different anti-aliasing weighs
/// little: poppler's covers about 0.1 % more area than resvg's at the edges.
const ZOOM: u32 = 8;

/// Intersection over union of the shapes two renderings show (pixels more than half
/// covered).
fn mask_iou(a: &[f32], b: &[f32]) -> f64 {
    let mask =
        |c: &[f32]| -> Vec<f32> { c.iter().map(|&x| if x > 0.5 { 1.0 } else { 0.0 }).collect() };
    coverage_iou(&mask(a), &mask(b))
}

/// An anti-aliased test image: a ring (a disk with a round hole), a square turned by 30°
/// (corners), and a small disk on its own. Coverage by 8×8 supersampling.
fn test_image(dir: &Path) -> PathBuf {
    let inside = |x: f64, y: f64| {
        let ring = {
            let r = (x - 60.0).hypot(y - 70.0);
            (18.0..=42.0).contains(&r)
        };
        let square = {
            let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
            let (dx, dy) = (x - 145.0, y - 60.0);
            let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
            u.abs() <= 28.0 && v.abs() <= 28.0
        };
        let dot = (x - 150.0).hypot(y - 125.0) <= 9.0;
        ring || square || dot
    };
    let img = image::GrayImage::from_fn(W, H, |px, py| {
        let mut n = 0;
        for j in 0..8 {
            for i in 0..8 {
                let x = f64::from(px) + (f64::from(i) + 0.5) / 8.0;
                let y = f64::from(py) + (f64::from(j) + 0.5) / 8.0;
                n += u32::from(inside(x, y));
            }
        }
        image::Luma([(255 - n * 255 / 64) as u8])
    });
    let path = dir.join("shapes.png");
    img.save(&path).unwrap();
    path
}

/// Runs `trace` on the image with `args`; panics with standard error on failure.
fn trace(input: &Path, args: &[&str]) {
    let out = bin()
        .arg("trace")
        .arg(input)
        .args(["--no-timings"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The SVG's rendering at ZOOM.
fn svg_coverage(svg: &Path) -> Vec<f32> {
    let text = std::fs::read_to_string(svg).unwrap();
    render_svg_coverage_scaled(&text, W * ZOOM, H * ZOOM, ZOOM as f32)
}

/// Coverage of a grey PGM rendering (black ink on white paper), with its size.
fn pgm_coverage(path: &Path) -> (u32, u32, Vec<f32>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_luma8();
    let (w, h) = img.dimensions();
    let cov = img
        .pixels()
        .map(|p| 1.0 - f32::from(p.0[0]) / 255.0)
        .collect();
    (w, h, cov)
}

/// Whether a program can be started (`--version` or `-v` answers).
fn have(program: &str, flag: &str) -> bool {
    Command::new(program)
        .arg(flag)
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn pdf_eps_and_postscript_render_like_the_svg_at_the_page_size_of_the_dpi() {
    let dir = scratch("pages");
    let input = test_image(&dir);
    let svg = dir.join("shapes.svg");
    trace(&input, &["-o", svg.to_str().unwrap()]);
    let reference = svg_coverage(&svg);
    // 300 dpi: the page is 200 × 72/300 = 48 pt wide; rendered at 2400 dpi it is 1600
    // pixels, ZOOM times the image.
    let dpi = "300";
    let render_dpi = (300 * ZOOM).to_string();
    for (format, reader) in [("pdf", "pdftoppm"), ("eps", "gs"), ("ps", "gs")] {
        let out = dir.join(format!("shapes.{format}"));
        trace(&input, &["-o", out.to_str().unwrap(), "--dpi", dpi]);
        let bytes = std::fs::read(&out).unwrap();
        let pgm = dir.join(format!("{format}.pgm"));
        if format == "pdf" {
            assert!(bytes.starts_with(b"%PDF-"));
            let text = String::from_utf8_lossy(&bytes);
            assert!(text.contains("/MediaBox [0 0 48 36]"), "page size");
        } else {
            let text = String::from_utf8(bytes).unwrap();
            assert!(text.contains("%%BoundingBox: 0 0 48 36\n"), "{text}");
            assert!(text.contains(" f*\n") || text.contains("\nf*\n"));
        }
        let ran = if reader == "pdftoppm" {
            if !have("pdftoppm", "-v") {
                eprintln!("skipped: pdftoppm (poppler-utils) is not installed; PDF not rendered");
                continue;
            }
            let prefix = dir.join(format!("{format}-render"));
            let s = Command::new("pdftoppm")
                .args(["-r", &render_dpi, "-gray", "-singlefile"])
                .arg(&out)
                .arg(&prefix)
                .status()
                .unwrap();
            std::fs::rename(prefix.with_extension("pgm"), &pgm).unwrap();
            s
        } else {
            if !have("gs", "--version") {
                eprintln!("skipped: Ghostscript is not installed; {format} not rendered");
                continue;
            }
            let mut cmd = Command::new("gs");
            cmd.args([
                "-q",
                "-dSAFER",
                "-dBATCH",
                "-dNOPAUSE",
                "-sDEVICE=pgmraw",
                "-dGraphicsAlphaBits=4",
                &format!("-r{render_dpi}"),
            ]);
            if format == "eps" {
                cmd.arg("-dEPSCrop");
            }
            // Ghostscript widens every fill by its "fill adjust" (0.3 device pixels unless
            // told otherwise): exact fills for an exact comparison.
            cmd.arg(format!("-sOutputFile={}", pgm.display()))
                .args(["-c", "0 0 .setfilladjust2", "-f"])
                .arg(&out);
            cmd.status().unwrap()
        };
        assert!(ran.success(), "{reader} failed on {format}");
        let (w, h, cov) = pgm_coverage(&pgm);
        assert_eq!(
            (w, h),
            (W * ZOOM, H * ZOOM),
            "{format}: page size for --dpi {dpi}"
        );
        let iou = mask_iou(&cov, &reference);
        assert!(iou >= 0.999, "{format}: IoU {iou} with the SVG");
    }
}

/// Runs the Python checker; `None` (after a message) when Python or its modules are
/// missing.
fn python_check(args: &[&str]) -> Option<serde_json::Value> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/exports/check_exports.py");
    let Ok(out) = Command::new("python3").arg(&script).args(args).output() else {
        eprintln!(
            "skipped: python3 is not installed; {} not read back",
            args[0]
        );
        return None;
    };
    match out.status.code() {
        Some(0) => Some(serde_json::from_slice(&out.stdout).unwrap()),
        Some(3) => {
            eprintln!(
                "skipped: {} (pip install ezdxf shapely); {} not read back",
                String::from_utf8_lossy(&out.stderr).trim(),
                args[0]
            );
            None
        }
        _ => panic!("{args:?}: {}", String::from_utf8_lossy(&out.stderr).trim()),
    }
}

/// Fills closed loops (in page units, y up) with the even-odd rule at ZOOM, mapped back
/// to image pixels.
fn loops_coverage(loops: &serde_json::Value, per_pixel: f64) -> Vec<f32> {
    let mut pb = PathBuilder::new();
    let z = f64::from(ZOOM);
    let at = |p: &serde_json::Value| {
        let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        (
            (x / per_pixel * z) as f32,
            ((f64::from(H) - y / per_pixel) * z) as f32,
        )
    };
    for l in loops.as_array().unwrap() {
        let points = l.as_array().unwrap();
        let (x, y) = at(&points[0]);
        pb.move_to(x, y);
        for p in &points[1..] {
            let (x, y) = at(p);
            pb.line_to(x, y);
        }
        pb.close();
    }
    let path = pb.finish().unwrap();
    let mut pixmap = Pixmap::new(W * ZOOM, H * ZOOM).unwrap();
    let mut paint = Paint::default();
    paint.set_color_rgba8(0, 0, 0, 255);
    paint.anti_alias = true;
    pixmap.fill_path(
        &path,
        &paint,
        FillRule::EvenOdd,
        Transform::identity(),
        None,
    );
    pixmap
        .pixels()
        .iter()
        .map(|p| f32::from(p.alpha()) / 255.0)
        .collect()
}

#[test]
fn dxf_splines_are_the_fitted_curves_and_read_back_in_their_units() {
    let dir = scratch("dxf");
    let input = test_image(&dir);
    let svg = dir.join("shapes.svg");
    let report = dir.join("shapes.json");
    trace(
        &input,
        &[
            "-o",
            svg.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ],
    );
    let reference = svg_coverage(&svg);
    // R2000 in millimetres at 300 dpi ($INSUNITS 4), in pixels (0), and R12.
    for (name, args, version, units, per_pixel) in [
        (
            "mm.dxf",
            &["--unit", "mm", "--dpi", "300"][..],
            "AC1015",
            "4",
            25.4 / 300.0,
        ),
        ("px.dxf", &[][..], "AC1015", "0", 1.0),
        ("r12.dxf", &["-b", "dxf-r12"][..], "AC1009", "0", 1.0),
    ] {
        let out = dir.join(name);
        let mut all = vec!["-o", out.to_str().unwrap()];
        all.extend_from_slice(args);
        trace(&input, &all);
        // Reproducible: no time stamp or random GUID in the header (the same outline
        // gives the same bytes whenever it is written).
        let text = std::fs::read_to_string(&out).unwrap();
        if version == "AC1015" {
            assert!(text.contains("$TDCREATE\r\n 40\r\n2451544.5\r\n"), "{name}");
            assert!(
                text.contains("$TDUUPDATE\r\n 40\r\n2451544.5\r\n"),
                "{name}"
            );
        }
        let again = dir.join(format!("again-{name}"));
        let mut all = vec!["-o", again.to_str().unwrap()];
        all.extend_from_slice(args);
        trace(&input, &all);
        assert_eq!(std::fs::read(&again).unwrap(), text.as_bytes(), "{name}");
        let Some(checked) = python_check(&[
            "dxf",
            out.to_str().unwrap(),
            report.to_str().unwrap(),
            version,
            units,
            &per_pixel.to_string(),
        ]) else {
            return;
        };
        let loops = &checked["loops"];
        // Three shapes, one hole.
        assert_eq!(loops.as_array().unwrap().len(), 4, "{name}");
        let iou = mask_iou(&loops_coverage(loops, per_pixel), &reference);
        assert!(iou >= 0.999, "{name}: IoU {iou} with the SVG");
    }
}

#[test]
fn geojson_polygons_are_valid_and_have_the_svgs_area() {
    let dir = scratch("geojson");
    let input = test_image(&dir);
    let svg = dir.join("shapes.svg");
    let out = dir.join("shapes.geojson");
    trace(&input, &["-o", svg.to_str().unwrap()]);
    trace(&input, &["-o", out.to_str().unwrap()]);
    let text = std::fs::read_to_string(&out).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let features = doc["features"].as_array().unwrap();
    assert_eq!(features.len(), 3);
    let holes: usize = features
        .iter()
        .map(|f| f["geometry"]["coordinates"].as_array().unwrap().len() - 1)
        .sum();
    assert_eq!(holes, 1);
    let Some(checked) = python_check(&["geojson", out.to_str().unwrap()]) else {
        return;
    };
    let area: f64 = checked["areas"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_f64().unwrap())
        .sum();
    let svg_area: f64 = svg_coverage(&svg)
        .iter()
        .map(|&c| f64::from(c))
        .sum::<f64>()
        / f64::from(ZOOM * ZOOM);
    assert!(
        (area - svg_area).abs() <= 1e-3 * svg_area,
        "GeoJSON area {area} px², SVG {svg_area} px²"
    );
}

#[test]
fn sizes_colours_and_stroke_only_are_written_as_asked() {
    let dir = scratch("sizes");
    let input = test_image(&dir);
    let read = |name: &str, args: &[&str]| {
        let out = dir.join(name);
        let mut all = vec!["-o", out.to_str().unwrap()];
        all.extend_from_slice(args);
        trace(&input, &all);
        std::fs::read_to_string(out).unwrap()
    };
    let plain = read("plain.svg", &[]);
    assert!(plain.starts_with(
        "<svg height=\"150\" viewBox=\"0 0 20000 15000\" width=\"200\" xmlns=\"http://www.w3.org/2000/svg\">"
    ));
    // 200 px at 300 dpi = 16.9333 mm; 150 px = 12.7 mm. The viewBox stays in hundredths
    // of a pixel.
    let mm = read("mm.svg", &["--unit", "mm", "--dpi", "300"]);
    assert!(
        mm.starts_with("<svg height=\"12.7mm\" viewBox=\"0 0 20000 15000\" width=\"16.9333mm\""),
        "{}",
        &mm[..120]
    );
    let scaled = read("scaled.svg", &["--scale", "2.5"]);
    assert!(scaled.contains("height=\"375\"") && scaled.contains("width=\"500\""));
    // The paths are the same whatever the size.
    let paths = |s: &str| s[s.find("<g").unwrap()..].to_string();
    assert_eq!(paths(&plain), paths(&mm));
    assert_eq!(paths(&plain), paths(&scaled));

    let coloured = read("c.svg", &["-C", "#ff8000"]);
    // One group carries the paint of every path.
    assert_eq!(coloured.matches("fill=\"#ff8000\"").count(), 1);
    assert_eq!(coloured.matches("<path").count(), 3);
    let eps = read("c.eps", &["-C", "ff8000"]);
    assert!(eps.contains("\n1 0.502 0 setrgbcolor\n"), "{eps}");

    let stroked = read("s.svg", &["--stroke-only", "-C", "#f00"]);
    assert_eq!(stroked.matches("fill=\"none\"").count(), 1);
    assert_eq!(stroked.matches("stroke=\"#ff0000\"").count(), 1);
    // One pixel in hundredths of a pixel.
    assert_eq!(stroked.matches("stroke-width=\"100\"").count(), 1);
    assert!(!stroked.contains("evenodd"));
    // Drawn as lines, the shapes cover a band along their outlines only: far less than
    // the filled area, far more than nothing.
    let ink = |svg: &str| -> f64 {
        render_svg_coverage_scaled(svg, W, H, 1.0)
            .iter()
            .map(|&c| f64::from(c))
            .sum()
    };
    let (filled, lines) = (ink(&plain), ink(&stroked));
    assert!(
        lines > 0.05 * filled && lines < 0.5 * filled,
        "{lines} vs {filled}"
    );
    let stroked_eps = read("s.eps", &["--stroke-only"]);
    assert!(stroked_eps.contains("\nS\n") && !stroked_eps.contains("\nf*\n"));

    for (args, says) in [
        (&["--dpi", "0"][..], "--dpi must be a positive number"),
        (&["--scale", "-1"][..], "--scale must be a positive number"),
        (&["-C", "red"][..], "is not a colour"),
        (&["--unit", "pt", "-b", "dxf"][..], "DXF has no point unit"),
        (&["--unit", "furlong"][..], "unknown unit"),
        (&["-b", "png"][..], "unknown format"),
    ] {
        let out = dir.join("refused.out");
        let o = bin()
            .arg("trace")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{args:?}: {err}");
        assert!(!out.exists());
    }
}

#[test]
fn potrace_names_give_the_same_output_as_the_long_forms() {
    let dir = scratch("aliases");
    let input = test_image(&dir);
    let run = |name: &str, args: &[&str]| -> Vec<u8> {
        let out = dir.join(name);
        let mut all = vec!["-o", out.to_str().unwrap()];
        all.extend_from_slice(args);
        trace(&input, &all);
        std::fs::read(out).unwrap()
    };
    for (k, (potrace, ours)) in [
        (&["-t", "40"][..], &["--min-area", "41"][..]),
        (&["--turdsize", "40"][..], &["--min-area", "41"][..]),
        (&["-k", "0.4"][..], &["--threshold", "102"][..]),
        (&["--blacklevel", "0.4"][..], &["--threshold", "102"][..]),
        (&["-a", "0.5"][..], &["--corner-angle", "67.5"][..]),
        (&["--alphamax", "0.5"][..], &["--corner-angle", "67.5"][..]),
        (&["-O", "0.5"][..], &["--tolerance", "0.5"][..]),
        (&["--opttolerance", "0.5"][..], &["--tolerance", "0.5"][..]),
        (
            &["-i", "--threshold", "40"][..],
            &["--invert", "--threshold", "40"][..],
        ),
        (&["-C", "#123456"][..], &["--color", "#123456"][..]),
        (
            &["-r", "300", "--unit", "in"][..],
            &["--dpi", "300", "--unit", "in"][..],
        ),
        (
            &["--resolution", "300", "--unit", "in"][..],
            &["--dpi", "300", "--unit", "in"][..],
        ),
        (&["-x", "2"][..], &["--scale", "2"][..]),
    ]
    .into_iter()
    .enumerate()
    {
        let a = run(&format!("p{k}.svg"), potrace);
        let b = run(&format!("o{k}.svg"), ours);
        assert_eq!(a, b, "{potrace:?} against {ours:?}");
    }
    // The backend by name: -b and --backend are --format.
    let a = run("b.out", &["-b", "pdf"]);
    let b = run("backend.out", &["--backend", "pdf"]);
    let c = run("format.out", &["--format", "pdf"]);
    assert!(a.starts_with(b"%PDF-"));
    assert!(a == b && b == c);
    // -t drops what potrace drops: the small disk (about 254 px²) goes at -t 300.
    let few = String::from_utf8(run("t300.svg", &["-t", "300"])).unwrap();
    assert_eq!(few.matches("<path").count(), 2);
}
