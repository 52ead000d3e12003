//! Dormand–Prince 8(5,3): the DOP853 code of Hairer, Nørsett & Wanner, *Solving Ordinary
//! Differential Equations I*, 2nd ed., Sec. II.10 — 12-stage 8th-order step, the combined
//! 5th/3rd-order error estimate, Hairer's step-size control, FSAL, and the 7th-order dense
//! output (3 extra stages), built only for the step where it is asked for.
//!
//! Nothing allocates: the state is `[f64; N]` and the 16 stages live on the stack. The
//! coefficients are Hairer's, as tabulated in scipy's public coefficient file.
#![allow(clippy::excessive_precision)]

/// An ODE system y' = f(t, y).
pub(crate) trait System<const N: usize> {
    /// f(t, y), or `None` when `y` lies outside the domain where f is defined; a step that
    /// meets such a stage is rejected and shrunk.
    fn rhs(&self, t: f64, y: &[f64; N]) -> Option<[f64; N]>;

    /// The size of each component that the relative tolerance refers to; |y_i| by default.
    fn magnitude(&self, y: &[f64; N]) -> [f64; N] {
        y.map(f64::abs)
    }

    /// An extra quantity q(y) whose local error is controlled too, as (q, ∂q/∂y): its
    /// error estimate is ∂q/∂y·e and its weight 1/(atol_q + rtol·max(|q(y₀)|, |q(y₁)|)).
    /// Useful when q is a small difference of large components.
    fn monitored(&self, _y: &[f64; N]) -> Option<(f64, [f64; N])> {
        None
    }

    /// Called as each trial step begins, before its stages: f is then evaluated at stages
    /// 1 to 11 in order (at t + c_i h, [`NODES`]) and, where the step is accepted, at its
    /// end (stage 12).
    fn trial_started(&self) {}

    /// Whether the Runge–Kutta sums are fused multiply-adds (one rounding per term:
    /// the same bits wherever the CPU has FMA or not, fast only where it has).
    const FUSED: bool = false;

    /// Whether the trial step is laid out for vectors: each stage's state and slope are
    /// kept in memory (so that the Runge–Kutta sums run on whole vectors where f reads
    /// the components one by one), and the error norm is summed in four lanes
    /// ([`sum_of_squares`]; its last bits, and so the steps', differ from the plain sum).
    const LANES: bool = false;
}

/// Per-step error control: a step is accepted when the weighted error norm is ≤ 1, with
/// weights 1/(atol_i + rtol·max(m_i(y₀), m_i(y₁))) and m = [`System::magnitude`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tolerances<const N: usize> {
    pub rtol: f64,
    pub atol: [f64; N],
    /// Absolute tolerance of [`System::monitored`].
    pub atol_monitored: f64,
}

/// Work counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Counters {
    pub accepted: usize,
    pub rejected: usize,
    pub evaluations: usize,
}

/// Why a step could not be taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum StepFailure {
    /// The step size fell below the resolution of t, or is not a finite number (an
    /// infinite first step stays infinite through every rejection).
    Underflow { t: f64 },
    /// f cannot be evaluated at the initial point.
    OutsideDomain { t: f64 },
}

/// Hairer's defaults: safety factor and the bounds 1/3 ≤ h_new/h ≤ 6.
const SAFETY: f64 = 0.9;
const MIN_RATIO: f64 = 0.333;
const MAX_RATIO: f64 = 6.0;
/// Shrink factor after a stage left the domain of f.
const DOMAIN_SHRINK: f64 = 0.25;

/// The integrator state, with the stages of the last step kept for its dense output.
pub(crate) struct Dop853<'s, S: System<N>, const N: usize> {
    sys: &'s S,
    tol: Tolerances<N>,
    t: f64,
    y: [f64; N],
    /// f(t, y), the first stage of the next step (FSAL).
    f: [f64; N],
    /// Step size proposed for the next step.
    h: f64,
    /// Start, size and initial state of the last accepted step.
    t0: f64,
    h0: f64,
    y0: [f64; N],
    /// Stages of the last accepted step; 12 is f at its end, 13..15 the dense-output stages.
    k: [[f64; N]; 16],
    /// The safety factor of the step-size control.
    safety: f64,
    pub counters: Counters,
}

