//! The Stokes EXR in the field's layouts (issue 16 item 1): `stokes` in the
//! spectral-polarized OpenEXR layout of Fichet, Pacanowski & Wilkie (JCGT
//! 10(3), 2021), `stokes-rgb` as Mitsuba 3's `stokes` integrator writes it.
//! Golden checks of the channel names and header attributes against the
//! layout's rules, and read-backs by the readers users have: spar's own,
//! colour-science's `read_spectral_image_Fichet2021` and OpenImageIO's
//! Python module by channel name (tests/support/python/read_stokes_exr.py,
//! in a virtual environment under target/ that this test installs with pip;
//! required when CI=true, skipped with the reason printed otherwise).

use crate::support::run::{code_out_err, spar, spar_ok};
use spar::image::Image;
use spar::spectrum::{Observer, WavelengthSet};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The wavelengths rendered: one with a fraction, to check the layout's
/// decimal comma.
const NM: [f64; 3] = [450.0, 550.5, 650.0];
const NM_ARG: &str = "450,550.5,650";
const NM_TEXT: [&str; 3] = ["450", "550,5", "650"];

/// The versions of the readers the test installs.
const PIP: [&str; 2] = ["colour-science==0.4.7", "openimageio==3.2.2.0"];

fn scene() -> &'static str {
    concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/calcite-polarized.toml")
}

fn read(path: &Path) -> Image {
    spar::image::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The Python of a virtual environment with colour-science and
/// OpenImageIO, made once per test run (kept under target/ for the next),
/// or `None` with the reason printed when it cannot be made outside CI.
fn python() -> Option<&'static PathBuf> {
    static PYTHON: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let made = PYTHON.get_or_init(|| {
        let venv = Path::new(env!("CARGO_TARGET_TMPDIR")).join("stokes-readers-venv");
        let py = venv.join("bin/python");
        let ready = |py: &Path| {
            Command::new(py)
                .args(["-W", "ignore", "-c", "import colour, OpenImageIO"])
                .output()
                .is_ok_and(|o| o.status.success())
        };
        if ready(&py) {
            return Ok(py);
        }
        let run = |cmd: &mut Command| -> Result<(), String> {
            let out = cmd.output().map_err(|e| format!("{cmd:?}: {e}"))?;
            if out.status.success() {
                Ok(())
            } else {
                Err(format!(
                    "{cmd:?} failed: {}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ))
            }
        };
        run(Command::new("python3").args(["-m", "venv"]).arg(&venv))?;
        run(Command::new(venv.join("bin/pip"))
            .args(["install", "-q", "--disable-pip-version-check"])
            .args(PIP))?;
        if ready(&py) {
            Ok(py)
        } else {
            Err(format!(
                "{} cannot import colour and OpenImageIO",
                py.display()
            ))
        }
    });
    match made {
        Ok(py) => Some(py),
        Err(e) if std::env::var("CI").is_ok_and(|v| v == "true") => {
            panic!("CI must read the Stokes EXR with colour-science and OpenImageIO: {e}")
        }
        Err(e) => {
            eprintln!("SKIPPED the colour-science / OpenImageIO read-back (not in CI): {e}");
            None
        }
    }
}

/// What read_stokes_exr.py found in `file`, with the named channels read
/// through OpenImageIO.
fn python_read(py: &Path, file: &Path, channels: &[&str]) -> serde_json::Value {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/support/python/read_stokes_exr.py"
    );
    let out = Command::new(py)
        .arg(script)
        .arg(file)
        .args(channels)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "the Python readers failed on {}: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the reader prints JSON")
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The values of a float channel a reader printed, as the file's f32 (the
/// JSON text of an f32 widened to f64 comes back to the same f32).
fn f32s(v: &serde_json::Value) -> Vec<f32> {
    floats(v).iter().map(|&x| x as f32).collect()
}

/// Linear sRGB of the spectrum of channel `S<c>.<λ>nm` at every pixel, by
/// spar's observer of the rendered wavelengths (what the R, G, B preview
/// and stokes-rgb are defined to hold).
fn integrated(stokes: &Image, c: usize) -> [Vec<f64>; 3] {
    let observer = Observer::new(&WavelengthSet::from_list(&NM).unwrap()).unwrap();
    let planes: Vec<Vec<f32>> = NM_TEXT
        .iter()
        .map(|t| stokes.channel(&format!("S{c}.{t}nm")).unwrap())
        .collect();
    let mut out: [Vec<f64>; 3] = Default::default();
    for p in 0..planes[0].len() {
        let spectrum: Vec<f64> = planes.iter().map(|pl| pl[p] as f64).collect();
        let rgb = observer.linear_srgb(&spectrum);
        for k in 0..3 {
            out[k].push(rgb[k]);
        }
    }
    out
}

/// `got` equals `want` to float rounding, relative to the image's largest
/// value (S1..S3 are differences and can be far below S0).
fn assert_close(what: &str, got: &[f32], want: &[f64]) {
    assert_eq!(got.len(), want.len(), "{what}");
    let scale = want.iter().fold(1e-6f64, |m, v| m.max(v.abs()));
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (*g as f64 - w).abs() <= 1e-5 * scale,
            "{what} pixel {i}: {g} in the file, {w} from the spectrum"
        );
    }
}

