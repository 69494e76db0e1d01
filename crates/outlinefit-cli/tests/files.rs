//! Files and inputs a user can trust, through the binary on files the tests create:
//! outputs only replace regular files, never each other; batch names never collide;
//! symlink loops end; truncated JPEGs, closed standard output and interrupted runs are
//! reported, and leave no debris; standard input is read; EXIF orientation is applied.

mod common;

use common::{bin, scratch};

use image::{GrayImage, Luma};
use std::path::Path;
use std::process::{Command, Stdio};

/// A 60×40 image: a dark bar 30 px wide and 10 px tall at (10, 5) on white, so that its
/// orientation is visible from the traced outline's bounding box.
fn bar() -> GrayImage {
    let mut img = GrayImage::from_pixel(60, 40, Luma([255]));
    for y in 5..15 {
        for x in 10..40 {
            img.put_pixel(x, y, Luma([0]));
        }
    }
    img
}

fn write_png(path: &Path) {
    bar().save(path).unwrap();
}

fn run(cmd: &mut Command) -> (i32, String, String) {
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Bounding box (min x, min y, max x, max y), in pixels, of the points and control points
/// of the first SVG path: user units scaled by the document's width over its `viewBox`
/// width.
fn path_box(svg: &str) -> [f64; 4] {
    let attribute = |name: &str| {
        let start = svg.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        &svg[start..start + svg[start..].find('"').unwrap()]
    };
    let view_width: f64 = attribute("viewBox")
        .split(' ')
        .nth(2)
        .unwrap()
        .parse()
        .unwrap();
    let k = attribute("width").parse::<f64>().unwrap() / view_width;
    use svgtypes::SimplePathSegment as S;
    let d = svg
        .split(" d=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for segment in svgtypes::SimplifyingPathParser::from(d) {
        let points = match segment.unwrap() {
            S::MoveTo { x, y } | S::LineTo { x, y } => vec![(x, y)],
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => vec![(x1, y1), (x2, y2), (x, y)],
            S::Quadratic { x1, y1, x, y } => vec![(x1, y1), (x, y)],
            S::ClosePath => Vec::new(),
        };
        for (x, y) in points {
            let (x, y) = (x * k, y * k);
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
    }
    b
}

/// Makes a FIFO at `path`.
#[cfg(unix)]
fn mkfifo(path: &Path) {
    assert!(Command::new("mkfifo").arg(path).status().unwrap().success());
}

#[cfg(unix)]
#[test]
fn outputs_never_replace_devices_fifos_or_links() {
    let dir = scratch("special");
    let input = dir.join("in.png");
    write_png(&input);
    // A FIFO stays a FIFO (and the run does not hang on it).
    let fifo = dir.join("fifo.svg");
    mkfifo(&fifo);
    let (code, _, err) = run(bin().arg("trace").arg(&input).arg("-o").arg(&fifo));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("FIFO"), "{err}");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    // A device: /dev/null exists on every Unix; it must stay a character device.
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("--report")
        .arg("/dev/null"));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("device"), "{err}");
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    // A link is refused, and followed on request.
    let target = dir.join("target.svg");
    std::fs::write(&target, "old").unwrap();
    let link = dir.join("link.svg");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let (code, _, err) = run(bin().arg("trace").arg(&input).arg("-o").arg(&link));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("symbolic link"), "{err}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "old");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&link)
        .arg("--follow-symlinks"));
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&target)
        .unwrap()
        .starts_with("<svg"));
    // A device path as input gets no output next to it.
    let (code, _, err) = run(bin().arg("trace").arg("/dev/stdin").stdin(Stdio::null()));
    assert_eq!(code, 1, "{err}");
    assert!(!Path::new("/dev/stdin.svg").exists());
}

#[test]
fn two_outputs_of_one_run_never_share_a_file() {
    let dir = scratch("dupes");
    let input = dir.join("in.png");
    write_png(&input);
    let x = dir.join("x.svg");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&x)
        .arg("--report")
        .arg(&x));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("both name"), "{err}");
    assert!(!x.exists());
    // The same file spelled differently.
    let y = dir.join("sub/../r.json");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("--csv")
        .arg(dir.join("r.json"))
        .arg("--report")
        .arg(&y));
    assert_eq!(code, 1, "{err}");
    // Two standard outputs.
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg("-")
        .arg("--report")
        .arg("-"));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("standard output"), "{err}");
    assert!(!dir.join("-").exists());
}

