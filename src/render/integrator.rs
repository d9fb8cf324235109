//! The backward ray-tree integrator with forward physics (docs/physics.md §5).
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
//! (docs/physics.md §4.5). The camera and every light are in air (n = 1), so along
//! any closed path from a light to the camera the factors of the media
//! entered and left cancel, and the integrator leaves them out: the Jones
//! blocks carry energy-normalized amplitudes only.
//!
//! Air here has n = 1 exactly (the ambient medium of every scene).
//!
//! This file is the incoherent model (`coherence = "incoherent"`) and what
//! both models share; the physical model, where paths from one source
//! mode add as amplitudes, is [`super::coherent`] (docs/physics.md §9).
//!
//! Model limits, stated so nobody mistakes them for bugs:
//! - Incoherent model: the o and e waves of a crystal are traced as
//!   separate, mutually incoherent rays (the seed paper's model, right
//!   when their paths differ by more than the light's coherence length).
//!   Where they do not separate — along the optic axis — physics would
//!   recombine them coherently and polarized light would pass unchanged;
//!   here it is depolarized by an amount that depends on how the
//!   degenerate o/e split is oriented. Unpolarized light is unaffected
//!   (tests/render/render_hard_cases). The physical model recombines them.
//! - Objects must not overlap or touch, and the camera must not be inside
//!   one: scene loading refuses both (`geometry::overlap`). Should a ray
//!   inside one object still meet another, it is counted as lost
//!   ([`LostCauses::overlap`]).
//!
//! Rays that arrive from outside the scene's bounding sphere (camera rays
//! of a distant camera) are started at that sphere, moved along the ray in
//! f64: the same ray, so exact for any camera, but the backend's f32
//! arithmetic then works at the scene's scale, not the camera's distance.

use crate::accel::convex::{ConvexInterior, Exit};
use crate::accel::{Hit, Intersector, Ray};
use crate::optics::backward::Feeders;
use crate::optics::modes::{Side, WaveKind};
use crate::optics::{Coherence, Interface, Jones, Medium};
use crate::render::absorb;
use crate::render::approx::{Branching, CoherenceModel, PolarizationModel, Strategy};
use crate::render::sampling::{dim, SampleKey};
use crate::render::world::Scene;
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
    /// counted and given zero radiance. The sum of [`Self::causes`].
    pub lost: u64,
    /// The lost rays by what the integrator saw.
    pub causes: LostCauses,
    /// Paths that added as amplitudes with at least one other path of
    /// their camera sample (the physical model's coherent groups,
    /// docs/physics.md §9.3); 0 in the incoherent model.
    pub coherent: u64,
    /// Nodes where a crystal's o and e waves travelled as one bundle
    /// (`render::bundle`): each stands for a node of both members.
    pub bundled: u64,
    /// Bundles whose members parted (different facets, or farther apart
    /// than the tolerance) and continued as exact rays.
    pub splits: u64,
    /// Camera samples taken (pixels × samples, fewer with adaptive
    /// sampling).
    pub samples: u64,
    /// Subtrees ended by Russian roulette (`roulette`, [`Tracer::roulette`]).
    pub rouletted: u64,
}

/// Lost rays by cause. Rays stopped by the depth limit are not lost light
/// in this sense (they are [`Stats::depth_cut`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LostCauses {
    /// A camera ray met its first surface from inside the object: the
    /// camera is inside an object (or the mesh is inside out).
    pub camera_inside: u64,
    /// A ray inside one object met another object's surface: the objects
    /// overlap or touch.
    pub overlap: u64,
    /// A ray inside an object left without meeting its surface again: an
    /// open (leaky) mesh, or precision at an edge.
    pub escaped: u64,
    /// A secondary ray met a facet from its far side: a self-intersecting
    /// mesh, objects inside one another, or a grazing ray at an edge.
    pub wrong_side: u64,
    /// The interface solver found no consistent waves (degenerate input).
    pub solver: u64,
    /// A ray a backend cannot trace (non-finite or too large coordinates).
    pub untraceable: u64,
}

impl std::ops::AddAssign for LostCauses {
    fn add_assign(&mut self, o: LostCauses) {
        self.camera_inside += o.camera_inside;
        self.overlap += o.overlap;
        self.escaped += o.escaped;
        self.wrong_side += o.wrong_side;
        self.solver += o.solver;
        self.untraceable += o.untraceable;
    }
}

impl std::ops::AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.rays += o.rays;
        self.nodes += o.nodes;
        self.pruned += o.pruned;
        self.depth_cut += o.depth_cut;
        self.lost += o.lost;
        self.causes += o.causes;
        self.coherent += o.coherent;
        self.bundled += o.bundled;
        self.splits += o.splits;
        self.samples += o.samples;
        self.rouletted += o.rouletted;
    }
}

/// The fraction of traced rays above which lost light is reported: 1e-4.
/// The scenes shipped in `scenes/` stay below it on both backends
/// (tests/render/render_lost_light.rs); the broken scenes of issue 15 lost 0.05
/// to 1 of their rays.
pub const LOST_WARNING_FRACTION: f64 = 1e-4;

impl Stats {
    /// Counts a lost ray of one cause.
    #[inline]
    pub(super) fn lose(&mut self, cause: fn(&mut LostCauses) -> &mut u64) {
        self.lost += 1;
        *cause(&mut self.causes) += 1;
    }