#[test]
fn the_stokes_exr_is_the_jcgt_2021_layout_and_its_readers_read_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        scene(),
        "--resolution",
        "8x6",
        "--samples",
        "1",
        "--wavelengths",
        NM_ARG,
        "--mode",
        "stokes",
        "-q",
        "-o",
        "s.exr",
    ];
    spar_ok(d, &args);
    let file = d.join("s.exr");
    let img = read(&file);

    // Golden: the channels the paper's rules give (S<c>.<λ>nm with a
    // decimal comma) and the linear sRGB preview, nothing else.
    let mut want: BTreeSet<String> = ["R", "G", "B"].iter().map(|s| s.to_string()).collect();
    for c in 0..4 {
        for t in NM_TEXT {
            want.insert(format!("S{c}.{t}nm"));
        }
    }
    let got: BTreeSet<String> = img.channels().iter().cloned().collect();
    assert_eq!(got, want);
    let meta = img.metadata();
    for (k, v) in [
        ("spectralLayoutVersion", "1.0"),
        ("emissiveUnits", "W.m^-2.sr^-1"),
        ("polarisationHandedness", "right"),
        ("spar:mode", "stokes"),
        ("spar:wavelengths_nm", "450,550.5,650"),
    ] {
        assert_eq!(meta.get(k).map(String::as_str), Some(v), "attribute {k}");
    }
    // The scene is polarized light through calcite: S1 is not all zero, so
    // the comparisons below compare something.
    assert!(img
        .channel("S1.550,5nm")
        .unwrap()
        .iter()
        .any(|v| v.abs() > 1.0));
    // The preview is S0 through the CIE observer to linear sRGB.
    let rgb = integrated(&img, 0);
    for (k, name) in ["R", "G", "B"].iter().enumerate() {
        assert_close(name, &img.channel(name).unwrap(), &rgb[k]);
    }

    let Some(py) = python() else { return };
    let by_name = ["S0.550,5nm", "S3.650nm", "S2.450nm", "R"];
    let found = python_read(py, &file, &by_name);
    eprintln!(
        "read back with colour-science {}",
        found["colour_version"].as_str().unwrap_or("?")
    );
    assert_eq!(found["is_emissive"], true);
    assert_eq!(found["is_polarised"], true);
    for (k, v) in [
        ("spectralLayoutVersion", "1.0"),
        ("emissiveUnits", "W.m^-2.sr^-1"),
        ("polarisationHandedness", "right"),
    ] {
        assert_eq!(found["attributes"][k], v, "colour-science's {k}");
        assert_eq!(found["oiio_attributes"][k], v, "OpenImageIO's {k}");
    }
    let components = found["components"].as_object().unwrap();
    assert_eq!(
        components.keys().collect::<Vec<_>>(),
        ["S0", "S1", "S2", "S3"]
    );
    for c in 0..4 {
        let comp = &components[&format!("S{c}")];
        assert_eq!(floats(&comp["wavelengths"]), NM, "S{c}'s wavelengths");
        let values = comp["values"].as_array().unwrap();
        for (t, v) in NM_TEXT.iter().zip(values) {
            let ours = img.channel(&format!("S{c}.{t}nm")).unwrap();
            assert_eq!(f32s(v), ours, "S{c} at {t} nm, colour-science against spar");
        }
    }
    for name in by_name {
        let ours = img.channel(name).unwrap();
        assert_eq!(f32s(&found["oiio"][name]), ours, "{name} by OpenImageIO");
    }
}

