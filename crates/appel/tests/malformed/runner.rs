//! Running a reader on malformed inputs: each one must give a scene or an error that names the
//! file (and the line or byte where the format has them), never a panic, and finish promptly. A
//! watchdog thread catches inputs that never finish; failing inputs are saved for the corpus.

use super::mutate::{mutate, truncations};
use super::rng::{fnv1a, Pcg32};
use super::targets::{Located, Target};
use appel::error::Error;
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::{Arc, Mutex, Once};
use std::time::{Duration, Instant};

/// An input that takes longer than this is a failure: every seed reads in milliseconds.
pub const SLOW: Duration = Duration::from_secs(5);
/// With no input finished for this long, the reader is taken to hang.
const HANG: Duration = Duration::from_secs(30);

#[derive(Debug)]
pub struct Failure {
    pub what: String,
    /// Where the input was saved.
    pub saved: Option<PathBuf>,
}

#[derive(Debug, Default)]
pub struct Report {
    pub inputs: usize,
    pub accepted: usize,
    pub rejected: usize,
    pub elapsed: Duration,
    pub slowest: Duration,
    pub slowest_input: Vec<u8>,
    pub failures: Vec<Failure>,
}

thread_local! {
    /// Set while a reader runs: its panic is recorded here instead of printed.
    static CAUGHT: RefCell<Option<Option<String>>> = const { RefCell::new(None) };
}

/// Panics inside a reader are caught and reported with their location; others print as usual.
fn install_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let caught = CAUGHT.with(|c| {
                let mut c = c.borrow_mut();
                if c.is_some() {
                    let message = info
                        .payload()
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| info.payload().downcast_ref::<String>().cloned())
                        .unwrap_or_default();
                    let at = info
                        .location()
                        .map(|l| format!("{}:{}", l.file(), l.line()))
                        .unwrap_or_default();
                    *c = Some(Some(format!("panicked at {at}: {message}")));
                    true
                } else {
                    false
                }
            });
            if !caught {
                default(info);
            }
        }));
    });
}

enum Verdict {
    Accepted,
    Rejected,
}

/// Reads one input written as `target.file` in `dir` (where the target's siblings are).
fn check_one(target: &Target, dir: &Path, input: &[u8]) -> Result<Verdict, String> {
    let path = dir.join(target.file);
    std::fs::write(&path, input).expect("the input is written");
    CAUGHT.with(|c| *c.borrow_mut() = Some(None));
    let result = std::panic::catch_unwind(|| (target.read)(&path));
    let panic = CAUGHT.with(|c| c.borrow_mut().take()).flatten();
    match result {
        // A panic on another thread (a rayon worker) arrives here without the hook's location.
        Err(payload) => Err(panic.unwrap_or_else(|| {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            format!("panicked on another thread: {message}")
        })),
        Ok(Ok(())) => Ok(Verdict::Accepted),
        Ok(Err(e)) => check_error(target, dir, &e).map(|()| Verdict::Rejected),
    }
}

/// The error names a file of the input's folder, with a line or byte where the format has them.
fn check_error(target: &Target, dir: &Path, e: &Error) -> Result<(), String> {
    let message = e.to_string();
    let bad = |why: &str| Err(format!("{why}: {message}"));
    let names_file = |p: &Path| {
        let p = p.to_string_lossy();
        p.starts_with(&*dir.to_string_lossy()) || p.contains(target.file)
    };
    match e {
        Error::Io { path, .. } if names_file(path) => Ok(()),
        Error::Input { location, .. } if names_file(&location.file) => {
            let in_input = location
                .file
                .file_name()
                .is_some_and(|f| f.to_string_lossy().contains(target.file));
            let placed = match target.located {
                Located::File => true,
                Located::Line => location.line.is_some(),
                Located::LineOrByte => location.line.is_some() || location.byte.is_some(),
            };
            // An error about another file (a texture a scene names) is held to that file's format,
            // which its own target checks.
            let whole_file = super::targets::NOT_PLACED
                .iter()
                .any(|m| message.contains(m));
            if placed || !in_input || whole_file {
                Ok(())
            } else {
                bad("the error does not say where in the file")
            }
        }
        _ => bad("the error does not name the file"),
    }
}

