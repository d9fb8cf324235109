//! Eigenwaves (plane-wave modes) of isotropic and uniaxial media that share
//! one tangential wave vector at an interface (docs/physics.md §4.1–4.3; Born & Wolf
//! ch. 15; Yariv & Yeh ch. 4).
//!
//! # Conventions (all of spar's interface physics uses these)
//!
//! - **Time dependence** `exp(i(k·r − ωt))`. A wave with complex `k` decays
//!   along `Im k`, so an evanescent wave on side + (where `N·r > 0`) has
//!   `Im q > 0`, on side − `Im q < 0`.
//! - **Units**: wave vectors in units of the vacuum wave number, so `|k| = n`
//!   in an isotropic medium of index `n`. Non-magnetic media (μ = 1) in
//!   normalized units: `H = k × E`, `D = ε E`, and the time-averaged
//!   Poynting vector of a unit-amplitude mode is `S = Re(E × H*) / 2`.
//! - **Interface**: the unit normal `N` points into side +. Every wave of one
//!   interface problem has `k = t + q N` with the same tangential `t`
//!   (`t · N = 0`).
//! - **Incoming/outgoing** is decided by energy, not by `k`: a wave on side σ
//!   (σ = +1 or −1) is outgoing when `σ (S·N) > 0` and incoming when
//!   `σ (S·N) < 0`. For the extraordinary wave the two rules differ near
//!   grazing incidence and only the energy rule is right (docs/physics.md §4.1).
//!   An outgoing evanescent wave is the one that decays away from the
//!   interface: `σ Im q > 0`.
//! - **Tangent frame** ([`TangentFrame`]): `s = unit(t × N)`; when
//!   `|t| < 1e-100` (normal incidence) `s` is the fixed tangent
//!   `N.any_orthonormal_vector()` — every result is invariant under the
//!   choice. `u = N × s`, so `t = |t| u` and `(s, u, N)` is right-handed.
//!   The boundary conditions are imposed on the components along `s` and
//!   `u`.
//!
//! # Field vectors of each mode (all at unit amplitude)
//!
//! - Isotropic `s`: `E = s` (the same real vector for every wave sharing
//!   `t`, on both sides).
//! - Isotropic `p`: `E = k × s / n`. For a propagating wave this is the real
//!   unit vector with `s × p = k̂`, i.e. `(s, p, k̂)` is right-handed.
//! - Ordinary: `E = unit(k × c)` (`c` the optic axis). When `k ∥ c`
//!   (`|k × c| ≤ 1e-14 |k|`) the o and e waves are degenerate and `E = s`,
//!   the choice "from the plane of incidence". That equals `±unit(k × c)` in
//!   the limit `k → c` within the plane of incidence. Near the axis the f64
//!   direction of `k × c` carries an error ≈ ε/sin θ (θ the angle to the
//!   axis); it costs nothing, because a polarization error φ mismatches the
//!   eigenmode only by φ × (the o/e splitting, ~ κ sin²θ) ≈ ε sin θ. (A
//!   double-double `k × c` was tried and changed no test statistic.)
//! - Extraordinary: `D ∥ k × E_o(k)` with `E_o(k)` the ordinary direction for
//!   the extraordinary wave vector, `E = ε⁻¹ D` normalized to unit length
//!   (not transverse to `k`; it is transverse to the ray `S`).
//! - `H = k × E` for every mode. Evanescent waves have complex `k`, `E` and
//!   `H`; the o and e fields are normalized to unit Hermitian length, the
//!   isotropic p field stays `k × s / n` (its bilinear square is 1, its
//!   Hermitian length is not), the vector the textbook `tp` refers to.

use super::linalg::CVec3;
use super::medium::Medium;
use glam::DVec3;
use num_complex::Complex64;

/// Below this squared tangential length (|t| < 1e-100) the plane of incidence
/// is undefined and `s` falls back to a fixed tangent of `N`.
const MIN_T_SQUARED: f64 = 1e-200;

/// `k ∥ c` (o/e degenerate) when `|k × c|² ≤ AXIS_TOL_SQUARED · |k|²`,
/// i.e. within 1e-14 rad of the optic axis.
const AXIS_TOL_SQUARED: f64 = 1e-28;

/// A sheet's Δ is evaluated in plain f64 when
/// `|Δ| > FAST_DISC_MARGIN · (Σ |terms of Δ|)`, in double-double otherwise
/// (see [`Sheet`] and [`TangentFrame::n2_minus_tt`]).
const FAST_DISC_MARGIN: f64 = 1.0 / 64.0;

/// One side of an interface; the normal points into [`Side::Plus`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    Plus,
    Minus,
}

