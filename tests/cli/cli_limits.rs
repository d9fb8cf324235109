//! What cannot fit is refused before it is allocated: an image or a
//! wavelength count whose film exceeds the machine's memory (exit status
//! 2, the flag or field named, the estimate in GiB and the memory
//! available), and a `--threads` count far past the cores (exit status 2,
//! the flag named). No output file in any case.

use crate::support::run;
use std::path::Path;
use std::time::{Duration, Instant};

const SCENE: &str = r#"
[camera]
eye = [0.0, -3.0, 2.0]
look_at = [0.0, 0.0, 0.0]
fov = 30.0
resolution = [8, 8]

[[object]]
mesh = "builtin:trichecker12"
medium = "n-bk7"

[[light]]
corners = [[-2.0, -2.0, -1.5], [2.0, -2.0, -1.5], [2.0, 2.0, -1.5], [-2.0, 2.0, -1.5]]
"#;

/// Runs spar in `dir`: exit status, standard error, and how long it took.
fn spar(dir: &Path, args: &[&str]) -> (i32, String, Duration) {
    let t = Instant::now();
    let (code, _, err) = run::code_out_err(&run::spar(dir, args));
    (code, err, t.elapsed())
}

/// `args` exit 2 saying each of `says`, before any rendering (well under
/// a minute: a refused job must not first allocate or spawn), and leave
/// no file in `dir` but the scene.
fn refused(dir: &Path, args: &[&str], says: &[&str]) {
    let (code, err, took) = spar(dir, args);
    assert_eq!(code, 2, "{args:?}: {err}");
    for s in says {
        assert!(err.contains(s), "{args:?}: `{s}` not in {err}");
    }
    assert!(took < Duration::from_secs(30), "{args:?} took {took:?}");
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "scene.toml")
        .collect();
    assert!(left.is_empty(), "{args:?} left {left:?}");
}

#[test]
fn films_that_cannot_fit_are_refused_with_the_estimate() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    let render = |extra: &[&'static str]| {
        let mut a = vec![
            "render",
            "scene.toml",
            "--samples",
            "1",
            "--quiet",
            "-o",
            "out.png",
        ];
        a.extend(extra);
        a
    };
    // Past the side limit: the estimate is in the message too.
    refused(
        d,
        &render(&["--resolution", "1000000x1000000"]),
        &[
            "--resolution 1000000x1000000",
            "at most 65536 pixels per side",
            "GiB of memory",
        ],
    );
    // Within it, but 65536² pixels of 21 wavelengths are terabytes.
    refused(
        d,
        &render(&["--resolution", "65536x65536"]),
        &[
            "--resolution 65536x65536",
            "render.wavelengths (21 traced)",
            "GiB of memory",
            "available",
        ],
    );
    // A raw part is sized by its region.
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "-q",
            "--resolution",
            "65536x65536",
            "--tile",
            "3/4",
            "-o",
            "p.exr",
        ],
        &["--resolution 65536x65536, region", "GiB of memory"],
    );
    // Wavelengths: past the bound, or too many for the image.
    refused(
        d,
        &render(&["--wavelengths", "100000"]),
        &["--wavelengths 100000", "at most 10000", "GiB"],
    );
    refused(
        d,
        &render(&["--wavelengths", "10000", "--resolution", "4000x4000"]),
        &[
            "--resolution 4000x4000 with --wavelengths 10000 (10000 traced)",
            "GiB of memory",
        ],
    );
    // A scene file's count.
    std::fs::write(
        d.join("scene.toml"),
        SCENE.replace(
            "[[object]]",
            "[render]\nwavelengths = 4000000000\n\n[[object]]",
        ),
    )
    .unwrap();
    refused(
        d,
        &render(&[]),
        &["scene.toml:9:", "4000000000 wavelengths: at most 10000"],
    );
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    // What fits renders.
    let (code, err, _) = spar(d, &render(&["--wavelengths", "10000"]));
    assert_eq!(code, 0, "{err}");
    assert!(d.join("out.png").exists());
}

#[test]
fn thread_counts_far_past_the_cores_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("scene.toml"), SCENE).unwrap();
    refused(
        d,
        &[
            "render",
            "scene.toml",
            "--samples",
            "1",
            "-q",
            "--threads",
            "100000",
            "-o",
            "out.png",
        ],
        &["--threads 100000: at most", "cores"],
    );
    // Every command that renders goes through the same check (contact
    // sheets need OpenImageIO for their labels, so the native build).
    #[cfg(feature = "native")]
    refused(
        d,
        &[
            "contact-sheet",
            "scene.toml",
            "--threads",
            "100000",
            "-o",
            "sheet.png",
        ],
        &["--threads 100000: at most"],
    );
    // 64 threads are always allowed, whatever the machine.
    let (code, err, _) = spar(
        d,
        &[
            "render",
            "scene.toml",
            "--samples",
            "1",
            "-q",
            "--threads",
            "64",
            "-o",
            "out.png",
        ],
    );
    assert_eq!(code, 0, "{err}");
}
