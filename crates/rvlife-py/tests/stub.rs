//! The native module's stub `python/rvlife/_rvlife.pyi` is generated (pyo3-stub-gen, from the
//! `#[pyfunction]`s' signatures), never edited by hand: this test fails while the file in the
//! tree differs from the generator's text. `RVLIFE_STUB_WRITE=1 cargo test --release -p
//! rvlife-py --test stub` writes it.

use std::path::Path;

#[test]
fn the_native_stub_is_generated_from_the_signatures() {
    let text = _rvlife::stub_text().expect("the stub's text");
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/rvlife/_rvlife.pyi");
    if std::env::var_os("RVLIFE_STUB_WRITE").is_some() {
        std::fs::write(&path, &text).expect("write the stub");
        return;
    }
    let in_tree = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        in_tree == text,
        "{} is not the generated stub: run `RVLIFE_STUB_WRITE=1 cargo test --release -p \
         rvlife-py --test stub` and commit it",
        path.display()
    );
}
