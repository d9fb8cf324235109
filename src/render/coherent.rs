//! The physical model of light (`coherence = "physical"`, docs/physics.md
//! §9): the paths of one camera sample that reach the same mode of the
//! same light add as complex amplitudes before a coherence matrix is
//! formed; other paths add as intensities.
//!
//! The tree is walked as in the incoherent model ([`super::integrator`]),
//! but a backward ray carries the transfer matrix `A` of its path (from its
//! wave's modes to the camera's basis, the product of the Jones blocks and
//! changes of basis along it) and its optical path length instead of
//! returning coherence matrices. Where a path reaches a light it becomes a
//! [`Leaf`]. A sample's leaves are then grouped by source mode: the same
//! light and the same direction of travel (within [`SAME_DIRECTION`]). For
//! a group `g` and a wavelength λ (§9.2):
//!
//! `J = Σ_{i,j ∈ g} γ_ij exp(i(φ_i − φ_j)) M_i J_L M_jᴴ`,
//!
//! `M_i` the transfer from the light's field basis to the camera's, `φ_i =
//! 2π L_i / λ` the phase of the optical path `L_i = Σ k·Δr` (the wave
//! vector of each segment's own eigenwave, in units of the vacuum wave
//! number, so an extraordinary wave's phase follows its wave normal while
//! its ray walks off), `J_L` the light's coherence matrix at unit radiance
//! scaled by the geometric mean of the two paths' radiances, and `γ_ij` the
//! product of the light's spatial coherence (1 for a light at infinity:
//! one direction is one plane wave; for an area light, van Cittert–Zernike:
//! the Fourier transform of its parallelogram seen from the path, `sinc(π
//! δ·θ_u / λ) sinc(π δ·θ_v / λ)` for paths δ apart and its angular edge
//! vectors θ_u, θ_v) and
//! the band's temporal coherence (`sinc(π ΔL Δλ / λ²)` for a flat band Δλ
//! wide). Groups are found by sorting, not by comparing every pair.

use super::absorb;
use super::integrator::{
    feeder_side, max_gain, CameraHit, Departure, Meeting, Region, Stats, Traced, Tracer,
    WavelengthMedia,
};
use super::sampling::SampleKey;
use crate::optics::backward::Feeders;
use crate::optics::modes::WaveKind;
use crate::optics::{Coherence, Jones};
use glam::DVec3;
use num_complex::Complex64;
use std::cell::RefCell;

/// Two paths travel in the same direction when their unit directions
/// differ by at most this much (radians, about): paths through parallel
/// flat faces agree to rounding (1e-15), paths through different facets
/// differ by far more.
pub const SAME_DIRECTION: f64 = 1e-9;

/// Which light a path reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Source {
    /// The uniform background, or the environment
    /// ([`crate::render::world::Scene::environment`]) where the scene has
    /// one: light at infinity from every direction, each direction a
    /// plane wave of its own.
    Background,
    /// Area light `i` of [`crate::render::world::Scene::lights`].
    Area(u32),
    /// Light at infinity `i` of
    /// [`crate::render::world::Scene::distant_lights`].
    Distant(u32),
}

/// A path that reached a light.
#[derive(Clone, Copy, Debug)]
struct Leaf {
    /// Camera basis (rows) ← the light's field basis [`source_basis`]
    /// (columns): the path's amplitude transfer, sampling weight included.
    m: [[Complex64; 2]; 2],
    /// Optical path length from the light's plane-wave reference (the
    /// world origin) to the camera, scene units.
    opl: f64,
    source: Source,
    /// Unit direction the light travels where the path leaves for it.
    k: DVec3,
    /// Where the path leaves for the light (a surface point, or the
    /// camera).
    point: DVec3,
    /// Face coordinates on an area light.
    st: (f64, f64),
    /// An area light's edges `u`, `v` as seen from `point`: their parts
    /// across `k` divided by the distance (the projected parallelogram's
    /// angular edge vectors, radians).
    extent: [DVec3; 2],
    /// The intensity the path keeps through absorbing media, per
    /// wavelength: an entry of [`Scratch::kept`] (`UNABSORBED`: all).
    kept: u32,
    /// The last roulette decision on the path: an entry of
    /// [`Scratch::roulette`] (`UNROULETTED`: none).
    roulette: u32,
}

/// A path that no roulette decision weighted.
const UNROULETTED: u32 = u32::MAX;

