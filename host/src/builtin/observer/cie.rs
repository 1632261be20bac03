//! The CIE standard observers, `observer: "cie1931-2"` (default), `cie1964-10`, `cie2015-2`,
//! `cie2015-10`: the colour-matching functions x̄, ȳ, z̄ at 1 nm. Four types of one kind in
//! one file because they differ only in their table. No parameters.
//!
//! | parameter | unit | default | meaning |
//! |-----------|------|---------|---------|
//! | (none)    |      |         |         |

use crate::builtin::{from_value, state_fns, Build, BuiltinType, Embed};
use crate::color::{CieObserverKind, Observer};
use crate::scene_file::FactoryError;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Parameters of a CIE observer: none.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CieParams {}

impl Embed for CieParams {}

fn build(kind: CieObserverKind, v: &ron::Value) -> Result<Arc<dyn Observer>, FactoryError> {
    let _: CieParams = from_value(v)?;
    Ok(Arc::new(kind.get().clone()))
}

macro_rules! cie {
    ($id:ident, $kind:ident, $name:literal, $what:literal) => {
        #[doc = $what]
        pub const $id: BuiltinType = BuiltinType {
            name: $name,
            aliases: &[],
            version: 1,
            description: $what,
            params: &[],
            build: Build::Observer(|v, _| build(CieObserverKind::$kind, v)),
            state: Some(state_fns::<CieParams>()),
        };
    };
}

cie!(
    CIE1931_2,
    Cie1931_2,
    "cie1931-2",
    "CIE 1931 2° standard observer (default)"
);
cie!(
    CIE1964_10,
    Cie1964_10,
    "cie1964-10",
    "CIE 1964 10° standard observer"
);
cie!(
    CIE2015_2,
    Cie2015_2,
    "cie2015-2",
    "CIE 2015 2° cone-fundamental-based observer"
);
cie!(
    CIE2015_10,
    Cie2015_10,
    "cie2015-10",
    "CIE 2015 10° cone-fundamental-based observer"
);
