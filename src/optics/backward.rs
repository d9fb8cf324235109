//! The backward query: which forward incident waves feed a given outgoing
//! wave, and with which Jones blocks (optics.md §5). This is the renderer's
//! hot path: no heap allocation, fixed-size results, closed-form Fresnel for
//! isotropic pairs and one 4×4 factorization shared by all candidates
//! otherwise.
//!
//! # What the caller passes
//!
//! An [`Interface`] (unit normal `N` into side +, the media on both sides)
//! and the outgoing forward wave `w`: its side, its [`WaveKind`] (isotropic,
//! ordinary or extraordinary) and its **forward** ray direction, pointing
//! away from the interface into `w`'s side (the reverse of the direction the
//! backward ray travels when it arrives at the surface). For an
//! extraordinary wave the wave vector is found from the ray direction,
//! `k = M⁻¹ S / sqrt(Sᵀ M⁻¹ S)` ([`super::modes::k_from_ray`]).
//!
//! # What comes back
//!
//! - `target`: `w` itself (its `k`, unit ray and basis).
//! - up to four feeders (reflection feeders, on `w`'s side, first; then
//!   transmission feeders from the other side), one per propagating incident
//!   wave with `w`'s tangential component that carries energy toward the
//!   interface: one for an isotropic side (modes s, p), two for a crystal
//!   side (o, e). At most 2 for two isotropic media, 3 for one crystal, 4
//!   for two; fewer under total internal reflection.
//!
//! # Bases (all real unit vectors; every wave here propagates)
//!
//! Let `s = unit(t × N)` (`t` the common tangential wave vector; at normal
//! incidence, `|t| < 1e-100`, the fixed tangent `N.any_orthonormal_vector()`).
//!
//! - Isotropic wave (target or feeder) with wave vector `k`:
//!   `basis = [s, p]`, `p = k̂ × s`. `(s, p, k̂)` is right-handed
//!   (`s × p = k̂`): a receiver looking back at the source (line of sight
//!   `−k̂`) sees `s` as its x axis and `p` as its y axis, with `x × y`
//!   pointing at itself — the (x, y) of optics.md §1, so Stokes parameters
//!   can be read off directly in `[s, p]`. The same `s` serves every wave of
//!   the query; `p` differs per wave.
//! - Ordinary or extraordinary wave: `basis = [ê, 0]` with `ê` the unit
//!   electric field (o: `unit(k × c)`, or `s` when `k ∥ c`; e:
//!   `unit(ε⁻¹ (k × ê_o))`, transverse to the ray but not to `k`). Its sign
//!   is arbitrary but fixed by these formulas.
//!
//! # The Jones block
//!
//! `block` has `rows = target modes` (2 for isotropic `w`, ordered `[s, p]`;
//! 1 for o or e) and `cols = feeder modes` (`[s, p]` or 1). Entry `(r, c)` is
//! the energy-normalized amplitude `ã = a sqrt(|F_w,r| / |F_c|)` of the
//! forward wave: a feeder field of unit energy-normalized amplitude along
//! its basis vector `c` produces `ã` times unit energy-normalized amplitude
//! along `w`'s basis vector `r`. A feeder's coherence matrix `J_c` in its
//! basis contributes `T J_c Tᴴ` to `w`'s, in `w`'s basis (optics.md §3); to
//! use another transverse basis, rotate `J` (the basis vectors are returned
//! for exactly that). Energy-normalized amplitudes make `Σ |ã|²` over all
//! outgoing waves of each incident mode 1; the `n²` radiance factor is left
//! out (see [`super::interface`]).
//!
//! # Use in a backward tracer
//!
//! ```text
//! backward ray arrives at the surface with direction d, on side σ, as wave K
//! f = interface.feeders(σ, K, −d)
//! J_w = Σ over x in f.as_slice():
//!         x.block · J_x · x.blockᴴ
//!       where J_x = trace(from the hit point, direction −x.wave.ray,
//!                         medium of x.wave.side, wave x.wave.kind),
//!             expressed in x.wave.basis
//! J_w is in f.target.basis.
//! ```

use super::fresnel::{fresnel_from_normals, normal_component};
use super::interface::{energy_factor, BoundarySystem, Interface, InterfaceError};
use super::jones::Jones;
use super::medium::Medium;
use super::modes::{k_from_ray, Eigenwave, Mode, Side, TangentFrame, Travel, WaveKind};
use glam::DVec3;
use num_complex::Complex64;

const ZERO: Complex64 = Complex64::new(0.0, 0.0);

