//! Any light measured as an instrument measures a lamp, through the same [`crate::light::Light`]
//! interface the integrators use: its intensity distribution as a goniophotometer records it
//! ([`goniometer`], for baking into a luminaire or exporting as IES/EULUMDAT) and its rays as a
//! TM-25 ray file ([`tm25_export`]). The file formats themselves are in [`crate::photometry`].

pub mod goniometer;
pub mod tm25_export;
