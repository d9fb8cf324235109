//! The backward ray-tree integrator with forward physics (optics.md §5).
//!
//! A camera ray is a forward wave arriving at the camera, traced backward.
//! At each surface it meets, the interface solver's backward query lists
//! the forward incident waves that feed it (reflection and refraction, o and
//! e modes in crystals) with their Jones blocks; each feeder is traced
//! further back, and the node sums `T J Tᴴ` over its feeders. Every call
//! returns the coherence matrix of its wave in the basis its caller names:
//! a 2×2 matrix for a wave in an isotropic medium, a scalar intensity for an
//! eigenwave (o or e) of a crystal.
//!
//! Radiance and the n² factor: radiance scales by n² between media
//! (optics.md §4). The camera and every light are in air (n = 1), so along
//! any closed path from a light to the camera the factors of the media
//! entered and left cancel, and the integrator leaves them out: the Jones
//! blocks carry energy-normalized amplitudes only.
//!
//! Air here has n = 1 exactly (the ambient medium of every scene).
//!
//! Model limits, stated so nobody mistakes them for bugs:
//! - The o and e waves of a crystal are traced as separate, mutually
//!   incoherent rays (the seed paper's model, right when their paths
//!   differ by more than the light's coherence length). Where they do not
//!   separate — along the optic axis — physics would recombine them
//!   coherently and polarized light would pass unchanged; here it is
//!   depolarized by an amount that depends on how the degenerate o/e split
//!   is oriented. Unpolarized light is unaffected (tests/render_hard_cases).
//! - Objects must not overlap or touch: a ray inside one object that meets
//!   another is counted as lost.

use crate::accel::{Intersector, Ray};
use crate::optics::backward::Feeders;
use crate::optics::modes::{Side, WaveKind};
use crate::optics::{Coherence, Interface, Jones, Medium};
use crate::scene::Scene;
use glam::DVec3;

/// The medium of air around every object.
pub const AMBIENT: Medium = Medium::Isotropic { n: 1.0 };

/// Where a backward ray travels: in air, or inside object `i`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    Ambient,
    Inside(u32),
}

/// Counters of one render, summed over threads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Rays traced (camera rays and every backward ray of every tree).
    pub rays: u64,
    /// Interface nodes evaluated (backward queries).
    pub nodes: u64,
    /// Subtrees skipped by the pruning bound.
    pub pruned: u64,
    /// Rays stopped by the depth limit while still inside the scene's
    /// objects.
    pub depth_cut: u64,
    /// Rays that found themselves inconsistent with the geometry (leaving a
    /// closed mesh without a hit, or meeting a facet from the wrong side):
    /// counted and given zero radiance.
    pub lost: u64,
}

impl std::ops::AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.rays += o.rays;
        self.nodes += o.nodes;
        self.pruned += o.pruned;
        self.depth_cut += o.depth_cut;
        self.lost += o.lost;
    }
}

/// Everything about one wavelength that does not change per ray: the media
/// of every object.
#[derive(Clone, Debug)]
pub struct WavelengthMedia {
    pub lambda_nm: f64,
    pub objects: Vec<Medium>,
}

impl WavelengthMedia {
    pub fn new(scene: &Scene, lambda_nm: f64) -> WavelengthMedia {
        WavelengthMedia {
            lambda_nm,
            objects: scene
                .objects
                .iter()
                .map(|o| {
                    o.material
                        .medium(lambda_nm, o.material.axis().unwrap_or(DVec3::ZERO))
                })
                .collect(),
        }
    }
}

/// Settings of the tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TreeSettings {
    /// Largest number of surface interactions along a path.
    pub max_depth: u32,
    /// Skip a subtree when its contribution bound (throughput × brightest
    /// radiance) is below this fraction of the brightest radiance.
    pub prune: f64,
}

/// Traces backward trees through one scene.
pub struct Tracer<'a> {
    scene: &'a Scene,
    accel: &'a dyn Intersector,
    settings: TreeSettings,
    /// Offset of secondary ray origins from the surface, in scene units.
    epsilon: f64,
}

/// One backward ray: the forward wave of `kind` that arrives at `origin`
/// travelling along `-dir`.
#[derive(Clone, Copy, Debug)]
struct Query {
    origin: DVec3,
    dir: DVec3,
    region: Region,
    kind: WaveKind,
    depth: u32,
    throughput: f64,
}