impl Side {
    /// σ = +1 for side +, −1 for side −.
    #[inline]
    pub fn sign(self) -> f64 {
        match self {
            Side::Plus => 1.0,
            Side::Minus => -1.0,
        }
    }

    /// The other side.
    #[inline]
    pub fn opposite(self) -> Side {
        match self {
            Side::Plus => Side::Minus,
            Side::Minus => Side::Plus,
        }
    }

    /// Index 0 for side +, 1 for side −.
    #[inline]
    pub fn index(self) -> usize {
        match self {
            Side::Plus => 0,
            Side::Minus => 1,
        }
    }
}

/// Whether a wave carries energy toward the interface or away from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Travel {
    /// `σ (S·N) < 0`: an incident wave.
    Incoming,
    /// `σ (S·N) > 0`: a reflected or transmitted wave (or, evanescent,
    /// decaying away from the interface).
    Outgoing,
}

/// A single polarization mode: `s`/`p` of an isotropic wave, `o`/`e` of a
/// uniaxial crystal, `fast`/`slow` of a biaxial one (the inner and outer
/// sheets of its index surface, see [`super::anisotropic`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mode {
    S,
    P,
    O,
    E,
    Fast,
    Slow,
}

impl Mode {
    /// The wave this mode belongs to.
    #[inline]
    pub fn kind(self) -> WaveKind {
        match self {
            Mode::S | Mode::P => WaveKind::Isotropic,
            Mode::O => WaveKind::Ordinary,
            Mode::E => WaveKind::Extraordinary,
            Mode::Fast => WaveKind::Fast,
            Mode::Slow => WaveKind::Slow,
        }
    }

    /// `"s"`, `"p"`, `"o"`, `"e"`, `"fast"` or `"slow"`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::S => "s",
            Mode::P => "p",
            Mode::O => "o",
            Mode::E => "e",
            Mode::Fast => "fast",
            Mode::Slow => "slow",
        }
    }

    /// Parse `"s"`, `"p"`, `"o"`, `"e"`, `"fast"` or `"slow"`
    /// (case-insensitive).
    pub fn parse(text: &str) -> Option<Mode> {
        match text.to_ascii_lowercase().as_str() {
            "s" => Some(Mode::S),
            "p" => Some(Mode::P),
            "o" => Some(Mode::O),
            "e" => Some(Mode::E),
            "fast" => Some(Mode::Fast),
            "slow" => Some(Mode::Slow),
            _ => None,
        }
    }

    /// True when `medium` supports this mode (s/p isotropic, o/e uniaxial,
    /// fast/slow biaxial).
    #[inline]
    pub fn exists_in(self, medium: &Medium) -> bool {
        match medium {
            Medium::Isotropic { .. } => matches!(self, Mode::S | Mode::P),
            Medium::Uniaxial { .. } => matches!(self, Mode::O | Mode::E),
            Medium::Biaxial { .. } => matches!(self, Mode::Fast | Mode::Slow),
        }
    }

    /// The two modes of a medium: `[S, P]`, `[O, E]` or `[Fast, Slow]`.
    #[inline]
    pub fn pair_of(medium: &Medium) -> [Mode; 2] {
        match medium {
            Medium::Isotropic { .. } => [Mode::S, Mode::P],
            Medium::Uniaxial { .. } => [Mode::O, Mode::E],
            Medium::Biaxial { .. } => [Mode::Fast, Mode::Slow],
        }
    }
}

/// A wave as the renderer sees it: an isotropic wave has two modes (s, p),
/// an eigenwave of a crystal one (o or e).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WaveKind {
    Isotropic,
    Ordinary,
    Extraordinary,
    /// The inner sheet of a biaxial crystal's index surface (lower index).
    Fast,
    /// The outer sheet (higher index).
    Slow,
}

impl WaveKind {
    /// Number of modes (Jones block dimension): 2 or 1.
    #[inline]
    pub fn mode_count(self) -> usize {
        match self {
            WaveKind::Isotropic => 2,
            _ => 1,
        }
    }

    /// The first mode of this wave (`S`, `O` or `E`).
    #[inline]
    pub fn first_mode(self) -> Mode {
        match self {
            WaveKind::Isotropic => Mode::S,
            WaveKind::Ordinary => Mode::O,
            WaveKind::Extraordinary => Mode::E,
            WaveKind::Fast => Mode::Fast,
            WaveKind::Slow => Mode::Slow,
        }
    }

    /// True when `medium` carries this wave.
    #[inline]
    pub fn exists_in(self, medium: &Medium) -> bool {
        self.first_mode().exists_in(medium)
    }