    /// The lost rays by cause, e.g. "3 overlap, 1 escaped" (empty when none
    /// was lost).
    pub fn lost_breakdown(&self) -> String {
        let c = &self.causes;
        [
            (c.camera_inside, "camera inside"),
            (c.overlap, "overlap"),
            (c.escaped, "escaped"),
            (c.wrong_side, "wrong side"),
            (c.solver, "solver"),
            (c.untraceable, "untraceable"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// Fraction of the traced rays that were lost.
    pub fn lost_fraction(&self) -> f64 {
        if self.rays == 0 {
            0.0
        } else {
            self.lost as f64 / self.rays as f64
        }
    }

    /// A warning when more than [`LOST_WARNING_FRACTION`] of the rays were
    /// lost: the count, the fraction, and the likely reasons, most frequent
    /// first; `None` otherwise.
    pub fn lost_light_warning(&self) -> Option<String> {
        if self.lost == 0 || self.lost_fraction() <= LOST_WARNING_FRACTION {
            return None;
        }
        let c = &self.causes;
        let mut reasons: Vec<(u64, &str)> = vec![
            (
                c.camera_inside,
                "camera rays started inside an object (is the camera inside a stone?)",
            ),
            (
                c.overlap,
                "rays inside one object met another (objects overlap or touch)",
            ),
            (
                c.escaped,
                "rays inside an object escaped without meeting its surface (an open or leaky \
                 mesh, or f32 precision: is the scene very large or far from the origin?)",
            ),
            (
                c.wrong_side,
                "rays met a facet from its back (a self-intersecting or inside-out mesh, or \
                 an object inside another)",
            ),
            (c.solver, "the interface solver found no consistent waves"),
            (
                c.untraceable,
                "rays had coordinates the backend cannot trace (non-finite or beyond 1e18)",
            ),
        ];
        reasons.retain(|r| r.0 > 0);
        reasons.sort_by_key(|r| std::cmp::Reverse(r.0));
        let list: Vec<String> = reasons
            .iter()
            .map(|(n, why)| format!("{n} because {why}"))
            .collect();
        Some(format!(
            "{} of {} rays ({:.2e}, more than {:.0e}) were lost and rendered black: {}",
            self.lost,
            self.rays,
            self.lost_fraction(),
            LOST_WARNING_FRACTION,
            list.join("; ")
        ))
    }
}

/// Everything about one wavelength that does not change per ray: the
/// wavelength whose emission is gathered, and the media of every object
/// (evaluated at `lambda_nm`, or at another wavelength when dispersion is
/// switched off).
#[derive(Clone, Debug)]
pub struct WavelengthMedia {
    pub lambda_nm: f64,
    pub objects: Vec<Medium>,
    /// Width of the band of the spectrum this wavelength stands for, nm
    /// (0: one wavelength, fully coherent): cross terms between coherent
    /// paths are weighted by the band's coherence (docs/physics.md §9.4).
    pub band_nm: f64,
    /// Each object's absorption coefficients `[α_o, α_e]` at `lambda_nm`
    /// (the emission's wavelength, not the geometry's), per scene unit
    /// (docs/physics.md §11); zeros for a colourless object.
    pub absorption: Vec<[f64; 2]>,
}

impl WavelengthMedia {
    /// Emission and media at `lambda_nm`.
    pub fn new(scene: &Scene, lambda_nm: f64) -> WavelengthMedia {
        WavelengthMedia::with_geometry_at(scene, lambda_nm, lambda_nm)
    }

    /// Emission at `lambda_nm`, media (and so every path) at
    /// `geometry_nm`: the "dispersion off" approximation, and the exact
    /// description of a scene whose indices do not depend on wavelength.
    pub fn with_geometry_at(scene: &Scene, lambda_nm: f64, geometry_nm: f64) -> WavelengthMedia {
        WavelengthMedia {
            lambda_nm,
            band_nm: 0.0,
            absorption: scene
                .objects
                .iter()
                .map(|o| {
                    o.material.absorption().map_or([0.0; 2], |a| {
                        // Coefficients are per mm; one scene unit is
                        // `unit_nm` nm.
                        let (a_o, a_e) = a.per_mm(lambda_nm);
                        let mm = scene.unit_nm * 1e-6;
                        [a_o * mm, a_e * mm]
                    })
                })
                .collect(),
            objects: scene
                .objects
                .iter()
                .map(|o| {
                    o.material
                        .medium(geometry_nm, o.material.axis().unwrap_or(DVec3::ZERO))
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
    /// Rays inside a convex object leave it by its facet planes
    /// ([`crate::accel::convex`]) instead of asking the backend: the same
    /// hits to f64 rounding, fewer instructions. On in every render; off
    /// only to compare with the backend's own hits.
    pub convex_exit: bool,
}

/// Where a feeder on `side` of a node travels, and which way its ray's
/// origin steps off the surface: the node's own region and along `normal`
/// for a reflection feeder (side +), the far region and against it for a
/// transmission feeder.
#[inline]
pub(super) fn feeder_side(
    side: Side,
    here: Region,
    other: Region,
    normal: DVec3,
) -> (Region, DVec3) {
    match side {
        Side::Plus => (here, normal),
        Side::Minus => (other, -normal),
    }
}

/// A traced backward ray: the ray handed to the backend (`None` when it
/// misses the scene's bounding sphere), its hit, and the query's own ray
/// parameter at the hit (∞ without one).
#[derive(Clone, Copy, Debug)]
pub(super) struct Traced {
    pub ray: Option<Ray>,
    pub hit: Option<Hit>,
    pub t_hit: f64,
}

/// A camera ray traced into the scene once, for every batch of
/// wavelengths of a sample: a ray in air meets the same surface at every
/// wavelength ([`Tracer::camera_hit`]).
#[derive(Clone, Copy, Debug)]
pub struct CameraHit {
    origin: DVec3,
    dir: DVec3,
    /// `None`: the backend could not trace it (each batch counts it lost).
    traced: Option<Traced>,
}

impl CameraHit {
    /// The camera ray's origin and direction.
    pub fn ray(&self) -> (DVec3, DVec3) {
        (self.origin, self.dir)
    }

    /// Whether the ray was traced and meets no object (it reaches a light
    /// or leaves the scene): a path every wavelength shares.
    pub fn meets_no_object(&self) -> bool {
        self.traced.is_some_and(|t| t.hit.is_none())
    }

    /// The traced ray, counting it lost in `stats` when it could not be.
    pub(super) fn traced(&self, stats: &mut Stats) -> Option<Traced> {
        if self.traced.is_none() {
            stats.lose(|c| &mut c.untraceable);
        }
        self.traced
    }
}

/// Where a secondary ray starts: on object `object`'s surface, stepped off
/// it along `normal` (the unit normal on the ray's side). A ray in air that
/// leaves a convex object this way cannot meet that object again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Departure {
    pub object: u32,
    pub normal: DVec3,
}

/// A surface a backward ray met, ready for the interface solver: the
/// backend's ray and hit, the normal into the ray's side, the region on
/// the far side, and the feeders of the ray's wave.
pub(super) struct Node {
    pub ray: Ray,
    pub hit: Hit,
    pub normal: DVec3,
    pub other: Region,
    pub feeders: Feeders,
}

/// A [`Node`] without its feeders: what [`Tracer::node_into`] returns
/// while it writes the feeders where the caller keeps them.
pub(super) struct Meeting {
    pub ray: Ray,
    pub hit: Hit,
    pub normal: DVec3,
    pub other: Region,
}

/// The feeders a node follows, each with the weight of its contribution
/// (`.1` of them used).
pub(super) type Chosen = ([(usize, f64); 4], usize);

/// Traces backward trees through one scene.
pub struct Tracer<'a> {
    pub(super) scene: &'a Scene,
    pub(super) accel: &'a dyn Intersector,
    pub(super) settings: TreeSettings,
    pub(super) strategy: Strategy,
    /// Offset of secondary ray origins from the surface of each object,
    /// in scene units ([`Tracer::epsilon`]).
    epsilon: Vec<f64>,
    /// A sphere (centre, radius) around every object: rays from outside it
    /// are started on it.
    bounds: Option<(DVec3, f64)>,
    /// Which objects absorb (the rest skip Beer–Lambert altogether).
    absorbing: Vec<bool>,
    /// The facet planes of each convex object: rays inside it leave by
    /// them without the backend ([`crate::accel::convex`]).
    convex: Vec<Option<ConvexInterior>>,
    /// Each object's bounding box, padded past the f32 rounding of the
    /// backend's copy of it: a ray that meets none of them meets nothing.
    boxes: Vec<(DVec3, DVec3)>,
}

/// One backward ray: the forward wave of `kind` that arrives at `origin`
/// travelling along `-dir`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Query {
    pub origin: DVec3,
    pub dir: DVec3,
    pub region: Region,
    pub kind: WaveKind,
    pub depth: u32,
    /// Product of the gains along the path (the bound pruning tests).
    pub throughput: f64,
    /// Which branch of the full part of the tree this is (for random
    /// numbers that differ between sibling subtrees).
    pub path: u64,
    /// The largest angle, radians, between this path's light and its
    /// exact ray, from waves that bundles carried on another wave's ray
    /// (render::bundle; 0 without bundles).
    pub drift: f64,
    /// The surface point the segment leaves (`origin` is a little off
    /// it): where an absorbing segment's length is measured from.
    pub anchor: DVec3,
    /// The product of the sampling weights (1/p of sampled branches and of
    /// roulette) from the camera to this ray: with `throughput`, what
    /// roulette compares with its threshold. 1 in the exact tree.
    pub weight: f64,
    /// The surface the ray leaves (`None`: the camera's).
    pub from: Option<Departure>,
}

/// Largest squared singular value of a Jones block: the most intensity it
/// can pass (λ_max of TᴴT, closed form for 2×2).
#[inline]
pub(super) fn max_gain(t: &Jones) -> f64 {
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

/// Intensity a block passes from unpolarized light: ‖T‖²_F / cols.
#[inline]
fn unpolarized_gain(t: &Jones) -> f64 {
    t.norm_sqr() / t.cols as f64
}

/// Whether the ray `origin + t dir`, t ≥ 0, meets the box `(lo, hi)`
/// (slabs; a 0·∞ on a slab's face is dropped by `min`/`max`, which keeps
/// the ray in that slab: the answer errs towards meeting).
#[inline]
fn ray_meets_box(origin: DVec3, dir: DVec3, (lo, hi): (DVec3, DVec3)) -> bool {
    let inv = dir.recip();
    let a = (lo - origin) * inv;
    let b = (hi - origin) * inv;
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element();
    !(far < near)
}

/// The facet planes of each object a ray inside can leave by alone: a
/// convex one whose bounding box meets no other object's (then nothing
/// else can stand between a point inside it and its surface, even in a
/// scene built without the loader's overlap checks).
fn convex_interiors(scene: &Scene, enabled: bool) -> Vec<Option<ConvexInterior>> {
    let boxes: Vec<(DVec3, DVec3)> = scene.objects.iter().map(|o| o.mesh.bounds()).collect();
    let apart =
        |a: &(DVec3, DVec3), b: &(DVec3, DVec3)| a.1.cmplt(b.0).any() || b.1.cmplt(a.0).any();
    scene
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let alone = boxes
                .iter()
                .enumerate()
                .all(|(j, b)| j == i || apart(&boxes[i], b));
            if enabled && alone {
                ConvexInterior::new(&o.mesh)
            } else {
                None
            }
        })
        .collect()
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, accel: &'a dyn Intersector, settings: TreeSettings) -> Tracer<'a> {
        // How far each object reaches: its size or its distance from the
        // origin, whichever is larger (what f32 coordinates on it are
        // relative to).
        let reach: Vec<f64> = scene
            .objects
            .iter()
            .map(|o| {
                let (lo, hi) = o.mesh.bounds();
                (hi - lo)
                    .max_element()
                    .max(lo.abs().max_element())
                    .max(hi.abs().max_element())
            })
            .collect();
        let extent = reach.iter().copied().fold(0.0, f64::max);
        let bounds = scene
            .objects
            .iter()
            .map(|o| o.mesh.bounds())
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
            .map(|(lo, hi)| {
                let centre = 0.5 * (lo + hi);
                // Padded so that the f32 rounding of the geometry stays
                // inside.
                let radius = 0.5 * (hi - lo).length() * 1.01 + 1e-6 * extent;
                (centre, radius)
            });
        Tracer {
            scene,
            accel,
            settings,
            bounds,
            strategy: Strategy::default(),
            // Embree works in f32: a hit on an object is good to a few
            // 1e-7 of the object's reach; step well clear of that. Per
            // object, not per scene: a 0.5 µm film near the origin keeps a
            // 50 nm offset however far away another object stands (with
            // the scene's extent it stepped through the film).
            epsilon: reach.iter().map(|r| 1e-5 * r.max(1e-30)).collect(),
            absorbing: scene
                .objects
                .iter()
                .map(|o| o.material.absorption().is_some())
                .collect(),
            convex: convex_interiors(scene, settings.convex_exit),
            boxes: scene
                .objects
                .iter()
                .zip(&reach)
                .map(|(o, r)| {
                    let (lo, hi) = o.mesh.bounds();
                    let pad = DVec3::splat(1e-6 * r);
                    (lo - pad, hi + pad)
                })
                .collect(),
        }
    }

    /// How far a secondary ray leaving object `object` starts from its
    /// surface, in scene units: 1e-5 of the object's reach (its size or
    /// its distance from the origin, whichever is larger).
    #[inline]
    pub(super) fn epsilon(&self, object: u32) -> f64 {
        self.epsilon[object as usize]
    }

    /// The object `region` is inside when it absorbs, else `None`.
    #[inline]
    pub(super) fn absorbing(&self, region: Region) -> Option<u32> {
        match region {
            Region::Inside(i) if self.absorbing[i as usize] => Some(i),
            _ => None,
        }
    }

    /// The weights `[w_o, w_e]` of the segment of a wave of `kind` inside
    /// absorbing object `object`, from `anchor` along `dir` to the traced
    /// hit `hit` of `ray` (its optical depth at each wavelength is
    /// `absorb::depth(w, media.absorption[object])`).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn segment_weights(
        &self,
        object: u32,
        kind: WaveKind,
        anchor: DVec3,
        dir: DVec3,
        ray: &Ray,
        hit: &Hit,
        media: &WavelengthMedia,
    ) -> [f64; 2] {
        let normal = self.scene.objects[hit.geom as usize]
            .mesh
            .triangle_normal(hit.prim);
        let length = absorb::segment_length(anchor, dir, ray.at(hit.t), normal);
        absorb::segment_weights(&media.objects[object as usize], kind, dir, length)
    }

    /// The largest fraction of intensity a segment of weights `w` inside
    /// `object` keeps at any wavelength of `batch` (the bound pruning
    /// multiplies in).
    #[inline]
    pub(super) fn kept_at_most(&self, object: u32, w: [f64; 2], batch: &[WavelengthMedia]) -> f64 {
        let least = batch
            .iter()
            .map(|m| absorb::depth(w, m.absorption[object as usize]))
            .fold(f64::INFINITY, f64::min);
        (-least).exp()
    }

    /// How many pixel footprints apart a bundle's members may be and
    /// still travel together (0: no bundles).
    #[inline]
    pub(super) fn bundle_tolerance(&self) -> f64 {
        self.strategy.bundle
    }

    /// The angle one pixel spans ([`crate::render::camera::Camera::pixel_angle`]).
    #[inline]
    pub(super) fn pixel_angle(&self) -> f64 {
        self.scene.camera.pixel_angle()
    }

    /// One pixel's footprint at `point` ([`crate::render::camera::Camera::footprint`]).
    #[inline]
    pub(super) fn footprint(&self, point: DVec3) -> f64 {
        self.scene.camera.footprint(point)
    }

    /// The same tracer with another strategy.
    pub fn with_strategy(mut self, strategy: Strategy) -> Tracer<'a> {
        self.strategy = strategy;
        self
    }

    /// True when paths add as amplitudes ([`CoherenceModel::Physical`]
    /// with the full polarization model: the scalar model carries
    /// intensities only, so its paths add as intensities).
    pub fn is_coherent(&self) -> bool {
        self.strategy.coherence == CoherenceModel::Physical
            && self.strategy.polarization == PolarizationModel::Full
    }

    /// True when one camera sample's estimate may be an unphysical
    /// coherence matrix (a negative intensity or a degree of polarization
    /// above 1) while the mean of many is right: sampled decisions (roulette,
    /// sampled branching) in the physical model, where a surviving path's
    /// weighted cross terms with its partners can outweigh its own light.
    /// Such estimates are summed as they are (`Coherence::stokes_linear`):
    /// clipping each to a physical state would bias the image.
    pub fn estimates_may_be_unphysical(&self) -> bool {
        self.is_coherent()
            && (self.strategy.roulette > 0.0 || self.strategy.branching != Branching::Full)
    }

    /// The coherence matrix, in the basis `basis` (two unit vectors
    /// transverse to `dir`), of the light arriving at `origin` along `−dir`
    /// in air: a camera ray at one wavelength, with the full tree (a
    /// sampled strategy uses sample key 0 here; see [`Self::trace_camera`]).
    pub fn camera_ray(
        &self,
        origin: DVec3,
        dir: DVec3,
        basis: [DVec3; 2],
        media: &WavelengthMedia,
        stats: &mut Stats,
    ) -> Coherence {
        let key = SampleKey {
            seed: 0,
            pixel: 0,
            sample: 0,
        };
        let mut out = [Coherence::zero(2)];
        self.trace_camera(
            origin,
            dir,
            basis,
            std::slice::from_ref(media),
            &key,
            &mut out,
            stats,
        );
        out[0]
    }

    /// The camera ray from `origin` along `dir`, traced to the first
    /// surface it meets: what [`Self::trace_camera_from`] starts every
    /// batch of wavelengths of one sample from.
    pub fn camera_hit(&self, origin: DVec3, dir: DVec3) -> CameraHit {
        // A ray the backend cannot trace is counted lost where it is used.
        let mut ignored = Stats::default();
        CameraHit {
            origin,
            dir,
            traced: self.trace(origin, dir, Region::Ambient, None, &mut ignored),
        }
    }

    /// A camera ray for a batch of wavelengths that share their geometry
    /// (every entry of `batch` has the same media, as in a scene without
    /// dispersion or with dispersion switched off): the tree is traced once
    /// and every leaf is evaluated at every wavelength. `out[i]` receives
    /// the coherence matrix at `batch[i].lambda_nm` in `basis`. `key` names
    /// the random numbers of sampled strategies.
    #[allow(clippy::too_many_arguments)]
    pub fn trace_camera(
        &self,
        origin: DVec3,
        dir: DVec3,
        basis: [DVec3; 2],
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let first = self.camera_hit(origin, dir);
        self.trace_camera_from(&first, basis, batch, key, out, stats);
    }

    /// [`Self::trace_camera`] for a camera ray already traced to its first
    /// surface ([`Self::camera_hit`]): the batches of one sample share it.
    /// A camera ray that meets no object takes a batch of any media (they
    /// differ only where a ray meets an object).
    pub fn trace_camera_from(
        &self,
        first: &CameraHit,
        basis: [DVec3; 2],
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let (origin, dir) = first.ray();
        assert_eq!(batch.len(), out.len());
        debug_assert!(
            first.meets_no_object() || batch.iter().all(|m| m.objects == batch[0].objects),
            "a batch must share its geometry"
        );
        if self.is_coherent() {
            return self.trace_coherent(first, basis, batch, key, out, stats);
        }
        let q = Query {
            origin,
            dir,
            region: Region::Ambient,
            kind: WaveKind::Isotropic,
            depth: 0,
            throughput: 1.0,
            path: 0,
            drift: 0.0,
            anchor: origin,
            weight: 1.0,
            from: None,
        };
        // One slot of `batch` matrices per level of the tree below the root
        // (twice that with bundles: a bundle that splits hands its members
        // a slot at its own depth).
        let levels = self.settings.max_depth as usize + 1;
        let levels = if self.strategy.bundle > 0.0 {
            2 * levels
        } else {
            levels
        };
        let mut scratch = vec![Coherence::zero(1); batch.len() * levels];
        stats.rays += 1;
        let traced = first.traced(stats);
        self.radiance_traced(&q, traced, &basis, batch, key, out, &mut scratch, stats);
    }

    /// The ray to hand the backend for a query from `origin` along `dir`,
    /// and the parameter along the query's ray where it starts: the query
    /// itself from inside the scene's bounding sphere; from outside, the
    /// same line started where it enters the sphere (in f64, so no
    /// precision is lost), or `None` when it misses the sphere and so every
    /// object.
    #[inline]
    fn start_in_bounds(&self, origin: DVec3, dir: DVec3) -> (Option<Ray>, f64) {
        let Some((centre, radius)) = self.bounds else {
            return (None, 0.0);
        };
        let oc = origin - centre;
        let c = oc.length_squared() - radius * radius;
        if !(c > 0.0) {
            return (Some(Ray::new(origin, dir)), 0.0);
        }
        let a = dir.length_squared();
        let b = oc.dot(dir);
        let disc = b * b - a * c;
        if b >= 0.0 || disc < 0.0 {
            // Moving away from the sphere, or passing it by.
            return if disc.is_finite() && b.is_finite() {
                (None, 0.0)
            } else {
                (Some(Ray::new(origin, dir)), 0.0)
            };
        }
        // The nearer root, in the cancellation-free form.
        let t0 = c / (-b + disc.sqrt());
        let start = origin + t0 * dir;
        if !start.is_finite() {
            return (Some(Ray::new(origin, dir)), 0.0);
        }
        (Some(Ray::new(start, dir)), t0)
    }

    /// Intersects the backward ray from `origin` along `dir` (started on
    /// the scene's bounding sphere when it comes from outside); `None`
    /// when the backend cannot trace it (counted lost).
    pub(super) fn trace(
        &self,
        origin: DVec3,
        dir: DVec3,
        region: Region,
        from: Option<Departure>,
        stats: &mut Stats,
    ) -> Option<Traced> {
        if region == Region::Ambient
            && from.is_some_and(|d| self.leaves_for_nothing(origin, dir, d))
        {
            return Some(Traced {
                ray: Some(Ray::new(origin, dir)),
                hit: None,
                t_hit: f64::INFINITY,
            });
        }
        // Inside a convex object its facet planes say where the ray leaves
        // (a ray the planes are unsure of goes to the backend).
        if let Region::Inside(object) = region {
            if let Some(cell) = &self.convex[object as usize] {
                if let Exit::Facet { t, facet, prim } = cell.exit(origin, dir) {
                    let ray = Ray::new(origin, dir);
                    // The renderer reads t, geom and prim; the barycentric
                    // coordinates are not computed (0), the normal is the
                    // facet's.
                    let hit = Hit {
                        t,
                        geom: object,
                        prim,
                        u: 0.0,
                        v: 0.0,
                        ng: self.scene.objects[object as usize].mesh.facets[facet as usize].normal,
                    };
                    return Some(Traced {
                        ray: Some(ray),
                        hit: Some(hit),
                        t_hit: t,
                    });
                }
            }
        }
        // The ray handed to the backend starts `t0` along the query's.
        let (ray, t0) = self.start_in_bounds(origin, dir);
        let hit = match ray {
            Some(ray) if crate::accel::traceable(&ray) => self.accel.intersect(&ray),
            Some(_) => {
                stats.lose(|c| &mut c.untraceable);
                return None;
            }
            None => None,
        };
        let t_hit = hit.map_or(f64::INFINITY, |h| h.t + t0);
        Some(Traced { ray, hit, t_hit })
    }

    /// True when the ray in air from `origin` along `dir`, started off a
    /// convex object's surface by `from`, can meet no object: it moves away
    /// from the plane it leaves (the object lies behind that plane, within
    /// [`crate::accel::convex::CONVEX_TOLERANCE`], far less than the
    /// origin's offset) and misses every other object's box. The backend
    /// would find no hit; most rays in a gem's tree that reach air are
    /// such rays (a stone's exterior reflections and every ray that leaves
    /// it), so they skip the backend.
    #[inline]
    fn leaves_for_nothing(&self, origin: DVec3, dir: DVec3, from: Departure) -> bool {
        let object = from.object as usize;
        self.convex[object].is_some()
            && dir.dot(from.normal) > 0.0
            && origin.is_finite()
            && dir.is_finite()
            && self
                .boxes
                .iter()
                .enumerate()
                .all(|(j, b)| j == object || !ray_meets_box(origin, dir, *b))
    }

    /// The nearest area light in front of `t_hit` along the ray from
    /// `origin` along `dir`: (t, index, face coordinates s and t).
    pub(super) fn nearest_light(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_hit: f64,
    ) -> Option<(f64, usize, f64, f64)> {
        let mut best: Option<(f64, usize, f64, f64)> = None;
        for (i, light) in self.scene.lights.iter().enumerate() {
            if let Some((t, s, tt)) = light.hit(origin, dir) {
                if t < t_hit && best.is_none_or(|b| t < b.0) {
                    best = Some((t, i, s, tt));
                }
            }
        }
        best
    }

    /// The node where a backward ray of wave `kind` in `region`, travelling
    /// along `dir`, meets the surface: `None` (counted: escaped, depth
    /// cut, overlap, wrong side or solver) when there is no wave to
    /// continue.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn node(
        &self,
        ray: Option<Ray>,
        hit: Option<Hit>,
        region: Region,
        kind: WaveKind,
        dir: DVec3,
        depth: u32,
        media: &WavelengthMedia,
        stats: &mut Stats,
    ) -> Option<Node> {
        let mut feeders = Feeders::EMPTY;
        let Meeting {
            ray,
            hit,
            normal,
            other,
        } = self.node_into(
            ray,
            hit,
            region,
            kind,
            dir,
            depth,
            media,
            stats,
            &mut feeders,
        )?;
        Some(Node {
            ray,
            hit,
            normal,
            other,
            feeders,
        })
    }

