//! The forward interface problem: one incident plane wave, every outgoing
//! wave with its amplitude (docs/physics.md §4.4; the tangential-field 4×4 method
//! of Berreman, JOSA 62, 502 (1972); Yariv & Yeh ch. 4; Born & Wolf
//! §1.5 and ch. 15).
//!
//! One 4×4 complex system covers every pair of media: the tangential
//! components (along `s` and `u = N × s`, see [`super::modes`]) of `E` and
//! `H` are continuous, the unknowns are the amplitudes of the two outgoing
//! modes on each side, and the incident field drives the system. Isotropic
//! pairs use the closed forms of [`super::fresnel`] instead (they agree with
//! the solver to rounding; the property tests check 1e-12).
//!
//! Amplitudes refer to the unit-amplitude field vectors of
//! [`Eigenwave`]; energy-normalized amplitudes are
//! `ã_j = a_j sqrt(|F_j| / |F_i|)` with `F = Re((E × H*)·N)/2`, and
//! `Σ |ã_j|² = 1` over the propagating outgoing waves.
//!
//! Radiance also scales by `n²` between media; the renderer's Jones blocks
//! use `ã` and leave that factor out, because for a camera and lights in
//! air it cancels along every closed path (docs/physics.md §4.5).

use super::directions::{k_from_wave_normal, ray_vector};
use super::fresnel::fresnel_from_normals;
use super::linalg::{CVec3, Lu2, Lu4, Scalar};
use super::medium::Medium;
use super::modes::{Eigenwave, Mode, Sheet, Side, TangentFrame, Travel};
use glam::DVec3;
use num_complex::Complex64;
use std::fmt;

/// Why an interface problem could not be set up.
#[derive(Clone, Debug, PartialEq)]
pub enum InterfaceError {
    /// A vector (normal, axis, direction, tangential component) is zero or
    /// not finite.
    BadVector(&'static str),
    /// A refractive index is not a finite positive number.
    BadIndex(f64),
    /// The mode does not exist in the medium on that side (s/p in a crystal,
    /// o/e in an isotropic medium).
    ModeNotInMedium { mode: Mode, side: Side },
    /// The wave does not carry energy toward the interface (an incident
    /// wave must).
    NotIncident,
    /// The wave does not carry energy away from the interface (the backward
    /// query needs an outgoing wave).
    NotOutgoing,
    /// No propagating wave of this mode has this tangential component.
    NoSuchWave,
    /// The boundary system is singular to working precision.
    Singular,
    /// Closed-form Fresnel was asked for a pair that is not isotropic.
    NotIsotropic,
}

impl fmt::Display for InterfaceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InterfaceError::BadVector(what) => write!(f, "{what} must be a finite non-zero vector"),
            InterfaceError::BadIndex(n) => {
                write!(f, "refractive index must be finite and positive, got {n}")
            }
            InterfaceError::ModeNotInMedium { mode, side } => {
                let side = match side {
                    Side::Plus => "incident-side (+)",
                    Side::Minus => "far-side (−)",
                };
                let has = match mode {
                    Mode::S | Mode::P => {
                        "a uniaxial crystal has modes o and e, a biaxial one fast and slow"
                    }
                    Mode::O | Mode::E => {
                        "an isotropic medium has modes s and p, a biaxial crystal fast and slow"
                    }
                    Mode::Fast | Mode::Slow => {
                        "an isotropic medium has modes s and p, a uniaxial crystal o and e"
                    }
                };
                write!(
                    f,
                    "mode {} does not exist in the {side} medium: {has}",
                    mode.name()
                )
            }
            InterfaceError::NotIncident => {
                f.write_str("the wave does not carry energy toward the interface")
            }
            InterfaceError::NotOutgoing => {
                f.write_str("the wave does not carry energy away from the interface")
            }
            InterfaceError::NoSuchWave => {
                f.write_str("no propagating wave of this mode has this tangential wave vector")
            }
            InterfaceError::Singular => f.write_str("the boundary-condition system is singular"),
            InterfaceError::NotIsotropic => {
                f.write_str("closed-form Fresnel needs isotropic media on both sides")
            }
        }
    }
}

impl std::error::Error for InterfaceError {}

/// A planar interface: unit normal `N` pointing into side +, and the media on
/// both sides at one wavelength (crystal axes unit, in the same frame as `N`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    normal: DVec3,
    media: [Medium; 2],
}

fn check_vector(v: DVec3, what: &'static str) -> Result<DVec3, InterfaceError> {
    let l = v.length();
    if !v.is_finite() || !(l > 0.0) || !l.is_finite() {
        return Err(InterfaceError::BadVector(what));
    }
    Ok(v / l)
}

