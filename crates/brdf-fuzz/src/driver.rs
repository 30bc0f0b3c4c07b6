//! The fuzzing loop: corpus → mutants → target, with every failure kept as a reproducer.
//!
//! - A panic is caught (`catch_unwind`) and its input written to the artifacts folder as
//!   `<target>-panic-<hash>.bin`; a [`Violation`](crate::Violation) (a call that returned something
//!   the contract forbids) likewise as `-violation-`.
//! - A hang: a watchdog thread sees an execution run past the timeout, writes its input as `-hang-`
//!   and ends the process with exit status [`HANG_EXIT`].
//! - What kills the process outright (an abort on a failed allocation, a stack overflow) cannot be
//!   caught in it; the `campaign` command of the binary runs chunks in child processes, and re-runs a
//!   chunk that died with `record`, which writes every input to `<target>-last-input.bin` before running
//!   it: since a run is a pure function of its seed, the file left is the input that killed it.
//!
//! The working pool starts as the corpus; mutants that the target *accepted* join it (up to
//! [`POOL_CAP`]), a cheap stand-in for coverage feedback that walks mutants deeper past the header
//! checks of a format.

use std::hash::{DefaultHasher, Hash, Hasher};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::mutate::{Mutator, dictionary};
use crate::{Outcome, Target};

/// Exit status of a process the watchdog ended because one execution hung.
pub const HANG_EXIT: i32 = 70;

/// Largest number of inputs in the working pool (corpus plus accepted mutants).
pub const POOL_CAP: usize = 512;

/// How to run one target.
#[derive(Debug, Clone)]
pub struct Config {
    /// The target.
    pub target: Target,
    /// Seed of the mutation stream: with the corpus, it determines every input.
    pub seed: u64,
    /// Executions to run (the unmutated corpus first, then mutants).
    pub execs: u64,
    /// Stop after this long even if `execs` are not done.
    pub max_time: Duration,
    /// Longest input made (bytes).
    pub max_len: usize,
    /// One execution running longer than this is a hang.
    pub timeout: Duration,
    /// Where reproducers go (created when needed); `None`: kept in the report only.
    pub artifacts: Option<PathBuf>,
    /// Write every input to `<artifacts>/<target>-last-input.bin` before running it (slow; to find the
    /// input that kills the process).
    pub record: bool,
}

impl Config {
    /// `execs` executions of `target` from `seed`, inputs up to 64 KiB, 10 s per execution, at most an
    /// hour, no artifacts folder.
    pub fn new(target: Target, seed: u64, execs: u64) -> Self {
        Self {
            target,
            seed,
            execs,
            max_time: Duration::from_secs(3600),
            max_len: 1 << 16,
            timeout: Duration::from_secs(10),
            artifacts: None,
            record: false,
        }
    }
}

/// One failure found.
#[derive(Debug, Clone)]
pub struct Failure {
    /// `panic` or `violation`.
    pub kind: &'static str,
    /// The panic message or the violation.
    pub message: String,
    /// The input.
    pub input: Vec<u8>,
    /// Where it was written, if an artifacts folder was given.
    pub path: Option<PathBuf>,
}

/// What a run did.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// Executions run.
    pub execs: u64,
    /// Inputs accepted.
    pub ok: u64,
    /// Inputs refused with a clear error.
    pub refused: u64,
    /// Panics caught.
    pub panics: u64,
    /// Contract violations (unclear message, non-finite data accepted, ...).
    pub violations: u64,
    /// Wall time \[s\].
    pub seconds: f64,
    /// The first failures (at most 16 kept, each distinct by kind and message).
    pub failures: Vec<Failure>,
}

impl Report {
    /// Panics plus violations.
    pub fn failed(&self) -> u64 {
        self.panics + self.violations
    }

    /// The report as one JSON object (no dependency for something this small).
    pub fn to_json(&self, target: Target, seed: u64) -> String {
        let failures: Vec<String> = self
            .failures
            .iter()
            .map(|f| {
                format!(
                    "{{\"kind\":\"{}\",\"message\":{},\"path\":{}}}",
                    f.kind,
                    json_string(&f.message),
                    f.path.as_ref().map_or("null".into(), |p| json_string(&p.display().to_string()))
                )
            })
            .collect();
        format!(
            "{{\"target\":\"{}\",\"seed\":{},\"execs\":{},\"ok\":{},\"refused\":{},\"panics\":{},\
             \"violations\":{},\"hangs\":0,\"crashes\":0,\"seconds\":{:.3},\"failures\":[{}]}}",
            target.name(),
            seed,
            self.execs,
            self.ok,
            self.refused,
            self.panics,
            self.violations,
            self.seconds,
            failures.join(",")
        )
    }
}

/// `s` as a JSON string literal.
pub fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The input of the execution in progress, for the watchdog.
struct Watch {
    /// Milliseconds since `epoch` at which the current execution started; 0 when idle.
    started: AtomicU64,
    input: Mutex<Vec<u8>>,
    done: AtomicBool,
    epoch: Instant,
}

