//! Throughput of the intersection backends, one ray at a time as the
//! integrator traces them, printed as a table of medians and ratios measured
//! in one run:
//!
//! - `raw`: `rtcIntersect1` called directly through `spar_sys::embree`, with
//!   the scene set up as spar's wrapper sets it up (robust, high quality):
//!   the most Embree can do for one ray;
//! - `embree`: spar's Embree backend through the `Intersector` trait;
//! - `rust`: spar's Rust BVH through the trait.
//!
//! Meshes: every gem in `scenes/gems/`, a bumpy icosphere of 81 920
//! triangles and a bumpy torus of 1 048 576. Rays: `coherent` (a pinhole
//! camera's grid from one point, aimed at the mesh) and `incoherent`
//! (origins uniform in the mesh's box enlarged by 20 %, directions uniform
//! on the sphere). Each row runs on one thread and on all threads; the
//! contenders take turns, repetition by repetition, so that load from other
//! processes spreads over all of them.
//!
//! `cargo bench --bench accel` (all rows) or `cargo bench --bench accel --
//! <filter>` (rows whose mesh name contains the filter). Without the
//! `native` feature only the Rust backend runs.

use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use spar::accel::bvh::RustBvh;
use spar::accel::{Intersector, Ray, TriangleMesh};
use std::path::Path;
use std::time::Instant;

/// A mesh owned by the benchmark.
struct OwnedMesh {
    name: String,
    vertices: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl OwnedMesh {
    fn view(&self) -> TriangleMesh<'_> {
        TriangleMesh {
            vertices: &self.vertices,
            triangles: &self.triangles,
        }
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        self.vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| {
                let p = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
                (lo.min(p), hi.max(p))
            },
        )
    }
}

fn gems() -> Vec<OwnedMesh> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gems");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    paths.sort();
    paths
        .iter()
        .map(|p| {
            let mesh = spar::geometry::load_obj(p).unwrap();
            OwnedMesh {
                name: p.file_stem().unwrap().to_string_lossy().into_owned(),
                vertices: mesh.vertices_f32(),
                triangles: mesh.triangles.clone(),
            }
        })
        .collect()
}

/// A radial bump field so that the generated meshes are not convex.
fn bump(p: DVec3) -> f64 {
    1.0 + 0.08 * (7.0 * p.x).sin() * (9.0 * p.y).sin() * (5.0 * p.z).sin()
}

/// An icosahedron subdivided `levels` times (20·4^levels triangles), pushed
/// out to a bumpy sphere.
fn bumpy_icosphere(levels: u32) -> OwnedMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, verts: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push(((verts[a as usize] + verts[b as usize]) / 2.0).normalize());
                verts.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = midpoint(a, b, &mut verts);
            let bc = midpoint(b, c, &mut verts);
            let ca = midpoint(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    OwnedMesh {
        name: format!("icosphere{}k", tris.len() / 1000),
        vertices: verts
            .iter()
            .map(|&p| (p * bump(p)).as_vec3().to_array())
            .collect(),
        triangles: tris,
    }
}