impl<'s, S: System<N>, const N: usize> Dop853<'s, S, N> {
    /// Starts at (t, y) with a first trial step `h` > 0.
    pub fn new(
        sys: &'s S,
        t: f64,
        y: [f64; N],
        tol: Tolerances<N>,
        h: f64,
    ) -> Result<Self, StepFailure> {
        let f = sys.rhs(t, &y).ok_or(StepFailure::OutsideDomain { t })?;
        Ok(Self {
            sys,
            tol,
            t,
            y,
            f,
            h,
            t0: t,
            h0: 0.0,
            y0: y,
            k: [[0.0; N]; 16],
            safety: SAFETY,
            counters: Counters {
                evaluations: 1,
                ..Counters::default()
            },
        })
    }

    pub fn t(&self) -> f64 {
        self.t
    }

    pub fn y(&self) -> &[f64; N] {
        &self.y
    }

    /// The step size proposed for the next step.
    pub fn next_step(&self) -> f64 {
        self.h
    }

    /// Sets the safety factor of the step-size control (Hairer's 0.9 by default): a
    /// smaller one takes smaller steps but has fewer rejected where the error estimate
    /// varies from step to step.
    pub fn set_safety(&mut self, safety: f64) {
        self.safety = safety;
    }

    /// Keeps the next step at most `h_max` long.
    pub fn limit_step(&mut self, h_max: f64) {
        if h_max > 0.0 {
            self.h = self.h.min(h_max);
        }
    }

    /// Starts again at (t, y) with a first trial step `h` (as [`Self::new`], keeping the
    /// counters and the tolerances).
    pub fn restart(&mut self, t: f64, y: [f64; N], h: f64) -> Result<(), StepFailure> {
        self.f = self.eval(t, &y).ok_or(StepFailure::OutsideDomain { t })?;
        (self.t, self.y, self.h, self.t0, self.y0) = (t, y, h, t, y);
        Ok(())
    }

    /// Start time and state of the last accepted step.
    pub fn last_start(&self) -> (f64, &[f64; N]) {
        (self.t0, &self.y0)
    }

    /// Takes one accepted step, retrying with smaller steps as the error control demands.
    #[inline(always)]
    pub fn step(&mut self) -> Result<(), StepFailure> {
        let mut rejected_before = false;
        loop {
            let h = self.h;
            if self.t + h <= self.t || !h.is_finite() {
                return Err(StepFailure::Underflow { t: self.t });
            }
            let Some((mut y1, err)) = self.trial(h) else {
                self.reject(DOMAIN_SHRINK * h);
                rejected_before = true;
                continue;
            };
            let fac = err.powf(0.125) / self.safety;
            if err <= 1.0 {
                in_memory(S::LANES, &mut y1);
                let Some(f1) = self.eval(self.t + h, &y1) else {
                    self.reject(DOMAIN_SHRINK * h);
                    rejected_before = true;
                    continue;
                };
                self.accept(h, y1, f1);
                let mut h_new = h / fac.clamp(1.0 / MAX_RATIO, 1.0 / MIN_RATIO);
                if rejected_before {
                    h_new = h_new.min(h);
                }
                self.h = h_new;
                return Ok(());
            }
            self.reject(h / fac.min(1.0 / MIN_RATIO));
            rejected_before = true;
        }
    }

