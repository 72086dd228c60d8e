//! Snapshot tests of a loader's refusals (DESIGN.md §13: every file error points at
//! file:line:column with the offending text and what was expected). Each bad file says in its
//! first comment what is wrong with it; its test checks the message names what it must and
//! snapshots the whole message as the command line prints it. Included by path
//! (`#[path = "support/bad_files.rs"] #[macro_use] mod bad_files;`), so a suite takes only this.

use std::fmt::Display;
use std::path::Path;

/// The errors `load` gives for `path`, as the command line prints them. Runs from the crate
/// root so that messages name files as a user at the root sees them; a bad file that loads
/// fails the test.
pub fn errors_of<T, E: Display>(path: &str, load: impl FnOnce(&Path) -> Result<T, E>) -> String {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    match load(Path::new(path)) {
        Ok(_) => panic!("{path} loaded"),
        Err(errors) => errors.to_string(),
    }
}

/// `bad_file!(load, "tests/dir", name, "must", ...)`: a test `name` that loads
/// `tests/dir/name.ron` with `load`, requires each `must` in the message and snapshots it.
macro_rules! bad_file {
    ($load:expr, $dir:literal, $name:ident, $($must:literal),+) => {
        #[test]
        fn $name() {
            let path = concat!($dir, "/", stringify!($name), ".ron");
            let shown = bad_files::errors_of(path, $load);
            $(assert!(shown.contains($must), "missing `{}` in:\n{shown}", $must);)+
            insta::assert_snapshot!(shown);
        }
    };
}