fn check_medium(m: Medium) -> Result<Medium, InterfaceError> {
    let good = |n: f64| n.is_finite() && n > 0.0;
    match m {
        Medium::Isotropic { n } => {
            if good(n) {
                Ok(m)
            } else {
                Err(InterfaceError::BadIndex(n))
            }
        }
        Medium::Uniaxial { n_o, n_e, axis } => {
            for n in [n_o, n_e] {
                if !good(n) {
                    return Err(InterfaceError::BadIndex(n));
                }
            }
            Ok(Medium::Uniaxial {
                n_o,
                n_e,
                axis: check_vector(axis, "optic axis")?,
            })
        }
        Medium::Biaxial { n, x, z } => {
            for n in n {
                if !good(n) {
                    return Err(InterfaceError::BadIndex(n));
                }
            }
            check_vector(z, "crystal z axis")?;
            check_vector(x, "crystal x axis")?;
            let (z, x) = super::medium::orthonormal_axes(z, x)
                .ok_or(InterfaceError::BadVector("crystal x axis (parallel to z)"))?;
            Ok(Medium::Biaxial { n, x, z })
        }
    }
}

impl Interface {
    /// An interface with normal `normal` (normalized here) pointing into the
    /// medium `plus`; `minus` is on the other side. Optic axes are
    /// normalized too.
    pub fn new(normal: DVec3, plus: Medium, minus: Medium) -> Result<Interface, InterfaceError> {
        Ok(Interface {
            normal: check_vector(normal, "interface normal")?,
            media: [check_medium(plus)?, check_medium(minus)?],
        })
    }

    /// Unit normal, pointing into side +.
    #[inline]
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The medium on `side`.
    #[inline]
    pub fn medium(&self, side: Side) -> &Medium {
        &self.media[side.index()]
    }

    /// True when a side is a biaxial crystal (its waves come from Booker's
    /// quartic, [`super::anisotropic`]).
    #[inline]
    pub fn has_biaxial(&self) -> bool {
        self.media[0].is_biaxial() || self.media[1].is_biaxial()
    }

    /// True when both media are isotropic (closed forms apply).
    #[inline]
    pub fn is_isotropic(&self) -> bool {
        self.media[0].is_isotropic() && self.media[1].is_isotropic()
    }

    /// The tangent frame for tangential wave vector `t`.
    #[inline]
    pub fn frame(&self, t: DVec3) -> TangentFrame {
        TangentFrame::new(self.normal, t)
    }

    /// The wave vector of a `mode` wave on `side` whose wave normal is along
    /// `direction`, checked to be an incident wave: its energy must flow
    /// toward the interface (`σ (S·N) < 0`, docs/physics.md §4.1).
    pub fn incident_k(
        &self,
        side: Side,
        mode: Mode,
        direction: DVec3,
    ) -> Result<DVec3, InterfaceError> {
        let d = check_vector(direction, "incident direction")?;
        let medium = self.medium(side);
        if !mode.exists_in(medium) {
            return Err(InterfaceError::ModeNotInMedium { mode, side });
        }
        let k = k_from_wave_normal(medium, mode.kind(), d);
        let s_n = ray_vector(medium, mode.kind(), k).dot(self.normal);
        if !(side.sign() * s_n < 0.0) {
            return Err(InterfaceError::NotIncident);
        }
        Ok(k)
    }

    /// The incident `mode` wave on `side` with tangential component `t`.
    pub fn incident_wave(
        &self,
        side: Side,
        mode: Mode,
        t: DVec3,
    ) -> Result<Eigenwave, InterfaceError> {
        if !t.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        self.incident_wave_in(side, mode, &self.frame(t))
    }

    /// The incident `mode` wave on `side` in a given tangent frame.
    pub fn incident_wave_in(
        &self,
        side: Side,
        mode: Mode,
        frame: &TangentFrame,
    ) -> Result<Eigenwave, InterfaceError> {
        let medium = self.medium(side);
        if !mode.exists_in(medium) {
            return Err(InterfaceError::ModeNotInMedium { mode, side });
        }
        eigenwave(medium, frame, side, Travel::Incoming, mode).ok_or(InterfaceError::NoSuchWave)
    }

    /// The four outgoing waves for tangential component `frame.t`, in the
    /// order `[+ mode₀, + mode₁, − mode₀, − mode₁]` with modes `(s, p)` or
    /// `(o, e)`.
    #[inline]
    pub fn outgoing_waves(&self, frame: &TangentFrame) -> [Eigenwave; 4] {
        if self.has_biaxial() {
            return self.outgoing_general(frame);
        }
        self.outgoing_on(frame, &self.sheets(frame))
    }

    /// The outgoing waves when a side is biaxial: that side's from Booker's
    /// quartic, the other side's from its sheets.
    pub(crate) fn outgoing_general(&self, frame: &TangentFrame) -> [Eigenwave; 4] {
        self.general_waves(frame).outgoing
    }

