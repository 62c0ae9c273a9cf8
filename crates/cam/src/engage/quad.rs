//! Quadrature over height with breakpoints.
//!
//! The integrand is a vector of closed-form inner integrals at height `z`,
//! smooth wherever the *signature* — which constraint makes each end of each
//! ρ- (or y-) interval — stays the same. [`integrate`] samples the signature,
//! finds every change between samples by bisection to a few ulps of the
//! range, and integrates each piece by 21-point Gauss–Kronrod after the
//! substitution `z = a + (b − a)(1 + sin(πx/2))/2`, which turns the
//! square-root ends of the pieces (a disc or strip appearing, the tip's
//! `√z`) into analytic ones. A piece whose Kronrod and embedded 10-point
//! Gauss results differ by more than the tolerance (a change the samples
//! missed) is halved, its signatures looked at again, and so on.

#![allow(clippy::excessive_precision)] // the published digits

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

/// Kronrod abscissae on `[−1, 1]` (the odd ones are the Gauss nodes),
/// QUADPACK's `qk21`.
const XGK: [f64; 11] = [
    0.995_657_163_025_808_080_735_527_280_689_003,
    0.973_906_528_517_171_720_077_964_012_084_452,
    0.930_157_491_355_708_226_001_207_180_059_508,
    0.865_063_366_688_984_510_732_096_688_423_493,
    0.780_817_726_586_416_897_063_717_578_345_042,
    0.679_409_568_299_024_406_234_327_365_114_874,
    0.562_757_134_668_604_683_339_000_099_272_694,
    0.433_395_394_129_247_190_799_265_943_165_784,
    0.294_392_862_701_460_198_131_126_603_103_866,
    0.148_874_338_981_631_210_884_826_001_129_720,
    0.0,
];

/// Kronrod weights.
const WGK: [f64; 11] = [
    0.011_694_638_867_371_874_278_064_396_062_192,
    0.032_558_162_307_964_727_478_818_972_459_390,
    0.054_755_896_574_351_996_031_381_300_244_580,
    0.075_039_674_810_919_952_767_043_140_916_190,
    0.093_125_454_583_697_605_535_065_465_083_366,
    0.109_387_158_802_297_641_899_210_590_325_805,
    0.123_491_976_262_065_851_077_208_980_239_403,
    0.134_709_217_311_473_325_928_054_001_771_707,
    0.142_775_938_577_060_080_797_094_273_138_717,
    0.147_739_104_901_338_491_374_841_515_972_068,
    0.149_445_554_002_916_905_664_936_468_389_821,
];

/// Gauss weights of the 10-point rule, at `XGK[1], XGK[3], …, XGK[9]`.
const WG: [f64; 5] = [
    0.066_671_344_308_688_137_593_568_809_893_332,
    0.149_451_349_150_580_593_145_776_339_657_697,
    0.219_086_362_515_982_043_995_534_934_228_163,
    0.269_266_719_309_996_355_091_226_921_569_469,
    0.295_524_224_714_752_870_173_892_994_651_338,
];

/// `(sin(π x/2), (π/4) cos(π x/2))` at the positive abscissae.
fn substitution() -> &'static [(f64, f64); 11] {
    static TABLE: OnceLock<[(f64, f64); 11]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = [(0.0, 0.0); 11];
        for (k, x) in XGK.iter().enumerate() {
            let a = FRAC_PI_2 * x;
            t[k] = (a.sin(), 0.5 * FRAC_PI_2 * a.cos());
        }
        t
    })
}

/// What is integrated over height.
pub(crate) trait Integrand<const N: usize> {
    /// Which constraint makes each end of each interval at `z`; 0 when the
    /// set is empty (the integrand is then 0).
    fn signature(&self, z: f64) -> u64;
    /// The inner integrals at `z`.
    fn values(&self, z: f64) -> [f64; N];
}

/// How finely to integrate.
#[derive(Clone, Debug)]
pub(crate) struct Settings<const N: usize> {
    /// Equal cells over the range in which the signature is first sampled.
    pub cells: usize,
    /// Largest accepted `|Kronrod − Gauss|` per piece, per component
    /// (0: not checked).
    pub tol: [f64; N],
    /// Bisection stops at this width.
    pub eps: f64,
    /// Most halvings of a piece that fails the tolerance.
    pub max_depth: u32,
    /// Heights where the integrand behaves like a square root from above
    /// (the tips of the bodies; where a rake segment starts to meet the
    /// body behind); NaN: none.
    pub roots: [f64; 3],
}

