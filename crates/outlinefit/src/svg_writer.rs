//! The one SVG writer every picture goes through: the traced outline, the diagnostic
//! overlay, the merged-curve pictures, the degree-reduction picture and the B-spline
//! conversion picture.
//!
//! The document itself (elements, attributes, their order and escaping, text and comments)
//! is built with the [`svg`] crate. Numbers and path data are formatted here, because the
//! crate's path numbers are `f32` (about 7 significant digits: too coarse for a large image
//! at the precision a small tolerance needs) and because the outline wants a compact,
//! drift-free relative syntax. One number format serves every picture: fixed decimals,
//! trailing zeros trimmed, never `-0` (`push_number`), so equal inputs give equal bytes.
//!
//! As the [`svg`] crate writes them, attributes come in alphabetical order, each child
//! element on its own line, and the document ends with a newline.

use crate::geom::Point;
use std::fmt;
use svg::node::element::{Element, SVG};
use svg::node::Value;
use svg::Node as _;

pub(crate) use svg::node::element::{Circle, Group, Image, Path, Rectangle};
pub(crate) use svg::node::Comment;

/// Largest number of decimals written; more would only print floating-point noise.
pub const MAX_PRECISION: usize = 12;

/// An SVG document under construction.
pub struct Document {
    root: SVG,
}

impl Document {
    /// A document shown at `width` × `height` (display units, written as integers when they
    /// are whole) with the user coordinates `view_box` = (x, y, width, height), written with
    /// `precision` decimals.
    pub fn new(width: f64, height: f64, view_box: [f64; 4], precision: usize) -> Self {
        let n = |x: f64| number(x, precision);
        let view_box = format!(
            "{} {} {} {}",
            n(view_box[0]),
            n(view_box[1]),
            n(view_box[2]),
            n(view_box[3])
        );
        Document {
            root: SVG::new()
                .set("width", n(width))
                .set("height", n(height))
                .set("viewBox", view_box),
        }
    }

    /// Sets an attribute of the root element.
    pub fn set(mut self, name: &str, value: impl Into<svg::node::Value>) -> Self {
        self.root.assign(name, value);
        self
    }

    /// Appends a child of the root element.
    pub fn add(&mut self, node: impl Into<Box<dyn svg::Node>>) {
        self.root.append(node);
    }

    /// Appends an XML comment (see [`comment`]).
    pub(crate) fn comment(&mut self, text: &str) {
        self.add(comment(text));
    }

    /// The document's text, ending with a newline.
    pub fn finish(self) -> String {
        let mut out = self.root.to_string();
        out.push('\n');
        out
    }
}

/// A `<text>` element with its content inline (`<text x="1">label</text>`; the crate's own
/// text element puts the content on a line of its own).
#[derive(Clone, Debug)]
pub struct Text(Element);

impl Text {
    /// A text element holding `content` (escaped when written).
    pub fn new(content: impl Into<String>) -> Self {
        let mut element = Element::new("text");
        element.append(svg::node::Text::new(content));
        Text(element)
    }

    /// Sets an attribute.
    pub fn set(mut self, name: &str, value: impl Into<Value>) -> Self {
        self.0.assign(name, value);
        self
    }
}

impl fmt::Display for Text {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The plain form writes a text child inline.
        write!(f, "{}", self.0)
    }
}

impl svg::Node for Text {
    fn get_name(&self) -> &str {
        self.0.get_name()
    }
}

impl svg::node::NodeDefaultHash for Text {
    fn default_hash(&self, state: &mut std::collections::hash_map::DefaultHasher) {
        self.0.default_hash(state);
    }
}

/// An XML comment with `text`, made safe (no `--` inside).
pub(crate) fn comment(text: &str) -> Comment {
    Comment::new(text.replace("--", "- -"))
}

/// The fewest decimals (at most [`MAX_PRECISION`]) whose unit is at most `unit`, so that
/// rounding (half a unit of the last decimal) moves a number by at most `unit / 2`.
/// Non-positive or non-finite units give [`MAX_PRECISION`].
pub fn decimals_for(unit: f64) -> usize {
    (0..MAX_PRECISION)
        .find(|&p| 10f64.powi(-(p as i32)) <= unit * (1.0 + 1e-9))
        .unwrap_or(MAX_PRECISION)
}

/// `x` with `push_number`'s format.
pub fn number(x: f64, precision: usize) -> String {
    let mut s = String::new();
    push_number(&mut s, x, precision);
    s
}

