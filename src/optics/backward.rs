//! The backward query: which forward incident waves feed a given outgoing
//! wave, and with which Jones blocks (docs/physics.md §4.6). This is the renderer's
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
//! `k = M⁻¹ S / sqrt(Sᵀ M⁻¹ S)` ([`super::directions::k_from_ray`]).
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
//!   pointing at itself — the (x, y) of docs/physics.md §1.3, so Stokes parameters
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
//! basis contributes `T J_c Tᴴ` to `w`'s, in `w`'s basis (docs/physics.md §3); to
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

use super::directions::k_from_ray;
use super::fresnel::{fresnel_from_normals, normal_component};
use super::interface::{
    energy_factor, tangential, tangential_real, with_full_system, with_system, Column, Interface,
    InterfaceError, Solve, WithSystem,
};
use super::jones::Jones;
use super::medium::Medium;
use super::modes::{
    evanescent_fields, Eigenwave, Mode, RealWave, Sheet, Side, TangentFrame, Travel, WaveKind,
};
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

/// The result of a backward query (fixed size, no allocation). Two
/// results are equal when their frames, targets and feeders are.
#[derive(Clone, Copy, Debug)]
pub struct Feeders {
    /// The tangent frame of the query (its `t` is `w`'s tangential wave
    /// vector, its `s` the `s` of every isotropic basis).
    pub frame: TangentFrame,
    pub target: WaveBasis,
    /// The first `len` entries; the others stay [`BLANK`].
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

    /// No feeders, no frame: a place for [`Interface::feeders_into`] to
    /// write.
    pub const EMPTY: Feeders = Feeders {
        frame: TangentFrame::ZERO,
        target: BLANK.wave,
        list: [BLANK; 4],
        len: 0,
    };

    /// No feeders yet in `frame`, the target to be set by the query. The
    /// entries past `len` are left as they were: nothing reads them.
    #[inline]
    fn reset(&mut self, frame: &TangentFrame) {
        self.frame = *frame;
        self.target = BLANK.wave;
        self.len = 0;
    }

    /// The next entry, counted in (the caller fills it).
    #[inline]
    fn next(&mut self) -> &mut Feeder {
        self.len += 1;
        &mut self.list[self.len - 1]
    }
}

impl PartialEq for Feeders {
    fn eq(&self, other: &Feeders) -> bool {
        self.frame == other.frame
            && self.target == other.target
            && self.as_slice() == other.as_slice()
    }
}

/// An unused entry (all bits zero, so filling a list with it is a memset).
const BLANK: Feeder = Feeder {
    wave: WaveBasis {
        side: Side::Plus,
        kind: WaveKind::Isotropic,
        k: DVec3::ZERO,
        ray: DVec3::ZERO,
        basis: [DVec3::ZERO; 2],
    },
    block: Jones {
        rows: 0,
        cols: 0,
        m: [[ZERO; 2]; 2],
    },
};

impl Interface {
    /// The backward query for the outgoing wave of `kind` on `side` whose
    /// forward ray leaves the interface along `ray` (module docs).
    ///
    /// Errors: `ray` zero or not finite; `kind` not carried by that side's
    /// medium; `ray` not leaving the interface into `side`
    /// (`σ (ray·N) ≤ 0`).
    #[inline(always)]
    pub fn feeders(
        &self,
        side: Side,
        kind: WaveKind,
        ray: DVec3,
    ) -> Result<Feeders, InterfaceError> {
        let mut result = Feeders::EMPTY;
        self.feeders_into(side, kind, ray, &mut result)?;
        Ok(result)
    }

    /// [`Interface::feeders`] written into `result` (whatever it held),
    /// for a caller that keeps the result where it is used: the renderer,
    /// whose every node would otherwise copy the near-kilobyte result.
    /// On error `result` holds no feeders.
    #[inline]
    pub fn feeders_into(
        &self,
        side: Side,
        kind: WaveKind,
        ray: DVec3,
        result: &mut Feeders,
    ) -> Result<(), InterfaceError> {
        result.len = 0;
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
        if !k.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        result.reset(&self.frame(k));
        let frame = result.frame;
        if self.has_biaxial() {
            return self.general_any(&frame, side, kind, Some(k), result);
        }
        self.fill(&frame, side, kind, result)
    }