/// A propagating wave of the query with its transverse basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveBasis {
    pub side: Side,
    pub kind: WaveKind,
    /// Wave vector (real).
    pub k: DVec3,
    /// Unit ray (energy) direction, forward in time: away from the interface
    /// for the target, toward it for a feeder.
    pub ray: DVec3,
    /// `[s, p]` for an isotropic wave, `[ê, 0]` for an eigenwave (module
    /// docs).
    pub basis: [DVec3; 2],
}

impl WaveBasis {
    /// Number of modes: 2 (isotropic) or 1.
    #[inline]
    pub fn modes(&self) -> usize {
        self.kind.mode_count()
    }
}

/// One forward incident wave that feeds the target, and its Jones block
/// (rows: target modes, cols: this wave's modes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feeder {
    pub wave: WaveBasis,
    pub block: Jones,
}

/// The result of a backward query (fixed size, no allocation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feeders {
    /// The tangent frame of the query (its `t` is `w`'s tangential wave
    /// vector, its `s` the `s` of every isotropic basis).
    pub frame: TangentFrame,
    pub target: WaveBasis,
    list: [Feeder; 4],
    len: usize,
}

impl Feeders {
    /// The feeders, reflection feeders first.
    #[inline]
    pub fn as_slice(&self) -> &[Feeder] {
        &self.list[..self.len]
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    #[inline]
    fn empty(frame: &TangentFrame, target: WaveBasis) -> Feeders {
        let blank = Feeder {
            wave: target,
            block: Jones {
                rows: 0,
                cols: 0,
                m: [[ZERO; 2]; 2],
            },
        };
        Feeders {
            frame: *frame,
            target,
            list: [blank; 4],
            len: 0,
        }
    }

    #[inline]
    fn push(&mut self, f: Feeder) {
        self.list[self.len] = f;
        self.len += 1;
    }
}

impl Interface {
    /// The backward query for the outgoing wave of `kind` on `side` whose
    /// forward ray leaves the interface along `ray` (module docs).
    ///
    /// Errors: `ray` zero or not finite; `kind` not carried by that side's
    /// medium; `ray` not leaving the interface into `side`
    /// (`σ (ray·N) ≤ 0`).
    #[inline]
    pub fn feeders(
        &self,
        side: Side,
        kind: WaveKind,
        ray: DVec3,
    ) -> Result<Feeders, InterfaceError> {
        let l2 = ray.length_squared();
        if !(l2 > 0.0) || !l2.is_finite() {
            return Err(InterfaceError::BadVector("ray direction"));
        }
        let medium = self.medium(side);
        if !kind.exists_in(medium) {
            return Err(InterfaceError::ModeNotInMedium {
                mode: kind.first_mode(),
                side,
            });
        }
        if !(side.sign() * ray.dot(self.normal()) > 0.0) {
            return Err(InterfaceError::NotOutgoing);
        }
        let k = k_from_ray(medium, kind, ray);
        self.feeders_tangential(side, kind, k)
    }

    /// The backward query for the outgoing wave of `kind` on `side` with
    /// tangential wave vector `t` (any normal component is ignored). Returns
    /// no feeders when that wave carries no normal flux: it grazes the
    /// interface, or `t` lies beyond its sheet (evanescent; from a ray
    /// direction this happens only by rounding at grazing).
    pub fn feeders_tangential(
        &self,
        side: Side,
        kind: WaveKind,
        t: DVec3,
    ) -> Result<Feeders, InterfaceError> {
        if !t.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        self.feeders_in(side, kind, &self.frame(t))
    }

    /// The backward query in a given tangent frame.
    pub fn feeders_in(
        &self,
        side: Side,
        kind: WaveKind,
        frame: &TangentFrame,
    ) -> Result<Feeders, InterfaceError> {
        if !kind.exists_in(self.medium(side)) {
            return Err(InterfaceError::ModeNotInMedium {
                mode: kind.first_mode(),
                side,
            });
        }
        match (*self.medium(side), *self.medium(side.opposite())) {
            (Medium::Isotropic { n: n_w }, Medium::Isotropic { n: n_x }) => {
                Ok(isotropic_pair(frame, side, n_w, n_x))
            }
            _ => self.general(frame, side, kind),
        }
    }

