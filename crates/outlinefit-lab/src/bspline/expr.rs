//! Planar parametric curves r(u) = (x(u), y(u)) given by two expressions in `u`, with
//! exact (symbolic) derivatives up to the third, and their curvature.
//!
//! Parsing and evaluation use the `exmex` crate (maintained, compiles an expression once
//! into a flat form that evaluates quickly, and differentiates symbolically, so curvature
//! and its derivative are exact rather than finite differences).
//!
//! The text is first checked and re-written by a small recursive-descent pass of our own,
//! for three reasons:
//!
//! * exmex lets a leading minus bind tighter than `^`, so `-u^2` would be (−u)² = u². The
//!   pass wraps every unary sign around its whole power chain, `(-(u^(2)))`, which gives the
//!   usual reading −(u²); `^` is made right-associative (`2^3^2` = 2⁹) the same way.
//! * Only the variable `u`, the constant `pi` (also `PI`, `π`) and the differentiable
//!   functions of [`FUNCTIONS`] are accepted; any other name is an error that says so
//!   (exmex would silently take an unknown name for a second variable).
//! * Numbers may use exponents (`1e-3`), which exmex's literal syntax lacks; they are
//!   passed on in plain decimal form (Rust prints every `f64` exactly that way).
//!
//! Grammar: `expr := operand (('+'|'-'|'*'|'/') operand)*`, `operand := ('+'|'-') operand
//! | power`, `power := atom ('^' operand)?`, `atom := number | u | pi | function '(' expr
//! ')' | '(' expr ')'`; `**` is accepted for `^`. Precedence of `+ - * /` is exmex's
//! (the usual one).

use crate::{Error, Result};
use exmex::prelude::*;
use outlinefit::Point;

/// The functions an expression may call (each one exmex can differentiate).
pub const FUNCTIONS: &[&str] = &[
    "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "exp", "ln", "log", "sqrt",
];

/// One coordinate function or one of its derivatives, compiled.
#[derive(Clone, Debug)]
enum Scalar {
    /// A constant (an expression without `u`, or the derivative of one).
    Const(f64),
    /// An expression whose only variable is `u`.
    Expr(Box<FlatEx<f64>>),
}

impl Scalar {
    /// Wraps a parsed expression, folding it to a constant when `u` does not occur.
    fn from_flat(e: FlatEx<f64>) -> Scalar {
        if e.var_names().is_empty() {
            // An expression without variables evaluates with an empty slice; failure is
            // impossible there, NaN keeps the type total.
            Scalar::Const(e.eval(&[]).unwrap_or(f64::NAN))
        } else {
            Scalar::Expr(Box::new(e))
        }
    }

    /// The value at `u` (NaN where the expression is undefined).
    #[inline]
    fn eval(&self, u: f64) -> f64 {
        match self {
            Scalar::Const(c) => *c,
            // The slice length equals the number of variables (exactly one, `u`), the only
            // thing exmex's `eval` checks; NaN keeps the function total.
            Scalar::Expr(e) => e.eval(&[u]).unwrap_or(f64::NAN),
        }
    }

    /// The symbolic derivative d/du.
    fn derivative(&self, what: &str) -> Result<Scalar> {
        match self {
            Scalar::Const(_) => Ok(Scalar::Const(0.0)),
            Scalar::Expr(e) => {
                e.clone()
                    .partial(0)
                    .map(Scalar::from_flat)
                    .map_err(|err| Error::InvalidInput {
                        what: what.to_string(),
                        message: format!("cannot differentiate: {err}"),
                    })
            }
        }
    }
}

/// A coordinate function with its first three derivatives.
#[derive(Clone, Debug)]
struct Coordinate {
    /// f, f′, f″, f‴.
    derivatives: [Scalar; 4],
}

impl Coordinate {
    fn parse(option: &str, text: &str) -> Result<Coordinate> {
        let what = format!("{option} '{text}'");
        let rewritten = rewrite(text).map_err(|message| Error::InvalidInput {
            what: what.clone(),
            message,
        })?;
        let flat = FlatEx::<f64>::parse(&rewritten).map_err(|err| Error::InvalidInput {
            what: what.clone(),
            message: err.to_string(),
        })?;
        if let Some(other) = flat.var_names().iter().find(|v| v.as_str() != "u") {
            // Unreachable after `rewrite`, kept so that no second variable can slip through.
            return Err(Error::InvalidInput {
                what,
                message: format!("unknown variable '{other}': the only variable is u"),
            });
        }
        let f0 = Scalar::from_flat(flat);
        let f1 = f0.derivative(&what)?;
        let f2 = f1.derivative(&what)?;
        let f3 = f2.derivative(&what)?;
        Ok(Coordinate {
            derivatives: [f0, f1, f2, f3],
        })
    }
}

