//! o and e waves that travel together (`bundle = TOL`, docs/physics.md
//! §10; in a biaxial crystal its fast and slow waves, member 0 and 1 as o
//! and e are): where a node feeds a crystal's two eigenwaves on one side, the
//! exact tree follows each (and each of them feeds two more at the next
//! internal reflection: 2^depth rays). A bundle follows both along one
//! facet sequence instead: its two members are the exact rays of the
//! all-o and the all-e chains, each traced and solved on its own, and the
//! waves that change mode at a reflection (o → e, e → o) ride on the
//! member of their new mode. A crystal's tree then grows as glass's does,
//! one internal child per node.
//!
//! The approximation is the geometry of the mode-changing waves: a riding
//! wave follows its member's ray instead of its own, which turns from it
//! by an angle of the order of the birefringence, and that angle persists
//! on every later segment. Light off its exact direction by θ lands at
//! most θ / (the pixel's angle) pixels from where it should, so a wave may
//! ride only while the angles summed along its path stay within `TOL`
//! pixel angles ([`Tracer::pixel_angle`]) and the members landed within
//! `TOL` pixel footprints of each other ([`Tracer::footprint`]: a riding
//! wave starts at the other member's point); otherwise each member's
//! reflected waves are traced on their own rays. Members are exact rays;
//! where they reach different facets each continues as an exact query of
//! the incoherent tree (and may bundle again at its next node). Energy is
//! carried exactly: every Jones block of the exact tree is applied, only
//! rays are shared.
//!
//! Sums are those of the incoherent model (`coherence = "incoherent"`):
//! the bundle's coherence matrix in its (o, e) mode basis is kept diagonal,
//! each mode an intensity, so where no mode changes (a plate seen once)
//! the bundled image equals the exact tree's. The physical model's o/e
//! interference needs the exact tree; the settings refuse the combination.
//!
//! Russian roulette (`Tracer::roulette`) decides wherever a bundle
//! follows a subtree, as the exact tree does: a new bundle once as a whole,
//! on its stronger member's share (one random number, one 1/p on both
//! members' light and in `Bundle::weight`); a member again on its own
//! once the bundle splits; every feeder traced as an exact query as the
//! exact tree's feeders are (docs/physics.md §10.2).

use super::absorb::depth as absorb_depth;
use super::integrator::{feeder_side, max_gain, Departure, Query, Region, Stats, Traced, Tracer};
use super::integrator::{Node, WavelengthMedia};
use super::sampling::SampleKey;
use crate::optics::backward::Feeder;
use crate::optics::modes::{Side, WaveKind};
use crate::optics::{Coherence, Jones};
use glam::DVec3;
use num_complex::Complex64;

/// One member of a bundle: the exact backward ray of one eigenwave.
#[derive(Clone, Copy, Debug)]
struct Member {
    origin: DVec3,
    dir: DVec3,
    kind: WaveKind,
    /// The surface point `origin` is a little off.
    anchor: DVec3,
}

/// A backward query for both eigenwaves of a crystal (member 0 the
/// ordinary or fast, member 1 the extraordinary or slow wave), inside
/// object `object`.
#[derive(Clone, Copy, Debug)]
struct Bundle {
    pub members: [Member; 2],
    pub object: u32,
    pub depth: u32,
    /// Each member's path gain: the largest of the gains of the exact
    /// tree's paths it stands for (what pruning tests).
    pub throughput: [f64; 2],
    pub path: u64,
    /// The largest angle, radians, between the light this bundle carries
    /// and its exact rays: the angles of the waves that rode on a member
    /// (each keeps its angle along every later segment), summed along the
    /// path.
    pub drift: f64,
    /// The sampling weights along the path (as [`Query::weight`]), the
    /// 1/p of this bundle's own roulette decision included: what roulette
    /// compares its members' throughputs with.
    pub weight: f64,
}

impl Bundle {
    /// The exact query of feeder `f` of this bundle's node, from `origin`
    /// into `region`, that survived roulette with weight `survived`.
    fn query(
        &self,
        (origin, anchor): (DVec3, DVec3),
        f: &Feeder,
        (region, from): (Region, Option<Departure>),
        (throughput, survived): (f64, f64),
        path: u64,
    ) -> Query {
        Query {
            origin,
            anchor,
            dir: -f.wave.ray,
            region,
            kind: f.wave.kind,
            depth: self.depth + 1,
            throughput,
            path,
            drift: self.drift,
            weight: self.weight * survived,
            from,
        }
    }
}

