//! Limits every sensor shares.

/// Most samples per point of a sensor (the sums stay exact enough in f64 far beyond this).
pub const MAX_SAMPLES: u32 = 1 << 24;
