"""spar: polarized light in cut gems and crystals, from Python.

Scenes are spar's TOML scene files (docs/scenes.md); renders come back as
NumPy arrays holding the values the command line's files hold; errors are
exceptions carrying the command line's messages. The guide is
docs/python.md.
"""

import os
from typing import Literal, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str
"""spar's version, with the git revision it was built from."""

NATIVE: bool
"""True when built with the `native` feature (Embree is available as
accel="embree"); False for the pure-Rust build (accel="rust" only)."""

Mode = Literal[
    "color",
    "mono",
    "dop",
    "ellipticity",
    "ellipticity-paper",
    "azimuth",
    "stokes",
    "polcam",
    "polcam-mosaic",
    "dichroscope",
]
Vector = Union[Sequence[float], str]

class SparError(Exception):
    """Any error spar reports; the message is the one the command line
    prints."""

class InputError(SparError, ValueError):
    """Bad input: a setting, a mode, a medium, a cut parameter (the command
    line's exit status 2)."""

class SceneError(InputError):
    """A scene that cannot be read. str(error) is spar's
    `FILE:LINE: field: reason`."""

    file: str
    """The scene file as given, or "<string>" for TOML text."""
    line: int | None
    """The line of the value at fault; None when the file has no place
    for it (a missing field, an unreadable file)."""
    field: str
    """The field at fault (`render.max_depth`); empty when the whole file
    is."""
    reason: str
    """Why, without the place."""

class Settings(TypedDict):
    samples: int
    resolution: tuple[int, int]
    wavelengths: list[float]
    max_depth: int
    prune: float
    seed: int
    branching: str
    polarization: str
    coherence: str
    spectral: str
    dispersion: str
    bundle: float
    roulette: float
    adaptive: float
    min_samples: int
    edges: float

