//! The convex-exit plane loop (`accel::convex`) in 256-bit AVX registers,
//! when the CPU has AVX: four planes per instruction instead of the
//! baseline build's two. The same operations in the same order and no
//! fused multiply-add, so every lane is the portable loop's bit for bit
//! (tested in `accel::convex`), and renders on machines with and without
//! AVX still merge.

use std::sync::OnceLock;

/// Four planes `n · x <= offset`, as rows: `[nx, ny, nz, offset]`.
pub type PlaneBlock = [[f64; 4]; 4];

/// Per lane, over every block: the nearest crossing as a fraction
/// `num / den` (start `1 / 0`), the plane it is on (block · 4 + lane; −1
/// for none) and the smallest distance inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes {
    pub num: [f64; 4],
    pub den: [f64; 4],
    pub plane: [f64; 4],
    pub least_inside: [f64; 4],
}

/// Whether this CPU has AVX (asked once).
fn has_avx() -> bool {
    static HAS: OnceLock<bool> = OnceLock::new();
    *HAS.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            std::arch::is_x86_feature_detected!("avx")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    })
}

/// The lanes of the plane loop for a ray from `o` along `d`, computed with
/// AVX; `None` when the CPU lacks it (the caller runs its portable loop).
#[inline]
pub fn nearest_crossing(blocks: &[PlaneBlock], o: [f64; 3], d: [f64; 3]) -> Option<Lanes> {
    #[cfg(target_arch = "x86_64")]
    if has_avx() {
        // SAFETY: the CPU supports AVX (checked above), the only
        // requirement of calling a function compiled for it.
        return Some(unsafe { nearest_avx(blocks, o, d) });
    }
    let _ = (blocks, o, d);
    None
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn nearest_avx(blocks: &[PlaneBlock], o: [f64; 3], d: [f64; 3]) -> Lanes {
    use std::arch::x86_64::*;
    let (ox, oy, oz) = (
        _mm256_set1_pd(o[0]),
        _mm256_set1_pd(o[1]),
        _mm256_set1_pd(o[2]),
    );
    let (dx, dy, dz) = (
        _mm256_set1_pd(d[0]),
        _mm256_set1_pd(d[1]),
        _mm256_set1_pd(d[2]),
    );
    let mut num = _mm256_set1_pd(1.0);
    let mut den = _mm256_setzero_pd();
    let mut least = _mm256_set1_pd(f64::INFINITY);
    let mut which = _mm256_set1_pd(-1.0);
    let mut plane = _mm256_setr_pd(0.0, 1.0, 2.0, 3.0);
    let four = _mm256_set1_pd(4.0);
    for b in blocks {
        // SAFETY: each row is four contiguous f64 (unaligned loads).
        let (nx, ny, nz, offset) = unsafe {
            (
                _mm256_loadu_pd(b[0].as_ptr()),
                _mm256_loadu_pd(b[1].as_ptr()),
                _mm256_loadu_pd(b[2].as_ptr()),
                _mm256_loadu_pd(b[3].as_ptr()),
            )
        };
        // inside = offset − ((nx·ox + ny·oy) + nz·oz), speed likewise.
        let at = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(nx, ox), _mm256_mul_pd(ny, oy)),
            _mm256_mul_pd(nz, oz),
        );
        let inside = _mm256_sub_pd(offset, at);
        let speed = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(nx, dx), _mm256_mul_pd(ny, dy)),
            _mm256_mul_pd(nz, dz),
        );
        // nearer = inside · den < num · speed (false on NaN, as `<`).
        let nearer =
            _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_mul_pd(inside, den), _mm256_mul_pd(num, speed));
        num = _mm256_blendv_pd(num, inside, nearer);
        den = _mm256_blendv_pd(den, speed, nearer);
        which = _mm256_blendv_pd(which, plane, nearer);
        plane = _mm256_add_pd(plane, four);
        // min(a, b) = a < b ? a : b, as the portable loop's select.
        least = _mm256_min_pd(inside, least);
    }
    let mut out = Lanes {
        num: [0.0; 4],
        den: [0.0; 4],
        plane: [0.0; 4],
        least_inside: [0.0; 4],
    };
    // SAFETY: each destination is four f64 (unaligned stores).
    unsafe {
        _mm256_storeu_pd(out.num.as_mut_ptr(), num);
        _mm256_storeu_pd(out.den.as_mut_ptr(), den);
        _mm256_storeu_pd(out.plane.as_mut_ptr(), which);
        _mm256_storeu_pd(out.least_inside.as_mut_ptr(), least);
    }
    out
}
