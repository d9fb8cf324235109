//! o and e waves that travel together (`bundle = TOL`, docs/physics.md
//! §10): where a node feeds a crystal's two eigenwaves on one side, the
//! exact tree follows each (and each of them feeds two more at the next
//! internal reflection: 2^depth rays). A bundle follows both along one
//! facet sequence instead: its two members are the exact rays of the
//! all-o and the all-e chains, each traced and solved on its own, and the
//! waves that change mode at a reflection (o → e, e → o) ride on the
//! member of their new mode. A crystal's tree then grows as glass's does,
//! one internal child per node.
//!
//! The approximation is the geometry of the mode-changing waves (the
//! member's ray instead of their own, which differs from it by the angle
//! between the o and e rays); it is bounded by splitting: where the
//! members reach different facets, or their hit points are more than `TOL`
//! pixel footprints apart ([`Tracer::footprint`]), each continues as an
//! exact query of the incoherent tree (and may bundle again at its next
//! node). Energy is carried exactly: every Jones block of the exact tree
//! is applied, only rays are shared.
//!
//! Sums are those of the incoherent model (`coherence = "incoherent"`):
//! the bundle's coherence matrix in its (o, e) mode basis is kept diagonal,
//! each mode an intensity, so where no mode changes (a plate seen once)
//! the bundled image equals the exact tree's. The physical model's o/e
//! interference needs the exact tree; the settings refuse the combination.

use super::integrator::{feeder_side, max_gain, Query, Region, Stats, Traced, Tracer};
use super::integrator::{Node, WavelengthMedia};
use super::sampling::SampleKey;
use crate::optics::backward::Feeder;
use crate::optics::modes::{Side, WaveKind};
use crate::optics::{Coherence, Jones};
use glam::DVec3;
use num_complex::Complex64;

/// One member of a bundle: the exact backward ray of one eigenwave.
#[derive(Clone, Copy, Debug)]
pub(super) struct Member {
    pub origin: DVec3,
    pub dir: DVec3,
    pub kind: WaveKind,
}

/// A backward query for both eigenwaves of a crystal (member 0 the
/// ordinary, member 1 the extraordinary wave), inside object `object`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bundle {
    pub members: [Member; 2],
    pub object: u32,
    pub depth: u32,
    /// Each member's path gain: the largest of the gains of the exact
    /// tree's paths it stands for (what pruning tests).
    pub throughput: [f64; 2],
    pub path: u64,
    /// How far (chord of unit directions) the mode-changing waves that
    /// ride on the members point from them on this segment (0 for a
    /// bundle whose members are the exact waves of one point).
    pub mismatch: f64,
}

/// The feeder of `kind` on `side` in a node's list.
fn find(list: &[Feeder], side: Side, kind: WaveKind) -> Option<&Feeder> {
    list.iter()
        .find(|f| f.wave.side == side && f.wave.kind == kind)
}

/// The o and e feeders on `side` of a node's list (indices), when it has
/// both.
pub(super) fn eigenwave_pair(list: &[Feeder], side: Side) -> Option<(usize, usize)> {
    let o = list
        .iter()
        .position(|f| f.wave.side == side && f.wave.kind == WaveKind::Ordinary)?;
    let e = list
        .iter()
        .position(|f| f.wave.side == side && f.wave.kind == WaveKind::Extraordinary)?;
    Some((o, e))
}

/// The block that takes a bundle's (o, e) modes to a node's target:
/// `[T_o | T_e]`, one column per member (each feeder block has one column).
pub(super) fn pair_block(o: &Jones, e: &Jones) -> Jones {
    let mut m = [[Complex64::new(0.0, 0.0); 2]; 2];
    for (r, row) in m.iter_mut().enumerate().take(o.rows) {
        *row = [o.m[r][0], e.m[r][0]];
    }
    Jones::from_entries(o.rows, 2, m)
}

/// The incoherent part of a bundle's matrix: each mode an intensity.
#[inline]
fn dephased(c: &Coherence) -> Coherence {
    Coherence::from_matrix([
        [Complex64::new(c.jxx(), 0.0), Complex64::new(0.0, 0.0)],
        [Complex64::new(0.0, 0.0), Complex64::new(c.jyy(), 0.0)],
    ])
}

