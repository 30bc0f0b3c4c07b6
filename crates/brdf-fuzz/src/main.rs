//! `brdf-fuzz`: fuzz the readers and mesh validation on the stable toolchain.
//!
//! ```text
//! brdf-fuzz run <target|all> [--execs N] [--seconds S] [--seed K] [--corpus DIR] [--artifacts DIR]
//!                            [--max-len BYTES] [--timeout-ms T] [--record]
//! brdf-fuzz campaign [--targets obj,ply,...] [--execs N per target] [--chunk N] [--jobs J]
//!                    [--chunk-timeout S] [--seed K] [--artifacts DIR] [--json FILE]
//! brdf-fuzz replay <target> FILE...
//! ```
//! `run` fuzzes in this process; `campaign` runs chunks of `run` in child processes (so an abort or a
//! hang is caught, and the input that caused it is found again with `--record`), sums their figures
//! and writes JSON; `replay` runs saved inputs (reproducers, corpus files) once each.
//! Exit status: 0 when nothing failed, 1 when something did, 2 on a usage error.

use std::path::PathBuf;
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use brdf_fuzz::driver::{self, HANG_EXIT, json_string};
use brdf_fuzz::{Config, Outcome, Target, default_corpus_dir, read_dir_files};

fn usage() -> ExitCode {
    eprintln!(
        "usage: brdf-fuzz run <target|all> [--execs N] [--seconds S] [--seed K] [--corpus DIR] \
         [--artifacts DIR] [--max-len BYTES] [--timeout-ms T] [--record]\n       \
         brdf-fuzz campaign [--targets a,b] [--execs N] [--chunk N] [--jobs J] [--chunk-timeout S] \
         [--seed K] [--artifacts DIR] [--json FILE]\n       brdf-fuzz replay <target> FILE...\n\
         targets: obj, ply, stl, merl, mit_dat, mesh, gltf, hdr, exr"
    );
    ExitCode::from(2)
}

/// `--name value` options after the positional arguments.
struct Options(Vec<String>);

impl Options {
    fn value(&self, name: &str) -> Option<&str> {
        self.0.iter().position(|a| a == name).and_then(|i| self.0.get(i + 1)).map(String::as_str)
    }

    fn flag(&self, name: &str) -> bool {
        self.0.iter().any(|a| a == name)
    }

    fn number<T: std::str::FromStr>(&self, name: &str, default: T) -> Result<T, String> {
        match self.value(name) {
            None => Ok(default),
            Some(v) => v.parse().map_err(|_| format!("{name}: expected a number, got {v:?}")),
        }
    }
}

fn targets(spec: &str) -> Result<Vec<Target>, String> {
    if spec == "all" {
        return Ok(Target::ALL.to_vec());
    }
    spec.split(',')
        .map(|name| {
            Target::from_name(name).ok_or_else(|| {
                format!("unknown target {name:?} (obj, ply, stl, merl, mit_dat, mesh, gltf, hdr, exr, all)")
            })
        })
        .collect()
}

fn corpus(dir: &std::path::Path, target: Target) -> Result<Vec<Vec<u8>>, String> {
    let files =
        read_dir_files(&dir.join(target.name())).map_err(|e| format!("corpus {}: {e}", dir.display()))?;
    Ok(files.into_iter().map(|(_, bytes)| bytes).collect())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("run") if args.len() >= 2 => cmd_run(&args[1], &Options(args[2..].to_vec())),
        Some("campaign") => cmd_campaign(&Options(args[1..].to_vec())),
        Some("replay") if args.len() >= 3 => cmd_replay(&args[1], &args[2..]),
        _ => return usage(),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(message) => {
            eprintln!("brdf-fuzz: {message}");
            ExitCode::from(2)
        }
    }
}

/// One line per target on stdout, `RESULT <json>`, which `campaign` reads back.
fn cmd_run(spec: &str, o: &Options) -> Result<bool, String> {
    let dir = o.value("--corpus").map_or_else(default_corpus_dir, PathBuf::from);
    let mut clean = true;
    for target in targets(spec)? {
        let mut config = Config::new(target, o.number("--seed", 0u64)?, o.number("--execs", 100_000u64)?);
        config.max_time = Duration::from_secs_f64(o.number("--seconds", 3600.0f64)?);
        config.max_len = o.number("--max-len", config.max_len)?;
        config.timeout = Duration::from_millis(o.number("--timeout-ms", 10_000u64)?);
        config.artifacts = o.value("--artifacts").map(PathBuf::from);
        config.record = o.flag("--record");
        let report = driver::run(&config, &corpus(&dir, target)?);
        for f in &report.failures {
            eprintln!(
                "{} {}: {} ({} bytes{})",
                target.name(),
                f.kind,
                f.message,
                f.input.len(),
                f.path.as_ref().map_or(String::new(), |p| format!(", saved as {}", p.display()))
            );
        }
        println!("RESULT {}", report.to_json(target, config.seed));
        clean &= report.failed() == 0;
    }
    Ok(clean)
}