class Scene:
    """A scene: objects, lights and camera as its file gave them, and
    settings that can be changed. Every change is checked by spar's
    validator, as the command line's flags are; a refused one raises
    InputError and changes nothing."""

    samples: int
    """Samples per pixel."""
    resolution: tuple[int, int]
    """(width, height) in pixels; also set as "WIDTHxHEIGHT"."""
    wavelengths: list[float]
    """The colour modes' wavelengths, nm. Set a count (spread over
    380–780 nm), a sequence in nm, or the flag's text ("580nm",
    "450,550,650")."""
    max_depth: int
    """The most surface interactions along a path (at most 1000)."""
    prune: float
    """Pruning threshold, a fraction of the brightest emitter (0: none)."""
    seed: int
    """The random seed."""
    branching: str
    """"full", "stochastic" or "hybrid:K"."""
    polarization: str
    """"full" (coherence matrices) or "scalar"."""
    coherence: str
    """"physical" or "incoherent" (the seed paper's model)."""
    spectral: str
    """"all" or "hero:K"."""
    dispersion: str
    """"on", "off" or "bands:K"."""
    bundle: float
    """o/e bundle tolerance in pixel footprints (0: every eigenwave its
    own ray, the exact tree); needs coherence "incoherent"."""
    roulette: float
    """Russian roulette threshold, a fraction of the brightest light: a
    subtree expected to carry less is traced with probability in
    proportion and weighted up (unbiased, noisier in dim light; 0: off,
    the exact tree)."""
    adaptive: float
    """Adaptive sampling: a pixel stops once the standard error of its
    mean is at most this, in display units (0: off; samples is then the
    most a pixel takes)."""
    min_samples: int
    """Samples every pixel takes before adaptive sampling's first check
    (at least 2)."""
    edges: float
    """Edge-adaptive sampling: every pixel takes min_samples samples, and
    only one that then differs from a neighbour by more than this (display
    units: sRGB values, normalized Stokes vectors) takes all samples
    (0: off)."""
    quality: Literal["draft", "fast", "default", "reference"]
    """Write-only (reading raises AttributeError): applies a preset of
    depth, pruning and approximations (docs/speed-vs-error.md); samples
    and wavelengths stay."""

    @property
    def settings(self) -> Settings:
        """Every setting, as plain values."""
    @property
    def label(self) -> str:
        """The scene as messages and metadata name it: its path as given,
        or "<string>"."""
    def set(
        self,
        *,
        samples: int | None = ...,
        resolution: tuple[int, int] | str | None = ...,
        wavelengths: int | Sequence[float] | str | None = ...,
        max_depth: int | None = ...,
        prune: float | None = ...,
        seed: int | None = ...,
        quality: Literal["draft", "fast", "default", "reference"] | None = ...,
        branching: str | None = ...,
        polarization: str | None = ...,
        coherence: str | None = ...,
        spectral: str | None = ...,
        dispersion: str | None = ...,
        bundle: float | None = ...,
        roulette: float | None = ...,
        adaptive: float | None = ...,
        min_samples: int | None = ...,
        edges: float | None = ...,
    ) -> None:
        """Changes several settings at once, checked together as the
        command line checks its flags (quality is a preset the others
        override). On an error nothing changes; an unknown name is a
        TypeError."""
    def copy(self) -> Scene:
        """A copy whose settings change without changing this scene."""
    def render(
        self,
        mode: Mode | str | Sequence[Mode] = "stokes",
        *,
        wavelength: float | None = None,
        accel: Literal["embree", "rust"] | None = None,
        threads: int | None = None,
        progress: bool = False,
        samples: int | None = ...,
        resolution: tuple[int, int] | str | None = ...,
        wavelengths: int | Sequence[float] | str | None = ...,
        max_depth: int | None = ...,
        prune: float | None = ...,
        seed: int | None = ...,
        quality: Literal["draft", "fast", "default", "reference"] | None = ...,
        branching: str | None = ...,
        polarization: str | None = ...,
        coherence: str | None = ...,
        spectral: str | None = ...,
        dispersion: str | None = ...,
        bundle: float | None = ...,
        roulette: float | None = ...,
        adaptive: float | None = ...,
        min_samples: int | None = ...,
        edges: float | None = ...,
        light_rig: str | None = ...,
        tilt: float | None = ...,
    ) -> Render:
        """Renders the scene in one or more modes (a name, "color,stokes"
        or a sequence), as `spar render --mode …` does.

        wavelength: the single-wavelength modes' wavelength, nm (default
        580); with "stokes", the Stokes array holds that wavelength only.
        accel: the intersection backend (default: embree where built in,
        else rust). threads: worker threads (None or 0: one per core).
        progress: a progress bar on standard error. The settings given
        here apply to this render only.

        The GIL is released while rendering. Ctrl-C (KeyboardInterrupt)
        stops the render after the tiles in flight and raises; the scene
        and the interpreter are unaffected. Lost light beyond 1e-4 of the
        image is a UserWarning.

        light_rig: a built-in rig instead of the scene's lights ("ring",
        "dome", "dome:DEG", "spot"; `spar render --light-rig`). tilt: the
        stone tilted by this many degrees about the camera's horizontal
        axis (`spar render --tilt`). Both for this render only (Scene.set
        refuses them)."""
    def __repr__(self) -> str: ...