    /// The waves of a medium: one for an isotropic medium, two (o, e) for a
    /// crystal.
    #[inline]
    pub fn all_of(medium: &Medium) -> &'static [WaveKind] {
        match medium {
            Medium::Isotropic { .. } => &[WaveKind::Isotropic],
            Medium::Uniaxial { .. } => &[WaveKind::Ordinary, WaveKind::Extraordinary],
            Medium::Biaxial { .. } => &[WaveKind::Fast, WaveKind::Slow],
        }
    }
}

/// The frame shared by all waves with tangential wave vector `t` at an
/// interface of unit normal `N` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// Unit normal, pointing into side +.
    pub normal: DVec3,
    /// Tangential wave-vector component (projected onto the plane).
    pub t: DVec3,
    /// `t · t` (rounded; the exact value, where it matters, is recomputed
    /// from `t`).
    pub tt: f64,
    /// `unit(t × N)`, or a fixed tangent at normal incidence.
    pub s: DVec3,
    /// `N × s` (equal to `unit(t)` away from normal incidence).
    pub u: DVec3,
}

impl TangentFrame {
    /// All zero: no frame (a placeholder to be overwritten).
    pub const ZERO: TangentFrame = TangentFrame {
        normal: DVec3::ZERO,
        t: DVec3::ZERO,
        tt: 0.0,
        s: DVec3::ZERO,
        u: DVec3::ZERO,
    };

    /// The frame for unit normal `normal` and tangential component `t` (any
    /// normal component of `t` is removed).
    #[inline]
    pub fn new(normal: DVec3, t: DVec3) -> TangentFrame {
        let t = t - normal * t.dot(normal);
        let v = t.cross(normal);
        let v2 = v.length_squared();
        let s = if v2 > MIN_T_SQUARED {
            v / v2.sqrt()
        } else {
            normal.any_orthonormal_vector()
        };
        TangentFrame {
            normal,
            t,
            tt: t.length_squared(),
            s,
            u: normal.cross(s),
        }
    }

    /// `t · t` in double-double (exact).
    #[inline]
    fn tt_exact(&self) -> Dd {
        Dd::dot(self.t, self.t)
    }

    /// `n² − t·t` without rounding the intermediate terms where that
    /// matters: `Q² = (n cos θ)²` of an isotropic wave of index `n` in this
    /// frame. Plain f64 when the result exceeds `FAST_DISC_MARGIN` of
    /// `n² + t·t` (its rounding error is below 2.5 ε of that sum, so below
    /// 4e-14 of the result), double-double near grazing and critical
    /// incidence.
    #[inline]
    pub fn n2_minus_tt(&self, n: f64) -> f64 {
        let n2 = n * n;
        let d = n2 - self.tt;
        if d.abs() > FAST_DISC_MARGIN * (n2 + self.tt) {
            d
        } else {
            Dd::prod(n, n).sub(self.tt_exact()).value()
        }
    }
}

/// The quadratic `A q² + 2 β q + C = 0` for the normal component `q` of
/// `k = t + q N` on one sheet of a medium's wave-vector surface, with
/// `Δ = β² − A C` (docs/physics.md §4.3, multiplied through so that no reciprocal
/// index is rounded).
///
/// - Isotropic or ordinary sheet `|k|² = n²`: `A = 1`, `β = 0`,
///   `C = T² − n²`, `Δ = n² − T²`.
/// - Extraordinary sheet, the ellipsoid of docs/physics.md §4.3 times `n_o² n_e²`:
///   `n_o² |k|² + δ (k·c)² = n_o² n_e²` with `δ = n_e² − n_o²`, `a = c·N`,
///   `b = c·t`: `A = n_o² + δ a²`, `β = δ a b`,
///   `C = n_o² T² + δ b² − n_o² n_e²` and, with the `δ² a² b²` terms
///   cancelled exactly, `Δ = n_o² [n_o² (n_e² − T²) − δ (b² + a² T² − a² n_e²)]`.
///
/// The ray direction is `g = M k` (the sheet's normal, docs/physics.md §4.3), and
/// `g·N = (A q + β) · g_scale = ±√Δ · g_scale` with `g_scale = 1/n²` or
/// `1/(n_o² n_e²)`: the sign of the root *is* the direction of the energy
/// flow across the interface.
///
/// Near zero, `Δ` is evaluated in double-double from the f64 inputs (see
/// `Dd`), so the o and e sheets describe one crystal and one `t` exactly
/// (measured against a 60-digit reference: without it, o and e waves that
/// are both near grazing and near the optic axis lost 1e-9 of energy).
/// `Δ` is small only near grazing or critical incidence of its own sheet;
/// elsewhere the extraordinary sheet keeps a plain f64 evaluation, accepted
/// when `|Δ|` exceeds `FAST_DISC_MARGIN` = 1/64 of the sum of the absolute
/// values of its terms. Its rounding error (about 10 ε of that sum) is then
/// below ~1.4e-13 of `Δ`: in 1 000 000 uniform and near-critical
/// configurations no solve's energy error grew by more than a factor 2
/// over the all-double-double evaluation (at a margin of 1/1000, 33 in
/// 400 000 did, by up to 22×). The isotropic and ordinary sheets take
/// `n² − T²` the same way ([`TangentFrame::n2_minus_tt`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheet {
    pub a: f64,
    pub beta: f64,
    pub c: f64,
    pub disc: f64,
    pub g_scale: f64,
    /// `√|Δ|` and `1/A`, shared by the sheet's two roots.
    sqrt_disc: f64,
    inv_a: f64,
}