    /// The 7th-order interpolant of the last accepted step (3 more evaluations of f).
    #[inline(always)]
    pub fn dense(&mut self) -> Result<Dense<N>, StepFailure> {
        let (t0, h, y0) = (self.t0, self.h0, self.y0);
        for i in 13..16 {
            // Plain sums: the dense output is built outside the step's (vectorised) code.
            let yi = combine(&y0, h, &self.k, A[i], false);
            self.k[i] = self
                .eval(t0 + NODES[i] * h, &yi)
                .ok_or(StepFailure::OutsideDomain {
                    t: t0 + NODES[i] * h,
                })?;
        }
        let k = &self.k;
        let mut cont = [[0.0; N]; 8];
        for n in 0..N {
            let dy = self.y[n] - y0[n];
            let bspl = h * k[0][n] - dy;
            cont[0][n] = y0[n];
            cont[1][n] = dy;
            cont[2][n] = bspl;
            cont[3][n] = dy - h * k[12][n] - bspl;
        }
        for (i, row) in D.iter().enumerate() {
            let s = weighted(k, row, false);
            for n in 0..N {
                cont[4 + i][n] = h * s[n];
            }
        }
        Ok(Dense { t0, h, cont })
    }

    #[inline(always)]
    fn eval(&mut self, t: f64, y: &[f64; N]) -> Option<[f64; N]> {
        self.counters.evaluations += 1;
        self.sys.rhs(t, y)
    }

    fn reject(&mut self, h_new: f64) {
        self.counters.rejected += 1;
        self.h = h_new;
    }

    fn accept(&mut self, h: f64, y1: [f64; N], f1: [f64; N]) {
        self.counters.accepted += 1;
        self.t0 = self.t;
        self.h0 = h;
        self.y0 = self.y;
        self.k[12] = f1;
        self.t += h;
        self.y = y1;
        self.f = f1;
    }

    /// One trial step of size h: the new state and the error norm (Hairer's `err`), or
    /// `None` if a stage left the domain.
    #[inline(always)]
    fn trial(&mut self, h: f64) -> Option<([f64; N], f64)> {
        self.sys.trial_started();
        let (t, y) = (self.t, self.y);
        self.k[0] = self.f;
        // Unrolled, so that each row of the tableau is a compile-time constant.
        macro_rules! stages {
            ($($i:literal)*) => {$(
                let mut yi = combine(&y, h, &self.k, A[$i], S::FUSED);
                in_memory(S::LANES, &mut yi);
                self.k[$i] = self.eval(t + NODES[$i] * h, &yi)?;
                in_memory(S::LANES, &mut self.k[$i]);
            )*};
        }
        stages!(1 2 3 4 5 6 7 8 9 10 11);
        let b = weighted(&self.k, A[12], S::FUSED);
        let mut y1 = b;
        for n in 0..N {
            y1[n] = if S::FUSED {
                h.mul_add(b[n], y[n])
            } else {
                y[n] + h * b[n]
            };
        }
        if y1.iter().any(|v| !v.is_finite()) {
            return Some((y1, f64::INFINITY));
        }
        let (m0, m1) = (self.sys.magnitude(&y), self.sys.magnitude(&y1));
        let bhh = weighted(&self.k, &BHH, S::FUSED);
        let e5 = weighted(&self.k, &E5, S::FUSED);
        // The errors in units of each component's tolerance.
        let (mut e3, mut w5, mut w3) = ([0.0; N], [0.0; N], [0.0; N]);
        for n in 0..N {
            // A component that is identically zero (atol 0) must not divide by zero.
            let scale =
                (self.tol.atol[n] + self.tol.rtol * m0[n].max(m1[n])).max(f64::MIN_POSITIVE);
            e3[n] = b[n] - bhh[n];
            w5[n] = e5[n] / scale;
            w3[n] = e3[n] / scale;
        }
        let (mut err5, mut err3) = (sum_of_squares(S::LANES, &w5), sum_of_squares(S::LANES, &w3));
        let mut count = N as f64;
        if let (Some((q0, grad)), Some((q1, _))) = (self.sys.monitored(&y), self.sys.monitored(&y1))
        {
            let scale = (self.tol.atol_monitored + self.tol.rtol * q0.abs().max(q1.abs()))
                .max(f64::MIN_POSITIVE);
            let project = |e: &[f64; N]| {
                let mut sum = 0.0;
                for n in 0..N {
                    sum += grad[n] * e[n];
                }
                sum
            };
            err5 += (project(&e5) / scale).powi(2);
            err3 += (project(&e3) / scale).powi(2);
            count += 1.0;
        }
        let mut deno = err5 + 0.01 * err3;
        if deno <= 0.0 || deno.is_nan() {
            deno = 1.0;
        }
        Some((y1, h.abs() * err5 * (1.0 / (count * deno)).sqrt()))
    }
}