#[test]
fn standard_input_is_traced_to_standard_output() {
    let dir = scratch("stdin");
    let input = dir.join("in.png");
    write_png(&input);
    let out = bin()
        .arg("trace")
        .arg("-")
        .stdin(std::fs::File::open(&input).unwrap())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = String::from_utf8(out.stdout).unwrap();
    let b = path_box(&svg);
    assert!(
        (b[0] - 10.0).abs() < 0.5 && (b[2] - 40.0).abs() < 0.5,
        "{b:?}"
    );
    assert!(!dir.join("-.svg").exists() && !dir.join("-").exists());
}

#[cfg(unix)]
#[test]
fn a_closed_standard_output_is_an_error() {
    let dir = scratch("closed");
    let input = dir.join("in.png");
    write_png(&input);
    // The shell closes descriptor 1 before starting the program.
    let status = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "\"{}\" trace \"{}\" -o - >&- 2>/dev/null",
            env!("CARGO_BIN_EXE_outlinefit"),
            input.display()
        ))
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(1));
}

#[test]
fn truncated_jpeg_is_refused() {
    let dir = scratch("jpeg");
    let whole = dir.join("whole.jpg");
    image::DynamicImage::ImageLuma8(bar())
        .to_rgb8()
        .save(&whole)
        .unwrap();
    let bytes = std::fs::read(&whole).unwrap();
    let cut = dir.join("cut.jpg");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&whole)
        .arg("-o")
        .arg(dir.join("w.svg")));
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&cut)
        .arg("-o")
        .arg(dir.join("c.svg")));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("truncated"), "{err}");
    assert!(!dir.join("c.svg").exists());
}

/// A PNG with an eXIf chunk saying "rotate 90° clockwise" (orientation 6): the wide bar
/// must come out tall.
#[test]
fn exif_orientation_is_applied() {
    let dir = scratch("exif");
    let plain = dir.join("plain.png");
    write_png(&plain);
    let png = std::fs::read(&plain).unwrap();
    // Little-endian TIFF header, one IFD entry: tag 0x0112 (Orientation), SHORT, 1, 6.
    let exif: Vec<u8> = vec![
        b'I', b'I', 42, 0, 8, 0, 0, 0, 1, 0, 0x12, 0x01, 3, 0, 1, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0,
    ];
    let mut chunk = Vec::new();
    chunk.extend_from_slice(&(exif.len() as u32).to_be_bytes());
    let mut body = b"eXIf".to_vec();
    body.extend_from_slice(&exif);
    chunk.extend_from_slice(&body);
    chunk.extend_from_slice(&crc32(&body).to_be_bytes());
    // Insert after IHDR (8-byte signature + 25-byte IHDR chunk).
    let mut rotated = png[..33].to_vec();
    rotated.extend_from_slice(&chunk);
    rotated.extend_from_slice(&png[33..]);
    let path = dir.join("rotated.png");
    std::fs::write(&path, rotated).unwrap();
    let (code, svg, err) = run(bin().arg("trace").arg(&path).arg("-o").arg("-"));
    assert_eq!(code, 0, "{err}");
    let b = path_box(&svg);
    assert!(
        svg.contains("width=\"40\"") && svg.contains("height=\"60\""),
        "{svg}"
    );
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    assert!((w - 10.0).abs() < 0.5 && (h - 30.0).abs() < 0.5, "{b:?}");

    // The same orientation in a JPEG's APP1 segment, right after the start-of-image marker.
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95)
        .encode_image(&bar())
        .unwrap();
    let mut app1 = vec![0xFF, 0xE1];
    app1.extend_from_slice(&((2 + 6 + exif.len()) as u16).to_be_bytes());
    app1.extend_from_slice(b"Exif\0\0");
    app1.extend_from_slice(&exif);
    let mut rotated = jpeg[..2].to_vec();
    rotated.extend_from_slice(&app1);
    rotated.extend_from_slice(&jpeg[2..]);
    let path = dir.join("rotated.jpg");
    std::fs::write(&path, rotated).unwrap();
    let (code, svg, err) = run(bin().arg("trace").arg(&path).arg("-o").arg("-"));
    assert_eq!(code, 0, "{err}");
    assert!(
        svg.contains("width=\"40\"") && svg.contains("height=\"60\""),
        "{svg}"
    );
    let b = path_box(&svg);
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    assert!((w - 10.0).abs() < 0.7 && (h - 30.0).abs() < 0.7, "{b:?}");
}