impl Sheet {
    /// The sheet of wave `kind` of `medium` (which must carry it) at the
    /// tangential component of `frame`.
    #[inline]
    pub fn new(medium: &Medium, kind: WaveKind, frame: &TangentFrame) -> Sheet {
        match (*medium, kind) {
            (Medium::Isotropic { n }, _)
            | (Medium::Uniaxial { n_o: n, .. }, WaveKind::Ordinary) => Sheet::from_parts(
                1.0,
                0.0,
                frame.tt - n * n,
                frame.n2_minus_tt(n),
                1.0 / (n * n),
            ),
            // Biaxial media have no quadratic sheet: their waves come from
            // Booker's quartic (`super::anisotropic`), and every caller in
            // the crate dispatches there first. Reported as carrying no
            // propagating wave.
            (Medium::Biaxial { .. }, _) => Sheet::from_parts(1.0, 0.0, 1.0, -1.0, 0.0),
            (Medium::Uniaxial { n_o, n_e, axis }, _) => {
                // Plain f64 first: where |Δ| exceeds its terms' magnitude
                // times FAST_DISC_MARGIN, f64 rounding (≈ 10 ε of that
                // magnitude) moves Δ by at most ~1e-13 relative, which no
                // energy statistic can see (see `Sheet`).
                let no2 = n_o * n_o;
                let ne2 = n_e * n_e;
                let d = ne2 - no2;
                let a = axis.dot(frame.normal);
                let b = axis.dot(frame.t);
                let (a2, b2, tt) = (a * a, b * b, frame.tt);
                let inner = no2 * (ne2 - tt) - d * (b2 + a2 * tt - a2 * ne2);
                let scale = no2 * (ne2 + tt) + d.abs() * (b2 + a2 * tt + a2 * ne2);
                if inner.abs() > FAST_DISC_MARGIN * scale {
                    return Sheet::from_parts(
                        no2 + d * a2,
                        d * a * b,
                        no2 * tt + d * b * b - no2 * ne2,
                        inner * no2,
                        1.0 / (no2 * ne2),
                    );
                }
                let no2 = Dd::prod(n_o, n_o);
                let ne2 = Dd::prod(n_e, n_e);
                let delta = ne2.sub(no2);
                let a_dd = Dd::dot(axis, frame.normal);
                let b_dd = Dd::dot(axis, frame.t);
                let tt = frame.tt_exact();
                let (a, b) = (a_dd.value(), b_dd.value());
                let a2 = a_dd.mul_dd(a_dd);
                let b2 = b_dd.mul_dd(b_dd);
                let big_a = delta.mul_dd(a2).add(no2).value();
                let d = delta.value();
                let beta = d * a * b;
                let c = no2.hi * frame.tt + d * b * b - no2.hi * ne2.hi;
                let inner = no2
                    .mul_dd(ne2.sub(tt))
                    .sub(delta.mul_dd(b2.add(a2.mul_dd(tt)).sub(a2.mul_dd(ne2))));
                Sheet::from_parts(
                    big_a,
                    beta,
                    c,
                    inner.value() * no2.hi,
                    1.0 / (no2.hi * ne2.hi),
                )
            }
        }
    }

    /// The sheet `A q² + 2 β q + C = 0` with `Δ = disc`.
    #[inline]
    fn from_parts(a: f64, beta: f64, c: f64, disc: f64, g_scale: f64) -> Sheet {
        Sheet {
            a,
            beta,
            c,
            disc,
            g_scale,
            sqrt_disc: disc.abs().sqrt(),
            inv_a: 1.0 / a,
        }
    }

    /// True when waves on this sheet propagate (real `q`, `Δ ≥ 0`).
    #[inline]
    pub fn propagates(&self) -> bool {
        self.disc >= 0.0
    }

