//! From a scene to what rendering it takes: the intersector over its
//! objects ([`accel`]), the wavelengths its camera modes trace
//! ([`lambdas`]) and the render options ([`options`], [`options_at`]).
//! The command line, tests and benchmarks all prepare renders here, so
//! that a scene's settings reach the renderer one way.

use super::integrator::TreeSettings;
use super::output::OutputMode;
use super::world::Scene;
use super::RenderOptions;
use crate::accel::{AccelError, AccelKind, Intersector, TriangleMesh};
use std::fmt;

/// Why a scene's intersector cannot be built.
#[derive(Debug)]
pub enum PrepareError {
    /// The backend is not in this build (Embree without the `native`
    /// feature).
    Unavailable(AccelKind),
    /// An instruction set was pinned for a backend other than Embree.
    IsaNotEmbree { kind: AccelKind, isa: String },
    /// The backend refused the scene's meshes.
    Build(AccelError),
}

impl fmt::Display for PrepareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PrepareError::Unavailable(kind) => write!(
                f,
                "--accel {kind}: this spar was built without the `native` feature, so Embree is \
                 not available; use --accel rust"
            ),
            PrepareError::IsaNotEmbree { kind, isa } => write!(
                f,
                "--isa {isa} pins Embree's instruction set; it does not apply to --accel {kind}"
            ),
            PrepareError::Build(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for PrepareError {}

/// Builds the `kind` backend over a scene's objects on `threads` threads
/// (0: all cores); `isa` pins Embree's instruction set. A backend this
/// build lacks, or an ISA for another backend than Embree, is refused
/// before anything is built.
pub fn accel(
    scene: &Scene,
    kind: AccelKind,
    threads: usize,
    isa: Option<&str>,
) -> Result<Box<dyn Intersector>, PrepareError> {
    check_backend(kind, isa)?;
    let verts: Vec<Vec<[f32; 3]>> = scene
        .objects
        .iter()
        .map(|o| o.mesh.vertices_f32())
        .collect();
    let meshes: Vec<TriangleMesh> = scene
        .objects
        .iter()
        .zip(&verts)
        .map(|(o, v)| TriangleMesh {
            vertices: v,
            triangles: &o.mesh.triangles,
        })
        .collect();
    match (kind, isa) {
        #[cfg(feature = "native")]
        (AccelKind::Embree, Some(isa)) => Ok(Box::new(
            crate::accel::embree::EmbreeAccel::build(&meshes, threads, Some(isa))
                .map_err(PrepareError::Build)?,
        )),
        _ => crate::accel::build(kind, &meshes, threads).map_err(PrepareError::Build),
    }
}

/// Refuses a backend this build lacks, and an instruction set pinned for
/// any backend but Embree.
pub fn check_backend(kind: AccelKind, isa: Option<&str>) -> Result<(), PrepareError> {
    if !kind.available() {
        return Err(PrepareError::Unavailable(kind));
    }
    if let (Some(isa), false) = (isa, kind == AccelKind::Embree) {
        return Err(PrepareError::IsaNotEmbree {
            kind,
            isa: isa.to_string(),
        });
    }
    Ok(())
}

/// The wavelengths `modes` need: the scene's colour wavelengths for the
/// spectral modes, `mono_nm` for the others.
///
/// The colour set comes first: [`options`] counts it as the set hero
/// sampling thins out. With hero sampling, a single-wavelength mode's
/// wavelength that is also in the colour set is moved to the end, so it is
/// traced for every sample (and the colour modes use it at weight 1).
pub fn lambdas(scene: &Scene, modes: &[OutputMode], mono_nm: f64) -> Vec<f64> {
    let same = |a: f64, b: f64| (a - b).abs() < 1e-9;
    let mono = modes.iter().any(|m| !m.is_spectral());
    let hero = scene.settings.approx.spectral.thins();
    let mut lambdas: Vec<f64> = Vec::new();
    if modes.iter().any(|m| m.needs_colour()) {
        lambdas.extend(
            scene
                .settings
                .wavelengths
                .lambdas()
                .iter()
                .filter(|&&l| !(mono && hero && same(l, mono_nm))),
        );
    }
    if mono && !lambdas.iter().any(|&l| same(l, mono_nm)) {
        lambdas.push(mono_nm);
    }
    lambdas
}

/// The render options for a scene and its modes (`spar render`'s): the
/// colour wavelengths first, a single-wavelength mode's right after them;
/// `progress` shows a progress bar.
pub fn options(scene: &Scene, modes: &[OutputMode], mono_nm: f64, progress: bool) -> RenderOptions {
    let lambdas = lambdas(scene, modes, mono_nm);
    let colour = scene.settings.wavelengths.lambdas();
    let mono = modes.iter().any(|m| !m.is_spectral());
    let same = |a: f64, b: f64| (a - b).abs() < 1e-9;
    // The colour set leads the list, a single-wavelength mode's
    // wavelength after it (`lambdas`).
    let colour_lambdas = if modes.iter().any(|m| m.needs_colour()) {
        lambdas
            .iter()
            .take_while(|&&l| colour.iter().any(|&c| same(c, l)) && !(mono && same(l, mono_nm)))
            .count()
    } else {
        0
    };
    RenderOptions {
        colour_lambdas,
        progress,
        ..options_at(scene, lambdas)
    }
}

/// The render options for a scene at `lambdas`, every one of them a
/// colour wavelength, without a progress bar.
pub fn options_at(scene: &Scene, lambdas: Vec<f64>) -> RenderOptions {
    RenderOptions {
        colour_lambdas: lambdas.len(),
        lambdas,
        tree: tree(scene),
        samples: scene.samples,
        seed: scene.settings.seed,
        progress: false,
        approx: scene.settings.approx,
        adaptive: scene.settings.adaptive,
    }
}

/// The scene's depth limit and pruning threshold, as the tree takes them.
pub fn tree(scene: &Scene) -> TreeSettings {
    TreeSettings {
        max_depth: scene.settings.max_depth,
        prune: scene.settings.prune,
        convex_exit: true,
    }
}