fn crc32(data: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &byte in data {
        c ^= u32::from(byte);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[test]
fn batch_names_never_collide() {
    let dir = scratch("collide");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    for name in ["a.png", "a.bmp", "a.png.bmp"] {
        image::DynamicImage::ImageLuma8(bar())
            .save(input.join(name))
            .unwrap();
    }
    let out = dir.join("out");
    let (code, _, err) = run(bin()
        .arg("batch")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .arg("--svg-only"));
    assert_eq!(code, 0, "{err}");
    let mut svgs: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".svg"))
        .collect();
    svgs.sort();
    assert_eq!(svgs, ["a.bmp.svg", "a.png.svg", "a.png~2.svg"]);
}

#[cfg(unix)]
#[test]
fn recursion_ends_in_a_symlink_loop() {
    let dir = scratch("loop");
    let input = dir.join("in");
    std::fs::create_dir_all(input.join("sub")).unwrap();
    write_png(&input.join("a.png"));
    std::os::unix::fs::symlink("..", input.join("sub/up")).unwrap();
    for follow in [false, true] {
        let out = dir.join(format!("out-{follow}"));
        let mut cmd = bin();
        cmd.arg("batch")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .arg("--recursive")
            .arg("--svg-only");
        if follow {
            cmd.arg("--follow-symlinks");
        }
        let (code, _, err) = run(&mut cmd);
        assert_eq!(code, 0, "{err}");
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        assert_eq!(summary.lines().count(), 2, "{summary}");
    }
}

#[cfg(unix)]
#[test]
fn an_interrupted_batch_leaves_no_debris_and_no_stale_summary() {
    let dir = scratch("interrupt");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    // Enough work to interrupt: large noisy images.
    let mut img = GrayImage::from_pixel(700, 700, Luma([255]));
    for y in 0..700u32 {
        for x in 0..700u32 {
            if (x / 3 + y / 5) % 4 == 0 || (x * 7 + y * 13) % 17 == 0 {
                img.put_pixel(x, y, Luma([0]));
            }
        }
    }
    for k in 0..6 {
        img.save(input.join(format!("n{k}.png"))).unwrap();
    }
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // Debris of a killed run (a process that no longer exists) and an old summary.
    let stale = out.join("n0.json.outlinefit-tmp-4000000-0");
    std::fs::write(&stale, "partial").unwrap();
    std::fs::write(out.join("summary.csv"), "file,status\nold.png,ok\n").unwrap();
    for signal in ["INT", "KILL"] {
        let mut child = bin()
            .arg("batch")
            .arg(&input)
            .arg("-o")
            .arg(&out)
            .arg("--jobs")
            .arg("2")
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(700));
        send(&child, signal);
        let status = child.wait().unwrap();
        assert!(!status.success());
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        assert!(!summary.contains("old.png"), "{summary}");
        assert!(summary.contains("unfinished"), "{signal}: {summary}");
        if signal == "INT" {
            let debris: Vec<_> = std::fs::read_dir(&out)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.contains(".outlinefit-tmp-"))
                .collect();
            assert!(debris.is_empty(), "{debris:?}");
        }
    }
    assert!(!stale.exists());
    // The next run cleans up after SIGKILL and finishes with a complete summary.
    let (code, _, err) = run(bin().arg("batch").arg(&input).arg("-o").arg(&out));
    assert_eq!(code, 0, "{err}");
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.contains(".outlinefit-tmp-")),
        "{names:?}"
    );
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 7, "{summary}");
    assert!(!summary.contains("unfinished"));
}

/// Sends `signal` (a `kill` name: INT, TERM, KILL) to `child`.
#[cfg(unix)]
fn send(child: &std::process::Child, signal: &str) {
    let sent = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .unwrap();
    assert!(sent.success());
}

/// Sends `signal` to `child` and waits at most 5 s for it to end.
#[cfg(unix)]
fn interrupt(child: &mut std::process::Child, signal: &str) -> std::process::ExitStatus {
    send(child, signal);
    for _ in 0..500 {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let _ = child.kill();
    panic!("SIG{signal} did not end the run within 5 s");
}

#[cfg(unix)]
#[test]
fn a_short_trace_interrupted_before_its_outputs_writes_none_and_ends_with_130() {
    // The image comes through a FIFO, so the signal lands while the run waits for it; a
    // trace of a small image has no thread waiting for signals and reads their flag
    // before its outputs (SIGINT and SIGTERM alike).
    for signal in ["INT", "TERM"] {
        let dir = scratch(&format!("interrupt-short-{signal}"));
        let fifo = dir.join("in.png");
        mkfifo(&fifo);
        let (out, report) = (dir.join("out.svg"), dir.join("out.json"));
        let child = bin()
            .arg("trace")
            .arg(&fifo)
            .arg("-o")
            .arg(&out)
            .arg("--report")
            .arg(&report)
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(300));
        send(&child, signal);
        let mut png = Vec::new();
        bar()
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        std::fs::write(&fifo, &png).unwrap();
        let result = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(130), "{signal}: {err}");
        assert!(err.contains("interrupted"), "{err}");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "in.png")
            .collect();
        assert!(left.is_empty(), "{signal}: {left:?}");
    }
}

