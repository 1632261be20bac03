//! `docs/scene-format.md` and `docs/scene-format/*.md` are generated from the registry's
//! parameter tables; this test fails when a file differs from what the tables produce (or a page
//! in `docs/scene-format/` is not one the generator writes), and says how to regenerate them.

use spectrace::plugin::reference::{scene_format_pages, KIND_PAGES_DIR, REGENERATE};
use std::path::Path;

/// Quantity: each page's text against the generated text (exact, after trimming trailing
/// whitespace: the generator ends each page with one newline). No tolerance: a reference that
/// says anything else than the code is wrong.
#[test]
fn scene_format_reference_is_up_to_date() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
    let pages = scene_format_pages(&spectrace::plugin::builtin_registry());
    for page in &pages {
        let on_disk = std::fs::read_to_string(docs.join(&page.path)).unwrap_or_default();
        assert!(
            on_disk.trim_end() == page.text.trim_end(),
            "docs/{} is out of date with the built-in types' parameter tables; \
             regenerate the reference with `{REGENERATE}`",
            page.path
        );
    }
    // No page left over from a kind or a name that no longer exists.
    for entry in std::fs::read_dir(docs.join(KIND_PAGES_DIR)).unwrap() {
        let name = format!(
            "{KIND_PAGES_DIR}/{}",
            entry.unwrap().file_name().to_string_lossy()
        );
        assert!(
            pages.iter().any(|p| p.path == name),
            "docs/{name} is not a generated page; remove it and run `{REGENERATE}`"
        );
    }
    // Every built-in name and alias appears on a page, and the overview links every page.
    let all: String = pages.iter().map(|p| p.text.as_str()).collect();
    for ty in spectrace::builtin::all() {
        for name in std::iter::once(ty.name).chain(ty.aliases.iter().copied()) {
            assert!(all.contains(&format!("`{name}`")), "{name} is missing");
        }
    }
    for page in &pages[1..] {
        assert!(
            pages[0].text.contains(&format!("]({})", page.path)),
            "the overview does not link {}",
            page.path
        );
    }
}