/// One roulette decision a path survived (Russian roulette, integrator's
/// [`Tracer::roulette`]): the decision above it on the same path, and the
/// product of 1/p of every decision from the camera down to this one.
#[derive(Clone, Copy, Debug)]
struct Decision {
    parent: u32,
    weight: f64,
}

/// A path that crossed no absorbing medium.
const UNABSORBED: u32 = u32::MAX;

/// One backward ray of the coherent walk.
#[derive(Clone, Copy, Debug)]
struct Path {
    /// Where the ray is traced from (offset from the surface it leaves).
    origin: DVec3,
    /// The exact point the ray leaves (on the surface, or the camera):
    /// phases are measured from here.
    anchor: DVec3,
    dir: DVec3,
    region: Region,
    kind: WaveKind,
    depth: u32,
    /// Product of the gains along the path (the bound pruning tests).
    throughput: f64,
    /// Which branch of the full tree this is (random numbers).
    branch: u64,
    /// Wave vector of the wave on this segment, units of the vacuum wave
    /// number.
    k: DVec3,
    /// Optical path length from this segment's far end to the camera.
    opl: f64,
    /// Camera basis ← the modes of the basis this ray was asked in.
    a: Jones,
    /// The intensity kept through absorbing media so far, per
    /// wavelength (an entry of [`Scratch::kept`], or `UNABSORBED`).
    kept: u32,
    /// The sampling weights from the camera to this ray (as the incoherent
    /// tree's `Query::weight`: what roulette compares).
    weight: f64,
    /// The last roulette decision on the path (`UNROULETTED`: none).
    roulette: u32,
    /// The surface the ray leaves (`None`: the camera's).
    from: Option<Departure>,
}

/// What every backward ray of one camera sample's walk shares: the
/// wavelengths, the sample's random numbers, and where its leaves and
/// their absorption go.
struct Walk<'b> {
    batch: &'b [WavelengthMedia],
    key: &'b SampleKey,
    leaves: &'b mut Vec<Leaf>,
    kept: &'b mut Vec<f64>,
    roulette: &'b mut Vec<Decision>,
}

thread_local! {
    /// Each rayon worker's buffers for one camera sample, kept between
    /// samples so the walk and the grouping allocate nothing once warm.
    static SCRATCH: RefCell<Scratch> = const { RefCell::new(Scratch::new()) };
}

/// The buffers of [`Tracer::trace_coherent`].
struct Scratch {
    leaves: Vec<Leaf>,
    /// The leaves' indices, sorted by source and direction.
    order: Vec<u32>,
    /// The first leaf of each leaf's group (`u32::MAX`: none yet).
    group_of: Vec<u32>,
    /// The group being summed.
    members: Vec<u32>,
    /// The coherence matrix at each wavelength being summed.
    acc: Vec<[[Complex64; 2]; 2]>,
    /// Entries of one value per wavelength of the batch: the fraction of
    /// intensity a path keeps through the absorbing media it crossed
    /// (Beer–Lambert, docs/physics.md §11); a path's amplitude keeps its
    /// square root. Appended as paths cross absorbing segments.
    kept: Vec<f64>,
    /// The roulette decisions the sample's paths survived, appended as
    /// they are made (a decision's parent comes before it).
    roulette: Vec<Decision>,
}

impl Scratch {
    const fn new() -> Scratch {
        Scratch {
            leaves: Vec::new(),
            order: Vec::new(),
            group_of: Vec::new(),
            members: Vec::new(),
            acc: Vec::new(),
            kept: Vec::new(),
            roulette: Vec::new(),
        }
    }
}

/// The light's field basis for a path leaving along `k`: `e1` the
/// reference `r` made transverse to `k`, `e2 = k × e1` (right-handed
/// with `k`). Every path of a group has the same `k` (to rounding), and
/// so the same basis.
fn source_basis(k: DVec3, r: DVec3) -> [DVec3; 2] {
    let mut e1 = (r - r.dot(k) * k).normalize_or_zero();
    if e1 == DVec3::ZERO {
        e1 = k.any_orthonormal_vector();
    }
    [e1, k.cross(e1)]
}