#[cfg(unix)]
#[test]
fn a_trace_waiting_for_standard_input_ends_at_once_when_interrupted() {
    // Reading standard input may block: a thread waits for the signal and ends the run.
    let dir = scratch("interrupt-stdin");
    let out = dir.join("out.svg");
    let mut child = bin()
        .arg("trace")
        .arg("-")
        .arg("-o")
        .arg(&out)
        .stdin(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    // Standard input stays open: only the signal can end the run.
    let status = interrupt(&mut child, "TERM");
    assert_eq!(status.code(), Some(130));
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn a_long_trace_ends_at_once_when_interrupted() {
    // Random pixels: a quarter of a million specks, seconds of work.
    let dir = scratch("interrupt-long");
    let input = dir.join("noise.png");
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let img = GrayImage::from_fn(1000, 1000, |_, _| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        Luma([if state & 1 == 0 { 0 } else { 255 }])
    });
    img.save(&input).unwrap();
    let out = dir.join("noise.svg");
    let mut child = bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(400));
    let sent = std::time::Instant::now();
    let status = interrupt(&mut child, "INT");
    let waited = sent.elapsed();
    assert_eq!(status.code(), Some(130));
    assert!(waited < std::time::Duration::from_secs(1), "{waited:?}");
    assert!(!out.exists());
}

/// A `width`×`height` image of 2×2 specks, one every 4 px: one contour of four segments
/// per speck.
fn specks(width: u32, height: u32) -> GrayImage {
    GrayImage::from_fn(width, height, |x, y| {
        let on = (1..width - 2).contains(&x) && (1..height - 2).contains(&y);
        Luma([if on && (x - 1) % 4 < 2 && (y - 1) % 4 < 2 {
            0
        } else {
            255
        }])
    })
}

#[test]
fn report_grows_linearly_and_modestly_with_the_contour_count() {
    let dir = scratch("specks");
    let mut sizes = Vec::new();
    for (w, h) in [(200u32, 100u32), (200, 200)] {
        let input = dir.join(format!("s{w}x{h}.png"));
        specks(w, h).save(&input).unwrap();
        let report = dir.join(format!("s{w}x{h}.json"));
        let (code, _, err) = run(bin()
            .arg("trace")
            .arg(&input)
            .arg("-o")
            .arg(dir.join(format!("s{w}x{h}.svg")))
            .arg("--report")
            .arg(&report));
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(&report).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let segments = json["images"][0]["summary"]["segments"].as_u64().unwrap();
        let contours = json["images"][0]["contours"].as_array().unwrap().len();
        assert_eq!(contours as u32, (w / 4) * (h / 4) - (w / 4 + h / 4) + 1);
        // Each segment is one line, not one line per number.
        let rows = text
            .lines()
            .filter(|l| l.contains("\"control_points\""))
            .count();
        assert_eq!(rows as u64, segments);
        let per_segment = text.len() as f64 / segments as f64;
        assert!(per_segment < 700.0, "{per_segment} bytes per segment");
        sizes.push((text.len() as f64, segments as f64));
    }
    // Twice the segments, at most twice the bytes (plus the fixed header).
    let (small, large) = (sizes[0], sizes[1]);
    assert!(large.1 > 1.9 * small.1);
    assert!(large.0 / small.0 <= large.1 / small.1 * 1.01, "{sizes:?}");
}