/// Where `on`, an opaque use of `x` ([`System::LANES`]): the compiler keeps it in memory,
/// and reads it from there afterwards, rather than forwarding the components one by one
/// (which turns the Runge–Kutta sums of the next stages into scalar code).
#[inline(always)]
fn in_memory<T>(on: bool, x: &mut T) {
    if on {
        std::hint::black_box(x);
    }
}

/// Σ w_n², in the order of the components, or where `lanes` ([`System::LANES`]) in four
/// lanes, components side by side (so that it vectorises; the same terms in another
/// order).
#[inline(always)]
fn sum_of_squares<const N: usize>(lanes: bool, w: &[f64; N]) -> f64 {
    if lanes {
        let mut sum = [0.0; 4];
        for (k, x) in w.iter().enumerate() {
            sum[k % 4] += x * x;
        }
        (sum[0] + sum[2]) + (sum[1] + sum[3])
    } else {
        let mut sum = 0.0;
        for x in w {
            sum += x.powi(2);
        }
        sum
    }
}

/// Σ_j a_j k_j for every component, summed in the order of the row (components side by
/// side, so that they vectorise); by fused multiply-adds if `fused`.
#[inline(always)]
fn weighted<const N: usize>(k: &[[f64; N]; 16], row: &[(usize, f64)], fused: bool) -> [f64; N] {
    let mut sum = [0.0; N];
    for &(j, a) in row {
        for n in 0..N {
            sum[n] = if fused {
                a.mul_add(k[j][n], sum[n])
            } else {
                sum[n] + a * k[j][n]
            };
        }
    }
    sum
}

/// y + h·Σ_j a_j k_j.
#[inline(always)]
fn combine<const N: usize>(
    y: &[f64; N],
    h: f64,
    k: &[[f64; N]; 16],
    row: &[(usize, f64)],
    fused: bool,
) -> [f64; N] {
    let mut out = weighted(k, row, fused);
    for n in 0..N {
        out[n] = if fused {
            h.mul_add(out[n], y[n])
        } else {
            y[n] + h * out[n]
        };
    }
    out
}

/// The 7th-order continuous extension of one step (Hairer's `contd8`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dense<const N: usize> {
    pub t0: f64,
    pub h: f64,
    cont: [[f64; N]; 8],
}

impl<const N: usize> Dense<N> {
    /// The interpolated state at time t (meant for t in [t0, t0 + h]).
    #[inline]
    pub fn eval(&self, t: f64) -> [f64; N] {
        self.eval_leading(t)
    }

    /// The first K components of [`Self::eval`] (K ≤ N): an event function that needs
    /// only those interpolates only them.
    #[inline(always)]
    pub fn eval_leading<const K: usize>(&self, t: f64) -> [f64; K] {
        let s = (t - self.t0) / self.h;
        let s1 = 1.0 - s;
        let c = &self.cont;
        let mut y = [0.0; K];
        for n in 0..K {
            let par = c[4][n] + s * (c[5][n] + s1 * (c[6][n] + s * c[7][n]));
            y[n] = c[0][n] + s * (c[1][n] + s1 * (c[2][n] + s * (c[3][n] + s1 * par)));
        }
        y
    }
}