    /// The backward query for the outgoing wave of `kind` on `side` with
    /// tangential wave vector `t` (any normal component is ignored). Returns
    /// no feeders when that wave carries no normal flux: it grazes the
    /// interface, or `t` lies beyond its sheet (evanescent; from a ray
    /// direction this happens only by rounding at grazing).
    #[inline(always)]
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
    #[inline(always)]
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
        // The result (nearly a kilobyte) is filled in place by a worker
        // that is not inlined, while this wrapper is: the caller's own
        // variable can then be the one filled, without a copy.
        let mut result = Feeders::EMPTY;
        result.reset(frame);
        self.fill(frame, side, kind, &mut result)?;
        Ok(result)
    }

    #[inline(never)]
    fn fill(
        &self,
        frame: &TangentFrame,
        side: Side,
        kind: WaveKind,
        result: &mut Feeders,
    ) -> Result<(), InterfaceError> {
        if self.has_biaxial() {
            return self.general_any(frame, side, kind, None, result);
        }
        match (*self.medium(side), *self.medium(side.opposite())) {
            (Medium::Isotropic { n: n_w }, Medium::Isotropic { n: n_x }) => {
                isotropic_pair(frame, side, n_w, n_x, result);
                Ok(())
            }
            _ => self.general(frame, side, kind, result),
        }
    }

    #[inline]
    fn general(
        &self,
        frame: &TangentFrame,
        side: Side,
        kind: WaveKind,
        result: &mut Feeders,
    ) -> Result<(), InterfaceError> {
        let sheets = self.sheets(frame);
        // Target rows: w's modes among the outgoing waves [+₀, +₁, −₀, −₁].
        let base = 2 * side.index();
        let (rows, first) = match kind {
            WaveKind::Isotropic | WaveKind::Ordinary | WaveKind::Fast => (kind.mode_count(), base),
            WaveKind::Extraordinary | WaveKind::Slow => (1, base + 1),
        };
        // Columns of the boundary system from the crystal sides' outgoing
        // waves (an isotropic side facing a crystal needs none: its modes
        // are eliminated in closed form), and w's own waves.
        let mut cols = [Column::Unused; 4];
        let mut target: [Option<RealWave>; 2] = [None; 2];
        for out_side in [Side::Plus, Side::Minus] {
            let medium = self.medium(out_side);
            let si = out_side.index();
            let dir = out_side.sign();
            match *medium {
                Medium::Isotropic { n } => {
                    let sheet = &sheets[si][0];
                    if out_side == side && sheet.propagates() {
                        let [s, p] = RealWave::isotropic_pair(n, frame, sheet, dir);
                        target = [Some(s), Some(p)];
                    }
                }
                // Biaxial media take `general_any` (see `fill`).
                Medium::Biaxial { .. } => {}
                Medium::Uniaxial { .. } => {
                    for (i, mode) in [Mode::O, Mode::E].into_iter().enumerate() {
                        let j = 2 * si + i;
                        let sheet = &sheets[si][i];
                        cols[j] = if sheet.propagates() {
                            let w = RealWave::on_sheet(medium, frame, sheet, mode, dir);
                            if j >= first && j < first + rows {
                                target[j - first] = Some(w);
                            }
                            Column::Real(tangential_real(frame, w.e, w.h))
                        } else {
                            let (_, _, e, h) = evanescent_fields(medium, frame, sheet, mode, dir);
                            Column::Complex(tangential(frame, e, h))
                        };
                    }
                }
            }
        }
        let w_medium = self.medium(side);
        let Some(w0) = target[0] else {
            // w is evanescent (t beyond its sheet, by rounding from a ray
            // direction): nothing feeds it. Report it as the forward solver
            // sees it.
            let wave = |i: usize| {
                let mode = Mode::pair_of(w_medium)[i];
                let sheet = &sheets[side.index()][i];
                Eigenwave::on_sheet(
                    w_medium,
                    frame,
                    sheet,
                    side,
                    Travel::Outgoing,
                    mode,
                    side.sign(),
                )
            };
            let w0 = wave(first - base);
            let w1 = (rows == 2).then(|| wave(1));
            result.target = basis_of(&w0, w1.as_ref(), kind);
            return Ok(());
        };
        let w1 = target[1].filter(|_| rows == 2);
        result.target = WaveBasis {
            side,
            kind,
            k: w0.k,
            ray: w0.ray(w_medium, kind),
            basis: [w0.e, w1.map_or(DVec3::ZERO, |w| w.e)],
        };
        let w_flux = [w0.flux(), w1.map_or(0.0, |w| w.flux())];
        if w_flux[0] == 0.0 {
            return Ok(());
        }
        let feed = Feed {
            iface: self,
            frame,
            sheets: &sheets,
            side,
            rows,
            first,
            w_flux,
            result,
        };
        with_system(self, &sheets, &cols, feed).ok_or(InterfaceError::Singular)
    }
}

