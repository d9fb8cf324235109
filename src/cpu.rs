//! The instruction set this build was compiled for, checked against the CPU
//! it runs on.
//!
//! On x86-64, spar is built for x86-64-v3 by default (`.cargo/config.toml`:
//! AVX2, FMA, BMI1/2, F16C, LZCNT, MOVBE: every x86-64 CPU since Intel
//! Haswell, 2013, and AMD Excavator, 2015). The renderer's f64 optics then
//! take 8–13 % less CPU (docs/speed-error/HISTORY.md, "Built for x86-64-v3")
//! and write the same images bit for bit, since Rust never
//! fuses a multiply and an add by itself. On an older CPU such a build
//! would die on its first AVX instruction with "Illegal instruction"; the
//! binary checks first ([`exit_if_unsupported`]) and says how to rebuild.
//! A build for another instruction set checks only what it was built for.

use std::io::Write;

/// Calls macro `$then` with the x86-64 features a build can be compiled
/// with, each as `index "name"` (the names of `RUSTFLAGS="-C
/// target-feature=…"`; the index is its bit in [`missing_mask`]): the one
/// list that the names, the check and the test share.
#[cfg(target_arch = "x86_64")]
macro_rules! with_features {
    ($then:ident) => {
        $then!(
            0 "sse3", 1 "ssse3", 2 "sse4.1", 3 "sse4.2", 4 "popcnt", 5 "cmpxchg16b", 6 "avx",
            7 "avx2", 8 "bmi1", 9 "bmi2", 10 "fma", 11 "f16c", 12 "lzcnt", 13 "movbe", 14 "xsave",
            15 "avx512f", 16 "avx512bw", 17 "avx512cd", 18 "avx512dq", 19 "avx512vl", 20 "adx"
        )
    };
}

#[cfg(target_arch = "x86_64")]
macro_rules! names {
    ($($i:literal $name:tt),*) => {
        [$($name),*]
    };
}

/// The features' names, in the order of [`missing_mask`]'s bits.
#[cfg(target_arch = "x86_64")]
const NAMES: [&str; 21] = with_features!(names);

/// The CPU's feature bits as CPUID reports them: leaf 1 ECX, leaf 7
/// (subleaf 0) EBX, leaf 0x8000_0001 ECX (Intel SDM vol. 2A, CPUID). Read
/// directly: `is_x86_feature_detected!` answers "yes" without asking for
/// every feature the build was compiled with.
#[cfg(target_arch = "x86_64")]
fn cpuid_bits() -> (u32, u32, u32) {
    use std::arch::x86_64::{__cpuid, __cpuid_count};
    let leaf1 = __cpuid(1).ecx;
    let leaf7 = if __cpuid(0).eax >= 7 {
        __cpuid_count(7, 0).ebx
    } else {
        0
    };
    let ext = if __cpuid(0x8000_0000).eax >= 0x8000_0001 {
        __cpuid(0x8000_0001).ecx
    } else {
        0
    };
    (leaf1, leaf7, ext)
}

/// Whether the CPU has feature `name` (one of [`NAMES`]); the AVX family
/// also needs the operating system to save AVX state (OSXSAVE).
#[cfg(target_arch = "x86_64")]
fn has(name: &str, (leaf1, leaf7, ext): (u32, u32, u32)) -> bool {
    let bit = |word: u32, i: u32| word >> i & 1 == 1;
    let os_avx = bit(leaf1, 27);
    match name {
        "sse3" => bit(leaf1, 0),
        "ssse3" => bit(leaf1, 9),
        "sse4.1" => bit(leaf1, 19),
        "sse4.2" => bit(leaf1, 20),
        "popcnt" => bit(leaf1, 23),
        "cmpxchg16b" => bit(leaf1, 13),
        "movbe" => bit(leaf1, 22),
        "xsave" => bit(leaf1, 26),
        "avx" => bit(leaf1, 28) && os_avx,
        "fma" => bit(leaf1, 12) && os_avx,
        "f16c" => bit(leaf1, 29) && os_avx,
        "avx2" => bit(leaf7, 5) && os_avx,
        "bmi1" => bit(leaf7, 3),
        "bmi2" => bit(leaf7, 8),
        "adx" => bit(leaf7, 19),
        "avx512f" => bit(leaf7, 16) && os_avx,
        "avx512dq" => bit(leaf7, 17) && os_avx,
        "avx512cd" => bit(leaf7, 28) && os_avx,
        "avx512bw" => bit(leaf7, 30) && os_avx,
        "avx512vl" => bit(leaf7, 31) && os_avx,
        "lzcnt" => bit(ext, 5),
        _ => false,
    }
}