/// Stage nodes c_i.
#[rustfmt::skip]
pub(crate) const NODES: [f64; 16] = [
    0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510, 0.281649658092772603273242802490,
    0.333333333333333333333333333333, 0.25, 0.307692307692307692307692307692,
    0.651282051282051282051282051282, 0.6, 0.857142857142857142857142857142, 1.0, 1.0, 0.1, 0.2,
    0.777777777777777777777777777778,
];
/// Nonzero stage coefficients a_ij (row 12 holds the weights b_j; stage 12 is the FSAL stage).
#[rustfmt::skip]
const A: [&[(usize, f64)]; 16] = [
    &[],
    &[
        (0, 5.26001519587677318785587544488e-2),
    ],
    &[
        (0, 1.97250569845378994544595329183e-2), (1, 5.91751709536136983633785987549e-2),
    ],
    &[
        (0, 2.95875854768068491816892993775e-2), (2, 8.87627564304205475450678981324e-2),
    ],
    &[
        (0, 2.41365134159266685502369798665e-1), (2, -8.84549479328286085344864962717e-1), (3,
        9.24834003261792003115737966543e-1),
    ],
    &[
        (0, 3.7037037037037037037037037037e-2), (3, 1.70828608729473871279604482173e-1), (4,
        1.25467687566822425016691814123e-1),
    ],
    &[
        (0, 3.7109375e-2), (3, 1.70252211019544039314978060272e-1), (4,
        6.02165389804559606850219397283e-2), (5, -1.7578125e-2),
    ],
    &[
        (0, 3.70920001185047927108779319836e-2), (3, 1.70383925712239993810214054705e-1), (4,
        1.07262030446373284651809199168e-1), (5, -1.53194377486244017527936158236e-2), (6,
        8.27378916381402288758473766002e-3),
    ],
    &[
        (0, 6.24110958716075717114429577812e-1), (3, -3.36089262944694129406857109825), (4,
        -8.68219346841726006818189891453e-1), (5, 2.75920996994467083049415600797e1), (6,
        2.01540675504778934086186788979e1), (7, -4.34898841810699588477366255144e1),
    ],
    &[
        (0, 4.77662536438264365890433908527e-1), (3, -2.48811461997166764192642586468), (4,
        -5.90290826836842996371446475743e-1), (5, 2.12300514481811942347288949897e1), (6,
        1.52792336328824235832596922938e1), (7, -3.32882109689848629194453265587e1), (8,
        -2.03312017085086261358222928593e-2),
    ],
    &[
        (0, -9.3714243008598732571704021658e-1), (3, 5.18637242884406370830023853209), (4,
        1.09143734899672957818500254654), (5, -8.14978701074692612513997267357), (6,
        -1.85200656599969598641566180701e1), (7, 2.27394870993505042818970056734e1), (8,
        2.49360555267965238987089396762), (9, -3.0467644718982195003823669022),
    ],
    &[
        (0, 2.27331014751653820792359768449), (3, -1.05344954667372501984066689879e1), (4,
        -2.00087205822486249909675718444), (5, -1.79589318631187989172765950534e1), (6,
        2.79488845294199600508499808837e1), (7, -2.85899827713502369474065508674), (8,
        -8.87285693353062954433549289258), (9, 1.23605671757943030647266201528e1), (10,
        6.43392746015763530355970484046e-1),
    ],
    &[
        (0, 5.42937341165687622380535766363e-2), (5, 4.45031289275240888144113950566), (6,
        1.89151789931450038304281599044), (7, -5.8012039600105847814672114227), (8,
        3.1116436695781989440891606237e-1), (9, -1.52160949662516078556178806805e-1), (10,
        2.01365400804030348374776537501e-1), (11, 4.47106157277725905176885569043e-2),
    ],
    &[
        (0, 5.61675022830479523392909219681e-2), (6, 2.53500210216624811088794765333e-1), (7,
        -2.46239037470802489917441475441e-1), (8, -1.24191423263816360469010140626e-1), (9,
        1.5329179827876569731206322685e-1), (10, 8.20105229563468988491666602057e-3), (11,
        7.56789766054569976138603589584e-3), (12, -8.298e-3),
    ],
    &[
        (0, 3.18346481635021405060768473261e-2), (5, 2.83009096723667755288322961402e-2), (6,
        5.35419883074385676223797384372e-2), (7, -5.49237485713909884646569340306e-2), (10,
        -1.08347328697249322858509316994e-4), (11, 3.82571090835658412954920192323e-4), (12,
        -3.40465008687404560802977114492e-4), (13, 1.41312443674632500278074618366e-1),
    ],
    &[
        (0, -4.28896301583791923408573538692e-1), (5, -4.69762141536116384314449447206), (6,
        7.68342119606259904184240953878), (7, 4.06898981839711007970213554331), (8,
        3.56727187455281109270669543021e-1), (12, -1.39902416515901462129418009734e-3), (13,
        2.9475147891527723389556272149), (14, -9.15095847217987001081870187138),
    ],
];
/// Weights b̂_j of the embedded 3rd-order method (nonzero ones; the estimate is b − b̂).
#[rustfmt::skip]
const BHH: [(usize, f64); 3] = [
    (0, 0.244094488188976377952755905512), (8, 0.733846688281611857341361741547), (11,
    0.220588235294117647058823529412e-1),
];
/// Coefficients of the 5th-order error estimate, over stages 0..11.
#[rustfmt::skip]
const E5: [(usize, f64); 8] = [
    (0, 0.1312004499419488073250102996e-1), (5, -0.1225156446376204440720569753e1), (6,
    -0.4957589496572501915214079952), (7, 0.1664377182454986536961530415e1), (8,
    -0.3503288487499736816886487290), (9, 0.3341791187130174790297318841), (10,
    0.8192320648511571246570742613e-1), (11, -0.2235530786388629525884427845e-1),
];
/// Dense-output coefficients d_ij of the 7th-order interpolant, over stages 0..15.
#[rustfmt::skip]
const D: [[(usize, f64); 12]; 4] = [
    [
        (0, -0.84289382761090128651353491142e1), (5, 0.56671495351937776962531783590), (6,
        -0.30689499459498916912797304727e1), (7, 0.23846676565120698287728149680e1), (8,
        0.21170345824450282767155149946e1), (9, -0.87139158377797299206789907490), (10,
        0.22404374302607882758541771650e1), (11, 0.63157877876946881815570249290), (12,
        -0.88990336451333310820698117400e-1), (13, 0.18148505520854727256656404962e2), (14,
        -0.91946323924783554000451984436e1), (15, -0.44360363875948939664310572000e1),
    ],
    [
        (0, 0.10427508642579134603413151009e2), (5, 0.24228349177525818288430175319e3), (6,
        0.16520045171727028198505394887e3), (7, -0.37454675472269020279518312152e3), (8,
        -0.22113666853125306036270938578e2), (9, 0.77334326684722638389603898808e1), (10,
        -0.30674084731089398182061213626e2), (11, -0.93321305264302278729567221706e1), (12,
        0.15697238121770843886131091075e2), (13, -0.31139403219565177677282850411e2), (14,
        -0.93529243588444783865713862664e1), (15, 0.35816841486394083752465898540e2),
    ],
    [
        (0, 0.19985053242002433820987653617e2), (5, -0.38703730874935176555105901742e3), (6,
        -0.18917813819516756882830838328e3), (7, 0.52780815920542364900561016686e3), (8,
        -0.11573902539959630126141871134e2), (9, 0.68812326946963000169666922661e1), (10,
        -0.10006050966910838403183860980e1), (11, 0.77771377980534432092869265740), (12,
        -0.27782057523535084065932004339e1), (13, -0.60196695231264120758267380846e2), (14,
        0.84320405506677161018159903784e2), (15, 0.11992291136182789328035130030e2),
    ],
    [
        (0, -0.25693933462703749003312586129e2), (5, -0.15418974869023643374053993627e3), (6,
        -0.23152937917604549567536039109e3), (7, 0.35763911791061412378285349910e3), (8,
        0.93405324183624310003907691704e2), (9, -0.37458323136451633156875139351e2), (10,
        0.10409964950896230045147246184e3), (11, 0.29840293426660503123344363579e2), (12,
        -0.43533456590011143754432175058e2), (13, 0.96324553959188282948394950600e2), (14,
        -0.39177261675615439165231486172e2), (15, -0.14972683625798562581422125276e3),
    ],
];

