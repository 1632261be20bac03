//! How a plugin declares its types and exports them: implement [`PluginType`] (parameters,
//! version, construction) plus the kind's trait, then list the types in [`export_plugin!`].
//! Parameters double as the saved state, so a type gets blob support for free.

use crate::error::{ErrorKind, PluginError, PluginResult};
use crate::host::{Host, HostRef};
use crate::module::{ObjectKind, ObjectSource, ParamInfo, TypeInfo};
use crate::representation::{BeamRepresentation, TypeRepresentation};
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
    /// makes the host call `next_represented_beam` instead of `next_beam` and convert each beam.
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
    }
}

/// The beam representation of light type `T`, for extension module v1's `type_representations`.
pub fn type_representation<T: PluginType>() -> TypeRepresentation {
    TypeRepresentation {
        kind: ObjectKind::Light,
        name: T::TYPE_NAME.into(),
        beams: T::BEAM_REPRESENTATION,
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
    value
        .into_rust()
        .map_err(|e| PluginError::invalid_parameter(format!("{type_name}: parameters: {e}")))
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
            $crate::__plugin_create_fn!(create_light, Light, light, LightBox, GuardedLight, [$($light),*]);
            $crate::__plugin_create_fn!(create_spd, Spd, spd, SpdBox, GuardedSpd, [$($spd),*]);
            $crate::__plugin_create_fn!(
                create_observer, Observer, observer, ObserverBox, GuardedObserver, [$($observer),*]
            );
            $crate::__plugin_create_fn!(
                create_material, Material, material, MaterialBox, GuardedMaterial, [$($material),*]
            );
            PluginModule {
                info,
                create_light,
                create_spd,
                create_observer,
                create_material,
                describe_state,
            }
            .leak_into_prefix()
        }

        /// This plugin's extension module, version 1 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v1() -> $crate::extension::ExtensionsV1Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr, RVec, StableAbi as _};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, type_representation, unknown_type, PluginType};
            use $crate::extension::{ExtensionsV1, ExtensionsV1Export, ExtensionsV1Ref};
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};
            use $crate::representation::TypeRepresentation;

            extern "C" fn type_representations() -> RResult<RVec<TypeRepresentation>, PluginError> {
                guarded("type_representations", || {
                    let all: ::std::vec::Vec<TypeRepresentation> =
                        ::std::vec![$(type_representation::<$light>(),)*];
                    Ok(all.into_iter().filter(|t| !t.beams.is_native()).collect())
                })
            }
            extern "C" fn create_represented_light(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<$crate::extension::RepresentedLightBox, PluginError> {
                guarded("create_represented_light", || {
                    let name = type_name.as_str();
                    $(if name == <$light as PluginType>::TYPE_NAME {
                        let obj = construct::<$light>(source, &host)?;
                        return Ok($crate::light::GuardedLight::boxed_represented(obj, save::<$light>));
                    })*
                    Err(unknown_type(ObjectKind::Light, name, &[$(<$light as PluginType>::TYPE_NAME),*]))
                })
            }
            ExtensionsV1Export {
                layout: <ExtensionsV1Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV1 {
                    type_representations,
                    create_represented_light,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 1 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v1() -> $crate::extension::ExtensionsV1Export {
            $crate::guard::set_library_mode();
            extensions_v1()
        }

        /// This plugin's extension module, version 2 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v2() -> $crate::extension::ExtensionsV2Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV2, ExtensionsV2Export, ExtensionsV2Ref, LightWithV2, MaterialWithV2,
                SpdWithLines,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_light(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<LightWithV2, PluginError> {
                guarded("create_light (v2)", || {
                    let name = type_name.as_str();
                    $(if name == <$light as PluginType>::TYPE_NAME {
                        let obj = construct::<$light>(source, &host)?;
                        return Ok($crate::light::GuardedLight::boxed_v2(obj, save::<$light>));
                    })*
                    Err(unknown_type(ObjectKind::Light, name, &[$(<$light as PluginType>::TYPE_NAME),*]))
                })
            }
            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV2, PluginError> {
                guarded("create_material (v2)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return Ok($crate::material::GuardedMaterial::boxed_v2(obj, save::<$material>));
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            extern "C" fn create_spd(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<SpdWithLines, PluginError> {
                guarded("create_spd (v2)", || {
                    let name = type_name.as_str();
                    $(if name == <$spd as PluginType>::TYPE_NAME {
                        let obj = construct::<$spd>(source, &host)?;
                        return SpdWithLines::new(obj, save::<$spd>).into_result();
                    })*
                    Err(unknown_type(ObjectKind::Spd, name, &[$(<$spd as PluginType>::TYPE_NAME),*]))
                })
            }
            ExtensionsV2Export {
                layout: <ExtensionsV2Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV2 {
                    create_light,
                    create_material,
                    create_spd,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 2 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v2() -> $crate::extension::ExtensionsV2Export {
            $crate::guard::set_library_mode();
            extensions_v2()
        }

        /// This plugin's extension module, version 3 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v3() -> $crate::extension::ExtensionsV3Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV3, ExtensionsV3Export, ExtensionsV3Ref, MaterialWithV3,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV3, PluginError> {
                guarded("create_material (v3)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v3(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            ExtensionsV3Export {
                layout: <ExtensionsV3Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV3 { create_material }.leak_into_prefix(),
            }
        }

        /// The exported extension module, version 3 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v3() -> $crate::extension::ExtensionsV3Export {
            $crate::guard::set_library_mode();
            extensions_v3()
        }

        /// This plugin's extension module, version 4 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v4() -> $crate::extension::ExtensionsV4Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV4, ExtensionsV4Export, ExtensionsV4Ref, LightWithV4, MaterialWithV4,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_light(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<LightWithV4, PluginError> {
                guarded("create_light (v4)", || {
                    let name = type_name.as_str();
                    $(if name == <$light as PluginType>::TYPE_NAME {
                        let obj = construct::<$light>(source, &host)?;
                        return $crate::light::GuardedLight::boxed_v4(obj, save::<$light>)
                            .into_result();
                    })*
                    Err(unknown_type(ObjectKind::Light, name, &[$(<$light as PluginType>::TYPE_NAME),*]))
                })
            }
            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV4, PluginError> {
                guarded("create_material (v4)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v4(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            ExtensionsV4Export {
                layout: <ExtensionsV4Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV4 {
                    create_light,
                    create_material,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 4 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v4() -> $crate::extension::ExtensionsV4Export {
            $crate::guard::set_library_mode();
            extensions_v4()
        }

        /// This plugin's extension module, version 5 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v5() -> $crate::extension::ExtensionsV5Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV5, ExtensionsV5Export, ExtensionsV5Ref, MaterialWithV5,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV5, PluginError> {
                guarded("create_material (v5)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v5(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            ExtensionsV5Export {
                layout: <ExtensionsV5Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV5 { create_material }.leak_into_prefix(),
            }
        }

        /// The exported extension module, version 5 (looked up by name by the host). Every
        /// extension symbol also puts the library's guards in library mode (only a host loading
        /// the library reaches them; see `spectrace_plugin_api::guard`).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v5() -> $crate::extension::ExtensionsV5Export {
            $crate::guard::set_library_mode();
            extensions_v5()
        }

        /// This plugin's extension module, version 6 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v6() -> $crate::extension::ExtensionsV6Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV6, ExtensionsV6Export, ExtensionsV6Ref, LightWithV6, MaterialWithV6,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_light(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<LightWithV6, PluginError> {
                guarded("create_light (v6)", || {
                    let name = type_name.as_str();
                    $(if name == <$light as PluginType>::TYPE_NAME {
                        let obj = construct::<$light>(source, &host)?;
                        return $crate::light::GuardedLight::boxed_v6(obj, save::<$light>)
                            .into_result();
                    })*
                    Err(unknown_type(ObjectKind::Light, name, &[$(<$light as PluginType>::TYPE_NAME),*]))
                })
            }
            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV6, PluginError> {
                guarded("create_material (v6)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v6(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            ExtensionsV6Export {
                layout: <ExtensionsV6Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV6 {
                    create_light,
                    create_material,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 6 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v6() -> $crate::extension::ExtensionsV6Export {
            $crate::guard::set_library_mode();
            extensions_v6()
        }

        /// This plugin's extension module, version 7 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v7() -> $crate::extension::ExtensionsV7Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV7, ExtensionsV7Export, ExtensionsV7Ref, MaterialWithV7,
                ObserverWithTable,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_observer(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<ObserverWithTable, PluginError> {
                guarded("create_observer (v7)", || {
                    let name = type_name.as_str();
                    $(if name == <$observer as PluginType>::TYPE_NAME {
                        let obj = construct::<$observer>(source, &host)?;
                        return $crate::observer::GuardedObserver::boxed_v7(obj, save::<$observer>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Observer, name, &[$(<$observer as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV7, PluginError> {
                guarded("create_material (v7)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v7(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            ExtensionsV7Export {
                layout: <ExtensionsV7Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV7 {
                    create_observer,
                    create_material,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 7 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v7() -> $crate::extension::ExtensionsV7Export {
            $crate::guard::set_library_mode();
            extensions_v7()
        }

        /// This plugin's extension module, version 8 (see `spectrace_plugin_api::extension`).
        pub fn extensions_v8() -> $crate::extension::ExtensionsV8Export {
            use $crate::__private::PrefixTypeTrait as _;
            use $crate::__private::{ROption, RResult, RStr};
            use $crate::error::PluginError;
            use $crate::export::{construct, save, unknown_type, PluginType};
            use $crate::extension::{
                ExtensionsV8, ExtensionsV8Export, ExtensionsV8Ref, MaterialWithV8,
            };
            use $crate::guard::guarded;
            use $crate::host::HostRef;
            use $crate::module::{ObjectKind, ObjectSource};

            extern "C" fn create_material(
                type_name: RStr<'_>,
                source: ObjectSource<'_>,
                host: HostRef<'_>,
            ) -> RResult<MaterialWithV8, PluginError> {
                guarded("create_material (v8)", || {
                    let name = type_name.as_str();
                    $(if name == <$material as PluginType>::TYPE_NAME {
                        let obj = construct::<$material>(source, &host)?;
                        return $crate::material::GuardedMaterial::boxed_v8(obj, save::<$material>)
                            .into_result();
                    })*
                    Err(unknown_type(
                        ObjectKind::Material, name, &[$(<$material as PluginType>::TYPE_NAME),*]
                    ))
                })
            }
            extern "C" fn take_error() -> ROption<PluginError> {
                $crate::guard::take_kept_error().into()
            }
            ExtensionsV8Export {
                layout: <ExtensionsV8Ref as $crate::__private::StableAbi>::LAYOUT,
                module: ExtensionsV8 {
                    create_material,
                    take_error,
                }
                .leak_into_prefix(),
            }
        }

        /// The exported extension module, version 8 (looked up by name by the host).
        #[no_mangle]
        pub extern "C" fn spectrace_plugin_extensions_v8() -> $crate::extension::ExtensionsV8Export {
            $crate::guard::set_library_mode();
            extensions_v8()
        }

        /// The exported root module (what the host finds in the library).
        #[$crate::__private::export_root_module]
        pub fn spectrace_plugin_root_module() -> $crate::module::PluginModuleRef {
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
                    return Ok($crate::$module::$guard::boxed(obj, save::<$t>));
                })*
                Err(unknown_type(ObjectKind::$kind, name, &[$(<$t as PluginType>::TYPE_NAME),*]))
            })
        }
    };
}