    /// [`Interface::outgoing_general`] with the incoming waves of each
    /// biaxial side, which the same solve of Booker's quartic gives: a
    /// caller that needs both (an incident wave, the backward query's
    /// candidates) solves each biaxial side once, not twice.
    pub(crate) fn general_waves(&self, frame: &TangentFrame) -> GeneralWaves {
        let pair = |side: Side| -> ([Eigenwave; 2], Option<[Eigenwave; 2]>) {
            let m = self.medium(side);
            if m.is_biaxial() {
                let w = super::anisotropic::waves(m, frame, side);
                return (w.outgoing, Some(w.incoming));
            }
            let out = Mode::pair_of(m).map(|mode| {
                let sheet = Sheet::new(m, mode.kind(), frame);
                Eigenwave::on_sheet(m, frame, &sheet, side, Travel::Outgoing, mode, side.sign())
            });
            (out, None)
        };
        let ([p0, p1], p_in) = pair(Side::Plus);
        let ([m0, m1], m_in) = pair(Side::Minus);
        GeneralWaves {
            outgoing: [p0, p1, m0, m1],
            incoming: [p_in, m_in],
        }
    }

    /// The sheets `[side][mode]` at this frame (an isotropic medium's s and
    /// p share one, computed once).
    #[inline]
    pub(crate) fn sheets(&self, frame: &TangentFrame) -> [[Sheet; 2]; 2] {
        let pair = |side: Side| {
            let m = self.medium(side);
            let [m0, m1] = Mode::pair_of(m);
            let s0 = Sheet::new(m, m0.kind(), frame);
            let s1 = if m1.kind() == m0.kind() {
                s0
            } else {
                Sheet::new(m, m1.kind(), frame)
            };
            [s0, s1]
        };
        [pair(Side::Plus), pair(Side::Minus)]
    }

    /// The outgoing waves on precomputed sheets.
    #[inline]
    pub(crate) fn outgoing_on(
        &self,
        frame: &TangentFrame,
        sheets: &[[Sheet; 2]; 2],
    ) -> [Eigenwave; 4] {
        let wave = |side: Side, i: usize| {
            let m = self.medium(side);
            let mode = Mode::pair_of(m)[i];
            let sheet = &sheets[side.index()][i];
            Eigenwave::on_sheet(m, frame, sheet, side, Travel::Outgoing, mode, side.sign())
        };
        [
            wave(Side::Plus, 0),
            wave(Side::Plus, 1),
            wave(Side::Minus, 0),
            wave(Side::Minus, 1),
        ]
    }

    /// Solve the forward problem for the incident `mode` wave on `side` with
    /// tangential wave vector `t` (any normal component of `t` is ignored,
    /// so a full incident `k` may be passed): closed-form Fresnel when both
    /// media are isotropic, the 4×4 solver otherwise.
    pub fn solve(&self, side: Side, mode: Mode, t: DVec3) -> Result<Scattering, InterfaceError> {
        if !t.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        self.solve_in(side, mode, &self.frame(t))
    }

    /// [`Interface::solve`] in a given tangent frame (bit-identical inputs to
    /// a backward query that reports the same frame).
    pub fn solve_in(
        &self,
        side: Side,
        mode: Mode,
        frame: &TangentFrame,
    ) -> Result<Scattering, InterfaceError> {
        if self.is_isotropic() {
            self.closed_form_in(side, mode, frame)
        } else {
            self.solver_in(side, mode, frame)
        }
    }

    /// [`Interface::solve`] for an incident wave given by its wave-normal
    /// direction (see [`Interface::incident_k`]).
    pub fn solve_direction(
        &self,
        side: Side,
        mode: Mode,
        direction: DVec3,
    ) -> Result<Scattering, InterfaceError> {
        let k = self.incident_k(side, mode, direction)?;
        self.solve(side, mode, k)
    }

    /// The forward problem by the general 4×4 boundary-condition solve
    /// (works for every pair of media).
    pub fn solve_4x4(
        &self,
        side: Side,
        mode: Mode,
        t: DVec3,
    ) -> Result<Scattering, InterfaceError> {
        if !t.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        self.solver_in(side, mode, &self.frame(t))
    }