/// 21-point Kronrod and 10-point Gauss results over `[a, b]` under the
/// sine substitution; where a square-root point `p` of the integrand (a
/// tip, where `w ~ √(z − p)`) lies just below `a`, in the variable
/// `s = √(z − p)`, in which it is analytic.
fn kronrod<const N: usize, F: Integrand<N>>(f: &F, a: f64, b: f64, roots: &[f64]) -> ([f64; N], [f64; N]) {
    let table = substitution();
    let p = roots.iter().copied().filter(|&r| r <= a).fold(f64::NEG_INFINITY, f64::max);
    let root = p.is_finite() && a - p < 4.0 * (b - a);
    let (lo, hi) = if root { ((a - p).sqrt(), (b - p).sqrt()) } else { (a, b) };
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let mut k = [0.0; N];
    let mut g = [0.0; N];
    for (j, &(sin, cos)) in table.iter().enumerate() {
        let signs: &[f64] = if j == 10 { &[1.0] } else { &[1.0, -1.0] };
        for &sign in signs {
            let t = mid + sign * half * sin;
            let (z, jac) = if root { (p + t * t, 2.0 * t * (hi - lo) * cos) } else { (t, (hi - lo) * cos) };
            let v = f.values(z);
            for i in 0..N {
                k[i] += WGK[j] * jac * v[i];
                if j % 2 == 1 {
                    g[i] += WG[j / 2] * jac * v[i];
                }
            }
        }
    }
    (k, g)
}

struct Run<'a, const N: usize, F: Integrand<N>> {
    f: &'a F,
    s: &'a Settings<N>,
    sum: [f64; N],
    pieces: usize,
}

impl<const N: usize, F: Integrand<N>> Run<'_, N, F> {
    /// `[a, b]` with signatures `sa`, `sb` at its ends.
    fn cell(&mut self, mut a: f64, mut sa: u64, b: f64, sb: u64, depth: u32) {
        loop {
            if sa == sb {
                if sa != 0 {
                    self.piece(a, b, sa, depth);
                }
                return;
            }
            // A change inside: bisect to it, integrate up to it, go on.
            let (lo, hi, shi) = self.change(a, sa, b);
            if sa != 0 && lo > a {
                self.piece(a, lo, sa, depth);
            }
            a = hi;
            sa = shi;
        }
    }

    /// Bisects `[a, b]`, signature `sa` at `a` and another at `b`, to a
    /// bracket `[lo, hi]` of width `eps` with `sa` at `lo`; also the
    /// signature at `hi`.
    fn change(&self, a: f64, sa: u64, b: f64) -> (f64, f64, u64) {
        let (mut lo, mut hi) = (a, b);
        let mut shi = self.f.signature(b);
        while hi - lo > self.s.eps {
            let m = 0.5 * (lo + hi);
            if m <= lo || m >= hi {
                break;
            }
            let sm = self.f.signature(m);
            if sm == sa {
                lo = m;
            } else {
                hi = m;
                shi = sm;
            }
        }
        (lo, hi, shi)
    }

    fn piece(&mut self, a: f64, b: f64, sa: u64, depth: u32) {
        let (k, g) = kronrod(self.f, a, b, &self.s.roots);
        let bad = (0..N).any(|i| self.s.tol[i] > 0.0 && (k[i] - g[i]).abs() > self.s.tol[i]);
        if bad && depth < self.s.max_depth && b - a > 4.0 * self.s.eps {
            let m = 0.5 * (a + b);
            let sm = self.f.signature(m);
            self.cell(a, sa, m, sm, depth + 1);
            self.cell(m, sm, b, sa, depth + 1);
            return;
        }
        self.pieces += 1;
        for (sum, v) in self.sum.iter_mut().zip(k) {
            *sum += v;
        }
    }
}