    /// [`Tracer::node`] with the feeders written into `feeders` (the
    /// renderer's hot path: a node's feeders are nearly a kilobyte, and
    /// returning them would copy them once or twice a ray).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn node_into(
        &self,
        ray: Option<Ray>,
        hit: Option<Hit>,
        region: Region,
        kind: WaveKind,
        dir: DVec3,
        depth: u32,
        media: &WavelengthMedia,
        stats: &mut Stats,
        feeders: &mut Feeders,
    ) -> Option<Meeting> {
        let Some(hit) = hit else {
            // Inside a closed mesh every ray must hit it again.
            stats.lose(|c| &mut c.escaped);
            return None;
        };
        let ray = ray.expect("a hit has a ray");
        if depth >= self.settings.max_depth {
            stats.depth_cut += 1;
            return None;
        }
        let object = hit.geom;
        let outward = self.scene.objects[object as usize]
            .mesh
            .triangle_normal(hit.prim);
        // Side + is where our wave lives: outside when we come from air.
        let (normal, other) = match region {
            Region::Ambient => (outward, Region::Inside(object)),
            Region::Inside(i) if i == object => (-outward, Region::Ambient),
            Region::Inside(_) => {
                // Objects must not overlap or touch.
                stats.lose(|c| &mut c.overlap);
                return None;
            }
        };
        let leaving = -dir;
        if !(leaving.dot(normal) > 0.0) {
            // Met the facet from its far side (a grazing ray at an edge, or
            // a camera inside the object): no outgoing wave on our side. A
            // camera ray that meets a back face at the triangle's edge
            // grazed the silhouette; inside it, the camera is in the
            // object.
            if depth == 0 && !at_triangle_edge(&hit) {
                stats.lose(|c| &mut c.camera_inside);
            } else {
                stats.lose(|c| &mut c.wrong_side);
            }
            return None;
        }
        let Ok(iface) = Interface::new(
            normal,
            self.medium_of(region, media),
            self.medium_of(other, media),
        ) else {
            stats.lose(|c| &mut c.solver);
            return None;
        };
        if iface
            .feeders_into(Side::Plus, kind, leaving, feeders)
            .is_err()
        {
            stats.lose(|c| &mut c.solver);
            return None;
        }
        Some(Meeting {
            ray,
            hit,
            normal,
            other,
        })
    }

    /// Which of a node's `n` feeders (with these gains) to follow, each with
    /// the weight its contribution gets: all with weight 1, or — where the
    /// strategy samples — one, chosen with probability gain / Σ gains, with
    /// weight 1/p. Returns whether the node sampled.
    pub(super) fn choose(
        &self,
        gains: &[f64; 4],
        n: usize,
        depth: u32,
        path: u64,
        key: &SampleKey,
    ) -> (bool, Chosen) {
        let sampled = match self.strategy.branching {
            Branching::Full => false,
            Branching::Stochastic => true,
            Branching::Hybrid { full_depth } => depth >= full_depth,
        };
        let total: f64 = gains.iter().sum();
        let mut chosen: [(usize, f64); 4] = [(0, 0.0); 4];
        let mut n_chosen = 0;
        if sampled {
            if total > 0.0 {
                // Stratified over the pixel's samples: a node that recurs
                // across them picks each feeder close to its share of times.
                let u = key.stratified_at(dim::BRANCH + depth, path) * total;
                let mut acc = 0.0;
                let mut pick = n - 1;
                for (i, g) in gains.iter().enumerate().take(n) {
                    acc += g;
                    if u < acc {
                        pick = i;
                        break;
                    }
                }
                // Never pick a feeder that cannot pass anything.
                while gains[pick] == 0.0 && pick > 0 {
                    pick -= 1;
                }
                chosen[0] = (pick, total / gains[pick]);
                n_chosen = 1;
            }
        } else {
            for i in 0..n {
                chosen[n_chosen] = (i, 1.0);
                n_chosen += 1;
            }
        }
        (sampled, (chosen, n_chosen))
    }

    /// Russian roulette (Arvo & Kirk 1990) for a subtree whose expected
    /// contribution is `effective` (its path's throughput times its sampling
    /// weights) of the brightest emitter: below the threshold it is traced
    /// with probability p = effective / threshold and its light weighted by
    /// 1/p, so the estimate stays unbiased. Returns the factor to weight it
    /// by (1 above the threshold or with roulette off), or `None` when the
    /// subtree is dropped. `stream` names the subtree's random number.
    #[inline]
    pub(super) fn roulette(
        &self,
        effective: f64,
        depth: u32,
        stream: u64,
        key: &SampleKey,
    ) -> Option<f64> {
        let threshold = self.strategy.roulette;
        if !(effective < threshold) {
            return Some(1.0);
        }
        let p = effective / threshold;
        // Stratified over the pixel's samples (docs/physics.md §6.6): a
        // subtree that recurs across them survives close to p of the time.
        if key.stratified_at(dim::ROULETTE + depth, stream) < p {
            Some(1.0 / p)
        } else {
            None
        }
    }

    fn medium_of(&self, region: Region, media: &WavelengthMedia) -> Medium {
        match region {
            Region::Ambient => AMBIENT,
            Region::Inside(i) => media.objects[i as usize],
        }
    }

    /// Fills `out` (one entry per wavelength of `batch`) with the light of
    /// `q`'s wave in `basis` (ignored for a one-mode wave). `scratch` holds
    /// the results of the levels below: a child writes into its first
    /// `batch.len()` entries and recurses with the rest.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn radiance(
        &self,
        q: &Query,
        basis: &[DVec3; 2],
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        stats.rays += 1;
        let traced = self.trace(q.origin, q.dir, q.region, q.from, stats);
        self.radiance_traced(q, traced, basis, batch, key, out, scratch, stats);
    }

    /// [`Self::radiance`] for a query whose ray has been traced already
    /// (`None`: it could not be, and was counted lost).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn radiance_traced(
        &self,
        q: &Query,
        traced: Option<Traced>,
        basis: &[DVec3; 2],
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let modes = q.kind.mode_count();
        let zero = |out: &mut [Coherence]| out.iter_mut().for_each(|o| *o = Coherence::zero(modes));
        let scalar = self.strategy.polarization == PolarizationModel::Scalar;
        let Some(Traced { ray, hit, t_hit }) = traced else {
            return zero(out);
        };

        if q.region == Region::Ambient {
            if let Some((_, i, s, tt)) = self.nearest_light(q.origin, q.dir, t_hit) {
                let light = &self.scene.lights[i];
                for (o, m) in out.iter_mut().zip(batch) {
                    let j = light.emitted(s, tt, m.lambda_nm, -q.dir, basis[0], basis[1]);
                    *o = if scalar {
                        Coherence::unpolarized(j.intensity())
                    } else {
                        j
                    };
                }
                return;
            }
            if hit.is_none() {
                if let Some(light) = self
                    .scene
                    .distant_lights
                    .iter()
                    .find(|l| l.seen_along(q.dir))
                {
                    for (o, m) in out.iter_mut().zip(batch) {
                        let j = light.emitted(m.lambda_nm, -q.dir, basis[0], basis[1]);
                        *o = if scalar {
                            Coherence::unpolarized(j.intensity())
                        } else {
                            j
                        };
                    }
                    return;
                }
                if let Some(env) = &self.scene.environment {
                    for (o, m) in out.iter_mut().zip(batch) {
                        *o = Coherence::unpolarized(env.spectral_radiance(-q.dir, m.lambda_nm));
                    }
                    return;
                }
                for (o, m) in out.iter_mut().zip(batch) {
                    *o = Coherence::unpolarized(
                        self.scene.background * crate::spectrum::cie::d65(m.lambda_nm),
                    );
                }
                return;
            }
        }
        // Inside an absorbing object: the segment's weights, and the bound
        // the subtree's pruning uses lowered by the most it keeps.
        let absorbed = match (self.absorbing(q.region), &ray, &hit) {
            (Some(object), Some(r), Some(h)) => {
                let w = self.segment_weights(object, q.kind, q.anchor, q.dir, r, h, &batch[0]);
                Some((object, w))
            }
            _ => None,
        };
        let attenuated;
        let q = match absorbed {
            Some((object, w)) => {
                attenuated = Query {
                    throughput: q.throughput * self.kept_at_most(object, w, batch),
                    ..*q
                };
                &attenuated
            }
            None => q,
        };
        let mut feeders = Feeders::EMPTY;
        let Some(Meeting {
            ray,
            hit,
            normal,
            other,
        }) = self.node_into(
            ray,
            hit,
            q.region,
            q.kind,
            q.dir,
            q.depth,
            &batch[0],
            stats,
            &mut feeders,
        )
        else {
            return zero(out);
        };
        stats.nodes += 1;
        let point = ray.at(hit.t);
        let target = feeders.target;
        let list = feeders.as_slice();
        let gains: [f64; 4] = std::array::from_fn(|i| {
            list.get(i).map_or(0.0, |f| {
                if scalar {
                    unpolarized_gain(&f.block)
                } else {
                    max_gain(&f.block)
                }
            })
        });

        // Which feeders to follow, each with the weight its contribution
        // gets: all with weight 1, or one sampled with weight 1/p.
        let (sampled, chosen) = self.choose(&gains, list.len(), q.depth, q.path, key);
        let (chosen, n_chosen) = chosen;

        let n = out.len();
        for o in out.iter_mut() {
            *o = Coherence::zero(target.modes());
        }
        // The o and e feeders of a crystal side travel as one bundle.
        let bundled = if self.strategy.bundle > 0.0 && !sampled && !scalar {
            let at = (point, hit.geom, normal, other);
            self.bundle_pairs(q, list, &gains, at, batch, key, out, scratch, stats)
        } else {
            [false; 4]
        };
        for &(i, weight) in &chosen[..n_chosen] {
            if bundled[i] {
                continue;
            }
            let f = &list[i];
            // Pruning looks at the path's physical throughput, whatever the
            // sampling weight, so every strategy cuts the same subtrees.
            let throughput = q.throughput * gains[i];
            if throughput < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            let path = if sampled {
                q.path
            } else {
                q.path.wrapping_mul(4).wrapping_add(i as u64 + 1)
            };
            let Some(survived) = self.roulette(throughput * q.weight * weight, q.depth, path, key)
            else {
                stats.rouletted += 1;
                continue;
            };
            let weight = weight * survived;
            let (region, offset) = feeder_side(f.wave.side, q.region, other, normal);
            let child = Query {
                origin: point + self.epsilon(hit.geom) * offset,
                dir: -f.wave.ray,
                region,
                kind: f.wave.kind,
                depth: q.depth + 1,
                throughput,
                path,
                drift: q.drift,
                anchor: point,
                weight: q.weight * weight,
                from: Some(Departure {
                    object: hit.geom,
                    normal: offset,
                }),
            };
            let (child_out, deeper) = scratch.split_at_mut(n);
            self.radiance(&child, &f.wave.basis, batch, key, child_out, deeper, stats);
            for (o, j) in out.iter_mut().zip(child_out.iter()) {
                let contribution = if scalar {
                    let i = unpolarized_gain(&f.block) * j.intensity();
                    if target.modes() == 1 {
                        Coherence::scalar(i)
                    } else {
                        Coherence::unpolarized(i)
                    }
                } else {
                    j.transform(&f.block)
                };
                *o += contribution * weight;
            }
        }
        if modes == 2 && !scalar {
            for o in out.iter_mut() {
                *o = o.change_basis(&target.basis, basis);
            }
        }
        // Beer–Lambert along this segment: exp(−τ(λ)) of the intensity.
        if let Some((object, w)) = absorbed {
            for (o, m) in out.iter_mut().zip(batch) {
                *o = *o * (-absorb::depth(w, m.absorption[object as usize])).exp();
            }
        }
    }
}