    fn solver_in(
        &self,
        side: Side,
        mode: Mode,
        frame: &TangentFrame,
    ) -> Result<Scattering, InterfaceError> {
        let medium = self.medium(side);
        if !mode.exists_in(medium) {
            return Err(InterfaceError::ModeNotInMedium { mode, side });
        }
        if self.has_biaxial() {
            return self.solver_general(side, mode, frame);
        }
        // The incident wave lies on the sheet its outgoing namesake uses.
        let sheets = self.sheets(frame);
        let sheet = &sheets[side.index()][mode_index(mode)];
        if !sheet.propagates() {
            return Err(InterfaceError::NoSuchWave);
        }
        let incident = Eigenwave::on_sheet(
            medium,
            frame,
            sheet,
            side,
            Travel::Incoming,
            mode,
            -side.sign(),
        );
        let out = self.outgoing_on(frame, &sheets);
        let cols = [0, 1, 2, 3].map(|j| Column::of(frame, &out[j]));
        // Incident on side σ: (+) fields − (−) fields = 0 with the incident
        // wave on the σ side moves to the right as −σ v_i.
        let sgn = -incident.side.sign();
        let rhs = if incident.evanescent {
            // Not an incident wave the solver builds (they propagate), but
            // solvable all the same.
            Column::Complex(tangential(frame, incident.e, incident.h).map(|x| x * sgn))
        } else {
            Column::Real(tangential_real(frame, incident.e.re, incident.h.re).map(|x| x * sgn))
        };
        let a =
            with_system(self, &sheets, &cols, SolveOnce(rhs)).ok_or(InterfaceError::Singular)?;
        Ok(Scattering::assemble(incident, out, a))
    }

    /// [`Interface::solver_in`] when a side is biaxial: the same 4×4
    /// boundary system on the general eigenwaves ([`super::anisotropic`]).
    fn solver_general(
        &self,
        side: Side,
        mode: Mode,
        frame: &TangentFrame,
    ) -> Result<Scattering, InterfaceError> {
        let waves = self.general_waves(frame);
        let incident = match waves.incoming[side.index()] {
            Some(pair) => incident_of(pair, mode),
            None => eigenwave(self.medium(side), frame, side, Travel::Incoming, mode),
        }
        .ok_or(InterfaceError::NoSuchWave)?;
        let out = waves.outgoing;
        let cols = [0, 1, 2, 3].map(|j| Column::of(frame, &out[j]));
        let sgn = -incident.side.sign();
        let rhs = Column::Complex(tangential(frame, incident.e, incident.h).map(|x| x * sgn));
        let a = with_full_system(&cols, SolveOnce(rhs)).ok_or(InterfaceError::Singular)?;
        Ok(Scattering::assemble(incident, out, a))
    }

    /// The forward problem for two isotropic media by the closed-form
    /// Fresnel coefficients.
    pub fn solve_closed_form(
        &self,
        side: Side,
        mode: Mode,
        t: DVec3,
    ) -> Result<Scattering, InterfaceError> {
        if !t.is_finite() {
            return Err(InterfaceError::BadVector("tangential wave vector"));
        }
        self.closed_form_in(side, mode, &self.frame(t))
    }

    fn closed_form_in(
        &self,
        side: Side,
        mode: Mode,
        frame: &TangentFrame,
    ) -> Result<Scattering, InterfaceError> {
        let (n1, n2) = match (*self.medium(side), *self.medium(side.opposite())) {
            (Medium::Isotropic { n: n1 }, Medium::Isotropic { n: n2 }) => (n1, n2),
            _ => return Err(InterfaceError::NotIsotropic),
        };
        let incident = self.incident_wave_in(side, mode, frame)?;
        let out = self.outgoing_waves(frame);
        // Q = |q| of the incident and transmitted waves (the same roots the
        // eigenwaves use), then the closed forms.
        let q1 = incident.q.re.abs();
        let tr = &out[2 * side.opposite().index()];
        let q2 = tr.q * side.opposite().sign();
        let f = fresnel_from_normals(n1, n2, q1, q2);
        let zero = Complex64::new(0.0, 0.0);
        let (r, tt) = match mode {
            Mode::S => ([f.rs, zero], [f.ts, zero]),
            _ => ([zero, f.rp], [zero, f.tp]),
        };
        let mut a = [zero; 4];
        let (ri, ti) = (2 * side.index(), 2 * side.opposite().index());
        a[ri] = r[0];
        a[ri + 1] = r[1];
        a[ti] = tt[0];
        a[ti + 1] = tt[1];
        Ok(Scattering::assemble(incident, out, a))
    }
}

/// [`Eigenwave::new`] for any medium: a biaxial one's waves from Booker's
/// quartic ([`super::anisotropic::waves`]), the wave of that name among the
/// two travelling as asked (an incident wave must propagate).
pub(crate) fn eigenwave(
    medium: &Medium,
    frame: &TangentFrame,
    side: Side,
    travel: Travel,
    mode: Mode,
) -> Option<Eigenwave> {
    if !medium.is_biaxial() {
        return Eigenwave::new(medium, frame, side, travel, mode);
    }
    let w = super::anisotropic::waves(medium, frame, side);
    match travel {
        Travel::Outgoing => w.outgoing.into_iter().find(|w| w.mode == mode),
        Travel::Incoming => incident_of(w.incoming, mode),
    }
}

