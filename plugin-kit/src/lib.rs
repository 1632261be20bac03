//! # spectrace-plugin-kit
//!
//! The conformance kit of spectrace plugins: checks, each with a statistic, a threshold and the
//! reason for both, that an object of a plugin keeps the contract of the plugin API. The same
//! checks run in two places:
//!
//! * in a plugin author's own `cargo test`, on the author's types in-process
//!   (`spectrace-plugin-kit` as a dev-dependency):
//!
//!   ```ignore
//!   #[test]
//!   fn my_material_conforms() {
//!       spectrace_plugin_kit::check_material::<my_plugin::Velvet>("(sheen: 0.3)").assert_pass();
//!   }
//!   // or every type of the plugin, through its root module, as the host would load it:
//!   #[test]
//!   fn the_plugin_conforms() {
//!       for report in spectrace_plugin_kit::check_module(my_plugin::root_module(), &Default::default()) {
//!           report.assert_pass();
//!       }
//!   }
//!   ```
//!
//! * in `spectrace plugins check LIB [--type NAME] [--params RON] [--json]`, on the objects of a
//!   library the host loaded through its normal loader ([`check_module_with_host`]).
//!
//! Either way the checks call the object through the API's stable-ABI trait objects
//! ([`MaterialObject`], [`LightObject`], [`SpdObject`], [`ObserverObject`]): in-process, the
//! author's type is put behind the very guard and trait object that `export_plugin!` uses.
//!
//! ## The checks
//!
//! | kind | checks (see each module for statistic, threshold and why) |
//! |---|---|
//! | material ([`material`]) | `finite`, `chi2`, `sample_pdf`, `pdf_integral`, `energy`, `reciprocity`, `determinism`, `threads`, `state` |
//! | light ([`light`]) | `power`, `beams_power`, `toward`, `emission`, `beams`, `state` |
//! | SPD ([`spd`]) | `integral`, `chi2`, `lines`, `state` |
//! | observer ([`observer`]) | `finite`, `range`, `state` |
//!
//! A type that cannot be built from the parameters given gets one failed check, `construct`.
//! Every statistical check uses fixed seeds ([`rng`]), so a plugin gets the same verdict on
//! every run and every machine; the chi-square tests are set so that a correct plugin fails a
//! check with probability below 1 % ([`stats`]).

#![warn(missing_docs)]

pub mod light;
pub mod material;
pub mod observer;
pub mod report;
pub mod rng;
pub mod spd;
pub mod stats;
pub mod subject;

pub use report::{Bound, CheckResult, Report, Status};

use spectrace_plugin_api::abi::sabi_trait::TD_Opaque;
use spectrace_plugin_api::abi::std_types::{RResult, RStr};
use spectrace_plugin_api::export::{construct, save};
use spectrace_plugin_api::host::{AbiHost, AbiHost_TO};
use spectrace_plugin_api::light::GuardedLight;
use spectrace_plugin_api::material::GuardedMaterial;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::observer::GuardedObserver;
use spectrace_plugin_api::spd::GuardedSpd;
use spectrace_plugin_api::{
    ColorObserver, LightObject, LightSource, Material, MaterialObject, ObjectKind, ObserverObject,
    PluginError, PluginModuleRef, PluginType, Spd, SpdObject, SpectralLine, WavelengthRange,
    WavelengthSample,
};
use subject::Calls;

/// Which types of a module to check, and from which parameters.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Only the type of this name (all the module's types when `None`).
    pub type_name: Option<String>,
    /// Parameters in scene (RON) syntax; `None` builds every type from `()` (all defaults),
    /// which fails `construct` for a type with required parameters.
    pub params: Option<String>,
}