/// The factor that turns the product of two paths' amplitudes, each
/// carrying √(1/p) of its own roulette decisions, into the weight the
/// pair's cross term needs: 1/p of every decision on either path, a
/// decision both share counted once. The cumulative weights of paths `a`
/// and `b` are `W_a`, `W_b` and of their shared decisions `W_s`: the
/// factor is `√(W_a W_b) / W_s`.
fn roulette_pair(decisions: &[Decision], a: u32, b: u32) -> f64 {
    let weight = |d: u32| {
        if d == UNROULETTED {
            1.0
        } else {
            decisions[d as usize].weight
        }
    };
    // The deepest decision on both paths: parents precede their children,
    // so step the later of the two up until they meet.
    let (mut x, mut y) = (a, b);
    while x != y && x != UNROULETTED && y != UNROULETTED {
        if x > y {
            x = decisions[x as usize].parent;
        } else {
            y = decisions[y as usize].parent;
        }
    }
    let shared = if x == y { weight(x) } else { 1.0 };
    (weight(a) * weight(b)).sqrt() / shared
}

/// `sin(x) / x`, the Fourier transform of a rectangle: the coherence of a
/// flat band at a path difference that makes `x = π ΔL Δλ / λ²` (Born &
/// Wolf §7.5.8), and along each edge of a uniform rectangular source at a
/// separation that makes `x = π δ θ / λ` (van Cittert–Zernike, B&W §10.4).
pub fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-8 {
        1.0
    } else {
        x.sin() / x
    }
}

fn c(re: f64) -> Complex64 {
    Complex64::new(re, 0.0)
}

/// `a · b · cᴴ` for 2×2 complex matrices.
#[inline]
fn sandwich(
    a: &[[Complex64; 2]; 2],
    b: &[[Complex64; 2]; 2],
    cm: &[[Complex64; 2]; 2],
) -> [[Complex64; 2]; 2] {
    let mut ab = [[Complex64::new(0.0, 0.0); 2]; 2];
    for r in 0..2 {
        for k in 0..2 {
            ab[r][k] = a[r][0] * b[0][k] + a[r][1] * b[1][k];
        }
    }
    let mut out = [[Complex64::new(0.0, 0.0); 2]; 2];
    for r in 0..2 {
        for k in 0..2 {
            out[r][k] = ab[r][0] * cm[k][0].conj() + ab[r][1] * cm[k][1].conj();
        }
    }
    out
}