    /// [`Sheet::root`] of a propagating sheet (`Δ ≥ 0`), in real
    /// arithmetic.
    #[inline]
    pub(crate) fn real_root(&self, dir: f64) -> (f64, f64) {
        let r = dir * self.sqrt_disc;
        // q = (−β + r)/A. `q` enters `k = t + q N` additively, so what
        // matters is its absolute error, ε (|β| + |r|)/A = O(ε n): the
        // "stable" small-root form C/(−β − r) would be worse here (C is
        // a cancelling O(1) sum, error ε/|β + r| when β is small).
        ((r - self.beta) * self.inv_a, r * self.g_scale)
    }

    /// The root whose energy flows along `dir · N` (`dir = ±1`), and its
    /// `g·N = dir √Δ · g_scale`. Under `Δ < 0` the wave is evanescent and
    /// `dir` must be the side's sign: the root that decays on that side,
    /// `q = (−β + i dir √(−Δ)) / A`, with `g·N` reported as 0.
    #[inline]
    pub fn root(&self, dir: f64) -> (Complex64, f64) {
        if self.disc >= 0.0 {
            let (q, g_n) = self.real_root(dir);
            (Complex64::new(q, 0.0), g_n)
        } else {
            let q = Complex64::new(-self.beta, dir * self.sqrt_disc) * self.inv_a;
            (q, 0.0)
        }
    }
}

/// `n² − T²` with `n²` unrounded (see `Dd`): the square of the normal
/// component `Q = n cos θ` of an isotropic wave, for a given `T²`.
#[inline]
pub fn n2_minus_tt(n: f64, tt: f64) -> f64 {
    Dd::prod(n, n).add_f64(-tt).value()
}

/// A double-double number `hi + lo` for the discriminant Δ.
///
/// Why: near grazing and critical incidence Δ → 0 by cancellation of O(1)
/// terms, and `q`, the flux and each mode's consistency with the others all
/// hang on √Δ. Rounding `t·t`, `c·t`, `c·N`, the squared indices or Δ in
/// f64 perturbs each sheet's `q` as if it saw its own slightly different `t`
/// or crystal (δq ≈ ε/√Δ); the waves are then no longer eigenmodes of one
/// common problem, and the energy balance, normalized by a small incident
/// flux, drifts (measured: up to 1e-9 where the o and e sheets are both near
/// grazing and near the optic axis). Evaluated exactly from the f64 inputs
/// (the vectors `t`, `c`, `N` and the indices), every sheet sees the same
/// `t` and the same crystal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dd {
    pub(crate) hi: f64,
    pub(crate) lo: f64,
}

impl Dd {
    /// Exact product (FMA error term).
    #[inline]
    pub(crate) fn prod(a: f64, b: f64) -> Dd {
        let hi = a * b;
        // With hardware FMA the error term is one fused operation; without
        // it `mul_add` would be a libm call, so use Dekker's exact split
        // product instead (valid for |a|, |b| < 2^996: indices and unit
        // vectors here).
        #[cfg(target_feature = "fma")]
        let lo = a.mul_add(b, -hi);
        #[cfg(not(target_feature = "fma"))]
        let lo = {
            const SPLIT: f64 = 134_217_729.0; // 2^27 + 1
            let split = |x: f64| {
                let c = SPLIT * x;
                let h = c - (c - x);
                (h, x - h)
            };
            let (ah, al) = split(a);
            let (bh, bl) = split(b);
            ((ah * bh - hi) + ah * bl + al * bh) + al * bl
        };
        Dd { hi, lo }
    }

    /// Exact sum of two f64 (Knuth's TwoSum).
    #[inline]
    pub(crate) fn two_sum(a: f64, b: f64) -> Dd {
        let hi = a + b;
        let bb = hi - a;
        Dd {
            hi,
            lo: (a - (hi - bb)) + (b - bb),
        }
    }

    #[inline]
    pub(crate) fn add(self, o: Dd) -> Dd {
        let s = Dd::two_sum(self.hi, o.hi);
        let lo = s.lo + self.lo + o.lo;
        let hi = s.hi + lo;
        Dd {
            hi,
            lo: lo - (hi - s.hi),
        }
    }

    /// Exact dot product of two f64 vectors, to double-double.
    #[inline]
    pub(crate) fn dot(a: DVec3, b: DVec3) -> Dd {
        Dd::prod(a.x, b.x)
            .add(Dd::prod(a.y, b.y))
            .add(Dd::prod(a.z, b.z))
    }

    /// Product of two double-doubles (dropping lo·lo).
    #[inline]
    pub(crate) fn mul_dd(self, o: Dd) -> Dd {
        let p = Dd::prod(self.hi, o.hi);
        let lo = p.lo + (self.hi * o.lo + self.lo * o.hi);
        let hi = p.hi + lo;
        Dd {
            hi,
            lo: lo - (hi - p.hi),
        }
    }

