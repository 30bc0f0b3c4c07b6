//! Fuzzing of brdfpy's file readers (OBJ, PLY, STL, MERL, MIT CSAIL .dat, glTF, Radiance HDR, OpenEXR) and of mesh validation, on the stable toolchain.
//!
//! - [`targets`]: one `fn(&[u8])` per reader, checking the error contract on what it returns
//!   (no panic; errors that name their source and say what is wrong; accepted data finite and in range).
//! - [`mutate`]: a coverage-free mutation engine seeded by one integer, so any run is reproduced exactly.
//! - [`driver`]: the loop (corpus → mutants → target under `catch_unwind`, a watchdog for hangs,
//!   reproducers written to a folder) behind the `brdf-fuzz` binary and the bounded run of the tests.
//!
//! Why not cargo-fuzz: libFuzzer needs a nightly compiler for its instrumentation, and the project's
//! machines and CI have one stable toolchain. The targets are plain `fn(&[u8])` (the mesh target reads
//! its arrays from the bytes with a small length-prefixed layout that mutations keep meaningful), so a
//! libFuzzer harness can call them unchanged where nightly exists. `DEVELOPERS.md` ("Fuzzing") has the commands.

pub mod driver;
pub mod mutate;
pub mod targets;

pub use driver::{Config, Report};
pub use targets::{Outcome, Target, Violation};

use std::path::{Path, PathBuf};

/// The committed seed corpus of the crate: `corpus/<target>/`.
pub fn default_corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus")
}

/// Every file of `dir` (sorted by name, so runs are reproducible), or nothing if it does not exist.
pub fn read_dir_files(dir: &Path) -> std::io::Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut paths: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_file()).collect(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    paths.sort();
    paths.into_iter().map(|p| std::fs::read(&p).map(|bytes| (p, bytes))).collect()
}
