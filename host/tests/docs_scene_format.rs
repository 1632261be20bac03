//! `docs/scene-format.md` is generated from the registry's parameter tables; this test fails
//! when the file differs from what the tables produce, and says how to regenerate it.

use spectrace::plugin::reference::{scene_format_markdown, REGENERATE};
use std::path::Path;

/// Quantity: the file's text against the generated text (exact, after trimming trailing
/// whitespace: the generator prints one final newline). No tolerance: a reference that says
/// anything else than the code is wrong.
#[test]
fn scene_format_reference_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scene-format.md");
    let generated = scene_format_markdown(&spectrace::plugin::builtin_registry());
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk.trim_end() == generated.trim_end(),
        "docs/scene-format.md is out of date with the built-in types' parameter tables; \
         regenerate it with `{REGENERATE}`"
    );
    // Every built-in name and alias appears in it.
    for ty in spectrace::builtin::all() {
        for name in std::iter::once(ty.name).chain(ty.aliases.iter().copied()) {
            assert!(
                generated.contains(&format!("`{name}`")),
                "{name} is missing"
            );
        }
    }
}