impl Interface {
    /// The backward query when a side is biaxial: every wave from
    /// [`Eigenwave`] (Booker's quartic on the biaxial side, see
    /// [`super::anisotropic`]), the full 4×4 system. The target is the
    /// outgoing wave of `kind` on `side`; when both outgoing waves of a
    /// biaxial side carry that name (a line `t + q N` that cuts one sheet
    /// twice, near an optic axis), the one nearest `hint` (the wave vector
    /// found from the ray direction).
    fn general_any(
        &self,
        frame: &TangentFrame,
        side: Side,
        kind: WaveKind,
        hint: Option<DVec3>,
        result: &mut Feeders,
    ) -> Result<(), InterfaceError> {
        let waves = self.general_waves(frame);
        let out = waves.outgoing;
        let base = 2 * side.index();
        let (first, rows) = if kind == WaveKind::Isotropic {
            (base, 2)
        } else {
            let mode = kind.first_mode();
            let named = [base, base + 1].map(|j| out[j].mode == mode);
            let pick = match (named, hint) {
                ([true, false], _) => base,
                ([false, true], _) => base + 1,
                // Both or neither named so: the one whose wave vector the
                // ray gave, else the slot of the name.
                (_, Some(k)) => {
                    let d = |j: usize| (out[j].k.re - k).length_squared();
                    if d(base + 1) < d(base) {
                        base + 1
                    } else {
                        base
                    }
                }
                (_, None) => base + super::interface::mode_index(mode),
            };
            (pick, 1)
        };
        let w0 = &out[first];
        let w1 = (rows == 2).then(|| &out[first + 1]);
        result.target = basis_of(w0, w1, kind);
        if w0.evanescent || w0.flux == 0.0 {
            // Grazing or evanescent: nothing feeds it.
            return Ok(());
        }
        let cols = [0, 1, 2, 3].map(|j| Column::of(frame, &out[j]));
        let w_flux = [w0.flux, w1.map_or(0.0, |w| w.flux)];
        let feed = FeedAny {
            iface: self,
            frame,
            side,
            rows,
            first,
            w_flux,
            incoming: waves.incoming,
            result,
        };
        with_full_system(&cols, feed).ok_or(InterfaceError::Singular)
    }
}

/// The candidates of [`Interface::general_any`]: every propagating
/// incident wave with the target's `t`, and its block.
struct FeedAny<'a> {
    iface: &'a Interface,
    frame: &'a TangentFrame,
    side: Side,
    rows: usize,
    first: usize,
    w_flux: [f64; 2],
    /// Each biaxial side's incoming waves, from the solve that gave the
    /// outgoing ones.
    incoming: [Option<[Eigenwave; 2]>; 2],
    result: &'a mut Feeders,
}

impl WithSystem for FeedAny<'_> {
    type Output = ();

    fn with<S: Solve>(self, system: &S) {
        let FeedAny {
            iface,
            frame,
            side,
            rows,
            first,
            w_flux,
            incoming: biaxial_incoming,
            result,
        } = self;
        for cand_side in [side, side.opposite()] {
            let medium = iface.medium(cand_side);
            let sigma = cand_side.sign();
            let incoming: [Option<Eigenwave>; 2] = if let Some(pair) =
                biaxial_incoming[cand_side.index()]
            {
                pair.map(Some)
            } else {
                Mode::pair_of(medium)
                    .map(|mode| Eigenwave::new(medium, frame, cand_side, Travel::Incoming, mode))
            };
            // ã into each of the target's modes for one incident wave.
            let column = |w: &Eigenwave| -> [Complex64; 2] {
                let v = tangential_real(frame, w.e.re, w.h.re);
                let a = system.solve_real_rows(v.map(|x| x * -sigma), first, rows);
                [0, 1].map(|r| a[r] * energy_factor(w_flux[r], w.flux))
            };
            let live = |w: &Option<Eigenwave>| w.filter(|w| !w.evanescent && w.flux != 0.0);
            if medium.is_isotropic() {
                let (Some(s), Some(p)) = (live(&incoming[0]), live(&incoming[1])) else {
                    continue;
                };
                let (cs, cp) = (column(&s), column(&p));
                *result.next() = Feeder {
                    wave: basis_of(&s, Some(&p), WaveKind::Isotropic),
                    block: Jones {
                        rows,
                        cols: 2,
                        m: [[cs[0], cp[0]], [cs[1], cp[1]]],
                    },
                };
            } else {
                for w in incoming.iter().filter_map(live) {
                    let c = column(&w);
                    *result.next() = Feeder {
                        wave: basis_of(&w, None, w.mode.kind()),
                        block: Jones {
                            rows,
                            cols: 1,
                            m: [[c[0], ZERO], [c[1], ZERO]],
                        },
                    };
                }
            }
        }
    }
}

/// The candidates' part of a backward query, once the system is factored:
/// every propagating incident wave with the target's `t`, and its block.
struct Feed<'a> {
    iface: &'a Interface,
    frame: &'a TangentFrame,
    sheets: &'a [[Sheet; 2]; 2],
    /// The target's side, its number of modes, the index of its first mode
    /// among the outgoing waves, and their fluxes.
    side: Side,
    rows: usize,
    first: usize,
    w_flux: [f64; 2],
    result: &'a mut Feeders,
}