#[test]
fn stokes_rgb_is_mitsubas_layout_each_component_integrated() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        scene(),
        "--resolution",
        "8x6",
        "--samples",
        "1",
        "--wavelengths",
        NM_ARG,
        "--mode",
        "stokes,stokes-rgb",
        "-q",
        "-o",
        "x.exr",
    ];
    spar_ok(d, &args);
    let stokes = read(&d.join("x-stokes.exr"));
    let file = d.join("x-stokes-rgb.exr");
    let rgb = read(&file);
    let mut want: BTreeSet<String> = ["R", "G", "B"].iter().map(|s| s.to_string()).collect();
    for c in 0..4 {
        for k in ["R", "G", "B"] {
            want.insert(format!("S{c}.{k}"));
        }
    }
    let got: BTreeSet<String> = rgb.channels().iter().cloned().collect();
    assert_eq!(got, want);
    assert_eq!(rgb.metadata()["spar:mode"], "stokes-rgb");
    for c in 0..4 {
        let want = integrated(&stokes, c);
        for (k, name) in ["R", "G", "B"].iter().enumerate() {
            let ch = format!("S{c}.{name}");
            assert_close(&ch, &rgb.channel(&ch).unwrap(), &want[k]);
        }
    }
    assert_eq!(rgb.channel("R").unwrap(), rgb.channel("S0.R").unwrap());
    assert!(rgb.channel("S1.G").unwrap().iter().any(|v| v.abs() > 0.01));

    // stokes-rgb integrates the colour wavelengths: --wavelength alone with
    // it is refused, not ignored.
    let (code, _, err) = code_out_err(&spar(
        d,
        &[
            "render",
            scene(),
            "--mode",
            "stokes-rgb",
            "--wavelength",
            "600",
            "-o",
            "y.exr",
        ],
    ));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--wavelength 600") && err.contains("stokes-rgb"),
        "{err}"
    );
    assert!(!d.join("y.exr").exists());

    let Some(py) = python() else { return };
    let names = ["S0.R", "S1.G", "S3.B", "R"];
    let found = python_read_oiio_only(py, &file, &names);
    for name in names {
        let ours = rgb.channel(name).unwrap();
        assert_eq!(f32s(&found[name]), ours, "{name} by OpenImageIO");
    }
}

/// OpenImageIO's values of `channels` (by name) in a file that is not in
/// the spectral layout.
fn python_read_oiio_only(py: &Path, file: &Path, channels: &[&str]) -> serde_json::Value {
    let code = "import sys, json, numpy as np, OpenImageIO as oiio\n\
                i = oiio.ImageInput.open(sys.argv[1]); s = i.spec()\n\
                px = i.read_image(0, 0, 0, s.nchannels, 'float')\n\
                out = {}\n\
                for n in sys.argv[2:]:\n    \
                    k = s.channelindex(n)\n    \
                    assert k >= 0, n\n    \
                    out[n] = np.asarray(px[:, :, k], dtype=np.float64).ravel().tolist()\n\
                json.dump(out, sys.stdout)\n";
    let out = Command::new(py)
        .args(["-c", code])
        .arg(file)
        .args(channels)
        .output()
        .expect("python runs");
    assert!(
        out.status.success(),
        "OpenImageIO failed on {}: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}
