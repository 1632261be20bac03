//! How a plugin declares its types and exports them: implement [`PluginType`] (parameters,
//! version, construction) plus the kind's trait, then list the types in [`export_plugin!`].
//! Parameters double as the saved state, so a type gets blob support for free.

use crate::error::{ErrorKind, PluginError, PluginResult};
use crate::host::{Host, HostRef};
use crate::module::{ObjectKind, ObjectSource, ParamInfo, TypeInfo};
use crate::representation::BeamRepresentation;
use abi_stable::std_types::{ROption, RString, RVec};
use serde::{de::DeserializeOwned, Serialize};

/// Largest saved state a plugin will decode (bytes). Guards against allocation bombs in
/// corrupted blobs: bincode would otherwise trust a length prefix.
pub const MAX_STATE_BYTES: usize = 64 << 20;

fn bincode_config() -> impl bincode::config::Config {
    bincode::config::standard().with_limit::<MAX_STATE_BYTES>()
}

/// Documentation of one parameter.
#[derive(Clone, Debug)]
pub struct ParamDoc {
    /// Name as written in the scene.
    pub name: &'static str,
    /// Unit ("" when unitless).
    pub unit: &'static str,
    /// Default in scene syntax, `None` when required.
    pub default: Option<&'static str>,
    /// What it does.
    pub description: &'static str,
}

impl ParamDoc {
    /// A parameter the scene must give.
    pub const fn required(
        name: &'static str,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: None,
            description,
        }
    }
    /// A parameter with a default.
    pub const fn optional(
        name: &'static str,
        unit: &'static str,
        default: &'static str,
        description: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: Some(default),
            description,
        }
    }
}

/// A type a plugin provides: its name, schema version, parameters and constructor.
pub trait PluginType: Sized + Send + Sync + 'static {
    /// Name scenes use to find it (`type: "point"`).
    const TYPE_NAME: &'static str;
    /// Saved-state schema version: bump it whenever `Params` changes shape.
    const TYPE_VERSION: u32;
    /// One line on what it is.
    const DESCRIPTION: &'static str;
    /// Lights only: the representation of the type's beams (see
    /// [`representation`](crate::representation)); other kinds ignore it. Anything but native
    /// makes the host convert each beam `next_beam` answers.
    const BEAM_REPRESENTATION: BeamRepresentation = BeamRepresentation::NATIVE;
    /// Constructor parameters, written in the scene as a RON struct; also the saved state.
    type Params: Serialize + DeserializeOwned;
    /// Parameter documentation (names, units, defaults).
    fn params_doc() -> Vec<ParamDoc>;
    /// Build from parameters; validate them and name the bad one in the error.
    fn new(params: Self::Params, host: &Host<'_, '_>) -> PluginResult<Self>;
    /// The parameters this object was built from (its saved state).
    fn params(&self) -> &Self::Params;
}

/// Metadata of `T` for [`PluginInfo`](crate::module::PluginInfo).
pub fn type_info<T: PluginType>(kind: ObjectKind) -> TypeInfo {
    TypeInfo {
        kind,
        name: T::TYPE_NAME.into(),
        version: T::TYPE_VERSION,
        description: T::DESCRIPTION.into(),
        params: T::params_doc()
            .into_iter()
            .map(|p| ParamInfo {
                name: p.name.into(),
                unit: p.unit.into(),
                default: p
                    .default
                    .map(RString::from)
                    .map(ROption::RSome)
                    .unwrap_or(ROption::RNone),
                description: p.description.into(),
            })
            .collect::<RVec<_>>(),
        beams: if kind == ObjectKind::Light {
            T::BEAM_REPRESENTATION
        } else {
            BeamRepresentation::NATIVE
        },
    }
}

