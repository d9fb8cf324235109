//! A build for x86-64-v3 (the default, `.cargo/config.toml`) run on an
//! older CPU: spar must stop with exit status 2 and say what is missing
//! and how to rebuild, not die on an illegal instruction. The older CPUs
//! are QEMU's user-mode emulator (`qemu-x86_64 -cpu MODEL`, Debian's
//! qemu-user), which reports each model's CPUID and traps instructions
//! that model lacks: without the check, this binary dies with SIGILL
//! there (measured: exit 132 on Nehalem and on Sandy Bridge).
//!
//! CI installs qemu-user and sets SPAR_REQUIRE_QEMU=1, so there the test
//! cannot pass by skipping; elsewhere it says that it skipped.

use crate::support::run::code_out_err;
use std::process::Command;

fn qemu_available() -> bool {
    Command::new("qemu-x86_64")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn an_older_cpu_gets_a_clear_error_instead_of_an_illegal_instruction() {
    if !cfg!(all(target_arch = "x86_64", target_feature = "avx2")) {
        eprintln!("skipped: this build does not assume AVX2");
        return;
    }
    if !qemu_available() {
        assert!(
            std::env::var_os("SPAR_REQUIRE_QEMU").is_none(),
            "SPAR_REQUIRE_QEMU is set but qemu-x86_64 is missing (apt-get install qemu-user)"
        );
        eprintln!("skipped: qemu-x86_64 not installed (apt-get install qemu-user)");
        return;
    }
    // Nehalem (2008): no AVX at all; Sandy Bridge (2011): AVX but not
    // AVX2, FMA or BMI; Haswell (2013): all of x86-64-v3.
    for (model, lacks) in [
        ("Nehalem", &["avx", "avx2", "fma", "bmi2"][..]),
        (
            "SandyBridge",
            &["avx2", "fma", "bmi1", "bmi2", "f16c", "lzcnt", "movbe"][..],
        ),
    ] {
        let out = Command::new("qemu-x86_64")
            .args(["-cpu", model, env!("CARGO_BIN_EXE_spar"), "--version"])
            .output()
            .unwrap();
        let (code, stdout, err) = code_out_err(&out);
        assert_eq!(code, 2, "{model}: {err}");
        assert!(stdout.is_empty(), "{model}: {stdout}");
        let missing = err
            .lines()
            .find_map(|l| l.split_once("missing: "))
            .map(|(_, m)| m.trim_end_matches('.').split(' ').collect::<Vec<_>>())
            .unwrap_or_else(|| panic!("{model}: no list of what is missing: {err}"));
        for feature in lacks {
            assert!(missing.contains(feature), "{model} lacks {feature}: {err}");
        }
        assert!(!missing.contains(&"sse4.2"), "{model} has SSE4.2: {err}");
        assert!(err.contains("RUSTFLAGS=\"-C target-cpu=x86-64\""), "{err}");
    }
    let out = Command::new("qemu-x86_64")
        .args(["-cpu", "Haswell", env!("CARGO_BIN_EXE_spar"), "--version"])
        .output()
        .unwrap();
    let (code, stdout, err) = code_out_err(&out);
    assert_eq!(code, 0, "Haswell: {err}");
    assert!(stdout.starts_with("spar "), "{stdout}");
}
