//! Scene analysis: which optical effects a scene calls for, found from every object's and
//! light's capability flags and spectra (built-in and plugin objects alike, through the same
//! `Material`/`Light` interfaces), each with the objects that call for it, and what the
//! renderer does about each and what it skips (`spectrace explain SCENE`).
//!
//! The integrator's [`RenderPlan`](crate::integrator::plan::RenderPlan) turns the findings and
//! the command line into what the render does. Data flows one way: the
//! [`crate::scene::Scene`] is only read, and this floor sits below the integrator.

pub mod analysis;
pub mod effect;

pub use analysis::{analyze, Caller, EffectSet, Finding};
pub use effect::Effect;
