//! A memory hint for the loops of the bvol crates that read bounds in an
//! order memory does not follow (a tree's leaves, the bodies of candidate
//! pairs): asking for a value some iterations ahead overlaps its cache
//! misses with the work in between instead of waiting on each in turn.

/// Asks the processor to start loading the cache lines that hold `value`,
/// without waiting for them. A hint only: it reads nothing the program sees,
/// cannot fault, and does nothing on targets other than x86_64.
///
/// ```
/// let boxes = vec![[0.0f32; 6]; 1000];
/// let order = [917, 3, 512, 40];
/// let mut sum = 0.0;
/// for (k, &i) in order.iter().enumerate() {
///     if let Some(&next) = order.get(k + 2) {
///         bvol_volumes::prefetch(&boxes[next]);
///     }
///     sum += boxes[i][0];
/// }
/// assert_eq!(sum, 0.0);
/// ```
#[inline(always)]
pub fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let first = (value as *const T).cast::<i8>();
        let last = first.wrapping_add(size_of::<T>().saturating_sub(1));
        // A value no larger than its alignment, which divides a 64-byte
        // line, never straddles two lines: one hint does.
        let one_line = size_of::<T>() <= align_of::<T>() && align_of::<T>() <= 64;
        // SAFETY: SSE is part of every x86_64 target, and a prefetch only
        // hints: it reads nothing the program sees and cannot fault, whatever
        // the address.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(first);
            if !one_line {
                _mm_prefetch::<_MM_HINT_T0>(last);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}