    fn general(
        &self,
        frame: &TangentFrame,
        side: Side,
        kind: WaveKind,
    ) -> Result<Feeders, InterfaceError> {
        let sheets = self.sheets(frame);
        let out = self.outgoing_on(frame, &sheets);
        // Target rows: indices into `out` of w's modes.
        let base = 2 * side.index();
        let (rows, first) = match kind {
            WaveKind::Isotropic | WaveKind::Ordinary => (kind.mode_count(), base),
            WaveKind::Extraordinary => (1, base + 1),
        };
        let w0 = &out[first];
        let target = basis_of(
            w0,
            if rows == 2 {
                Some(&out[first + 1])
            } else {
                None
            },
            kind,
        );
        let mut result = Feeders::empty(frame, target);
        if w0.evanescent || w0.flux == 0.0 {
            return Ok(result);
        }
        let system = BoundarySystem::new(frame, &out).ok_or(InterfaceError::Singular)?;
        for cand_side in [side, side.opposite()] {
            let medium = self.medium(cand_side);
            for &ck in WaveKind::all_of(medium) {
                let modes: &[_] = match ck {
                    WaveKind::Isotropic => &[Mode::S, Mode::P],
                    WaveKind::Ordinary => &[Mode::O],
                    WaveKind::Extraordinary => &[Mode::E],
                };
                let mut waves = [None; 2];
                for (i, &m) in modes.iter().enumerate() {
                    // The incoming wave shares its sheet with the outgoing
                    // one of the same mode; it exists only if it propagates.
                    let idx = if ck == WaveKind::Extraordinary { 1 } else { i };
                    let sheet = &sheets[cand_side.index()][idx];
                    if sheet.propagates() {
                        let dir = -cand_side.sign();
                        waves[i] = Some(Eigenwave::on_sheet(
                            medium,
                            frame,
                            sheet,
                            cand_side,
                            Travel::Incoming,
                            m,
                            dir,
                        ));
                    }
                }
                let c0 = match waves[0] {
                    Some(w) if w.flux != 0.0 => w,
                    _ => continue,
                };
                let mut m = [[ZERO; 2]; 2];
                for (c, cw) in waves.iter().take(modes.len()).enumerate() {
                    let cw = cw
                        .as_ref()
                        .expect("both modes of an isotropic wave propagate together");
                    let a = system.solve(frame, cw);
                    for (r, row) in m.iter_mut().take(rows).enumerate() {
                        let j = first + r;
                        row[c] = a[j] * energy_factor(out[j].flux, cw.flux);
                    }
                }
                let wave = basis_of(&c0, waves[1].as_ref().filter(|_| modes.len() == 2), ck);
                result.push(Feeder {
                    wave,
                    block: Jones {
                        rows,
                        cols: modes.len(),
                        m,
                    },
                });
            }
        }
        Ok(result)
    }
}

/// The basis of a propagating wave: `[s, p]` from its two isotropic modes,
/// or `[ê, 0]`.
#[inline]
fn basis_of(w0: &Eigenwave, w1: Option<&Eigenwave>, kind: WaveKind) -> WaveBasis {
    let basis = match w1 {
        Some(w1) => [w0.e.re, w1.e.re],
        None => [w0.e.re, DVec3::ZERO],
    };
    WaveBasis {
        side: w0.side,
        kind,
        k: w0.k.re,
        ray: w0.ray,
        basis,
    }
}

/// Two isotropic media: the closed forms (optics.md §4), the target on
/// `side` in index `n_w`, the other side of index `n_x`.
#[inline]
fn isotropic_pair(frame: &TangentFrame, side: Side, n_w: f64, n_x: f64) -> Feeders {
    let sigma = side.sign();
    let n_dir = frame.normal;
    let s = frame.s;
    let dw = frame.n2_minus_tt(n_w);
    let q_w = dw.max(0.0).sqrt();
    let k_w = frame.t + n_dir * (sigma * q_w);
    let wave = |side: Side, k: DVec3, n: f64| WaveBasis {
        side,
        kind: WaveKind::Isotropic,
        k,
        ray: k / n,
        basis: [s, k.cross(s) / n],
    };
    let target = wave(side, k_w, n_w);
    let mut result = Feeders::empty(frame, target);
    if !(dw > 0.0) {
        // w grazes the interface: no normal flux to feed.
        return result;
    }
    let q_x = normal_component(frame.n2_minus_tt(n_x));
    let dx = q_x.re;
    let diag = |a: Complex64, b: Complex64| Jones {
        rows: 2,
        cols: 2,
        m: [[a, ZERO], [ZERO, b]],
    };
    // Reflection feeder: incident on w's side, q = −σ Q_w.
    let f = fresnel_from_normals(n_w, n_x, q_w, q_x);
    result.push(Feeder {
        wave: wave(side, frame.t - n_dir * (sigma * q_w), n_w),
        block: diag(f.rs, f.rp),
    });
    // Transmission feeder: incident on the other side (−σ) toward w, q = σ Q_x.
    if dx > 0.0 {
        let f = fresnel_from_normals(n_x, n_w, q_x.re, Complex64::new(q_w, 0.0));
        result.push(Feeder {
            wave: wave(side.opposite(), frame.t + n_dir * (sigma * q_x.re), n_x),
            block: diag(f.ts_energy, f.tp_energy),
        });
    }
    result
}