    #[inline]
    pub(crate) fn add_f64(self, b: f64) -> Dd {
        self.add(Dd { hi: b, lo: 0.0 })
    }

    #[inline]
    pub(crate) fn sub(self, o: Dd) -> Dd {
        self.add(Dd {
            hi: -o.hi,
            lo: -o.lo,
        })
    }

    #[inline]
    pub(crate) fn value(self) -> f64 {
        self.hi + self.lo
    }
}

/// One plane-wave mode at an interface, at unit amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigenwave {
    pub side: Side,
    pub mode: Mode,
    pub travel: Travel,
    /// Wave vector `t + q N` (complex when evanescent).
    pub k: CVec3,
    /// Normal component `q`.
    pub q: Complex64,
    /// Unit ray (energy) direction. For an evanescent wave: the direction of
    /// its time-averaged Poynting vector (tangential), or zero.
    pub ray: DVec3,
    /// Electric field at unit amplitude.
    pub e: CVec3,
    /// Magnetic field `k × E`.
    pub h: CVec3,
    /// Normal energy flux at unit amplitude, `F = Re((E × H*)·N)/2`
    /// (signed along `N`; 0 when evanescent or grazing).
    pub flux: f64,
    /// True when `q` is complex (the wave decays away from the interface).
    pub evanescent: bool,
}

impl Eigenwave {
    /// The `mode` wave of `medium` on `side` for the frame's tangential
    /// component, travelling as `travel`. The caller guarantees that the
    /// mode exists in the medium. An incoming wave under `Δ < 0` does not
    /// exist; this returns `None` for it (and for nothing else). Isotropic
    /// and uniaxial media only: a biaxial medium's waves come from
    /// [`super::anisotropic::waves`] (the interface dispatches).
    pub fn new(
        medium: &Medium,
        frame: &TangentFrame,
        side: Side,
        travel: Travel,
        mode: Mode,
    ) -> Option<Eigenwave> {
        debug_assert!(mode.exists_in(medium), "mode {mode:?} not in {medium:?}");
        let sheet = Sheet::new(medium, mode.kind(), frame);
        let sigma = side.sign();
        let dir = match travel {
            Travel::Outgoing => sigma,
            Travel::Incoming => {
                if !sheet.propagates() {
                    return None;
                }
                -sigma
            }
        };
        Some(Eigenwave::on_sheet(
            medium, frame, &sheet, side, travel, mode, dir,
        ))
    }

    /// Build the wave on a precomputed sheet (`dir` as in [`Sheet::root`]).
    #[inline]
    pub(crate) fn on_sheet(
        medium: &Medium,
        frame: &TangentFrame,
        sheet: &Sheet,
        side: Side,
        travel: Travel,
        mode: Mode,
        dir: f64,
    ) -> Eigenwave {
        if sheet.propagates() {
            // Real arithmetic: the same numbers the complex formulas give
            // when every imaginary part is zero (see `RealWave`).
            let w = RealWave::on_sheet(medium, frame, sheet, mode, dir);
            return Eigenwave {
                side,
                mode,
                travel,
                k: CVec3::real(w.k),
                q: Complex64::new(w.q, 0.0),
                ray: w.ray(medium, mode.kind()),
                e: CVec3::real(w.e),
                h: CVec3::real(w.h),
                flux: w.flux(),
                evanescent: false,
            };
        }
        let (q, k, e, h) = evanescent_fields(medium, frame, sheet, mode, dir);
        // Time-averaged Poynting vector of a single decaying wave: no
        // normal component in a lossless medium; report its direction.
        let p = e.cross(h.conj()).re;
        let l = p.length();
        let ray = if l > 0.0 && l.is_finite() {
            p / l
        } else {
            DVec3::ZERO
        };
        Eigenwave {
            side,
            mode,
            travel,
            k,
            q,
            ray,
            e,
            h,
            flux: 0.0,
            evanescent: true,
        }
    }
}

/// `q`, `k`, `E` and `H = k × E` of the evanescent wave on `sheet`
/// (`Δ < 0`; `dir` the sign of the side it decays into).
#[inline]
pub(crate) fn evanescent_fields(
    medium: &Medium,
    frame: &TangentFrame,
    sheet: &Sheet,
    mode: Mode,
    dir: f64,
) -> (Complex64, CVec3, CVec3, CVec3) {
    let (q, _) = sheet.root(dir);
    let k = CVec3::new(frame.t + frame.normal * q.re, frame.normal * q.im);
    let e = field(medium, frame, mode, k);
    (q, k, e, k.cross(e))
}