/// The incident wave of name `mode` among a biaxial side's two incoming
/// waves (an incident wave must propagate).
fn incident_of(incoming: [Eigenwave; 2], mode: Mode) -> Option<Eigenwave> {
    incoming
        .into_iter()
        .find(|w| w.mode == mode)
        .filter(|w| !w.evanescent)
}

/// The waves of an interface with a biaxial side
/// ([`Interface::general_waves`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct GeneralWaves {
    /// `[+ mode₀, + mode₁, − mode₀, − mode₁]`, as [`Interface::outgoing_waves`].
    pub outgoing: [Eigenwave; 4],
    /// The incoming pair (fast first) of each side `[+, −]` that is
    /// biaxial; `None` for a side whose waves come from its sheets.
    pub incoming: [Option<[Eigenwave; 2]>; 2],
}

/// Position of `mode` in its medium's pair (`[s, p]` or `[o, e]`).
#[inline]
pub(crate) fn mode_index(mode: Mode) -> usize {
    match mode {
        Mode::S | Mode::O | Mode::Fast => 0,
        Mode::P | Mode::E | Mode::Slow => 1,
    }
}

/// The tangential components `(E·s, E·u, H·s, H·u)` of one outgoing wave:
/// a column of the boundary-condition matrix (before its side's sign).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Column {
    Real([f64; 4]),
    Complex([Complex64; 4]),
    /// Not computed: an isotropic side's waves when the other side is a
    /// crystal (their columns are known in closed form, see [`Reduced`]).
    Unused,
}

impl Column {
    /// The column of an [`Eigenwave`].
    #[inline]
    pub(crate) fn of(frame: &TangentFrame, w: &Eigenwave) -> Column {
        if w.evanescent {
            Column::Complex(tangential(frame, w.e, w.h))
        } else {
            // A propagating wave's fields are real (zero imaginary parts).
            Column::Real(tangential_real(frame, w.e.re, w.h.re))
        }
    }

    #[inline]
    fn complex(&self) -> [Complex64; 4] {
        match *self {
            Column::Real(v) => v.map(|x| Complex64::new(x, 0.0)),
            Column::Complex(v) => v,
            Column::Unused => [Complex64::new(0.0, 0.0); 4],
        }
    }
}

/// The boundary-condition system for one tangential component, factored
/// once: columns are the outgoing waves `[+₀, +₁, −₀, −₁]`, rows the
/// tangential components `(E·s, E·u, H·s, H·u)`, side − columns negated so
/// that `Σ₊ − Σ₋ = −(incident)` expresses continuity.
///
/// Between a crystal and an isotropic medium the isotropic side's two
/// modes are eliminated in closed form ([`Reduced`]), leaving a 2×2 system
/// for the crystal's o and e amplitudes; otherwise (two crystals, or two
/// isotropic media asked for the general solver) the 4×4 matrix is
/// factored by [`Lu4`] ([`Full`]), in real arithmetic when every wave
/// propagates. Each kind is its own type, built where it is used
/// ([`with_system`]): no large value is moved around.
pub(crate) trait Solve {
    /// Amplitudes `[+₀, +₁, −₀, −₁]` of the outgoing waves for the
    /// right-hand side `b` (an incident wave's tangential components times
    /// `−σ`).
    fn solve_real(&self, b: [f64; 4]) -> [Complex64; 4];
    /// The same for a complex right-hand side.
    fn solve_complex(&self, b: [Complex64; 4]) -> [Complex64; 4];

    /// The amplitudes of outgoing waves `first` and, when `rows` is 2,
    /// `first + 1` only (0 in place of the second otherwise), for a real
    /// right-hand side.
    #[inline]
    fn solve_real_rows(&self, b: [f64; 4], first: usize, rows: usize) -> [Complex64; 2] {
        let a = self.solve_real(b);
        [
            a[first],
            if rows == 2 {
                a[first + 1]
            } else {
                Complex64::new(0.0, 0.0)
            },
        ]
    }
}

/// What to do with the factored system ([`with_system`]).
pub(crate) trait WithSystem {
    type Output;
    fn with<S: Solve>(self, system: &S) -> Self::Output;
}