/// A planar parametric curve r(u) = (x(u), y(u)) with exact derivatives.
#[derive(Clone, Debug)]
pub struct ParametricCurve {
    x: Coordinate,
    y: Coordinate,
}

impl ParametricCurve {
    /// Parses the two coordinate expressions.
    ///
    /// Errors: [`Error::InvalidInput`] naming the expression (`--x '…'` or `--y '…'`) when
    /// it does not parse, uses a name other than `u`, `pi` and [`FUNCTIONS`], or cannot be
    /// differentiated.
    pub fn parse(x: &str, y: &str) -> Result<ParametricCurve> {
        Ok(ParametricCurve {
            x: Coordinate::parse("--x", x)?,
            y: Coordinate::parse("--y", y)?,
        })
    }

    /// The point r(u) (coordinates NaN where an expression is undefined).
    #[inline]
    pub fn point(&self, u: f64) -> Point {
        self.derivative(u, 0)
    }

    /// The `order`-th derivative r⁽ᵒʳᵈᵉʳ⁾(u), for `order` ≤ 3 (higher orders give NaN).
    #[inline]
    pub fn derivative(&self, u: f64, order: usize) -> Point {
        match (self.x.derivatives.get(order), self.y.derivatives.get(order)) {
            (Some(x), Some(y)) => Point::new(x.eval(u), y.eval(u)),
            _ => Point::new(f64::NAN, f64::NAN),
        }
    }

    /// Signed curvature κ = (x′y″ − y′x″) / |r′|³ (positive when turning left; NaN where
    /// r′ = 0 or an expression is undefined).
    pub fn curvature(&self, u: f64) -> f64 {
        let d1 = self.derivative(u, 1);
        let d2 = self.derivative(u, 2);
        let speed2 = d1.length_squared();
        if speed2 == 0.0 {
            return f64::NAN;
        }
        d1.cross(d2) / (speed2 * speed2.sqrt())
    }

    /// dκ/du, exactly from the first three derivatives:
    /// κ′ = N′/D^{3/2} − (3/2)·N·D′/D^{5/2} with N = x′y″ − y′x″, N′ = x′y‴ − y′x‴,
    /// D = |r′|², D′ = 2 r′·r″.
    pub fn curvature_derivative(&self, u: f64) -> f64 {
        let d1 = self.derivative(u, 1);
        let d2 = self.derivative(u, 2);
        let d3 = self.derivative(u, 3);
        let d = d1.length_squared();
        if d == 0.0 {
            return f64::NAN;
        }
        let n = d1.cross(d2);
        let n1 = d1.cross(d3);
        let dd = 2.0 * d1.dot(d2);
        let d32 = d * d.sqrt();
        n1 / d32 - 1.5 * n * dd / (d32 * d)
    }
}

/// A token of an expression, with its byte offset.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    /// One of `+ - * / ^`.
    Op(char),
    Open,
    Close,
}

fn describe(t: &Token) -> String {
    match t {
        Token::Number(v) => format!("'{v}'"),
        Token::Name(n) => format!("'{n}'"),
        Token::Op(c) => format!("'{c}'"),
        Token::Open => "'('".to_string(),
        Token::Close => "')'".to_string(),
    }
}

fn tokenize(text: &str) -> std::result::Result<Vec<Token>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < chars.len() && chars[i] == '.' {
                i += 1;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v: f64 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
            if !v.is_finite() {
                return Err(format!("'{s}' is too large"));
            }
            out.push(Token::Number(v));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Token::Name(chars[start..i].iter().collect()));
        } else if c == '*' && chars.get(i + 1) == Some(&'*') {
            out.push(Token::Op('^'));
            i += 2;
        } else if "+-*/^".contains(c) {
            out.push(Token::Op(c));
            i += 1;
        } else if c == '(' {
            out.push(Token::Open);
            i += 1;
        } else if c == ')' {
            out.push(Token::Close);
            i += 1;
        } else {
            return Err(format!(
                "unexpected character '{c}' (allowed: numbers, u, pi, + - * / ^, parentheses, {})",
                FUNCTIONS.join(" ")
            ));
        }
    }
    Ok(out)
}

