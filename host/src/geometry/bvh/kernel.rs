//! The box-test kernels the traversal can run, and which one this CPU runs fastest.

/// Which box-test kernel the traversal runs (see [`super::traverse`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TraversalKernel {
    /// Two four-wide halves per node (`glam::Vec4`); runs everywhere.
    #[default]
    Portable,
    /// One 256-bit AVX operation per node; only where the CPU has AVX2 (and `popcnt` and FMA,
    /// which every AVX2 CPU has: `popcnt` orders the hit children, FMA decodes quantised
    /// planes in one exact step).
    Avx2,
}

impl TraversalKernel {
    /// The fastest kernel this CPU runs.
    pub fn best_available() -> TraversalKernel {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("popcnt")
            && std::arch::is_x86_feature_detected!("fma")
        {
            return TraversalKernel::Avx2;
        }
        TraversalKernel::Portable
    }
}