impl Tracer<'_> {
    /// [`Tracer::trace_camera`] in the physical model.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn trace_coherent(
        &self,
        first: &CameraHit,
        basis: [DVec3; 2],
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let (origin, dir) = first.ray();
        SCRATCH.with(|cell| {
            let scratch = &mut *cell.borrow_mut();
            scratch.leaves.clear();
            scratch.kept.clear();
            scratch.roulette.clear();
            let root = Path {
                origin,
                anchor: origin,
                dir,
                region: Region::Ambient,
                kind: WaveKind::Isotropic,
                depth: 0,
                throughput: 1.0,
                branch: 0,
                k: -dir,
                opl: 0.0,
                a: Jones::identity(2),
                kept: UNABSORBED,
                weight: 1.0,
                roulette: UNROULETTED,
                from: None,
            };
            let mut walk = Walk {
                batch,
                key,
                leaves: &mut scratch.leaves,
                kept: &mut scratch.kept,
                roulette: &mut scratch.roulette,
            };
            stats.rays += 1;
            let traced = first.traced(stats);
            self.walk_traced(&root, &basis, traced, &mut walk, stats);
            stats.coherent += self.sum_leaves(scratch, batch, out);
        });
    }

    /// Follows one backward ray, pushing a leaf for every path that reaches
    /// a light. `basis` is the basis the ray's wave was asked in.
    fn walk(&self, p: &Path, basis: &[DVec3; 2], w: &mut Walk<'_>, stats: &mut Stats) {
        stats.rays += 1;
        let traced = self.trace(p.origin, p.dir, p.region, p.from, stats);
        self.walk_traced(p, basis, traced, w, stats);
    }

    /// [`Self::walk`] for a ray already traced (`None`: it could not be,
    /// and was counted lost).
    fn walk_traced(
        &self,
        p: &Path,
        basis: &[DVec3; 2],
        traced: Option<Traced>,
        w: &mut Walk<'_>,
        stats: &mut Stats,
    ) {
        let Some(Traced { ray, hit, t_hit }) = traced else {
            return;
        };
        if p.region == Region::Ambient && self.reach_light(p, basis, t_hit, w.leaves) {
            return;
        }
        let media = &w.batch[0];
        // Inside an absorbing object: the fraction of intensity the path
        // keeps at each wavelength after this segment (appended to
        // `w.kept`), and the pruning bound lowered by the most it keeps.
        let mut kept = p.kept;
        let mut throughput_here = p.throughput;
        if let (Some(object), Some(r), Some(h)) = (self.absorbing(p.region), &ray, &hit) {
            let weights = self.segment_weights(object, p.kind, p.anchor, p.dir, r, h, media);
            let n = w.batch.len();
            let entry = w.kept.len();
            for (i, m) in w.batch.iter().enumerate() {
                let before = if p.kept == UNABSORBED {
                    1.0
                } else {
                    w.kept[p.kept as usize * n + i]
                };
                let after = before * (-absorb::depth(weights, m.absorption[object as usize])).exp();
                w.kept.push(after);
            }
            kept = (entry / n) as u32;
            throughput_here *= self.kept_at_most(object, weights, w.batch);
        }
        let mut feeders = Feeders::EMPTY;
        let Some(Meeting {
            ray,
            hit,
            normal,
            other,
        }) = self.node_into(
            ray,
            hit,
            p.region,
            p.kind,
            p.dir,
            p.depth,
            media,
            stats,
            &mut feeders,
        )
        else {
            return;
        };
        stats.nodes += 1;
        // The hit on the facet's plane along this path's own line from its
        // anchor: the traced ray started `epsilon` off the surface, which
        // would shift the phase by up to ε·|t|²/k_N (tenths of a wave).
        let traced = ray.at(hit.t);
        let denom = p.dir.dot(normal);
        let s = (traced - p.anchor).dot(normal) / denom;
        let point = if s.is_finite() && s > 0.0 && denom.abs() > 1e-12 {
            p.anchor + s * p.dir
        } else {
            traced
        };
        // Forward, the segment's wave travels from `point` to the anchor.
        let opl = p.opl + p.k.dot(p.anchor - point);
        let target = feeders.target;
        let list = feeders.as_slice();
        // The target's field in the basis this ray was asked in.
        let into_asked = Jones::change_of_basis(
            &target.basis[..target.modes()],
            &basis[..p.kind.mode_count()],
        );
        let a_node = p.a.product(&into_asked);
        let gains: [f64; 4] =
            std::array::from_fn(|i| list.get(i).map_or(0.0, |f| max_gain(&f.block)));

        let (sampled, (chosen, n_chosen)) =
            self.choose(&gains, list.len(), p.depth, p.branch, w.key);
        for &(i, weight) in &chosen[..n_chosen] {
            let f = &list[i];
            let throughput = throughput_here * gains[i];
            if throughput < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            let branch = if sampled {
                p.branch
            } else {
                p.branch.wrapping_mul(4).wrapping_add(i as u64 + 1)
            };
            let Some(survived) =
                self.roulette(throughput * p.weight * weight, p.depth, branch, w.key)
            else {
                stats.rouletted += 1;
                continue;
            };
            // A roulette survivor's 1/p goes on its intensity (√ on its
            // amplitude); the decision is recorded so that pairs of
            // coherent paths weight it once per decision (`add_group`).
            let mut roulette = p.roulette;
            if survived != 1.0 {
                let above = if roulette == UNROULETTED {
                    1.0
                } else {
                    w.roulette[roulette as usize].weight
                };
                roulette = w.roulette.len() as u32;
                w.roulette.push(Decision {
                    parent: p.roulette,
                    weight: above * survived,
                });
            }
            let (region, offset) = feeder_side(f.wave.side, p.region, other, normal);
            // A sampled branch stands for its siblings with weight 1/p on
            // its intensity: √weight on its amplitude.
            let mut a = a_node.product(&f.block);
            if weight * survived != 1.0 {
                a = a.scaled(c((weight * survived).sqrt()));
            }
            let child = Path {
                // Traced from the backend's hit, as the incoherent tree is
                // (so both models follow the same rays); phases from the
                // exact point.
                origin: traced + self.epsilon(hit.geom) * offset,
                anchor: point,
                dir: -f.wave.ray,
                region,
                kind: f.wave.kind,
                depth: p.depth + 1,
                throughput,
                branch,
                k: f.wave.k,
                opl,
                a,
                kept,
                weight: p.weight * weight * survived,
                roulette,
                from: Some(Departure {
                    object: hit.geom,
                    normal: offset,
                }),
            };
            self.walk(&child, &f.wave.basis, w, stats);
        }
    }

    /// For a ray in air: pushes the leaf of the light it reaches before
    /// `t_hit` (the nearest area light in front of the nearest surface;
    /// with no surface, a light at infinity it looks into, or the
    /// background) and returns true when the ray ends there.
    fn reach_light(
        &self,
        p: &Path,
        basis: &[DVec3; 2],
        t_hit: f64,
        leaves: &mut Vec<Leaf>,
    ) -> bool {
        let scene = self.scene;
        let k = -p.dir;
        let best = self.nearest_light(p.origin, p.dir, t_hit);
        let (source, reference, st, extent) = if let Some((t, i, s, tt)) = best {
            let light = &scene.lights[i];
            let across = |e: DVec3| (e - e.dot(k) * k) / t;
            let extent = [across(light.u), across(light.v)];
            (Source::Area(i as u32), light.u, (s, tt), extent)
        } else if t_hit.is_finite() {
            return false;
        } else if let Some(i) = scene
            .distant_lights
            .iter()
            .position(|l| l.seen_along(p.dir))
        {
            let l = &scene.distant_lights[i];
            (
                Source::Distant(i as u32),
                l.direction.any_orthonormal_vector(),
                (0.0, 0.0),
                [DVec3::ZERO; 2],
            )
        } else if scene.background > 0.0 || scene.environment.is_some() {
            (Source::Background, DVec3::Z, (0.0, 0.0), [DVec3::ZERO; 2])
        } else {
            return true;
        };
        let sb = source_basis(k, reference);
        let m = p.a.product(&Jones::change_of_basis(&sb, basis));
        leaves.push(Leaf {
            m: m.m,
            opl: p.opl + k.dot(p.anchor),
            source,
            k,
            point: p.anchor,
            st,
            extent,
            kept: p.kept,
            roulette: p.roulette,
        });
        true
    }

    /// The camera's coherence matrix at each wavelength of `batch` from a
    /// sample's leaves (module docs); returns how many leaves joined a
    /// group of two or more.
    fn sum_leaves(
        &self,
        scratch: &mut Scratch,
        batch: &[WavelengthMedia],
        out: &mut [Coherence],
    ) -> u64 {
        let Scratch {
            leaves,
            order,
            group_of,
            members,
            acc,
            kept,
            roulette,
        } = scratch;
        let mut coherent = 0;
        acc.clear();
        acc.resize(batch.len(), [[Complex64::new(0.0, 0.0); 2]; 2]);
        // Sort by source, then by the first direction component, and sweep:
        // each leaf joins the first earlier leaf of its source whose
        // direction matches (a group's members then follow its first).
        order.clear();
        order.extend(0..leaves.len() as u32);
        order.sort_unstable_by(|&a, &b| {
            let (la, lb) = (&leaves[a as usize], &leaves[b as usize]);
            la.source.cmp(&lb.source).then(la.k.x.total_cmp(&lb.k.x))
        });
        group_of.clear();
        group_of.resize(leaves.len(), u32::MAX);
        for (pos, &i) in order.iter().enumerate() {
            if group_of[i as usize] != u32::MAX {
                continue;
            }
            let li = &leaves[i as usize];
            members.clear();
            members.push(i);
            group_of[i as usize] = i;
            for &j in &order[pos + 1..] {
                let lj = &leaves[j as usize];
                if lj.source != li.source || lj.k.x - li.k.x > SAME_DIRECTION {
                    break;
                }
                if group_of[j as usize] == u32::MAX
                    && (lj.k - li.k).length_squared() <= SAME_DIRECTION * SAME_DIRECTION
                {
                    group_of[j as usize] = i;
                    members.push(j);
                }
            }
            if members.len() > 1 {
                coherent += members.len() as u64;
            }
            self.add_group(leaves, members, (kept, roulette), batch, acc);
        }
        for (o, a) in out.iter_mut().zip(acc.iter()) {
            *o = Coherence::from_matrix(*a);
        }
        coherent
    }

    /// Adds one group's `Σ γ_ij e^{i(φ_i − φ_j)} √(l_i l_j) M_i J M_jᴴ` at
    /// every wavelength (module docs).
    fn add_group(
        &self,
        leaves: &[Leaf],
        members: &[u32],
        (kept, roulette): (&[f64], &[Decision]),
        batch: &[WavelengthMedia],
        acc: &mut [[[Complex64; 2]; 2]],
    ) {
        let scene = self.scene;
        let first = &leaves[members[0] as usize];
        // The light's state at unit radiance, in the group's source basis.
        // (The same references as [`Self::reach_light`]'s.)
        let state = match first.source {
            Source::Background => Coherence::unpolarized(1.0),
            Source::Area(i) => {
                let l = &scene.lights[i as usize];
                let b = source_basis(first.k, l.u);
                l.state(first.k, b[0], b[1])
            }
            Source::Distant(i) => {
                let l = &scene.distant_lights[i as usize];
                let b = source_basis(first.k, l.direction.any_orthonormal_vector());
                l.state(first.k, b[0], b[1])
            }
        };
        let j_l = state.matrix();
        // The radiance a leaf brings at wavelength `i` of the batch, times
        // the intensity its path keeps through absorbing media (so a pair's
        // √(l_i l_j) carries each amplitude's e^{−τ/2}).
        let n = batch.len();
        let radiance = |leaf: &Leaf, i: usize, lambda: f64| -> f64 {
            let through = if leaf.kept == UNABSORBED {
                1.0
            } else {
                kept[leaf.kept as usize * n + i]
            };
            through
                * match leaf.source {
                    Source::Background => match &scene.environment {
                        Some(env) => env.spectral_radiance(leaf.k, lambda),
                        None => scene.background * crate::spectrum::cie::d65(lambda),
                    },
                    Source::Area(i) => {
                        scene.lights[i as usize].spectral_radiance(leaf.st.0, leaf.st.1, lambda)
                    }
                    Source::Distant(i) => {
                        scene.distant_lights[i as usize].spectral_radiance(lambda)
                    }
                }
        };
        let unit = scene.unit_nm;
        for (w, (m, a)) in batch.iter().zip(acc.iter_mut()).enumerate() {
            let lambda = m.lambda_nm;
            if members.len() == 1 {
                let l = radiance(first, w, lambda);
                if l == 0.0 {
                    continue;
                }
                let x = sandwich(&first.m, &j_l, &first.m);
                for r in 0..2 {
                    for col in 0..2 {
                        a[r][col] += x[r][col] * l;
                    }
                }
                continue;
            }
            let k0 = 2.0 * std::f64::consts::PI / lambda;
            for (ii, &i) in members.iter().enumerate() {
                let li = &leaves[i as usize];
                let ri = radiance(li, w, lambda);
                if ri == 0.0 {
                    continue;
                }
                let x = sandwich(&li.m, &j_l, &li.m);
                for r in 0..2 {
                    for col in 0..2 {
                        a[r][col] += x[r][col] * ri;
                    }
                }
                for &j in &members[ii + 1..] {
                    let lj = &leaves[j as usize];
                    let rj = radiance(lj, w, lambda);
                    if rj == 0.0 {
                        continue;
                    }
                    let dl = (li.opl - lj.opl) * unit;
                    let mut gamma = sinc(std::f64::consts::PI * dl * m.band_nm / (lambda * lambda));
                    if let Source::Area(_) = li.source {
                        // van Cittert–Zernike for the light's projected
                        // parallelogram (docs/physics.md §9.3).
                        let d = li.point - lj.point;
                        let across = (d - d.dot(li.k) * li.k) * (unit / lambda);
                        gamma *= sinc(std::f64::consts::PI * across.dot(li.extent[0]))
                            * sinc(std::f64::consts::PI * across.dot(li.extent[1]));
                    }
                    if gamma == 0.0 {
                        continue;
                    }
                    // Each amplitude carries √(1/p) of its path's roulette
                    // decisions; the pair's term needs 1/p once per
                    // decision on either path (unbiased: a shared decision
                    // keeps or drops both).
                    let pair = roulette_pair(roulette, li.roulette, lj.roulette);
                    let phase = Complex64::from_polar(gamma * (ri * rj).sqrt() * pair, k0 * dl);
                    let x = sandwich(&li.m, &j_l, &lj.m);
                    // X + Xᴴ: the (i, j) and (j, i) terms.
                    for r in 0..2 {
                        for col in 0..2 {
                            a[r][col] += x[r][col] * phase + (x[col][r] * phase).conj();
                        }
                    }
                }
            }
        }
    }
}
