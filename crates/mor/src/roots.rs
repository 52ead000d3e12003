//! Roots of an event function on a step's dense output: regula falsi in the Illinois
//! variant (to round-off) and the Anderson–Björck one (to an accuracy asked).

/// Root of f in [a, b] with f(a) > 0 ≥ f(b), by the Illinois variant of regula falsi
/// to round-off; used to locate events on a step's dense output.
pub(crate) fn illinois(f: impl Fn(f64) -> f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    regula_falsi(f, a, b, 0.0, false)
}

/// Root of f in [a, b] with f(a) > 0 ≥ f(b), by the Anderson–Björck variant of regula
/// falsi (it converges in fewer evaluations than the Illinois one on smooth f), done at
/// the first iterate c with |f(c)| ≤ `enough` or at round-off.
#[inline(always)]
pub(crate) fn anderson_bjorck(
    f: impl Fn(f64) -> f64,
    a: (f64, f64),
    b: (f64, f64),
    enough: f64,
) -> f64 {
    regula_falsi(f, a, b, enough, true)
}

/// Regula falsi that scales the value at the end kept twice in a row: by 1/2 (Illinois),
/// or by 1 − f(c)/f(end replaced) where that is positive (Anderson–Björck).
#[inline(always)]
fn regula_falsi(
    f: impl Fn(f64) -> f64,
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    enough: f64,
    anderson_bjorck: bool,
) -> f64 {
    let scale = |fc: f64, replaced: f64| {
        let m = 1.0 - fc / replaced;
        if anderson_bjorck && m > 0.0 { m } else { 0.5 }
    };
    let mut side = 0i8;
    let mut c = b;
    for _ in 0..200 {
        if fb == 0.0 || (side == 1 && fb.abs() <= enough) {
            return b;
        }
        if side == -1 && fa.abs() <= enough {
            return a;
        }
        let mut next = (a * fb - b * fa) / (fb - fa);
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
        }
        let converged = (next - c).abs() <= 4.0 * f64::EPSILON * next.abs();
        c = next;
        if converged || b - a <= 4.0 * f64::EPSILON * b.abs() {
            break;
        }
        let fc = f(c);
        if fc > 0.0 {
            if side == -1 {
                fb *= scale(fc, fa);
            }
            a = c;
            fa = fc;
            side = -1;
        } else {
            if side == 1 {
                fa *= scale(fc, fb);
            }
            b = c;
            fb = fc;
            side = 1;
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regula_falsi_finds_the_root_to_the_accuracy_asked() {
        // cos on [0, 3]: the root π/2, to round-off or to |cos| ≤ 10⁻⁶.
        let at = |x: f64| (x, x.cos());
        let both = [
            illinois(f64::cos, at(0.0), at(3.0)),
            anderson_bjorck(f64::cos, at(0.0), at(3.0), 0.0),
        ];
        for x in both {
            assert!((x - std::f64::consts::FRAC_PI_2).abs() <= 4e-16, "{x}");
        }
        let x = anderson_bjorck(f64::cos, at(0.0), at(3.0), 1e-6);
        assert!(x.cos().abs() <= 1e-6 && (x - std::f64::consts::FRAC_PI_2).abs() <= 2e-6);
    }
}
