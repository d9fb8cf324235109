//! ABI: the sizes, alignments and field offsets of the Embree structs spar
//! passes by pointer, as bindgen declared them, against what a C compiler
//! reads from `embree3/rtcore.h` itself. A mismatch here would be a silent
//! memory corruption in `rtcIntersect1`.
#![cfg(feature = "native")]

use spar_sys::embree::{RTCBounds, RTCHit, RTCIntersectContext, RTCRay, RTCRayHit};
use std::mem::{align_of, offset_of, size_of};
use std::process::Command;

fn c_layout() -> Vec<(String, usize)> {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("abi.c");
    std::fs::write(
        &src,
        r#"
#include <stdio.h>
#include <stddef.h>
#include <embree3/rtcore.h>
#define S(T) printf(#T " size %zu\n" #T " align %zu\n", sizeof(struct T), _Alignof(struct T));
#define O(T, f) printf(#T "." #f " %zu\n", offsetof(struct T, f));
int main(void) {
  S(RTCRayHit) S(RTCRay) S(RTCHit) S(RTCIntersectContext) S(RTCBounds)
  O(RTCRayHit, ray) O(RTCRayHit, hit)
  O(RTCRay, org_x) O(RTCRay, tnear) O(RTCRay, dir_x) O(RTCRay, time) O(RTCRay, tfar)
  O(RTCRay, mask) O(RTCRay, id) O(RTCRay, flags)
  O(RTCHit, Ng_x) O(RTCHit, u) O(RTCHit, v) O(RTCHit, primID) O(RTCHit, geomID) O(RTCHit, instID)
  O(RTCIntersectContext, flags) O(RTCIntersectContext, filter) O(RTCIntersectContext, instID)
  return 0;
}
"#,
    )
    .unwrap();
    let exe = dir.path().join("abi");
    let mut cmd = Command::new(std::env::var("CC").unwrap_or_else(|_| "cc".into()));
    if let Some(prefix) = std::env::var_os("EMBREE_DIR") {
        cmd.arg(format!(
            "-I{}/include",
            std::path::Path::new(&prefix).display()
        ));
    }
    let status = cmd
        .arg("-std=c11")
        .arg(&src)
        .arg("-o")
        .arg(&exe)
        .status()
        .expect("a C compiler (cc) is needed for the ABI test");
    assert!(status.success(), "compiling the ABI probe failed");
    let out = Command::new(&exe).output().unwrap();
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            let (k, v) = l.rsplit_once(' ').unwrap();
            (k.to_string(), v.parse().unwrap())
        })
        .collect()
}

#[test]
fn bound_structs_match_the_c_header() {
    let c = c_layout();
    let rust: Vec<(&str, usize)> = vec![
        ("RTCRayHit size", size_of::<RTCRayHit>()),
        ("RTCRayHit align", align_of::<RTCRayHit>()),
        ("RTCRay size", size_of::<RTCRay>()),
        ("RTCRay align", align_of::<RTCRay>()),
        ("RTCHit size", size_of::<RTCHit>()),
        ("RTCHit align", align_of::<RTCHit>()),
        ("RTCIntersectContext size", size_of::<RTCIntersectContext>()),
        (
            "RTCIntersectContext align",
            align_of::<RTCIntersectContext>(),
        ),
        ("RTCBounds size", size_of::<RTCBounds>()),
        ("RTCBounds align", align_of::<RTCBounds>()),
        ("RTCRayHit.ray", offset_of!(RTCRayHit, ray)),
        ("RTCRayHit.hit", offset_of!(RTCRayHit, hit)),
        ("RTCRay.org_x", offset_of!(RTCRay, org_x)),
        ("RTCRay.tnear", offset_of!(RTCRay, tnear)),
        ("RTCRay.dir_x", offset_of!(RTCRay, dir_x)),
        ("RTCRay.time", offset_of!(RTCRay, time)),
        ("RTCRay.tfar", offset_of!(RTCRay, tfar)),
        ("RTCRay.mask", offset_of!(RTCRay, mask)),
        ("RTCRay.id", offset_of!(RTCRay, id)),
        ("RTCRay.flags", offset_of!(RTCRay, flags)),
        ("RTCHit.Ng_x", offset_of!(RTCHit, Ng_x)),
        ("RTCHit.u", offset_of!(RTCHit, u)),
        ("RTCHit.v", offset_of!(RTCHit, v)),
        ("RTCHit.primID", offset_of!(RTCHit, primID)),
        ("RTCHit.geomID", offset_of!(RTCHit, geomID)),
        ("RTCHit.instID", offset_of!(RTCHit, instID)),
        (
            "RTCIntersectContext.flags",
            offset_of!(RTCIntersectContext, flags),
        ),
        (
            "RTCIntersectContext.filter",
            offset_of!(RTCIntersectContext, filter),
        ),
        (
            "RTCIntersectContext.instID",
            offset_of!(RTCIntersectContext, instID),
        ),
    ];
    assert_eq!(c.len(), rust.len(), "probe printed {c:?}");
    for ((ck, cv), (rk, rv)) in c.iter().zip(&rust) {
        assert_eq!(ck, rk);
        assert_eq!(cv, rv, "{rk}: C says {cv}, Rust says {rv}");
    }
    // The documented facts native-notes relies on.
    assert_eq!(size_of::<RTCRayHit>(), 80);
    assert_eq!(align_of::<RTCRayHit>(), 16);
}

#[test]
fn init_intersect_context_matches_the_inline_header_function() {
    let ctx = spar_sys::embree::rtc_init_intersect_context();
    assert!(ctx.filter.is_none());
    assert!(ctx.instID.iter().all(|&i| i == u32::MAX));
    assert_eq!(
        ctx.flags,
        spar_sys::embree::RTCIntersectContextFlags::RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
    );
}