#[test]
fn messages_say_what_happened() {
    let dir = scratch("messages");
    let dots = dir.join("dots.png");
    let mut img = GrayImage::from_pixel(50, 50, Luma([255]));
    img.put_pixel(10, 10, Luma([0]));
    img.put_pixel(30, 30, Luma([0]));
    img.save(&dots).unwrap();
    let blank = dir.join("blank.png");
    GrayImage::from_pixel(50, 50, Luma([255]))
        .save(&blank)
        .unwrap();
    let out = dir.join("out.svg");
    let trace = |input: &Path, extra: &[&str]| {
        run(bin()
            .arg("trace")
            .arg(input)
            .arg("-o")
            .arg(&out)
            .args(extra))
    };
    let (code, _, err) = trace(&dots, &[]);
    assert_eq!(code, 1);
    assert!(
        err.contains("all 2 shapes are smaller than the minimum area of 2 px²"),
        "{err}"
    );
    let (code, _, err) = trace(&dots, &["--min-area", "0.5"]);
    assert_eq!(code, 0, "{err}");
    std::fs::remove_file(&out).unwrap();
    let (code, _, err) = trace(&blank, &[]);
    assert_eq!(code, 1);
    // It says what would count as a shape, not "background (luminance below …)", which
    // reads as the opposite.
    assert!(
        err.contains("no pixel has luminance below ")
            && err.contains(", so every pixel is background"),
        "{err}"
    );
    // Negative values reach the range checks instead of being taken for options.
    for (args, status, expect) in [
        (["--tolerance", "-1"], 1, "--tolerance"),
        (["--min-area", "-2"], 1, "--min-area"),
        (["--budget", "-5"], 2, "must be 0 or more"),
        (["--threshold", "300"], 2, "must be at most 255"),
        (["--seed", "1.5"], 2, "must be a whole number"),
    ] {
        let (code, _, err) = trace(&dots, &args);
        assert_eq!(code, status, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!err.contains("unexpected argument"), "{err}");
    }
    assert!(!out.exists());
    for command in ["trace", "batch"] {
        let (code, help, _) = run(bin().arg(command).arg("--help"));
        assert_eq!(code, 0);
        assert!(
            help.contains("Exit status:") && help.contains("130"),
            "{help}"
        );
    }
}

#[test]
fn one_transparent_pixel_does_not_switch_to_alpha() {
    let dir = scratch("alpha");
    // The bar of `bar()` in an opaque RGBA image with one transparent corner pixel.
    let grey = bar();
    let img = image::RgbaImage::from_fn(grey.width(), grey.height(), |x, y| {
        let v = grey.get_pixel(x, y)[0];
        image::Rgba([v, v, v, if (x, y) == (0, 0) { 0 } else { 255 }])
    });
    let input = dir.join("one.png");
    img.save(&input).unwrap();
    let svg = dir.join("one.svg");
    let report = dir.join("one.json");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&svg)
        .arg("--report")
        .arg(&report));
    assert_eq!(code, 0, "{err}");
    let b = path_box(&std::fs::read_to_string(&svg).unwrap());
    assert!(
        (b[0] - 10.0).abs() < 0.01 && (b[2] - 40.0).abs() < 0.01,
        "{b:?}"
    );
    assert!(
        (b[1] - 5.0).abs() < 0.01 && (b[3] - 15.0).abs() < 0.01,
        "{b:?}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["images"][0]["image"]["from_alpha"], false);
    // --alpha traces the opaque rectangle instead.
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&input)
        .arg("-o")
        .arg(&svg)
        .arg("--alpha"));
    assert_eq!(code, 0, "{err}");
    let b = path_box(&std::fs::read_to_string(&svg).unwrap());
    assert!(b[2] - b[0] > 59.0 && b[3] - b[1] > 39.0, "{b:?}");
}

/// A 60×40 image with a dark 15×15 square at (20, 20): the second frame of the animations.
fn square() -> GrayImage {
    GrayImage::from_fn(60, 40, |x, y| {
        let on = (20..35).contains(&x) && (20..35).contains(&y);
        Luma([if on { 0 } else { 255 }])
    })
}