/// Factor the boundary system of the outgoing waves' columns `cols` (an
/// isotropic side's may be [`Column::Unused`] when the other side is a
/// crystal) and hand it to `user`; `None` when it is singular.
#[inline]
pub(crate) fn with_system<W: WithSystem>(
    iface: &Interface,
    sheets: &[[Sheet; 2]; 2],
    cols: &[Column; 4],
    user: W,
) -> Option<W::Output> {
    let iso = match (*iface.medium(Side::Plus), *iface.medium(Side::Minus)) {
        (Medium::Isotropic { n }, Medium::Uniaxial { .. }) => Some((Side::Plus, n)),
        (Medium::Uniaxial { .. }, Medium::Isotropic { n }) => Some((Side::Minus, n)),
        _ => None,
    };
    let Some((iso_side, n)) = iso else {
        return with_full_system(cols, user);
    };
    let c = 2 * iso_side.opposite().index();
    // The isotropic side's outgoing normal component (both modes).
    let sheet = &sheets[iso_side.index()][0];
    let sigma = iso_side.sign();
    match (cols[c], cols[c + 1]) {
        (Column::Real(o), Column::Real(e)) if sheet.propagates() => {
            let (q, _) = sheet.real_root(sigma);
            let system = Reduced::new(iso_side, n, q, o, e);
            system.regular().then(|| user.with(&system))
        }
        _ => {
            let (q, _) = sheet.root(sigma);
            let (o, e) = (cols[c].complex(), cols[c + 1].complex());
            let system = Reduced::new(iso_side, n, q, o, e);
            system.regular().then(|| user.with(&system))
        }
    }
}

/// Factor the full 4×4 boundary system of the outgoing waves' columns
/// (every column computed) and hand it to `user`; `None` when it is
/// singular.
#[inline]
pub(crate) fn with_full_system<W: WithSystem>(cols: &[Column; 4], user: W) -> Option<W::Output> {
    let mut lu = Lu4::zero();
    let mut real = true;
    for (j, col) in cols.iter().enumerate() {
        let sgn = if j < 2 { 1.0 } else { -1.0 };
        match col {
            Column::Real(v) => {
                for (row, x) in v.iter().enumerate() {
                    lu.set(row, j, x * sgn, 0.0);
                }
            }
            Column::Complex(v) => {
                for (row, x) in v.iter().enumerate() {
                    lu.set(row, j, x.re * sgn, x.im * sgn);
                }
                real = false;
            }
            Column::Unused => return None,
        }
    }
    if real {
        lu.factor_real_in_place()
            .then(|| user.with(&Full::<true>(&lu)))
    } else {
        lu.factor_in_place().then(|| user.with(&Full::<false>(&lu)))
    }
}

/// The 4×4 system factored by [`Lu4`]; `REAL` when every column is real
/// (factored and solved in real arithmetic).
pub(crate) struct Full<'a, const REAL: bool>(&'a Lu4);

impl Solve for Full<'_, true> {
    #[inline]
    fn solve_real(&self, b: [f64; 4]) -> [Complex64; 4] {
        self.0.solve_real(b).map(|x| Complex64::new(x, 0.0))
    }

    #[inline]
    fn solve_complex(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        let xr = self.0.solve_real(b.map(|z| z.re));
        let xi = self.0.solve_real(b.map(|z| z.im));
        [0, 1, 2, 3].map(|i| Complex64::new(xr[i], xi[i]))
    }
}

impl Solve for Full<'_, false> {
    #[inline]
    fn solve_real(&self, b: [f64; 4]) -> [Complex64; 4] {
        let (xr, xi) = self.0.solve_parts(b, [0.0; 4]);
        [0, 1, 2, 3].map(|i| Complex64::new(xr[i], xi[i]))
    }

    #[inline]
    fn solve_complex(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        let (xr, xi) = self.0.solve_parts(b.map(|z| z.re), b.map(|z| z.im));
        [0, 1, 2, 3].map(|i| Complex64::new(xr[i], xi[i]))
    }
}

impl Solve for Reduced<f64> {
    #[inline]
    fn solve_real(&self, b: [f64; 4]) -> [Complex64; 4] {
        self.solve(b).map(|x| Complex64::new(x, 0.0))
    }

    #[inline]
    fn solve_real_rows(&self, b: [f64; 4], first: usize, rows: usize) -> [Complex64; 2] {
        self.rows(b, first, rows).map(|x| Complex64::new(x, 0.0))
    }

    #[inline]
    fn solve_complex(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        let xr = self.solve(b.map(|z| z.re));
        let xi = self.solve(b.map(|z| z.im));
        [0, 1, 2, 3].map(|i| Complex64::new(xr[i], xi[i]))
    }
}

impl Solve for Reduced<Complex64> {
    #[inline]
    fn solve_real(&self, b: [f64; 4]) -> [Complex64; 4] {
        self.solve(b.map(|x| Complex64::new(x, 0.0)))
    }

    #[inline]
    fn solve_complex(&self, b: [Complex64; 4]) -> [Complex64; 4] {
        self.solve(b)
    }

    #[inline]
    fn solve_real_rows(&self, b: [f64; 4], first: usize, rows: usize) -> [Complex64; 2] {
        self.rows(b.map(|x| Complex64::new(x, 0.0)), first, rows)
    }
}

