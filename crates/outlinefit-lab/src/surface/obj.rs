//! A fitted surface as a Wavefront OBJ mesh (vertices, texture coordinates = the surface
//! parameters, quads), which Blender, MeshLab and most 3-D tools open.

use super::BezierSurface;
use std::fmt::Write as _;

/// The surface sampled on `res` × `res` parameters (at least 2) as OBJ text; `comment`
/// lines go in the header.
pub fn to_obj(surface: &BezierSurface, res: usize, comment: &[String]) -> String {
    let res = res.max(2);
    let mesh = surface.mesh(res);
    let mut out = String::with_capacity(mesh.len() * 80);
    for line in comment {
        let _ = writeln!(out, "# {line}");
    }
    let _ = writeln!(
        out,
        "# Bézier surface of degree ({}, {}) sampled on {res} × {res} parameters",
        surface.degree_u, surface.degree_v
    );
    out.push_str("o bezier_surface\n");
    for p in &mesh {
        let _ = writeln!(out, "v {} {} {}", p[0], p[1], p[2]);
    }
    let step = 1.0 / (res - 1) as f64;
    for a in 0..res {
        for b in 0..res {
            let _ = writeln!(out, "vt {} {}", a as f64 * step, b as f64 * step);
        }
    }
    // Vertex (a, b) is number a·res + b + 1; each quad is counter-clockwise in (u, v).
    for a in 0..res - 1 {
        for b in 0..res - 1 {
            let k = |a: usize, b: usize| a * res + b + 1;
            let (p, q, r, s) = (k(a, b), k(a + 1, b), k(a + 1, b + 1), k(a, b + 1));
            let _ = writeln!(out, "f {p}/{p} {q}/{q} {r}/{r} {s}/{s}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_has_every_vertex_once_and_quads_between_them() {
        let s = BezierSurface {
            degree_u: 1,
            degree_v: 1,
            poles: vec![
                [0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 1.0],
            ],
        };
        let obj = to_obj(&s, 3, &["test".into()]);
        let v: Vec<&str> = obj.lines().filter(|l| l.starts_with("v ")).collect();
        let f: Vec<&str> = obj.lines().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(v.len(), 9);
        assert_eq!(f.len(), 4);
        // The bilinear patch's centre vertex (5th) is S(½, ½) = (0.5, 0.5, 0.25).
        assert_eq!(v[4], "v 0.5 0.5 0.25");
        assert_eq!(f[0], "f 1/1 4/4 5/5 2/2");
        assert!(obj.starts_with("# test\n"));
    }
}
