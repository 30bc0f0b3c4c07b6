//! The bounded fuzzing run of CI: every committed corpus file (seeds and the reproducers of fixed bugs)
//! once, then a fixed number of mutants per target from a fixed seed. A failure prints the message and
//! the input's size; `cargo run --release -p brdf-fuzz -- run <target> --seed <seed> --artifacts DIR`
//! saves it.

use brdf_fuzz::driver::{self, Config};
use brdf_fuzz::{Outcome, Target, default_corpus_dir, read_dir_files};

/// Mutants per target in CI (about 10 s for all targets in a debug build on a loaded machine).
const MUTANTS: u64 = 2500;

fn corpus(target: Target) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    read_dir_files(&default_corpus_dir().join(target.name())).expect("the corpus folder is readable")
}

#[test]
fn every_target_has_a_corpus_with_an_accepted_seed() {
    for target in Target::ALL {
        let files = corpus(target);
        assert!(!files.is_empty(), "{}: no corpus", target.name());
        let accepted = files.iter().filter(|(_, b)| target.run(b) == Ok(Outcome::Ok)).count();
        assert!(accepted > 0, "{}: no seed is accepted, so mutants never get past validation", target.name());
    }
}

#[test]
fn corpus_files_keep_the_contract() {
    for target in Target::ALL {
        for (path, bytes) in corpus(target) {
            let result = std::panic::catch_unwind(|| target.run(&bytes));
            match result {
                Ok(Ok(_)) => {}
                Ok(Err(v)) => panic!("{}: {}", path.display(), v.0),
                Err(_) => panic!("{}: panicked", path.display()),
            }
        }
    }
}

#[test]
fn mutants_keep_the_contract() {
    for target in Target::ALL {
        let seeds: Vec<Vec<u8>> = corpus(target).into_iter().map(|(_, b)| b).collect();
        let config = Config::new(target, 20261202, MUTANTS);
        let report = driver::run(&config, &seeds);
        assert_eq!(report.execs, MUTANTS, "{}", target.name());
        let failures: Vec<String> = report
            .failures
            .iter()
            .map(|f| format!("{} ({} bytes): {}", f.kind, f.input.len(), f.message))
            .collect();
        assert_eq!(report.failed(), 0, "{}: {failures:#?}", target.name());
        // Mutants reach both sides of validation, else the run tests nothing.
        assert!(
            report.ok > 0 && report.refused > 0,
            "{}: ok {} refused {}",
            target.name(),
            report.ok,
            report.refused
        );
    }
}