#[cfg(test)]
mod tests {
    use super::*;

    /// y'' = −y as a first-order system: y = (cos t, −sin t).
    struct Oscillator;
    impl System<2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2]) -> Option<[f64; 2]> {
            Some([y[1], -y[0]])
        }
    }

    /// y' = 7t⁶ (y = t⁷, which the 7th-order interpolant must reproduce to round-off)
    /// and y' = y (y = eᵗ).
    struct PolyExp;
    impl System<2> for PolyExp {
        fn rhs(&self, t: f64, y: &[f64; 2]) -> Option<[f64; 2]> {
            Some([7.0 * t.powi(6), y[1]])
        }
    }

    fn tol<const N: usize>(rtol: f64, atol: f64) -> Tolerances<N> {
        Tolerances {
            rtol,
            atol: [atol; N],
            atol_monitored: 0.0,
        }
    }

    /// Integrates to t_end and checks step ends and the dense output at interior points.
    fn check<S: System<2>>(
        sys: &S,
        y0: [f64; 2],
        t_end: f64,
        exact: impl Fn(f64) -> [f64; 2],
        bound: f64,
    ) -> Counters {
        let mut ode = Dop853::new(sys, 0.0, y0, tol(1e-13, 1e-13), 0.01).unwrap();
        while ode.t() < t_end {
            ode.step().unwrap();
            let (t, y) = (ode.t(), *ode.y());
            for (yn, en) in y.iter().zip(exact(t)) {
                assert!((yn - en).abs() <= bound, "end of step at t = {t}");
            }
            let dense = ode.dense().unwrap();
            for s in [0.0, 0.13, 0.3, 0.5, 0.71, 0.9, 1.0] {
                let ti = dense.t0 + s * dense.h;
                let (yi, ei) = (dense.eval(ti), exact(ti));
                for n in 0..2 {
                    let d = (yi[n] - ei[n]).abs();
                    assert!(d <= bound, "dense output off by {d:e} at s = {s}, t = {ti}");
                }
            }
        }
        ode.counters
    }

    #[test]
    fn oscillator_steps_and_dense_output_are_accurate() {
        let c = check(
            &Oscillator,
            [1.0, 0.0],
            20.0,
            |t| [t.cos(), -t.sin()],
            1e-11,
        );
        assert!(c.accepted > 10 && c.accepted < 400, "{c:?}");
    }

    #[test]
    fn dense_output_is_exact_for_a_seventh_degree_polynomial_and_accurate_for_exp() {
        // The interpolant is exact for polynomials of degree ≤ 7: swapping s and 1 − s in
        // its higher terms (a known bug of one published implementation) fails this.
        check(
            &PolyExp,
            [0.0, 1.0],
            2.0,
            |t| [t.powi(7), t.exp()],
            2e-12 * 2f64.exp(),
        );
    }

    #[test]
    fn a_stage_outside_the_domain_shrinks_the_step() {
        /// y' = 1 on y < 0.5 only.
        struct Wall;
        impl System<1> for Wall {
            fn rhs(&self, _t: f64, y: &[f64; 1]) -> Option<[f64; 1]> {
                (y[0] < 0.5).then_some([1.0])
            }
        }
        let mut ode = Dop853::new(&Wall, 0.0, [0.0], tol(1e-10, 1e-10), 10.0).unwrap();
        ode.step().unwrap();
        assert!(ode.y()[0] < 0.5 && ode.counters.rejected >= 1);
        assert!((ode.t() - ode.y()[0]).abs() < 1e-15);
    }

    #[test]
    fn tableau_rows_sum_to_their_nodes() {
        for (i, row) in A.iter().enumerate() {
            let s: f64 = row.iter().map(|&(_, a)| a).sum();
            assert!((s - NODES[i]).abs() < 1e-14, "row {i}: {s} vs {}", NODES[i]);
        }
        let bhh: f64 = BHH.iter().map(|&(_, b)| b).sum();
        assert!((bhh - 1.0).abs() < 1e-14);
        assert!(E5.iter().map(|&(_, e)| e).sum::<f64>().abs() < 1e-14);
    }
}