/// One solve, for the right-hand side it holds.
struct SolveOnce(Column);

impl WithSystem for SolveOnce {
    type Output = [Complex64; 4];
    #[inline]
    fn with<S: Solve>(self, system: &S) -> [Complex64; 4] {
        match self.0 {
            Column::Real(b) => system.solve_real(b),
            Column::Complex(b) => system.solve_complex(b),
            Column::Unused => [Complex64::new(0.0, 0.0); 4],
        }
    }
}

/// The boundary system between a crystal and an isotropic medium of index
/// `n`, with the isotropic side's modes eliminated in closed form.
///
/// With the conventions of [`super::modes`] (`E_s = s`, `E_p = k × s / n`,
/// `t = T u`, `k·k = T² + q² = n²`) the outgoing s and p waves of the
/// isotropic side have the tangential components
///
/// ```text
/// s: (E·s, E·u, H·s, H·u) = (1, 0,   0, q)
/// p:                        (0, q/n, −n, 0)
/// ```
///
/// (`q` their common normal component, complex when they are evanescent).
/// Rows 0 and 2 give `a_s` and `a_p` (pivots 1 and −n, never small);
/// substituting them into rows 3 and 1 leaves, with `C_r = σ_c (a_o O_r +
/// a_e E_r)` the crystal's part of row `r` and `r = q/n²`,
///
/// ```text
/// C₃ − q C₀ = b₃ − q b₀        C₁ + r C₂ = b₁ + r b₂
/// ```
///
/// a 2×2 system for `a_o`, `a_e`; then `σ_i a_s = b₀ − C₀` and
/// `σ_i a_p = (C₂ − b₂)/n`. This is Gaussian elimination with those two
/// pivots, whose multipliers `q` and `q/n²` are bounded by the indices, so
/// it is as stable as the pivoted 4×4 factorization, at a fraction of the
/// work.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reduced<T> {
    /// The isotropic side and its index.
    iso: Side,
    n: f64,
    /// Normal component of the isotropic side's outgoing waves, and q/n².
    q: T,
    r: T,
    /// Tangential components of the crystal's outgoing o and e waves.
    o: [T; 4],
    e: [T; 4],
    lu: Lu2<T>,
}

impl<T: Scalar> Reduced<T> {
    /// The system, factored; check [`Reduced::regular`] before solving.
    #[inline]
    fn new(iso: Side, n: f64, q: T, o: [T; 4], e: [T; 4]) -> Reduced<T> {
        let sigma_c = iso.opposite().sign();
        let r = q * (1.0 / (n * n));
        let m = [
            [(o[3] - q * o[0]) * sigma_c, (e[3] - q * e[0]) * sigma_c],
            [(o[1] + r * o[2]) * sigma_c, (e[1] + r * e[2]) * sigma_c],
        ];
        Reduced {
            iso,
            n,
            q,
            r,
            o,
            e,
            lu: Lu2::factor(m),
        }
    }

    /// False when the system is singular to working precision.
    #[inline]
    fn regular(&self) -> bool {
        self.lu.regular()
    }

    /// Amplitudes `[+₀, +₁, −₀, −₁]` for the right-hand side `b`.
    #[inline]
    fn solve(&self, b: [T; 4]) -> [T; 4] {
        let [a_o, a_e] = self.crystal(b);
        let [a_s, a_p] = self.isotropic(b, [a_o, a_e]);
        match self.iso {
            Side::Plus => [a_s, a_p, a_o, a_e],
            Side::Minus => [a_o, a_e, a_s, a_p],
        }
    }

    /// [`Solve::solve_real_rows`].
    #[inline]
    fn rows(&self, b: [T; 4], first: usize, rows: usize) -> [T; 2] {
        let crystal = self.crystal(b);
        let c = 2 * self.iso.opposite().index();
        if first >= c && first < c + 2 {
            match (first - c, rows) {
                (0, 2) => crystal,
                (i, _) => [crystal[i], T::ZERO],
            }
        } else {
            self.isotropic(b, crystal)
        }
    }

    /// The crystal's amplitudes `[a_o, a_e]`.
    #[inline]
    fn crystal(&self, b: [T; 4]) -> [T; 2] {
        self.lu.solve([b[3] - self.q * b[0], b[1] + self.r * b[2]])
    }

    /// The isotropic side's amplitudes `[a_s, a_p]` given the crystal's.
    #[inline]
    fn isotropic(&self, b: [T; 4], [a_o, a_e]: [T; 2]) -> [T; 2] {
        let (o, e) = (&self.o, &self.e);
        let sigma_i = self.iso.sign();
        let sigma_c = -sigma_i;
        let c0 = (o[0] * a_o + e[0] * a_e) * sigma_c;
        let c2 = (o[2] * a_o + e[2] * a_e) * sigma_c;
        [(b[0] - c0) * sigma_i, (c2 - b[2]) * (sigma_i / self.n)]
    }
}

