//! The envelope of a disk curve: the two curves that the family of circles
//! `(C(t), R(t))` touches,
//! `E±(t) = C − (R R' / |C'|²) C' ± (R √(|C'|² − R'²) / |C'|²) C'⊥`. Where `|R'| ≥ |C'|` a
//! disk contains its neighbours and the envelope has no point there.

use super::disk::DiskWangBall;
use crate::geom::Point;

/// The two envelope curves of a disk curve, sampled (`None` where no envelope point exists).
pub fn envelope(curve: &DiskWangBall, samples: usize) -> Vec<Option<(Point, Point)>> {
    (0..=samples)
        .map(|i| {
            let t = i as f64 / samples as f64;
            let d = curve.eval(t);
            let dc = curve.center_derivative(t);
            let dr = curve.radius_derivative(t);
            envelope_points(d.center, d.radius, dc, dr)
        })
        .collect()
}

/// The closed polygon of the envelope band: the `+` side forwards, then the `−` side
/// backwards, over the samples where both exist. `None` when fewer than two samples have
/// envelope points or some point is not finite.
pub fn envelope_band(curve: &DiskWangBall, samples: usize) -> Option<Vec<Point>> {
    let env: Vec<(Point, Point)> = envelope(curve, samples).into_iter().flatten().collect();
    let band: Vec<Point> = env
        .iter()
        .map(|e| e.0)
        .chain(env.iter().rev().map(|e| e.1))
        .collect();
    (env.len() >= 2 && band.iter().all(|p| p.is_finite())).then_some(band)
}

/// The two envelope points of the circle family at one parameter.
pub fn envelope_points(c: Point, r: f64, dc: Point, dr: f64) -> Option<(Point, Point)> {
    let s = dc.length_squared();
    if s.is_nan() || s <= 0.0 || dr * dr >= s {
        return None;
    }
    let along = c - dc * (r * dr / s);
    let across = dc.perp() * (r * (s - dr * dr).sqrt() / s);
    Some((along + across, along - across))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::wang_ball::Disk;

    #[test]
    fn envelope_of_a_constant_radius_line_is_its_offset() {
        let c = DiskWangBall::new(vec![
            Disk::new(Point::new(0.0, 0.0), 0.5),
            Disk::new(Point::new(4.0, 0.0), 0.5),
        ]);
        for e in envelope(&c, 10) {
            let (a, b) = e.unwrap();
            assert!((a.y.abs() - 0.5).abs() < 1e-12 && (b.y.abs() - 0.5).abs() < 1e-12);
            assert!((a.y + b.y).abs() < 1e-12);
        }
    }

    #[test]
    fn envelope_points_touch_their_circle_and_the_next_one() {
        // On a growing-radius line each envelope point is on its circle, and (first order)
        // on the neighbouring circle too.
        let c = DiskWangBall::new(vec![
            Disk::new(Point::new(0.0, 0.0), 0.2),
            Disk::new(Point::new(1.0, 2.0), 0.6),
            Disk::new(Point::new(3.0, 1.0), 0.4),
        ]);
        let t = 0.37;
        let h = 1e-6;
        let (a, _) = envelope(&c, 1000)[370].unwrap();
        let d = c.eval(t);
        assert!((a.distance(d.center) - d.radius).abs() < 1e-12);
        let e = c.eval(t + h);
        assert!((a.distance(e.center) - e.radius).abs() < 1e-9);
    }
}