impl WithSystem for Feed<'_> {
    type Output = ();

    #[inline]
    fn with<S: Solve>(self, system: &S) {
        let Feed {
            iface,
            frame,
            sheets,
            side,
            rows,
            first,
            w_flux,
            result,
        } = self;
        // ã = a sqrt(|F_w| / |F_in|) (see `energy_factor`), with the square
        // roots of w's fluxes taken once.
        let sqrt_w = w_flux.map(|f| f.abs().sqrt());
        // The block column of one incident wave `c` of a candidate: ã into
        // each of w's modes.
        let block_column = |m: &mut [[Complex64; 2]; 2], c: usize, w: &RealWave, sgn: f64| {
            let v = tangential_real(frame, w.e, w.h);
            let a = system.solve_real_rows(v.map(|x| x * sgn), first, rows);
            let f_in = w.flux();
            if f_in != 0.0 {
                let inv = 1.0 / f_in.abs().sqrt();
                for r in 0..rows {
                    m[r][c] = a[r] * (sqrt_w[r] * inv);
                }
            } else {
                for r in 0..rows {
                    m[r][c] = a[r] * energy_factor(w_flux[r], f_in);
                }
            }
        };
        for cand_side in [side, side.opposite()] {
            let medium = iface.medium(cand_side);
            let si = cand_side.index();
            // Incoming: energy toward the interface, −σ; on the right-hand
            // side of the system with the sign −σ (see `Solve`).
            let sigma = cand_side.sign();
            match *medium {
                Medium::Isotropic { n } => {
                    // The incoming wave shares its sheet with the outgoing
                    // one of the same mode; it exists only if it propagates.
                    let sheet = &sheets[si][0];
                    if !sheet.propagates() {
                        continue;
                    }
                    let [s, p] = RealWave::isotropic_pair(n, frame, sheet, -sigma);
                    if s.flux() == 0.0 {
                        continue;
                    }
                    let mut m = [[ZERO; 2]; 2];
                    block_column(&mut m, 0, &s, -sigma);
                    block_column(&mut m, 1, &p, -sigma);
                    *result.next() = Feeder {
                        wave: WaveBasis {
                            side: cand_side,
                            kind: WaveKind::Isotropic,
                            k: s.k,
                            ray: s.ray(medium, WaveKind::Isotropic),
                            basis: [s.e, p.e],
                        },
                        block: Jones { rows, cols: 2, m },
                    };
                }
                // Biaxial media take `general_any` (see `fill`).
                Medium::Biaxial { .. } => {}
                Medium::Uniaxial { .. } => {
                    for (i, (mode, ck)) in [
                        (Mode::O, WaveKind::Ordinary),
                        (Mode::E, WaveKind::Extraordinary),
                    ]
                    .into_iter()
                    .enumerate()
                    {
                        let sheet = &sheets[si][i];
                        if !sheet.propagates() {
                            continue;
                        }
                        let w = RealWave::on_sheet(medium, frame, sheet, mode, -sigma);
                        if w.flux() == 0.0 {
                            continue;
                        }
                        let mut m = [[ZERO; 2]; 2];
                        block_column(&mut m, 0, &w, -sigma);
                        *result.next() = Feeder {
                            wave: WaveBasis {
                                side: cand_side,
                                kind: ck,
                                k: w.k,
                                ray: w.ray(medium, ck),
                                basis: [w.e, DVec3::ZERO],
                            },
                            block: Jones { rows, cols: 1, m },
                        };
                    }
                }
            }
        }
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

/// Two isotropic media: the closed forms (docs/physics.md §4.2), the target on
/// `side` in index `n_w`, the other side of index `n_x`.
#[inline]
fn isotropic_pair(frame: &TangentFrame, side: Side, n_w: f64, n_x: f64, result: &mut Feeders) {
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
    result.target = wave(side, k_w, n_w);
    if !(dw > 0.0) {
        // w grazes the interface: no normal flux to feed.
        return;
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
    *result.next() = Feeder {
        wave: wave(side, frame.t - n_dir * (sigma * q_w), n_w),
        block: diag(f.rs, f.rp),
    };
    // Transmission feeder: incident on the other side (−σ) toward w, q = σ Q_x.
    if dx > 0.0 {
        let f = fresnel_from_normals(n_x, n_w, q_x.re, Complex64::new(q_w, 0.0));
        *result.next() = Feeder {
            wave: wave(side.opposite(), frame.t + n_dir * (sigma * q_x.re), n_x),
            block: diag(f.ts_energy, f.tp_energy),
        };
    }
}