/// Checks `text` against the grammar of the module docs and re-writes it with explicit
/// parentheses for exmex.
fn rewrite(text: &str) -> std::result::Result<String, String> {
    let tokens = tokenize(text)?;
    if tokens.is_empty() {
        return Err("empty expression".to_string());
    }
    let mut r = Rewriter {
        tokens: &tokens,
        pos: 0,
        out: String::with_capacity(2 * text.len()),
        depth: 0,
    };
    r.expr()?;
    if let Some(t) = r.peek() {
        return Err(format!(
            "unexpected {} after a complete expression (a missing operator?)",
            describe(t)
        ));
    }
    Ok(r.out)
}

struct Rewriter<'a> {
    tokens: &'a [Token],
    pos: usize,
    out: String,
    depth: usize,
}

/// Nesting deeper than this is refused (protects the stack from hostile input).
const MAX_DEPTH: usize = 200;

impl Rewriter<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn enter(&mut self) -> std::result::Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(format!("nested more than {MAX_DEPTH} levels deep"));
        }
        Ok(())
    }

    fn expr(&mut self) -> std::result::Result<(), String> {
        self.enter()?;
        self.operand()?;
        while let Some(Token::Op(c @ ('+' | '-' | '*' | '/'))) = self.peek() {
            self.out.push(*c);
            self.pos += 1;
            self.operand()?;
        }
        self.depth -= 1;
        Ok(())
    }

    fn operand(&mut self) -> std::result::Result<(), String> {
        self.enter()?;
        match self.peek() {
            Some(Token::Op(c @ ('+' | '-'))) => {
                let sign = *c;
                self.pos += 1;
                self.out.push('(');
                self.out.push(sign);
                self.out.push('(');
                self.operand()?;
                self.out.push_str("))");
            }
            _ => self.power()?,
        }
        self.depth -= 1;
        Ok(())
    }

    fn power(&mut self) -> std::result::Result<(), String> {
        self.atom()?;
        if let Some(Token::Op('^')) = self.peek() {
            self.pos += 1;
            self.out.push_str("^(");
            self.operand()?;
            self.out.push(')');
        }
        Ok(())
    }

    fn atom(&mut self) -> std::result::Result<(), String> {
        let Some(token) = self.peek().cloned() else {
            return Err(
                "the expression ends where a number, u, a function or '(' is expected".to_string(),
            );
        };
        self.pos += 1;
        match token {
            Token::Number(v) => {
                // Display prints every finite f64 in plain decimal, exactly.
                self.out.push_str(&format!("{v}"));
                Ok(())
            }
            Token::Open => {
                self.out.push('(');
                self.expr()?;
                self.close()
            }
            Token::Name(name) => {
                if self.peek() == Some(&Token::Open) {
                    if !FUNCTIONS.contains(&name.as_str()) {
                        return Err(format!(
                            "unknown function '{name}' (known: {})",
                            FUNCTIONS.join(", ")
                        ));
                    }
                    self.pos += 1;
                    self.out.push_str(&name);
                    self.out.push('(');
                    self.expr()?;
                    self.close()
                } else if name == "u" {
                    self.out.push('u');
                    Ok(())
                } else if matches!(name.as_str(), "pi" | "PI" | "π") {
                    self.out.push_str("PI");
                    Ok(())
                } else if FUNCTIONS.contains(&name.as_str()) {
                    Err(format!("function '{name}' needs parentheses: {name}(…)"))
                } else {
                    Err(format!("unknown variable '{name}': the only variable is u"))
                }
            }
            other => Err(format!(
                "unexpected {} where a number, u, a function or '(' is expected",
                describe(&other)
            )),
        }
    }

    fn close(&mut self) -> std::result::Result<(), String> {
        match self.peek() {
            Some(Token::Close) => {
                self.pos += 1;
                self.out.push(')');
                Ok(())
            }
            Some(t) => Err(format!("expected ')' but found {}", describe(t))),
            None => Err("missing ')'".to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(x: &str) -> ParametricCurve {
        ParametricCurve::parse(x, "u").unwrap()
    }

    #[test]
    fn accepts_the_papers_equations_and_evaluates_them() {
        // Eq. (5), Example 1.
        let c = ParametricCurve::parse(
            "-26*u^4+64*u^3-52*u^2+16*u-1",
            "-112/3*u^4 + 224/3*u^3 - 48*u^2 + 32/3*u",
        )
        .unwrap();
        for &u in &[0.0f64, 0.3, 0.5, 1.0] {
            let x: f64 = -26.0 * u.powi(4) + 64.0 * u.powi(3) - 52.0 * u * u + 16.0 * u - 1.0;
            let y: f64 =
                -112.0 / 3.0 * u.powi(4) + 224.0 / 3.0 * u.powi(3) - 48.0 * u * u + 32.0 / 3.0 * u;
            let p = c.point(u);
            assert!((p.x - x).abs() < 1e-12 && (p.y - y).abs() < 1e-12, "{u}");
            let dx = -104.0 * u.powi(3) + 192.0 * u * u - 104.0 * u + 16.0;
            assert!((c.derivative(u, 1).x - dx).abs() < 1e-11);
            let d3x = -624.0 * u + 384.0;
            assert!((c.derivative(u, 3).x - d3x).abs() < 1e-10);
        }
        // Eqs. (8) and (9).
        let c = ParametricCurve::parse("u^2 - 1", "u^3 - u").unwrap();
        assert_eq!(c.point(2.0), Point::new(3.0, 6.0));
        let c = ParametricCurve::parse("u^3 + u + 2", "2*u^3 - 3*u^2 - 12*u + 5").unwrap();
        assert_eq!(c.point(2.0), Point::new(12.0, -15.0));
    }

    #[test]
    fn unary_minus_binds_looser_than_power_and_power_is_right_associative() {
        assert_eq!(curve("-u^2").point(0.5).x, -0.25);
        assert_eq!(curve("2*-u^2").point(3.0).x, -18.0);
        assert_eq!(curve("2^-u").point(1.0).x, 0.5);
        assert_eq!(curve("2^3^2").point(0.0).x, 512.0);
        assert_eq!(curve("--u").point(3.0).x, 3.0);
        assert_eq!(curve("1 - u/2*4").point(1.0).x, -1.0);
        assert_eq!(curve("u**2").point(3.0).x, 9.0);
        assert_eq!(curve("1.5e-3*u").point(2.0).x, 3e-3);
        assert!(
            (curve("sin(pi*u) + cos(PI) + sqrt(u) * exp(u)")
                .point(0.25)
                .x
                - ((std::f64::consts::PI * 0.25).sin() - 1.0 + 0.5 * 0.25f64.exp()))
            .abs()
                < 1e-14
        );
        assert_eq!(curve("7").derivative(1.0, 1).x, 0.0);
        assert_eq!(curve("7").point(1.0).x, 7.0);
    }

    #[test]
    fn rejects_unknown_names_and_malformed_text_with_a_message() {
        for (x, expect) in [
            ("u + v", "unknown variable 'v'"),
            ("t^2", "unknown variable 't'"),
            ("foo(u)", "unknown function 'foo'"),
            ("sin u", "needs parentheses"),
            ("2u", "missing operator"),
            ("(u", "missing ')'"),
            ("u)", "unexpected"),
            ("u^", "ends"),
            ("", "empty"),
            ("u # 2", "unexpected character"),
            ("atan2(u, 1)", "unexpected character ','"),
        ] {
            let err = ParametricCurve::parse(x, "u").unwrap_err().to_string();
            assert!(err.contains(expect), "{x:?}: {err}");
            assert!(err.starts_with("--x '"), "{err}");
        }
        let err = ParametricCurve::parse("u", "w").unwrap_err().to_string();
        assert!(err.starts_with("--y 'w'"), "{err}");
        let deep = format!("{}u{}", "(".repeat(1000), ")".repeat(1000));
        assert!(ParametricCurve::parse(&deep, "u").is_err());
    }

    #[test]
    fn curvature_and_its_derivative_are_exact() {
        // Ellipse a = 2, b = 1: κ(t) = ab / (a² sin² t + b² cos² t)^{3/2}, t = 2πu.
        let c = ParametricCurve::parse("2*cos(2*pi*u)", "sin(2*pi*u)").unwrap();
        for &u in &[0.0, 0.1, 0.3] {
            let t = std::f64::consts::TAU * u;
            let q: f64 = 4.0 * t.sin().powi(2) + t.cos().powi(2);
            assert!((c.curvature(u) - 2.0 / q.powf(1.5)).abs() < 1e-12);
            let h = 1e-5;
            let fd = (c.curvature(u + h) - c.curvature(u - h)) / (2.0 * h);
            assert!((c.curvature_derivative(u) - fd).abs() < 1e-5 * (1.0 + fd.abs()));
        }
    }
}