class Render:
    """A finished render: one float32 array per mode.

    - "stokes": (wavelengths, height, width, 4), S0..S3 per pixel, the
      mean over the samples, in the Stokes frame of docs/outputs.md (the
      values of the command line's Stokes EXR, bit for bit).
    - "polcam": (4, height, width), the linear intensities behind
      polarizers at 0°, 45°, 90°, 135° (the float EXRs' values).
    - "polcam-mosaic": (height, width), the sensor mosaic's intensities.
    - "color", "mono", "dop", "ellipticity", "ellipticity-paper",
      "azimuth": (height, width, 3), display values in [0, 1] (sRGB
      encoded: the PNG's values before 8-bit quantization).
    - "dichroscope": (height, 2 * width, 3), the colour behind a polarizer
      along image right (left half) and along image up (right half), as
      "color" (docs/outputs.md).

    Rows run down the image, as in the files."""

    modes: list[str]
    """The modes rendered, in the order asked."""
    images: dict[str, npt.NDArray[np.float32]]
    """mode name → array."""
    wavelengths: npt.NDArray[np.float64]
    """The wavelengths of the Stokes array, nm; without the stokes mode,
    every traced wavelength."""
    wavelength: float
    """The single-wavelength modes' wavelength, nm."""
    metadata: dict[str, str]
    """spar:version, spar:scene, spar:scene_hash, spar:settings: what the
    command line's files of the same render carry."""
    stats: dict[str, float]
    """rays, nodes, pruned, rouletted, depth_cut, coherent, lost; accel_seconds,
    render_seconds."""

    @property
    def stokes(self) -> npt.NDArray[np.float32]:
        """images["stokes"]."""
    def __getitem__(self, mode: str) -> npt.NDArray[np.float32]:
        """images[mode]; a KeyError names the modes rendered."""

def load_scene(
    source: Union[str, os.PathLike[str]], *, base_dir: Union[str, os.PathLike[str], None] = None
) -> Scene:
    """Reads a scene: a path to a scene file (relative paths inside it are
    relative to its directory), or the TOML text of one (a str with a line
    break; relative paths resolve against base_dir, default the working
    directory). A bad scene raises SceneError naming file, line and
    field."""

def default_scene() -> Scene:
    """The embedded default scene (`spar render` without a scene file)."""

class Wave(TypedDict):
    side: Literal["reflected", "transmitted"]
    mode: Literal["s", "p", "o", "e"]
    k: list[float]
    """Real part of the wave vector, units of the vacuum wave number."""
    ray: list[float]
    """Unit energy direction (tangential for an evanescent wave)."""
    evanescent: bool
    energy: float
    """Fraction of the incident normal energy flux."""

def interface(
    from_: str,
    to: str,
    *,
    incident: Vector,
    mode: Literal["s", "p", "o", "e", "fast", "slow"],
    axis: Vector | None = None,
    axis_x: Vector | None = None,
    normal: Vector | None = None,
    wavelength: float = 589.3,
) -> list[Wave]:
    """Solves one interface: the four outgoing waves for one incident wave
    (reflected first, then transmitted), as `spar interface --json`
    prints them.

    from_, to: media (a built-in name such as air, n-bk7, calcite, quartz,
    sapphire, diamond; "iso:N"; "uniaxial:NO:NE"; "biaxial:NX:NY:NZ").
    incident: the incident wave vector's direction, toward the interface.
    mode: s or p (isotropic), o or e (uniaxial), fast or slow (biaxial).
    axis: the optic axis of whichever side is uniaxial, or a biaxial
    side's crystal z (default z). axis_x: a biaxial side's crystal x, made
    normal to axis (default: +x, or +y when axis is within 45° of ±x).
    normal: the interface normal,
    into the from_ medium (default z). Vectors are 3 numbers or "x,y,z".
    Errors carry the command line's messages (which name its flags)."""

class CutMesh(TypedDict):
    vertices: npt.NDArray[np.float64]
    """(N, 3) vertex positions, scene units."""
    faces: list[npt.NDArray[np.uint32]]
    """The facets: vertex indices, counter-clockwise seen from outside
    (the OBJ's `f` lines, 0-based)."""
    facet_names: list[str | None]
    triangles: npt.NDArray[np.uint32]
    """(M, 3): the triangles the renderer traces."""
    triangle_facet: npt.NDArray[np.uint32]
    """(M,): each triangle's facet."""
    summary: str
    """The validation summary `spar cut` prints."""
    notes: list[str]
    """Facets that vanished and validation warnings."""

def cut(cut: str, **params: float) -> CutMesh:
    """A cut's stone: "round-brilliant", "oval", "princess", "emerald"
    with parameters as keywords (table=0.56, crown_angle=33, …: the keys
    of a scene's `cut = { … }` table, docs/scenes.md), or a GemCAD .asc
    file's path (no parameters)."""