fn cmd_replay(target: &str, files: &[String]) -> Result<bool, String> {
    let target = Target::from_name(target).ok_or_else(|| format!("unknown target {target:?}"))?;
    let mut clean = true;
    for file in files {
        let bytes = std::fs::read(file).map_err(|e| format!("{file}: {e}"))?;
        let outcome = std::panic::catch_unwind(|| target.run(&bytes));
        let line = match outcome {
            Ok(Ok(Outcome::Ok)) => "ok".to_owned(),
            Ok(Ok(Outcome::Refused)) => "refused (clean error)".to_owned(),
            Ok(Err(v)) => {
                clean = false;
                format!("VIOLATION: {}", v.0)
            }
            Err(_) => {
                clean = false;
                "PANIC (message above)".to_owned()
            }
        };
        println!("{file}: {line}");
    }
    Ok(clean)
}

/// Sums over the chunks of one target.
#[derive(Default)]
struct Totals {
    execs: u64,
    ok: u64,
    refused: u64,
    panics: u64,
    violations: u64,
    hangs: u64,
    crashes: u64,
    seconds: f64,
    failures: Vec<String>,
}

/// A field `"name":<integer or float>` of the child's one-line JSON report.
fn field(json: &str, name: &str) -> f64 {
    let key = format!("\"{name}\":");
    json.find(&key)
        .map(|i| &json[i + key.len()..])
        .and_then(|rest| rest.split([',', '}']).next())
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.0)
}

