//! Loading plugin libraries. The only `unsafe` of the project lives behind abi_stable here:
//! opening a library runs its code, which the user chose to trust by naming it.
//!
//! abi_stable's `RootModule::load_from_file` caches one library per root-module type, and every
//! plugin shares ours, so it would hand the first plugin back for every path. We go one level
//! lower, `lib_header_from_path` + `init_root_module`, which opens each path on its own.
//! Libraries are never unloaded (objects from them may live until the process ends).

use spectrace_plugin_api::abi::library::{lib_header_from_path, LibraryError};
use spectrace_plugin_api::{PluginInfo, PluginModuleRef};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Why a library was refused, in one line; the full report (for `--verbose`) in `detail`.
#[derive(Debug, Clone)]
pub struct LoadError {
    /// The library file.
    pub path: PathBuf,
    /// The cause, one line.
    pub cause: String,
    /// Everything abi_stable said, which for a layout mismatch runs to hundreds of lines.
    pub detail: String,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.cause)
    }
}

impl std::error::Error for LoadError {}

impl LoadError {
    pub(crate) fn new(path: &Path, cause: impl Into<String>, detail: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            cause: cause.into(),
            detail: detail.into(),
        }
    }

    /// The message with the full report appended, for `--verbose`.
    pub fn verbose(&self) -> String {
        if self.detail.is_empty() {
            self.to_string()
        } else {
            format!("{self}\n{}", self.detail)
        }
    }
}

/// A plugin library that passed every check.
#[derive(Clone)]
pub struct LoadedPlugin {
    /// Where it was loaded from.
    pub path: PathBuf,
    /// What it says about itself.
    pub info: PluginInfo,
    /// Its root module.
    pub module: PluginModuleRef,
    /// The SHA-256 of the library file (64 lower-case hex digits); `None` for a plugin linked
    /// in-process.
    pub sha256: Option<String>,
}

impl fmt::Debug for LoadedPlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LoadedPlugin")
            .field("path", &self.path)
            .field("name", &self.info.name)
            .field("version", &self.info.version)
            .finish()
    }
}

impl LoadedPlugin {
    /// Wrap a root module obtained in-process (a plugin crate linked as a Rust library): the
    /// same checks and calls as for a loaded library, without the file.
    pub fn from_module(module: PluginModuleRef, origin: &str) -> Result<Self, LoadError> {
        let path = PathBuf::from(origin);
        let info = (module.info())().into_result().map_err(|e| {
            LoadError::new(&path, format!("its `info` call failed: {e}"), String::new())
        })?;
        Ok(Self {
            path,
            info,
            module,
            sha256: None,
        })
    }
}

/// Load one plugin library: its file is checked whole ([`super::library_check`]) before it is
/// mapped, then the abi_stable header, the interface version and the whole layout of the root
/// module before anything in it is called.
pub fn load_library(path: &Path) -> Result<LoadedPlugin, LoadError> {
    load_library_pinned(path, None)
}

/// [`load_library`], refusing a file whose SHA-256 is not `sha256` (when given) with a message
/// naming both hashes (see [`super::pin`]). The hash is taken of the file that is then opened.
pub fn load_library_pinned(path: &Path, sha256: Option<&str>) -> Result<LoadedPlugin, LoadError> {
    let file = resolve_library_path(path)?;
    if file.is_dir() {
        return Err(LoadError::new(
            path,
            "is a directory, not a plugin library",
            "",
        ));
    }
    let actual =
        crate::scene_file::pin::sha256_file(&file).map_err(|e| LoadError::new(path, e, ""))?;
    if let Some(expected) = sha256 {
        crate::scene_file::pin::check(expected, &actual)
            .map_err(|e| LoadError::new(path, e, ""))?;
    }
    let mut plugin = load_resolved(path, &file)?;
    plugin.sha256 = Some(actual);
    Ok(plugin)
}

/// Check and open the resolved library `file` (`path` as the user wrote it names it in errors).
fn load_resolved(path: &Path, file: &Path) -> Result<LoadedPlugin, LoadError> {
    let file = file.to_path_buf();
    if file.is_dir() {
        return Err(LoadError::new(
            path,
            "is a directory, not a plugin library",
            "",
        ));
    }
    super::library_check::check_library_file(&file).map_err(|e| LoadError::new(path, e, ""))?;
    if let Some(exe) = PROBE_EXE.get() {
        probe_in_child(exe, path, &file)?;
    }
    load_checked_file(path, &file)
}

/// The hidden subcommand a probe process runs: `spectrace probe-plugin FILE`.
pub const PROBE_SUBCOMMAND: &str = "probe-plugin";

/// How long a probe process may take to open a library before it is killed.
pub const PROBE_TIMEOUT: Duration = Duration::from_secs(30);