/// Parse RON parameter text into `P`. The text is read as a RON value first and then converted,
/// so a list may be written `(1, 2, 3)` or `[1, 2, 3]` and a struct `(a: 1)` or `{"a": 1}`: the
/// host re-serialises scene values without knowing the plugin's types. Syntax errors carry RON's
/// line:column; others name the field.
pub fn parse_params<P: DeserializeOwned>(type_name: &str, text: &str) -> PluginResult<P> {
    let value: ron::Value = ron::from_str(text)
        .map_err(|e| PluginError::invalid_parameter(format!("{type_name}: parameters: {e}")))?;
    // `()` reads as the unit value; for parameters it means "all defaults".
    let value = match value {
        ron::Value::Unit => ron::Value::Map(ron::Map::new()),
        v => v,
    };
    match value.clone().into_rust() {
        Ok(p) => Ok(p),
        // Scene files give an optional parameter bare (`roughness: 0.3` for an `Option<f64>`),
        // which serde's reading of a `ron::Value` refuses ("expected option"); read again
        // from struct syntax with RON's implicit-`Some` extension before giving up.
        Err(e) => implicit_some(&value)
            .ok_or_else(|| PluginError::invalid_parameter(format!("{type_name}: parameters: {e}"))),
    }
}

/// `value` (a map of parameter names) read as a struct with RON's `implicit_some` extension.
fn implicit_some<P: DeserializeOwned>(value: &ron::Value) -> Option<P> {
    let ron::Value::Map(map) = value else {
        return None;
    };
    let mut text = String::from("(");
    for (key, v) in map.iter() {
        let ron::Value::String(key) = key else {
            return None;
        };
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return None;
        }
        text.push_str(key);
        text.push_str(": ");
        text.push_str(&ron::to_string(v).ok()?);
        text.push_str(", ");
    }
    text.push(')');
    ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .from_str(&text)
        .ok()
}

/// Encode parameters as saved state (bincode, standard config).
pub fn encode_state<P: Serialize>(params: &P) -> PluginResult<Vec<u8>> {
    bincode::serde::encode_to_vec(params, bincode_config())
        .map_err(|e| PluginError::new(ErrorKind::Other, format!("cannot encode state: {e}")))
}

/// Decode saved state, refusing trailing bytes and oversized lengths.
pub fn decode_state<P: DeserializeOwned>(type_name: &str, bytes: &[u8]) -> PluginResult<P> {
    let (p, used) = bincode::serde::decode_from_slice(bytes, bincode_config()).map_err(|e| {
        PluginError::new(
            ErrorKind::BadState,
            format!("{type_name}: cannot decode state: {e}"),
        )
    })?;
    if used != bytes.len() {
        return Err(PluginError::new(
            ErrorKind::BadState,
            format!(
                "{type_name}: state has {} trailing bytes after {used} bytes of payload",
                bytes.len() - used
            ),
        ));
    }
    Ok(p)
}

/// Build `T` from parameters or saved state.
pub fn construct<T: PluginType>(source: ObjectSource<'_>, host: &HostRef<'_>) -> PluginResult<T> {
    let host = Host::new(host);
    let params = match source {
        ObjectSource::Params(text) => parse_params::<T::Params>(T::TYPE_NAME, text.as_str())?,
        ObjectSource::State {
            type_version,
            bytes,
        } => {
            if type_version != T::TYPE_VERSION {
                return Err(PluginError::new(
                    ErrorKind::BadState,
                    format!(
                        "{}: state was written by type version {type_version}, this plugin reads version {}",
                        T::TYPE_NAME,
                        T::TYPE_VERSION
                    ),
                ));
            }
            decode_state::<T::Params>(T::TYPE_NAME, bytes.as_slice())?
        }
    };
    T::new(params, &host)
}

/// Saved state of `T` decoded and written back as RON parameters.
pub fn describe<T: PluginType>(type_version: u32, bytes: &[u8]) -> PluginResult<String> {
    if type_version != T::TYPE_VERSION {
        return Err(PluginError::new(
            ErrorKind::BadState,
            format!(
                "{}: state was written by type version {type_version}, this plugin reads version {}",
                T::TYPE_NAME,
                T::TYPE_VERSION
            ),
        ));
    }
    let params: T::Params = decode_state(T::TYPE_NAME, bytes)?;
    ron::ser::to_string_pretty(&params, ron::ser::PrettyConfig::default())
        .map_err(|e| PluginError::new(ErrorKind::Other, format!("{}: {e}", T::TYPE_NAME)))
}