fn cmd_campaign(o: &Options) -> Result<bool, String> {
    let targets = targets(o.value("--targets").unwrap_or("all"))?;
    let execs: u64 = o.number("--execs", 2_500_000)?;
    let chunk: u64 = o.number("--chunk", 250_000)?.max(1);
    let jobs: usize = o.number("--jobs", 1usize)?.max(1);
    let chunk_timeout = Duration::from_secs_f64(o.number("--chunk-timeout", 1800.0f64)?);
    let base_seed: u64 = o.number("--seed", 1)?;
    let artifacts = PathBuf::from(o.value("--artifacts").unwrap_or("fuzz-artifacts"));
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this executable: {e}"))?;
    let t0 = Instant::now();

    // (target, seed, execs) for every chunk, run `jobs` at a time.
    let mut pending: Vec<(Target, u64, u64)> = Vec::new();
    for &target in &targets {
        let mut left = execs;
        let mut k = 0u64;
        while left > 0 {
            let n = left.min(chunk);
            pending.push((target, base_seed.wrapping_mul(1_000_003).wrapping_add(k), n));
            left -= n;
            k += 1;
        }
    }
    pending.reverse();
    let mut totals: Vec<Totals> = targets.iter().map(|_| Totals::default()).collect();
    let spawn = |target: Target, seed: u64, n: u64, record: bool| {
        let mut cmd = Command::new(&exe);
        cmd.args(["run", target.name(), "--seed", &seed.to_string(), "--execs", &n.to_string()])
            .arg("--artifacts")
            .arg(&artifacts)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit());
        if let Some(c) = o.value("--corpus") {
            cmd.args(["--corpus", c]);
        }
        if record {
            cmd.arg("--record");
        }
        cmd.spawn()
    };
    let mut running: Vec<(Target, u64, u64, Instant, std::process::Child)> = Vec::new();
    while !pending.is_empty() || !running.is_empty() {
        while running.len() < jobs {
            let Some((target, seed, n)) = pending.pop() else { break };
            let child = spawn(target, seed, n, false).map_err(|e| format!("cannot start a child: {e}"))?;
            running.push((target, seed, n, Instant::now(), child));
        }
        std::thread::sleep(Duration::from_millis(50));
        let mut i = 0;
        while i < running.len() {
            let (target, seed, n, started, child) = &mut running[i];
            let status = child.try_wait().map_err(|e| e.to_string())?;
            let timed_out = status.is_none() && started.elapsed() > chunk_timeout;
            if status.is_none() && !timed_out {
                i += 1;
                continue;
            }
            if timed_out {
                let _ = child.kill();
            }
            let output = child.stdout.take().map(std::io::read_to_string).transpose().unwrap_or_default();
            let _ = child.wait();
            let t = &mut totals[targets.iter().position(|x| x == target).unwrap_or(0)];
            let (target, seed, n) = (*target, *seed, *n);
            running.swap_remove(i);
            let code = status.and_then(|s| s.code());
            let lines: Vec<&str> =
                output.as_deref().unwrap_or("").lines().filter_map(|l| l.strip_prefix("RESULT ")).collect();
            if let (Some(json), Some(0 | 1)) = (lines.first(), code) {
                t.execs += field(json, "execs") as u64;
                t.ok += field(json, "ok") as u64;
                t.refused += field(json, "refused") as u64;
                t.panics += field(json, "panics") as u64;
                t.violations += field(json, "violations") as u64;
                t.seconds += field(json, "seconds");
                if code == Some(1) {
                    t.failures.push(format!("seed {seed}: {json}"));
                }
                continue;
            }
            // The child died (signal, abort) or hung: find the input again, recording each one.
            let what = if timed_out || code == Some(HANG_EXIT) { "hang" } else { "crash" };
            if what == "hang" {
                t.hangs += 1;
            } else {
                t.crashes += 1;
            }
            let mut again = spawn(target, seed, n, true).map_err(|e| format!("cannot start a child: {e}"))?;
            let t1 = Instant::now();
            while again.try_wait().map_err(|e| e.to_string())?.is_none() {
                if t1.elapsed() > chunk_timeout * 4 {
                    let _ = again.kill();
                    break;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
            let _ = again.wait();
            let last = artifacts.join(format!("{}-last-input.bin", target.name()));
            let kept = artifacts.join(format!("{}-{what}-seed{seed}.bin", target.name()));
            let saved = std::fs::rename(&last, &kept).is_ok();
            t.failures.push(format!(
                "seed {seed}: {what} (exit {code:?}); reproducer {}",
                if saved { kept.display().to_string() } else { "not found".into() }
            ));
            eprintln!("brdf-fuzz: {} chunk seed {seed}: {what}", target.name());
        }
    }

    let mut clean = true;
    let mut rows = Vec::new();
    println!("target   execs        ok           refused      panics violations hangs crashes  execs/s");
    for (target, t) in targets.iter().zip(&totals) {
        let rate = if t.seconds > 0.0 { t.execs as f64 / t.seconds } else { 0.0 };
        println!(
            "{:8} {:12} {:12} {:12} {:6} {:10} {:5} {:7}  {:.0}",
            target.name(),
            t.execs,
            t.ok,
            t.refused,
            t.panics,
            t.violations,
            t.hangs,
            t.crashes,
            rate
        );
        for f in &t.failures {
            println!("  {f}");
        }
        clean &= t.panics + t.violations + t.hangs + t.crashes == 0;
        let failures: Vec<String> = t.failures.iter().map(|f| json_string(f)).collect();
        rows.push(format!(
            "{{\"target\":\"{}\",\"execs\":{},\"ok\":{},\"refused\":{},\"panics\":{},\"violations\":{},\
             \"hangs\":{},\"crashes\":{},\"cpu_seconds\":{:.1},\"execs_per_second\":{:.0},\"failures\":[{}]}}",
            target.name(),
            t.execs,
            t.ok,
            t.refused,
            t.panics,
            t.violations,
            t.hangs,
            t.crashes,
            t.seconds,
            rate,
            failures.join(",")
        ));
    }
    let total: u64 = totals.iter().map(|t| t.execs).sum();
    println!("total {total} executions in {:.0} s wall, {jobs} job(s)", t0.elapsed().as_secs_f64());
    if let Some(path) = o.value("--json") {
        let json = format!(
            "{{\"total_execs\":{total},\"wall_seconds\":{:.1},\"jobs\":{jobs},\"chunk\":{chunk},\"seed\":{base_seed},\
             \"targets\":[{}]}}\n",
            t0.elapsed().as_secs_f64(),
            rows.join(",")
        );
        std::fs::write(path, json).map_err(|e| format!("{path}: {e}"))?;
    }
    Ok(clean)
}