/// Bit i set: the build was compiled with feature `NAMES[i]` and this CPU
/// lacks it. Plain scalar code (no tables built on the stack), so that the
/// check runs on a CPU without the features it checks.
#[cfg(target_arch = "x86_64")]
#[inline(never)]
fn missing_mask() -> u32 {
    let bits = cpuid_bits();
    let mut mask = 0u32;
    macro_rules! check {
        ($($i:literal $name:tt),*) => {$(
            if cfg!(target_feature = $name) && !has($name, bits) {
                mask |= 1 << $i;
            }
        )*};
    }
    with_features!(check);
    mask
}

#[cfg(not(target_arch = "x86_64"))]
const NAMES: [&str; 0] = [];

#[cfg(not(target_arch = "x86_64"))]
fn missing_mask() -> u32 {
    0
}

/// Whether this CPU has every instruction-set feature the build assumes.
pub fn supported() -> bool {
    missing_mask() == 0
}

/// The message for a CPU that lacks features of the build, around the
/// list of what it lacks: [`unsupported_message`] and
/// [`exit_if_unsupported`] say the same words.
const LACKS: &str = "this CPU lacks instructions this spar was built for (the default build \
                     is for x86-64-v3: AVX2, FMA, x86-64 CPUs since 2013-2015); missing:";
const REBUILD: &str = "Build spar for this CPU with: RUSTFLAGS=\"-C target-cpu=x86-64\" cargo \
                       build --release\n(about a tenth slower; the same images bit for bit).";

/// The message for a CPU that lacks features of the build: what is
/// missing and how to build spar for that CPU.
pub fn unsupported_message() -> String {
    let mask = missing_mask();
    let mut message = LACKS.to_string();
    for (i, name) in NAMES.iter().enumerate() {
        if mask >> i & 1 == 1 {
            message.push(' ');
            message.push_str(name);
        }
    }
    format!("{message}.\n{REBUILD}")
}

/// Exits with status 2 and a message on standard error when this CPU
/// lacks features the build was compiled with; returns otherwise. Called
/// first thing by `main`, before any code that may use those
/// instructions. The message is written without formatting machinery or
/// allocation: on such a CPU anything more could itself fault.
#[inline(never)]
pub fn exit_if_unsupported() {
    let mask = missing_mask();
    if mask == 0 {
        return;
    }
    let mut err = std::io::stderr().lock();
    let _ = err.write_all(b"spar: error: ");
    let _ = err.write_all(LACKS.as_bytes());
    for (i, name) in NAMES.iter().enumerate() {
        if mask >> i & 1 == 1 {
            let _ = err.write_all(b" ");
            let _ = err.write_all(name.as_bytes());
        }
    }
    let _ = err.write_all(b".\n");
    let _ = err.write_all(REBUILD.as_bytes());
    let _ = err.write_all(b"\n");
    let _ = err.flush();
    std::process::exit(2);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_machine_running_the_tests_has_what_the_build_assumes() {
        // The tests run on the machine they were built for: if this failed,
        // every other test would have died on an illegal instruction first.
        assert!(supported(), "{}", unsupported_message());
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn cpuid_bits_agree_with_std_for_features_the_build_does_not_assume() {
        // For a feature not compiled in, `is_x86_feature_detected!` really
        // asks the CPU (an independent reading of the same bits); for one
        // compiled in, the test machine must have it.
        let bits = cpuid_bits();
        macro_rules! agree {
            ($($i:literal $name:tt),*) => {$(
                if !cfg!(target_feature = $name) {
                    assert_eq!(has($name, bits), std::arch::is_x86_feature_detected!($name), $name);
                } else {
                    assert!(has($name, bits), $name);
                }
            )*};
        }
        with_features!(agree);
    }
}