/// The saved state of `T` (its parameters, bincode-encoded).
pub fn save<T: PluginType>(t: &T) -> PluginResult<Vec<u8>> {
    encode_state(t.params())
}

/// The error for a type name the plugin does not provide.
pub fn unknown_type(kind: ObjectKind, name: &str, known: &[&str]) -> PluginError {
    PluginError::new(
        ErrorKind::UnknownType,
        format!(
            "no {kind} type `{name}` in this plugin (it provides: {})",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        ),
    )
}

/// Export a plugin: its name and version and the types it provides, by kind.
///
/// Invoke it once, at the root of a `cdylib` crate (it aliases this crate as `abi_stable` in the
/// crate root so that abi_stable's export machinery resolves without a direct dependency). It
/// defines `pub fn root_module()` for in-process use (tests, static linking) and exports the same
/// module from the library.
///
/// ```ignore
/// spectrace_plugin_api::export_plugin! {
///     name: "my-lights",
///     version: env!("CARGO_PKG_VERSION"),
///     lights: [MyLight],
///     spds: [],
///     observers: [],
///     materials: [],
/// }
/// ```
#[macro_export]
macro_rules! export_plugin {
    (
        name: $name:expr,
        version: $version:expr,
        lights: [$($light:ty),* $(,)?],
        spds: [$($spd:ty),* $(,)?],
        observers: [$($observer:ty),* $(,)?],
        materials: [$($material:ty),* $(,)?] $(,)?
    ) => {
        extern crate spectrace_plugin_api as abi_stable;

        /// This plugin's root module, built in-process: the same path the host takes after
        /// loading the library, without the library.
        pub fn root_module() -> $crate::module::PluginModuleRef {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::export::{construct, describe, save, type_info, unknown_type, PluginType};
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource, PluginInfo, PluginModule};
            use $crate::error::PluginError;

            extern "C" fn info() -> RResult<PluginInfo, PluginError> {
                guarded("info", || Ok(PluginInfo {
                    name: ($name).into(),
                    version: ($version).into(),
                    api_version: $crate::module::API_VERSION.into(),
                    types: ::std::vec![
                        $(type_info::<$light>(ObjectKind::Light),)*
                        $(type_info::<$spd>(ObjectKind::Spd),)*
                        $(type_info::<$observer>(ObjectKind::Observer),)*
                        $(type_info::<$material>(ObjectKind::Material),)*
                    ]
                    .into(),
                }))
            }
            extern "C" fn describe_state(
                kind: ObjectKind,
                type_name: RStr<'_>,
                type_version: u32,
                bytes: $crate::__private::RSlice<'_, u8>,
            ) -> RResult<$crate::__private::RString, PluginError> {
                guarded("describe_state", || {
                    let name = type_name.as_str();
                    let bytes = bytes.as_slice();
                    let known: &[&str] = match kind {
                        ObjectKind::Light => &[$(<$light as PluginType>::TYPE_NAME),*],
                        ObjectKind::Spd => &[$(<$spd as PluginType>::TYPE_NAME),*],
                        ObjectKind::Observer => &[$(<$observer as PluginType>::TYPE_NAME),*],
                        ObjectKind::Material => &[$(<$material as PluginType>::TYPE_NAME),*],
                    };
                    let describers: &[fn(u32, &[u8]) -> Result<::std::string::String, PluginError>] = match kind {
                        ObjectKind::Light => &[$(describe::<$light>),*],
                        ObjectKind::Spd => &[$(describe::<$spd>),*],
                        ObjectKind::Observer => &[$(describe::<$observer>),*],
                        ObjectKind::Material => &[$(describe::<$material>),*],
                    };
                    if let Some(i) = known.iter().position(|k| *k == name) {
                        return describers[i](type_version, bytes).map(Into::into);
                    }
                    Err(unknown_type(kind, name, known))
                })
            }
            $crate::__plugin_create_fn!(create_light, Light, light, LightObject, GuardedLight, [$($light),*]);
            $crate::__plugin_create_fn!(create_spd, Spd, spd, SpdObject, GuardedSpd, [$($spd),*]);
            $crate::__plugin_create_fn!(
                create_observer, Observer, observer, ObserverObject, GuardedObserver, [$($observer),*]
            );
            $crate::__plugin_create_fn!(
                create_material, Material, material, MaterialObject, GuardedMaterial, [$($material),*]
            );
            extern "C" fn take_error() -> $crate::__private::ROption<PluginError> {
                $crate::guard::take_kept_error().into()
            }
            PluginModule {
                info,
                create_light,
                create_spd,
                create_observer,
                create_material,
                describe_state,
                take_error,
            }
            .leak_into_prefix()
        }

        /// The exported root module (what the host finds in the library).
        #[$crate::__private::export_root_module]
        pub fn spectrace_plugin_root_module() -> $crate::module::PluginModuleRef {
            // Only a host loading the library reaches this symbol (see the API's `guard`).
            $crate::guard::set_library_mode();
            root_module()
        }
    };
}