static PROBE_EXE: OnceLock<PathBuf> = OnceLock::new();

/// From now on, open each library first in a child process (`exe probe-plugin FILE`, `exe`
/// being the `spectrace` command itself) so that a library whose loading crashes — damage the
/// structure check cannot see, or start-up code that aborts — costs the child, not this process.
/// The `spectrace` command turns this on; a program that embeds the library may too.
pub fn enable_child_probe(exe: PathBuf) {
    let _ = PROBE_EXE.set(exe);
}

/// What a probe process does: open the library (structure-checked) and report, exit code 0 or 1.
pub fn probe_main(file: &Path) -> i32 {
    match super::library_check::check_library_file(file)
        .map_err(|e| LoadError::new(file, e, ""))
        .and_then(|()| load_checked_file(file, file))
    {
        Ok(p) => {
            println!("ok {} {}", p.info.name, p.info.version);
            0
        }
        Err(e) => {
            println!("refused {e}");
            1
        }
    }
}

/// Open `file` in a probe process; only a crash (a signal) or a hang is an error here: a refusal
/// the child survived is reproduced in-process, with its full detail, by the caller.
fn probe_in_child(exe: &Path, path: &Path, file: &Path) -> Result<(), LoadError> {
    use std::process::{Command, Stdio};
    let Ok(mut child) = Command::new(exe)
        .arg(PROBE_SUBCOMMAND)
        .arg(file)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
    else {
        // No probe process to be had (for example the executable was removed): the structure
        // check above is all there is.
        return Ok(());
    };
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if start.elapsed() < PROBE_TIMEOUT => {
                std::thread::sleep(Duration::from_millis(2))
            }
            Ok(None) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(LoadError::new(
                    path,
                    format!(
                        "opening it did not finish within {} s in a probe process; its start-up \
                         code hangs",
                        PROBE_TIMEOUT.as_secs()
                    ),
                    "",
                ));
            }
            Err(_) => return Ok(()),
        }
    };
    if status.code().is_some() {
        return Ok(());
    }
    Err(LoadError::new(
        path,
        format!(
            "opening it crashed a probe process ({}); the library is damaged or its start-up \
             code is broken, so it was not opened here",
            describe_signal(&status)
        ),
        "",
    ))
}

#[cfg(unix)]
fn describe_signal(status: &std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match status.signal() {
        Some(6) => "SIGABRT".into(),
        Some(7) => "SIGBUS".into(),
        Some(11) => "SIGSEGV".into(),
        Some(4) => "SIGILL".into(),
        Some(8) => "SIGFPE".into(),
        Some(n) => format!("signal {n}"),
        None => status.to_string(),
    }
}

#[cfg(not(unix))]
fn describe_signal(status: &std::process::ExitStatus) -> String {
    status.to_string()
}

/// Open a library whose file passed the structure check. `path` names it in errors.
fn load_checked_file(path: &Path, file: &Path) -> Result<LoadedPlugin, LoadError> {
    let header = lib_header_from_path(file).map_err(|e| describe(path, e))?;
    let module = header
        .init_root_module::<PluginModuleRef>()
        .map_err(|e| describe(path, e))?;
    let plugin = LoadedPlugin::from_module(module, &path.to_string_lossy())?;
    Ok(LoadedPlugin {
        path: path.to_path_buf(),
        ..plugin
    })
}

/// The file to open for `path`. The system loader looks a name without a slash up on its own
/// search path only, never in the current directory, so `--plugin libfoo.so` would miss the
/// `libfoo.so` beside the user: such a name is tried in the current directory first, then in
/// the directories of the loader's search variable (`LD_LIBRARY_PATH`, `DYLD_LIBRARY_PATH` or
/// `PATH`), and the file found is what is checked and opened.
pub fn resolve_library_path(path: &Path) -> Result<PathBuf, LoadError> {
    let bare = path.components().count() == 1 && path.parent() == Some(Path::new(""));
    if path.exists() {
        return Ok(if bare {
            Path::new(".").join(path)
        } else {
            path.to_path_buf()
        });
    }
    let var = if cfg!(target_os = "macos") {
        "DYLD_LIBRARY_PATH"
    } else if cfg!(windows) {
        "PATH"
    } else {
        "LD_LIBRARY_PATH"
    };
    if bare {
        if let Some(dirs) = std::env::var_os(var) {
            if let Some(found) = std::env::split_paths(&dirs)
                .filter(|d| !d.as_os_str().is_empty())
                .map(|d| d.join(path))
                .find(|p| p.is_file())
            {
                return Ok(found);
            }
        }
        return Err(LoadError::new(
            path,
            format!("no such file in the current directory or on {var}"),
            "",
        ));
    }
    Err(LoadError::new(path, "no such file", ""))
}