/// A torus (radii 1 and 0.35) of `nu × nv` quads, bumpy.
fn bumpy_torus(nu: u32, nv: u32) -> OwnedMesh {
    let mut vertices = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (
                i as f64 / nu as f64 * std::f64::consts::TAU,
                j as f64 / nv as f64 * std::f64::consts::TAU,
            );
            let r = 0.35 * bump(DVec3::new(u.cos(), u.sin(), v.sin()));
            let p = DVec3::new(
                (1.0 + r * v.cos()) * u.cos(),
                (1.0 + r * v.cos()) * u.sin(),
                r * v.sin(),
            );
            vertices.push(p.as_vec3().to_array());
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let mut triangles = Vec::with_capacity((2 * nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    OwnedMesh {
        name: format!("torus{}k", triangles.len() / 1000),
        vertices,
        triangles,
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum RayKind {
    Coherent,
    Incoherent,
}

impl RayKind {
    fn name(self) -> &'static str {
        match self {
            RayKind::Coherent => "coherent",
            RayKind::Incoherent => "incoherent",
        }
    }
}

fn rays(mesh: &OwnedMesh, kind: RayKind, n: usize) -> Vec<Ray> {
    let (lo, hi) = mesh.bounds();
    let center = (lo + hi) / 2.0;
    let radius = (hi - lo).length() / 2.0;
    let mut rng = Pcg64Mcg::seed_from_u64(0x5eed);
    match kind {
        RayKind::Incoherent => (0..n)
            .map(|_| {
                let u = DVec3::new(rng.gen(), rng.gen(), rng.gen());
                let o = center + (u - DVec3::splat(0.5)) * (hi - lo) * 1.2;
                let d = loop {
                    let d = DVec3::new(
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                    );
                    if d.length_squared() <= 1.0 && d.length_squared() > 1e-6 {
                        break d.normalize();
                    }
                };
                Ray::new(o, d)
            })
            .collect(),
        RayKind::Coherent => {
            // A pinhole at 3 radii, looking at the centre; the image plane
            // spans the bounding sphere.
            let eye = center + DVec3::new(0.6, -0.7, 0.4).normalize() * 3.0 * radius;
            let w = (center - eye).normalize();
            let u = w.cross(DVec3::Z).normalize();
            let v = u.cross(w);
            let side = (n as f64).sqrt().ceil() as usize;
            let half = (radius / (3.0 * radius)) * 1.05;
            (0..n)
                .map(|i| {
                    let (x, y) = ((i % side) as f64, (i / side) as f64);
                    let sx = (2.0 * (x + 0.5) / side as f64 - 1.0) * half;
                    let sy = (2.0 * (y + 0.5) / side as f64 - 1.0) * half;
                    Ray::new(eye, (w + sx * u + sy * v).normalize())
                })
                .collect()
        }
    }
}

/// Something that traces a batch of rays and returns how many hit and a
/// checksum of the primitives hit (so that no work can be skipped, and so
/// that the contenders can be seen to agree).
trait Contender: Sync {
    fn trace(&self, rays: &[Ray]) -> (usize, u64);
}

struct Trait<'a>(&'a dyn Intersector);

impl Contender for Trait<'_> {
    fn trace(&self, rays: &[Ray]) -> (usize, u64) {
        let (mut hits, mut sum) = (0, 0u64);
        for r in rays {
            if let Some(h) = self.0.intersect(r) {
                hits += 1;
                sum = sum.wrapping_add(h.prim as u64);
            }
        }
        (hits, sum)
    }
}

#[cfg(feature = "native")]
mod raw {
    //! `rtcIntersect1` without spar's wrapper.
    use spar::accel::{Ray, TriangleMesh};
    use spar_sys::embree as sys;

    pub struct RawEmbree {
        device: sys::RTCDevice,
        scene: sys::RTCScene,
    }

    // SAFETY: a committed Embree scene may be traced from many threads.
    unsafe impl Send for RawEmbree {}
    unsafe impl Sync for RawEmbree {}

    impl RawEmbree {
        pub fn new(meshes: &[TriangleMesh<'_>], threads: usize) -> RawEmbree {
            let config = std::ffi::CString::new(format!("threads={threads}")).unwrap();
            // SAFETY: plain Embree API use, as in its tutorials; buffers are
            // allocated by Embree with the sizes given and filled in bounds.
            unsafe {
                let device = sys::rtcNewDevice(config.as_ptr());
                assert!(!device.is_null());
                let scene = sys::rtcNewScene(device);
                sys::rtcSetSceneFlags(scene, sys::RTCSceneFlags::RTC_SCENE_FLAG_ROBUST);
                sys::rtcSetSceneBuildQuality(scene, sys::RTCBuildQuality::RTC_BUILD_QUALITY_HIGH);
                for m in meshes {
                    let g = sys::rtcNewGeometry(
                        device,
                        sys::RTCGeometryType::RTC_GEOMETRY_TYPE_TRIANGLE,
                    );
                    let vb = sys::rtcSetNewGeometryBuffer(
                        g,
                        sys::RTCBufferType::RTC_BUFFER_TYPE_VERTEX,
                        0,
                        sys::RTCFormat::RTC_FORMAT_FLOAT3,
                        12,
                        m.vertices.len(),
                    ) as *mut [f32; 3];
                    let ib = sys::rtcSetNewGeometryBuffer(
                        g,
                        sys::RTCBufferType::RTC_BUFFER_TYPE_INDEX,
                        0,
                        sys::RTCFormat::RTC_FORMAT_UINT3,
                        12,
                        m.triangles.len(),
                    ) as *mut [u32; 3];
                    std::ptr::copy_nonoverlapping(m.vertices.as_ptr(), vb, m.vertices.len());
                    std::ptr::copy_nonoverlapping(m.triangles.as_ptr(), ib, m.triangles.len());
                    sys::rtcCommitGeometry(g);
                    sys::rtcAttachGeometry(scene, g);
                    sys::rtcReleaseGeometry(g);
                }
                sys::rtcCommitScene(scene);
                assert_eq!(
                    sys::rtcGetDeviceError(device),
                    sys::RTCError::RTC_ERROR_NONE
                );
                RawEmbree { device, scene }
            }
        }
    }

    impl Drop for RawEmbree {
        fn drop(&mut self) {
            // SAFETY: released once, scene before device.
            unsafe {
                sys::rtcReleaseScene(self.scene);
                sys::rtcReleaseDevice(self.device);
            }
        }
    }

    impl super::Contender for RawEmbree {
        fn trace(&self, rays: &[Ray]) -> (usize, u64) {
            spar::native::embree::set_denormal_flags_for_this_thread();
            let mut context = sys::rtc_init_intersect_context();
            let (mut hits, mut sum) = (0, 0u64);
            for r in rays {
                let mut rh = sys::RTCRayHit {
                    ray: sys::RTCRay {
                        org_x: r.origin.x as f32,
                        org_y: r.origin.y as f32,
                        org_z: r.origin.z as f32,
                        tnear: r.tmin as f32,
                        dir_x: r.dir.x as f32,
                        dir_y: r.dir.y as f32,
                        dir_z: r.dir.z as f32,
                        time: 0.0,
                        tfar: f32::INFINITY,
                        mask: u32::MAX,
                        id: 0,
                        flags: 0,
                    },
                    hit: sys::RTCHit {
                        geomID: sys::RTC_INVALID_GEOMETRY_ID,
                        ..Default::default()
                    },
                };
                // SAFETY: committed scene; context and ray are ours, the
                // ray is 16-byte aligned by its type.
                unsafe { sys::rtcIntersect1(self.scene, &mut context, &mut rh) };
                if rh.hit.geomID != sys::RTC_INVALID_GEOMETRY_ID {
                    hits += 1;
                    sum = sum.wrapping_add(rh.hit.primID as u64);
                }
            }
            (hits, sum)
        }
    }
}

/// Rays per second of `c` on `rays` with `pool`: median of the samples.
fn run(pool: &rayon::ThreadPool, c: &dyn Contender, rays: &[Ray]) -> (f64, usize) {
    let start = Instant::now();
    let (hits, _) = pool.install(|| {
        rays.par_chunks(2048)
            .map(|chunk| c.trace(chunk))
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1.wrapping_add(b.1)))
    });
    (rays.len() as f64 / start.elapsed().as_secs_f64(), hits)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let all_threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let reps: usize = std::env::var("ACCEL_BENCH_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);

    let mut meshes = gems();
    meshes.push(bumpy_icosphere(6));
    meshes.push(bumpy_torus(1024, 512));
    meshes.retain(|m| filter.as_ref().is_none_or(|f| m.name.contains(f.as_str())));

    println!(
        "# rays/s (millions), median of {reps}; ratios to raw rtcIntersect1; {all_threads} threads max"
    );
    println!(
        "{:<22} {:>8} {:<10} {:>3} | {:>8} | {:>8} {:>6} | {:>8} {:>6} | hits raw/emb/rust",
        "mesh", "tris", "rays", "thr", "raw", "embree", "ratio", "rust", "ratio"
    );
    for mesh in &meshes {
        let view = [mesh.view()];
        let t0 = Instant::now();
        let rust = RustBvh::build(&view, all_threads).unwrap();
        let rust_build = t0.elapsed().as_secs_f64();
        #[cfg(feature = "native")]
        let (raw, embree, raw_build) = {
            let t0 = Instant::now();
            let raw = raw::RawEmbree::new(&view, all_threads);
            let raw_build = t0.elapsed().as_secs_f64();
            let embree = spar::accel::embree::EmbreeAccel::build(&view, all_threads, None).unwrap();
            (raw, embree, raw_build)
        };
        let n = if mesh.triangles.len() > 10_000 {
            1 << 18
        } else {
            1 << 20
        };
        for kind in [RayKind::Coherent, RayKind::Incoherent] {
            let rays = rays(mesh, kind, n);
            for threads in [1, all_threads] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let rust_c = Trait(&rust);
                #[cfg(feature = "native")]
                let embree_c = Trait(&embree);
                #[cfg(feature = "native")]
                let contenders: Vec<&dyn Contender> = vec![&raw, &embree_c, &rust_c];
                #[cfg(not(feature = "native"))]
                let contenders: Vec<&dyn Contender> = vec![&rust_c];
                let mut samples = vec![Vec::new(); contenders.len()];
                let mut hits = vec![0; contenders.len()];
                for c in &contenders {
                    run(&pool, *c, &rays); // warm-up
                }
                for _ in 0..reps {
                    for (i, c) in contenders.iter().enumerate() {
                        let (rate, h) = run(&pool, *c, &rays);
                        samples[i].push(rate);
                        hits[i] = h;
                    }
                }
                let med: Vec<f64> = samples.into_iter().map(median).collect();
                let m = |x: f64| x / 1e6;
                if cfg!(feature = "native") {
                    println!(
                        "{:<22} {:>8} {:<10} {:>3} | {:>8.2} | {:>8.2} {:>6.2} | {:>8.2} {:>6.2} | {}/{}/{}",
                        mesh.name,
                        mesh.triangles.len(),
                        kind.name(),
                        threads,
                        m(med[0]),
                        m(med[1]),
                        med[1] / med[0],
                        m(med[2]),
                        med[2] / med[0],
                        hits[0],
                        hits[1],
                        hits[2]
                    );
                } else {
                    println!(
                        "{:<22} {:>8} {:<10} {:>3} | {:>8} | {:>8} {:>6} | {:>8.2} {:>6} | -/-/{}",
                        mesh.name,
                        mesh.triangles.len(),
                        kind.name(),
                        threads,
                        "-",
                        "-",
                        "-",
                        m(med[0]),
                        "-",
                        hits[0]
                    );
                }
            }
        }
        #[cfg(feature = "native")]
        println!(
            "{:<22} build: rust {:.1} ms, embree {:.1} ms; rust {:?}",
            mesh.name,
            rust_build * 1e3,
            raw_build * 1e3,
            rust.stats()
        );
        #[cfg(not(feature = "native"))]
        println!(
            "{:<22} build: rust {:.1} ms; {:?}",
            mesh.name,
            rust_build * 1e3,
            rust.stats()
        );
    }
}