/// `∫ f dz` over `[lo, hi]`, with `fixed` extra breakpoints (the joints of
/// the profiles); also the number of pieces used.
pub(crate) fn integrate<const N: usize, F: Integrand<N>>(
    f: &F,
    lo: f64,
    hi: f64,
    fixed: &[f64],
    s: &Settings<N>,
) -> ([f64; N], usize) {
    let mut run = Run { f, s, sum: [0.0; N], pieces: 0 };
    if hi.is_nan() || lo.is_nan() || hi <= lo {
        return (run.sum, 0);
    }
    let n = s.cells.max(1);
    // Sample knots, and the fixed breakpoints, which always end a piece.
    let mut knots: Vec<(f64, bool)> = (0..=n).map(|i| (lo + (hi - lo) * i as f64 / n as f64, i == n)).collect();
    knots[n].0 = hi;
    knots.extend(fixed.iter().filter(|&&z| z > lo && z < hi).map(|&z| (z, true)));
    knots.sort_by(|a, b| a.0.total_cmp(&b.0));
    knots.dedup_by(|a, b| {
        let same = (a.0 - b.0).abs() <= s.eps;
        if same {
            b.1 |= a.1;
        }
        same
    });
    // Runs of equal signature make one piece; a change between two knots
    // is bisected to.
    let (mut a, mut sa) = (knots[0].0, f.signature(knots[0].0));
    let mut prev = a;
    for &(k, forced) in &knots[1..] {
        let sk = f.signature(k);
        let mut from = prev;
        while sa != sk {
            let (l, h, sh) = run.change(from, sa, k);
            if sa != 0 && l > a {
                run.piece(a, l, sa, 0);
            }
            a = h;
            sa = sh;
            from = h;
        }
        if forced {
            if sa != 0 && k > a {
                run.piece(a, k, sa, 0);
            }
            a = k;
        }
        prev = k;
    }
    (run.sum, run.pieces)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Power(i32);
    impl Integrand<1> for Power {
        fn signature(&self, _z: f64) -> u64 {
            1
        }
        fn values(&self, z: f64) -> [f64; 1] {
            [z.powi(self.0)]
        }
    }

    /// The constants: on `[−1, 1]` without the substitution, Kronrod is
    /// exact to degree 31 and Gauss to 19.
    #[test]
    fn kronrod_and_gauss_constants_are_exact_for_polynomials() {
        for d in 0..32 {
            let exact = if d % 2 == 1 { 0.0 } else { 2.0 / (d as f64 + 1.0) };
            let (mut k, mut g) = (0.0, 0.0);
            for j in 0..11 {
                let x = XGK[j];
                let v = x.powi(d) + if j < 10 { (-x).powi(d) } else { 0.0 };
                k += WGK[j] * v;
                if j % 2 == 1 {
                    g += WG[j / 2] * v;
                }
            }
            assert!((k - exact).abs() < 1e-14, "kronrod degree {d}: {k} vs {exact}");
            if d < 20 {
                assert!((g - exact).abs() < 1e-14, "gauss degree {d}: {g} vs {exact}");
            }
        }
    }

    /// A square-root end is integrated to rounding after the substitution.
    #[test]
    fn square_root_ends_are_exact() {
        struct Sqrt;
        impl Integrand<1> for Sqrt {
            fn signature(&self, _z: f64) -> u64 {
                1
            }
            fn values(&self, z: f64) -> [f64; 1] {
                [(z * (1.0 - z)).max(0.0).sqrt()]
            }
        }
        let s = Settings { cells: 1, tol: [1e-15], eps: 1e-15, max_depth: 0, roots: [f64::NAN; 3] };
        let (v, _) = integrate(&Sqrt, 0.0, 1.0, &[], &s);
        assert!((v[0] - std::f64::consts::PI / 8.0).abs() < 1e-14, "{}", v[0]);
        let (v, _) = integrate(&Power(7), 0.0, 2.0, &[], &s);
        assert!((v[0] - 32.0).abs() < 1e-12, "{}", v[0]);
    }

    /// A kink the samples cannot see (the signature never changes) is found
    /// by halving.
    #[test]
    fn a_hidden_kink_is_found_by_halving() {
        struct Abs;
        impl Integrand<1> for Abs {
            fn signature(&self, _z: f64) -> u64 {
                1
            }
            fn values(&self, z: f64) -> [f64; 1] {
                [(z - 0.3).abs()]
            }
        }
        let s = Settings { cells: 1, tol: [1e-13], eps: 1e-15, max_depth: 60, roots: [f64::NAN; 3] };
        let (v, _) = integrate(&Abs, 0.0, 1.0, &[], &s);
        assert!((v[0] - (0.045 + 0.245)).abs() < 1e-12, "{}", v[0]);
    }
}