/// The file names a plugin library can have on this platform.
pub fn is_library_file(path: &Path) -> bool {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    matches!(ext, "so" | "dylib" | "dll")
}

/// Load every library in `dir` (not recursive), in file-name order. A bad library does not stop
/// the others: its error is returned beside the plugins that loaded.
pub fn load_dir(dir: &Path) -> Result<(Vec<LoadedPlugin>, Vec<LoadError>), LoadError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| LoadError::new(dir, format!("cannot read plugin directory: {e}"), ""))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && is_library_file(p))
        .collect();
    paths.sort();
    let mut loaded = Vec::new();
    let mut errors = Vec::new();
    for p in paths {
        match load_library(&p) {
            Ok(l) => loaded.push(l),
            Err(e) => errors.push(e),
        }
    }
    Ok((loaded, errors))
}

/// Turn abi_stable's error into one line a user can act on.
fn describe(path: &Path, err: LibraryError) -> LoadError {
    let detail = err.to_string();
    let cause = match err {
        LibraryError::OpenError { err, .. } => {
            format!(
                "not a loadable shared library ({})",
                first_line(&err.to_string())
            )
        }
        LibraryError::GetSymbolError { .. } => {
            "not a spectrace plugin: the library exports no abi_stable root module \
             (was it built with `export_plugin!`?)"
                .to_string()
        }
        LibraryError::InvalidAbiHeader(h) => format!(
            "built with an incompatible abi_stable (header {h:?}); rebuild it against this \
             host's spectrace-plugin-api"
        ),
        LibraryError::InvalidCAbi { .. } => {
            "built by a compiler whose C ABI differs from this host's".to_string()
        }
        LibraryError::IncompatibleVersionNumber {
            expected_version,
            actual_version,
            ..
        } => format!(
            "built against spectrace-plugin-api {actual_version}, but this host speaks \
             {expected_version} ({}); rebuild the plugin against {expected_version}",
            if version_older(actual_version.to_string(), expected_version.to_string()) {
                "the plugin's API is too old"
            } else {
                "the plugin's API is too new"
            }
        ),
        LibraryError::ParseVersionError(e) => format!("its API version string is malformed: {e}"),
        LibraryError::AbiInstability(e) => format!(
            "ABI layout mismatch: the plugin's root module does not match this host's \
             interface ({}); run with --verbose for the full layout report",
            first_cause(&e.to_string())
        ),
        LibraryError::RootModule { err, .. } => {
            format!(
                "its root module failed to initialise: {}",
                first_line(&err.to_string())
            )
        }
        LibraryError::Many(list) => match list.into_iter().next() {
            Some(first) => return describe(path, first).with_detail(detail),
            None => "unknown loading error".to_string(),
        },
    };
    LoadError::new(path, cause, detail)
}

impl LoadError {
    fn with_detail(mut self, detail: String) -> Self {
        self.detail = detail;
        self
    }
}

fn first_line(s: &str) -> &str {
    s.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("")
}

/// One line from abi_stable's layout report: the expected and the found type, where it states
/// them, else the first line that names a difference.
fn first_cause(report: &str) -> String {
    let summary = |marker: &str| -> Option<String> {
        let start = report.rfind(marker)? + marker.len();
        let mut ty = None;
        let mut size = None;
        let mut package = None;
        for line in report[start..].lines().map(str::trim).take(8) {
            if let Some(v) = line.strip_prefix("type:") {
                ty.get_or_insert(v.to_string());
            } else if let Some(v) = line.strip_prefix("size:") {
                size.get_or_insert(v.split_whitespace().next().unwrap_or("").to_string());
            } else if let Some(v) = line.strip_prefix("package:") {
                package.get_or_insert(v.replace('\'', "").replace(" version:", " "));
            }
        }
        Some(format!("`{}` of {}, {} bytes", ty?, package?, size?))
    };
    if let (Some(expected), Some(found)) = (
        summary("Layout of expected type:"),
        summary("Layout of found type:"),
    ) {
        return format!("expected {expected}, found {found}");
    }
    first_line_with_difference(report)
}

fn first_line_with_difference(report: &str) -> String {
    let keywords = ["mismatch", "expected", "found", "different", "Mismatched"];
    report
        .lines()
        .map(str::trim)
        .find(|l| keywords.iter().any(|k| l.contains(k)))
        .map(|l| l.chars().take(200).collect())
        .unwrap_or_else(|| first_line(report).chars().take(200).collect())
}

fn version_older(a: String, b: String) -> bool {
    let parse = |s: &str| -> Vec<u64> { s.split('.').filter_map(|p| p.parse().ok()).collect() };
    parse(&a) < parse(&b)
}
