//! `spectrace plugins new NAME --kind K` writes a crate that builds and whose tests (the
//! conformance kit on its type) pass: one of each kind is generated into a temporary folder,
//! then `cargo test --release --offline` runs in each, as an author would right after
//! generating it. This is how CI "builds one of each kind": CI runs the suite.
//!
//! The crates share the target folder `target/external` with the other out-of-tree builds of
//! the tests (`support::build_external`), and get the workspace's lock file so they resolve to
//! the dependency versions already built: after the first run only the four small crates
//! compile.

use spectrace_tests::artifact_dir;
use std::path::Path;
use std::process::Command;

#[test]
fn one_generated_crate_of_each_kind_builds_and_passes_its_conformance_test() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let dir = artifact_dir().join("plugin-template-test");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let target = artifact_dir().parent().unwrap().join("external");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    for kind in ["light", "material", "spd", "observer"] {
        let name = format!("my-{kind}");
        let out = Command::new(artifact_dir().join("spectrace"))
            .args(["plugins", "new", &name, "--kind", kind, "--dir"])
            .arg(&dir)
            .args(["--api-path"])
            .arg(repo)
            .output()
            .expect("run spectrace");
        assert!(
            out.status.success(),
            "plugins new {name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let krate = dir.join(&name);
        for f in ["Cargo.toml", "src/lib.rs", "tests/conformance.rs"] {
            assert!(krate.join(f).is_file(), "{name}: {f} not written");
        }
        // A second `new` with the same name refuses to overwrite it.
        let again = Command::new(artifact_dir().join("spectrace"))
            .args(["plugins", "new", &name, "--kind", kind, "--dir"])
            .arg(&dir)
            .output()
            .expect("run spectrace");
        assert!(!again.status.success());
        std::fs::copy(repo.join("Cargo.lock"), krate.join("Cargo.lock")).unwrap();
        let build = Command::new(&cargo)
            .args(["build", "--release", "--offline", "--manifest-path"])
            .arg(krate.join("Cargo.toml"))
            .arg("--target-dir")
            .arg(&target)
            .output()
            .expect("run cargo");
        assert!(
            build.status.success(),
            "{name}: cargo build failed:\n{}",
            String::from_utf8_lossy(&build.stderr)
        );
        let test = Command::new(&cargo)
            .args(["test", "--release", "--offline", "--manifest-path"])
            .arg(krate.join("Cargo.toml"))
            .arg("--target-dir")
            .arg(&target)
            .output()
            .expect("run cargo");
        let stdout = String::from_utf8_lossy(&test.stdout);
        assert!(
            test.status.success(),
            "{name}: cargo test failed:\n{stdout}\n{}",
            String::from_utf8_lossy(&test.stderr)
        );
        // Both conformance tests ran and passed (not zero tests).
        assert!(
            stdout.contains("test result: ok. 2 passed"),
            "{name}: {stdout}"
        );
        // The library it builds is one the host loads and checks.
        let lib = target.join("release").join(format!(
            "{}{}{}",
            std::env::consts::DLL_PREFIX,
            name.replace('-', "_"),
            std::env::consts::DLL_SUFFIX
        ));
        assert!(lib.is_file(), "{} not built", lib.display());
        let check = Command::new(artifact_dir().join("spectrace"))
            .args(["plugins", "check"])
            .arg(&lib)
            .output()
            .expect("run spectrace");
        assert!(
            check.status.success(),
            "plugins check {name}:\n{}{}",
            String::from_utf8_lossy(&check.stdout),
            String::from_utf8_lossy(&check.stderr)
        );
    }
}