/// Appends `x` rounded to `precision` decimals (at most [`MAX_PRECISION`]), with trailing
/// zeros and a trailing point trimmed and `-0` written as `0`: `12.5`, `3`, `-0.001`.
/// Non-finite values, which callers filter out beforehand, are written as `0` so that the
/// document stays valid.
pub(crate) fn push_number(out: &mut String, x: f64, precision: usize) {
    if !x.is_finite() {
        out.push('0');
        return;
    }
    let s = format!("{:.*}", precision.min(MAX_PRECISION), x);
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s.as_str()
    };
    out.push_str(if s == "-0" { "0" } else { s });
}

/// `x y` with [`push_number`].
pub(crate) fn push_point(out: &mut String, p: Point, precision: usize) {
    push_number(out, p.x, precision);
    out.push(' ');
    push_number(out, p.y, precision);
}

/// The `points` attribute of a `<polyline>`: `x,y x,y …`, non-finite points left out.
pub fn points_attribute(points: &[Point], precision: usize) -> String {
    let mut out = String::new();
    for p in points.iter().filter(|p| p.is_finite()) {
        if !out.is_empty() {
            out.push(' ');
        }
        push_number(&mut out, p.x, precision);
        out.push(',');
        push_number(&mut out, p.y, precision);
    }
    out
}

/// Path data in absolute coordinates: `M x y`, `L x y x y …` (the letter written once per
/// run), `Z`.
pub struct PathData {
    out: String,
    precision: usize,
    last: char,
}

impl PathData {
    /// Empty path data whose numbers get `precision` decimals.
    pub fn new(precision: usize) -> Self {
        PathData {
            out: String::new(),
            precision,
            last: ' ',
        }
    }

    fn point(&mut self, letter: char, p: Point) {
        if letter != self.last {
            self.out.push(letter);
            self.last = letter;
        } else {
            self.out.push(' ');
        }
        push_point(&mut self.out, p, self.precision);
    }

    /// Starts a subpath at `p`.
    pub fn move_to(&mut self, p: Point) {
        self.last = ' ';
        self.point('M', p);
    }

    /// A straight line to `p`.
    pub fn line_to(&mut self, p: Point) {
        self.point('L', p);
    }

    /// A polyline through `points` (the first one starts a subpath).
    pub fn polyline(&mut self, points: impl IntoIterator<Item = Point>) {
        for (k, p) in points.into_iter().enumerate() {
            if k == 0 {
                self.move_to(p);
            } else {
                self.line_to(p);
            }
        }
    }

    /// A zero-length stroke at `p` (`M x y h0`), which a round cap draws as a dot.
    pub fn dot(&mut self, p: Point) {
        self.move_to(p);
        self.out.push_str("h0");
        self.last = 'h';
    }

    /// Closes the current subpath.
    pub fn close(&mut self) {
        self.out.push('Z');
        self.last = 'Z';
    }

    /// True when nothing has been written.
    pub fn is_empty(&self) -> bool {
        self.out.is_empty()
    }

    /// The `d` attribute.
    pub fn finish(self) -> String {
        self.out
    }
}

/// Room for the decimal digits of any u128 (39) with up to [`MAX_PRECISION`] + 1 zeros in
/// front.
const DIGITS: usize = 56;