fn artifact_path(dir: &Path, target: Target, kind: &str, input: &[u8]) -> PathBuf {
    let mut h = DefaultHasher::new();
    input.hash(&mut h);
    dir.join(format!("{}-{kind}-{:016x}.bin", target.name(), h.finish()))
}

fn write_artifact(dir: &Path, target: Target, kind: &str, input: &[u8]) -> Option<PathBuf> {
    std::fs::create_dir_all(dir).ok()?;
    let path = artifact_path(dir, target, kind, input);
    std::fs::write(&path, input).ok()?;
    Some(path)
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(a panic with a non-string payload)".to_owned()
    }
}

/// Run `config.target` on each input of `corpus` unchanged, then on mutants, until `config.execs`
/// executions or `config.max_time`.
///
/// Panics are caught with the default hook silenced for the run (the report holds their messages).
pub fn run(config: &Config, corpus: &[Vec<u8>]) -> Report {
    let t0 = Instant::now();
    let mut report = Report::default();
    let empty: Vec<Vec<u8>> = vec![Vec::new()];
    let mut pool: Vec<Vec<u8>> = if corpus.is_empty() { empty } else { corpus.to_vec() };
    let mut mutator = Mutator::new(config.seed, dictionary(config.target), config.max_len);

    let watch = Arc::new(Watch {
        started: AtomicU64::new(0),
        input: Mutex::new(Vec::new()),
        done: AtomicBool::new(false),
        epoch: Instant::now(),
    });
    let watchdog = {
        let watch = Arc::clone(&watch);
        let (timeout, target, artifacts) = (config.timeout, config.target, config.artifacts.clone());
        std::thread::spawn(move || {
            let tick = (timeout / 4).clamp(Duration::from_millis(5), Duration::from_millis(250));
            while !watch.done.load(Ordering::Relaxed) {
                std::thread::sleep(tick);
                let started = watch.started.load(Ordering::Relaxed);
                let now = watch.epoch.elapsed().as_millis() as u64 + 1;
                if started != 0 && now.saturating_sub(started) > timeout.as_millis() as u64 {
                    let input = watch.input.lock().map(|i| i.clone()).unwrap_or_default();
                    let path = artifacts.as_deref().and_then(|d| write_artifact(d, target, "hang", &input));
                    eprintln!(
                        "brdf-fuzz: {} hung for more than {timeout:?} on an input of {} bytes (saved as {})",
                        target.name(),
                        input.len(),
                        path.map_or("nothing: no artifacts folder".into(), |p| p.display().to_string())
                    );
                    std::process::exit(HANG_EXIT);
                }
            }
        })
    };

    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut input = Vec::new();
    let mut exec = 0u64;
    while exec < config.execs && t0.elapsed() < config.max_time {
        if (exec as usize) < corpus.len() {
            input.clone_from(&corpus[exec as usize]);
        } else {
            let a = mutator.rng().below(pool.len());
            let b = mutator.rng().below(pool.len());
            input.clone_from(&pool[a]);
            let other = pool[b].clone();
            mutator.mutate(&mut input, &other);
        }
        if config.record {
            if let Some(dir) = &config.artifacts {
                let _ = std::fs::create_dir_all(dir);
                let _ = std::fs::write(dir.join(format!("{}-last-input.bin", config.target.name())), &input);
            }
        }
        if let Ok(mut slot) = watch.input.lock() {
            slot.clone_from(&input);
        }
        watch.started.store(watch.epoch.elapsed().as_millis() as u64 + 1, Ordering::Relaxed);
        let result = catch_unwind(AssertUnwindSafe(|| config.target.run(&input)));
        watch.started.store(0, Ordering::Relaxed);
        exec += 1;
        let failure = match result {
            Ok(Ok(Outcome::Ok)) => {
                report.ok += 1;
                if (exec as usize) > corpus.len() {
                    if pool.len() < POOL_CAP {
                        pool.push(input.clone());
                    } else if corpus.len() < POOL_CAP {
                        // Replace an earlier mutant, never a corpus file.
                        let slot = corpus.len() + mutator.rng().below(POOL_CAP - corpus.len());
                        pool[slot].clone_from(&input);
                    }
                }
                None
            }
            Ok(Ok(Outcome::Refused)) => {
                report.refused += 1;
                None
            }
            Ok(Err(violation)) => {
                report.violations += 1;
                Some(("violation", violation.0))
            }
            Err(payload) => {
                report.panics += 1;
                Some(("panic", panic_message(payload.as_ref())))
            }
        };
        if let Some((kind, message)) = failure {
            let known = report.failures.iter().any(|f| f.kind == kind && f.message == message);
            if !known && report.failures.len() < 16 {
                let path =
                    config.artifacts.as_deref().and_then(|d| write_artifact(d, config.target, kind, &input));
                report.failures.push(Failure { kind, message, input: input.clone(), path });
            }
        }
    }
    std::panic::set_hook(previous_hook);
    watch.done.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    report.execs = exec;
    report.seconds = t0.elapsed().as_secs_f64();
    report
}
