//! Build logic for spar-sys: bindings to Embree 3 (bindgen), linked into
//! spar, and the C++ shim over OpenImageIO, built as its own shared library
//! (`libspar_oiio.so`) that spar loads with `dlopen` the first time it needs
//! OpenImageIO.
//!
//! Why a separate library: OpenImageIO pulls in about 260 shared libraries
//! (OpenCV, ffmpeg, OpenVDB, …). Linked into spar they were mapped at every
//! start (0.2 s and 130 MiB for `spar --version`). The shim library links
//! them instead, so only a process that reads or writes an image through
//! OpenImageIO pays for them. spar itself never links OpenImageIO.
//!
//! The library is written to `OUT_DIR`, and its path is handed to the
//! spar-sys crate as `SPAR_OIIO_SHIM_BUILT` (`spar_sys::oiio::BUILT_LIBRARY`)
//! so that binaries run from the build tree (`cargo run`, `cargo test`,
//! `target/release/spar`) find it with no extra step.
//!
//! Each library is found through a ladder, first rung that works wins:
//!
//! Embree 3 (Debian ships no pkg-config file for it):
//!   1. `EMBREE_DIR`: a prefix with `include/embree3/rtcore.h` and
//!      `lib/libembree3.so` (or `lib64/`);
//!   2. pkg-config `embree3`, for distributions that ship one;
//!   3. the system default (`/usr/include`, the linker's search path).
//!
//! OpenImageIO:
//!   1. `OIIO_DIR`: a prefix with `include/OpenImageIO/` and `lib/`;
//!   2. pkg-config `OpenImageIO` (Debian's `libopenimageio-dev`).
//!
//! When a rung fails the build stops with a message that names the Debian
//! package to install. Embree's link directories are passed on to dependent
//! crates as `DEP_EMBREE3_LIB_DIRS` (see spar's own `build.rs`, which adds
//! an rpath for libraries outside the system directories); the shim library
//! gets its own rpath to an OpenImageIO outside them.

use std::env;
use std::path::{Path, PathBuf};

const DEBIAN_HINT_EMBREE: &str =
    "install Embree 3 (Debian/Ubuntu: `apt-get install libembree-dev`) \
     or set EMBREE_DIR to a prefix containing include/embree3/rtcore.h";
const DEBIAN_HINT_OIIO: &str =
    "install OpenImageIO (Debian/Ubuntu: `apt-get install libopenimageio-dev`) \
     or set OIIO_DIR to a prefix containing include/OpenImageIO/imageio.h";

/// File name of the shim library (also `spar_sys::oiio::LIBRARY_FILE`).
const SHIM_FILE: &str = "libspar_oiio.so";

/// Where a native library's headers and shared objects are.
struct Found {
    include_dirs: Vec<PathBuf>,
    lib_dirs: Vec<PathBuf>,
    /// Libraries to link, without `lib` and suffix (OpenImageIO only;
    /// Embree's is linked by name).
    libs: Vec<String>,
}