/// A hit's barycentric distance to its triangle's edges below which a
/// camera ray that meets the triangle from behind is taken to have grazed
/// an edge of the silhouette (rounding at the edge) rather than to have
/// started inside the object (whose rays meet back faces anywhere).
const EDGE_BAND: f64 = 1e-6;

/// Whether `hit` lies on its triangle's edge (within [`EDGE_BAND`] of it in
/// barycentric coordinates).
fn at_triangle_edge(hit: &Hit) -> bool {
    hit.u.min(hit.v).min(1.0 - hit.u - hit.v) < EDGE_BAND
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(u: f64, v: f64) -> Hit {
        Hit {
            t: 1.0,
            geom: 0,
            prim: 0,
            u,
            v,
            ng: DVec3::Z,
        }
    }

    /// Near any of the three edges (u = 0, v = 0, u + v = 1) a hit is at the
    /// edge; at the centroid and a little inside, it is not.
    #[test]
    fn hits_on_a_triangles_edges_are_told_from_hits_inside_it() {
        for (u, v) in [
            (0.0, 0.5),
            (1e-9, 0.3),
            (0.5, 1e-8),
            (0.4, 0.6 - 1e-9),
            (0.0, 0.0),
        ] {
            assert!(at_triangle_edge(&hit(u, v)), "({u}, {v})");
        }
        for (u, v) in [(1.0 / 3.0, 1.0 / 3.0), (1e-4, 0.5), (0.5, 0.5 - 1e-4)] {
            assert!(!at_triangle_edge(&hit(u, v)), "({u}, {v})");
        }
    }
}
