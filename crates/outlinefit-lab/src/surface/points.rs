//! Reading point clouds: one point per line, `x y z` separated by spaces, tabs, commas or
//! semicolons (so both whitespace XYZ files and CSV read). Empty lines and lines starting
//! with `#` are skipped, and so is a first line that is not three numbers (a CSV header).

use super::P3;
use crate::Error;
use std::path::Path;

/// Parses points from `text`; `what` names the source in errors.
pub fn parse(text: &str, what: &str) -> Result<Vec<P3>, Error> {
    let invalid = |message: String| Error::InvalidInput {
        what: what.to_string(),
        message,
    };
    let mut points = Vec::new();
    let mut first = true;
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        let header = first && numbers.iter().any(Option::is_none);
        first = false;
        if header {
            continue;
        }
        let line_no = index + 1;
        if fields.len() != 3 {
            return Err(invalid(format!(
                "line {line_no} has {} values; each point needs exactly three (x y z)",
                fields.len()
            )));
        }
        let mut p = [0.0; 3];
        for (k, (field, number)) in fields.iter().zip(&numbers).enumerate() {
            match number {
                Some(v) if v.is_finite() => p[k] = *v,
                Some(_) => {
                    return Err(invalid(format!(
                        "line {line_no}: '{field}' is not a finite number"
                    )))
                }
                None => {
                    return Err(invalid(format!(
                        "line {line_no}: '{field}' is not a number"
                    )))
                }
            }
        }
        points.push(p);
    }
    if points.is_empty() {
        return Err(invalid("no points (expected one 'x y z' per line)".into()));
    }
    Ok(points)
}

/// Reads points from a file, or from standard input for `-`.
pub fn read(path: &Path) -> Result<Vec<P3>, Error> {
    let text = if path.as_os_str() == "-" {
        std::io::read_to_string(std::io::stdin().lock())
    } else {
        std::fs::read_to_string(path)
    }
    .map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse(&text, &path.display().to_string())
}

/// Writes points as `x y z` lines with every digit of each double.
pub fn to_xyz(points: &[P3]) -> String {
    let mut out = String::with_capacity(points.len() * 60);
    for p in points {
        out.push_str(&format!("{} {} {}\n", p[0], p[1], p[2]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_csv_with_header_and_whitespace_xyz() {
        let csv = "x,y,z\n1,2,3\n# comment\n\n4.5, -6e-1 ,7\n";
        assert_eq!(
            parse(csv, "a").unwrap(),
            vec![[1.0, 2.0, 3.0], [4.5, -0.6, 7.0]]
        );
        let xyz = "1 2 3\n\t4 5\t6\n";
        assert_eq!(
            parse(xyz, "b").unwrap(),
            vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]
        );
    }

    #[test]
    fn refuses_bad_lines_with_their_number() {
        let e = parse("1 2 3\n1 2\n", "f").unwrap_err().to_string();
        assert_eq!(
            e,
            "f: line 2 has 2 values; each point needs exactly three (x y z)"
        );
        let e = parse("1 2 3\n1 nan 3\n", "f").unwrap_err().to_string();
        assert_eq!(e, "f: line 2: 'nan' is not a finite number");
        let e = parse("1 2 3\n1 x 3\n", "f").unwrap_err().to_string();
        assert_eq!(e, "f: line 2: 'x' is not a number");
        let e = parse("\n# nothing\n", "f").unwrap_err().to_string();
        assert_eq!(e, "f: no points (expected one 'x y z' per line)");
    }
}