fn main() {
    println!("cargo:rerun-if-env-changed=EMBREE_DIR");
    println!("cargo:rerun-if-env-changed=OIIO_DIR");
    println!("cargo:rerun-if-changed=shim/oiio_shim.cpp");
    println!("cargo:rerun-if-changed=shim/oiio_shim.h");
    println!("cargo:rerun-if-changed=wrapper.h");

    let embree = find_embree().unwrap_or_else(|e| fail(&e));
    check_embree_version(&embree).unwrap_or_else(|e| fail(&e));
    generate_embree_bindings(&embree);
    for dir in &embree.lib_dirs {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    println!("cargo:rustc-link-lib=dylib=embree3");

    let oiio = find_oiio().unwrap_or_else(|e| fail(&e));
    let shim = build_oiio_shim(&oiio);
    println!("cargo:rustc-env=SPAR_OIIO_SHIM_BUILT={}", shim.display());

    // Metadata for dependents (`links = "embree3"` makes these visible as
    // DEP_EMBREE3_*): where Embree's shared objects live, for rpath hints.
    let lib_dirs: Vec<String> = embree
        .lib_dirs
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    println!("cargo:lib_dirs={}", lib_dirs.join(":"));
}

fn fail(message: &str) -> ! {
    eprintln!("\nspar-sys: {message}\n");
    panic!("spar-sys: {message}");
}

/// Ladder for Embree 3: EMBREE_DIR, pkg-config, system default.
fn find_embree() -> Result<Found, String> {
    // Rung 1: explicit override.
    if let Some(prefix) = env::var_os("EMBREE_DIR") {
        let prefix = PathBuf::from(prefix);
        let include = prefix.join("include");
        if !include.join("embree3/rtcore.h").is_file() {
            return Err(format!(
                "EMBREE_DIR={} has no include/embree3/rtcore.h; {DEBIAN_HINT_EMBREE}",
                prefix.display()
            ));
        }
        let lib_dirs = ["lib", "lib64"]
            .iter()
            .map(|d| prefix.join(d))
            .filter(|d| d.is_dir())
            .collect();
        return Ok(Found {
            include_dirs: vec![include],
            lib_dirs,
            libs: Vec::new(),
        });
    }
    // Rung 2: pkg-config, where a distribution ships embree3.pc.
    if let Ok(lib) = pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("embree3")
    {
        return Ok(Found {
            include_dirs: lib.include_paths,
            lib_dirs: lib.link_paths,
            libs: Vec::new(),
        });
    }
    // Rung 3: the system default.
    for include in ["/usr/include", "/usr/local/include"] {
        if Path::new(include).join("embree3/rtcore.h").is_file() {
            return Ok(Found {
                include_dirs: vec![PathBuf::from(include)],
                lib_dirs: Vec::new(),
                libs: Vec::new(),
            });
        }
    }
    Err(format!("Embree 3 headers not found; {DEBIAN_HINT_EMBREE}"))
}

/// Embree 4 ships under the same Debian package name with another API.
fn check_embree_version(found: &Found) -> Result<(), String> {
    for dir in &found.include_dirs {
        let config = dir.join("embree3/rtcore_config.h");
        if let Ok(text) = std::fs::read_to_string(&config) {
            let major = text
                .lines()
                .find_map(|l| l.strip_prefix("#define RTC_VERSION_MAJOR "))
                .map(|v| v.trim().to_string());
            return match major.as_deref() {
                Some("3") => Ok(()),
                Some(v) => Err(format!(
                    "{} says Embree version {v}; spar needs Embree 3 (3.13). {DEBIAN_HINT_EMBREE}",
                    config.display()
                )),
                None => Err(format!(
                    "cannot read RTC_VERSION_MAJOR from {}",
                    config.display()
                )),
            };
        }
    }
    Err(format!(
        "embree3/rtcore_config.h not found; {DEBIAN_HINT_EMBREE}"
    ))
}

fn generate_embree_bindings(found: &Found) {
    let mut builder = bindgen::Builder::default()
        .header("wrapper.h")
        .allowlist_function("rtc.*")
        .allowlist_type("RTC.*")
        .allowlist_var("RTC.*")
        .rustified_enum("RTCError")
        .rustified_enum("RTCFormat")
        .rustified_enum("RTCGeometryType")
        .rustified_enum("RTCBufferType")
        .rustified_enum("RTCBuildQuality")
        .rustified_enum("RTCDeviceProperty")
        .bitfield_enum("RTCSceneFlags")
        .bitfield_enum("RTCIntersectContextFlags")
        .derive_default(true)
        .layout_tests(true)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    for dir in &found.include_dirs {
        builder = builder.clang_arg(format!("-I{}", dir.display()));
    }
    let bindings = builder.generate().unwrap_or_else(|e| {
        fail(&format!(
            "bindgen failed on embree3/rtcore.h ({e}). bindgen needs libclang and its \
             headers: `apt-get install libclang-dev` (or libclang-common-14-dev)"
        ))
    });
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR")).join("embree.rs");
    bindings
        .write_to_file(&out)
        .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", out.display())));
}

/// The oldest OpenImageIO the shim is built and tested against (Debian 12
/// ships 2.4.7; the shim uses `ColorConfig::isColorSpaceLinear`, which
/// older releases lack).
const OIIO_MIN_VERSION: (u32, u32) = (2, 4);

/// Ladder for OpenImageIO: OIIO_DIR, then pkg-config.
fn find_oiio() -> Result<Found, String> {
    let (min_major, min_minor) = OIIO_MIN_VERSION;
    // Rung 1: explicit override.
    if let Some(prefix) = env::var_os("OIIO_DIR") {
        let prefix = PathBuf::from(prefix);
        let include = prefix.join("include");
        if !include.join("OpenImageIO/imageio.h").is_file() {
            return Err(format!(
                "OIIO_DIR={} has no include/OpenImageIO/imageio.h; {DEBIAN_HINT_OIIO}",
                prefix.display()
            ));
        }
        let version_h = include.join("OpenImageIO/oiioversion.h");
        let text = std::fs::read_to_string(&version_h)
            .map_err(|e| format!("cannot read {}: {e}", version_h.display()))?;
        let define = |name: &str| -> Option<u32> {
            text.lines()
                .find_map(|l| l.trim().strip_prefix(&format!("#define {name} ")))
                .and_then(|v| v.trim().parse().ok())
        };
        match (define("OIIO_VERSION_MAJOR"), define("OIIO_VERSION_MINOR")) {
            (Some(major), Some(minor)) if (major, minor) >= OIIO_MIN_VERSION => {}
            (Some(major), Some(minor)) => {
                return Err(format!(
                    "{} says OpenImageIO {major}.{minor}; spar needs {min_major}.{min_minor} or newer. \
                     {DEBIAN_HINT_OIIO}",
                    version_h.display()
                ))
            }
            _ => return Err(format!("cannot find the version in {}", version_h.display())),
        }
        let lib_dirs: Vec<PathBuf> = ["lib", "lib64"]
            .iter()
            .map(|d| prefix.join(d))
            .filter(|d| d.is_dir())
            .collect();
        return Ok(Found {
            include_dirs: vec![include],
            lib_dirs,
            libs: vec!["OpenImageIO".into(), "OpenImageIO_Util".into()],
        });
    }
    // Rung 2: pkg-config. Its link flags go to the shim library, not to
    // spar: no cargo metadata.
    match pkg_config::Config::new()
        .atleast_version(&format!("{min_major}.{min_minor}"))
        .cargo_metadata(false)
        .probe("OpenImageIO")
    {
        Ok(lib) => Ok(Found {
            include_dirs: lib.include_paths,
            lib_dirs: lib.link_paths,
            libs: lib.libs,
        }),
        Err(e) => Err(format!(
            "OpenImageIO {min_major}.{min_minor} or newer not found through pkg-config ({e}); \
             {DEBIAN_HINT_OIIO}"
        )),
    }
}

/// Compiles and links `shim/oiio_shim.cpp` into `OUT_DIR/libspar_oiio.so`
/// against OpenImageIO, and returns its path. The compiler and its flags
/// (optimization, debug info, `-fPIC`, C++17, warnings) are the `cc`
/// crate's, as for a static library; only the link step is added here.
fn build_oiio_shim(found: &Found) -> PathBuf {
    let out_dir = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    let output = out_dir.join(SHIM_FILE);
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        .pic(true)
        .include("shim")
        .warnings(true)
        // Only the `spar_oiio_*` functions are exported (SPAR_OIIO_API).
        .flag_if_supported("-fvisibility=hidden");
    for dir in &found.include_dirs {
        build.include(dir);
    }
    let compiler = build
        .try_get_compiler()
        .unwrap_or_else(|e| fail(&format!("no C++ compiler for the OpenImageIO shim: {e}")));
    let mut command = compiler.to_command();
    command
        .arg("-shared")
        .arg(format!("-Wl,-soname,{SHIM_FILE}"))
        // Every symbol resolved now, not at dlopen time.
        .arg("-Wl,--no-undefined")
        .arg("shim/oiio_shim.cpp")
        .arg("-o")
        .arg(&output);
    for dir in &found.lib_dirs {
        command.arg(format!("-L{}", dir.display()));
        if !is_system_dir(dir) {
            command.arg(format!("-Wl,-rpath,{}", dir.display()));
        }
    }
    for lib in &found.libs {
        command.arg(format!("-l{lib}"));
    }
    let result = command.output().unwrap_or_else(|e| {
        fail(&format!(
            "cannot run the C++ compiler {} for the OpenImageIO shim: {e}",
            compiler.path().display()
        ))
    });
    let stderr = String::from_utf8_lossy(&result.stderr);
    if !result.status.success() {
        fail(&format!(
            "building {SHIM_FILE} failed ({:?}):\n{stderr}",
            command
        ));
    }
    for line in stderr.lines().filter(|l| !l.trim().is_empty()) {
        println!("cargo:warning={line}");
    }
    output
}

/// Whether the dynamic linker searches `dir` by default (no rpath needed).
fn is_system_dir(dir: &Path) -> bool {
    let dir = dir.to_string_lossy();
    ["/usr/lib", "/lib", "/usr/lib64", "/lib64"]
        .iter()
        .any(|s| dir == *s || dir.starts_with(&format!("{s}/x86_64-linux-gnu")))
}