/// One `create_*` entry of [`export_plugin!`]: build the named type of one kind from parameters
/// or saved state, wrapped in that kind's guard. The four kinds differ only in these names, so
/// one definition keeps them identical. Not public API.
#[doc(hidden)]
#[macro_export]
macro_rules! __plugin_create_fn {
    ($fn_name:ident, $kind:ident, $module:ident, $boxed:ident, $guard:ident, [$($t:ty),*]) => {
        extern "C" fn $fn_name(
            type_name: RStr<'_>,
            source: ObjectSource<'_>,
            host: HostRef<'_>,
        ) -> RResult<$crate::$module::$boxed, PluginError> {
            guarded(stringify!($fn_name), || {
                let name = type_name.as_str();
                $(if name == <$t as PluginType>::TYPE_NAME {
                    let obj = construct::<$t>(source, &host)?;
                    return $crate::$module::$guard::object(obj, save::<$t>).into_result();
                })*
                Err(unknown_type(ObjectKind::$kind, name, &[$(<$t as PluginType>::TYPE_NAME),*]))
            })
        }
    };
}

#[cfg(test)]
mod tests {
    use super::parse_params;
    use serde::Deserialize;

    #[derive(Deserialize, Debug, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct P {
        metal: String,
        #[serde(default)]
        roughness: Option<f64>,
    }

    /// An optional parameter given bare, as scene files write it (and as the host passes a
    /// scene's parameters: map syntax), reads as `Some`; absent, as `None`; `Some(..)` still
    /// works; a wrong type or an unknown name is still an error naming the type.
    #[test]
    fn optional_parameters_are_given_bare() {
        let p: P = parse_params("t", r#"{"metal": "gold", "roughness": 0.3}"#).unwrap();
        assert_eq!(p.roughness, Some(0.3));
        let p: P = parse_params("t", r#"(metal: "gold", roughness: 0.3)"#).unwrap();
        assert_eq!(p.roughness, Some(0.3));
        let p: P = parse_params("t", r#"(metal: "gold", roughness: Some(0.5))"#).unwrap();
        assert_eq!(p.roughness, Some(0.5));
        let p: P = parse_params("t", r#"(metal: "gold")"#).unwrap();
        assert_eq!(p.roughness, None);
        let e = parse_params::<P>("t", r#"(metal: "gold", roughness: "rough")"#).unwrap_err();
        assert!(e.to_string().contains("t: parameters"), "{e}");
        assert!(parse_params::<P>("t", r#"(metal: "gold", colour: 1)"#).is_err());
    }
}