/// Largest squared singular value of a Jones block: the most intensity it
/// can pass (λ_max of TᴴT, closed form for 2×2).
#[inline]
fn max_gain(t: &Jones) -> f64 {
    let col = |c: usize| (0..t.rows).map(|r| t.m[r][c].norm_sqr()).sum::<f64>();
    if t.cols == 1 {
        return col(0);
    }
    let a = col(0);
    let d = col(1);
    let b = (0..t.rows)
        .map(|r| t.m[r][0].conj() * t.m[r][1])
        .sum::<num_complex::Complex64>();
    0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b.norm_sqr()).sqrt()
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, accel: &'a dyn Intersector, settings: TreeSettings) -> Tracer<'a> {
        let extent = scene
            .objects
            .iter()
            .map(|o| {
                let (lo, hi) = o.mesh.bounds();
                (hi - lo)
                    .max_element()
                    .max(lo.abs().max_element())
                    .max(hi.abs().max_element())
            })
            .fold(0.0, f64::max);
        Tracer {
            scene,
            accel,
            settings,
            // Embree works in f32: hit points are good to a few 1e-7 of the
            // scene's extent; step well clear of that.
            epsilon: 1e-5 * extent.max(1e-30),
        }
    }

    /// The coherence matrix, in the basis `basis` (two unit vectors
    /// transverse to `dir`), of the light arriving at `origin` along `−dir`
    /// in air: a camera ray.
    pub fn camera_ray(
        &self,
        origin: DVec3,
        dir: DVec3,
        basis: [DVec3; 2],
        media: &WavelengthMedia,
        stats: &mut Stats,
    ) -> Coherence {
        let q = Query {
            origin,
            dir,
            region: Region::Ambient,
            kind: WaveKind::Isotropic,
            depth: 0,
            throughput: 1.0,
        };
        self.radiance(&q, &basis, media, stats)
    }

    fn medium_of(&self, region: Region, media: &WavelengthMedia) -> Medium {
        match region {
            Region::Ambient => AMBIENT,
            Region::Inside(i) => media.objects[i as usize],
        }
    }

    /// The light of `q`'s wave in `basis` (ignored for a one-mode wave).
    fn radiance(
        &self,
        q: &Query,
        basis: &[DVec3; 2],
        media: &WavelengthMedia,
        stats: &mut Stats,
    ) -> Coherence {
        stats.rays += 1;
        let modes = q.kind.mode_count();
        let ray = Ray::new(q.origin, q.dir);
        let hit = self.accel.intersect(&ray);
        let t_hit = hit.map_or(f64::INFINITY, |h| h.t);

        if q.region == Region::Ambient {
            // The nearest light in front of the nearest surface.
            let mut best: Option<(f64, usize, f64, f64)> = None;
            for (i, light) in self.scene.lights.iter().enumerate() {
                if let Some((t, s, tt)) = light.hit(q.origin, q.dir) {
                    if t < t_hit && best.is_none_or(|b| t < b.0) {
                        best = Some((t, i, s, tt));
                    }
                }
            }
            if let Some((_, i, s, tt)) = best {
                return self.scene.lights[i].emitted(
                    s,
                    tt,
                    media.lambda_nm,
                    -q.dir,
                    basis[0],
                    basis[1],
                );
            }
            if hit.is_none() {
                let l = self.scene.background * crate::spectrum::cie::d65(media.lambda_nm);
                return Coherence::unpolarized(l);
            }
        }
        let Some(hit) = hit else {
            // Inside a closed mesh every ray must hit it again.
            stats.lost += 1;
            return Coherence::zero(modes);
        };
        if q.depth >= self.settings.max_depth {
            stats.depth_cut += 1;
            return Coherence::zero(modes);
        }
        let object = hit.geom;
        let outward = self.scene.objects[object as usize]
            .mesh
            .triangle_normal(hit.prim);
        // Side + is where our wave lives: outside when we come from air.
        let (normal, other) = match q.region {
            Region::Ambient => (outward, Region::Inside(object)),
            Region::Inside(i) if i == object => (-outward, Region::Ambient),
            Region::Inside(_) => {
                // Objects must not overlap or touch.
                stats.lost += 1;
                return Coherence::zero(modes);
            }
        };
        let leaving = -q.dir;
        if !(leaving.dot(normal) > 0.0) {
            // Met the facet from its far side (a grazing ray at an edge):
            // no outgoing wave on our side to feed.
            stats.lost += 1;
            return Coherence::zero(modes);
        }
        let Ok(iface) = Interface::new(
            normal,
            self.medium_of(q.region, media),
            self.medium_of(other, media),
        ) else {
            stats.lost += 1;
            return Coherence::zero(modes);
        };
        let Ok(feeders): Result<Feeders, _> = iface.feeders(Side::Plus, q.kind, leaving) else {
            stats.lost += 1;
            return Coherence::zero(modes);
        };
        stats.nodes += 1;
        let point = ray.at(hit.t);
        let target = feeders.target;
        let mut sum = Coherence::zero(target.modes());
        for f in feeders.as_slice() {
            let throughput = q.throughput * max_gain(&f.block);
            if throughput < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            let (region, offset) = match f.wave.side {
                Side::Plus => (q.region, normal),
                Side::Minus => (other, -normal),
            };
            let child = Query {
                origin: point + self.epsilon * offset,
                dir: -f.wave.ray,
                region,
                kind: f.wave.kind,
                depth: q.depth + 1,
                throughput,
            };
            let fb = &f.wave.basis;
            let j = self.radiance(&child, fb, media, stats);
            sum += j.transform(&f.block);
        }
        if modes == 2 {
            sum.change_basis(&target.basis, basis)
        } else {
            sum
        }
    }
}