#[test]
fn frames_and_pages_are_chosen_and_named() {
    use image::codecs::gif::GifEncoder;
    use image::{DynamicImage, Frame};
    let dir = scratch("frames");
    // An animated GIF and a two-page TIFF: the bar, then the square.
    let gif = dir.join("anim.gif");
    {
        let mut enc = GifEncoder::new(std::fs::File::create(&gif).unwrap());
        for img in [bar(), square()] {
            let rgba = DynamicImage::ImageLuma8(img).to_rgba8();
            enc.encode_frame(Frame::new(rgba)).unwrap();
        }
    }
    let tif = dir.join("pages.tif");
    {
        let mut enc =
            tiff::encoder::TiffEncoder::new(std::fs::File::create(&tif).unwrap()).unwrap();
        for img in [bar(), square()] {
            enc.write_image::<tiff::encoder::colortype::Gray8>(60, 40, img.as_raw())
                .unwrap();
        }
    }
    let svg = dir.join("out.svg");
    for input in [&gif, &tif] {
        let trace = |frame: &str| {
            run(bin()
                .arg("trace")
                .arg(input)
                .arg("-o")
                .arg(&svg)
                .args(["--frame", frame]))
        };
        let (code, _, err) = trace("0");
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("traced frame 0 of 2"), "{err}");
        let b = path_box(&std::fs::read_to_string(&svg).unwrap());
        assert!(
            (b[0] - 10.0).abs() < 0.01 && (b[2] - 40.0).abs() < 0.01,
            "{b:?}"
        );
        let (code, _, err) = trace("1");
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("traced frame 1 of 2"), "{err}");
        let b = path_box(&std::fs::read_to_string(&svg).unwrap());
        assert!(
            (b[0] - 20.0).abs() < 0.01 && (b[3] - 35.0).abs() < 0.01,
            "{b:?}"
        );
        std::fs::remove_file(&svg).unwrap();
        let (code, _, err) = trace("2");
        assert_eq!(code, 1);
        assert!(err.contains("the file has 2 frames"), "{err}");
        assert!(!svg.exists());
    }
    // A still image has one frame and no note.
    let png = dir.join("still.png");
    bar().save(&png).unwrap();
    let (code, _, err) = run(bin().arg("trace").arg(&png).arg("-o").arg(&svg));
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("frame"), "{err}");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&png)
        .arg("-o")
        .arg(dir.join("x.svg"))
        .args(["--frame", "1"]));
    assert_eq!(code, 1);
    assert!(err.contains("the file has 1 frame "), "{err}");
}

#[test]
fn float_tiff_is_traced_and_unsupported_samples_are_named() {
    let dir = scratch("float");
    let tif = dir.join("float.tif");
    let values: Vec<f32> = bar().pixels().map(|p| f32::from(p[0]) / 255.0).collect();
    tiff::encoder::TiffEncoder::new(std::fs::File::create(&tif).unwrap())
        .unwrap()
        .write_image::<tiff::encoder::colortype::Gray32Float>(60, 40, &values)
        .unwrap();
    let svg = dir.join("float.svg");
    let (code, _, err) = run(bin().arg("trace").arg(&tif).arg("-o").arg(&svg));
    assert_eq!(code, 0, "{err}");
    let b = path_box(&std::fs::read_to_string(&svg).unwrap());
    assert!(
        (b[0] - 10.0).abs() < 0.01 && (b[3] - 15.0).abs() < 0.01,
        "{b:?}"
    );
    // Signed integers: one line that says what the file has and what is read.
    let signed = dir.join("signed.tif");
    let ints: Vec<i32> = bar().pixels().map(|p| i32::from(p[0])).collect();
    tiff::encoder::TiffEncoder::new(std::fs::File::create(&signed).unwrap())
        .unwrap()
        .write_image::<tiff::encoder::colortype::GrayI32>(60, 40, &ints)
        .unwrap();
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&signed)
        .arg("-o")
        .arg(dir.join("signed.svg")));
    assert_eq!(code, 1);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("signed integer samples") && err.contains("outlinefit reads"),
        "{err}"
    );
}

/// A PNG whose header claims `width`×`height` grey pixels, with one tiny IDAT chunk: enough
/// for a decoder to read the size, not to decode the pixels.
fn png_header_only(width: u32, height: u32) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        png.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        png.extend(&body);
        png.extend(crc32(&body).to_be_bytes());
    };
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]);
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01]);
    chunk(b"IEND", &[]);
    png
}

#[cfg(target_os = "linux")]
#[test]
fn an_image_beyond_memory_is_refused_before_allocating() {
    let dir = scratch("memory");
    // 10 000 000 000 pixels: about 50 GB to trace, more than this machine or CI has.
    let huge = dir.join("huge.png");
    std::fs::write(&huge, png_header_only(100_000, 100_000)).unwrap();
    let svg = dir.join("huge.svg");
    let (code, _, err) = run(bin().arg("trace").arg(&huge).arg("-o").arg(&svg));
    assert_eq!(code, 1);
    assert!(err.contains("--max-pixels"), "{err}");
    let (code, _, err) = run(bin()
        .arg("trace")
        .arg(&huge)
        .arg("-o")
        .arg(&svg)
        .args(["--max-pixels", "20000000000"]));
    assert_eq!(code, 1, "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("needs about") && err.contains("MB are available"),
        "{err}"
    );
    assert!(!svg.exists());
}
