//! Refusing sizes that cannot be allocated, before allocating them: an
//! allocation failure aborts the process, which no error at the Python boundary
//! can catch.

/// Whether `bytes` can be allocated now: one fallible reservation of that size,
/// released at once. The probe goes through `black_box`, because an allocation
/// nobody reads may be elided by the optimiser: release builds did, so the probe
/// always "succeeded" and the real arrays then exhausted memory (the cyclogram's
/// `bad_input_is_an_error_not_a_panic` test was killed by the OOM killer).
pub(crate) fn can_allocate(bytes: usize) -> bool {
    let mut probe: Vec<u8> = Vec::new();
    let ok = probe.try_reserve_exact(bytes).is_ok();
    std::hint::black_box(&mut probe);
    ok
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_sizes_fit_and_impossible_ones_do_not() {
        assert!(can_allocate(0));
        assert!(can_allocate(1 << 20));
        // More than any machine's address space: refused in debug and release.
        assert!(!can_allocate(usize::MAX / 2));
        assert!(!can_allocate(1 << 62));
    }
}
