//! How much memory a job may take: the machine's available memory (Linux
//! `/proc/meminfo`), checked against an estimate before anything large is
//! allocated, so that an image or wavelength count that cannot fit is a
//! named error instead of an abort or a machine swapping to a halt.

/// Bytes in a GiB.
pub const GIB: f64 = (1u64 << 30) as f64;

/// Where the available memory was learned, and how much there is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Available {
    pub bytes: f64,
    /// `true` when read from the system, `false` for the fallback bound.
    pub measured: bool,
}

/// The fallback when the system does not say: the 47-bit user address
/// space of x86-64 and AArch64 Linux (128 TiB), which nothing larger can
/// fit in.
pub const ADDRESS_SPACE: f64 = (1u64 << 47) as f64;

/// `MemAvailable` of `/proc/meminfo` (the kernel's estimate of what can be
/// allocated without swapping), else `MemFree`, else [`ADDRESS_SPACE`].
pub fn available() -> Available {
    std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| parse_meminfo(&text))
        .map_or(
            Available {
                bytes: ADDRESS_SPACE,
                measured: false,
            },
            |bytes| Available {
                bytes,
                measured: true,
            },
        )
}

/// `MemAvailable` (or `MemFree`) of `/proc/meminfo` text, in bytes.
pub fn parse_meminfo(text: &str) -> Option<f64> {
    let field = |name: &str| {
        text.lines().find_map(|l| {
            let rest = l.strip_prefix(name)?.strip_prefix(':')?.trim();
            let kib: f64 = rest
                .strip_suffix("kB")
                .unwrap_or(rest)
                .trim()
                .parse()
                .ok()?;
            Some(kib * 1024.0)
        })
    };
    field("MemAvailable").or_else(|| field("MemFree"))
}

impl Available {
    /// "this machine has N GiB available" (or the fallback's wording).
    pub fn describe(&self) -> String {
        if self.measured {
            format!(
                "this machine has {:.1} GiB available (MemAvailable, /proc/meminfo)",
                self.bytes / GIB
            )
        } else {
            format!(
                "more than the {:.0} GiB a process can address",
                self.bytes / GIB
            )
        }
    }
}

/// Checks that `need` bytes fit in the available memory; the error names
/// what needs them, the estimate in GiB and what is available.
pub fn check(need: f64, what: &str) -> Result<(), String> {
    let avail = available();
    if need > avail.bytes {
        return Err(format!(
            "{what} would need about {:.1} GiB of memory; {}",
            need / GIB,
            avail.describe()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_gives_available_then_free() {
        let text =
            "MemTotal:       16000000 kB\nMemFree:         1000 kB\nMemAvailable:    2048 kB\n";
        assert_eq!(parse_meminfo(text), Some(2048.0 * 1024.0));
        assert_eq!(parse_meminfo("MemFree: 4 kB\n"), Some(4096.0));
        assert_eq!(parse_meminfo("nothing"), None);
    }

    #[test]
    fn a_petabyte_does_not_fit() {
        let e = check(1e15, "--resolution 1x1").unwrap_err();
        assert!(e.contains("--resolution 1x1") && e.contains("GiB"), "{e}");
        assert!(check(1024.0, "a kilobyte").is_ok());
    }
}