impl Tracer<'_> {
    /// Fills `out` (one 2-mode matrix per wavelength of `batch`, in the
    /// bundle's (o, e) mode basis, diagonal) with the light of both
    /// members of `b`, and returns true; or returns false, with `out`
    /// unspecified, when the mode-changing waves riding on `b`'s members
    /// would end more than the tolerance away from them (the caller then
    /// traces them on their own). `scratch` as in [`Tracer::radiance`].
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bundle_radiance(
        &self,
        b: &Bundle,
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) -> bool {
        let n = out.len();
        let region = Region::Inside(b.object);
        let [mo, me] = b.members;
        stats.rays += 2;
        let traced = (
            self.trace(mo.origin, mo.dir, stats),
            self.trace(me.origin, me.dir, stats),
        );
        let (Some(to), Some(te)) = traced else {
            if b.mismatch > 0.0 {
                return false;
            }
            stats.rays -= 2;
            self.split(b, batch, key, out, scratch, stats);
            return true;
        };
        let (Some(ho), Some(he)) = (to.hit, te.hit) else {
            if b.mismatch > 0.0 {
                return false;
            }
            stats.rays -= 2;
            self.split(b, batch, key, out, scratch, stats);
            return true;
        };
        let (po, pe) = (to.ray.expect("hit").at(ho.t), te.ray.expect("hit").at(he.t));
        let allowed = self.bundle_tolerance() * self.footprint(po);
        // The riding waves drift from their members by the angle between
        // them times the segment's length.
        let length = (po - mo.origin).length().max((pe - me.origin).length());
        if b.mismatch * length > allowed {
            return false;
        }
        // The members stay together while both reach the same facet plane,
        // close enough.
        let together = ho.geom == he.geom && {
            let mesh = &self.scene.objects[ho.geom as usize].mesh;
            let (no, ne) = (mesh.triangle_normal(ho.prim), mesh.triangle_normal(he.prim));
            let plane = ho.prim == he.prim
                || (no.dot(ne) > 1.0 - 1e-12 && (po - pe).dot(no).abs() <= self.epsilon(ho.geom));
            plane && (po - pe).length() <= allowed
        };
        if !together {
            // The trace above is repeated by the members' own queries.
            stats.rays -= 2;
            self.split(b, batch, key, out, scratch, stats);
            return true;
        }
        out.iter_mut().for_each(|o| *o = Coherence::zero(2));
        let media = &batch[0];
        let Traced { ray, hit, .. } = to;
        let node_o = self.node(ray, hit, region, mo.kind, mo.dir, b.depth, media, stats);
        let Traced { ray, hit, .. } = te;
        let node_e = self.node(ray, hit, region, me.kind, me.dir, b.depth, media, stats);
        let (Some(node_o), Some(node_e)) = (node_o, node_e) else {
            // Depth cut or a lost ray (counted by `node`): nothing more.
            return true;
        };
        stats.nodes += 2;
        stats.bundled += 1;
        let nodes = [&node_o, &node_e];
        let lists = [node_o.feeders.as_slice(), node_e.feeders.as_slice()];
        // Reflection: each member continues as its own mode's specular
        // feeder; the mode-changing feeders ride on the other member.
        let own = [
            find(lists[0], Side::Plus, WaveKind::Ordinary),
            find(lists[1], Side::Plus, WaveKind::Extraordinary),
        ];
        let riding = [
            find(lists[1], Side::Plus, WaveKind::Ordinary),
            find(lists[0], Side::Plus, WaveKind::Extraordinary),
        ];
        let mut merged = false;
        if let [Some(fo), Some(fe)] = own {
            // R[a][c]: member a's target fed by mode c.
            let entry = |a: usize, kind: WaveKind| {
                find(lists[a], Side::Plus, kind)
                    .map_or(Complex64::new(0.0, 0.0), |f| f.block.m[0][0])
            };
            let r = Jones::from_entries(
                2,
                2,
                [
                    [
                        entry(0, WaveKind::Ordinary),
                        entry(0, WaveKind::Extraordinary),
                    ],
                    [
                        entry(1, WaveKind::Ordinary),
                        entry(1, WaveKind::Extraordinary),
                    ],
                ],
            );
            // Mode c's strongest path: through whichever member feeds it
            // most.
            let throughput: [f64; 2] = std::array::from_fn(|c| {
                (0..2)
                    .map(|a| b.throughput[a] * r.m[a][c].norm_sqr())
                    .fold(0.0, f64::max)
            });
            if throughput[0].max(throughput[1]) < self.settings.prune {
                stats.pruned += 1;
                merged = true;
            } else {
                let drift = |x: Option<&Feeder>, f: &Feeder| {
                    x.map_or(0.0, |x| (x.wave.ray - f.wave.ray).length())
                };
                let member = |node: &Node, f: &Feeder| Member {
                    origin: node.ray.at(node.hit.t) + self.epsilon(node.hit.geom) * node.normal,
                    dir: -f.wave.ray,
                    kind: f.wave.kind,
                };
                let child = Bundle {
                    members: [member(&node_o, fo), member(&node_e, fe)],
                    object: b.object,
                    depth: b.depth + 1,
                    throughput,
                    path: b.path.wrapping_mul(4).wrapping_add(1),
                    mismatch: drift(riding[0], fo).max(drift(riding[1], fe)),
                };
                let (child_out, deeper) = scratch.split_at_mut(n);
                if self.bundle_radiance(&child, batch, key, child_out, deeper, stats) {
                    merged = true;
                    for (o, c) in out.iter_mut().zip(child_out.iter()) {
                        *o += dephased(&c.transform(&r));
                    }
                }
            }
        }
        if !merged {
            // Each member's reflected waves on their own rays.
            for (a, node) in nodes.iter().enumerate() {
                self.reflect_member(node, a, b, batch, key, out, scratch, stats);
            }
        }
        // Transmission: each member's own feeders on the far side (air, or
        // another medium), traced as exact queries.
        for (a, list) in lists.iter().enumerate() {
            let node = nodes[a];
            for (i, f) in list.iter().enumerate() {
                if f.wave.side != Side::Minus {
                    continue;
                }
                let throughput = b.throughput[a] * max_gain(&f.block);
                if throughput < self.settings.prune {
                    stats.pruned += 1;
                    continue;
                }
                let (region, offset) = feeder_side(f.wave.side, region, node.other, node.normal);
                let q = Query {
                    origin: node.ray.at(node.hit.t) + self.epsilon(node.hit.geom) * offset,
                    dir: -f.wave.ray,
                    region,
                    kind: f.wave.kind,
                    depth: b.depth + 1,
                    throughput,
                    path: b.path.wrapping_mul(4).wrapping_add(2 + i as u64),
                };
                let (air_out, deeper) = scratch.split_at_mut(n);
                self.radiance(&q, &f.wave.basis, batch, key, air_out, deeper, stats);
                for (o, j) in out.iter_mut().zip(air_out.iter()) {
                    *o += on_mode(a, j.transform(&f.block).jxx());
                }
            }
        }
        true
    }

    /// Adds to mode `a` of `out` the light member `a` of `b` receives from
    /// its own reflected waves at `node`, each on its own ray (a new bundle
    /// of the two, which starts as the exact waves of one point).
    #[allow(clippy::too_many_arguments)]
    fn reflect_member(
        &self,
        node: &Node,
        a: usize,
        b: &Bundle,
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let n = out.len();
        let list = node.feeders.as_slice();
        let origin = node.ray.at(node.hit.t) + self.epsilon(node.hit.geom) * node.normal;
        let (child_out, deeper) = scratch.split_at_mut(n);
        if let Some((io, ie)) = eigenwave_pair(list, Side::Plus) {
            let (fo, fe) = (&list[io], &list[ie]);
            let throughput = [
                b.throughput[a] * max_gain(&fo.block),
                b.throughput[a] * max_gain(&fe.block),
            ];
            if throughput[0].max(throughput[1]) < self.settings.prune {
                stats.pruned += 1;
                return;
            }
            let member = |f: &Feeder| Member {
                origin,
                dir: -f.wave.ray,
                kind: f.wave.kind,
            };
            let child = Bundle {
                members: [member(fo), member(fe)],
                object: b.object,
                depth: b.depth + 1,
                throughput,
                path: b.path.wrapping_mul(8).wrapping_add(5 + a as u64),
                mismatch: 0.0,
            };
            let accepted = self.bundle_radiance(&child, batch, key, child_out, deeper, stats);
            debug_assert!(accepted, "a bundle without riding waves is never refused");
            let block = pair_block(&fo.block, &fe.block);
            for (o, c) in out.iter_mut().zip(child_out.iter()) {
                *o += on_mode(a, c.transform(&block).jxx());
            }
            return;
        }
        for (i, f) in list.iter().enumerate() {
            if f.wave.side != Side::Plus {
                continue;
            }
            let throughput = b.throughput[a] * max_gain(&f.block);
            if throughput < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            let q = Query {
                origin,
                dir: -f.wave.ray,
                region: Region::Inside(b.object),
                kind: f.wave.kind,
                depth: b.depth + 1,
                throughput,
                path: b.path.wrapping_mul(8).wrapping_add(i as u64),
            };
            self.radiance(&q, &f.wave.basis, batch, key, child_out, deeper, stats);
            for (o, j) in out.iter_mut().zip(child_out.iter()) {
                *o += on_mode(a, j.transform(&f.block).jxx());
            }
        }
    }

    /// Both members of `b` as exact queries of their own: `out` =
    /// diag(o's intensity, e's intensity).
    fn split(
        &self,
        b: &Bundle,
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let n = out.len();
        stats.splits += 1;
        out.iter_mut().for_each(|o| *o = Coherence::zero(2));
        for (a, m) in b.members.iter().enumerate() {
            if b.throughput[a] < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            let q = Query {
                origin: m.origin,
                dir: m.dir,
                region: Region::Inside(b.object),
                kind: m.kind,
                depth: b.depth,
                throughput: b.throughput[a],
                path: b.path.wrapping_mul(2).wrapping_add(a as u64),
            };
            let (member_out, deeper) = scratch.split_at_mut(n);
            // A member's own wave has one mode: its basis is unused.
            self.radiance(&q, &[DVec3::ZERO; 2], batch, key, member_out, deeper, stats);
            for (o, j) in out.iter_mut().zip(member_out.iter()) {
                *o += on_mode(a, j.jxx());
            }
        }
    }
}

/// An intensity `c` on mode `a` of a bundle (0: o, 1: e).
#[inline]
fn on_mode(a: usize, c: f64) -> Coherence {
    let z = Complex64::new(0.0, 0.0);
    let c = Complex64::new(c, 0.0);
    Coherence::from_matrix(if a == 0 {
        [[c, z], [z, z]]
    } else {
        [[z, z], [z, c]]
    })
}
