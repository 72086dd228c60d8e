//! The committed header is the one cbindgen generates from the crate's source today
//! (`include/kairos.h`; DESIGN.md §10): a change to the C ABI that forgot the header fails here.
//! `KAIROS_BLESS=1 cargo test -p kairos-ffi --test header` writes it.

use std::path::Path;

fn generate() -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config =
        cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml reads");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen parses the crate");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("the header is UTF-8")
}

#[test]
fn the_committed_header_is_the_generated_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/kairos.h");
    let generated = generate();
    if std::env::var_os("KAIROS_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("include/kairos.h is writable");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != generated {
        let line = (committed.lines().zip(generated.lines()))
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
        panic!(
            "include/kairos.h differs from what cbindgen generates (first at line {}): \
             run `KAIROS_BLESS=1 cargo test -p kairos-ffi --test header` and commit it",
            line + 1
        );
    }
}