/// A propagating wave (`Δ ≥ 0`, real `q`) in real arithmetic: what the
/// boundary solve and the backward query need of it. [`Eigenwave`] takes
/// its propagating waves from here, so forward solves and backward queries
/// see the same numbers; the formulas are the module's, with the divisions
/// by indices folded into the sheet's `g_scale` where a vector is
/// normalized afterwards anyway.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RealWave {
    /// Normal component of `k`.
    pub q: f64,
    /// `t + q N`.
    pub k: DVec3,
    /// Unit-amplitude electric field.
    pub e: DVec3,
    /// `k × E`.
    pub h: DVec3,
    /// `g·N` of the root ([`Sheet::root`]).
    pub g_n: f64,
    /// The sheet's `g_scale` (`1/n²`, or `1/(n_o² n_e²)`).
    pub g_scale: f64,
}

impl RealWave {
    /// The root of `sheet` (which must propagate) whose energy flows along
    /// `dir · N`, with the `mode` field.
    #[inline]
    pub(crate) fn on_sheet(
        medium: &Medium,
        frame: &TangentFrame,
        sheet: &Sheet,
        mode: Mode,
        dir: f64,
    ) -> RealWave {
        let (q, g_n) = sheet.real_root(dir);
        let k = frame.t + frame.normal * q;
        let e = field_real(medium, frame, sheet, mode, k);
        RealWave {
            q,
            k,
            e,
            h: k.cross(e),
            g_n,
            g_scale: sheet.g_scale,
        }
    }

    /// The `s` and `p` waves of an isotropic medium of index `n` on one
    /// propagating root (they share `q` and `k`).
    #[inline]
    pub(crate) fn isotropic_pair(
        n: f64,
        frame: &TangentFrame,
        sheet: &Sheet,
        dir: f64,
    ) -> [RealWave; 2] {
        let (q, g_n) = sheet.real_root(dir);
        let k = frame.t + frame.normal * q;
        let s = frame.s;
        // p = k × s / n, with 1/n = n · (1/n²).
        let p = k.cross(s) * (n * sheet.g_scale);
        [s, p].map(|e| RealWave {
            q,
            k,
            e,
            h: k.cross(e),
            g_n,
            g_scale: sheet.g_scale,
        })
    }

    /// Normal energy flux at unit amplitude, `|H|²/2 · g·N` (see
    /// [`Eigenwave::on_sheet`]).
    #[inline]
    pub(crate) fn flux(&self) -> f64 {
        0.5 * self.h.length_squared() * self.g_n
    }

    /// Unit ray (energy) direction: that of `M k` ([`ray_vector`]), `k`
    /// itself for an isotropic or ordinary wave, and
    /// `n_e² M k = k + (n_e² − n_o²)/n_o² (k·c) c` for the extraordinary
    /// one.
    #[inline]
    pub(crate) fn ray(&self, medium: &Medium, kind: WaveKind) -> DVec3 {
        match (*medium, kind) {
            (Medium::Uniaxial { n_o, n_e, axis }, WaveKind::Extraordinary) => {
                let ne2 = n_e * n_e;
                // (n_e² − n_o²)/n_o² = (n_e² − n_o²) n_e² · g_scale.
                let c = (ne2 - n_o * n_o) * ne2 * self.g_scale;
                (self.k + axis * (self.k.dot(axis) * c)).normalize()
            }
            // Not built for biaxial media (see `Sheet::new`).
            _ => self.k.normalize(),
        }
    }
}

/// `ε⁻¹ v = v / n_o² − κ (c·v) c` for a uniaxial medium.
#[inline]
fn inverse_epsilon(n_o: f64, n_e: f64, axis: DVec3, v: CVec3) -> CVec3 {
    let kappa = 1.0 / (n_o * n_o) - 1.0 / (n_e * n_e);
    let cv = v.dot_real(axis);
    v * (1.0 / (n_o * n_o)) - CVec3::real(axis).scale(cv * kappa)
}

/// Unit (Hermitian) direction of `v`, or `fallback` when `v` is below
/// `tol2 · scale2` in squared length.
#[inline]
fn unit_or(v: CVec3, scale2: f64, tol2: f64, fallback: DVec3) -> CVec3 {
    let l2 = v.norm_sqr();
    if l2 > tol2 * scale2 && l2.is_finite() {
        v * (1.0 / l2.sqrt())
    } else {
        CVec3::real(fallback)
    }
}

