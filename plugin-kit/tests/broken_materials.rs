//! Each deliberately broken fixture type (plugins/fixtures/broken-*) is caught by the one check
//! named for its defect, and passes every other check: the kit's checks are each proven to see
//! what they claim to, and not to blame a contract that holds. Run in-process on the fixture's
//! root module (the same objects a loaded library gives; `tests/tests/plugin_kit.rs` checks the
//! built libraries through `spectrace plugins check`).

mod common;
use common::{assert_only, check};

#[test]
fn each_broken_material_fails_its_check_alone() {
    for (ty, check_name) in [
        ("negative_eval", "finite"),
        ("uniform_sampler", "chi2"),
        ("record_pdf_doubled", "sample_pdf"),
        ("pdf_too_large", "pdf_integral"),
        ("creates_energy", "energy"),
        ("not_reciprocal", "reciprocity"),
        ("own_random_numbers", "determinism"),
        ("per_thread_cache", "threads"),
        ("state_forgets", "state"),
    ] {
        let r = check(spectrace_fixture_broken_materials::root_module(), ty);
        println!("{r}");
        assert_only(&r, check_name);
    }
}
