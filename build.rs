//! Binary-level build work only: a version string, and an rpath for the
//! Embree that spar-sys found outside the system directories.

use std::process::Command;

fn main() {
    // Version: the crate version, plus the git revision when there is one.
    let mut version = env!("CARGO_PKG_VERSION").to_string();
    let rev = Command::new("git")
        .args(["rev-parse", "--short=10", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok());
    if let Some(rev) = rev {
        let rev = rev.trim();
        if !rev.is_empty() {
            version = format!("{version} (git {rev})");
        }
    }
    println!("cargo:rustc-env=SPAR_VERSION={version}");
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/refs/heads");

    // spar-sys has `links = "embree3"`, so its `cargo:lib_dirs=` metadata
    // arrives here as DEP_EMBREE3_LIB_DIRS: Embree's directories. Found in a
    // non-system prefix (EMBREE_DIR) they get an rpath so the binary runs as
    // built. OpenImageIO is not linked into spar: its rpath (OIIO_DIR) is in
    // spar-sys's shim library, loaded at run time.
    if let Ok(dirs) = std::env::var("DEP_EMBREE3_LIB_DIRS") {
        for dir in dirs.split(':').filter(|d| !d.is_empty()) {
            let system = ["/usr/lib", "/lib", "/usr/lib64", "/lib64"]
                .iter()
                .any(|s| dir == *s || dir.starts_with(&format!("{s}/x86_64-linux-gnu")));
            if !system {
                println!("cargo:rustc-link-arg-bins=-Wl,-rpath,{dir}");
            }
        }
    }
}