/// What tells failures apart: the panic's location, or the error without its numbers and folder.
fn failure_kind(what: &str, dir: &Path) -> String {
    let first = what.lines().next().unwrap_or("");
    let first = first.replace(&*dir.to_string_lossy(), "");
    match first.split_once(": ") {
        Some((at, _)) if first.starts_with("panicked") => at.to_string(),
        _ => first.chars().filter(|c| !c.is_ascii_digit()).collect(),
    }
}

fn save(target: &Target, input: &[u8]) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("malformed-failures")
        .join(target.name);
    std::fs::create_dir_all(&dir).ok()?;
    let ext = Path::new(target.file).extension()?.to_str()?;
    let path = dir.join(format!("{:016x}.{ext}", fnv1a(input)));
    std::fs::write(&path, input).ok()?;
    Some(path)
}

/// How long a fuzzing run goes on.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    pub iterations: usize,
    pub time: Duration,
    pub seed: u64,
}

/// Feeds `inputs` (then, if `mutations`, mutants of the target's seeds until the budget is spent)
/// to the target on a worker thread, watching for hangs.
pub fn run(target: &'static Target, inputs: Vec<Vec<u8>>, mutations: Option<Budget>) -> Report {
    install_hook();
    let (tx, rx) = mpsc::channel::<()>();
    let current = Arc::new(Mutex::new(Vec::<u8>::new()));
    let worker_current = Arc::clone(&current);
    let worker = std::thread::spawn(move || {
        let dir = tempfile::tempdir().expect("a temporary folder");
        for (name, bytes) in (target.siblings)() {
            std::fs::write(dir.path().join(name), bytes).expect("a sibling is written");
        }
        let start = Instant::now();
        let mut report = Report::default();
        let mut seen = std::collections::HashSet::new();
        let mut one = |input: Vec<u8>, report: &mut Report| {
            *worker_current.lock().unwrap() = input.clone();
            let t = Instant::now();
            let verdict = check_one(target, dir.path(), &input);
            let took = t.elapsed();
            report.inputs += 1;
            if took > report.slowest {
                report.slowest = took;
                report.slowest_input = input.clone();
            }
            let what = match verdict {
                Ok(Verdict::Accepted) => {
                    report.accepted += 1;
                    None
                }
                Ok(Verdict::Rejected) => {
                    report.rejected += 1;
                    None
                }
                Err(what) => Some(what),
            };
            let what =
                what.or_else(|| (took > SLOW).then(|| format!("took {:.1} s", took.as_secs_f64())));
            if let Some(what) = what {
                // One example of each distinct failure (its first line names where it happened).
                let key = failure_kind(&what, dir.path());
                if seen.insert(key) {
                    let saved = save(target, &input);
                    report.failures.push(Failure { what, saved });
                }
            }
            let _ = tx.send(());
        };
        for input in inputs {
            one(input, &mut report);
        }
        if let Some(budget) = mutations {
            let seeds = (target.seeds)();
            for seed in &seeds {
                for cut in truncations(seed, 64) {
                    one(cut, &mut report);
                }
            }
            let mut rng = Pcg32::new(budget.seed, fnv1a(target.name.as_bytes()));
            let mut n = 0;
            while n < budget.iterations && start.elapsed() < budget.time {
                let seed = rng.pick(&seeds);
                let input = mutate(&mut rng, seed, &seeds, target.text);
                one(input, &mut report);
                n += 1;
            }
        }
        report.elapsed = start.elapsed();
        report
    });
    loop {
        match rx.recv_timeout(HANG) {
            Ok(()) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                let input = current.lock().unwrap().clone();
                let saved = save(target, &input);
                panic!(
                    "{}: an input has not finished after {} s (saved as {saved:?})",
                    target.name,
                    HANG.as_secs()
                );
            }
        }
    }
    worker.join().expect("the worker catches every panic")
}
