//! The fuzz targets' committed inputs, which the suite's brief fuzz campaigns start from:
//! `fuzz/seeds/<target>/` (valid inputs) and `fuzz/regressions/<target>/` (inputs that once
//! failed).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The workspace's `fuzz/` folder.
pub fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz")
}

/// The files of a directory by name (none if it does not exist).
pub fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return BTreeMap::new();
    };
    entries
        .map(|e| {
            let e = e.expect("a readable directory entry");
            let name = e.file_name().into_string().expect("a UTF-8 file name");
            let bytes = std::fs::read(e.path()).expect("a readable file");
            (name, bytes)
        })
        .collect()
}

/// A target's seeds by name.
pub fn seeds(target: &str) -> BTreeMap<String, Vec<u8>> {
    files(&fuzz_dir().join("seeds").join(target))
}

/// A target's regressions by name.
pub fn regressions(target: &str) -> BTreeMap<String, Vec<u8>> {
    files(&fuzz_dir().join("regressions").join(target))
}