/// Tangential components `(E·s, E·u, H·s, H·u)` of complex fields.
#[inline]
pub(crate) fn tangential(frame: &TangentFrame, e: CVec3, h: CVec3) -> [Complex64; 4] {
    [
        e.dot_real(frame.s),
        e.dot_real(frame.u),
        h.dot_real(frame.s),
        h.dot_real(frame.u),
    ]
}

/// Tangential components `(E·s, E·u, H·s, H·u)` of real fields.
#[inline]
pub(crate) fn tangential_real(frame: &TangentFrame, e: DVec3, h: DVec3) -> [f64; 4] {
    [
        e.dot(frame.s),
        e.dot(frame.u),
        h.dot(frame.s),
        h.dot(frame.u),
    ]
}

/// `sqrt(|F_out| / |F_in|)`, the factor from amplitudes to energy-normalized
/// amplitudes. A grazing incident wave (`F_in = 0`) carries no flux: in the
/// limit all of it stays in the outgoing waves that graze too (the reflected
/// copy of the incident wave, with `|r| → 1`), so those get factor 1 and all
/// others 0.
#[inline]
pub(crate) fn energy_factor(f_out: f64, f_in: f64) -> f64 {
    if f_in != 0.0 {
        (f_out / f_in).abs().sqrt()
    } else if f_out == 0.0 {
        1.0
    } else {
        0.0
    }
}

/// One outgoing wave of a forward solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outgoing {
    pub wave: Eigenwave,
    /// Complex amplitude `a` (field = `a · wave.e` for a unit incident wave).
    pub amplitude: Complex64,
    /// Energy-normalized amplitude `ã = a sqrt(|F_out|/|F_in|)` (0 when
    /// evanescent).
    pub normalized: Complex64,
    /// Fraction of the incident normal energy flux, `|ã|²` (0 when
    /// evanescent).
    pub energy: f64,
}

impl Outgoing {
    /// True when this wave is on the incident side.
    #[inline]
    pub fn is_reflected(&self, incident: &Eigenwave) -> bool {
        self.wave.side == incident.side
    }
}

/// The result of a forward solve: the incident wave and the four outgoing
/// modes, reflected pair first: `[reflected mode₀, reflected mode₁,
/// transmitted mode₀, transmitted mode₁]` with modes `(s, p)` or `(o, e)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scattering {
    pub incident: Eigenwave,
    pub outgoing: [Outgoing; 4],
}

impl Scattering {
    /// Build from outgoing waves and amplitudes in physical-side order
    /// `[+₀, +₁, −₀, −₁]`.
    fn assemble(incident: Eigenwave, out: [Eigenwave; 4], a: [Complex64; 4]) -> Scattering {
        let f_in = incident.flux;
        let make = |j: usize| {
            let w = out[j];
            // Evanescent waves carry no flux: ã = 0 (also when F_in = 0).
            let factor = if w.evanescent {
                0.0
            } else {
                energy_factor(w.flux, f_in)
            };
            let normalized = a[j] * factor;
            Outgoing {
                wave: w,
                amplitude: a[j],
                normalized,
                energy: normalized.norm_sqr(),
            }
        };
        let (r, t) = (
            2 * incident.side.index(),
            2 * incident.side.opposite().index(),
        );
        Scattering {
            incident,
            outgoing: [make(r), make(r + 1), make(t), make(t + 1)],
        }
    }

    /// The two reflected modes.
    #[inline]
    pub fn reflected(&self) -> &[Outgoing] {
        &self.outgoing[..2]
    }

    /// The two transmitted modes.
    #[inline]
    pub fn transmitted(&self) -> &[Outgoing] {
        &self.outgoing[2..]
    }

    /// Sum of the energy fractions of all outgoing waves (1 up to rounding).
    #[inline]
    pub fn energy_sum(&self) -> f64 {
        self.outgoing.iter().map(|o| o.energy).sum()
    }

    /// The outgoing wave of `side` and `mode`, if any.
    #[inline]
    pub fn find(&self, side: Side, mode: Mode) -> Option<&Outgoing> {
        self.outgoing
            .iter()
            .find(|o| o.wave.side == side && o.wave.mode == mode)
    }

    /// The total outgoing field `Σ a_j E_j` on `side` (physical, independent
    /// of how each mode's field vector is chosen).
    #[inline]
    pub fn field_on(&self, side: Side) -> CVec3 {
        self.outgoing
            .iter()
            .filter(|o| o.wave.side == side)
            .fold(CVec3::ZERO, |acc, o| acc + o.wave.e.scale(o.amplitude))
    }
}
