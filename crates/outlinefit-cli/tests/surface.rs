//! `outlinefit surface` through the binary: the three outputs, an exact grid recovered from
//! a points file, and one clear line for each kind of bad input.

mod common;
use common::{bin, scratch};
use std::fs;

fn run(args: &[&str]) -> (i32, String, String) {
    let out = bin().arg("surface").args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn an_exact_grid_from_a_file_is_recovered_and_written_three_ways() {
    // z = x² y on a 9 × 8 grid with uneven columns: a degree (2, 1) polynomial surface whose
    // x and y are linear in the parameters, so the fit is exact.
    let dir = scratch("exact");
    let xs = [0.0, 0.1, 0.25, 0.3, 0.5, 0.55, 0.7, 0.9, 1.0];
    let ys = [0.0, 0.2, 0.3, 0.45, 0.6, 0.8, 0.85, 1.0];
    let mut text = String::from("x,y,z\n");
    for x in xs {
        for y in ys {
            text.push_str(&format!("{x},{y},{}\n", x * x * y));
        }
    }
    let input = dir.join("grid.csv");
    fs::write(&input, &text).unwrap();
    let (code, _, err) = run(&[
        input.to_str().unwrap(),
        "--grid",
        "9x8",
        "--degree",
        "2,1",
        "--mesh-res",
        "5",
    ]);
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("grid.json")).unwrap()).unwrap();
    let y = json["fit"]["error"].as_f64().unwrap();
    assert!(y < 1e-20, "Y = {y:e}");
    // The row parameters are the x values (x is linear in τ, pinned at 0 and 1).
    let tau: Vec<f64> = json["fit"]["params"]["tau"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for (t, x) in tau.iter().zip(xs) {
        assert!((t - x).abs() < 1e-9, "{tau:?}");
    }
    let obj = fs::read_to_string(dir.join("grid.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 25);
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 16);
    let svg = fs::read_to_string(dir.join("grid.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.matches("<circle").count() >= 72);
}

#[test]
fn an_example_is_reproducible_and_correction_beats_centripetal() {
    let dir = scratch("example");
    let y = |method: &str| {
        let out = dir.join(method);
        let (code, _, err) = run(&[
            "--example",
            "I",
            "--param",
            method,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let json: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(out.with_extension("json")).unwrap()).unwrap();
        assert_eq!(json["points"], 841);
        json["fit"]["error"].as_f64().unwrap()
    };
    let (corrected, centripetal) = (y("correct"), y("centripetal"));
    assert!(
        corrected < 0.9 * centripetal,
        "{corrected} vs {centripetal}"
    );
    assert_eq!(y("correct"), corrected);
}

#[test]
fn bad_input_gets_one_line_and_no_output() {
    let dir = scratch("bad");
    let cases: &[(&str, &[&str], &str)] = &[
        ("", &[], "no points (expected one 'x y z' per line)"),
        (
            "1 2 3\n1 2\n",
            &[],
            "line 2 has 2 values; each point needs exactly three (x y z)",
        ),
        (
            "1 2 3\n1 NaN 3\n",
            &[],
            "line 2: 'NaN' is not a finite number",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n",
            &["--grid", "2x2"],
            "a 2×2 grid needs 4 points, got 3",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n1 1 1\n",
            &["--grid", "2x2"],
            "a 2×2 grid is too small for degree (5, 5)",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n1 1 1\n",
            &[],
            "4 points are too few for degree (5, 5), which has 36 poles",
        ),
    ];
    for (k, (text, extra, message)) in cases.iter().enumerate() {
        let input = dir.join(format!("p{k}.xyz"));
        fs::write(&input, text).unwrap();
        let mut args = vec![input.to_str().unwrap()];
        args.extend_from_slice(extra);
        let (code, _, err) = run(&args);
        assert_eq!(code, 1, "case {k}: {err}");
        assert_eq!(err.lines().count(), 1, "case {k}: {err}");
        assert!(err.contains(message), "case {k}: {err}");
        assert!(!dir.join(format!("p{k}.json")).exists());
    }
    let (code, _, err) = run(&["--example", "I", "-o", "-"]);
    assert_eq!(code, 1);
    assert!(err.contains("-o needs a file name"), "{err}");
    let (code, _, err) = run(&["--example", "IV"]);
    assert_eq!(code, 2, "{err}");
}