/// The unit-amplitude electric field of `mode` with wave vector `k` (see the
/// module docs for each case).
#[inline]
fn field(medium: &Medium, frame: &TangentFrame, mode: Mode, k: CVec3) -> CVec3 {
    match (*medium, mode) {
        // Isotropic s: E = s (docs/physics.md §4.2).
        (Medium::Isotropic { .. }, Mode::S) => CVec3::real(frame.s),
        // Isotropic p: E = k × s / n, so (s, p, k̂) is right-handed.
        (Medium::Isotropic { n }, _) => k.cross_real(frame.s) * (1.0 / n),
        // Ordinary: E ∥ k × c; s when k ∥ c (degenerate).
        (Medium::Uniaxial { axis, .. }, Mode::O) => {
            unit_or(k.cross_real(axis), k.norm_sqr(), AXIS_TOL_SQUARED, frame.s)
        }
        // Extraordinary: D ∥ k × E_o(k), E = ε⁻¹ D (docs/physics.md §4.3, B&W ch. 15).
        (Medium::Uniaxial { n_o, n_e, axis }, _) => {
            let e_o = unit_or(k.cross_real(axis), k.norm_sqr(), AXIS_TOL_SQUARED, frame.s);
            let d = k.cross(e_o);
            let e = inverse_epsilon(n_o, n_e, axis, d);
            e * (1.0 / e.norm_sqr().sqrt())
        }
        // Not used for biaxial media (see `Sheet::new`): the null space of
        // W(k) is in `super::anisotropic`.
        (Medium::Biaxial { .. }, _) => CVec3::real(frame.s),
    }
}

/// [`field`] for a real wave vector on `sheet`, in real arithmetic. The
/// extraordinary field is normalized after `ε⁻¹` is applied, so it is
/// computed as `n_o² ε⁻¹ D = D − (n_e² − n_o²)/n_e² (c·D) c` with the
/// sheet's `g_scale = 1/(n_o² n_e²)` (no division).
#[inline]
fn field_real(medium: &Medium, frame: &TangentFrame, sheet: &Sheet, mode: Mode, k: DVec3) -> DVec3 {
    let unit_or = |v: DVec3, scale2: f64, fallback: DVec3| {
        let l2 = v.length_squared();
        if l2 > AXIS_TOL_SQUARED * scale2 && l2.is_finite() {
            v * (1.0 / l2.sqrt())
        } else {
            fallback
        }
    };
    match (*medium, mode) {
        (Medium::Isotropic { .. }, Mode::S) => frame.s,
        // 1/n = n · (1/n²).
        (Medium::Isotropic { n }, _) => k.cross(frame.s) * (n * sheet.g_scale),
        (Medium::Uniaxial { axis, .. }, Mode::O) => {
            unit_or(k.cross(axis), k.length_squared(), frame.s)
        }
        (Medium::Uniaxial { n_o, n_e, axis }, _) => {
            // D ∥ k × E_o; E is normalized below, so E_o need not be.
            let v = k.cross(axis);
            let l2 = v.length_squared();
            let e_o = if l2 > AXIS_TOL_SQUARED * k.length_squared() && l2.is_finite() {
                v
            } else {
                frame.s
            };
            let d = k.cross(e_o);
            let no2 = n_o * n_o;
            // (n_e² − n_o²)/n_e² = (n_e² − n_o²) n_o² · g_scale.
            let c = (n_e * n_e - no2) * no2 * sheet.g_scale;
            let e = d - axis * (d.dot(axis) * c);
            e * (1.0 / e.length_squared().sqrt())
        }
        // Not used for biaxial media (see `Sheet::new`).
        (Medium::Biaxial { .. }, _) => frame.s,
    }
}

#[cfg(test)]
mod tests {
    use super::super::directions::ray_vector;
    use super::*;

    #[test]
    fn sheet_roots_follow_the_energy_rule() {
        // Calcite-like crystal, axis tilted: g·N of each root has the
        // requested sign and the root satisfies the quadratic.
        let m = Medium::Uniaxial {
            n_o: 1.6584,
            n_e: 1.4864,
            axis: DVec3::new(0.3, -0.5, 0.8).normalize(),
        };
        let n = DVec3::Z;
        let f = TangentFrame::new(n, DVec3::new(0.7, 0.4, 0.0));
        let sh = Sheet::new(&m, WaveKind::Extraordinary, &f);
        for dir in [1.0, -1.0] {
            let (q, g_n) = sh.root(dir);
            let q = q.re;
            assert!((sh.a * q * q + 2.0 * sh.beta * q + sh.c).abs() < 1e-14);
            assert!(g_n * dir > 0.0);
            let k = f.t + n * q;
            let g = ray_vector(&m, WaveKind::Extraordinary, k);
            assert!((g.dot(n) - g_n).abs() < 1e-15);
            // On the ellipsoid: kᵀ M k = 1.
            assert!((g.dot(k) - 1.0).abs() < 1e-14);
        }
    }
}