/// The member that carries a wave of `kind`: 0 for the ordinary wave of
/// a uniaxial crystal or the fast wave of a biaxial one, 1 for the
/// extraordinary or slow wave. (A node's feeders on one side are all of
/// one medium, so the two names never meet in one list.)
fn member_of(kind: WaveKind) -> Option<usize> {
    match kind {
        WaveKind::Ordinary | WaveKind::Fast => Some(0),
        WaveKind::Extraordinary | WaveKind::Slow => Some(1),
        WaveKind::Isotropic => None,
    }
}

/// The feeder of member `m`'s wave on `side` in a node's list.
fn find(list: &[Feeder], side: Side, m: usize) -> Option<&Feeder> {
    list.iter()
        .find(|f| f.wave.side == side && member_of(f.wave.kind) == Some(m))
}

/// The two eigenwave feeders on `side` of a node's list (indices, member 0
/// then 1: o and e, or fast and slow), when it has both.
fn eigenwave_pair(list: &[Feeder], side: Side) -> Option<(usize, usize)> {
    let at = |m| {
        list.iter()
            .position(|f| f.wave.side == side && member_of(f.wave.kind) == Some(m))
    };
    Some((at(0)?, at(1)?))
}

/// The block that takes a bundle's (o, e) modes to a node's target:
/// `[T_o | T_e]`, one column per member (each feeder block has one column).
fn pair_block(o: &Jones, e: &Jones) -> Jones {
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
    /// Russian roulette ([`Tracer::roulette`]) for a subtree a bundle
    /// would follow: `throughput` its path gain (a bundle's: the larger of
    /// its members'), `weight` the sampling weights above it, decided at a
    /// node at `depth` on random stream `stream` (the subtree's path, as
    /// the exact tree's feeders). The factor to weight its light by, or
    /// `None` (counted) when it is dropped.
    fn roulette_subtree(
        &self,
        (throughput, weight): (f64, f64),
        depth: u32,
        stream: u64,
        key: &SampleKey,
        stats: &mut Stats,
    ) -> Option<f64> {
        let survived = self.roulette(throughput * weight, depth, stream, key);
        if survived.is_none() {
            stats.rouletted += 1;
        }
        survived
    }

    /// At a node of the exact query `q` (at `point` on object `object`,
    /// `normal` into `q`'s side, `other` across), traces each side's o and
    /// e feeders in `list` (with `gains`) as one bundle and adds their
    /// light to `out` (in the node's target basis); returns which feeders
    /// it took.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn bundle_pairs(
        &self,
        q: &Query,
        list: &[Feeder],
        gains: &[f64; 4],
        (point, object, normal, other): (DVec3, u32, DVec3, Region),
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) -> [bool; 4] {
        let n = out.len();
        let mut bundled = [false; 4];
        for side in [Side::Plus, Side::Minus] {
            let Some((io, ie)) = eigenwave_pair(list, side) else {
                continue;
            };
            bundled[io] = true;
            bundled[ie] = true;
            let throughput = [q.throughput * gains[io], q.throughput * gains[ie]];
            if throughput[0].max(throughput[1]) < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            // One roulette decision for the bundle as a whole, on its
            // stronger member (the weaker one is decided again on its own
            // if the bundle splits).
            let path = q.path.wrapping_mul(4).wrapping_add(io as u64 + 1);
            let strongest = throughput[0].max(throughput[1]);
            let Some(survived) =
                self.roulette_subtree((strongest, q.weight), q.depth, path, key, stats)
            else {
                continue;
            };
            let (fo, fe) = (&list[io], &list[ie]);
            let (region, offset) = feeder_side(side, q.region, other, normal);
            let Region::Inside(crystal) = region else {
                unreachable!("eigenwaves live inside a crystal")
            };
            let origin = point + self.epsilon(object) * offset;
            let member = |f: &Feeder| Member {
                origin,
                dir: -f.wave.ray,
                kind: f.wave.kind,
                anchor: point,
            };
            let b = Bundle {
                members: [member(fo), member(fe)],
                object: crystal,
                depth: q.depth + 1,
                throughput,
                path,
                drift: q.drift,
                weight: q.weight * survived,
            };
            let (child_out, deeper) = scratch.split_at_mut(n);
            self.bundle_radiance(&b, batch, key, child_out, deeper, stats);
            let block = pair_block(&fo.block, &fe.block);
            for (o, j) in out.iter_mut().zip(child_out.iter()) {
                *o += j.transform(&block) * survived;
            }
        }
        bundled
    }

    /// Fills `out` (one 2-mode matrix per wavelength of `batch`, in the
    /// bundle's (o, e) mode basis, diagonal) with the light of both
    /// members of `b`. `scratch` as in [`Tracer::radiance`].
    #[allow(clippy::too_many_arguments)]
    fn bundle_radiance(
        &self,
        b: &Bundle,
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let n = out.len();
        let region = Region::Inside(b.object);
        let [mo, me] = b.members;
        if b.throughput[0].min(b.throughput[1]) < self.settings.prune {
            // One member is pruned: the other alone, as the exact tree.
            return self.split(b, None, batch, key, out, scratch, stats);
        }
        stats.rays += 2;
        let traced = (
            self.trace(mo.origin, mo.dir, region, None, stats),
            self.trace(me.origin, me.dir, region, None, stats),
        );
        let (Some(to), Some(te)) = traced else {
            return self.split(
                b,
                Some([traced.0, traced.1]),
                batch,
                key,
                out,
                scratch,
                stats,
            );
        };
        let (Some(ho), Some(he)) = (to.hit, te.hit) else {
            return self.split(
                b,
                Some([Some(to), Some(te)]),
                batch,
                key,
                out,
                scratch,
                stats,
            );
        };
        let (po, pe) = (to.ray.expect("hit").at(ho.t), te.ray.expect("hit").at(he.t));
        let allowed = self.bundle_tolerance() * self.footprint(po);
        // The members stay together while both reach the same facet plane
        // (they are exact rays: how far apart matters only to the waves
        // that would ride on them, below).
        let together = ho.geom == he.geom && {
            let mesh = &self.scene.objects[ho.geom as usize].mesh;
            let (no, ne) = (mesh.triangle_normal(ho.prim), mesh.triangle_normal(he.prim));
            ho.prim == he.prim
                || (no.dot(ne) > 1.0 - 1e-12 && (po - pe).dot(no).abs() <= self.epsilon(ho.geom))
        };
        if !together {
            return self.split(
                b,
                Some([Some(to), Some(te)]),
                batch,
                key,
                out,
                scratch,
                stats,
            );
        }
        out.iter_mut().for_each(|o| *o = Coherence::zero(2));
        let media = &batch[0];
        // In an absorbing crystal: each member's segment weights, and its
        // pruning bound lowered by the most its segment keeps.
        let absorbed = self.absorbing(region).and_then(|object| {
            let w = |m: &Member, t: &Traced| {
                let (ray, hit) = (t.ray.as_ref()?, t.hit.as_ref()?);
                Some(self.segment_weights(object, m.kind, m.anchor, m.dir, ray, hit, media))
            };
            Some((object, [w(&mo, &to)?, w(&me, &te)?]))
        });
        let attenuated;
        let b = match absorbed {
            Some((object, w)) => {
                attenuated = Bundle {
                    throughput: std::array::from_fn(|a| {
                        b.throughput[a] * self.kept_at_most(object, w[a], batch)
                    }),
                    ..*b
                };
                &attenuated
            }
            None => b,
        };
        let Traced { ray, hit, .. } = to;
        let node_o = self.node(ray, hit, region, mo.kind, mo.dir, b.depth, media, stats);
        let Traced { ray, hit, .. } = te;
        let node_e = self.node(ray, hit, region, me.kind, me.dir, b.depth, media, stats);
        let (Some(node_o), Some(node_e)) = (node_o, node_e) else {
            // Depth cut or a lost ray (counted by `node`): nothing more.
            return;
        };
        stats.nodes += 2;
        stats.bundled += 1;
        let nodes = [&node_o, &node_e];
        let lists = [node_o.feeders.as_slice(), node_e.feeders.as_slice()];
        // Reflection: each member continues as its own mode's specular
        // feeder; the mode-changing feeders ride on the other member.
        let own = [find(lists[0], Side::Plus, 0), find(lists[1], Side::Plus, 1)];
        let riding = [find(lists[1], Side::Plus, 0), find(lists[0], Side::Plus, 1)];
        let mut merged = false;
        if let [Some(fo), Some(fe)] = own {
            // R[a][c]: member a's target fed by mode c.
            let entry = |a: usize, mode: usize| {
                find(lists[a], Side::Plus, mode)
                    .map_or(Complex64::new(0.0, 0.0), |f| f.block.m[0][0])
            };
            let r = Jones::from_entries(
                2,
                2,
                [[entry(0, 0), entry(0, 1)], [entry(1, 0), entry(1, 1)]],
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
                // The angle between a riding wave's ray and its member's.
                let turn = |x: Option<&Feeder>, f: &Feeder| {
                    x.map_or(0.0, |x| {
                        2.0 * (0.5 * (x.wave.ray - f.wave.ray).length()).min(1.0).asin()
                    })
                };
                // Seen from the camera, light that left its exact ray at an
                // angle reaches a source far away up to that angle / the
                // pixel's angle in pixel footprints from where it should
                // (nearer sources: less).
                let drift = b.drift + turn(riding[0], fo).max(turn(riding[1], fe));
                // A riding wave also starts at the other member's point: at
                // most TOL pixel footprints away.
                let close = (po - pe).length() <= allowed;
                let together = close
                    && (drift == 0.0 || drift <= self.bundle_tolerance() * self.pixel_angle());
                // One roulette decision for the reflected bundle as a whole,
                // on its stronger mode (dropped: nothing reflected).
                let path = b.path.wrapping_mul(4).wrapping_add(1);
                let strongest = throughput[0].max(throughput[1]);
                if together {
                    merged = true;
                    if let Some(survived) =
                        self.roulette_subtree((strongest, b.weight), b.depth, path, key, stats)
                    {
                        let member = |node: &Node, f: &Feeder| Member {
                            origin: node.ray.at(node.hit.t)
                                + self.epsilon(node.hit.geom) * node.normal,
                            dir: -f.wave.ray,
                            kind: f.wave.kind,
                            anchor: node.ray.at(node.hit.t),
                        };
                        let child = Bundle {
                            members: [member(&node_o, fo), member(&node_e, fe)],
                            object: b.object,
                            depth: b.depth + 1,
                            throughput,
                            path,
                            drift,
                            weight: b.weight * survived,
                        };
                        let (child_out, deeper) = scratch.split_at_mut(n);
                        self.bundle_radiance(&child, batch, key, child_out, deeper, stats);
                        for (o, c) in out.iter_mut().zip(child_out.iter()) {
                            *o += dephased(&c.transform(&r)) * survived;
                        }
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
                let anchor = node.ray.at(node.hit.t);
                let origin = anchor + self.epsilon(node.hit.geom) * offset;
                let path = b.path.wrapping_mul(4).wrapping_add(2 + i as u64);
                let Some(survived) =
                    self.roulette_subtree((throughput, b.weight), b.depth, path, key, stats)
                else {
                    continue;
                };
                let from = Departure {
                    object: node.hit.geom,
                    normal: offset,
                };
                let q = b.query(
                    (origin, anchor),
                    f,
                    (region, Some(from)),
                    (throughput, survived),
                    path,
                );
                self.add_exact(&q, f, (a, survived), batch, key, out, scratch, stats);
            }
        }
        // Beer–Lambert along each member's segment: its mode's amplitude
        // keeps exp(−τ/2), D J Dᴴ with D = diag(e^{−τ_o/2}, e^{−τ_e/2}).
        if let Some((object, w)) = absorbed {
            for (o, m) in out.iter_mut().zip(batch) {
                let alpha = m.absorption[object as usize];
                let amp = |w| Complex64::new((-0.5 * absorb_depth(w, alpha)).exp(), 0.0);
                let zero = Complex64::new(0.0, 0.0);
                let d = Jones::from_entries(2, 2, [[amp(w[0]), zero], [zero, amp(w[1])]]);
                *o = o.transform(&d);
            }
        }
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
        let anchor = node.ray.at(node.hit.t);
        let origin = anchor + self.epsilon(node.hit.geom) * node.normal;
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
            let path = b.path.wrapping_mul(8).wrapping_add(5 + a as u64);
            let strongest = throughput[0].max(throughput[1]);
            let Some(survived) =
                self.roulette_subtree((strongest, b.weight), b.depth, path, key, stats)
            else {
                return;
            };
            let member = |f: &Feeder| Member {
                origin,
                dir: -f.wave.ray,
                kind: f.wave.kind,
                anchor,
            };
            let child = Bundle {
                members: [member(fo), member(fe)],
                object: b.object,
                depth: b.depth + 1,
                throughput,
                path,
                drift: b.drift,
                weight: b.weight * survived,
            };
            self.bundle_radiance(&child, batch, key, child_out, deeper, stats);
            let block = pair_block(&fo.block, &fe.block);
            for (o, c) in out.iter_mut().zip(child_out.iter()) {
                *o += on_mode(a, c.transform(&block).jxx() * survived);
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
            let path = b.path.wrapping_mul(8).wrapping_add(i as u64);
            let Some(survived) =
                self.roulette_subtree((throughput, b.weight), b.depth, path, key, stats)
            else {
                continue;
            };
            let q = b.query(
                (origin, anchor),
                f,
                (Region::Inside(b.object), None),
                (throughput, survived),
                path,
            );
            self.add_exact(&q, f, (a, survived), batch, key, out, scratch, stats);
        }
    }

    /// Adds to mode `a` of `out` the light feeder `f` brings along the
    /// exact query `q`, times `survived` (its roulette weight).
    #[allow(clippy::too_many_arguments)]
    fn add_exact(
        &self,
        q: &Query,
        f: &Feeder,
        (a, survived): (usize, f64),
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let (child_out, deeper) = scratch.split_at_mut(out.len());
        self.radiance(q, &f.wave.basis, batch, key, child_out, deeper, stats);
        for (o, j) in out.iter_mut().zip(child_out.iter()) {
            *o += on_mode(a, j.transform(&f.block).jxx() * survived);
        }
    }

    /// Both members of `b` as exact queries of their own, their rays
    /// traced already (`traced`) or not: `out` = diag(o's intensity, e's
    /// intensity).
    #[allow(clippy::too_many_arguments)]
    fn split(
        &self,
        b: &Bundle,
        traced: Option<[Option<Traced>; 2]>,
        batch: &[WavelengthMedia],
        key: &SampleKey,
        out: &mut [Coherence],
        scratch: &mut [Coherence],
        stats: &mut Stats,
    ) {
        let n = out.len();
        stats.splits += 1;
        out.iter_mut().for_each(|o| *o = Coherence::zero(2));
        let mut traced = traced.map(|[o, e]| [Some(o), Some(e)]);
        for (a, m) in b.members.iter().enumerate() {
            if b.throughput[a] < self.settings.prune {
                stats.pruned += 1;
                continue;
            }
            // The bundle's roulette decision was on its stronger member;
            // on its own each member is decided again on its own
            // throughput, with the bundle's 1/p in `b.weight`: over both
            // decisions a member survives with min(1, its own expected
            // share / threshold), as in the exact tree.
            let path = b.path.wrapping_mul(2).wrapping_add(a as u64);
            let Some(survived) =
                self.roulette_subtree((b.throughput[a], b.weight), b.depth, path, key, stats)
            else {
                continue;
            };
            let q = Query {
                origin: m.origin,
                dir: m.dir,
                region: Region::Inside(b.object),
                kind: m.kind,
                depth: b.depth,
                throughput: b.throughput[a],
                path,
                drift: b.drift,
                anchor: m.anchor,
                weight: b.weight * survived,
                from: None,
            };
            let (member_out, deeper) = scratch.split_at_mut(n);
            // A member's own wave has one mode: its basis is unused.
            let basis = &[DVec3::ZERO; 2];
            match traced.as_mut().and_then(|t| t[a].take()) {
                Some(t) => {
                    self.radiance_traced(&q, t, basis, batch, key, member_out, deeper, stats)
                }
                None => self.radiance(&q, basis, batch, key, member_out, deeper, stats),
            }
            for (o, j) in out.iter_mut().zip(member_out.iter()) {
                *o += on_mode(a, j.jxx() * survived);
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