/// The objects the kit checks, one per kind.
trait Checked: Sized {
    const KIND: ObjectKind;
    fn run(&self, calls: &Calls<'_, Self>) -> Vec<CheckResult>;
}
impl Checked for MaterialObject {
    const KIND: ObjectKind = ObjectKind::Material;
    fn run(&self, calls: &Calls<'_, Self>) -> Vec<CheckResult> {
        material::run(self, calls)
    }
}
impl Checked for LightObject {
    const KIND: ObjectKind = ObjectKind::Light;
    fn run(&self, calls: &Calls<'_, Self>) -> Vec<CheckResult> {
        light::run(self, calls)
    }
}
impl Checked for SpdObject {
    const KIND: ObjectKind = ObjectKind::Spd;
    fn run(&self, calls: &Calls<'_, Self>) -> Vec<CheckResult> {
        spd::run(self, calls)
    }
}
impl Checked for ObserverObject {
    const KIND: ObjectKind = ObjectKind::Observer;
    fn run(&self, calls: &Calls<'_, Self>) -> Vec<CheckResult> {
        observer::run(self, calls)
    }
}

/// Build an object from `params` with `build`, run its kind's checks (the `state` check
/// rebuilding it with `build` from its saved state, written by `version`).
fn check_built<O: Checked>(
    type_name: &str,
    version: u32,
    params: &str,
    build: &dyn Fn(ObjectSource<'_>) -> Result<O, PluginError>,
    take_error: &(dyn Fn() -> Option<PluginError> + Sync),
) -> Report {
    let mut report = Report {
        kind: O::KIND.to_string(),
        type_name: type_name.to_string(),
        params: params.to_string(),
        checks: Vec::new(),
    };
    let obj = match build(ObjectSource::Params(RStr::from_str(params))) {
        Ok(o) => o,
        Err(e) => {
            report.checks.push(CheckResult::failed(
                "construct",
                format!("building it from `{params}` failed: {e} (give its parameters)"),
            ));
            return report;
        }
    };
    let restore = |bytes: &[u8]| {
        build(ObjectSource::State {
            type_version: version,
            bytes: bytes.into(),
        })
    };
    report.checks = obj.run(&Calls {
        take_error,
        restore: Some(&restore),
    });
    report
}

/// Check the types of a plugin's root module, built with `host`'s services (what
/// `spectrace plugins check` does with the library it loaded, lending the host's SPD lookup).
/// One report per type checked; an empty list when `options.type_name` names no type (the
/// error says which types there are).
pub fn check_module_with_host<H: AbiHost>(
    module: PluginModuleRef,
    options: &Options,
    host: &H,
) -> Result<Vec<Report>, String> {
    let info = (module.info())()
        .into_result()
        .map_err(|e| format!("the plugin's `info` call failed: {e}"))?;
    let take = module.take_error();
    let take_error = move || take().into_option();
    let params = options.params.as_deref().unwrap_or("()");
    let types: Vec<_> = info
        .types
        .iter()
        .filter(|t| {
            options
                .type_name
                .as_deref()
                .is_none_or(|n| t.name.as_str() == n)
        })
        .collect();
    if types.is_empty() {
        let known: Vec<_> = info.types.iter().map(|t| t.name.to_string()).collect();
        return Err(match &options.type_name {
            Some(n) => format!(
                "plugin `{}` has no type `{n}` (it provides: {})",
                info.name,
                known.join(", ")
            ),
            None => format!("plugin `{}` provides no types", info.name),
        });
    }
    let hostref = || AbiHost_TO::from_ptr(host, TD_Opaque);
    let mut out = Vec::new();
    for t in types {
        let name = t.name.as_str();
        let r = match t.kind {
            ObjectKind::Material => check_built::<MaterialObject>(
                name,
                t.version,
                params,
                &|src| (module.create_material())(name.into(), src, hostref()).into_result(),
                &take_error,
            ),
            ObjectKind::Light => check_built::<LightObject>(
                name,
                t.version,
                params,
                &|src| (module.create_light())(name.into(), src, hostref()).into_result(),
                &take_error,
            ),
            ObjectKind::Spd => check_built::<SpdObject>(
                name,
                t.version,
                params,
                &|src| (module.create_spd())(name.into(), src, hostref()).into_result(),
                &take_error,
            ),
            ObjectKind::Observer => check_built::<ObserverObject>(
                name,
                t.version,
                params,
                &|src| (module.create_observer())(name.into(), src, hostref()).into_result(),
                &take_error,
            ),
        };
        out.push(r);
    }
    Ok(out)
}

/// [`check_module_with_host`] with the kit's own stand-in host ([`KitHost`]): what a plugin's
/// `cargo test` calls with its `root_module()`. Panics when `options.type_name` names no type
/// of the module (a mistake in the test itself).
pub fn check_module(module: PluginModuleRef, options: &Options) -> Vec<Report> {
    check_module_with_host(module, options, &KitHost).unwrap_or_else(|e| panic!("{e}"))
}

fn in_process_error() -> Option<PluginError> {
    spectrace_plugin_api::guard::take_kept_error()
}

/// Check the material type `T` built in-process from `params` (RON, scene syntax; `"()"` for
/// all defaults), behind the same guard and trait object as in a library.
pub fn check_material<T: Material + PluginType>(params: &str) -> Report {
    check_built::<MaterialObject>(
        T::TYPE_NAME,
        T::TYPE_VERSION,
        params,
        &|src| {
            let obj = construct::<T>(src, &AbiHost_TO::from_ptr(&KitHost, TD_Opaque))?;
            GuardedMaterial::object(obj, save::<T>).into_result()
        },
        &in_process_error,
    )
}

/// Check the light type `T` built in-process from `params` (see [`check_material`]).
pub fn check_light<T: LightSource + PluginType>(params: &str) -> Report {
    check_built::<LightObject>(
        T::TYPE_NAME,
        T::TYPE_VERSION,
        params,
        &|src| {
            let obj = construct::<T>(src, &AbiHost_TO::from_ptr(&KitHost, TD_Opaque))?;
            GuardedLight::object(obj, save::<T>).into_result()
        },
        &in_process_error,
    )
}

/// Check the SPD type `T` built in-process from `params` (see [`check_material`]).
pub fn check_spd<T: Spd + PluginType>(params: &str) -> Report {
    check_built::<SpdObject>(
        T::TYPE_NAME,
        T::TYPE_VERSION,
        params,
        &|src| {
            let obj = construct::<T>(src, &AbiHost_TO::from_ptr(&KitHost, TD_Opaque))?;
            GuardedSpd::object(obj, save::<T>).into_result()
        },
        &in_process_error,
    )
}

/// Check the observer type `T` built in-process from `params` (see [`check_material`]).
pub fn check_observer<T: ColorObserver + PluginType>(params: &str) -> Report {
    check_built::<ObserverObject>(
        T::TYPE_NAME,
        T::TYPE_VERSION,
        params,
        &|src| {
            let obj = construct::<T>(src, &AbiHost_TO::from_ptr(&KitHost, TD_Opaque))?;
            GuardedObserver::object(obj, save::<T>).into_result()
        },
        &in_process_error,
    )
}

/// The kit's stand-in for the host's services in an author's tests: it resolves the SPD spec
/// `"e"` (equal energy, 1/470 per nm over 360–830 nm) and refuses every other spec with a
/// message saying so. Give a type under test parameters that use `"e"`, or check it with
/// `spectrace plugins check`, which lends the host's full SPD lookup.
pub struct KitHost;

impl AbiHost for KitHost {
    fn spd(&self, spec: RStr<'_>) -> RResult<SpdObject, PluginError> {
        if spec.as_str().trim() == "e" {
            return GuardedSpd::object(EqualEnergy, |_| {
                Err(PluginError::unsupported(
                    "the kit's equal-energy SPD has no state",
                ))
            });
        }
        RResult::RErr(PluginError::invalid_parameter(format!(
            "spd `{spec}`: the conformance kit's stand-in host resolves only \"e\"; \
             check with `spectrace plugins check` for the host's SPDs"
        )))
    }
}

/// Equal energy over 360–830 nm, normalised.
struct EqualEnergy;

impl Spd for EqualEnergy {
    fn value(&self, nm: f64) -> spectrace_plugin_api::PluginResult<f64> {
        Ok(if (360.0..=830.0).contains(&nm) {
            1.0 / 470.0
        } else {
            0.0
        })
    }
    fn sample(&self, u: f64) -> spectrace_plugin_api::PluginResult<WavelengthSample> {
        Ok(WavelengthSample {
            nm: 360.0 + 470.0 * u,
            pdf: 1.0 / 470.0,
        })
    }
    fn pdf(&self, nm: f64) -> spectrace_plugin_api::PluginResult<f64> {
        self.value(nm)
    }
    fn range_nm(&self) -> WavelengthRange {
        WavelengthRange {
            min_nm: 360.0,
            max_nm: 830.0,
        }
    }
    fn lines(&self) -> Vec<SpectralLine> {
        Vec::new()
    }
}