/// Writes the decimal digits of `v`, at least `min` of them (zeros in front), at the end
/// of `buf`; returns how many.
fn write_digits(mut v: u128, min: usize, buf: &mut [u8; DIGITS]) -> usize {
    let mut len = 0;
    // u64 arithmetic once the value fits: u128 division is a library call.
    while v > u128::from(u64::MAX) {
        len += 1;
        buf[DIGITS - len] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    let mut v = v as u64;
    while v > 0 || len < min {
        len += 1;
        buf[DIGITS - len] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    len
}

/// Grid units per picture unit on the grid of `precision` decimals (at most
/// [`MAX_PRECISION`]): 10^precision. A document whose path data is written in grid units
/// ([`PathUnits::Grid`]) scales its `viewBox` by this.
pub(crate) fn grid_per_unit(precision: usize) -> f64 {
    10f64.powi(precision.min(MAX_PRECISION) as i32)
}

/// How compact path data writes its numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PathUnits {
    /// In the picture's units, with the grid's decimals: `12.34` on the grid of 2.
    Picture,
    /// In grid units, as whole numbers: `1234` for 12.34 on the grid of 2 decimals, one
    /// character shorter per number. The document's `viewBox` must be given in grid units
    /// too (10^precision times the picture's), as potrace's scaled coordinates are.
    Grid,
}

/// Path data on the grid of a fixed number of decimals, written compactly (as potrace and
/// SVG optimisers do): points are given in grid units (`10^-precision`), commands are
/// relative, a command letter is not repeated for consecutive commands of the same kind,
/// a number's leading `0` is dropped (`.5`), and no separator is written before a minus
/// sign or before a `.` that follows a number with a `.`.
pub(crate) struct CompactPath {
    out: String,
    /// Grid units per picture unit: 10^precision.
    scale: f64,
    /// Decimals written: the grid's in picture units, none in grid units.
    decimals: usize,
    /// The last command letter written.
    last_command: char,
    /// Whether the last thing written is a number containing a `.` (a following `.5`
    /// then needs no separator), a number without one, or a command letter.
    last: Last,
}

#[derive(Clone, Copy, PartialEq)]
enum Last {
    Command,
    Integer,
    Decimal,
}

impl CompactPath {
    /// Empty path data on the grid of `precision` decimals (at most [`MAX_PRECISION`]),
    /// its numbers written in `units`.
    pub(crate) fn new(precision: usize, units: PathUnits) -> CompactPath {
        let precision = precision.min(MAX_PRECISION);
        CompactPath {
            out: String::new(),
            scale: grid_per_unit(precision),
            decimals: match units {
                PathUnits::Picture => precision,
                PathUnits::Grid => 0,
            },
            last_command: ' ',
            last: Last::Command,
        }
    }

    /// Half a grid unit, in picture units: the most rounding moves a coordinate.
    pub(crate) fn half_unit(&self) -> f64 {
        0.5 / self.scale
    }

    /// `p` in grid units.
    pub(crate) fn grid(&self, p: Point) -> (i128, i128) {
        (
            (p.x * self.scale).round() as i128,
            (p.y * self.scale).round() as i128,
        )
    }

    /// Writes `letter` unless it repeats the last command (SVG repeats it implicitly).
    pub(crate) fn command(&mut self, letter: char) {
        if letter != self.last_command {
            self.out.push(letter);
            self.last_command = letter;
            self.last = Last::Command;
        }
    }

    /// A relative line from `from` to `to` (grid units): `h` or `v` when axis-parallel.
    pub(crate) fn line(&mut self, from: (i128, i128), to: (i128, i128)) {
        let (dx, dy) = (to.0 - from.0, to.1 - from.1);
        if dy == 0 {
            self.command('h');
            self.number(dx);
        } else if dx == 0 {
            self.command('v');
            self.number(dy);
        } else {
            self.command('l');
            self.number(dx);
            self.number(dy);
        }
    }

    /// Writes `units` grid units: as a decimal number in picture units, or as itself.
    /// Without allocating: a page of text writes a quarter of a million numbers.
    pub(crate) fn number(&mut self, units: i128) {
        let p = self.decimals;
        // The magnitude's digits, at least p + 1 of them (zeros in front).
        let mut buf = [b'0'; DIGITS];
        let len = write_digits(units.unsigned_abs(), p + 1, &mut buf);
        let digits = &buf[DIGITS - len..];
        let (int, frac) = digits.split_at(len - p);
        let frac = &frac[..frac.iter().rposition(|&d| d != b'0').map_or(0, |k| k + 1)];
        // `0.5` as `.5`.
        let with_int = int != b"0" || frac.is_empty();
        let separator = match self.last {
            Last::Command => false,
            _ if units < 0 => false,
            Last::Decimal => with_int,
            Last::Integer => true,
        };
        if separator {
            self.out.push(' ');
        }
        if units < 0 {
            self.out.push('-');
        }
        if with_int {
            self.out.extend(int.iter().map(|&b| char::from(b)));
        }
        if frac.is_empty() {
            self.last = Last::Integer;
        } else {
            self.out.push('.');
            self.out.extend(frac.iter().map(|&b| char::from(b)));
            self.last = Last::Decimal;
        }
    }

    /// The `d` attribute.
    pub(crate) fn finish(self) -> String {
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_exact_and_never_negative_zero() {
        let f = number;
        assert_eq!(f(12.5, 3), "12.5");
        assert_eq!(f(12.0, 3), "12");
        assert_eq!(f(100.0, 3), "100");
        assert_eq!(f(0.0, 3), "0");
        assert_eq!(f(-0.0, 3), "0");
        assert_eq!(f(-0.0004, 3), "0");
        assert_eq!(f(-0.0006, 3), "-0.001");
        assert_eq!(f(1.23456, 3), "1.235");
        assert_eq!(f(1.23456, 1), "1.2");
        assert_eq!(f(7.6, 0), "8");
        assert_eq!(f(1.0 / 3.0, 40), "0.333333333333");
        assert_eq!(f(f64::NAN, 3), "0");
        assert_eq!(f(1e6 + 0.25, 3), "1000000.25");
    }

    #[test]
    fn decimals_for_a_unit_are_the_fewest_that_reach_it() {
        assert_eq!(decimals_for(0.02), 2);
        assert_eq!(decimals_for(0.01), 2);
        assert_eq!(decimals_for(0.005), 3);
        assert_eq!(decimals_for(1.0), 0);
        assert_eq!(decimals_for(0.0), MAX_PRECISION);
        assert_eq!(decimals_for(f64::NAN), MAX_PRECISION);
    }

    /// The path's numbers are what formatting each through a string gives (the way they
    /// were first written): sign, zeros, the dropped leading `0` and the separators, for
    /// magnitudes up to the largest i128 and every number of decimals.
    #[test]
    fn compact_numbers_match_formatting_through_strings() {
        fn reference(units: i128, p: usize, last: &mut Last, out: &mut String) {
            let digits = format!("{:0width$}", units.unsigned_abs(), width = p + 1);
            let (int, frac) = digits.split_at(digits.len() - p);
            let frac = frac.trim_end_matches('0');
            let mut text = String::new();
            if units < 0 {
                text.push('-');
            }
            if int != "0" || frac.is_empty() {
                text.push_str(int);
            }
            if !frac.is_empty() {
                text.push('.');
                text.push_str(frac);
            }
            let separator = match *last {
                Last::Command => false,
                _ if text.starts_with('-') => false,
                Last::Decimal => !text.starts_with('.'),
                Last::Integer => true,
            };
            if separator {
                out.push(' ');
            }
            *last = if text.contains('.') {
                Last::Decimal
            } else {
                Last::Integer
            };
            out.push_str(&text);
        }
        let mut values: Vec<i128> = vec![0, 1, -1, 5, -5, 10, 100, 1234, -1234, 1000000];
        values.extend([u64::MAX as i128, -(u64::MAX as i128), u64::MAX as i128 + 1]);
        values.extend([i128::MAX, i128::MIN + 1, i128::MIN]);
        let mut x: i128 = 7;
        for _ in 0..2000 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            values.push(x >> (x.unsigned_abs() % 120) as u32);
        }
        for p in 0..=MAX_PRECISION {
            let mut w = CompactPath::new(p, PathUnits::Picture);
            w.command('m');
            let (mut last, mut expected) = (Last::Command, String::from("m"));
            for &v in &values {
                w.number(v);
                reference(v, p, &mut last, &mut expected);
            }
            assert_eq!(w.finish(), expected, "{p} decimals");
        }
    }

    #[test]
    fn compact_numbers_keep_their_separators() {
        let numbers = [1250, -5, 50, 7, -120, 0, 3, 100];
        let mut w = CompactPath::new(2, PathUnits::Picture);
        w.command('M');
        for units in numbers {
            w.number(units);
        }
        assert_eq!(w.finish(), "M12.5-.05.5.07-1.2 0 .03 1");
        // In grid units the same numbers are whole, and only a minus sign saves a space.
        let mut w = CompactPath::new(2, PathUnits::Grid);
        assert_eq!(w.half_unit(), 0.005);
        w.command('M');
        for units in numbers {
            w.number(units);
        }
        assert_eq!(w.finish(), "M1250-5 50 7-120 0 3 100");
        let mut w = CompactPath::new(0, PathUnits::Picture);
        w.command('c');
        w.number(-3);
        w.number(4);
        assert_eq!(w.finish(), "c-3 4");
    }

    #[test]
    fn absolute_path_data_writes_each_letter_once_per_run() {
        let mut d = PathData::new(2);
        d.polyline([
            Point::new(0.0, 0.0),
            Point::new(1.5, 2.0),
            Point::new(-0.25, 3.0),
        ]);
        d.close();
        d.dot(Point::new(4.0, 5.0));
        d.move_to(Point::new(1.0, 1.0));
        d.line_to(Point::new(2.0, 1.0));
        assert_eq!(d.finish(), "M0 0L1.5 2 -0.25 3ZM4 5h0M1 1L2 1");
    }

    #[test]
    fn documents_escape_text_and_order_attributes() {
        let mut doc = Document::new(16.0, 8.0, [0.0, 0.0, 16.0, 8.0], 2);
        doc.add(Text::new("a <1> & \"b\"").set("y", 5).set("x", 1));
        doc.comment("a -- b");
        let svg = doc.finish();
        assert_eq!(
            svg,
            "<svg height=\"8\" viewBox=\"0 0 16 8\" width=\"16\" \
             xmlns=\"http://www.w3.org/2000/svg\">\n\
             <text x=\"1\" y=\"5\">a &lt;1&gt; &amp; \"b\"</text>\n\
             <!-- a - - b -->\n</svg>\n"
        );
        roxmltree::Document::parse(&svg).unwrap();
    }
}
